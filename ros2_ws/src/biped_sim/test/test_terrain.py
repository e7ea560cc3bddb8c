"""Tests of the tiled uneven terrain generator."""

import math

import numpy as np
import pytest

from biped_sim.errors import ConfigError
from biped_sim.terrain import generate_terrain, PAPER_TILE_AREAS, TerrainParams


@pytest.mark.parametrize('area', PAPER_TILE_AREAS)
def test_tiles_have_the_paper_sizes_and_heights(area):
    terrain = generate_terrain(TerrainParams(tile_area=area, side_length=4.0, seed=7))
    side = math.sqrt(area)
    assert terrain.tile_side ** 2 == pytest.approx(area)
    assert terrain.tiles_per_side == round(4.0 / side)
    assert terrain.tiles_per_side * side == pytest.approx(4.0)
    assert terrain.heights.min() >= 0.025 and terrain.heights.max() <= 0.05
    # Uniform heights: the spread fills most of the range.
    assert terrain.heights.max() - terrain.heights.min() > 0.02
    centres = terrain.tile_centres()
    assert centres.shape == (terrain.tiles_per_side ** 2, 2)
    gaps = np.diff(np.unique(centres[:, 0]))
    assert np.allclose(gaps, side)


def test_seed_reproduces_and_differs():
    a = generate_terrain(TerrainParams(seed=1))
    b = generate_terrain(TerrainParams(seed=1))
    c = generate_terrain(TerrainParams(seed=2))
    assert np.array_equal(a.heights, b.heights)
    assert not np.array_equal(a.heights, c.heights)


def test_height_at_matches_tiles_and_is_zero_outside():
    terrain = generate_terrain(TerrainParams(tile_area=0.04, side_length=1.0,
                                             origin=(0.5, -0.5), seed=3))
    centres = terrain.tile_centres()
    assert np.allclose(terrain.height_at(centres[:, 0], centres[:, 1]),
                       terrain.heights.ravel())
    assert terrain.height_at(0.5 + 0.2 * 2 + 0.01, -0.5 + 0.2 * 3 + 0.19) == \
        terrain.heights[2, 3]
    assert np.all(terrain.height_at([0.0, 2.0, 1.0], [0.0, 0.0, 0.6]) == 0.0)


@pytest.mark.parametrize('kwargs, field', [
    ({'tile_area': 0.0}, 'tile_area'),
    ({'tile_area': math.nan}, 'tile_area'),
    ({'min_height': -0.01}, 'min_height'),
    ({'min_height': 0.06, 'max_height': 0.05}, 'max_height'),
    ({'side_length': 0.1}, 'side_length'),
    ({'origin': (0.0,)}, 'origin'),
    ({'origin': (0.0, math.inf)}, 'origin'),
])
def test_bad_params_raise(kwargs, field):
    with pytest.raises(ConfigError, match=field):
        TerrainParams(**kwargs)
