"""2D occupancy grid of the environment (the paper's grid map) and obstacle inflation.

Layout as in nav_msgs/OccupancyGrid: values row-major, row = y index, column = x index; the
origin is the world position of the corner of cell (0, 0); cell (row, col) covers
[x0 + col * res, x0 + (col + 1) * res] x [y0 + row * res, y0 + (row + 1) * res]. Values 0..100
are occupancy probabilities in percent, -1 is unknown.
"""
from dataclasses import dataclass
import math
from typing import Iterable, Sequence, Tuple

import numpy as np
from scipy import ndimage

from biped_planner.errors import ConfigError, MapError
from biped_planner.input_checks import check_integer, check_number, is_finite_number
from biped_planner.parameter_fields import parameter, validate_fields

UNKNOWN = -1
MAX_CELLS = 25_000_000


@dataclass(frozen=True)
class BoxObstacle:
    """Axis-aligned box obstacle.

    :param x_min: lower x (m)
    :param y_min: lower y (m)
    :param x_max: upper x (m), > x_min
    :param y_max: upper y (m), > y_min
    """

    x_min: float
    y_min: float
    x_max: float
    y_max: float

    def __post_init__(self) -> None:
        for name in ('x_min', 'y_min', 'x_max', 'y_max'):
            check_number(f'BoxObstacle.{name}', getattr(self, name))
        if not (self.x_max > self.x_min and self.y_max > self.y_min):
            raise ConfigError(f'BoxObstacle needs x_max > x_min and y_max > y_min, got {self}')


@dataclass(frozen=True)
class DiscObstacle:
    """Disc obstacle.

    :param x: centre x (m)
    :param y: centre y (m)
    :param radius: radius (m), > 0
    """

    x: float
    y: float
    radius: float

    def __post_init__(self) -> None:
        check_number('DiscObstacle.x', self.x)
        check_number('DiscObstacle.y', self.y)
        check_number('DiscObstacle.radius', self.radius, low=0.0, low_open=True, unit=' m')


@dataclass(frozen=True)
class InflationParams:
    """How cells become blocked for the planner (ranges in each parameter()).

    The default robot radius keeps the feet (at +-d from the path) off the obstacles;
    outside_is_occupied lets the robot radius keep the path (and the feet beside it) away from
    the map border.
    """

    scale: float = parameter(1.1, "obstacles are scaled about their centre by this factor before "
                             "planning (the paper's 1.1)", low=1.0, high=3.0)
    robot_radius: float = parameter(
        0.2, 'cells closer than this to a (scaled) obstacle cell are blocked too (m)',
        low=0.0, high=5.0)
    occupied_threshold: int = parameter(
        50, 'a cell with a value >= this is occupied (percent)', low=1, high=100)
    unknown_is_occupied: bool = parameter(True, 'unknown cells (-1) are treated as occupied')
    outside_is_occupied: bool = parameter(True, 'the space around the map counts as occupied')

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


