"""A trial's graph that does not come up in time is started once more (no ROS: a test double
stands in for GraphSession)."""
import pytest

from biped_tools.scenarios import trial as trial_module
from biped_tools.scenarios.trial import GRAPH_ATTEMPTS, graph_for, HOLD_AT, Trial


class SlowGraph:
    """GraphSession's context protocol; the first `failures` graphs never get ready."""
    started, closed, resumed, hold_at = [], [], [], []

    def __init__(self, domain_id, **kwargs):
        self.number = len(SlowGraph.started)
        SlowGraph.started.append(domain_id)
        SlowGraph.hold_at.append(kwargs.get('hold_at'))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        SlowGraph.closed.append(self.number)
        return False

    def wait_until_ready(self):
        if self.number < SlowGraph.failures:
            raise TimeoutError('graph not ready after 60.0 s')

    def resume_clock(self):
        SlowGraph.resumed.append(self.number)
        return 'the clock resumes at t=2.00 s'


@pytest.fixture
def slow_graph(monkeypatch):
    SlowGraph.started, SlowGraph.closed, SlowGraph.resumed, SlowGraph.hold_at = [], [], [], []
    monkeypatch.setattr(trial_module, 'GraphSession', SlowGraph)
    return SlowGraph


def make_trial(tmp_path, lines):
    return Trial('push', 'three_mass', 'x', tmp_path, 42, record=False, log=lines.append)


def test_a_graph_that_is_not_ready_is_started_again_and_the_trial_runs(tmp_path, slow_graph):
    slow_graph.failures = 1
    lines = []
    with graph_for(make_trial(tmp_path, lines)) as session:
        assert session.number == 1
    assert slow_graph.started == [42, 42] and slow_graph.closed == [0, 1]
    assert any('started again' in line for line in lines)
    # the clock holds at HOLD_AT in every graph; only the ready one is let run on
    assert slow_graph.hold_at == [HOLD_AT, HOLD_AT]
    assert slow_graph.resumed == [1]


def test_after_the_last_attempt_the_timeout_is_raised(tmp_path, slow_graph):
    slow_graph.failures = GRAPH_ATTEMPTS
    with pytest.raises(TimeoutError):
        with graph_for(make_trial(tmp_path, [])):
            pass
    assert len(slow_graph.started) == GRAPH_ATTEMPTS == len(slow_graph.closed)
