"""Lift-off gate: the foot the plan lifts stays down while the robot stands on it."""
import math

import numpy as np
import pytest

from biped_mpc.balance.lift_off_gate import LiftOffGate, LiftOffGateParams
from biped_mpc.errors import ConfigError, InputError

DT = 0.02
SOLES = np.array([[0.0, 0.07, 0.0], [0.0, -0.07, 0.0]])
YAWS = (0.0, 0.0)
RIGHT_LIFTS = (False, True)  # a left single support: the plan has the right foot in the air
ON_RIGHT = (20.0, 280.0)     # N: the robot stands on the right foot


def gate(**fields) -> LiftOffGate:
    return LiftOffGate(LiftOffGateParams(**fields))


def test_a_lifting_foot_that_carries_the_robot_with_the_dcm_over_it_is_held():
    held = gate().update(DT, RIGHT_LIFTS, ON_RIGHT, (0.02, -0.09), SOLES, YAWS)
    assert held == [False, True]


@pytest.mark.parametrize('dcm, inside', [
    ((0.1, -0.07), True), ((0.1 + 1e-6, -0.07), False),        # the sole's front edge
    ((0.0, -0.12), True), ((0.0, -0.12 - 1e-6), False),        # its outer edge
    ((0.0, -0.02 + 1e-6), False)])                             # beyond its inner edge
def test_the_dcm_must_be_over_the_sole_rectangle(dcm, inside):
    held = gate().update(DT, RIGHT_LIFTS, ON_RIGHT, dcm, SOLES, YAWS)
    assert held[1] is inside


def test_a_margin_widens_the_rectangle_by_itself_on_every_side():
    dcm = (0.0, -0.12 - 0.02)
    assert gate(dcm_margin=0.0).update(DT, RIGHT_LIFTS, ON_RIGHT, dcm, SOLES, YAWS)[1] is False
    assert gate(dcm_margin=0.021).update(DT, RIGHT_LIFTS, ON_RIGHT, dcm, SOLES, YAWS)[1] is True


@pytest.mark.parametrize('yaw', [math.pi / 2, -2.5])
def test_the_sole_rectangle_turns_with_the_sole(yaw):
    """A point half a sole length ahead along the sole's heading is on the front edge."""
    centre = np.array([0.3, -0.2, 0.05])
    soles = np.array([SOLES[0], centre])
    yaws = (0.0, yaw)
    ahead = centre[:2] + 0.1 * np.array([math.cos(yaw), math.sin(yaw)])
    aside = centre[:2] + 0.05 * np.array([-math.sin(yaw), math.cos(yaw)])

    def held(dcm):
        return gate().update(DT, RIGHT_LIFTS, ON_RIGHT, dcm, soles, yaws)[1]

    assert held(ahead * 0.999999 + centre[:2] * 1e-6)
    assert not held(centre[:2] + 1.001 * (ahead - centre[:2]))
    assert held(centre[:2] + 0.999 * (aside - centre[:2]))
    assert not held(centre[:2] + 1.001 * (aside - centre[:2]))


@pytest.mark.parametrize('forces, held', [
    ((74.0, 226.0), True),     # 75.3 % of the load
    ((76.0, 224.0), False),    # 74.7 %
    ((0.0, 40.0), False),      # all of it, but under min_load: the robot is in the air
    ((-30.0, 60.0), True)])    # a negative reading counts as none
def test_the_load_share_and_the_least_load_decide(forces, held):
    assert gate().update(DT, RIGHT_LIFTS, forces, (0.0, -0.07), SOLES, YAWS)[1] is held


@pytest.mark.parametrize('lifting', [(False, False), (True, True)])
def test_nothing_is_held_outside_a_single_support(lifting):
    assert gate().update(DT, lifting, ON_RIGHT, (0.0, -0.07), SOLES, YAWS) == [False, False]


def test_a_hold_lasts_at_most_max_hold_per_swing_and_a_new_swing_starts_afresh():
    lift_gate = gate(max_hold=0.1)
    held = [lift_gate.update(DT, RIGHT_LIFTS, ON_RIGHT, (0.0, -0.07), SOLES, YAWS)[1]
            for _ in range(8)]
    assert held == [True] * 5 + [False] * 3
    lift_gate.update(DT, (False, False), ON_RIGHT, (0.0, -0.07), SOLES, YAWS)  # it landed
    assert lift_gate.update(DT, RIGHT_LIFTS, ON_RIGHT, (0.0, -0.07), SOLES, YAWS)[1] is True


def test_a_foot_released_in_a_swing_is_not_held_again_before_it_lands():
    """A foot that lands early under the DCM is the landing logic's, not a lift-off."""
    lift_gate = gate()
    light = (200.0, 100.0)
    held = [lift_gate.update(DT, RIGHT_LIFTS, f, (0.0, -0.07), SOLES, YAWS)[1]
            for f in (ON_RIGHT, light, ON_RIGHT, ON_RIGHT)]
    assert held == [True, False, False, False]
    lift_gate.update(DT, (False, False), ON_RIGHT, (0.0, -0.07), SOLES, YAWS)  # it landed
    assert lift_gate.update(DT, RIGHT_LIFTS, ON_RIGHT, (0.0, -0.07), SOLES, YAWS)[1] is True


def test_a_swing_that_starts_unloaded_is_never_held():
    lift_gate = gate()
    held = [lift_gate.update(DT, RIGHT_LIFTS, f, (0.0, -0.07), SOLES, YAWS)[1]
            for f in ((290.0, 10.0), ON_RIGHT)]
    assert held == [False, False]


def test_reset_forgets_the_time_held():
    lift_gate = gate(max_hold=0.02)
    lift_gate.update(DT, RIGHT_LIFTS, ON_RIGHT, (0.0, -0.07), SOLES, YAWS)
    assert lift_gate.update(DT, RIGHT_LIFTS, ON_RIGHT, (0.0, -0.07), SOLES, YAWS)[1] is False
    lift_gate.reset()
    assert lift_gate.held == [False, False]
    assert lift_gate.update(DT, RIGHT_LIFTS, ON_RIGHT, (0.0, -0.07), SOLES, YAWS)[1] is True


@pytest.mark.parametrize('field, value', [('load_share', 0.4), ('load_share', 1.1),
                                          ('min_load', -1.0), ('max_hold', math.nan),
                                          ('dcm_margin', 0.5), ('sole_width', 0.0)])
def test_parameters_out_of_range_are_refused(field, value):
    with pytest.raises(ConfigError, match=field):
        LiftOffGateParams(**{field: value})


@pytest.mark.parametrize('dt', [0.0, -0.02, math.inf, math.nan])
def test_a_period_that_is_not_a_positive_number_is_refused(dt):
    with pytest.raises(InputError, match='dt'):
        gate().update(dt, RIGHT_LIFTS, ON_RIGHT, (0.0, -0.07), SOLES, YAWS)
