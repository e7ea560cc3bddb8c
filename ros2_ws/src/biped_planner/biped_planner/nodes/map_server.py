"""The map server node: the map the graph plans on, latched, as nav2's map_server serves it.

Parameters (read-only: the map is loaded once, at start): yaml_filename (a nav2 map_server YAML
file naming a PGM/PNG image, with resolution, origin, thresholds, negate and mode; empty: an
empty map), frame_id, and empty_map.* (size, resolution and centre of the empty map: the
robot's start pose; see biped_planner.map_source).
Publishes: map (nav_msgs/OccupancyGrid, reliable, transient local: late subscribers get it).

A map file that cannot be used (missing, malformed YAML, a bad field, an unreadable image) is
a start-up error naming the file and the field: the node logs it and exits with status 1, so
that the bring-up reports the dead node.
"""
import sys

from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from rclpy.exceptions import InvalidParameterValueException
from rclpy.node import Node

from biped_planner.errors import BipedPlannerError
from biped_planner.map_source import EmptyMapParams, map_from_source
from biped_planner.node_support.dataclass_parameters import (declare_dataclass_parameters,
                                                             declare_node_parameters)
from biped_planner.node_support.map_messages import grid_to_msg
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.qos import LATCHED


class MapStartError(Exception):
    """The node cannot serve a map: it must not start."""


class MapServerNode(Node):
    """Loads the map once and publishes it latched."""

    def __init__(self, **kwargs) -> None:
        super().__init__('map_server', **kwargs)
        try:
            declare_node_parameters(self, {
                'yaml_filename': ('', 'nav2 map_server YAML file of the map (image, resolution, '
                                  'origin, occupied_thresh, free_thresh, negate, mode); empty: '
                                  'an empty map around the start pose (empty_map.*)', None),
                'frame_id': ('map', 'frame of the published map', None)},
                read_only=('yaml_filename', 'frame_id'))
            empty = declare_dataclass_parameters(self, EmptyMapParams(), {},
                                                 prefix='empty_map.')
            filename = self.get_parameter('yaml_filename').value
            grid = map_from_source(filename, empty)
        except (BipedPlannerError, ValueError, InvalidParameterValueException) as error:
            self.get_logger().fatal(f'no map to serve: {error}')
            raise MapStartError(str(error)) from None
        frame = self.get_parameter('frame_id').value
        if not frame.strip():
            self.get_logger().fatal('no map to serve: frame_id is empty')
            raise MapStartError('frame_id is empty')
        self._publisher = self.create_publisher(OccupancyGridMsg, 'map', LATCHED)
        self._publisher.publish(grid_to_msg(grid, frame, self.get_clock().now().to_msg()))
        x0, x1, y0, y1 = grid.extent
        source = f'from {filename}' if filename.strip() else 'empty (no yaml_filename)'
        self.get_logger().info(
            f'serving map {source}: {grid.shape[1]} x {grid.shape[0]} cells of '
            f'{grid.resolution} m, [{x0:.2f}, {x1:.2f}] x [{y0:.2f}, {y1:.2f}] m in {frame!r}')


def main(args=None) -> None:
    try:
        run_node(MapServerNode, args)
    except MapStartError:
        sys.exit(1)


if __name__ == '__main__':
    main()
