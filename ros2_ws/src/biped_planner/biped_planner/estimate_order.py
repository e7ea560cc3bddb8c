"""Which of the controller's balance estimates a reference answers, whatever order DDS brought
them and the controller's commands in.

The reference of period t answers the estimate of t - 1 and no later one. The controller sends
that estimate before its command of t - 1, which sends the reference, but DDS does not order
two topics: on a loaded machine the estimate can come second, and the step adjuster would then
answer it a period later in one run than in another. So when the estimate of t - 2 was
answered and the one of t - 1 is not in, the reference waits for it, ESTIMATE_WAIT of wall time
at most (the controller may have stopped estimating: a fall, a reset, its loss). Estimates
stamped up to two periods after t - 1 (the controller can estimate the next period before this
reference goes out) wait for the next reference; any other stamp is answered now (and refused
there if it is wrong). Pure Python: the reader, the clock and the sleep are arguments.
"""
import time
from typing import Callable, List, Sequence, Tuple

# s of wall time a reference waits for the estimate of the period before it
ESTIMATE_WAIT = 0.02
POLL = 0.0002  # s between looks while it waits


class EstimateOrder:
    """The estimates taken but not yet answered, and the newest stamp answered."""

    def __init__(self, period_ns: int) -> None:
        self._period_ns = period_ns
        self._answered_ns = -1  # ns: the newest stamp answered (capped at its reference's)
        self._later: List = []  # taken before their reference: answered with it

    def restart(self) -> None:
        """The clock went back (a reset): nothing answered, nothing waiting."""
        self._answered_ns, self._later = -1, []

    def take(self, expected_ns: int, take_all: Callable[[], Sequence],
             stamp_ns: Callable[[object], int], monotonic: Callable[[], float] = time.monotonic,
             sleep: Callable[[float], None] = time.sleep) -> Tuple[List, bool]:
        """The estimates the reference answering expected_ns (the period before its own, ns)
        answers now, in the order taken.

        :param take_all: returns the estimates received since its last call
        :param stamp_ns: an estimate's stamp (ns)
        :return: (those estimates, whether the one of expected_ns was awaited and did not come
            in ESTIMATE_WAIT: the step adjuster then answers it with a later reference, and the
            run may differ from one on a quieter machine)
        """
        messages = self._later + list(take_all())

        def arrived() -> bool:
            return any(stamp_ns(m) >= expected_ns for m in messages)
        missed = False
        if self._answered_ns == expected_ns - self._period_ns and not arrived():
            deadline = monotonic() + ESTIMATE_WAIT
            while not arrived() and monotonic() < deadline:
                sleep(POLL)
                messages += take_all()
            missed = not arrived()
        horizon = expected_ns + 2 * self._period_ns

        def later(msg) -> bool:
            return expected_ns < stamp_ns(msg) <= horizon
        self._later = [m for m in messages if later(m)]
        answered = [m for m in messages if not later(m)]
        for msg in answered:
            self._answered_ns = max(self._answered_ns, min(stamp_ns(msg), expected_ns))
        return answered, missed
