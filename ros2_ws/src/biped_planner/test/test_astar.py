"""Tests of biped_planner.astar: optimality against Dijkstra, validity, errors."""
import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from biped_planner.astar import AStarPlanner, MOVES
from biped_planner.errors import (ConfigError, GoalOccupiedError, GoalOutsideMapError,
                                  NoPathError, StartOccupiedError, StartOutsideMapError)
from biped_planner.occupancy_grid import BoxObstacle, InflationParams, OccupancyGrid

NO_INFLATION = InflationParams(scale=1.0, robot_radius=0.0)


def _dijkstra_costs(blocked, source):
    """Shortest path lengths (cells) from source on the 8-connected, no-corner-cutting graph."""
    height, width = blocked.shape
    free = ~blocked
    index = np.arange(height * width).reshape(height, width)
    rows, cols = np.nonzero(free)
    heads, tails, weights = [], [], []
    for d_row, d_col, cost in MOVES:
        to_row, to_col = rows + d_row, cols + d_col
        ok = (to_row >= 0) & (to_row < height) & (to_col >= 0) & (to_col < width)
        ok[ok] = free[to_row[ok], to_col[ok]]
        if d_row and d_col:
            ok[ok] = free[rows[ok] + d_row, cols[ok]] & free[rows[ok], cols[ok] + d_col]
        heads.append(index[rows[ok], cols[ok]])
        tails.append(index[to_row[ok], to_col[ok]])
        weights.append(np.full(ok.sum(), cost))
    graph = coo_matrix((np.concatenate(weights), (np.concatenate(heads), np.concatenate(tails))),
                       shape=(height * width, height * width)).tocsr()
    return dijkstra(graph, indices=index[source]).reshape(height, width)


def _check_path(path, blocked, start, goal):
    cells = path.cells
    assert tuple(cells[0]) == tuple(start) and tuple(cells[-1]) == tuple(goal)
    assert not blocked[cells[:, 0], cells[:, 1]].any()
    steps = np.diff(cells, axis=0)
    assert np.abs(steps).max(initial=0) <= 1 and np.all(np.abs(steps).sum(axis=1) > 0)
    diagonal = np.all(steps != 0, axis=1)
    # no corner cutting: both cells beside a diagonal move are free
    assert not blocked[cells[:-1][diagonal, 0] + steps[diagonal, 0],
                       cells[:-1][diagonal, 1]].any()
    assert not blocked[cells[:-1][diagonal, 0],
                       cells[:-1][diagonal, 1] + steps[diagonal, 1]].any()
    return float(np.hypot(steps[:, 0], steps[:, 1]).sum())


@pytest.mark.parametrize('method', ['jump', 'plain'])
@pytest.mark.parametrize('seed', range(6))
def test_cost_equals_the_dijkstra_optimum_on_random_maps(method, seed):
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(25):
        height, width = rng.integers(4, 36, size=2)
        density = rng.uniform(0.0, 0.45)
        values = (rng.random((height, width)) < density).astype(np.int8) * 100
        resolution = 0.1
        planner = AStarPlanner(OccupancyGrid(values, resolution), NO_INFLATION, method)
        free = np.argwhere(~planner.blocked)
        if len(free) < 2:
            continue
        start, goal = free[rng.choice(len(free), 2, replace=False)]
        optimum = _dijkstra_costs(planner.blocked, tuple(start))[tuple(goal)]
        if not np.isfinite(optimum):
            with pytest.raises(NoPathError):
                planner.plan_cells(tuple(start), tuple(goal))
            continue
        path = planner.plan_cells(tuple(start), tuple(goal))
        assert path.cost == pytest.approx(optimum * resolution, abs=1e-9)
        assert _check_path(path, planner.blocked, start, goal) == pytest.approx(optimum,
                                                                               abs=1e-9)
        checked += 1
    assert checked >= 10


