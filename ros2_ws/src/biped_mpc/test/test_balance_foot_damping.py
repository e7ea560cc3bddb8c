"""Foot damping: first-order closed form, rate and angle limits, release and reset, a tile."""
import math

import numpy as np
import pytest

from biped_mpc.balance.foot_damping import FootDamping, FootDampingParams
from biped_mpc.errors import ConfigError, InputError

DT = 0.02


def test_step_response_is_the_first_order_closed_form():
    params = FootDampingParams(roll_gain=0.01, pitch_gain=0.02, spring_time_constant=0.8)
    damping = FootDamping(params)
    error = np.array([5.0, -3.0])
    for k in range(1, 150):
        result = damping.update(DT, True, [1.0, 1.0], 1.0 + error)
        final = np.array([0.01, 0.02]) * error * 0.8
        np.testing.assert_allclose(result.offset, final * (1.0 - math.exp(-k * DT / 0.8)),
                                   atol=1e-15)
        assert not result.rate_limited and not result.angle_limited
    np.testing.assert_allclose(result.torque_error, error)


def test_the_only_supporting_foot_follows_the_single_support_gain():
    """Two feet settling on uneven ground yield more than the one foot the robot balances on:
    the same closed form with single_support_gain on both axes."""
    params = FootDampingParams(roll_gain=0.015, pitch_gain=0.015, single_support_gain=0.01,
                               spring_time_constant=0.8)
    double, single = FootDamping(params), FootDamping(params)
    error = np.array([5.0, -3.0])
    for k in range(1, 50):
        shape = 0.8 * (1.0 - math.exp(-k * DT / 0.8)) * error
        np.testing.assert_allclose(double.update(DT, True, [0.0, 0.0], error).offset,
                                   0.015 * shape, atol=1e-15)
        np.testing.assert_allclose(single.update(DT, True, [0.0, 0.0], error,
                                                 single_support=True).offset,
                                   0.01 * shape, atol=1e-15)


def test_rate_limit_then_angle_limit():
    params = FootDampingParams(rate_limit=0.2, angle_limit=0.15)
    damping = FootDamping(params)
    for k in range(1, 60):
        result = damping.update(DT, True, [0.0, 0.0], [100.0, -100.0])
        expected = min(0.2 * k * DT, 0.15)
        np.testing.assert_allclose(result.offset, [expected, -expected], atol=1e-12)
        # the demanded 1 rad/s is cut by the rate limit all along, at the angle limit too
        assert result.rate_limited
        assert result.angle_limited == (expected >= 0.15 - 1e-12)
        assert np.all(np.abs(result.rate) <= 0.2 + 1e-9)


def test_liftoff_returns_to_nominal_at_the_release_rate_and_reset_zeroes():
    params = FootDampingParams(release_rate=1.0)
    damping = FootDamping(params)
    for _ in range(40):
        damping.update(DT, True, [0.0, 0.0], [100.0, 10.0])
    start = damping.offset
    assert start[0] == pytest.approx(0.15)
    for k in range(1, 12):
        result = damping.update(DT, False, [0.0, 0.0], [100.0, 10.0])
        np.testing.assert_allclose(result.offset[0], max(start[0] - k * DT, 0.0), atol=1e-12)
        np.testing.assert_array_equal(result.torque_error, [0.0, 0.0])
    np.testing.assert_array_equal(damping.offset, [0.0, 0.0])
    damping.update(DT, True, [0.0, 0.0], [3.0, 3.0])
    assert np.all(damping.offset > 0.0)
    damping.reset()
    np.testing.assert_array_equal(damping.offset, [0.0, 0.0])


def test_sole_settles_on_a_tilted_tile():
    # The tile is tilted by alpha about x (its +y side higher); the ground torque on a foot at
    # roll theta pushes the CoP to the side that touches first: tau_x = k (alpha - theta),
    # saturated at the sole edge (|y_cop| <= 5 cm under 150 N).
    alpha, stiffness = 0.08, 2000.0
    damping = FootDamping(FootDampingParams(spring_time_constant=100.0))
    for _ in range(400):
        torque = float(np.clip(stiffness * (alpha - damping.offset[0]), -7.5, 7.5))
        damping.update(DT, True, [0.0, 0.0], [torque, 0.0])
    assert damping.offset[0] == pytest.approx(alpha, abs=2e-3)


@pytest.mark.parametrize('change', [{'rate_limit': 0.0}, {'roll_gain': -0.1},
                                    {'spring_time_constant': 0.0}, {'angle_limit': 1.0}])
def test_bad_parameters_are_refused(change):
    with pytest.raises(ConfigError):
        FootDampingParams(**change)


@pytest.mark.parametrize('args', [(0.0, True, [0, 0], [0, 0]), (DT, True, [0, math.nan], [0, 0]),
                                  (DT, True, [0, 0], [0, 0, 0])])
def test_bad_inputs_are_refused(args):
    with pytest.raises(InputError):
        FootDamping().update(*args)
