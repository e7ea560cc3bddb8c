"""Tests of biped_planner.footstep_planner on the paper's START-GOAL map and simple paths."""
import math

import numpy as np
import pytest

from biped_planner.astar import AStarPlanner
from biped_planner.errors import ConfigError, NoPathError, PlanningError
from biped_planner.example_maps import paper_start_goal_example
from biped_planner.footstep_planner import (FootstepPlanner, FootstepPlannerParams,
                                            shortcut_path)
from biped_planner.footsteps import check_footstep_sequence, LEFT
from biped_planner.kinematic_limits import KinematicLimits, step_violations
from biped_planner.occupancy_grid import BoxObstacle, OccupancyGrid
from biped_planner.pose2d import Pose2D

LIMITS = KinematicLimits()


@pytest.fixture(name='paper', scope='module')
def fixture_paper():
    grid, start, goal = paper_start_goal_example()
    astar = AStarPlanner(grid)
    return astar, start, goal, FootstepPlanner().plan_on_map(astar, start, goal)


def _check_sequence(footsteps):
    check_footstep_sequence(footsteps)
    stance = footsteps[0]
    for landing in footsteps[2:]:
        assert step_violations(stance, landing, LIMITS) == []
        stance = landing


def _sole_points(step, length=0.16, width=0.08, count=9):
    u, v = np.meshgrid(np.linspace(-0.5, 0.5, count), np.linspace(-0.5, 0.5, count))
    local = np.column_stack((u.ravel() * length, v.ravel() * width))
    cos_yaw, sin_yaw = math.cos(step.yaw), math.sin(step.yaw)
    return local @ np.array([[cos_yaw, sin_yaw], [-sin_yaw, cos_yaw]]) + [step.x, step.y]


def test_paper_example_footsteps_reach_the_goal(paper):
    _, start, goal, plan = paper
    steps = plan.footsteps
    _check_sequence(steps)
    last, before = steps[-1], steps[-2]
    assert 0.5 * (last.x + before.x) == pytest.approx(goal.x, abs=0.011)
    assert 0.5 * (last.y + before.y) == pytest.approx(goal.y, abs=0.011)
    assert math.remainder(last.yaw - goal.yaw, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    assert math.remainder(before.yaw - goal.yaw, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    assert math.hypot(last.x - before.x, last.y - before.y) == pytest.approx(0.2, abs=1e-9)
    first_left = steps[0] if steps[0].side == LEFT else steps[1]
    assert (first_left.x, first_left.y) == pytest.approx((start.x - 0.1, start.y))


def test_paper_example_footsteps_stay_off_the_obstacles(paper):
    astar, _, _, plan = paper
    grid = astar.grid
    for step in plan.footsteps:
        points = _sole_points(step)
        cols = np.floor((points[:, 0] - grid.origin[0]) / grid.resolution).astype(int)
        rows = np.floor((points[:, 1] - grid.origin[1]) / grid.resolution).astype(int)
        assert not astar.occupied[rows, cols].any()


def test_paper_example_steps_are_at_most_r(paper):
    _, _, _, plan = paper
    steps = plan.footsteps
    # consecutive footsteps are R apart along the path plus the lateral 2d
    for previous, landing in zip(steps[1:-1], steps[2:]):
        assert math.hypot(landing.x - previous.x, landing.y - previous.y) <= math.hypot(
            0.1, 0.2) + 0.03


def test_shortened_path_is_clear_and_keeps_the_ends(paper):
    astar, start, goal, plan = paper
    assert len(plan.path) < len(plan.grid_path.points)
    np.testing.assert_allclose(plan.path[[0, -1]], [[start.x, start.y], [goal.x, goal.y]])
    for a, b in zip(plan.path[:-1], plan.path[1:]):
        samples = a + np.linspace(0, 1, 200)[:, None] * (b - a)
        cells = np.floor(samples / astar.grid.resolution).astype(int)
        assert not astar.blocked[cells[:, 1], cells[:, 0]].any()


def test_straight_path_gives_steps_of_r():
    planner = FootstepPlanner(FootstepPlannerParams(lag_time_constant=0.0))
    path = np.array([[0.0, 0.0], [2.0, 0.0]])
    steps = planner.plan_along_path(path, Pose2D(0.0, 0.0, 0.0), Pose2D(2.0, 0.0, 0.0))
    _check_sequence(steps)
    landings_x = np.array([step.x for step in steps[2:]])
    np.testing.assert_allclose(np.diff(landings_x)[:-1], 0.1, atol=1e-9)
    np.testing.assert_allclose([abs(step.y) for step in steps], 0.1, atol=1e-9)
    assert landings_x[-1] == pytest.approx(2.0)


def test_turn_in_place_to_the_goal_heading():
    planner = FootstepPlanner()
    steps = planner.plan_along_path(np.array([[0.0, 0.0]]), Pose2D(0.0, 0.0, 0.0),
                                    Pose2D(0.0, 0.0, math.pi))
    _check_sequence(steps)
    assert math.remainder(steps[-1].yaw - math.pi, 2 * math.pi) == pytest.approx(0, abs=1e-9)
    assert len(steps) - 2 >= math.pi / LIMITS.max_turn


def test_shortcut_of_a_zig_zag_in_free_space_is_one_segment():
    grid = OccupancyGrid(np.zeros((20, 20), dtype=np.int8), 0.1)
    astar = AStarPlanner(grid)
    zig = np.array([[0.55, 0.55], [0.65, 0.65], [0.75, 0.65], [0.85, 0.75], [1.55, 0.85]])
    np.testing.assert_allclose(shortcut_path(zig, astar), zig[[0, -1]])


def test_errors():
    grid = OccupancyGrid.from_obstacles((2.0, 2.0), 0.1, [BoxObstacle(0.9, 0.0, 1.1, 2.0)])
    astar = AStarPlanner(grid)
    planner = FootstepPlanner()
    with pytest.raises(NoPathError):
        planner.plan_on_map(astar, Pose2D(0.4, 1.0), Pose2D(1.6, 1.0))
    with pytest.raises(ConfigError):
        planner.plan_on_map(astar, (0.4, 1.0, 0.0), Pose2D(1.6, 1.0))
    with pytest.raises(ConfigError):
        planner.plan_along_path(np.array([[0.0, math.nan]]), Pose2D(0, 0), Pose2D(1, 0))
    with pytest.raises(ConfigError):
        planner.plan_along_path(np.zeros((3, 3)), Pose2D(0, 0), Pose2D(1, 0))
    with pytest.raises(ConfigError):
        planner.plan_along_path(np.zeros((1, 2)), Pose2D(0, 0), Pose2D(1, 0), first_swing=5)
    short = FootstepPlanner(FootstepPlannerParams(max_steps=3))
    with pytest.raises(PlanningError, match='did not reach'):
        short.plan_along_path(np.array([[0.0, 0.0], [3.0, 0.0]]), Pose2D(0, 0),
                              Pose2D(3.0, 0.0))
    with pytest.raises(ConfigError):
        FootstepPlanner({'step_length': 0.1})
    for kwargs in (dict(step_length=0.0), dict(lookahead=math.inf), dict(max_steps=0),
                   dict(max_steps=2.5), dict(limits=None)):
        with pytest.raises(ConfigError):
            FootstepPlannerParams(**kwargs)
