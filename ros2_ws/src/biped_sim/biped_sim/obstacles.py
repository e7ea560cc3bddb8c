"""Static obstacles for the simulator, from a planner-like list of boxes and discs.

The planner describes obstacles in the ground plane; the simulator extrudes them to a height.
:func:`as_sim_obstacle` accepts these classes or any object with the same attributes (duck
typing: the planner's obstacles, or a user's): a disc has ``radius`` and a centre given as
``x, y`` or ``center``; a box has ``x, y, size_x, size_y`` (optional ``yaw``) or
``x_min, y_min, x_max, y_max``.
"""

from dataclasses import dataclass

from biped_sim.errors import ConfigError
from biped_sim.validation import finite_number

DEFAULT_OBSTACLE_HEIGHT = 0.5  # m
_POSITIVE = ('size_x', 'size_y', 'radius', 'height')


@dataclass(frozen=True)
class BoxObstacle:
    """An upright box standing on the ground.

    :param x: centre x (m).
    :param y: centre y (m).
    :param size_x: length along its own x axis (m), > 0.
    :param size_y: length along its own y axis (m), > 0.
    :param yaw: heading of its x axis (rad).
    :param height: height (m), > 0.
    """

    x: float
    y: float
    size_x: float
    size_y: float
    yaw: float = 0.0
    height: float = DEFAULT_OBSTACLE_HEIGHT

    def __post_init__(self):
        for name in ('x', 'y', 'yaw', 'size_x', 'size_y', 'height'):
            object.__setattr__(self, name, finite_number('BoxObstacle.' + name,
                                                         getattr(self, name),
                                                         positive=name in _POSITIVE))


@dataclass(frozen=True)
class DiscObstacle:
    """An upright cylinder standing on the ground (the paper's disk).

    :param x: centre x (m).
    :param y: centre y (m).
    :param radius: radius (m), > 0.
    :param height: height (m), > 0.
    """

    x: float
    y: float
    radius: float
    height: float = DEFAULT_OBSTACLE_HEIGHT

    def __post_init__(self):
        for name in ('x', 'y', 'radius', 'height'):
            object.__setattr__(self, name, finite_number('DiscObstacle.' + name,
                                                         getattr(self, name),
                                                         positive=name in _POSITIVE))


def as_sim_obstacle(obstacle, height: float = DEFAULT_OBSTACLE_HEIGHT):
    """Convert a planner-like obstacle to a BoxObstacle or DiscObstacle.

    :param obstacle: a BoxObstacle, DiscObstacle or an object with their attributes (see the
        module docstring).
    :param height: height given to obstacles that do not carry one (m).
    :return: BoxObstacle or DiscObstacle.
    :raises ConfigError: if the object is neither a box nor a disc, or has bad values.
    """
    if isinstance(obstacle, (BoxObstacle, DiscObstacle)):
        return obstacle
    height = getattr(obstacle, 'height', height)
    if hasattr(obstacle, 'radius'):
        if hasattr(obstacle, 'center'):
            x, y = obstacle.center[0], obstacle.center[1]
        else:
            x, y = obstacle.x, obstacle.y
        return DiscObstacle(x, y, obstacle.radius, height)
    if all(hasattr(obstacle, a) for a in ('x_min', 'y_min', 'x_max', 'y_max')):
        return BoxObstacle(0.5 * (obstacle.x_min + obstacle.x_max),
                           0.5 * (obstacle.y_min + obstacle.y_max),
                           obstacle.x_max - obstacle.x_min, obstacle.y_max - obstacle.y_min,
                           0.0, height)
    if all(hasattr(obstacle, a) for a in ('x', 'y', 'size_x', 'size_y')):
        return BoxObstacle(obstacle.x, obstacle.y, obstacle.size_x, obstacle.size_y,
                           getattr(obstacle, 'yaw', 0.0), height)
    raise ConfigError('obstacle %r is neither a disc (radius and x, y or center) nor a box '
                      '(x, y, size_x, size_y or x_min, y_min, x_max, y_max)' % (obstacle,))


def boxes_from_occupied_cells(occupied, resolution: float, origin: tuple,
                              height: float = DEFAULT_OBSTACLE_HEIGHT) -> list:
    """Boxes covering the occupied cells of a grid, one per horizontal run of cells in a row.

    :param occupied: (rows, cols) boolean array, row = y index (as nav_msgs/OccupancyGrid)
    :param resolution: cell side (m), > 0
    :param origin: world (x, y) of the corner of cell (0, 0) (m)
    :param height: box height (m)
    :return: list of BoxObstacle
    """
    resolution = finite_number('grid.resolution', resolution, positive=True)
    boxes = []
    for row, cells in enumerate(occupied):
        col = 0
        width = len(cells)
        while col < width:
            if not cells[col]:
                col += 1
                continue
            start = col
            while col < width and cells[col]:
                col += 1
            boxes.append(BoxObstacle(
                x=origin[0] + 0.5 * (start + col) * resolution,
                y=origin[1] + (row + 0.5) * resolution,
                size_x=(col - start) * resolution, size_y=resolution, height=height))
    return boxes
