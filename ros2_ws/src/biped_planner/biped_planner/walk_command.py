"""Walk commands as library values, validated against the robot's limits.

The numbers of the command kinds are those of biped_msgs/WalkCommand, so that a node converts a
message field by field. The other two ways a user asks for a walk are checked here too: a goal
pose (the RViz convention: position and orientation in the map frame) becomes a GOTO command,
and a velocity command (the cmd_vel convention) becomes a checked (vx, vy, wz).
"""
from dataclasses import dataclass
import enum
import math

from biped_planner.errors import CommandError, ConfigError, FrameError
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.rotations import yaw_of_quaternion


class CommandKind(enum.IntEnum):
    STOP = 0
    START = 1
    GOTO = 2
    OMNI = 3
    RESET = 4


@dataclass(frozen=True)
class CommandLimits:
    """What a walk command may ask for (each field's range is in its parameter()).

    min_step_time must not exceed max_step_time.
    """

    max_step_length: float = parameter(0.3, 'largest |step_length| of an OMNI command (m)',
                                       low=0.01, high=1.0)
    max_step_width: float = parameter(0.2, 'largest |step_width| of an OMNI command (m)',
                                      low=0.01, high=1.0)
    max_step_angle: float = parameter(0.5, 'largest |step_angle| of an OMNI command (rad)',
                                      low=0.01, high=1.5)
    min_step_time: float = parameter(0.2, 'shortest step_time a command may ask for (s)',
                                     low=0.05, high=10.0)
    max_step_time: float = parameter(3.0, 'longest step_time a command may ask for (s)',
                                     low=0.05, high=10.0)
    max_goal_distance: float = parameter(
        1000.0, 'largest |goal_x|, |goal_y| of a GOTO command (m)', low=1.0, high=1e6)
    max_linear_speed: float = parameter(
        1.0, 'largest |linear.x|, |linear.y| of a cmd_vel (m/s)', low=0.01, high=10.0)
    max_angular_speed: float = parameter(
        2.0, 'largest |angular.z| of a cmd_vel (rad/s)', low=0.01, high=20.0)
    quaternion_tolerance: float = parameter(
        0.01, 'largest | |q| - 1 | of a goal orientation quaternion', low=1e-6, high=0.5)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        if self.min_step_time > self.max_step_time:
            raise ConfigError(f'CommandLimits.min_step_time {self.min_step_time} > '
                              f'max_step_time {self.max_step_time}')


@dataclass(frozen=True)
class WalkCommand:
    """A validated walk command.

    :param kind: what to do
    :param goal: (x, y, yaw) in the map frame, for GOTO (m, m, rad)
    :param step: (length, width, angle) per step, for OMNI (m, m, rad)
    :param step_time: step duration (s); 0 keeps the configured one
    """

    kind: CommandKind
    goal: tuple = (0.0, 0.0, 0.0)
    step: tuple = (0.0, 0.0, 0.0)
    step_time: float = 0.0

    @classmethod
    def from_fields(cls, command: int, goal, step, step_time: float,
                    limits: CommandLimits) -> 'WalkCommand':
        """Validate raw fields (as in the message) and build a command.

        :raises CommandError: unknown command, a non-finite value, or a value out of its range;
            the message names the field, its value and the allowed range
        """
        try:
            kind = CommandKind(command)
        except ValueError:
            known = ', '.join(f'{k.value}={k.name}' for k in CommandKind)
            raise CommandError(f'unknown command {command} (known: {known})') from None
        goal = tuple(float(v) for v in goal)
        step = tuple(float(v) for v in step)
        step_time = float(step_time)
        for name, value in zip(('goal_x', 'goal_y', 'goal_yaw', 'step_length', 'step_width',
                                'step_angle', 'step_time'), goal + step + (step_time,)):
            if not math.isfinite(value):
                raise CommandError(f'{name} must be finite, got {value}')
        if step_time != 0.0 and not limits.min_step_time <= step_time <= limits.max_step_time:
            raise CommandError(f'step_time {step_time} s outside [{limits.min_step_time}, '
                               f'{limits.max_step_time}] (0 keeps the configured value)')
        if kind == CommandKind.OMNI:
            for name, value, bound in (('step_length', step[0], limits.max_step_length),
                                       ('step_width', step[1], limits.max_step_width),
                                       ('step_angle', step[2], limits.max_step_angle)):
                if abs(value) > bound:
                    raise CommandError(f'{name} {value} outside [-{bound}, {bound}]')
        if kind == CommandKind.GOTO:
            for name, value in (('goal_x', goal[0]), ('goal_y', goal[1])):
                if abs(value) > limits.max_goal_distance:
                    raise CommandError(f'{name} {value} m outside '
                                       f'[-{limits.max_goal_distance}, '
                                       f'{limits.max_goal_distance}]')
        return cls(kind=kind, goal=goal, step=step, step_time=step_time)


