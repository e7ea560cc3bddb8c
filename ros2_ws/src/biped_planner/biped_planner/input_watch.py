"""Which inputs stopped arriving: the watch over the producers a node depends on.

Two kinds of inputs:

- streams (odometry, references, controller diagnostics) are expected all the time once they
  have been seen: silent for longer than the timeout, they are stale;
- due inputs (the extension of a continuous footstep plan) are expected after an event (a step
  began that the last plan did not extend for): not arrived within the timeout, they are stale.

Silence is measured on two clocks at once, the node's clock (in simulation the simulated time,
the robot's time) and a monotonic wall clock, and a gap counts only when it exceeds the timeout
on both. A simulation that runs faster than real time therefore does not make a live producer
look silent (its messages are spaced in wall time), and a machine too loaded to advance the
simulation does not either (the simulated clock stands still). When the simulated clock itself
stands still for the timeout of wall time, the clock is reported stale, and the streams of the
clock's producer (the simulator's odometry) are judged by wall time alone.

A stale input stays stale until it arrives again. Times are arguments.
"""
from dataclasses import dataclass
from typing import Dict, Optional, Sequence, Tuple

from biped_planner.input_checks import check_number

Stamp = Tuple[float, float]  # (clock time, wall time), s


@dataclass
class _Input:
    due_kind: bool
    seen: Optional[Stamp] = None
    due: Optional[Stamp] = None
    stale: bool = False


class InputWatch:
    """Arrival times of named inputs and which of them are stale.

    :param streams: names of the inputs expected continuously once seen
    :param due_inputs: names of the inputs expected only when due()
    :param timeout: silence that makes an input stale (s, on both clocks), > 0
    :param clock_name: name to report when the clock stands still (None: the clock is not
        watched, e.g. on wall time)
    :param clock_sources: streams published by the clock's producer
    :raises ConfigError: for a timeout that is not positive, or an unknown clock source
    """

    def __init__(self, streams: Sequence[str], due_inputs: Sequence[str] = (),
                 timeout: float = 0.5, clock_name: Optional[str] = None,
                 clock_sources: Sequence[str] = ()) -> None:
        self.timeout = check_number('timeout', timeout, low=0.0, low_open=True, unit=' s')
        self._inputs: Dict[str, _Input] = {name: _Input(False) for name in streams}
        self._inputs.update({name: _Input(True) for name in due_inputs})
        unknown = [name for name in clock_sources if name not in streams]
        if unknown:
            from biped_planner.errors import ConfigError
            raise ConfigError(f'clock sources {unknown} are not streams {list(streams)}')
        self._clock_name = clock_name
        self._clock_sources = tuple(clock_sources)
        self._clock: Optional[Stamp] = None   # clock time and the wall time it last changed
        self._clock_ticked = False

    def arrived(self, name: str, t: float, wall: float) -> None:
        """An input arrived at clock time t, wall time `wall`: it is live and no longer due."""
        item = self._inputs[name]
        item.seen, item.due, item.stale = (t, wall), None, False

    def due(self, name: str, t: float, wall: float) -> None:
        """A due input is expected from now on (the earliest call counts until it arrives)."""
        item = self._inputs[name]
        if item.due is None:
            item.due = (t, wall)

    def withdraw(self, name: str) -> None:
        """A due input is no longer expected; one already stale stays so until it arrives."""
        item = self._inputs[name]
        if not item.stale:
            item.due = None

    def is_due(self, name: str) -> bool:
        return self._inputs[name].due is not None

    def clock(self, t: float, wall: float) -> None:
        """The node's clock reads t at wall time `wall` (call it before check())."""
        if self._clock is None:
            self._clock = (t, wall)
        elif t != self._clock[0]:
            self._clock, self._clock_ticked = (t, wall), True

    def clock_stopped(self, wall: float) -> bool:
        """Whether a watched clock that has run stands still for longer than the timeout."""
        return self._clock_name is not None and self._clock_ticked and \
            wall - self._clock[1] > self.timeout

    def check(self, t: float, wall: float) -> Tuple[str, ...]:
        """:return: the names of the stale inputs (in the order given, the clock last)."""
        frozen = self.clock_stopped(wall)
        stale = []
        for name, item in self._inputs.items():
            since = item.due if item.due_kind else item.seen
            if not item.stale and since is not None:
                gap = wall - since[1]
                if not (frozen and name in self._clock_sources):
                    gap = min(gap, t - since[0])
                item.stale = gap > self.timeout
            if item.stale:
                stale.append(name)
        if frozen:
            stale.append(self._clock_name)
        return tuple(stale)
