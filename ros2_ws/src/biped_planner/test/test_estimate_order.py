from biped_planner.estimate_order import ESTIMATE_WAIT, EstimateOrder

PERIOD = 20_000_000  # ns


class Wire:
    """Estimates (their stamps, ns) that arrive at given times of a fake wall clock."""

    def __init__(self, arrivals=()):
        self.now = 100.0
        self.pending = sorted(arrivals, key=lambda a: a[0])  # (wall time s, stamp ns)
        self.slept = 0.0

    def take_all(self):
        due = [stamp for at, stamp in self.pending if at <= self.now]
        self.pending = [(at, stamp) for at, stamp in self.pending if at > self.now]
        return due

    def sleep(self, seconds):
        self.now += seconds
        self.slept += seconds

    def take(self, order, expected_ns):
        return order.take(expected_ns, self.take_all, lambda stamp: stamp, lambda: self.now,
                          self.sleep)


def test_the_estimate_of_the_period_before_answers_at_once_when_it_is_in():
    order, wire = EstimateOrder(PERIOD), Wire([(0.0, 5 * PERIOD)])
    assert wire.take(order, 5 * PERIOD) == ([5 * PERIOD], False) and wire.slept == 0.0


def test_it_waits_for_the_estimate_after_one_was_answered_the_period_before():
    order = EstimateOrder(PERIOD)
    wire = Wire([(0.0, 5 * PERIOD), (100.005, 6 * PERIOD)])  # the second 5 ms late
    assert wire.take(order, 5 * PERIOD) == ([5 * PERIOD], False)
    assert wire.take(order, 6 * PERIOD) == ([6 * PERIOD], False)
    assert 0.004 < wire.slept < 0.006


def test_an_estimate_that_does_not_come_in_the_wait_is_reported_missed_and_answered_later():
    order = EstimateOrder(PERIOD)
    wire = Wire([(0.0, 5 * PERIOD), (100.5, 6 * PERIOD)])
    wire.take(order, 5 * PERIOD)
    assert wire.take(order, 6 * PERIOD) == ([], True)
    assert abs(wire.slept - ESTIMATE_WAIT) < 0.001
    wire.now = 101.0  # it came: the next reference answers it; the estimate of that
    wire.slept = 0.0  # reference's own period is not awaited (the one before it was missed)
    assert wire.take(order, 7 * PERIOD) == ([6 * PERIOD], False) and wire.slept == 0.0


def test_no_wait_when_the_estimates_had_stopped_already():
    """The period before's estimate was not answered (a fall, a reset, a lost controller):
    no estimate is expected, nothing waits."""
    order, wire = EstimateOrder(PERIOD), Wire([(0.0, 5 * PERIOD)])
    wire.take(order, 5 * PERIOD)
    assert wire.take(order, 7 * PERIOD) == ([], False) and wire.slept == 0.0


def test_later_estimates_wait_for_their_reference_and_others_are_answered_now():
    order = EstimateOrder(PERIOD)
    stamps = [5 * PERIOD, 6 * PERIOD, 7 * PERIOD, 9 * PERIOD, 3 * PERIOD]
    wire = Wire([(0.0, s) for s in stamps])
    answered, missed = wire.take(order, 5 * PERIOD)
    # 6 and 7 are the next two periods'; 9 is beyond them (refused by the node), 3 is old
    assert (answered, missed) == ([5 * PERIOD, 9 * PERIOD, 3 * PERIOD], False)
    assert wire.take(order, 6 * PERIOD) == ([6 * PERIOD], False)
    assert wire.take(order, 7 * PERIOD) == ([7 * PERIOD], False)


def test_a_restart_forgets_what_waited_and_what_was_answered():
    order, wire = EstimateOrder(PERIOD), Wire([(0.0, 5 * PERIOD), (0.0, 6 * PERIOD)])
    wire.take(order, 5 * PERIOD)
    order.restart()
    wire.pending = []
    assert wire.take(order, 1 * PERIOD) == ([], False) and wire.slept == 0.0
