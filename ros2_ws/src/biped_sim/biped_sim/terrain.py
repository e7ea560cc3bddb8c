"""Uneven terrain of square tiles with random heights (paper: "Walking on Uneven Terrains").

The paper fills a 4 m square with tiles of one size (100, 400 or 625 cm^2) and a random height
each, uniform in 25..50 mm. This module only generates the height map (numpy); a simulator
backend turns it into collision bodies.
"""

from dataclasses import dataclass
import math

import numpy as np

from biped_sim.errors import ConfigError

PAPER_TILE_AREAS = (0.01, 0.04, 0.0625)  # m^2: 100, 400 and 625 cm^2


@dataclass(frozen=True)
class TerrainParams:
    """Parameters of a tiled terrain.

    :param tile_area: area of one square tile (m^2), > 0 (side = sqrt(area)).
    :param side_length: side of the square area to cover (m), >= one tile; the area holds
        ceil(side_length / tile side) tiles per side.
    :param min_height: lowest tile top above the ground plane (m), >= 0.
    :param max_height: highest tile top (m), >= min_height.
    :param origin: (x, y) of the area's corner with the smallest coordinates (m).
    :param seed: seed of the random heights.
    """

    tile_area: float = 0.04
    side_length: float = 4.0
    min_height: float = 0.025
    max_height: float = 0.05
    origin: tuple = (-2.0, -2.0)
    seed: int = 0

    def __post_init__(self):
        checks = (('tile_area', self.tile_area > 0.0, '> 0'),
                  ('min_height', self.min_height >= 0.0, '>= 0'),
                  ('max_height', self.max_height >= self.min_height, '>= min_height'))
        for name, ok, allowed in checks:
            value = getattr(self, name)
            if not (math.isfinite(value) and ok):
                raise ConfigError('TerrainParams.%s = %r must be finite and %s'
                                  % (name, value, allowed))
        if not (math.isfinite(self.side_length) and self.side_length >= self.tile_side - 1e-12):
            raise ConfigError('TerrainParams.side_length = %r m must be finite and >= the tile '
                              'side %.4f m' % (self.side_length, self.tile_side))
        origin = np.asarray(self.origin, dtype=float)
        if origin.shape != (2,) or not np.all(np.isfinite(origin)):
            raise ConfigError('TerrainParams.origin = %r must be 2 finite numbers'
                              % (self.origin,))
        object.__setattr__(self, 'origin', (float(origin[0]), float(origin[1])))

    @property
    def tile_side(self) -> float:
        """Side of one tile (m)."""
        return math.sqrt(self.tile_area)


@dataclass(frozen=True)
class Terrain:
    """A generated tiled terrain.

    :param params: what it was generated from.
    :param heights: (n, n) tile top heights (m); heights[i, j] is the tile at column i along x
        and row j along y.
    """

    params: TerrainParams
    heights: np.ndarray

    @property
    def tile_side(self) -> float:
        """Side of one tile (m)."""
        return self.params.tile_side

    @property
    def tiles_per_side(self) -> int:
        """Number of tiles along x and along y."""
        return self.heights.shape[0]

    def tile_centres(self) -> np.ndarray:
        """Return the (n * n, 2) tile centres (m), in heights.ravel() order."""
        n, side = self.tiles_per_side, self.tile_side
        centres = self.params.origin[0] + side * (np.arange(n) + 0.5)
        rows = self.params.origin[1] + side * (np.arange(n) + 0.5)
        grid_x, grid_y = np.meshgrid(centres, rows, indexing='ij')
        return np.column_stack([grid_x.ravel(), grid_y.ravel()])

    def height_at(self, x, y) -> np.ndarray:
        """Return the terrain height (m) at points; 0 outside the tiled area.

        :param x: x coordinates (m), any shape.
        :param y: y coordinates (m), same shape.
        :return: heights, same shape.
        """
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        n, side = self.tiles_per_side, self.tile_side
        i = np.floor((x - self.params.origin[0]) / side).astype(int)
        j = np.floor((y - self.params.origin[1]) / side).astype(int)
        inside = (i >= 0) & (i < n) & (j >= 0) & (j < n)
        out = np.zeros(x.shape)
        out[inside] = self.heights[i[inside], j[inside]]
        return out


def generate_terrain(params: TerrainParams) -> Terrain:
    """Draw the tile heights uniformly in [min_height, max_height] with the params' seed.

    :param params: terrain parameters.
    :return: the terrain.
    """
    n = int(math.ceil(params.side_length / params.tile_side - 1e-9))
    rng = np.random.default_rng(params.seed)
    heights = rng.uniform(params.min_height, params.max_height, size=(n, n))
    return Terrain(params, heights)
