"""Tests of the plans the reference session accepts."""
import dataclasses

import numpy as np
import pytest

from biped_planner.errors import ConfigError
from biped_planner.footsteps import Footstep, straight_footsteps
from biped_planner.reference_session import check_footsteps, check_plan_start
from biped_planner.sides import LEFT, RIGHT


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


def test_a_plan_starts_within_the_offset_of_the_standing_feet_of_its_own_sides():
    feet = (Footstep(RIGHT, 0.3, -0.07), Footstep(LEFT, 0.3, 0.07))  # any order
    check_plan_start(straight_footsteps(2, 0.1, 0.14, x0=0.27), feet, 0.05)  # 3 cm off
    with pytest.raises(ConfigError, match=r'footstep 0 \(right foot\) is 0.300 m'):
        check_plan_start(straight_footsteps(2, 0.1, 0.14), feet, 0.05)
    swapped = [Footstep(RIGHT, 0.3, 0.07), Footstep(LEFT, 0.3, -0.07)]  # sides crossed
    with pytest.raises(ConfigError, match=r'\(right foot\) is 0.140 m'):
        check_plan_start(swapped, feet, 0.05)


def test_before_a_scheduled_start_the_window_stands_whenever_the_plan_came():
    """A walk whose start is ahead of the clock: the samples before it are the standing ones
    (the same as before its plan arrived), the ones from it on the walk's."""
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import ReferenceSession
    from biped_planner.standing_reference import standing_window
    from biped_planner.step_timing import StepTiming
    steps = straight_footsteps(4, 0.1, 0.14)
    params = ReferenceParams()
    session = ReferenceSession(params)
    standing = (steps[0], steps[1]) if steps[0].y > 0 else (steps[1], steps[0])
    session.set_plan(1, steps, StepTiming(0.4, 0.2), 0.0)
    assert session.start_walk(2.0)
    window = session.window(1.5, 50, 0.02, standing)
    still = standing_window(*standing, params, 1.5, 50, 0.02)
    early = window.t < 2.0
    assert early.sum() == 25
    np.testing.assert_array_equal(window.hip[early], still.hip[early])
    np.testing.assert_array_equal(window.zmp_min[early], still.zmp_min[early])
    walk = session.window(2.0, 25, 0.02, standing)
    np.testing.assert_allclose(window.hip[~early], walk.hip, atol=1e-9)  # t rounding
    np.testing.assert_array_equal(window.support[~early], walk.support)


def test_the_session_moves_the_step_under_way_and_reports_what_moved():
    """A lateral DCM error in single support of step 1 (1.5 .. 1.9 s, the right foot swinging
    to footsteps[3]) moves that landing; the report is what the rest of the graph follows."""
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import ReferenceSession
    from biped_planner.step_adjuster import OnlineStepAdjuster, OnlineStepAdjusterParams
    from biped_planner.step_timing import StepTiming
    steps = straight_footsteps(4, 0.1, 0.2)
    bare = OnlineStepAdjusterParams(dcm_deadband=0.0, ankle_authority=0.0,
                                    location_threshold=1e-6, timing_threshold=1e-6)
    session = ReferenceSession(ReferenceParams(), OnlineStepAdjuster(bare))
    session.set_plan(7, steps, StepTiming(0.4, 0.1), 0.0)
    assert session.adjust(1.6, (0.0, 0.0), (0.0, 0.0)) is None  # no walk yet
    session.start_walk(0.0)
    hip, dcm = session.reference.lipm.state_at(1.6)
    assert session.adjust(1.6, hip, dcm) is None  # on the plan
    assert session.adjust(1.45, hip, dcm + [0.0, -0.05]) is None  # double support
    adjustment = session.adjust(1.6, hip, dcm + [0.0, -0.05])
    assert adjustment.plan_id == 7 and adjustment.revision == 1 and adjustment.step_index == 1
    assert adjustment.planned_touchdown == pytest.approx(1.9)
    landing, planned = adjustment.footsteps[3], steps[3]
    assert landing.y < planned.y - 0.01  # towards the error, outwards under the right foot
    assert adjustment.footsteps[:3] == tuple(steps[:3])
    reference = session.reference
    assert adjustment.footsteps == tuple(reference.footsteps)
    assert session.plan_revision == reference.revision >= 1 and session.adjustments == 1
    assert session.walk_adjustments == 1
    single = reference.single_support_at(1.6)
    assert adjustment.touchdown == pytest.approx(reference.phases[single].t_end)
    assert ReferenceSession(ReferenceParams()).adjust(1.6, hip, dcm) is None  # no adjuster


