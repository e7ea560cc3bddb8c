import pytest

from biped_planner.footsteps import Footstep
from biped_planner.reference_params import ReferenceParams
from biped_planner.step_timing import StepTiming
from biped_planner.stop_step import committed_step, stated_stop_step, STOP_LEAD, stop_due_at
from biped_planner.walking_reference import WalkingReference

SINGLE, DOUBLE = 0.3, 0.1  # s: the paper's step timing


@pytest.mark.parametrize('double_support, time_left, expected', [
    (False, 0.3, 4), (False, STOP_LEAD, 4), (False, STOP_LEAD - 1e-9, 5), (False, 0.0, 5),
    (True, 0.1, 5), (True, 0.0, 5)])
def test_the_next_step_is_committed_in_a_double_support_and_late_in_a_single_one(
        double_support, time_left, expected):
    assert committed_step(4, double_support, time_left) == expected


def state_at(t: float, walk_start: float):
    """(step_index, double support, time left in the phase) of a walk of single then double
    supports from walk_start: a step counts as completed at the end of its double support."""
    k, into = divmod(t - walk_start, SINGLE + DOUBLE)
    if into < SINGLE:
        return int(k), False, SINGLE - into
    return int(k), True, SINGLE + DOUBLE - into


@pytest.mark.parametrize('walk_start', [0.0, 12.345])
def test_a_stated_stop_ends_the_walk_after_the_step_a_stop_arriving_at_its_time_would(
        walk_start):
    """Answered at the first single support start it is due at, the step that single support
    begins is the one the rule for a stop arriving at the stated time commits (nominal timing,
    every 5 ms over six steps)."""
    for i in range(1, 480):
        stop_time = walk_start + 0.005 * i + 1e-4  # off the phase boundaries by 0.1 ms
        starts = [walk_start + k * (SINGLE + DOUBLE) for k in range(12)]
        answered = next(k for k, start in enumerate(starts)
                        if stop_due_at(start, stop_time, SINGLE))
        assert starts[answered] <= stop_time + SINGLE, 'answered after its step ended'
        assert answered == committed_step(*state_at(stop_time, walk_start)), stop_time


def test_a_stop_stated_at_a_single_support_start_is_due_at_it_despite_float_rounding():
    start = 20.0 + 3 * 0.4  # not exactly representable; stamps are whole nanoseconds
    assert stop_due_at(start - 4e-7, start, SINGLE)
    assert stop_due_at(start, start + SINGLE - STOP_LEAD, SINGLE)
    assert not stop_due_at(start, start + SINGLE - STOP_LEAD + 1e-5, SINGLE)


def test_the_generator_finds_the_single_support_the_planner_answers_a_stated_stop_at():
    """stated_stop_step over a reference's phases is the first single support start the
    planner's rule (stop_due_at, applied as each single support starts) answers the STOP at;
    None once the walk's last single support ends before it."""
    left, right = Footstep(side=0, x=0.0, y=0.1), Footstep(side=1, x=0.0, y=-0.1)
    feet = [left, right] + [right if i % 2 == 0 else left for i in range(6)]
    reference = WalkingReference(feet, StepTiming(SINGLE, DOUBLE), ReferenceParams(),
                                 t_start=10.0)
    starts = [p.t_begin for p in reference.phases if p.kind == 'single_support']
    for stop_time in (9.0, starts[0] + 0.01, starts[2] + SINGLE - STOP_LEAD,
                      starts[2] + SINGLE - STOP_LEAD + 0.001, starts[5] + 0.2):
        expected = next((start for start in starts if stop_due_at(start, stop_time, SINGLE)),
                        None)
        assert stated_stop_step(reference.phases, stop_time, SINGLE) == expected
    assert stated_stop_step(reference.phases, starts[2] + SINGLE - STOP_LEAD + 0.001,
                            SINGLE) == starts[3]
    assert stated_stop_step(reference.phases, starts[-1] + SINGLE, SINGLE) is None
