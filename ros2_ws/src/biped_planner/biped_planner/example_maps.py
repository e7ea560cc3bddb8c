"""Example maps shared by the plots, benchmarks and demos."""
import math
from typing import List, Tuple

import numpy as np

from biped_planner.occupancy_grid import BoxObstacle, DiscObstacle, OccupancyGrid
from biped_planner.pose2d import Pose2D

PAPER_MAP_SIZE = (4.0, 4.0)      # m
PAPER_MAP_RESOLUTION = 0.1       # m, the paper's cell size


def paper_start_goal_obstacles() -> List[object]:
    """The obstacles of paper_start_goal_example (world frame, m)."""
    return [BoxObstacle(1.2, 0.0, 1.6, 1.6),
            BoxObstacle(2.4, 2.1, 2.8, 4.0),
            DiscObstacle(0.7, 2.9, 0.35),
            BoxObstacle(3.2, 0.5, 3.8, 0.9),
            DiscObstacle(1.9, 3.3, 0.2)]


def paper_start_goal_example() -> Tuple[OccupancyGrid, Pose2D, Pose2D]:
    """An equivalent of the paper's planning figure (Fig. PathPlanning): a 4 x 4 m map with
    0.1 m cells, START near one corner, GOAL near the opposite one and a few obstacles between.

    :return: (grid, start pose, goal pose)
    """
    grid = OccupancyGrid.from_obstacles(PAPER_MAP_SIZE, PAPER_MAP_RESOLUTION,
                                        paper_start_goal_obstacles())
    return grid, Pose2D(0.5, 0.5, math.pi / 2), Pose2D(3.4, 3.4, math.pi / 2)


def benchmark_map(size: float = 20.0, resolution: float = 0.05,
                  seed: int = 1) -> Tuple[OccupancyGrid, Pose2D, Pose2D]:
    """A large map for benchmarks: random boxes (0.3 to 2 m) and discs, none within 1 m of the
    start (near one corner) or the goal (near the opposite corner).

    :param size: side of the square map (m)
    :param resolution: cell side (m)
    :param seed: random seed
    :return: (grid, start pose, goal pose)
    """
    rng = np.random.default_rng(seed)
    start = Pose2D(0.6, 0.6, 0.0)
    goal = Pose2D(size - 0.6, size - 0.6, math.pi / 2)
    ends = np.array([[start.x, start.y], [goal.x, goal.y]])
    obstacles: List[object] = []
    count = int(round(0.15 * size * size))
    while len(obstacles) < count:
        x, y = rng.uniform(0.0, size, size=2)
        if np.min(np.hypot(*(ends - [x, y]).T)) < 3.0:
            continue
        if rng.random() < 0.65:
            width, height = rng.uniform(0.3, 2.0, size=2)
            obstacles.append(BoxObstacle(float(x - width / 2), float(y - height / 2),
                                         float(x + width / 2), float(y + height / 2)))
        else:
            obstacles.append(DiscObstacle(float(x), float(y), float(rng.uniform(0.2, 0.8))))
    return OccupancyGrid.from_obstacles((size, size), resolution, obstacles), start, goal
