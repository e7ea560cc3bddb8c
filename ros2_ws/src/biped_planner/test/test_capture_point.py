"""Closed forms of biped_planner.capture_point against integration and each other."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from biped_planner.capture_point import (
    dcm, dcm_at, instantaneous_capture_point, lipm_state_at, n_step_capture_bound,
    natural_frequency)
from biped_planner.errors import InputError

OMEGA = natural_frequency(0.5, 9.81)


def test_natural_frequency():
    assert natural_frequency(0.5, 9.81) == pytest.approx(math.sqrt(19.62))


@pytest.mark.parametrize('height, gravity', [(0.0, 9.81), (-1.0, 9.81), (0.5, 0.0),
                                             (math.nan, 9.81), (0.5, math.inf)])
def test_natural_frequency_rejects(height, gravity):
    with pytest.raises(InputError):
        natural_frequency(height, gravity)


def test_capture_point_is_the_horizontal_dcm():
    com, velocity = np.array([0.1, -0.2, 0.5]), np.array([0.4, 0.3, 0.0])
    np.testing.assert_allclose(instantaneous_capture_point(com, velocity, OMEGA),
                               com[:2] + velocity[:2] / OMEGA)
    np.testing.assert_allclose(dcm(com, velocity, OMEGA), com + velocity / OMEGA)


@pytest.mark.parametrize('com, velocity, zmp, duration', [
    ([0.0, 0.0], [0.3, -0.2], [0.05, 0.1], 0.4),
    ([0.2, -0.1], [-0.5, 0.1], [0.0, 0.0], 1.3),
    ([0.0, 0.1], [0.0, 0.0], [0.0, 0.1], 2.0),
])
def test_lipm_state_matches_integration(com, velocity, zmp, duration):
    zmp = np.asarray(zmp, dtype=float)

    def dynamics(_, state):
        return np.concatenate([state[2:], OMEGA ** 2 * (state[:2] - zmp)])

    result = solve_ivp(dynamics, (0.0, duration), np.concatenate([com, velocity]),
                       rtol=1e-11, atol=1e-12)
    position, speed = lipm_state_at(com, velocity, zmp, OMEGA, duration)
    np.testing.assert_allclose(position, result.y[:2, -1], atol=1e-8)
    np.testing.assert_allclose(speed, result.y[2:, -1], atol=1e-8)
    # the DCM of the propagated state is the DCM propagated in closed form
    np.testing.assert_allclose(dcm(position, speed, OMEGA),
                               dcm_at(dcm(com, velocity, OMEGA), zmp, OMEGA, duration),
                               atol=1e-10)


def test_zmp_on_the_capture_point_stops_the_pendulum():
    com, velocity = np.array([0.0, 0.0]), np.array([0.5, -0.2])
    capture = instantaneous_capture_point(com, velocity, OMEGA)
    position, speed = lipm_state_at(com, velocity, capture, OMEGA, 3.0)
    np.testing.assert_allclose(position, capture, atol=1e-4)
    np.testing.assert_allclose(speed, 0.0, atol=1e-3)
    # anywhere else it does not
    position, _ = lipm_state_at(com, velocity, capture + [0.01, 0.0], OMEGA, 3.0)
    assert abs(position[0] - capture[0]) > 1.0


def test_dcm_at_zero_and_backwards():
    np.testing.assert_allclose(dcm_at([0.2, 0.1], [0.0, 0.0], OMEGA, 0.0), [0.2, 0.1])
    ahead = dcm_at([0.2, 0.1], [0.05, 0.0], OMEGA, 0.3)
    np.testing.assert_allclose(dcm_at(ahead, [0.05, 0.0], OMEGA, -0.3), [0.2, 0.1])


def _one_step(distance, length, duration, radius):
    """Distance of the DCM from the new ankle after one step with the CoP at the edge."""
    return radius + (distance - radius) * math.exp(OMEGA * duration) - length


@pytest.mark.parametrize('length, duration, radius', [(0.3, 0.3, 0.0), (0.4, 0.25, 0.05),
                                                      (0.2, 0.5, 0.02)])
def test_n_step_bound_recursion_and_limit(length, duration, radius):
    bounds = [n_step_capture_bound(n, length, duration, OMEGA, radius) for n in range(6)]
    assert bounds[0] == pytest.approx(radius)
    for previous, current in zip(bounds, bounds[1:]):
        assert current > previous
        # from exactly d_N, one step leaves the DCM exactly d_{N-1} from the new ankle
        assert _one_step(current, length, duration, radius) == pytest.approx(previous)
    limit = n_step_capture_bound(-1, length, duration, OMEGA, radius)
    assert bounds[-1] < limit
    assert n_step_capture_bound(200, length, duration, OMEGA, radius) == pytest.approx(limit)


def test_one_step_bound_separates_capturable_states():
    bound = n_step_capture_bound(1, 0.3, 0.3, OMEGA, 0.0)
    assert _one_step(bound - 1e-3, 0.3, 0.3, 0.0) < 0.0
    assert _one_step(bound + 1e-3, 0.3, 0.3, 0.0) > 0.0


@pytest.mark.parametrize('length, duration, radius', [(-0.1, 0.3, 0.0), (0.3, 0.0, 0.0),
                                                      (0.3, 0.3, -0.01)])
def test_n_step_bound_rejects(length, duration, radius):
    with pytest.raises(InputError):
        n_step_capture_bound(1, length, duration, OMEGA, radius)