def test_jump_and_plain_agree_on_an_inflated_obstacle_map():
    obstacles = [BoxObstacle(1.0, 0.0, 1.4, 2.2), BoxObstacle(2.2, 1.0, 2.6, 4.0),
                 BoxObstacle(0.5, 3.0, 1.8, 3.3)]
    grid = OccupancyGrid.from_obstacles((4.0, 4.0), 0.05, obstacles)
    jump = AStarPlanner(grid)
    plain = AStarPlanner(grid, method='plain')
    first = jump.plan((0.3, 0.3), (3.7, 3.7))
    second = plain.plan((0.3, 0.3), (3.7, 3.7))
    assert first.cost == pytest.approx(second.cost, abs=1e-9)
    _check_path(first, jump.blocked, first.cells[0], first.cells[-1])
    assert first.expanded < second.expanded
    # the path keeps the robot radius away from the real obstacles
    occupied = np.argwhere(jump.occupied)
    distance = np.min(np.hypot(*(first.cells[:, None, :] - occupied[None]).transpose(2, 0, 1)),
                      axis=1) * grid.resolution
    assert distance.min() > InflationParams().robot_radius


def test_straight_and_diagonal_paths_in_free_space():
    planner = AStarPlanner(OccupancyGrid(np.zeros((20, 30), dtype=np.int8), 0.1),
                           NO_INFLATION)
    path = planner.plan_cells((2, 3), (2, 25))
    assert path.cost == pytest.approx(2.2)
    assert len(path.cells) == 23
    path = planner.plan_cells((0, 0), (10, 14))
    assert path.cost == pytest.approx((10 * math.sqrt(2) + 4) * 0.1)
    single = planner.plan_cells((5, 5), (5, 5))
    assert single.cost == 0.0 and single.cells.tolist() == [[5, 5]]


def test_world_points_map_to_cell_centres():
    grid = OccupancyGrid(np.zeros((10, 10), dtype=np.int8), 0.2, origin=(-1.0, 2.0))
    path = AStarPlanner(grid, NO_INFLATION).plan((-0.95, 2.05), (0.95, 2.05))
    np.testing.assert_allclose(path.points[[0, -1]], [[-0.9, 2.1], [0.9, 2.1]])


def _wall_map():
    values = np.zeros((10, 10), dtype=np.int8)
    values[:, 5] = 100
    return OccupancyGrid(values, 0.1)


@pytest.mark.parametrize('start, goal, error, match', [
    ((-0.1, 0.5), (0.2, 0.2), StartOutsideMapError, 'start .* outside the map'),
    ((0.2, 0.2), (0.2, 1.0), GoalOutsideMapError, 'goal .* outside the map'),
    ((0.55, 0.5), (0.2, 0.2), StartOccupiedError, 'inside an obstacle'),
    ((0.2, 0.2), (0.55, 0.2), GoalOccupiedError, 'inside an obstacle'),
    ((0.2, 0.2), (0.8, 0.2), NoPathError, 'not reachable'),
    ((math.nan, 0.2), (0.8, 0.2), ConfigError, 'finite'),
    ((0.2,), (0.8, 0.2), ConfigError, 'finite'),
])
def test_planning_errors(start, goal, error, match):
    planner = AStarPlanner(_wall_map(), NO_INFLATION)
    with pytest.raises(error, match=match):
        planner.plan(start, goal)


def test_cell_in_the_inflated_margin_names_the_margin():
    planner = AStarPlanner(_wall_map(), InflationParams(scale=1.0, robot_radius=0.1,
                                                        outside_is_occupied=False))
    with pytest.raises(StartOccupiedError, match='inflated margin'):
        planner.plan_cells((3, 4), (3, 0))
    with pytest.raises(GoalOutsideMapError):
        planner.plan_cells((3, 0), (3, 10))


def test_diagonal_gap_is_not_squeezed_through():
    values = np.zeros((4, 4), dtype=np.int8)
    values[0, 1] = values[1, 0] = 100   # only a corner-cutting move joins (0, 0) to the rest
    planner = AStarPlanner(OccupancyGrid(values, 0.1), NO_INFLATION)
    with pytest.raises(NoPathError):
        planner.plan_cells((0, 0), (3, 3))


def test_constructor_rejects_bad_arguments():
    grid = _wall_map()
    with pytest.raises(ConfigError):
        AStarPlanner(np.zeros((3, 3)))
    with pytest.raises(ConfigError):
        AStarPlanner(grid, params={'scale': 1.1})
    with pytest.raises(ConfigError):
        AStarPlanner(grid, method='dijkstra')
