from biped_planner.extension_wait import awaited_extension
from biped_planner.footsteps import Footstep
from biped_planner.reference_params import ReferenceParams
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import WalkingReference

DELAY = 0.35


def in_place_reference(steps=6):
    left, right = Footstep(side=0, x=0.0, y=0.1), Footstep(side=1, x=0.0, y=-0.1)
    feet = [left, right] + [right if i % 2 == 0 else left for i in range(steps)]
    return WalkingReference(feet, StepTiming(0.3, 0.1), ReferenceParams(), t_start=10.0)


def single_support_starts(reference):
    return [p.t_begin for p in reference.phases if p.kind == 'single_support']


def test_the_first_step_is_never_awaited_the_second_from_its_start_plus_the_delay():
    reference = in_place_reference()
    first, second = single_support_starts(reference)[:2]
    assert awaited_extension(reference.phases, first + 1.0 * DELAY, DELAY, None) is None
    assert awaited_extension(reference.phases, second + DELAY - 0.001, DELAY, None) is None
    assert awaited_extension(reference.phases, second + DELAY, DELAY, None) == second


def test_an_extension_stamped_with_the_step_start_ends_the_wait_an_older_one_does_not():
    reference = in_place_reference()
    starts = single_support_starts(reference)
    t = starts[3] + DELAY + 0.01
    assert awaited_extension(reference.phases, t, DELAY, starts[2]) == starts[3]
    assert awaited_extension(reference.phases, t, DELAY, starts[3] - 0.02) is None  # one tick
    assert awaited_extension(reference.phases, t, DELAY, starts[3] + 0.5) is None


def test_after_the_last_step_the_last_one_stays_awaited_until_its_extension_comes():
    reference = in_place_reference(steps=4)
    last = single_support_starts(reference)[-1]
    assert awaited_extension(reference.phases, reference.t_end + 5.0, DELAY, None) == last
    assert awaited_extension(reference.phases, reference.t_end + 5.0, DELAY, last) is None


def test_a_step_adjustment_is_awaited_from_its_time_plus_the_delay_in_any_walk():
    reference = in_place_reference()
    starts = single_support_starts(reference)
    adjusted = starts[3] + 0.1   # the adjuster moved step 3 a tenth into its single support
    # a goal walk (not continuous) awaits no step's extension, only the adjustment's replan
    assert awaited_extension(reference.phases, starts[4] + DELAY, DELAY, None, False) is None
    assert awaited_extension(reference.phases, adjusted + DELAY - 0.001, DELAY, None, False,
                             [adjusted]) is None
    assert awaited_extension(reference.phases, adjusted + DELAY, DELAY, None, False,
                             [adjusted]) == adjusted
    # the replan stamped with the adjustment ends the wait, an older extension does not
    assert awaited_extension(reference.phases, adjusted + DELAY, DELAY, adjusted, False,
                             [adjusted]) is None
    assert awaited_extension(reference.phases, adjusted + DELAY, DELAY, starts[3], True,
                             [adjusted]) == adjusted
    # a second adjustment does not hide the first one's replan, due before it
    second = adjusted + 0.04
    assert awaited_extension(reference.phases, adjusted + DELAY, DELAY, None, False,
                             [adjusted, second]) == adjusted
    assert awaited_extension(reference.phases, second + DELAY, DELAY, adjusted, False,
                             [adjusted, second]) == second
    # a teleop walk: whichever is later is awaited, the next step's start once it is due
    t = starts[4] + DELAY
    assert awaited_extension(reference.phases, t, DELAY, adjusted, True, [adjusted]) == starts[4]


def test_an_adjustment_replan_is_awaited_after_its_own_delay():
    reference = in_place_reference()
    adjusted = single_support_starts(reference)[3] + 0.1
    assert awaited_extension(reference.phases, adjusted + 0.039, DELAY, None, False,
                             [adjusted], 0.04) is None
    assert awaited_extension(reference.phases, adjusted + 0.04, DELAY, None, False,
                             [adjusted], 0.04) == adjusted


def test_a_step_extension_superseded_by_an_adjustment_before_its_splice_is_awaited_again():
    # teleop walk: step 3's extension came, then the adjuster moved the step a tenth into its
    # single support, before that extension's splice (start + 0.35 s), and the planner's replan
    # of the adjustment came; the extension as it was is dropped at its splice, so the one the
    # planner sends after the adjustment is awaited
    reference = in_place_reference()
    start = single_support_starts(reference)[3]
    adjusted = start + 0.1
    t = start + DELAY
    assert awaited_extension(reference.phases, t, DELAY, adjusted, True, [adjusted], 0.04,
                             refreshed=None) == start
    assert awaited_extension(reference.phases, t, DELAY, adjusted, True, [adjusted], 0.04,
                             refreshed=start) is None
    # not before the extension's own splice time
    assert awaited_extension(reference.phases, t - 0.02, DELAY, adjusted, True, [adjusted],
                             0.04, refreshed=None) is None
    # an adjustment after the splice leaves the spliced extension alone: only its replan
    late = start + DELAY + 0.01
    assert awaited_extension(reference.phases, late + 0.04, DELAY, late, True, [late], 0.04,
                             refreshed=None) is None


def test_a_stated_stops_step_is_awaited_in_a_goal_walk_and_at_the_first_two_steps():
    """The planner answers a STOP stated ahead at the start of any step, the first included,
    in any walk: its change is awaited from that start plus the delay, and a later step's
    extension of a continuous walk still is."""
    reference = in_place_reference()
    starts = single_support_starts(reference)
    for k in (0, 1, 4):
        stop_step = starts[k]
        assert awaited_extension(reference.phases, stop_step + DELAY - 0.001, DELAY, None,
                                 False, stop_step=stop_step) is None
        assert awaited_extension(reference.phases, stop_step + DELAY, DELAY, None, False,
                                 stop_step=stop_step) == stop_step
        assert awaited_extension(reference.phases, stop_step + DELAY, DELAY, stop_step, False,
                                 stop_step=stop_step) is None
    # continuous: the extension of the step after the stop's is the one awaited then
    t = starts[3] + DELAY
    assert awaited_extension(reference.phases, t, DELAY, starts[1], True,
                             stop_step=starts[1]) == starts[3]
    assert awaited_extension(reference.phases, t, DELAY, starts[3], True,
                             stop_step=starts[1]) is None
