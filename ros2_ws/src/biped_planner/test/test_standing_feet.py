"""The standing feet a node plans from change only when a foot really moved."""
import math

from biped_planner.footsteps import Footstep, LEFT, RIGHT
from biped_planner.standing_feet import foot_moved, MOVED_DISTANCE, MOVED_YAW, settled_feet

HELD = (Footstep(LEFT, 0.0, 0.07, 0.0), Footstep(RIGHT, 0.0, -0.07, 0.0))


def test_settling_by_micrometres_keeps_the_held_feet():
    creep = (Footstep(LEFT, 2e-6, 0.07 - 1e-6, 1e-5), Footstep(RIGHT, -3e-6, -0.07, -1e-5))
    assert settled_feet(HELD, creep) == HELD


def test_one_foot_moved_takes_both_measured_feet():
    pushed = (Footstep(LEFT, 1e-6, 0.07, 0.0), Footstep(RIGHT, 0.0, -0.07 - 0.006, 0.0))
    assert settled_feet(HELD, pushed) == pushed


def test_without_held_feet_the_measured_ones_are_taken():
    assert settled_feet(None, HELD) == HELD


def test_the_limits_are_a_distance_and_a_wrapped_yaw():
    foot = HELD[0]
    along = MOVED_DISTANCE / math.sqrt(2.0)
    assert not foot_moved(foot, Footstep(LEFT, 0.99 * along, 0.07 + 0.99 * along))
    assert foot_moved(foot, Footstep(LEFT, 1.01 * along, 0.07 + 1.01 * along))
    assert not foot_moved(Footstep(LEFT, 0.0, 0.0, math.pi - 0.5 * MOVED_YAW),
                          Footstep(LEFT, 0.0, 0.0, -math.pi + 0.4 * MOVED_YAW))
    assert foot_moved(foot, Footstep(LEFT, 0.0, 0.07, 1.5 * MOVED_YAW))
