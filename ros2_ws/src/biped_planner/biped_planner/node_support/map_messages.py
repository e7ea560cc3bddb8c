"""nav_msgs/OccupancyGrid <-> biped_planner.occupancy_grid.OccupancyGrid.

Shared by the footstep planner (which plans on the map), the simulator (which builds the map's
obstacles) and the tools that publish maps.
"""
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
import numpy as np

from biped_planner.errors import MapError
from biped_planner.occupancy_grid import OccupancyGrid
from biped_planner.rotations import yaw_of_quaternion


def grid_from_msg(msg: OccupancyGridMsg) -> OccupancyGrid:
    """:raises MapError: for a rotated origin or malformed sizes and values."""
    q = msg.info.origin.orientation
    if abs(yaw_of_quaternion((q.x, q.y, q.z, q.w))) > 1e-6 or abs(q.x) > 1e-6 or abs(q.y) > 1e-6:
        raise MapError('map origin must not be rotated (yaw 0), got quaternion '
                       f'({q.x}, {q.y}, {q.z}, {q.w})')
    return OccupancyGrid.from_flat(np.frombuffer(bytes(np.asarray(msg.data, dtype=np.int8)),
                                                 dtype=np.int8),
                                   msg.info.width, msg.info.height, msg.info.resolution,
                                   (msg.info.origin.position.x, msg.info.origin.position.y))


def grid_to_msg(grid: OccupancyGrid, frame_id: str, stamp) -> OccupancyGridMsg:
    msg = OccupancyGridMsg()
    msg.header.frame_id = frame_id
    msg.header.stamp = stamp
    msg.info.resolution = float(grid.resolution)
    msg.info.height, msg.info.width = (int(v) for v in grid.shape)
    msg.info.origin.position.x, msg.info.origin.position.y = grid.origin
    msg.info.origin.orientation.w = 1.0
    msg.data = grid.values.astype(np.int8).ravel().tolist()
    return msg
