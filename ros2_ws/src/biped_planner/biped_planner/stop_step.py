"""Which step a STOP lets the walk finish before its closing step, for a STOP that arrives now
and for one stated for a later time.

A STOP ends a planned walk after the step under way and one closing step with the feet side by
side. From its double support on, or less than STOP_LEAD before it, the next step counts as
under way: the plan changes at the reference generator a little after it is made, and the next
step's swing must not be changed once it started. A STOP answered when it arrives therefore
ends the walk at a step that depends on when the message got through; one stated for time t is
answered at the start of the single support that is under way at t by that rule (the first one
whose end is at least STOP_LEAD after t), from that step's own walking_state, so a scripted
trial stops at the same step, with the same plan stamp, on a quiet and on a loaded machine.
The reference generator finds that single support in its own phases to wait for the plan
answering the STOP (stated_stop_step). Pure Python, times are arguments.
"""
from typing import Optional, Sequence

from biped_planner.reference_phases import PHASE_SINGLE_SUPPORT
from biped_planner.scheduled_commands import RESOLUTION

# s: less than this before the end of a single support, the next step is committed
STOP_LEAD = 0.1


def committed_step(step_index: int, double_support: bool, time_left: float) -> int:
    """The last step the walk takes before the closing one.

    :param step_index: the walking_state's step index (steps completed)
    :param double_support: the walk is in a double support
    :param time_left: s left in the current phase
    """
    if double_support or time_left < STOP_LEAD:
        return step_index + 1
    return step_index


def stop_due_at(single_support_start: float, stop_time: float, single_support: float) -> bool:
    """Whether the STOP stated for stop_time ends the walk after the step whose single support
    starts at single_support_start (s), or after an earlier one: the walk's first single
    support with this true is the one the STOP is answered at.

    :param single_support: the plan's single support duration (s); a late or early landing
        moves a step's end, not this rule, so the answer is the same in every run
    """
    return single_support_start + single_support - STOP_LEAD >= stop_time - RESOLUTION


def stated_stop_step(phases: Sequence, stop_time: float,
                     single_support: float) -> Optional[float]:
    """The start (s) of the single support a STOP stated for stop_time is answered at: the
    first of phases (ReferencePhase, in time order) with stop_due_at; None when the walk ends
    before (then nothing answers it).

    :param single_support: the plan's single support duration (s)
    """
    for phase in phases:
        if phase.kind == PHASE_SINGLE_SUPPORT and \
                stop_due_at(phase.t_begin, stop_time, single_support):
            return phase.t_begin
    return None