class OccupancyGrid:
    """An occupancy grid: int8 values (height, width), resolution and origin."""

    def __init__(self, values: np.ndarray, resolution: float,
                 origin: Tuple[float, float] = (0.0, 0.0)) -> None:
        """Wrap a 2D array of occupancy values.

        :param values: (height, width) integers in -1..100, row = y index
        :param resolution: cell side (m), > 0
        :param origin: world (x, y) of the corner of cell (0, 0) (m)
        :raises MapError: if the array, the resolution or the origin is malformed
        """
        values = np.asarray(values)
        if values.ndim != 2 or values.shape[0] < 1 or values.shape[1] < 1:
            raise MapError(f'grid values must be a non-empty 2D array, got shape {values.shape}')
        if values.size > MAX_CELLS:
            raise MapError(f'grid has {values.size} cells, more than {MAX_CELLS}')
        if values.dtype.kind not in 'iub':
            if values.dtype.kind != 'f' or not np.all(np.isfinite(values)) or np.any(
                    values != np.round(values)):
                raise MapError(f'grid values must be integers, got dtype {values.dtype}')
        if values.size and (values.min() < UNKNOWN or values.max() > 100):
            raise MapError(f'grid values must be in -1..100, got [{values.min()}, '
                           f'{values.max()}]')
        check_number('resolution', resolution, low=0.0, low_open=True, unit=' m', error=MapError)
        origin = tuple(origin)
        if len(origin) != 2 or not all(is_finite_number(v) for v in origin):
            raise MapError(f'origin must be two finite numbers (x, y), got {origin!r}')
        self._values = values.astype(np.int8)
        self._values.setflags(write=False)
        self._resolution = float(resolution)
        self._origin = (float(origin[0]), float(origin[1]))

    @classmethod
    def from_flat(cls, data: Sequence[int], width: int, height: int, resolution: float,
                  origin: Tuple[float, float] = (0.0, 0.0)) -> 'OccupancyGrid':
        """Build from the fields of a nav_msgs/OccupancyGrid (origin yaw must be zero).

        :param data: width * height int8 values, row-major, row = y index
        :param width: cells along x, >= 1
        :param height: cells along y, >= 1
        :param resolution: cell side (m)
        :param origin: world (x, y) of the corner of cell (0, 0) (m)
        :return: the grid
        :raises MapError: if the sizes do not match or a value is malformed
        """
        for name, value in (('width', width), ('height', height)):
            check_integer(name, value, low=1, error=MapError)
        flat = np.asarray(data)
        if flat.ndim != 1 or flat.size != width * height:
            raise MapError(f'data must hold width * height = {width * height} values, got '
                           f'{flat.size}')
        return cls(flat.reshape(height, width), resolution, origin)

    @classmethod
    def from_obstacles(cls, size: Tuple[float, float], resolution: float,
                       obstacles: Iterable[object] = (),
                       origin: Tuple[float, float] = (0.0, 0.0)) -> 'OccupancyGrid':
        """Rasterise boxes and discs: a cell is occupied (100) if the shape overlaps it.

        :param size: map size (x, y) (m), each > 0
        :param resolution: cell side (m), > 0
        :param obstacles: BoxObstacle and DiscObstacle items (world frame)
        :param origin: world (x, y) of the corner of cell (0, 0) (m)
        :return: the grid, free cells 0 and occupied cells 100
        :raises MapError: if the size or resolution is malformed
        :raises ConfigError: if an obstacle is neither a BoxObstacle nor a DiscObstacle
        """
        if len(size) != 2 or not all(is_finite_number(v) and v > 0 for v in size):
            raise MapError(f'size must be two finite numbers > 0 (m), got {size!r}')
        check_number('resolution', resolution, low=0.0, low_open=True, unit=' m', error=MapError)
        width = int(round(size[0] / resolution))
        height = int(round(size[1] / resolution))
        if width < 1 or height < 1 or width * height > MAX_CELLS:
            raise MapError(f'size {size} at resolution {resolution} gives {width} x {height} '
                           'cells')
        values = np.zeros((height, width), dtype=np.int8)
        x_low = origin[0] + resolution * np.arange(width)
        y_low = origin[1] + resolution * np.arange(height)
        for obstacle in obstacles:
            if isinstance(obstacle, BoxObstacle):
                columns = (x_low + resolution > obstacle.x_min) & (x_low < obstacle.x_max)
                rows = (y_low + resolution > obstacle.y_min) & (y_low < obstacle.y_max)
                values[np.ix_(rows, columns)] = 100
            elif isinstance(obstacle, DiscObstacle):
                near_x = np.clip(obstacle.x, x_low, x_low + resolution) - obstacle.x
                near_y = np.clip(obstacle.y, y_low, y_low + resolution) - obstacle.y
                inside = near_y[:, None] ** 2 + near_x[None, :] ** 2 < obstacle.radius ** 2
                values[inside] = 100
            else:
                raise ConfigError(f'obstacles must be BoxObstacle or DiscObstacle, got '
                                  f'{type(obstacle).__name__}')
        return cls(values, resolution, origin)

    @property
    def values(self) -> np.ndarray:
        """Occupancy values (height, width), read-only int8."""
        return self._values

    @property
    def resolution(self) -> float:
        """Cell side (m)."""
        return self._resolution

    @property
    def origin(self) -> Tuple[float, float]:
        """World (x, y) of the corner of cell (0, 0) (m)."""
        return self._origin

    @property
    def shape(self) -> Tuple[int, int]:
        """(height, width) in cells."""
        return self._values.shape

    @property
    def extent(self) -> Tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) of the map (m)."""
        height, width = self._values.shape
        return (self._origin[0], self._origin[0] + width * self._resolution,
                self._origin[1], self._origin[1] + height * self._resolution)

    def occupied(self, params: InflationParams = InflationParams()) -> np.ndarray:
        """Cells that are occupied before inflation.

        :param params: threshold and treatment of unknown cells
        :return: (height, width) bool
        """
        blocked = self._values >= params.occupied_threshold
        if params.unknown_is_occupied:
            blocked |= self._values == UNKNOWN
        return blocked

    def inflated(self, params: InflationParams = InflationParams()) -> np.ndarray:
        """Cells the planner may not use: occupied cells scaled and grown by the robot radius.

        :param params: inflation parameters
        :return: (height, width) bool
        """
        return inflate(self.occupied(params), self._resolution, params.scale,
                       params.robot_radius, params.outside_is_occupied)

    def contains(self, x: float, y: float) -> bool:
        """Whether a world point lies on the map.

        :param x: world x (m)
        :param y: world y (m)
        :return: True inside [x_min, x_max) x [y_min, y_max)
        """
        x_min, x_max, y_min, y_max = self.extent
        return x_min <= x < x_max and y_min <= y < y_max

    def world_to_cell(self, x: float, y: float) -> Tuple[int, int]:
        """The cell (row, col) containing a world point (no bounds check).

        :param x: world x (m)
        :param y: world y (m)
        :return: (row, col)
        """
        return (int(math.floor((y - self._origin[1]) / self._resolution)),
                int(math.floor((x - self._origin[0]) / self._resolution)))

    def cell_centres(self, cells: np.ndarray) -> np.ndarray:
        """World centres of cells.

        :param cells: (K, 2) integer (row, col)
        :return: (K, 2) world (x, y) (m)
        """
        cells = np.asarray(cells, dtype=float).reshape(-1, 2)
        return np.column_stack((self._origin[0] + (cells[:, 1] + 0.5) * self._resolution,
                                self._origin[1] + (cells[:, 0] + 0.5) * self._resolution))


def scale_obstacles(occupied: np.ndarray, scale: float) -> np.ndarray:
    """Scale every 8-connected obstacle about the centre of its bounding box.

    A cell is blocked if it was occupied or if its centre, mapped back by 1 / scale about the
    obstacle's centre, falls in a cell of that obstacle.

    :param occupied: (height, width) bool
    :param scale: scale factor >= 1
    :return: (height, width) bool, a superset of occupied
    """
    result = occupied.copy()
    if scale == 1.0 or not occupied.any():
        return result
    labels, _ = ndimage.label(occupied, structure=np.ones((3, 3), dtype=bool))
    height, width = occupied.shape
    for index, bounds in enumerate(ndimage.find_objects(labels), start=1):
        rows, columns = bounds
        centre_row = 0.5 * (rows.start + rows.stop - 1)
        centre_col = 0.5 * (columns.start + columns.stop - 1)
        half_rows = 0.5 * (rows.stop - rows.start) * scale
        half_cols = 0.5 * (columns.stop - columns.start) * scale
        row_range = np.arange(max(0, int(math.floor(centre_row - half_rows))),
                              min(height, int(math.ceil(centre_row + half_rows)) + 1))
        col_range = np.arange(max(0, int(math.floor(centre_col - half_cols))),
                              min(width, int(math.ceil(centre_col + half_cols)) + 1))
        source_rows = np.floor(centre_row + (row_range - centre_row) / scale + 0.5).astype(int)
        source_cols = np.floor(centre_col + (col_range - centre_col) / scale + 0.5).astype(int)
        np.clip(source_rows, 0, height - 1, out=source_rows)
        np.clip(source_cols, 0, width - 1, out=source_cols)
        hit = labels[np.ix_(source_rows, source_cols)] == index
        result[np.ix_(row_range, col_range)] |= hit
    return result


def inflate(occupied: np.ndarray, resolution: float, scale: float, robot_radius: float,
            outside_is_occupied: bool = False) -> np.ndarray:
    """Scale the obstacles, then block every cell whose centre is within robot_radius of a
    blocked cell's centre (Euclidean distance transform).

    :param occupied: (height, width) bool
    :param resolution: cell side (m)
    :param scale: obstacle scale factor >= 1
    :param robot_radius: clearance (m), >= 0
    :param outside_is_occupied: the cells just outside the map count as blocked cells
    :return: (height, width) bool
    """
    blocked = scale_obstacles(occupied, scale)
    if robot_radius <= 0.0:
        return blocked
    if outside_is_occupied:
        blocked = np.pad(blocked, 1, constant_values=True)
    if not blocked.any():
        return blocked
    inflated = ndimage.distance_transform_edt(~blocked) * resolution <= robot_radius + 1e-9
    return inflated[1:-1, 1:-1] if outside_is_occupied else inflated
