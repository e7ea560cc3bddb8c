"""Uneven terrain of square tiles with random heights (paper: "Walking on Uneven Terrains").

The paper fills a 4 m square with tiles of one size (100, 400 or 625 cm^2) and a random height
each, uniform in 25..50 mm. This module only generates the height map (numpy); a simulator
backend turns it into collision bodies.
"""

from dataclasses import dataclass
import math

import numpy as np

from biped_planner.parameter_fields import parameter, validate_fields

from biped_sim.errors import ConfigError
from biped_sim.validation import number_tuple

PAPER_TILE_AREAS = (0.01, 0.04, 0.0625)  # m^2: 100, 400 and 625 cm^2


@dataclass(frozen=True)
class TerrainParams:
    """Parameters of a tiled terrain; the area holds ceil(side_length / tile side) tiles per side.

    :param origin: (x, y) of the area's corner with the smallest coordinates (m).
    """

    tile_area: float = parameter(0.04, 'area of one square tile (m^2), side = sqrt(area)',
                                 low=1e-4, high=100.0)
    side_length: float = parameter(4.0, 'side of the square area to cover (m), at least one '
                                   'tile', low=0.0, high=100.0, low_open=True)
    min_height: float = parameter(0.025, 'lowest tile top above the ground plane (m)', low=0.0,
                                  high=1.0)
    max_height: float = parameter(0.05, 'highest tile top (m), at least min_height', low=0.0,
                                  high=1.0)
    origin: tuple = parameter((-2.0, -2.0), 'x, y of the corner of the area with the smallest '
                              'coordinates (m)', low=-1e4, high=1e4)
    seed: int = parameter(0, 'seed of the random tile heights', low=0, high=2 ** 31 - 1)

    def __post_init__(self):
        object.__setattr__(self, 'origin', number_tuple('TerrainParams.origin', self.origin, 2))
        validate_fields(self, ConfigError)
        if self.max_height < self.min_height:
            raise ConfigError('TerrainParams.max_height = %r m must be >= min_height = %r m'
                              % (self.max_height, self.min_height))
        if self.side_length < self.tile_side - 1e-12:
            raise ConfigError('TerrainParams.side_length = %r m must be >= the tile side %.4f m'
                              % (self.side_length, self.tile_side))

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
