"""Tests of biped_planner.occupancy_grid."""
import math

import numpy as np
import pytest

from biped_planner.errors import ConfigError, MapError
from biped_planner.occupancy_grid import (BoxObstacle, DiscObstacle, inflate, InflationParams,
                                          OccupancyGrid, scale_obstacles)


def test_from_flat_is_row_major_with_row_as_y():
    data = [0] * 12
    data[1 * 4 + 3] = 100          # row 1 (y), column 3 (x)
    grid = OccupancyGrid.from_flat(data, width=4, height=3, resolution=0.5, origin=(1.0, -1.0))
    assert grid.shape == (3, 4)
    assert grid.values[1, 3] == 100
    assert grid.extent == (1.0, 3.0, -1.0, 0.5)
    assert grid.world_to_cell(2.6, -0.3) == (1, 3)
    np.testing.assert_allclose(grid.cell_centres(np.array([[1, 3]])), [[2.75, -0.25]])
    assert grid.contains(1.0, -1.0) and not grid.contains(3.0, 0.0)


def test_occupied_threshold_and_unknown():
    grid = OccupancyGrid(np.array([[0, 49, 50, 100, -1]]), 0.1)
    np.testing.assert_array_equal(grid.occupied(), [[False, False, True, True, True]])
    np.testing.assert_array_equal(grid.occupied(InflationParams(unknown_is_occupied=False)),
                                  [[False, False, True, True, False]])
    np.testing.assert_array_equal(grid.occupied(InflationParams(occupied_threshold=100)),
                                  [[False, False, False, True, True]])


def test_obstacles_are_rasterised_where_they_overlap_cells():
    grid = OccupancyGrid.from_obstacles((1.0, 1.0), 0.1,
                                        [BoxObstacle(0.15, 0.25, 0.35, 0.3),
                                         DiscObstacle(0.75, 0.75, 0.1)])
    rows, cols = np.nonzero(grid.values[:5, :5])
    assert set(zip(rows.tolist(), cols.tolist())) == {(2, 1), (2, 2), (2, 3)}
    # the disc of radius 0.1 at (0.75, 0.75) reaches the 3 x 3 cells around (0.75, 0.75) (their
    # nearest corners are 0.071 m away) and no other (the next cells are 0.15 m away)
    np.testing.assert_array_equal(np.argwhere(grid.values[5:, 5:]) + 5,
                                  [[r, c] for r in (6, 7, 8) for c in (6, 7, 8)])


def test_rasterised_disc_matches_dense_sampling():
    grid = OccupancyGrid.from_obstacles((1.0, 1.0), 0.1, [DiscObstacle(0.43, 0.58, 0.23)])
    samples = 0.1 * np.arange(10)[:, None] + np.linspace(0.0, 0.1, 41)[None, :]   # (cell, k)
    squared = ((samples[None, :, None, :] - 0.43) ** 2
               + (samples[:, None, :, None] - 0.58) ** 2)                        # (r, c, i, j)
    sampled = squared.min(axis=(2, 3)) < 0.23 ** 2
    # sampling at 2.5 mm can only miss cells the disc barely touches
    disagree = sampled != (grid.values == 100)
    assert np.all(np.abs(np.sqrt(squared.min(axis=(2, 3)))[disagree] - 0.23) < 0.003)
    assert sampled.sum() > 10


def test_scaling_grows_an_obstacle_about_its_centre():
    occupied = np.zeros((30, 30), dtype=bool)
    occupied[10:20, 5:25] = True             # 10 x 20 cells
    scaled = scale_obstacles(occupied, 1.2)  # 12 x 24 cells, one and two cells more per side
    rows, cols = np.nonzero(scaled)
    assert (rows.min(), rows.max(), cols.min(), cols.max()) == (9, 20, 3, 26)
    assert np.all(scaled[occupied])
    np.testing.assert_array_equal(scale_obstacles(occupied, 1.0), occupied)


