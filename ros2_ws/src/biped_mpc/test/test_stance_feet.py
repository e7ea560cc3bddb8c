"""StanceFeet: latching, release and the ground height the pelvis target stands on."""
import numpy as np
import pytest

from biped_mpc.stance_feet import StanceFeet
from biped_planner.sides import SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT


def _soles(left_z: float, right_z: float) -> tuple:
    return ((np.array([0.0, 0.07, left_z]), np.eye(3)),
            (np.array([0.0, -0.07, right_z]), np.eye(3)))


def test_the_ground_is_the_mean_height_of_the_held_feet():
    stance = StanceFeet(relatch_followers=False)
    stance.reset(_soles(0.038, 0.030))
    assert stance.ground_height(SUPPORT_DOUBLE) == pytest.approx(0.034)
    assert stance.ground_height(SUPPORT_LEFT) == pytest.approx(0.038)
    assert stance.ground_height(SUPPORT_RIGHT) == pytest.approx(0.030)


def test_without_a_held_foot_the_ground_stays_where_the_feet_last_stood():
    stance = StanceFeet(relatch_followers=False)
    stance.reset(_soles(0.038, 0.038))
    # The plan lifts the left foot; the right one has not been confirmed yet on its new
    # support: it is released too (its contact dropped), so no foot is held.
    stance.update(SUPPORT_RIGHT, _soles(0.06, 0.038), (False, True))
    assert stance.ground_height(SUPPORT_RIGHT) == pytest.approx(0.038)
    stance.update(SUPPORT_LEFT, _soles(0.045, 0.06), (False, False))
    assert stance.held(SUPPORT_LEFT) == [False, False]
    assert stance.ground_height(SUPPORT_LEFT) == pytest.approx(0.038)  # not the world's 0
    stance.update(SUPPORT_LEFT, _soles(0.045, 0.06), (True, False))
    assert stance.ground_height(SUPPORT_LEFT) == pytest.approx(0.045)


@pytest.mark.parametrize('zmp, expected', [
    ((0.0, 0.07), 0.038),       # on the left foot
    ((0.0, -0.07), 0.030),      # on the right foot
    ((0.0, 0.0), 0.034),        # midway
    ((0.03, 0.035), 0.036),     # a quarter of the way, off the segment: its projection
    ((0.0, 0.2), 0.038),        # beyond a foot: clamped
    ((0.0, -0.3), 0.030),
])
def test_the_ground_under_the_zmp_weighs_the_held_feet_by_where_it_is(zmp, expected):
    stance = StanceFeet(relatch_followers=False)
    stance.reset(_soles(0.038, 0.030))
    assert stance.ground_height(SUPPORT_DOUBLE, np.array(zmp)) == pytest.approx(expected)
    # one held foot: its height whatever the ZMP
    assert stance.ground_height(SUPPORT_LEFT, np.array(zmp)) == pytest.approx(0.038)


def test_under_the_zmp_a_touchdown_and_a_lift_off_leave_the_ground_where_it_was():
    """The right foot lands 20 mm lower while the ZMP is still on the left foot, then the
    left one lifts once the ZMP is on the right: no step, where the mean stepped 10 mm at
    each."""
    stance = StanceFeet(relatch_followers=False)
    stance.reset(_soles(0.05, 0.05))
    stance.update(SUPPORT_LEFT, _soles(0.05, 0.08), (True, False))
    on_left, on_right = np.array([0.0, 0.07]), np.array([0.1, -0.07])
    before = stance.ground_height(SUPPORT_LEFT, on_left)
    stance.update(SUPPORT_DOUBLE, (_soles(0.05, 0.03)[0], (np.array([0.1, -0.07, 0.03]),
                                                            np.eye(3))), (True, True))
    assert stance.ground_height(SUPPORT_DOUBLE, on_left) == pytest.approx(before) == 0.05
    assert stance.ground_height(SUPPORT_DOUBLE) == pytest.approx(0.04)  # the mean steps
    at_right = stance.ground_height(SUPPORT_DOUBLE, on_right)
    stance.update(SUPPORT_RIGHT, _soles(0.07, 0.03), (False, True))
    assert stance.ground_height(SUPPORT_RIGHT, on_right) == pytest.approx(at_right) == 0.03
