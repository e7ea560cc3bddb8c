"""The walking state machine of the paper's architecture (section "Architecture").

Idle -> Initialize -> Single Support <-> Double Support -> Idle, and Fallen from any phase.
Transitions come from timers (the phase durations of the step timing) and conditions (a start or
stop request, the end of the footstep plan, a fall detected by biped_planner.fall_detector, a
reset). Every reset starts a new epoch: the consumers of the state re-initialise from the sensors.
Time is always an argument.
"""
from dataclasses import dataclass, field, replace
import enum
from typing import List, Optional

from biped_planner.errors import CommandError, ConfigError
from biped_planner.input_checks import check_number
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.sides import other_side, SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT


class Phase(enum.IntEnum):
    """Walking phases; the values are those of biped_msgs/WalkingState."""

    IDLE = 0
    INITIALIZE = 1
    SINGLE_SUPPORT = 2
    DOUBLE_SUPPORT = 3
    FALLEN = 4


WALKING_PHASES = (Phase.INITIALIZE, Phase.SINGLE_SUPPORT, Phase.DOUBLE_SUPPORT)
# WalkingStatus.reason of a single support retimed mid-step
MOVED_REASON = 'touchdown moved by the step adjuster'
EARLY_REASON = 'the swing foot met the ground early'


class Support(enum.IntEnum):
    """Which foot carries the robot (biped_planner.sides, the values of biped_msgs)."""

    LEFT = SUPPORT_LEFT
    RIGHT = SUPPORT_RIGHT
    DOUBLE = SUPPORT_DOUBLE


@dataclass(frozen=True)
class StateMachineParams:
    """Timing and first support foot of the walking state machine (ranges in each parameter())."""

    initialize_duration: float = parameter(
        1.0, 'time to shift the COM over the first support foot (s)', low=0.1, high=5.0)
    single_support: float = parameter(0.4, 'default single support duration (s)',
                                      low=0.1, high=5.0)
    double_support: float = parameter(0.1, 'default double support duration (s)',
                                      low=0.02, high=5.0)
    first_support: Support = parameter(
        Support.RIGHT, 'first support foot when no plan says: 0 left, 1 right', low=0, high=1)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        if self.first_support not in (Support.LEFT, Support.RIGHT):
            raise ConfigError(f'StateMachineParams.first_support must be LEFT or RIGHT, got '
                              f'{self.first_support!r}')


@dataclass(frozen=True)
class WalkingStatus:
    """A snapshot of the state machine.

    :param phase: the current phase
    :param support: the foot (or feet) carrying the robot
    :param step_index: steps completed since the start request
    :param phase_start: clock time at which the phase began (s)
    :param phase_duration: duration of the phase's timer (s); 0 for Idle and Fallen
    :param walk_start: clock time of the start request that began this walk (s)
    :param stop_requested: a stop was requested and the current step is being finished
    :param reason: why the last transition happened
    :param epoch: number of resets so far
    """

    phase: Phase = Phase.IDLE
    support: Support = Support.DOUBLE
    step_index: int = 0
    phase_start: float = 0.0
    phase_duration: float = 0.0
    walk_start: float = 0.0
    stop_requested: bool = False
    reason: str = 'initial state'
    epoch: int = 0

    def time_in_phase(self, t: float) -> float:
        """:return: seconds since the phase began, at clock time t."""
        return max(0.0, t - self.phase_start)

    @property
    def fallen(self) -> bool:
        return self.phase == Phase.FALLEN


@dataclass
class _Timing:
    single_support: float
    double_support: float


