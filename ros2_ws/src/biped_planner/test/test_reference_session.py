"""Tests of the plans the reference session accepts."""
import pytest

from biped_planner.errors import ConfigError
from biped_planner.footsteps import Footstep, straight_footsteps
from biped_planner.reference_session import check_footsteps
from biped_planner.sides import LEFT


def test_a_plan_of_straight_steps_passes():
    check_footsteps(straight_footsteps(5, 0.2, 0.14), 1000.0, 1.0)


@pytest.mark.parametrize('footsteps, words', [
    ([Footstep(LEFT, 0.0, 0.07)], '2 initial feet'),
    (straight_footsteps(2, 0.1, 0.14)[:3] + [Footstep(LEFT, 1e30, 0.07)], 'workspace'),
    (straight_footsteps(2, 0.1, 0.14)[:3] + [Footstep(LEFT, 3.0, 0.07)], 'from footstep 2'),
])
def test_plans_the_robot_cannot_walk_are_refused(footsteps, words):
    with pytest.raises(ConfigError, match=words):
        check_footsteps(footsteps, 1000.0, 1.0)
