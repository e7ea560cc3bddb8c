import pytest

from biped_planner.errors import InputError
from biped_planner.footstep_planner import FootstepPlanner, FootstepPlannerParams
from biped_planner.omnidirectional_stepper import StepCommand, StepperParams
from biped_planner.plan_session import PlanMode, PlanSession
from biped_planner.pose2d import Pose2D


def session(lookahead=2):
    return PlanSession(FootstepPlanner(FootstepPlannerParams()), StepperParams(),
                       lookahead=lookahead)


def test_a_teleop_plan_stays_lookahead_steps_ahead_of_the_step_being_taken():
    s = session()
    first = s.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    assert first.continuous and first.plan_id == 1
    assert len(first.footsteps) == 0 + 3 + 2
    assert s.on_step(0) is None  # already far enough ahead
    grown = s.on_step(1)
    assert grown.plan_id == 1 and len(grown.footsteps) == 1 + 3 + 2
    # a new command keeps the plan (same id) and applies to the steps appended from now on
    assert s.teleop(StepCommand(0.0, 0.0, 0.0), 0.6, Pose2D(5.0, 5.0), 1).plan_id == 1


@pytest.mark.parametrize('step_index', [4294967295, 7, -1])
def test_a_step_index_beyond_the_plan_is_refused_and_changes_nothing(step_index):
    """A step the robot cannot be taking (a walking_state of 2**32 - 1 once made the planner
    extend its plan forever)."""
    s = session()
    plan = s.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    with pytest.raises(InputError, match='step_index'):
        s.on_step(step_index)
    with pytest.raises(InputError, match='step_index'):
        s.teleop(StepCommand(0.2, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0), step_index)
    assert s.on_step(0) is None and s.mode == PlanMode.TELEOP
    assert len(s.on_step(1).footsteps) == len(plan.footsteps) + 1


def test_stop_ends_the_plan_after_the_step_and_a_closing_step():
    s = session()
    s.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    s.on_step(1)
    stopped = s.stop(1, walking=True)
    assert not stopped.continuous and len(stopped.footsteps) == 1 + 3 + 1
    last, closing = stopped.footsteps[-2:]
    assert closing.side != last.side and closing.x == pytest.approx(last.x)
    assert s.mode == PlanMode.NONE
    assert s.stop(1, walking=True) is None  # nothing left to stop


def test_a_stop_while_standing_drops_the_plan_and_the_next_command_starts_a_new_one():
    s = session()
    s.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    assert s.stop(0, walking=False) is None
    assert s.teleop(StepCommand(), 0.6, Pose2D(1.0, 0.0)).plan_id == 2
    s.walk_finished()
    assert s.teleop(StepCommand(), 0.6, Pose2D(1.0, 0.0)).plan_id == 3