def test_the_session_holds_a_late_swing_and_reports_it_for_the_graph():
    """Step 1's right foot (single support 1.5 .. 1.9 s) is reported seeking 8 mm below its
    landing at 1.92 s: the single support is held, then ended by the touchdown."""
    from biped_planner.errors import InputError
    from biped_planner.landing_hold import LandingHold, LandingHoldParams
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import KIND_HELD, ReferenceSession
    from biped_planner.step_timing import StepTiming
    steps = straight_footsteps(4, 0.1, 0.2)
    hold = LandingHold(LandingHoldParams(enabled=True, hold_time=0.1))
    session = ReferenceSession(ReferenceParams(), landing_hold=hold)
    session.set_plan(7, steps, StepTiming(0.4, 0.1), 0.0)
    seeking_right = (('none', 'seeking'), (0.0, 0.008))
    assert session.hold_landing(1.92, *seeking_right) is None  # no walk yet
    session.start_walk(0.0)
    assert session.hold_landing(1.92, ('seeking', 'none'), (0.008, 0.0)) is None  # other foot
    held = session.hold_landing(1.92, *seeking_right)
    assert (held.kind, held.plan_id, held.step_index, held.revision) == (KIND_HELD, 7, 1, 1)
    assert held.touchdown == pytest.approx(2.0) and held.planned_touchdown == pytest.approx(1.9)
    assert held.footsteps == tuple(steps)
    assert session.reference.sample(1.95, 1, 0.01).zmp[0] == pytest.approx([steps[2].x,
                                                                             steps[2].y])
    resumed = session.hold_landing(1.96, ('none', 'landed'), (0.0, 0.0))
    assert resumed.touchdown == pytest.approx(1.961) and resumed.revision == 2
    assert session.walk_holds == 2 and session.walk_adjustments == 0
    with pytest.raises(InputError):
        session.hold_landing(1.97, ('none',), (0.0,))
    # off: nothing held
    assert ReferenceSession(ReferenceParams()).hold_landing(1.92, *seeking_right) is None


def test_the_walk_adjustments_count_the_walk_under_way_and_restart_with_a_walk():
    """walk_adjustments tells the controller the walk's plan follows the measured DCM: it
    counts the adjusted steps of the walk under way and is 0 again once the robot stands and
    for the next walk (the session's total goes on)."""
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import ReferenceSession
    from biped_planner.step_adjuster import OnlineStepAdjuster, OnlineStepAdjusterParams
    from biped_planner.step_timing import StepTiming
    steps = straight_footsteps(6, 0.1, 0.2)
    bare = OnlineStepAdjusterParams(dcm_deadband=0.0, ankle_authority=0.0,
                                    location_threshold=1e-6, timing_threshold=1e-6)
    session = ReferenceSession(ReferenceParams(), OnlineStepAdjuster(bare))
    session.set_plan(7, steps, StepTiming(0.4, 0.1), 0.0)
    session.start_walk(0.0)
    assert session.walk_adjustments == 0
    for t in (1.6, 2.6):  # the single supports of steps 1 and 3
        hip, dcm = session.reference.lipm.state_at(t)
        assert session.adjust(t, hip, dcm + [0.0, 0.06 * (-1) ** int(t)]) is not None
    assert session.walk_adjustments == 2 and session.adjustments == 2
    session.end_walk()
    assert session.walk_adjustments == 0 and session.adjustments == 2
    session.set_plan(8, straight_footsteps(4, 0.1, 0.2), StepTiming(0.4, 0.1), 10.0)
    session.start_walk(10.0)
    assert session.walk_adjustments == 0 and session.adjustments == 2


