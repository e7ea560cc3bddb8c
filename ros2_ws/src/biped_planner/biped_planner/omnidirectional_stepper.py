"""Footsteps from walk commands, without a path: the paper's tele-operation / omnidirectional mode.

A command is the step action per step: step length X (forward), step width Y (sideways, left
positive) and turn alpha (counter-clockwise positive), or a velocity (vx, vy, wz) multiplied by
the step time. Every command passes through a first-order lag filter (one update per step).

The feet state is the paper's s = (x_l, y_l, theta_l, phi_l, x_r, y_r, theta_r, phi_r). The body
frame is the point between the feet, in line with the last landing: on each step
(X, Y, alpha) the body heading turns by alpha and the body moves by (X, Y) expressed in the
heading halfway through the turn; the swing foot lands at d = step_width / 2 to its side of the
new body pose, clamped to the kinematic limits relative to the stance foot. Then the state
transits, the footstep is saved and phi_l, phi_r toggle. Consecutive footsteps are X apart
along the heading (the ZMP moves by X per step), as in footsteps.straight_footsteps.
"""
from dataclasses import dataclass
import math
from typing import Callable, List, Optional, Sequence, Tuple

from biped_planner.errors import CommandError, ConfigError
from biped_planner.footsteps import Footstep
from biped_planner.input_checks import check_number, check_side, check_type
from biped_planner.feet_state import FeetState
from biped_planner.kinematic_limits import KinematicLimits
from biped_planner.lag_filter import FirstOrderLag
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.pose2d import Pose2D
from biped_planner.sides import LEFT


@dataclass(frozen=True)
class StepCommand:
    """Step action for one step.

    :param step_length: X, forward displacement per step (m)
    :param step_width: Y, sideways displacement per step, left positive (m)
    :param step_angle: alpha, heading change per step, counter-clockwise positive (rad)
    """

    step_length: float = 0.0
    step_width: float = 0.0
    step_angle: float = 0.0

    def __post_init__(self) -> None:
        for name in ('step_length', 'step_width', 'step_angle'):
            check_number(f'StepCommand.{name}', getattr(self, name), error=CommandError)


def command_from_twist(vx: float, vy: float, wz: float, step_time: float) -> StepCommand:
    """Convert a body velocity to the per-step action (velocity times step time).

    :param vx: forward velocity (m/s)
    :param vy: sideways velocity, left positive (m/s)
    :param wz: yaw rate, counter-clockwise positive (rad/s)
    :param step_time: duration of one step (s), > 0
    :return: the step command
    :raises CommandError: if a velocity is not finite
    :raises ConfigError: if step_time is not a finite number > 0
    """
    check_number('step_time', step_time, low=0.0, low_open=True, unit=' s')
    for name, value in (('vx', vx), ('vy', vy), ('wz', wz)):
        check_number(name, value, error=CommandError)
    return StepCommand(vx * step_time, vy * step_time, wz * step_time)


@dataclass(frozen=True)
class StepperParams:
    """Parameters of the omnidirectional stepper (each field's range is in its parameter()).

    :param limits: kinematic limits between consecutive footsteps
    """

    step_width: float = parameter(0.2, 'nominal distance between the sole centres, 2 d (m)',
                                  low=0.0, high=1.0, low_open=True)
    lag_time_constant: float = parameter(
        0.5, 'tau of the lag filter on the commands (s); 0: no filtering', low=0.0, high=100.0)
    max_step_length: float = parameter(0.2, '|X| bound of a step command (m)',
                                       low=0.0, high=1.0)
    max_step_width: float = parameter(0.1, '|Y| bound of a step command (m)', low=0.0, high=1.0)
    max_step_angle: float = parameter(math.radians(20.0), '|alpha| bound of a step command (rad)',
                                      low=0.0, high=math.pi / 2)
    limits: KinematicLimits = KinematicLimits()

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        check_type('StepperParams.limits', self.limits, KinematicLimits)


