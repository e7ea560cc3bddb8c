"""Tests of biped_planner.feet_state: the feet state s and its transition."""
import math

import pytest

from biped_planner.feet_state import FeetState
from biped_planner.kinematic_limits import KinematicLimits, step_violations
from biped_planner.pose2d import Pose2D
from biped_planner.sides import LEFT, RIGHT

LIMITS = KinematicLimits()


def test_start_puts_the_feet_side_by_side_around_the_body():
    state = FeetState(Pose2D(1.0, 2.0, math.pi / 2), 0.2, LEFT, LIMITS)
    left, right = state.feet[LEFT], state.feet[RIGHT]
    assert (left.x, left.y) == pytest.approx((0.9, 2.0))
    assert (right.x, right.y) == pytest.approx((1.1, 2.0))
    assert state.footsteps == [right, left]  # first support, then the first swing foot
    assert state.vector() == pytest.approx((0.9, 2.0, math.pi / 2, 1.0,
                                            1.1, 2.0, math.pi / 2, -1.0))


def test_a_landing_moves_the_body_beside_it_and_swaps_the_feet():
    state = FeetState(Pose2D(0.0, 0.0, 0.0), 0.2, LEFT, LIMITS)
    landing = state.land(0.1, 0.0, 0.0)
    assert landing.side == LEFT and (landing.x, landing.y) == pytest.approx((0.1, 0.1))
    assert (state.body.x, state.body.y, state.body.yaw) == pytest.approx((0.1, 0.0, 0.0))
    assert state.swing == RIGHT and state.footsteps[-1] == landing
    assert state.vector()[3] == -1.0 and state.vector()[7] == 1.0


def test_a_landing_out_of_reach_is_clamped_to_the_limits():
    state = FeetState(Pose2D(0.0, 0.0, 0.0), 0.2, RIGHT, LIMITS)
    stance = state.feet[LEFT]
    landing = state.land(2.0, 0.0, 1.0)
    assert step_violations(stance, landing, LIMITS) == []
    assert landing.x == pytest.approx(stance.x + LIMITS.max_forward)
    assert landing.yaw == pytest.approx(LIMITS.max_turn)
