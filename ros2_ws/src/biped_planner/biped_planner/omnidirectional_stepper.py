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
from biped_planner.footsteps import Footstep, LEFT, other_side, RIGHT
from biped_planner.kinematic_limits import clamp_step, KinematicLimits
from biped_planner.lag_filter import FirstOrderLag
from biped_planner.pose2d import Pose2D


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
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value):
                raise CommandError(f'StepCommand.{name} must be a finite number, got {value!r}')


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
    if isinstance(step_time, bool) or not isinstance(step_time, (int, float)) \
            or not math.isfinite(step_time) or step_time <= 0.0:
        raise ConfigError(f'step_time must be a finite number > 0 s, got {step_time!r}')
    for name, value in (('vx', vx), ('vy', vy), ('wz', wz)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            raise CommandError(f'{name} must be a finite number, got {value!r}')
    return StepCommand(vx * step_time, vy * step_time, wz * step_time)


@dataclass(frozen=True)
class StepperParams:
    """Parameters of the omnidirectional stepper.

    :param step_width: nominal distance between the sole centres, 2 d (m), (0, 1]
    :param lag_time_constant: tau of the command filter (s), [0, 100]; 0: no filtering
    :param max_step_length: |X| bound of a command (m), [0, 1]
    :param max_step_width: |Y| bound of a command (m), [0, 1]
    :param max_step_angle: |alpha| bound of a command (rad), [0, pi/2]
    :param limits: kinematic limits between consecutive footsteps
    """

    step_width: float = 0.2
    lag_time_constant: float = 0.5
    max_step_length: float = 0.2
    max_step_width: float = 0.1
    max_step_angle: float = math.radians(20.0)
    limits: KinematicLimits = KinematicLimits()

    def __post_init__(self) -> None:
        for name, low, high in (('step_width', 1e-6, 1.0), ('lag_time_constant', 0.0, 100.0),
                                ('max_step_length', 0.0, 1.0), ('max_step_width', 0.0, 1.0),
                                ('max_step_angle', 0.0, math.pi / 2)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value) or not low <= value <= high:
                raise ConfigError(f'StepperParams.{name} must be a finite number in [{low}, '
                                  f'{high}], got {value!r}')
        if not isinstance(self.limits, KinematicLimits):
            raise ConfigError(f'StepperParams.limits must be KinematicLimits, got '
                              f'{type(self.limits).__name__}')


def _feet_at(pose: Pose2D, half_width: float) -> Tuple[Footstep, Footstep]:
    cos_yaw, sin_yaw = math.cos(pose.yaw), math.sin(pose.yaw)
    left = Footstep(LEFT, pose.x - sin_yaw * half_width, pose.y + cos_yaw * half_width, pose.yaw)
    right = Footstep(RIGHT, pose.x + sin_yaw * half_width, pose.y - cos_yaw * half_width,
                     pose.yaw)
    return left, right


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
        if not isinstance(start, Pose2D):
            raise ConfigError(f'start must be a Pose2D, got {type(start).__name__}')
        if not isinstance(params, StepperParams):
            raise ConfigError(f'params must be StepperParams, got {type(params).__name__}')
        if first_swing not in (LEFT, RIGHT) or isinstance(first_swing, bool):
            raise ConfigError(f'first_swing must be LEFT or RIGHT, got {first_swing!r}')
        self._params = params
        self._half_width = 0.5 * params.step_width
        left, right = _feet_at(start, self._half_width)
        self._feet = {LEFT: left, RIGHT: right}
        self._swing = first_swing
        self._body = start
        self._filter = FirstOrderLag(params.lag_time_constant, [0.0, 0.0, 0.0])
        self._footsteps = [self._feet[other_side(first_swing)], self._feet[first_swing]]

    @property
    def footsteps(self) -> List[Footstep]:
        """All footsteps so far in the footstep-list convention (a copy)."""
        return list(self._footsteps)

    @property
    def swing_side(self) -> int:
        """The foot that swings next."""
        return self._swing

    @property
    def body(self) -> Pose2D:
        """Body pose after the last step."""
        return self._body

    @property
    def filtered_command(self) -> StepCommand:
        """The command after the lag filter, as used by the last step."""
        return StepCommand(*(float(v) for v in self._filter.value))

    def state(self) -> Tuple[float, ...]:
        """The paper's feet state s = (x_l, y_l, theta_l, phi_l, x_r, y_r, theta_r, phi_r).

        :return: the 8-tuple; phi is 1 for the foot that swings next and -1 for the other
        """
        left, right = self._feet[LEFT], self._feet[RIGHT]
        return (left.x, left.y, left.yaw, 1.0 if self._swing == LEFT else -1.0,
                right.x, right.y, right.yaw, 1.0 if self._swing == RIGHT else -1.0)

    def next_footstep(self, command: StepCommand, step_time: float) -> Footstep:
        """Plan the next landing of the swing foot with the current command.

        :param command: the step action (clipped to the parameter bounds, then filtered)
        :param step_time: duration of the step, the filter's update interval (s), > 0
        :return: the landing (also appended to footsteps)
        :raises CommandError: if command is not a StepCommand
        :raises ConfigError: if step_time is not a finite number > 0
        """
        if not isinstance(command, StepCommand):
            raise CommandError(f'command must be a StepCommand, got {type(command).__name__}')
        params = self._params
        target = [min(max(command.step_length, -params.max_step_length), params.max_step_length),
                  min(max(command.step_width, -params.max_step_width), params.max_step_width),
                  min(max(command.step_angle, -params.max_step_angle), params.max_step_angle)]
        forward, sideways, turn = (float(v) for v in self._filter.update(target, step_time))
        return self._step(forward, sideways, turn)

    def close(self) -> Footstep:
        """A final step that brings the swing foot beside the stance foot (no filtering); the
        filter is reset to zero so that the next walk starts gently.

        :return: the landing (also appended to footsteps)
        """
        self._filter.reset([0.0, 0.0, 0.0])
        return self._step(0.0, 0.0, 0.0)

    def _step(self, forward: float, sideways: float, turn: float) -> Footstep:
        body = self._body
        heading = body.yaw + 0.5 * turn
        cos_h, sin_h = math.cos(heading), math.sin(heading)
        moved = Pose2D(body.x + cos_h * forward - sin_h * sideways,
                       body.y + sin_h * forward + cos_h * sideways, body.yaw + turn)
        swing = self._swing
        desired = _feet_at(moved, self._half_width)[0 if swing == LEFT else 1]
        stance = self._feet[other_side(swing)]
        landing = clamp_step(stance, desired, self._params.limits)
        sign = 1.0 if swing == LEFT else -1.0
        self._body = Pose2D(landing.x + sign * math.sin(landing.yaw) * self._half_width,
                            landing.y - sign * math.cos(landing.yaw) * self._half_width,
                            landing.yaw)
        self._feet[swing] = landing
        self._footsteps.append(landing)
        self._swing = other_side(swing)
        return landing


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
    if isinstance(duration, bool) or not isinstance(duration, (int, float)) \
            or not math.isfinite(duration) or duration < 0.0:
        raise ConfigError(f'duration must be a finite number >= 0 s, got {duration!r}')
    if isinstance(step_time, bool) or not isinstance(step_time, (int, float)) \
            or not math.isfinite(step_time) or step_time <= 0.0:
        raise ConfigError(f'step_time must be a finite number > 0 s, got {step_time!r}')
    t0 = 0.0 if t_first_step is None else t_first_step
    count = int(math.floor(duration / step_time + 1e-9))
    commands = [schedule(t0 + k * step_time) for k in range(count)]
    return footsteps_from_commands(start, commands, step_time, params, first_swing)
