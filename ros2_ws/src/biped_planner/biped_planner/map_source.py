"""The map the graph plans on: a nav2 map file, or an empty map around the robot's start.

The map_server node (nodes/map_server.py) serves what map_from_source returns. A map file is
read by biped_planner.map_file.load_map (nav2 map_server YAML + PGM/PNG). Without one, the map is
free space: a square of `size` metres with cells of `resolution`, centred on the start pose,
so that a goal sent without preparing a map (the README's goal_pose line) can be planned.
"""
from dataclasses import dataclass
from pathlib import Path
from typing import Union

import numpy as np

from biped_planner.errors import ConfigError, MapError
from biped_planner.map_file import load_map
from biped_planner.occupancy_grid import MAX_CELLS, OccupancyGrid
from biped_planner.parameter_fields import parameter, validate_fields


@dataclass(frozen=True)
class EmptyMapParams:
    """The map served when no map file is given (ranges in each parameter())."""

    size: float = parameter(10.0, 'side of the square empty map (m)', low=0.5, high=1000.0)
    resolution: float = parameter(0.05, 'cell side of the empty map (m)', low=0.005, high=1.0)
    center_x: float = parameter(0.0, "x of the empty map's centre: the robot's start (m)",
                                low=-1e5, high=1e5)
    center_y: float = parameter(0.0, "y of the empty map's centre: the robot's start (m)",
                                low=-1e5, high=1e5)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        cells = self.cells ** 2
        if cells > MAX_CELLS:
            raise ConfigError(f'an empty map of {self.size} m at {self.resolution} m has {cells} '
                              f'cells, more than {MAX_CELLS}: raise resolution or lower size')

    @property
    def cells(self) -> int:
        """Cells along each side (the size rounded up to whole cells)."""
        return int(np.ceil(self.size / self.resolution - 1e-9))


def empty_map(params: EmptyMapParams) -> OccupancyGrid:
    """A free square map centred on (center_x, center_y)."""
    n = params.cells
    half = 0.5 * n * params.resolution
    return OccupancyGrid(np.zeros((n, n), dtype=np.int8), params.resolution,
                         (params.center_x - half, params.center_y - half))


def map_from_source(yaml_filename: Union[str, Path], empty: EmptyMapParams) -> OccupancyGrid:
    """The map file's grid, or the empty map when no file is named.

    :param yaml_filename: a nav2 map_server YAML file; '' for the empty map
    :param empty: the empty map's size, resolution and centre
    :raises MapError: naming the file and the field when the file cannot be used
    """
    if not str(yaml_filename).strip():
        return empty_map(empty)
    path = Path(yaml_filename).expanduser()
    if not path.is_file():
        raise MapError(f'map file {path} does not exist (yaml_filename)')
    return load_map(path)
