"""The hip strategy's trunk against the closed form of a damped oscillator and its limits."""
import math

import numpy as np
import pytest

from biped_mpc.balance.hip_strategy import HipStrategy, HipStrategyParams
from biped_mpc.errors import ConfigError, InputError

WIDE = dict(rate_limit=50.0, angle_limit=1.0)


def run(strategy, excess, seconds, dt=0.001, yaw=0.0):
    return [strategy.update(dt, excess, yaw) for _ in range(int(round(seconds / dt)))]


def test_without_an_excess_or_a_gain_the_trunk_stays_upright():
    assert not np.any(run(HipStrategy(HipStrategyParams(gain=1.0)), (0.0, 0.0), 1.0))
    assert not np.any(run(HipStrategy(), (0.0, -0.05), 1.0))  # gain 0: off


def test_a_constant_excess_gives_the_critically_damped_step_response():
    """theta'' = a - w^2 theta - 2 w theta', theta(0) = theta'(0) = 0:
    theta(t) = a / w^2 (1 - (1 + w t) exp(-w t))."""
    params = HipStrategyParams(gain=0.5, mass=30.0, inertia=0.5, return_frequency=6.0,
                                 **WIDE)
    excess = 0.002  # m towards -y: a roll (trunk to the right)
    a = params.gain * params.mass * params.gravity * excess / params.inertia
    w = params.return_frequency
    angles = run(HipStrategy(params), (0.0, -excess), 1.0, dt=1e-4)
    for k in (499, 1999, 9999):
        t = (k + 1) * 1e-4
        expected = a / w ** 2 * (1.0 - (1.0 + w * t) * math.exp(-w * t))
        assert angles[k][0] == pytest.approx(expected, rel=0.01, abs=1e-6)
        assert angles[k][1] == 0.0


def test_the_trunk_swings_towards_the_excess_in_the_heading_frame():
    """A ZMP wanted ahead pitches the trunk forward; one to the left rolls it left (negative
    roll); with the robot facing +y, a ZMP wanted towards +y is ahead."""
    params = HipStrategyParams(gain=1.0)
    assert run(HipStrategy(params), (0.01, 0.0), 0.05)[-1][1] > 0.0
    assert run(HipStrategy(params), (0.0, 0.01), 0.05)[-1][0] < 0.0
    turned = run(HipStrategy(params), (0.0, 0.01), 0.05, yaw=math.pi / 2)[-1]
    assert turned[1] > 0.0 and turned[0] == pytest.approx(0.0, abs=1e-12)


def test_speed_and_angle_are_limited_and_the_spring_brings_it_back():
    params = HipStrategyParams(gain=1.0, rate_limit=2.0, angle_limit=0.3)
    strategy = HipStrategy(params)
    angles = np.array(run(strategy, (0.0, -0.1), 0.5, dt=0.01))
    assert np.max(np.abs(np.diff(angles[:, 0]))) <= 2.0 * 0.01 + 1e-12
    assert angles[-1][0] == pytest.approx(0.3)
    back = run(strategy, (0.0, 0.0), 2.0, dt=0.01)
    assert abs(back[-1][0]) < 0.01


def test_bad_inputs_are_refused():
    with pytest.raises(ConfigError):
        HipStrategyParams(gain=-1.0)
    with pytest.raises(ConfigError):
        HipStrategy(params={'gain': 1.0})
    strategy = HipStrategy(HipStrategyParams(gain=1.0))
    for dt, excess, yaw in ((0.0, (0.0, 0.0), 0.0), (0.01, (math.nan, 0.0), 0.0),
                            (0.01, (0.0,), 0.0), (0.01, (0.0, 0.0), math.inf)):
        with pytest.raises(InputError):
            strategy.update(dt, excess, yaw)