@dataclass
class WalkingStateMachine:
    """Walking phases driven by timers and conditions.

    A walk is Initialize (shift the COM over the first support foot), then steps: a step is a
    single support on one foot (the other swings) followed by a double support, after which the
    feet swap roles. A walk ends in Idle at the end of a double support when the footstep plan
    has no step left, or when a stop was requested and no planner drives the walk; a planner
    answers a stop with a plan that ends after the current step and one closing step (feet side
    by side), so a planned walk always ends on its plan, unless the stop says the planner does
    not answer. Fallen is entered from any phase; reset() leaves it (or re-initialises a
    standing robot) and is refused while walking.

    :param params: timing and first support foot
    """

    params: StateMachineParams = field(default_factory=StateMachineParams)

    def __post_init__(self) -> None:
        self._status = WalkingStatus()
        self._timing = _Timing(self.params.single_support, self.params.double_support)
        self._steps_in_plan: Optional[int] = None
        self._plan_driven = False
        self._first_support = Support(self.params.first_support)

    @property
    def status(self) -> WalkingStatus:
        return self._status

    @property
    def single_support(self) -> float:
        return self._timing.single_support

    @property
    def double_support(self) -> float:
        return self._timing.double_support

    def set_timing(self, single_support: float, double_support: float) -> None:
        """Change the step timing; it applies from the next phase on.

        :raises CommandError: if a duration is not finite or out of range
        """
        try:
            replace(self.params, single_support=single_support, double_support=double_support)
        except ConfigError as error:
            raise CommandError(str(error)) from error
        self._timing = _Timing(float(single_support), float(double_support))

    def set_step_time(self, step_time: float) -> None:
        """Scale single and double support to a new step duration, keeping their ratio.

        :raises CommandError: if step_time is not finite and positive, or out of range
        """
        check_number('step_time', step_time, low=0.0, low_open=True, unit=' s',
                     error=CommandError)
        ratio = self._timing.single_support / (
            self._timing.single_support + self._timing.double_support)
        self.set_timing(step_time * ratio, step_time * (1.0 - ratio))

    def set_plan(self, steps: Optional[int], first_support: Optional[Support] = None,
                 planned: bool = False) -> None:
        """Set how many steps the current footstep plan has (None: walk until stopped).

        :param steps: number of swing steps in the plan, counted from the start of the walk
        :param first_support: first support foot of the plan (applies at the next start)
        :param planned: a planner drives the walk: a stop ends it on the plan's closing step
        :raises CommandError: if steps is negative
        """
        if steps is not None and steps < 0:
            raise CommandError(f'steps must be >= 0 or None, got {steps}')
        self._steps_in_plan = steps
        self._plan_driven = planned
        if first_support is not None:
            self._first_support = Support(first_support)

    def retime_single_support(self, step_index: int, end: float,
                              reason: str = MOVED_REASON) -> bool:
        """The touchdown of the step under way moved (the step adjuster, or an early landing):
        its single support ends at `end` (the phases after it keep their durations, as in the
        adjusted reference).

        :param step_index: the adjusted step
        :param end: the new end of its single support (clock time, s); already past: the next
            update() ends it
        :param reason: the status's reason (MOVED_REASON, EARLY_REASON)
        :return: whether it applied (False: the machine is not in that step's single support)
        :raises CommandError: if end is not finite
        """
        check_number('end', end, unit=' s', error=CommandError)
        status = self._status
        if status.phase != Phase.SINGLE_SUPPORT or status.step_index != step_index or \
                end <= status.phase_start:
            return False
        self._status = replace(status, phase_duration=float(end) - status.phase_start,
                               reason=reason)
        return True

    def hold_single_support(self, step_index: int, end: float) -> bool:
        """A late landing: the single support of step_index lasts until `end`.

        In that step's single support it is retimed (as retime_single_support); in the double
        support its timer began at the planned landing (the hold comes a period or two after
        it), that double support was not one: the single support starts again, from the
        planned landing to `end`. A second call with an earlier end is the touchdown.

        :param step_index: the held step
        :param end: the new end of its single support (clock time, s)
        :return: whether it applied (False: the machine is in another step or phase)
        :raises CommandError: if end is not finite
        """
        check_number('end', end, unit=' s', error=CommandError)
        status = self._status
        if status.step_index != step_index or end <= status.phase_start:
            return False
        reason = 'single support held: the swing foot has not met the ground'
        if status.phase == Phase.SINGLE_SUPPORT:
            self._status = replace(status, phase_duration=float(end) - status.phase_start,
                                   reason=reason)
            return True
        if status.phase == Phase.DOUBLE_SUPPORT:
            self._status = replace(status, phase=Phase.SINGLE_SUPPORT,
                                   support=self.support_of_step(step_index),
                                   phase_duration=float(end) - status.phase_start,
                                   reason=reason)
            return True
        return False

    def request_start(self, t: float) -> List[WalkingStatus]:
        """Start walking (from Idle), or cancel a pending stop (while walking).

        :raises CommandError: if the robot has fallen
        """
        status = self._status
        if status.phase == Phase.FALLEN:
            raise CommandError('cannot start: the robot has fallen; send RESET once it stands')
        if status.phase == Phase.IDLE:
            return [self._enter(Phase.INITIALIZE, t, 'start requested', step_index=0,
                                walk_start=t, stop_requested=False)]
        if status.stop_requested:
            self._status = replace(status, stop_requested=False, reason='stop cancelled')
        return []

    def request_stop(self, t: float, reason: str = 'stop requested',
                     unplanned: bool = False) -> List[WalkingStatus]:
        """Stop walking: finish the current step into double support, then Idle.

        :param reason: why, for the status
        :param unplanned: end after the current step even if a planner drives the walk (the
            planner does not answer, so no closing plan will come)
        """
        status = self._status
        if unplanned:
            self._plan_driven = False
        if status.phase == Phase.INITIALIZE:
            return [self._enter(Phase.IDLE, t, f'{reason} before the first step')]
        if status.phase in (Phase.SINGLE_SUPPORT, Phase.DOUBLE_SUPPORT):
            self._status = replace(status, stop_requested=True, reason=reason)
        return []

    def report_fall(self, t: float, reason: str = 'fall detected') -> List[WalkingStatus]:
        """Enter Fallen (from any phase but Fallen)."""
        if self._status.phase == Phase.FALLEN:
            return []
        return [self._enter(Phase.FALLEN, t, reason, support=Support.DOUBLE)]

    def reset(self, t: float) -> List[WalkingStatus]:
        """Start a new epoch in Idle: leave Fallen (the robot stands again) or re-initialise a
        standing robot.

        :raises CommandError: while walking (Initialize, Single or Double support)
        """
        phase = self._status.phase
        if phase in WALKING_PHASES:
            raise CommandError(f'cannot reset while walking ({phase.name}): send STOP and wait '
                               'for IDLE')
        reason = 'reset after a fall' if phase == Phase.FALLEN else 'reset'
        return [self._enter(Phase.IDLE, t, reason, step_index=0,
                            epoch=self._status.epoch + 1)]

    def update(self, t: float) -> List[WalkingStatus]:
        """Advance the timers to clock time t.

        Several transitions can happen in one call when t jumped past more than one phase.

        :param t: clock time (s), not earlier than the start of the current phase
        :return: the status after each transition, in order (empty if none happened)
        """
        check_number('time t', t, error=CommandError)
        transitions = []
        while True:
            status = self._status
            if status.phase in (Phase.IDLE, Phase.FALLEN):
                break
            end = status.phase_start + status.phase_duration
            if t < end:
                break
            transitions.append(self._after_timer(end))
        return transitions

    def _after_timer(self, t: float) -> WalkingStatus:
        status = self._status
        if status.phase == Phase.INITIALIZE:
            if self._steps_in_plan == 0:
                return self._enter(Phase.IDLE, t, 'the plan has no step')
            return self._enter(Phase.SINGLE_SUPPORT, t, 'COM over the first support foot',
                               support=self._first_support)
        if status.phase == Phase.SINGLE_SUPPORT:
            return self._enter(Phase.DOUBLE_SUPPORT, t, 'swing foot landed',
                               support=Support.DOUBLE)
        # End of a double support: one step done.
        steps = status.step_index + 1
        if status.stop_requested and not self._plan_driven:
            return self._enter(Phase.IDLE, t, 'stopped after the step', step_index=steps)
        if self._steps_in_plan is not None and steps >= self._steps_in_plan:
            return self._enter(Phase.IDLE, t, 'plan finished', step_index=steps)
        return self._enter(Phase.SINGLE_SUPPORT, t, 'next step', step_index=steps,
                           support=self.support_of_step(steps))

    def support_of_step(self, step_index: int) -> Support:
        """:return: the support foot of single support number step_index (0-based)."""
        first = self._first_support
        return first if step_index % 2 == 0 else Support(other_side(first))

    def _enter(self, phase: Phase, t: float, reason: str, **changes) -> WalkingStatus:
        durations = {
            Phase.INITIALIZE: self.params.initialize_duration,
            Phase.SINGLE_SUPPORT: self._timing.single_support,
            Phase.DOUBLE_SUPPORT: self._timing.double_support,
        }
        changes.setdefault('support', Support.DOUBLE)
        if phase in (Phase.IDLE, Phase.FALLEN):
            changes['stop_requested'] = False
        self._status = replace(self._status, phase=phase, phase_start=t,
                               phase_duration=durations.get(phase, 0.0), reason=reason,
                               **changes)
        return self._status
