import pytest

from biped_planner.errors import ConfigError
from biped_planner.plan_requests import (MAX_REQUEST_ID, PlanRequests, PlanUse, RequestKind,
                                         walk_request_refusal)
from biped_planner.walk_command import CommandKind
from biped_planner.walking_state_machine import Phase

START, GOTO, OMNI, STOP = (int(k) for k in (CommandKind.START, CommandKind.GOTO,
                                             CommandKind.OMNI, CommandKind.STOP))


def start_request(requests, wall=0.0, command=START):
    request, _ = requests.new(RequestKind.COMMAND, command, True, True, wall)
    return request


def test_request_ids_count_from_one_and_never_give_zero_when_they_wrap():
    requests = PlanRequests(2.0)
    ids = [requests.new(RequestKind.CANCEL, STOP, False, False, 0.0)[0].request_id
           for _ in range(3)]
    assert ids == [1, 2, 3]
    requests._last_id = MAX_REQUEST_ID - 1
    ids = [requests.new(RequestKind.CANCEL, STOP, False, False, 0.0)[0].request_id
           for _ in range(3)]
    assert ids == [MAX_REQUEST_ID, 1, 2]


def test_a_walk_starts_only_on_the_plan_of_its_own_request():
    requests = PlanRequests(2.0)
    request = start_request(requests)
    assert requests.start_pending
    # a plan of no request (the planner's own extension) and one of another request: stale
    assert requests.use_of_plan(0, 4, True, False, 0)[0] == PlanUse.IGNORE
    assert requests.use_of_plan(request.request_id + 7, 4, True, False, 0)[0] == PlanUse.IGNORE
    assert requests.start_pending
    use, answered = requests.use_of_plan(request.request_id, 5, True, False, 0)
    assert use == PlanUse.START and answered == request
    assert not requests.start_pending
    # the same plan again (latched, or a duplicate) does not start a second walk
    assert requests.use_of_plan(request.request_id, 5, True, False, 0)[0] == PlanUse.IGNORE


def test_a_newer_start_request_supersedes_the_older_whose_plan_is_then_stale():
    requests = PlanRequests(2.0)
    first = start_request(requests, command=GOTO)
    second, superseded = requests.new(RequestKind.VELOCITY, OMNI, True, True, 0.1)
    assert superseded == first
    assert requests.use_of_plan(first.request_id, 1, True, False, 0)[0] == PlanUse.IGNORE
    assert requests.use_of_plan(second.request_id, 2, True, False, 0)[0] == PlanUse.START


def test_while_walking_only_the_walks_own_plan_is_followed():
    requests = PlanRequests(2.0)
    assert requests.use_of_plan(0, 3, True, True, 3) == (PlanUse.FOLLOW, None)
    assert requests.use_of_plan(9, 3, True, True, 3) == (PlanUse.FOLLOW, None)
    assert requests.use_of_plan(0, 4, True, True, 3)[0] == PlanUse.IGNORE
    assert requests.use_of_plan(0, 3, False, True, 3)[0] == PlanUse.IGNORE  # failed
    assert requests.use_of_plan(0, 0, True, True, 0)[0] == PlanUse.IGNORE  # walk without plan


def test_a_failed_plan_answers_its_request():
    requests = PlanRequests(2.0)
    request = start_request(requests, command=GOTO)
    assert requests.use_of_plan(request.request_id, 2, False, False, 0) == (PlanUse.FAILED,
                                                                            request)
    assert not requests.start_pending


def test_acceptance_keeps_a_start_request_waiting_for_its_plan_and_closes_the_others():
    requests = PlanRequests(2.0)
    start = start_request(requests)
    steer, _ = requests.new(RequestKind.VELOCITY, OMNI, False, True, 0.0)
    assert requests.accepted(start.request_id, 8).plan_id == 8
    assert requests.start_pending
    assert requests.accepted(steer.request_id, 8) is not None
    assert requests.get(steer.request_id) is None
    assert requests.accepted(steer.request_id, 8) is None  # answered once
    assert requests.refused(start.request_id) is not None
    assert requests.refused(start.request_id) is None
    assert not requests.start_pending


def test_requests_not_answered_in_time_expire_once():
    requests = PlanRequests(2.0)
    early = start_request(requests, wall=10.0)
    late, _ = requests.new(RequestKind.CANCEL, STOP, False, False, 11.5)
    assert requests.expired(11.9) == []
    assert requests.expired(12.1) == [early]
    assert not requests.start_pending
    assert requests.expired(14.0) == [late]
    assert requests.expired(20.0) == []


def test_a_stop_cancels_the_walk_waiting_for_its_plan():
    requests = PlanRequests(2.0)
    request = start_request(requests)
    assert requests.cancel_start() == request
    assert requests.cancel_start() is None
    assert requests.use_of_plan(request.request_id, 1, True, False, 0)[0] == PlanUse.IGNORE


def test_the_timeout_must_be_positive():
    with pytest.raises(ConfigError, match='timeout'):
        PlanRequests(0.0)


@pytest.mark.parametrize('phase, planner, goto, continuous, stopping, words', [
    (Phase.IDLE, True, True, False, False, None),
    (Phase.IDLE, False, False, False, False, None),           # walks in place
    (Phase.IDLE, False, True, False, False, 'no footstep planner'),
    (Phase.FALLEN, True, False, False, False, 'fallen'),
    (Phase.SINGLE_SUPPORT, True, True, True, False, 'GOTO while walking'),
    (Phase.SINGLE_SUPPORT, True, False, True, False, None),  # steer a teleop walk
    (Phase.DOUBLE_SUPPORT, True, False, False, False, 'goal plan or is stopping'),
    (Phase.SINGLE_SUPPORT, True, False, True, True, 'goal plan or is stopping'),
    (Phase.INITIALIZE, False, False, False, True, None),     # no planner: cancels the stop
])
def test_when_a_walk_request_is_refused(phase, planner, goto, continuous, stopping, words):
    refusal = walk_request_refusal(phase, planner, goto, continuous, stopping)
    assert refusal is None if words is None else words in refusal
