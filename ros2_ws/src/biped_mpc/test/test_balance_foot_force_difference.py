"""Foot force difference: first-order closed forms and two feet on tiles of unequal height."""
import math

import numpy as np
import pytest

from biped_mpc.balance.foot_force_difference import (
    FootForceDifference, FootForceDifferenceParams)
from biped_mpc.errors import ConfigError, InputError
from biped_planner.sides import LEFT, RIGHT

DT = 0.02
WEIGHT = 31.0 * 9.81


def test_held_error_without_leak_is_a_ramp():
    control = FootForceDifference(FootForceDifferenceParams(gain=1e-4, leak_rate=0.0))
    for k in range(1, 20):
        result = control.update(DT, True, [150.0, 150.0], [170.0, 130.0])
        assert result.dz == pytest.approx(1e-4 * 40.0 * k * DT, abs=1e-15)
        np.testing.assert_allclose(result.offsets, [0.5 * result.dz, -0.5 * result.dz])
        assert result.error == 40.0 and result.active


def test_held_error_with_leak_is_the_exponential():
    params = FootForceDifferenceParams(gain=2e-4, leak_rate=2.0)
    control = FootForceDifference(params)
    for k in range(1, 100):
        result = control.update(DT, True, [200.0, 100.0], [100.0, 200.0])
        # error -200 N: dz -> K_f e T_damp = -0.02 m
        assert result.dz == pytest.approx(-0.02 * (1.0 - math.exp(-2.0 * k * DT)), abs=1e-15)


def test_outside_double_support_only_the_leak_acts_and_the_limit_holds():
    control = FootForceDifference(FootForceDifferenceParams(leak_rate=1.0, max_offset=0.03))
    control.reset(0.02)
    result = control.update(DT, False, [0.0, 300.0], [300.0, 0.0])
    assert result.dz == pytest.approx(0.02 * math.exp(-DT))
    assert result.error == 0.0 and not result.active
    for _ in range(200):
        result = control.update(DT, True, [0.0, 300.0], [300.0, 0.0])
    assert result.dz == 0.03 and result.limited
    control.reset(-1.0)
    assert control.dz == -0.03


def test_a_swinging_foot_returns_its_offset_the_supporting_one_keeps_its_own():
    params = FootForceDifferenceParams(leak_rate=0.5, swing_return_rate=10.0)
    control = FootForceDifference(params)
    control.reset(0.02)  # left +1 cm, right -1 cm
    for k in range(1, 21):  # 0.4 s of single support on the right foot
        result = control.update(DT, False, [0.0, 300.0], [0.0, 300.0], swinging=(True, False))
        assert result.offsets[LEFT] == pytest.approx(0.01 * math.exp(-10.0 * k * DT))
        assert result.offsets[RIGHT] == pytest.approx(-0.01 * math.exp(-0.5 * k * DT))
        assert result.dz == pytest.approx(result.offsets[LEFT] - result.offsets[RIGHT])
    # the left foot lands within 0.2 mm of its planned height (e^-4 of 1 cm)
    assert abs(result.offsets[LEFT]) < 2e-4
    # back in double support the difference moves both feet again, from where they are
    before = result.offsets.copy()
    result = control.update(DT, True, [150.0, 150.0], [170.0, 130.0])
    decay = math.exp(-0.5 * DT)
    change = 0.5 * ((decay * (before[LEFT] - before[RIGHT])
                     + (1.0 - decay) * 1e-4 * 40.0 / 0.5) - (before[LEFT] - before[RIGHT]))
    np.testing.assert_allclose(result.offsets, before + [change, -change], atol=1e-15)


def test_without_a_swing_return_a_swinging_foot_keeps_its_offset():
    control = FootForceDifference(FootForceDifferenceParams(leak_rate=0.0,
                                                            swing_return_rate=0.0))
    control.reset(0.02)
    for _ in range(20):
        result = control.update(DT, False, [0.0, 300.0], [0.0, 300.0], swinging=(False, True))
    np.testing.assert_allclose(result.offsets, [0.01, -0.01])


def tile_forces(dz, heights, stiffness, weight=WEIGHT):
    """Normal forces of two spring feet on tiles, the body height solving their sum = weight.

    Foot i is commanded at z_i = b + (+dz/2, -dz/2)_i and pressed into its tile with
    f_i = k max(0, h_i - z_i); b (the unknown body offset) is found by bisection.
    """
    soles = np.array([0.5 * dz, -0.5 * dz])
    low, high = -1.0, 1.0
    for _ in range(200):
        body = 0.5 * (low + high)
        forces = stiffness * np.maximum(0.0, np.asarray(heights) - (body + soles))
        low, high = (body, high) if forces.sum() > weight else (low, body)
    return forces


@pytest.mark.parametrize('leak_rate', [0.0, 0.1])
def test_feet_on_tiles_of_unequal_height_come_to_share_the_load(leak_rate):
    heights, stiffness = (0.025, 0.0), 2e5
    params = FootForceDifferenceParams(gain=1e-4, leak_rate=leak_rate)
    control = FootForceDifference(params)
    desired = [WEIGHT / 2, WEIGHT / 2]
    forces = tile_forces(0.0, heights, stiffness)
    assert forces[RIGHT] == 0.0  # at first the left foot on the higher tile carries all
    for _ in range(300):
        result = control.update(DT, True, desired, forces)
        forces = tile_forces(result.dz, heights, stiffness)
    rate = params.gain * stiffness
    expected_dz = 0.025 * rate / (rate + leak_rate)
    assert result.dz == pytest.approx(expected_dz, abs=1e-7)
    assert forces[LEFT] - forces[RIGHT] == pytest.approx(leak_rate * expected_dz / 1e-4,
                                                         abs=1e-2)
    if leak_rate == 0.0:
        assert abs(forces[LEFT] - forces[RIGHT]) < 1e-2


@pytest.mark.parametrize('change', [{'gain': -1e-4}, {'leak_rate': math.inf},
                                    {'max_offset': 1.0}])
def test_bad_parameters_are_refused(change):
    with pytest.raises(ConfigError):
        FootForceDifferenceParams(**change)


@pytest.mark.parametrize('args', [(0.0, True, [0, 0], [0, 0]), (DT, True, [0, math.nan], [0, 0]),
                                  (DT, True, [0, 0], [0, 0, 0]),
                                  (DT, False, [0, 0], [0, 0], (True,))])
def test_bad_inputs_are_refused(args):
    with pytest.raises(InputError):
        FootForceDifference().update(*args)
    with pytest.raises(InputError):
        FootForceDifference().reset(math.nan)