class OmnidirectionalStepper:
    """Incremental footstep generator: ask for the next footstep with the current command."""

    def __init__(self, start: Pose2D, params: StepperParams = StepperParams(),
                 first_swing: int = LEFT) -> None:
        """Start with the feet side by side around a body pose.

        :param start: body pose between the feet (m, rad)
        :param params: stepper parameters
        :param first_swing: the foot that swings first, LEFT or RIGHT
        :raises ConfigError: if an argument has the wrong type or first_swing is not a foot
        """
        check_type('start', start, Pose2D)
        check_type('params', params, StepperParams)
        check_side('first_swing', first_swing)
        self._params = params
        self._feet = FeetState(start, params.step_width, first_swing, params.limits)
        self._filter = FirstOrderLag(params.lag_time_constant, [0.0, 0.0, 0.0])
        # the filter's output after each length of the footstep list, for adopt
        self._filter_outputs = {len(self._feet.footsteps): self._filter.value}

    @property
    def footsteps(self) -> List[Footstep]:
        """All footsteps so far in the footstep-list convention (a copy)."""
        return list(self._feet.footsteps)

    @property
    def swing_side(self) -> int:
        """The foot that swings next."""
        return self._feet.swing

    @property
    def body(self) -> Pose2D:
        """Body pose after the last step."""
        return self._feet.body

    @property
    def filtered_command(self) -> StepCommand:
        """The command after the lag filter, as used by the last step."""
        return StepCommand(*(float(v) for v in self._filter.value))

    def state(self) -> Tuple[float, ...]:
        """The paper's feet state s = (x_l, y_l, theta_l, phi_l, x_r, y_r, theta_r, phi_r).

        :return: the 8-tuple; phi is 1 for the foot that swings next and -1 for the other
        """
        return self._feet.vector()

    def next_footstep(self, command: StepCommand, step_time: float) -> Footstep:
        """Plan the next landing of the swing foot with the current command.

        :param command: the step action (clipped to the parameter bounds, then filtered)
        :param step_time: duration of the step, the filter's update interval (s), > 0
        :return: the landing (also appended to footsteps)
        :raises CommandError: if command is not a StepCommand
        :raises ConfigError: if step_time is not a finite number > 0
        """
        check_type('command', command, StepCommand, error=CommandError)
        params = self._params
        target = [min(max(command.step_length, -params.max_step_length), params.max_step_length),
                  min(max(command.step_width, -params.max_step_width), params.max_step_width),
                  min(max(command.step_angle, -params.max_step_angle), params.max_step_angle)]
        forward, sideways, turn = (float(v) for v in self._filter.update(target, step_time))
        landing = self._step(forward, sideways, turn)
        self._filter_outputs[len(self._feet.footsteps)] = self._filter.value
        return landing

    def adopt(self, footsteps) -> None:
        """Go on from these footsteps (a step adjuster moved a landing and the later ones with
        it); the command filter goes back to its output after the last of them, as this
        stepper made it. Footsteps it had appended beyond them (an extension the adjuster had
        not yet seen) are dropped with their filter updates, so the next footstep does not
        depend on whether that extension was made before the adjustment came or after (the
        order of two messages).

        :param footsteps: the footstep list, >= 2 footsteps of alternating sides
        """
        self._feet = FeetState.from_footsteps(footsteps, self._params.step_width,
                                              self._params.limits)
        count = len(self._feet.footsteps)
        if count in self._filter_outputs:
            self._filter.reset(self._filter_outputs[count])
        self._filter_outputs = {n: v for n, v in self._filter_outputs.items() if n <= count}
        self._filter_outputs[count] = self._filter.value

    def close(self) -> Footstep:
        """A final step that brings the swing foot beside the stance foot (no filtering); the
        filter is reset to zero so that the next walk starts gently.

        :return: the landing (also appended to footsteps)
        """
        self._filter.reset([0.0, 0.0, 0.0])
        landing = self._step(0.0, 0.0, 0.0)
        self._filter_outputs[len(self._feet.footsteps)] = self._filter.value
        return landing

    def _step(self, forward: float, sideways: float, turn: float) -> Footstep:
        """Move the body by (forward, sideways) in the heading halfway through the turn, then
        land the swing foot beside it."""
        body = self._feet.body
        heading = body.yaw + 0.5 * turn
        cos_h, sin_h = math.cos(heading), math.sin(heading)
        return self._feet.land(body.x + cos_h * forward - sin_h * sideways,
                               body.y + sin_h * forward + cos_h * sideways, body.yaw + turn)


def footsteps_from_commands(start: Pose2D, commands: Sequence[StepCommand], step_time: float,
                            params: StepperParams = StepperParams(), first_swing: int = LEFT,
                            close: bool = True) -> List[Footstep]:
    """Batch mode: the footsteps of a sequence of per-step commands.

    :param start: body pose between the initial feet
    :param commands: one command per step
    :param step_time: duration of each step (s), > 0
    :param params: stepper parameters
    :param first_swing: the foot that swings first
    :param close: add a final step that brings the feet side by side
    :return: the footstep list (initial feet, then the landings)
    :raises CommandError: if a command is malformed
    :raises ConfigError: if an argument is out of range
    """
    stepper = OmnidirectionalStepper(start, params, first_swing)
    for command in commands:
        stepper.next_footstep(command, step_time)
    if close:
        stepper.close()
    return stepper.footsteps


def footsteps_from_schedule(start: Pose2D, schedule: Callable[[float], StepCommand],
                            duration: float, step_time: float,
                            params: StepperParams = StepperParams(), first_swing: int = LEFT,
                            t_first_step: Optional[float] = None) -> List[Footstep]:
    """Batch mode for a time schedule of commands (the paper's omnidirectional scenario): step k
    uses schedule(t_k) at its start time t_k = t_first_step + k * step_time.

    :param start: body pose between the initial feet
    :param schedule: command as a function of time
    :param duration: time span to plan (s), >= 0
    :param step_time: duration of each step (s), > 0
    :param params: stepper parameters
    :param first_swing: the foot that swings first
    :param t_first_step: start time of the first step (s), default 0
    :return: the footstep list, closed with the feet side by side
    :raises ConfigError: if duration or step_time is out of range
    """
    check_number('duration', duration, low=0.0, unit=' s')
    check_number('step_time', step_time, low=0.0, low_open=True, unit=' s')
    t0 = 0.0 if t_first_step is None else t_first_step
    count = int(math.floor(duration / step_time + 1e-9))
    commands = [schedule(t0 + k * step_time) for k in range(count)]
    return footsteps_from_commands(start, commands, step_time, params, first_swing)
