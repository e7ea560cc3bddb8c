"""Deadline accounting of a control loop: how many periods' commands were late, and the
latency distribution, as a robot's real-time supervisor keeps them.

A period's command is late when it leaves more than `deadline` after the sensor data it
answers arrived (the servo then runs one more period on the previous setpoints). The count is
over the whole run; the quantiles over the last `window` periods, so that a long run reports
its present, not its start-up.
"""
import bisect
from collections import deque
from dataclasses import dataclass
import math

from biped_mpc.errors import ConfigError


@dataclass(frozen=True)
class DeadlineReport:
    """:param periods: periods recorded; late: those over the deadline; p50, p99, max: latency
    quantiles over the window (s; NaN before the first period)."""

    periods: int
    late: int
    p50: float
    p99: float
    max: float

    @property
    def late_per_10000(self) -> float:
        return 1e4 * self.late / self.periods if self.periods else 0.0


class DeadlineMonitor:
    """:param deadline: the latency budget of one period (s), > 0
    :param window: periods the quantiles are taken over, >= 1
    :raises ConfigError: for a deadline or window out of range
    """

    def __init__(self, deadline: float, window: int = 1000) -> None:
        if not (math.isfinite(deadline) and deadline > 0.0):
            raise ConfigError(f'deadline must be a positive number of seconds, got {deadline}')
        if int(window) != window or window < 1:
            raise ConfigError(f'window must be a positive integer, got {window}')
        self.deadline = float(deadline)
        self._latencies = deque(maxlen=int(window))
        # the window kept sorted as well: the quantiles are read every period, and a
        # percentile of the whole window each time cost 70 us of the controller's cycle
        self._sorted = []
        self._periods = 0
        self._late = 0

    def record(self, latency: float) -> bool:
        """Count one period; :return: whether it was late. A non-finite or negative latency
        (a clock that went back) counts as late: the deadline was not shown to be met."""
        self._periods += 1
        late = not (math.isfinite(latency) and 0.0 <= latency <= self.deadline)
        self._late += late
        if math.isfinite(latency):
            value = max(0.0, float(latency))
            if len(self._latencies) == self._latencies.maxlen:
                del self._sorted[bisect.bisect_left(self._sorted, self._latencies[0])]
            self._latencies.append(value)
            bisect.insort(self._sorted, value)
        return late

    def report(self) -> DeadlineReport:
        if not self._sorted:
            return DeadlineReport(self._periods, self._late, math.nan, math.nan, math.nan)
        return DeadlineReport(self._periods, self._late, self._quantile(0.5),
                              self._quantile(0.99), self._sorted[-1])

    def _quantile(self, q: float) -> float:
        """The q-quantile of the window, interpolated between order statistics as numpy's
        default ('linear') percentile."""
        values = self._sorted
        position = q * (len(values) - 1)
        low = int(math.floor(position))
        high = min(low + 1, len(values) - 1)
        return values[low] + (values[high] - values[low]) * (position - low)
