"""The paper's push scenario asks for its pushes at the same phase of a step, and a push whose
answer was lost ends the schedule instead of the run."""
import pytest

from biped_tools.scenarios.push import (FIRST_PUSH, INTERVAL, PUSH_PHASE, schedule_pushes,
                                        TIMING)

STEP = sum(TIMING)


class PushService:
    """The session's push: answers from a list; None is a lost answer (TimeoutError)."""

    def __init__(self, answers):
        self.answers, self.requests = list(answers), []

    def push(self, fx, fy=0.0, duration=0.1, at=None):  # GraphSession.push's signature
        self.requests.append((fx, fy, duration, at))
        answer = self.answers.pop(0)
        if answer is None:
            raise TimeoutError('the push service did not answer in 30 s')
        return answer


def test_every_push_starts_a_whole_number_of_steps_after_the_first_single_support():
    service = PushService([True] * 3)
    times, unanswered = schedule_pushes(service, [80.0, 100.0, 120.0], 11.1, -1.0)
    assert unanswered is None
    assert [(fx, fy) for fx, fy, _, _ in service.requests] == \
        [(-80.0, 0.0), (-100.0, 0.0), (-120.0, 0.0)]
    for k, at in enumerate(times):
        steps = (at - PUSH_PHASE - 11.1) / STEP
        assert steps == pytest.approx(round(steps), abs=1e-9)
        assert abs(at - 11.1 - (FIRST_PUSH + k * INTERVAL)) <= STEP / 2 + PUSH_PHASE


def test_a_lost_answer_is_the_last_push_watched_not_an_error_of_the_run():
    service = PushService([True, None, True])
    times, unanswered = schedule_pushes(service, [80.0, 100.0, 120.0], 11.1, 1.0)
    assert len(times) == 2 and len(service.requests) == 2
    assert 'did not answer' in unanswered


def test_a_refused_push_stops_the_run():
    with pytest.raises(RuntimeError, match='push of 100.0 N .* refused'):
        schedule_pushes(PushService([True, False]), [80.0, 100.0], 11.1, 1.0)
