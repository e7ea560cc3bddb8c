"""Tests of biped_planner.example_maps: the maps are what the demos and benchmarks assume."""
import numpy as np
import pytest

from biped_planner.astar import AStarPlanner
from biped_planner.example_maps import benchmark_map, paper_start_goal_example
from biped_planner.occupancy_grid import OccupancyGrid
from biped_planner.pose2d import Pose2D


def test_paper_example_is_a_4_m_map_with_a_path_around_obstacles():
    grid, start, goal = paper_start_goal_example()
    assert isinstance(grid, OccupancyGrid)
    assert isinstance(start, Pose2D) and isinstance(goal, Pose2D)
    assert grid.shape == (40, 40) and grid.resolution == pytest.approx(0.1)
    astar = AStarPlanner(grid)
    path = astar.plan((start.x, start.y), (goal.x, goal.y))
    straight = np.hypot(goal.x - start.x, goal.y - start.y)
    assert path.cost > 1.2 * straight          # the obstacles are in the way
    assert grid.occupied().sum() > 50


def test_benchmark_map_has_160000_cells_and_a_path():
    grid, start, goal = benchmark_map()
    assert grid.shape == (400, 400)
    path = AStarPlanner(grid).plan((start.x, start.y), (goal.x, goal.y))
    assert path.cost > np.hypot(goal.x - start.x, goal.y - start.y)
