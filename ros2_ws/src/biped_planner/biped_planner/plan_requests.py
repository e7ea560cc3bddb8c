"""Requests for footstep plans, and which plan a walk may start on.

The state machine is the one entry point of user intent: it asks the planner for a plan with a
request id (1, 2, ..., wrapping, never 0: 0 marks the planner's own extension of a continuous
plan), the planner accepts or refuses the request and publishes the plan with that request id.
A walk starts only on the plan that answers the latest request to start one; while walking, only
plans of the walk's own plan id are followed. Any other plan is stale and is never walked (the
plan of a request that was superseded, cancelled or answered too late).

Times are arguments: the node passes a monotonic wall time (a request is a round trip between
processes, so its timeout is not measured on the simulated clock).
"""
from dataclasses import dataclass, replace
import enum
from typing import Dict, List, Optional, Tuple

from biped_planner.input_checks import check_number
from biped_planner.walking_state_machine import Phase, WALKING_PHASES

MAX_REQUEST_ID = 2 ** 32 - 1  # request ids are uint32; 0 is the planner's own extension


class RequestKind(enum.IntEnum):
    """What a request carries; the values are those of biped_msgs/PlanWalk's KIND_*."""

    COMMAND = 0   # a walk command (START, GOTO, OMNI, STOP)
    GOAL = 1      # a goal pose
    VELOCITY = 2  # a velocity command (teleop)
    CANCEL = 3    # end the current plan (cmd_vel timeout, lost inputs, reset)


class PlanUse(enum.Enum):
    """What the state machine does with a plan it receives."""

    START = 'start'    # the answer to the pending start request: start the walk on it
    FOLLOW = 'follow'  # the walk's own plan, changed or extended: follow it
    FAILED = 'failed'  # a failed answer to a pending request: report it
    IGNORE = 'ignore'  # stale or somebody else's: never walked


@dataclass(frozen=True)
class PlanRequest:
    """One request to the planner.

    :param request_id: its id, in [1, MAX_REQUEST_ID]
    :param kind: what it carries
    :param command: the walk command kind it serves (biped_msgs/WalkCommand values), for the
        status answered to the user
    :param starts_walk: a walk starts on the plan that answers it
    :param answer_owed: the user still waits for a status about it
    :param sent_at: wall time it was sent (s)
    :param plan_id: the plan id the planner announced when it accepted (0: not yet)
    :param start_time: the clock time the walk it starts begins at, at the earliest (s)
    """

    request_id: int
    kind: RequestKind
    command: int
    starts_walk: bool
    answer_owed: bool
    sent_at: float
    plan_id: int = 0
    start_time: float = 0.0


