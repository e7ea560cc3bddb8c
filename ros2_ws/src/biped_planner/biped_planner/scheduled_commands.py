"""Step commands stated for a later time: each takes effect from the first step that starts at
or after its time.

A teleop command changes the steps appended to a continuous plan from then on, and the plan is
extended as each step starts. Applied when its message arrives, a command would change the walk
from whichever step started next, which depends on the machine's load; stated for a time, it
changes it from the first step starting at or after that time, whenever it arrived before then.
Pure Python, time is an argument.
"""
import bisect
import math
from typing import Any, List, Tuple

from biped_planner.errors import InputError

MAX_WAITING = 100  # commands; more waiting at once are refused (a flood, not a schedule)
RESOLUTION = 1e-6  # s: a time this close after a step start counts as that start (ns stamps)


class ScheduledCommands:
    """Commands waiting for their time, kept in time order (equal times in arrival order)."""

    def __init__(self) -> None:
        self._waiting: List[Tuple[float, int, Any]] = []
        self._count = 0

    def __len__(self) -> int:
        return len(self._waiting)

    def add(self, time: float, command: Any) -> None:
        """Keep command until a step starts at or after time (s).

        :raises InputError: for a time that is not finite, or when MAX_WAITING wait already
        """
        if isinstance(time, bool) or not isinstance(time, (int, float)) or \
                not math.isfinite(time):
            raise InputError(f'a scheduled command needs a finite time, got {time!r}')
        if len(self._waiting) >= MAX_WAITING:
            raise InputError(f'{MAX_WAITING} commands are waiting already')
        self._count += 1
        bisect.insort(self._waiting, (float(time), self._count, command))

    def due(self, step_start: float) -> List[Any]:
        """The commands whose time has come for a step starting at step_start (s), in order;
        they are removed."""
        index = bisect.bisect_right([entry[0] for entry in self._waiting],
                                    step_start + RESOLUTION)
        taken, self._waiting = self._waiting[:index], self._waiting[index:]
        return [entry[2] for entry in taken]

    def next_time(self) -> float:
        """Time of the next waiting command (s), inf when none waits."""
        return self._waiting[0][0] if self._waiting else math.inf

    def clear(self) -> int:
        """Drop every waiting command; return how many were dropped."""
        dropped = len(self._waiting)
        self._waiting = []
        return dropped
