"""DCM feedback: exact-discretisation closed loops, zero gains, the support polygon clamp."""
import math

import numpy as np
import pytest

from biped_mpc.balance.dcm_feedback import (
    convex_hull, DcmFeedback, DcmFeedbackParams, project_into_polygon, rectangle_vertices)
from biped_mpc.errors import ConfigError, InputError

DT = 0.02


def lipm_step(com, velocity, zmp, omega, dt):
    """Exact LIPM over dt under a held ZMP: DCM and convergent component in closed form."""
    dcm = com + velocity / omega
    convergent = com - velocity / omega
    dcm = zmp + (dcm - zmp) * math.exp(omega * dt)
    convergent = zmp + (convergent - zmp) * math.exp(-omega * dt)
    return 0.5 * (dcm + convergent), 0.5 * omega * (dcm - convergent)


def closed_loop(feedback, com, velocity, steps, zmp_disturbance=np.zeros(2), polygon=None):
    """Standing reference at the origin; returns the DCM errors and desired ZMPs per cycle."""
    omega = feedback.params.omega
    errors, zmps = [], []
    for _ in range(steps):
        result = feedback.update(DT, np.zeros(2), com + velocity / omega, np.zeros(2), polygon)
        errors.append(result.dcm_error)
        zmps.append(result.zmp)
        com, velocity = lipm_step(com, velocity, result.zmp + zmp_disturbance, omega, DT)
    return np.array(errors), np.array(zmps)


def test_proportional_loop_follows_the_discrete_closed_form():
    params = DcmFeedbackParams(proportional_gain=3.0, integral_gain=0.0)
    omega = params.omega
    growth = math.exp(omega * DT)
    factor = growth - (growth - 1.0) * (1.0 + 3.0 / omega)
    com, velocity = np.array([0.02, -0.01]), np.array([0.05, 0.03])
    errors, _ = closed_loop(DcmFeedback(params), com, velocity, 200)
    initial = -(com + velocity / omega)
    expected = initial * factor ** np.arange(200)[:, None]
    np.testing.assert_allclose(errors, expected, atol=1e-12)
    assert 0.0 < factor < 1.0
    assert abs(errors[-1]).max() < 1e-4 * abs(initial).max()


def test_moving_reference_with_initial_error_converges():
    params = DcmFeedbackParams(proportional_gain=4.0, integral_gain=3.0,
                               integral_time_constant=100.0, integral_limit=10.0)
    omega = params.omega
    feedback = DcmFeedback(params)
    # A consistent reference: the DCM of an LIPM whose ZMP moves at constant speed.
    speed = np.array([0.2, 0.0])
    reference_dcm = lambda t: speed * t + speed / omega  # noqa: E731
    com, velocity = np.array([0.03, 0.02]), np.zeros(2)
    for k in range(500):
        t = k * DT
        result = feedback.update(DT, reference_dcm(t), com + velocity / omega, speed * t)
        com, velocity = lipm_step(com, velocity, result.zmp, omega, DT)
    # The held ZMP lags the reference's ramp (a DCM drift of about 9 mm/s here); the leaky
    # integral leaves e = drift / (k_p + k_i T_i), 3e-5 m, of the initial 3.6e-2 m.
    assert np.linalg.norm(com + velocity / omega - reference_dcm(500 * DT)) < 5e-5


def test_integral_removes_a_constant_zmp_disturbance():
    disturbance = np.array([0.01, -0.005])
    proportional = DcmFeedbackParams(proportional_gain=3.0, integral_gain=0.0)
    pi = DcmFeedbackParams(proportional_gain=3.0, integral_gain=4.0,
                           integral_time_constant=1000.0, integral_limit=10.0)
    errors_p, _ = closed_loop(DcmFeedback(proportional), np.zeros(2), np.zeros(2), 400,
                              disturbance)
    errors_pi, _ = closed_loop(DcmFeedback(pi), np.zeros(2), np.zeros(2), 400, disturbance)
    # P only: steady error e = omega d / k_p (e_dot = -k_p e + omega d in continuous time).
    # The same holds exactly for the held ZMP of the discrete loop.
    np.testing.assert_allclose(errors_p[-1], proportional.omega * disturbance / 3.0, rtol=1e-6)
    assert abs(errors_pi[-1]).max() < 1e-3 * abs(errors_p[-1]).max()


def test_zero_gains_give_the_reference_zmp():
    params = DcmFeedbackParams(proportional_gain=0.0, integral_gain=0.0)
    feedback = DcmFeedback(params)
    result = feedback.update(DT, [0.1, 0.0], [0.0, 0.05], [0.03, -0.02])
    # k_p = 0 still keeps the "1" of (1 + k_p / omega): the ZMP that holds the DCM error.
    np.testing.assert_allclose(result.zmp, [0.03 - 0.1, -0.02 + 0.05])
    result = feedback.update(DT, [0.1, 0.0], [0.1, 0.0], [0.03, -0.02])
    np.testing.assert_array_equal(result.zmp, [0.03, -0.02])
    assert not result.clamped


