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
