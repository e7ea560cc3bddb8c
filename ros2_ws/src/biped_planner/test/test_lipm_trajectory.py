"""Tests of biped_planner.lipm_trajectory: ODE, eq. com_traj_x0xf, boundary conditions."""
import math

import numpy as np
import pytest

from biped_planner.errors import ConfigError
from biped_planner.lipm_trajectory import PiecewiseLipm

OMEGA = math.sqrt(9.81 / 0.5)


def _walk_knots():
    """Initial shift, three steps of single + double support, final settle (times, ZMP)."""
    times = [0.0, 0.5, 1.0]
    zmp = [[0.0, 0.0], [0.0, -0.05], [0.0, -0.1]]
    feet = [[0.0, -0.1], [0.1, 0.1], [0.2, -0.1], [0.3, 0.1]]
    t = 1.0
    for k in range(3):
        times += [t + 0.4]
        zmp += [feet[k]]
        t += 0.5
        times += [t]
        zmp += [feet[k + 1]]
    times += [t + 0.4, t + 0.9, t + 1.4]
    zmp += [feet[3], [0.3, 0.05], [0.3, 0.0]]
    return np.array(times), np.array(zmp, dtype=float)


@pytest.fixture(name='walk')
def fixture_walk():
    times, zmp = _walk_knots()
    return PiecewiseLipm(times, zmp, OMEGA, zmp[0], zmp[0], (1, times.size - 2))


def test_hip_satisfies_the_lipm_ode(walk):
    h = 1e-4
    t = np.linspace(walk.times[0], walk.times[-1], 3001)
    near_knot = np.min(np.abs(t[:, None] - walk.times[None, :]), axis=1) < 3 * h
    t = t[~near_knot]
    _, before = walk.evaluate(t - h)
    zmp, hip = walk.evaluate(t)
    _, after = walk.evaluate(t + h)
    acceleration = (after - 2 * hip + before) / h ** 2
    np.testing.assert_allclose(acceleration, OMEGA ** 2 * (hip - zmp), atol=2e-5)


def test_constant_zmp_segments_follow_eq_com_traj_x0xf(walk):
    """The paper's closed form with p_h0, p_hf the hip at the segment ends."""
    checked = 0
    for j in range(walk.times.size - 1):
        if not np.allclose(walk.zmp[j], walk.zmp[j + 1]):
            continue
        t0, tf = walk.times[j], walk.times[j + 1]
        _, ends = walk.evaluate(np.array([t0, tf]))
        t = np.linspace(t0, tf, 50)
        p = walk.zmp[j]
        expected = p + (((p - ends[1]) * np.sinh((t - t0) * OMEGA)[:, None]
                         + (ends[0] - p) * np.sinh((t - tf) * OMEGA)[:, None])
                        / np.sinh((t0 - tf) * OMEGA))
        np.testing.assert_allclose(walk.evaluate(t)[1], expected, atol=1e-12)
        checked += 1
    assert checked == 4


def test_velocity_and_acceleration_are_continuous_at_the_knots(walk):
    eps = 1e-9
    inner = walk.times[1:-1]
    left = walk.hip_velocity(inner - eps)
    right = walk.hip_velocity(inner + eps)
    np.testing.assert_allclose(left, right, atol=1e-6)
    zmp, hip = walk.evaluate(inner)
    zmp_left, _ = walk.evaluate(inner - eps)
    np.testing.assert_allclose(zmp, zmp_left, atol=1e-7)


def test_starts_and_ends_at_rest(walk):
    zmp, hip = walk.evaluate(np.array([walk.times[0], walk.times[-1], walk.times[-1] + 1.0]))
    np.testing.assert_allclose(hip[0], walk.zmp[0], atol=1e-15)
    np.testing.assert_allclose(hip[1:], [[0.3, 0.0], [0.3, 0.0]], atol=1e-12)
    velocity = walk.hip_velocity(np.array([walk.times[0] + 1e-12, walk.times[-1] - 1e-12]))
    np.testing.assert_allclose(velocity, 0.0, atol=1e-9)


def test_velocity_matches_finite_differences(walk):
    t = np.array([0.3, 1.2, 1.45, 2.1, 3.0])
    h = 1e-6
    difference = (walk.evaluate(t + h)[1] - walk.evaluate(t - h)[1]) / (2 * h)
    np.testing.assert_allclose(walk.hip_velocity(t), difference, atol=1e-7)


def test_given_moving_start_state_is_matched():
    times, zmp = _walk_knots()
    hip_start = np.array([0.02, -0.01])
    dcm_start = np.array([0.05, 0.01])
    lipm = PiecewiseLipm(times, zmp, OMEGA, hip_start, dcm_start, (1, times.size - 2))
    hip, dcm = lipm.state_at(times[0] + 1e-12)
    np.testing.assert_allclose(hip, hip_start, atol=1e-10)
    np.testing.assert_allclose(dcm, dcm_start, atol=1e-9)


def test_without_free_knots_the_hip_converges_to_the_final_zmp():
    times = np.array([0.0, 1.0, 2.0])
    zmp = np.array([[0.0, 0.0], [0.1, 0.0], [0.1, 0.0]])
    lipm = PiecewiseLipm(times, zmp, OMEGA, np.zeros(2))
    # bounded solution: xi at the end equals the final ZMP
    np.testing.assert_allclose(lipm.dcm[-1], [0.1, 0.0])
    np.testing.assert_allclose(lipm.correction, 0.0)


def test_concatenate_keeps_the_head():
    times, zmp = _walk_knots()
    head = PiecewiseLipm(times, zmp, OMEGA, zmp[0], zmp[0], (1, times.size - 2))
    cut = 4
    tail = PiecewiseLipm(times[cut:], zmp[cut:], OMEGA, zmp[cut] + head.offsets[cut],
                         head.dcm[cut], (cut + 1 - cut, times.size - 2 - cut))
    joined = PiecewiseLipm.concatenate(head, cut, tail)
    t = np.linspace(0.0, times[cut], 40)
    np.testing.assert_allclose(joined.evaluate(t)[1], head.evaluate(t)[1], atol=1e-15)
    assert joined.times.size == times.size
    with pytest.raises(ConfigError):
        PiecewiseLipm.concatenate(head, cut + 1, tail)


@pytest.mark.parametrize('change', ['short', 'shape', 'order', 'nan', 'omega', 'free_ends',
                                    'free_same', 'no_dcm'])
def test_rejects_malformed_input(change):
    times, zmp = _walk_knots()
    kwargs = dict(times=times, zmp=zmp, omega=OMEGA, hip_start=zmp[0], dcm_start=zmp[0],
                  free_knots=(1, times.size - 2))
    if change == 'short':
        kwargs.update(times=times[:1], zmp=zmp[:1])
    elif change == 'shape':
        kwargs.update(zmp=zmp[:, :1])
    elif change == 'order':
        kwargs.update(times=times[::-1].copy())
    elif change == 'nan':
        bad = zmp.copy()
        bad[3, 1] = math.nan
        kwargs.update(zmp=bad)
    elif change == 'omega':
        kwargs.update(omega=0.0)
    elif change == 'free_ends':
        kwargs.update(free_knots=(0, times.size - 2))
    elif change == 'free_same':
        kwargs.update(free_knots=(2, 2))
    else:
        kwargs.update(dcm_start=None)
    with pytest.raises(ConfigError):
        PiecewiseLipm(**kwargs)
