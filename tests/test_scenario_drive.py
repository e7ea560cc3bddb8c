"""trial.drive with a held clock: the decision the clock waits for is retried while it waits.

A CI run's disk trial hung for 300 s: the session held the paced clock for a step's command,
the plan it waited for did not arrive, and its wall-time fallback was only looked at on a new
sim time, which the held clock never gave."""
from biped_tools.scenarios import trial


class HeldClockSession:
    """A session whose sim time stands still; spin_until turns the predicate `turns` times."""

    def __init__(self, pace_limit, turns=50):
        self.pace_limit, self.turns = pace_limit, turns

    def sim_time(self):
        return 3.0

    def fallen(self):
        return False

    def spin_until(self, predicate, timeout, what='condition'):
        for _ in range(self.turns):
            if predicate():
                return True
        return predicate()


def run(session, decide_on_call):
    calls = []

    def on_time(t):
        calls.append(t)
        return len(calls) >= decide_on_call

    done = trial.drive(session, on_time, 10.0, lambda session, note='': None)
    return done, calls


def test_a_clock_held_for_a_decision_calls_on_time_again_until_it_decides():
    done, calls = run(HeldClockSession(pace_limit=2.9), decide_on_call=7)
    assert done and calls == [3.0] * 7


def test_a_clock_not_held_calls_on_time_once_per_sim_time():
    done, calls = run(HeldClockSession(pace_limit=None), decide_on_call=7)
    assert not done and calls == [3.0]
