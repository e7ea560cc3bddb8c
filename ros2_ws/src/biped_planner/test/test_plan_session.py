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


def moved(footsteps, index, dx, dy):
    from biped_planner.plan_adjustment import moved_landings
    step = footsteps[index]
    return tuple(footsteps[:index]) + moved_landings(footsteps, index,
                                                     (step.x + dx, step.y + dy))


def test_a_teleop_walk_steps_on_from_an_adjusted_landing():
    s = session()
    plan = s.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    adjusted = moved(plan.footsteps, 2, 0.05, -0.04)
    update = s.adopt_adjustment(plan.plan_id, 0, adjusted)
    assert update.plan_id == plan.plan_id and update.footsteps == adjusted
    new = s.on_step(1).footsteps[-1]
    unadjusted = session()
    unadjusted.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    planned = unadjusted.on_step(1).footsteps[-1]
    # the next landing keeps its place relative to the moved feet
    assert (new.x - planned.x, new.y - planned.y) == pytest.approx((0.05, -0.04), abs=1e-9)


def test_the_landings_after_an_adjustment_do_not_depend_on_an_extension_made_before_it():
    # The planner extends a teleop walk when a step starts and adopts a step adjustment when
    # it hears of one; which comes first is the order of two messages. Its lag filter on the
    # command must not count the extension it made before the adjustment and then dropped.
    early, late = session(), session()
    for s in (early, late):
        seen = s.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
        for step in range(1, 5):
            seen = s.on_step(step) or seen
    assert early.on_step(5) is not None  # its extension, made before the adjustment came
    adjusted = moved(seen.footsteps, 6, 0.03, -0.02)  # the adjuster saw the plan without it
    for s in (early, late):
        s.adopt_adjustment(seen.plan_id, 4, adjusted)
    assert early.on_step(5).footsteps == late.on_step(5).footsteps


def test_a_goal_walk_is_planned_anew_from_the_adjusted_landing_to_its_goal():
    from biped_planner.astar import AStarPlanner
    from biped_planner.example_maps import paper_start_goal_example
    grid, start, goal = paper_start_goal_example()
    astar = AStarPlanner(grid)
    s = session()
    plan = s.goto(astar, start, goal)
    adjusted = moved(plan.footsteps, 4, -0.06, 0.05)
    update = s.adopt_adjustment(plan.plan_id, 2, adjusted)
    assert update.footsteps[:5] == adjusted[:5]
    last_two = update.footsteps[-2:]
    end = ((last_two[0].x + last_two[1].x) / 2, (last_two[0].y + last_two[1].y) / 2)
    tolerance = FootstepPlannerParams().goal_tolerance + 0.01
    assert abs(end[0] - goal.x) < tolerance and abs(end[1] - goal.y) < tolerance
    # the translated landings would have ended off the goal by the adjustment
    translated = adjusted[-2:]
    off = ((translated[0].x + translated[1].x) / 2 - goal.x,
           (translated[0].y + translated[1].y) / 2 - goal.y)
    assert max(abs(off[0]), abs(off[1])) > 0.04


def test_an_adjustment_of_another_plan_or_of_walked_footsteps_changes_nothing():
    s = session()
    plan = s.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    assert s.adopt_adjustment(plan.plan_id + 1, 0, moved(plan.footsteps, 2, 0.05, 0.0)) is None
    with pytest.raises(InputError, match='before its landing'):
        s.adopt_adjustment(plan.plan_id, 1, moved(plan.footsteps, 2, 0.05, 0.0))
    with pytest.raises(InputError, match='step_index'):
        s.adopt_adjustment(plan.plan_id, 99, plan.footsteps)
    assert s.on_step(0) is None and s.on_step(1).footsteps[:5] == plan.footsteps


def test_set_command_steers_only_the_steps_appended_after_it():
    s = session()
    in_place = s.teleop(StepCommand(0.0, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    assert s.set_command(StepCommand(0.1, 0.0, 0.0), 0.6)
    assert s.on_step(0) is None  # nothing appended yet: the plan is unchanged
    grown = s.on_step(1)
    xs = [f.x for f in grown.footsteps]
    assert xs[:len(in_place.footsteps)] == [f.x for f in in_place.footsteps]
    assert xs[-1] > max(xs[:-1]) + 0.05  # the appended step moves forward (lag-filtered)


def test_set_command_without_a_teleop_walk_does_nothing():
    s = session()
    assert not s.set_command(StepCommand(0.1, 0.0, 0.0), 0.6)
    assert s.mode != PlanMode.TELEOP


def test_a_stopping_walk_adjusted_on_the_plan_before_its_stop_keeps_its_end():
    """The step adjuster moved a landing of the plan the references still walked (the stop
    not yet spliced in): the stop's last step and its closing step stand, from the moved
    feet."""
    s = session()
    plan = s.teleop(StepCommand(0.1, 0.0, 0.0), 0.6, Pose2D(0.0, 0.0))
    before_stop = s.on_step(2).footsteps
    stopped = s.stop(2, walking=True)
    adjusted = moved(before_stop, 4, 0.03, -0.02)  # step 2, the stop's last
    update = s.adopt_adjustment(plan.plan_id, 2, adjusted)
    assert not update.continuous and len(update.footsteps) == len(stopped.footsteps)
    assert update.footsteps[:5] == adjusted[:5]
    last, closing = update.footsteps[-2:]
    expected = stopped.footsteps[-1]
    assert (closing.side, closing.x, closing.y) == \
        (expected.side, pytest.approx(expected.x + 0.03), pytest.approx(expected.y - 0.02))
    # an adjustment of the stop plan itself (its closing step) is kept as it is
    closing_moved = moved(update.footsteps, 5, 0.02, 0.0)
    assert s.adopt_adjustment(plan.plan_id, 3, closing_moved).footsteps == closing_moved