def test_a_planner_change_without_the_newest_adjusted_landing_is_dropped_not_spliced():
    """The planner's plans made before it learnt of the adjuster's newest move would undo the
    move: dropped on arrival, and when queued before the move, at their time."""
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import ReferenceSession
    from biped_planner.step_adjuster import OnlineStepAdjuster, OnlineStepAdjusterParams
    from biped_planner.step_timing import StepTiming
    steps = straight_footsteps(6, 0.1, 0.2)
    timing = StepTiming(0.4, 0.1)
    bare = OnlineStepAdjusterParams(dcm_deadband=0.0, ankle_authority=0.0,
                                    location_threshold=1e-6, timing_threshold=1e-6)
    session = ReferenceSession(ReferenceParams(), OnlineStepAdjuster(bare))
    session.set_plan(7, steps[:7], timing, 0.0)
    session.start_walk(0.0)
    longer = straight_footsteps(7, 0.1, 0.2)  # the planner's extension, made before the move
    assert session.set_plan(7, longer, timing, 1.55, apply_at=1.9) == 'queued'
    hip, dcm = session.reference.lipm.state_at(1.6)
    adjustment = session.adjust(1.6, hip, dcm + [0.0, -0.05])
    moved = adjustment.footsteps
    assert moved[3] != longer[3]
    assert session.apply_due(2.0) is None  # its time came after the move: dropped
    assert tuple(session.reference.footsteps) == moved
    assert session.set_plan(7, longer, timing, 1.62, apply_at=1.9) == 'superseded'
    # the planner's plan after the move carries the moved landing: spliced in at its time
    replan = moved + tuple(longer[len(moved):])
    assert session.set_plan(7, replan, timing, 1.62, apply_at=1.64) == 'queued'
    assert session.apply_due(1.64) == 'extended'
    assert tuple(session.reference.footsteps) == replan


def test_an_estimate_far_from_the_plan_is_refused_not_answered():
    from biped_planner.errors import InputError
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import MAX_ESTIMATE_OFFSET, ReferenceSession
    from biped_planner.step_adjuster import OnlineStepAdjuster
    from biped_planner.step_timing import StepTiming
    session = ReferenceSession(ReferenceParams(), OnlineStepAdjuster())
    session.set_plan(1, straight_footsteps(4, 0.1, 0.2), StepTiming(0.4, 0.1), 0.0)
    session.start_walk(0.0)
    hip, dcm = session.reference.lipm.state_at(1.6)
    far = hip + [MAX_ESTIMATE_OFFSET + 0.01, 0.0]
    with pytest.raises(InputError, match='from the plan'):
        session.adjust(1.6, far, far)
    assert session.adjustments == 0


def test_a_scheduled_walk_enters_the_window_at_its_notice_whenever_its_plan_came():
    """Until WALK_NOTICE before the start the window is the standing one, although the
    horizon reaches the start: the walk enters the preview at a stated time, not when the
    plan or the walking state arrived."""
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import ReferenceSession, WALK_NOTICE
    from biped_planner.standing_reference import standing_window
    from biped_planner.step_timing import StepTiming
    steps = straight_footsteps(4, 0.1, 0.2)
    standing = (steps[1], steps[0])
    session = ReferenceSession(ReferenceParams())
    session.set_plan(1, steps, StepTiming(0.4, 0.1), 0.0)
    session.start_walk(5.0)
    before = session.window(5.0 - WALK_NOTICE - 0.02, 90, 0.02, standing)
    still = standing_window(*standing, ReferenceParams(), 5.0 - WALK_NOTICE - 0.02, 90, 0.02)
    assert before.t[-1] > 5.0
    np.testing.assert_array_equal(before.hip, still.hip)
    at_notice = session.window(5.0 - WALK_NOTICE, 90, 0.02, standing)
    assert np.abs(at_notice.hip[-1] - still.hip[-1]).max() > 1e-3


