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