def test_inflation_by_robot_radius_matches_brute_force():
    rng = np.random.default_rng(3)
    occupied = rng.random((25, 30)) < 0.05
    resolution, radius = 0.1, 0.25
    inflated = inflate(occupied, resolution, 1.0, radius)
    cells = np.argwhere(occupied)
    grid_rows, grid_cols = np.indices(occupied.shape)
    distance = np.min(np.hypot(grid_rows[..., None] - cells[:, 0],
                               grid_cols[..., None] - cells[:, 1]), axis=-1) * resolution
    np.testing.assert_array_equal(inflated, distance <= radius + 1e-9)


def test_inflated_uses_scale_then_radius():
    grid = OccupancyGrid.from_obstacles((2.0, 2.0), 0.1, [BoxObstacle(0.5, 0.5, 1.5, 1.5)])
    params = InflationParams(scale=1.1, robot_radius=0.1, outside_is_occupied=False)
    blocked = grid.inflated(params)
    expected = inflate(scale_obstacles(grid.occupied(params), 1.1), 0.1, 1.0, 0.1)
    np.testing.assert_array_equal(blocked, expected)
    assert blocked.sum() > grid.occupied(params).sum()


def test_outside_of_the_map_is_inflated_into_the_border():
    grid = OccupancyGrid(np.zeros((10, 12), dtype=np.int8), 0.1)
    blocked = grid.inflated(InflationParams(robot_radius=0.2))
    # cells whose centre is within 0.2 m of a cell centre outside the map: two rings
    expected = np.ones((10, 12), dtype=bool)
    expected[2:-2, 2:-2] = False
    np.testing.assert_array_equal(blocked, expected)
    assert not grid.inflated(InflationParams(robot_radius=0.2,
                                             outside_is_occupied=False)).any()


@pytest.mark.parametrize('values, resolution, origin', [
    (np.zeros(5), 0.1, (0, 0)), (np.zeros((0, 3)), 0.1, (0, 0)),
    (np.full((2, 2), 101), 0.1, (0, 0)), (np.full((2, 2), -2), 0.1, (0, 0)),
    (np.full((2, 2), 0.5), 0.1, (0, 0)), (np.zeros((2, 2)), 0.0, (0, 0)),
    (np.zeros((2, 2)), math.nan, (0, 0)), (np.zeros((2, 2)), 0.1, (0, math.inf)),
    (np.zeros((2, 2)), 0.1, (0,))])
def test_malformed_grids_are_rejected(values, resolution, origin):
    with pytest.raises(MapError):
        OccupancyGrid(values, resolution, origin)


@pytest.mark.parametrize('kwargs', [dict(data=[0] * 5, width=2, height=3),
                                    dict(data=[0] * 6, width=0, height=3),
                                    dict(data=[0] * 6, width=2.0, height=3)])
def test_from_flat_rejects_size_mismatch(kwargs):
    with pytest.raises(MapError):
        OccupancyGrid.from_flat(resolution=0.1, **kwargs)


def test_from_obstacles_rejects_bad_input():
    with pytest.raises(MapError):
        OccupancyGrid.from_obstacles((0.0, 1.0), 0.1)
    with pytest.raises(MapError):
        OccupancyGrid.from_obstacles((1.0, 1.0), -0.1)
    with pytest.raises(ConfigError):
        OccupancyGrid.from_obstacles((1.0, 1.0), 0.1, [(0, 0, 1, 1)])


@pytest.mark.parametrize('make', [
    lambda: BoxObstacle(1.0, 0.0, 0.5, 1.0), lambda: BoxObstacle(0.0, math.nan, 1.0, 1.0),
    lambda: DiscObstacle(0.0, 0.0, 0.0), lambda: DiscObstacle(math.inf, 0.0, 1.0),
    lambda: InflationParams(scale=0.9), lambda: InflationParams(robot_radius=-0.1),
    lambda: InflationParams(occupied_threshold=0), lambda: InflationParams(
        unknown_is_occupied=1), lambda: InflationParams(scale=math.nan),
    lambda: InflationParams(outside_is_occupied=None)])
def test_bad_parameters_are_rejected(make):
    with pytest.raises(ConfigError):
        make()