def test_clamp_keeps_the_zmp_inside_and_stops_the_integral():
    feedback = DcmFeedback(DcmFeedbackParams(integral_gain=5.0))
    foot = rectangle_vertices([0.0, 0.0], 0.3, 0.2, 0.1)
    result = feedback.update(DT, [0.0, 0.0], [0.5, 0.4], [0.0, 0.0], polygon=foot)
    assert result.clamped
    projected, inside = project_into_polygon(result.zmp, foot)
    assert inside
    np.testing.assert_array_equal(result.integral, np.zeros(2))
    held = feedback.update(DT, [0.0, 0.0], [0.001, 0.0], [0.0, 0.0], in_the_air=True)
    np.testing.assert_array_equal(held.integral, np.zeros(2))


def test_integral_is_limited_and_reset():
    feedback = DcmFeedback(DcmFeedbackParams(integral_limit=0.01))
    for _ in range(100):
        result = feedback.update(DT, [1.0, -1.0], [0.0, 0.0], [0.0, 0.0])
    np.testing.assert_allclose(result.integral, [0.01, -0.01])
    feedback.reset()
    np.testing.assert_array_equal(feedback.integral, np.zeros(2))
    feedback.reset([1.0, 0.002])
    np.testing.assert_allclose(feedback.integral, [0.01, 0.002])


@pytest.mark.parametrize('seed', range(5))
def test_projection_matches_brute_force(seed):
    rng = np.random.default_rng(seed)
    left = rectangle_vertices([0.0, 0.1], rng.uniform(-0.5, 0.5), 0.2, 0.1)
    right = rectangle_vertices([0.15, -0.1], rng.uniform(-0.5, 0.5), 0.2, 0.1)
    polygon = np.vstack([left, right])
    hull = convex_hull(polygon)
    edges = list(zip(hull, np.roll(hull, -1, axis=0)))
    grid = np.stack(np.meshgrid(np.linspace(-0.2, 0.35, 221), np.linspace(-0.25, 0.25, 201)),
                    axis=-1).reshape(-1, 2)
    inside = np.all([(b[0] - a[0]) * (grid[:, 1] - a[1]) - (b[1] - a[1]) * (grid[:, 0] - a[0])
                     >= 0.0 for a, b in edges], axis=0)
    for point in rng.uniform([-0.4, -0.4], [0.6, 0.4], size=(20, 2)):
        projected, was_inside = project_into_polygon(point, polygon)
        nearest = grid[inside][np.argmin(np.linalg.norm(grid[inside] - point, axis=1))]
        distance = np.linalg.norm(projected - point)
        # No point inside is closer; the grid's nearest is within its spacing of as close.
        assert distance <= np.linalg.norm(nearest - point) + 1e-9
        assert distance >= np.linalg.norm(nearest - point) - 2.5e-3 * math.sqrt(2.0)
        assert project_into_polygon(projected, polygon)[1] or not was_inside


@pytest.mark.parametrize('seed', range(5))
def test_convex_hull_matches_qhull(seed):
    from scipy.spatial import ConvexHull
    points = np.random.default_rng(seed).uniform(-1.0, 1.0, size=(12, 2))
    hull = convex_hull(points)
    expected = points[ConvexHull(points).vertices]  # counter-clockwise, another start
    start = int(np.flatnonzero(np.all(expected == hull[0], axis=1))[0])
    np.testing.assert_array_equal(hull, np.roll(expected, -start, axis=0))


def test_degenerate_polygons():
    np.testing.assert_allclose(project_into_polygon([1.0, 1.0], [[0.0, 0.0]])[0], [0.0, 0.0])
    segment = [[0.0, 0.0], [1.0, 0.0]]
    np.testing.assert_allclose(project_into_polygon([0.5, 1.0], segment)[0], [0.5, 0.0])
    assert project_into_polygon([0.5, 0.0], segment)[1]
    assert len(convex_hull([[0, 0], [1, 0], [2, 0], [1, 1]])) == 3


@pytest.mark.parametrize('change', [{'proportional_gain': -1.0}, {'com_height': 0.0},
                                    {'integral_time_constant': 0.0}, {'gravity': math.nan}])
def test_bad_parameters_are_refused(change):
    with pytest.raises(ConfigError):
        DcmFeedbackParams(**change)


@pytest.mark.parametrize('args', [
    (0.0, [0, 0], [0, 0], [0, 0]), (DT, [0, math.nan], [0, 0], [0, 0]),
    (DT, [0, 0], [0, 0, 0], [0, 0]), (DT, [0, 0], [0, 0], [math.inf, 0])])
def test_bad_inputs_are_refused(args):
    with pytest.raises(InputError):
        DcmFeedback().update(*args)
    with pytest.raises(InputError):
        project_into_polygon([0.0, 0.0], np.zeros((0, 2)))
