"""A planar pose (x, y, yaw) of the robot's body, used for start and goal poses."""
from dataclasses import dataclass

from biped_planner.input_checks import check_number


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
            check_number(f'Pose2D.{name}', getattr(self, name))
