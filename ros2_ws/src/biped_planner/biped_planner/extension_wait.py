"""Which of the planner's extensions a continuous walk's reference must wait for in lockstep.

The planner extends a continuous (teleop) plan as each step from the second one starts (or sends
the plan of a STOP stated for that step instead), and stamps the extension with that step's
start; the reference generator splices it in at stamp + extension delay. In lockstep nothing
else waits for the planner: on a loaded machine an extension could come after its splice time
and be spliced later, which changes the run. The generator therefore holds the reference of a
time by which an extension is due until the extension has come (or the planner is gone). The
same holds for the plan the planner publishes after a step adjustment (any walk: a teleop walk
steps on from the adjusted landing, a goal walk is planned anew to its goal), stamped with the
adjustment's time. A step's extension that came before an adjustment made while it waited for
its splice is dropped then (it lacks the moved landing), and the planner sends it again: that
one is awaited too. A STOP stated ahead is answered by the planner with the same kind of change
at the start of the step under way at its time (biped_planner.stop_step), in any walk and at any
step, the first two included: that change is awaited as well. Pure Python, time is an argument.
"""
from typing import Optional, Sequence

from biped_planner.reference_phases import PHASE_SINGLE_SUPPORT

FIRST_EXTENDED_STEP = 2  # the phases' step_index of the first step the planner extends at
STAMP_TOLERANCE = 0.03  # s: the state machine's phase start and the reference's agree to this


def awaited_extension(phases: Sequence, t: float, delay: float,
                      newest_extension: Optional[float], continuous: bool = True,
                      adjusted: Sequence[float] = (),
                      adjusted_delay: Optional[float] = None,
                      refreshed: Optional[float] = None,
                      stop_step: Optional[float] = None) -> Optional[float]:
    """The stamp of the latest extension due by t that has not come: a step's start, or a
    step adjustment's time.

    :param phases: the reference's phases (ReferencePhase), in time order
    :param t: the time of the reference about to go out (s)
    :param delay: how long after its stamp an extension is spliced in (s)
    :param newest_extension: stamp of the newest extension received for this plan (s), None
        when none has come
    :param continuous: the planner extends the walk at each step (a teleop walk)
    :param adjusted: times of this plan's step adjustments (s)
    :param adjusted_delay: how long after an adjustment the planner's plan after it is spliced
        in (s); None: delay
    :param refreshed: stamp of the newest step extension (not a plan after an adjustment)
        received since this plan's latest adjustment (s), None when none has come since
    :param stop_step: start of the step at which the planner answers a STOP stated ahead (s),
        None when none is due
    :return: that stamp (s), None when nothing is awaited
    """
    step = None
    for phase in phases if continuous else ():
        if phase.t_begin + delay > t:
            break
        if phase.kind == PHASE_SINGLE_SUPPORT and phase.step_index >= FIRST_EXTENDED_STEP:
            step = phase.t_begin
    after = delay if adjusted_delay is None else adjusted_delay
    due = step
    if stop_step is not None and stop_step + delay <= t and (due is None or stop_step > due):
        due = stop_step
    due_adjusted = max((a for a in adjusted if a + after <= t), default=None)
    if due_adjusted is not None and (due is None or due_adjusted > due):
        due = due_adjusted
    if due is not None and (newest_extension is None or
                            newest_extension < due - STAMP_TOLERANCE):
        return due
    # the step's extension as it was before an adjustment made while it waited is dropped at
    # its splice: the one sent after that adjustment must be in
    if step is not None and any(step + STAMP_TOLERANCE < a < step + delay and a <= t
                                for a in adjusted) and \
            (refreshed is None or refreshed < step - STAMP_TOLERANCE):
        return step
    return None
