"""A planar pose (x, y, yaw) of the robot's body, used for start and goal poses."""
from dataclasses import dataclass
import math

from biped_planner.errors import ConfigError


@dataclass(frozen=True)
class Pose2D:
    """Planar pose in the world frame.

    :param x: position x (m)
    :param y: position y (m)
    :param yaw: heading, counter-clockwise from world x (rad)
    """

    x: float
    y: float
    yaw: float = 0.0

    def __post_init__(self) -> None:
        for name in ('x', 'y', 'yaw'):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value):
                raise ConfigError(f'Pose2D.{name} must be a finite number, got {value!r}')