class PlanRequests:
    """The requests sent to the planner that have not been answered yet.

    :param timeout: a request not answered within this wall time is dropped (s), > 0
    """

    def __init__(self, timeout: float) -> None:
        self.timeout = check_number('timeout', timeout, low=0.0, low_open=True, unit=' s')
        self._pending: Dict[int, PlanRequest] = {}
        self._last_id = 0
        self._start_id: Optional[int] = None

    @property
    def start_pending(self) -> bool:
        """Whether a walk waits for the plan of its request."""
        return self._start_id is not None

    def new(self, kind: RequestKind, command: int, starts_walk: bool, answer_owed: bool,
            wall: float, start_time: float = 0.0) -> Tuple[PlanRequest, Optional[PlanRequest]]:
        """Make a request with a fresh id.

        :param start_time: clock time the walk it starts begins at, at the earliest (s)

        :return: the request, and the start request it supersedes (a newer request to start a
            walk replaces the older one, whose plan will not be walked), or None
        """
        self._last_id = self._last_id % MAX_REQUEST_ID + 1
        request = PlanRequest(self._last_id, RequestKind(kind), int(command), bool(starts_walk),
                              bool(answer_owed), float(wall), start_time=float(start_time))
        superseded = None
        if starts_walk:
            superseded = self._close(self._start_id)
            self._start_id = request.request_id
        self._pending[request.request_id] = request
        return request, superseded

    def get(self, request_id: int) -> Optional[PlanRequest]:
        return self._pending.get(request_id)

    def _close(self, request_id: Optional[int]) -> Optional[PlanRequest]:
        if request_id is None:
            return None
        if request_id == self._start_id:
            self._start_id = None
        return self._pending.pop(request_id, None)

    def accepted(self, request_id: int, plan_id: int) -> Optional[PlanRequest]:
        """The planner accepted a request. A start request stays pending until its plan
        arrives; any other request is done.

        :return: the request (with plan_id), or None if it is no longer pending
        """
        request = self._pending.get(request_id)
        if request is None:
            return None
        request = replace(request, plan_id=int(plan_id))
        if request.starts_walk:
            self._pending[request_id] = request
            return request
        self._close(request_id)
        return request

    def refused(self, request_id: int) -> Optional[PlanRequest]:
        """The planner refused a request (or the call failed): it is done.

        :return: the request, or None if it is no longer pending
        """
        return self._close(request_id)

    def cancel_start(self) -> Optional[PlanRequest]:
        """A stop or a reset: the walk waiting for its plan will not start.

        :return: the cancelled request, or None
        """
        return self._close(self._start_id)

    def expired(self, wall: float) -> List[PlanRequest]:
        """Drop and return the requests older than the timeout at wall time `wall`."""
        late = [r for r in self._pending.values() if wall - r.sent_at > self.timeout]
        for request in late:
            self._close(request.request_id)
        return late

    def use_of_plan(self, request_id: int, plan_id: int, ok: bool, walking: bool,
                    walked_plan_id: int) -> Tuple[PlanUse, Optional[PlanRequest]]:
        """What to do with a plan that arrived.

        :param request_id: the request the plan answers (0: the planner's own extension)
        :param plan_id: the plan's id
        :param ok: the plan succeeded
        :param walking: the robot is walking
        :param walked_plan_id: the plan the walk follows (0: none)
        :return: the use, and the request the plan answers when it closes one
        """
        request = self._pending.get(request_id) if request_id else None
        if walking:
            if ok and walked_plan_id and plan_id == walked_plan_id:
                return PlanUse.FOLLOW, None
            return PlanUse.IGNORE, None
        if request is None:
            return PlanUse.IGNORE, None
        if request.starts_walk and request_id == self._start_id:
            self._close(request_id)
            return (PlanUse.START if ok else PlanUse.FAILED), request
        if not ok:
            self._close(request_id)
            return PlanUse.FAILED, request
        return PlanUse.IGNORE, None


@dataclass(frozen=True)
class ReceivedPlan:
    """What the state machine needs of a footstep plan it received.

    :param plan_id: the plan's id
    :param request_id: the request it answers (0: the planner's own extension)
    :param ok: the plan succeeded
    :param continuous: more steps will follow (teleop)
    :param steps: swing steps in the plan (footsteps but the first two)
    :param first_support: side of the first support foot (biped_planner.sides), None if none
    :param single_support: single support duration of its steps (s)
    :param double_support: double support duration (s)
    :param error_code: the planner's error code (biped_msgs/FootstepPlan ERROR_*)
    :param error_msg: the planner's message
    """

    plan_id: int
    request_id: int
    ok: bool
    continuous: bool = False
    steps: int = 0
    first_support: Optional[int] = None
    single_support: float = 0.0
    double_support: float = 0.0
    error_code: int = 0
    error_msg: str = ''


def walk_request_refusal(phase: int, planner_ready: bool, goto: bool, walk_plan_continuous: bool,
                         stopping: bool) -> Optional[str]:
    """Why a request to start or steer a walk cannot go now, or None if it can.

    :param phase: the walking phase (biped_planner.walking_state_machine.Phase)
    :param planner_ready: a planner serves plan_walk
    :param goto: the request is a goal (GOTO or goal_pose)
    :param walk_plan_continuous: the walk follows a continuous (teleop) plan
    :param stopping: the walk is stopping
    """
    if phase == Phase.FALLEN:
        return 'the robot has fallen: call the reset service (or send RESET) first'
    if goto and not planner_ready:
        return 'no footstep planner (service plan_walk) to plan to the goal'
    if phase not in WALKING_PHASES or not planner_ready:
        return None
    if goto:
        return 'GOTO while walking: send STOP first, then the goal'
    if not walk_plan_continuous or stopping:
        return 'the walk follows a goal plan or is stopping: send STOP and wait for IDLE first'
    return None
