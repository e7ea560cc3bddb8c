"""Walk commands as library values, validated against the robot's limits.

The numbers of the command kinds are those of biped_msgs/WalkCommand, so that a node converts a
message field by field.
"""
from dataclasses import dataclass
import enum
import math

from biped_planner.errors import CommandError, ConfigError
from biped_planner.parameter_fields import parameter, validate_fields


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
