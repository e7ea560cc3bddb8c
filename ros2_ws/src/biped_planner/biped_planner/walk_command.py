"""Walk commands as library values, validated against the robot's limits.

The numbers of the command kinds are those of biped_msgs/WalkCommand, so that a node converts a
message field by field.
"""
from dataclasses import dataclass
import enum
import math

from biped_planner.errors import CommandError, ConfigError


class CommandKind(enum.IntEnum):
    STOP = 0
    START = 1
    GOTO = 2
    OMNI = 3
    RESET = 4


@dataclass(frozen=True)
class CommandLimits:
    """What a walk command may ask for.

    :param max_step_length: largest |step_length| per step (m)
    :param max_step_width: largest |step_width| per step (m)
    :param max_step_angle: largest |step_angle| per step (rad)
    :param min_step_time: shortest step duration (s)
    :param max_step_time: longest step duration (s)
    :param max_goal_distance: largest |goal| coordinate (m)
    """

    max_step_length: float = 0.3
    max_step_width: float = 0.2
    max_step_angle: float = 0.5
    min_step_time: float = 0.2
    max_step_time: float = 3.0
    max_goal_distance: float = 1000.0

    def __post_init__(self) -> None:
        for name in ('max_step_length', 'max_step_width', 'max_step_angle', 'min_step_time',
                     'max_step_time', 'max_goal_distance'):
            value = getattr(self, name)
            if not math.isfinite(value) or value <= 0.0:
                raise ConfigError(f'{name} must be finite and > 0, got {value!r}')
        if self.min_step_time > self.max_step_time:
            raise ConfigError(f'min_step_time {self.min_step_time} > max_step_time '
                              f'{self.max_step_time}')


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