def goal_command(frame_id: str, expected_frame: str, position, orientation_xyzw,
                 limits: CommandLimits) -> WalkCommand:
    """A GOTO command from a goal pose (geometry_msgs/PoseStamped fields).

    :param frame_id: the pose's frame; it must be expected_frame (an empty frame is an error:
        there is no default frame)
    :param position: (x, y, z) in that frame (m); z is not used
    :param orientation_xyzw: quaternion (x, y, z, w), normalised within
        limits.quaternion_tolerance; its yaw is the goal heading
    :raises FrameError: for another frame
    :raises CommandError: for a non-finite value, a goal beyond limits.max_goal_distance or a
        quaternion that is not normalised
    """
    if frame_id != expected_frame:
        raise FrameError(f'goal frame_id {frame_id!r} is not the map frame {expected_frame!r} '
                         '(no tf here)')
    values = tuple(float(v) for v in position) + tuple(float(v) for v in orientation_xyzw)
    for name, value in zip(('position.x', 'position.y', 'position.z', 'orientation.x',
                            'orientation.y', 'orientation.z', 'orientation.w'), values):
        if not math.isfinite(value):
            raise CommandError(f'goal {name} must be finite, got {value}')
    norm = math.sqrt(sum(v * v for v in values[3:]))
    if abs(norm - 1.0) > limits.quaternion_tolerance:
        raise CommandError(f'goal orientation is not a unit quaternion: |q| = {norm:.6g} (allowed '
                           f'1 +- {limits.quaternion_tolerance})')
    yaw = yaw_of_quaternion(tuple(v / norm for v in values[3:]))
    return WalkCommand.from_fields(CommandKind.GOTO, (values[0], values[1], yaw), (0.0, 0.0, 0.0),
                                   0.0, limits)


def velocity_command(linear, angular, limits: CommandLimits) -> tuple:
    """The (vx, vy, wz) of a velocity command (geometry_msgs/Twist fields), checked.

    :param linear: (x, y, z) (m/s); z is not used
    :param angular: (x, y, z) (rad/s); x and y are not used
    :return: (vx, vy, wz)
    :raises CommandError: for a non-finite field, or a speed beyond the limits
    """
    values = tuple(float(v) for v in linear) + tuple(float(v) for v in angular)
    for name, value in zip(('linear.x', 'linear.y', 'linear.z', 'angular.x', 'angular.y',
                            'angular.z'), values):
        if not math.isfinite(value):
            raise CommandError(f'cmd_vel {name} must be finite, got {value}')
    for name, value, bound in (('linear.x', values[0], limits.max_linear_speed),
                               ('linear.y', values[1], limits.max_linear_speed),
                               ('angular.z', values[5], limits.max_angular_speed)):
        if abs(value) > bound:
            raise CommandError(f'cmd_vel {name} {value} outside [-{bound}, {bound}]')
    return values[0], values[1], values[5]


MAX_START_LEAD = 60.0  # s: a start_time farther ahead is refused (a typo, not a plan)


def start_time_of(start_time, now: float) -> float:
    """When a walk asked to start at start_time starts: at start_time, or now if that is past.

    :param start_time: the command's start_time (s); 0: at once
    :param now: the clock now (s)
    :return: the start time (s), >= now
    :raises CommandError: for a start_time that is not finite, negative, or more than
        MAX_START_LEAD ahead of now
    """
    if isinstance(start_time, bool) or not isinstance(start_time, (int, float)) or \
            not math.isfinite(start_time) or start_time < 0.0:
        raise CommandError(f'start_time must be a finite time >= 0 s, got {start_time!r}')
    if start_time > now + MAX_START_LEAD:
        raise CommandError(f'start_time {start_time:.3f} s is more than {MAX_START_LEAD:g} s '
                           f'ahead of the clock ({now:.3f} s)')
    return max(float(start_time), float(now))


def check_command_frame(command: WalkCommand, frame_id: str, expected_frame: str) -> None:
    """A GOTO command's goal is in the map frame: its header may name it or leave it empty
    (biped_msgs/WalkCommand defines the goal in the map frame).

    :raises FrameError: when a GOTO names another frame
    """
    if command.kind == CommandKind.GOTO and frame_id not in ('', expected_frame):
        raise FrameError(f'GOTO in frame {frame_id!r}: the goal must be in the map frame '
                         f'{expected_frame!r} (no tf here)')
