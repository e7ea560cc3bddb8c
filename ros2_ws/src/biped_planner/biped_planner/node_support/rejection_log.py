"""Log lines for refused inputs: every kind of refusal is named, none floods the log.

rclpy's throttle_duration_sec throttles a call site: one line for all the refusals a node logs
from one place, so the second kind of bad input within the period is never named. Here each
(topic, kind) is limited on its own; the kind is the reason with its numbers taken out, so a
stream of the same bad value logs once per period while a new kind logs at once.
"""
import re
import time
from typing import Callable, Dict, Tuple

MAX_KINDS = 256
_NUMBER = re.compile(r'[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|nan|inf', re.IGNORECASE)


class RejectionLog:
    """Logs "<topic> rejected: <reason>", at most once per period for each (topic, kind).

    :param log: the logging function (e.g. node.get_logger().error)
    :param period: wall seconds between two lines of one (topic, kind)
    :param clock: wall clock (s), monotonic
    """

    def __init__(self, log: Callable[[str], None], period: float = 2.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self._log = log
        self._period = period
        self._clock = clock
        self._last: Dict[Tuple[str, str], float] = {}
        self._suppressed: Dict[Tuple[str, str], int] = {}

    def __call__(self, topic: str, reason) -> None:
        reason = str(reason)
        key = (topic, _NUMBER.sub('#', reason))
        now = self._clock()
        last = self._last.get(key)
        if last is not None and now - last < self._period:
            self._suppressed[key] = self._suppressed.get(key, 0) + 1
            return
        more = self._suppressed.pop(key, 0)
        if len(self._last) >= MAX_KINDS:  # kinds made of arbitrary text: forget the old ones
            self._last = {k: t for k, t in self._last.items() if now - t < self._period}
        self._last[key] = now
        self._log(f'{topic} rejected: {reason}' +
                  (f' ({more} more like it since the last line)' if more else ''))