def _walk_with_extension(arrival: float, apply_at, steps_now: int = 6, more: int = 3):
    """A walk of straight steps started at 0, then the same plan with `more` steps, arriving at
    `arrival`; windows of 1.8 s sampled every 20 ms from 0 to 6 s."""
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import ReferenceSession
    from biped_planner.step_timing import StepTiming
    longer = straight_footsteps(steps_now + more, 0.1, 0.2)
    timing = StepTiming(0.4, 0.2)
    session = ReferenceSession(ReferenceParams())
    session.set_plan(1, longer[:steps_now + 2], timing, 0.0)
    assert session.start_walk(0.0)
    windows, done = {}, []
    for k in range(301):
        t = round(0.02 * k, 2)
        if abs(t - arrival) < 1e-9:
            done.append(session.set_plan(1, longer, timing, t, apply_at))
        done.append(session.apply_due(t))
        windows[t] = session.window(t, 90, 0.02, None)
    return windows, [d for d in done if d is not None]


def test_an_extension_applies_at_its_stated_time_whenever_it_arrived_before_it():
    """Arriving at 1.0 s or 2.0 s, an extension due at 2.3 s gives the same windows at every
    time: those before 2.3 s are the unextended walk's, the later ones the extended walk's."""
    early, done_early = _walk_with_extension(1.0, 2.3)
    late, done_late = _walk_with_extension(2.0, 2.3)
    plain, _ = _walk_with_extension(99.0, None)
    assert done_early == done_late == ['queued', 'extended']
    for t in early:
        np.testing.assert_array_equal(early[t].hip, late[t].hip)
        np.testing.assert_array_equal(early[t].zmp_min, late[t].zmp_min)
        if t < 2.3:
            np.testing.assert_array_equal(early[t].hip, plain[t].hip)
    assert not np.array_equal(early[2.32].hip, plain[2.32].hip)  # the walk goes on


def test_an_extension_that_comes_after_its_time_applies_on_arrival():
    """Without a stated time (or past it) the splice is at the arrival: the windows change
    from then on, and which steps it replans depends on when that was."""
    stated_late, done = _walk_with_extension(2.5, 2.3)
    on_arrival, done_plain = _walk_with_extension(2.5, None)
    assert done == done_plain == ['extended']
    for t in stated_late:
        np.testing.assert_array_equal(stated_late[t].hip, on_arrival[t].hip)


def test_a_newer_plan_replaces_waiting_changes_which_otherwise_apply_in_time_order():
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.reference_params import ReferenceParams
    from biped_planner.reference_session import ReferenceSession
    from biped_planner.step_timing import StepTiming
    steps = straight_footsteps(9, 0.1, 0.2)
    timing = StepTiming(0.4, 0.2)
    session = ReferenceSession(ReferenceParams())
    session.set_plan(1, steps[:8], timing, 0.0)
    assert session.start_walk(0.0)
    assert session.set_plan(1, steps[:10], timing, 1.0, apply_at=2.3) == 'queued'
    assert session.set_plan(1, steps, timing, 1.2) == 'extended'  # a user's change: at once
    assert session.apply_due(2.4) is None
    assert len(session.reference.footsteps) == len(steps)
    # a change that is not an append (a later landing moved: the planner's goal walk after a
    # step adjustment) waits for its time too, and changes apply in the order of their times
    moved = list(steps)
    moved[-1] = dataclasses.replace(steps[-1], x=steps[-1].x - 0.05)
    further = list(moved)
    further[-1] = dataclasses.replace(steps[-1], x=steps[-1].x - 0.08)
    assert session.set_plan(1, further, timing, 1.3, apply_at=2.5) == 'queued'
    assert session.set_plan(1, moved, timing, 1.31, apply_at=2.3) == 'queued'
    assert session.apply_due(2.29) is None and session.reference.footsteps[-1] == steps[-1]
    assert session.apply_due(2.3) == 'extended'
    assert session.reference.footsteps[-1] == moved[-1]
    assert session.apply_due(2.6) == 'extended'
    assert session.reference.footsteps[-1] == further[-1]
    assert session.set_plan(2, steps[:8], timing, 1.4, apply_at=2.3) == 'stored'
