"""The map server node: a nav2 map file or an empty map around the start, latched on `map`."""
from pathlib import Path
import subprocess

from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
import numpy as np
import pytest
import rclpy
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from biped_planner.example_maps import paper_start_goal_example
from biped_planner.map_file import save_map
from biped_planner.node_support.map_messages import grid_from_msg
from biped_planner.nodes.map_server import MapServerNode, MapStartError
from biped_planner.occupancy_grid import BoxObstacle, OccupancyGrid
from ros_harness import Collector, PYTHON, REPO, ros_environment

SHIPPED = REPO / 'ros2_ws' / 'src' / 'biped_planner' / 'maps' / 'paper_start_goal.yaml'
# What the planner and the simulator subscribe with.
LATCHED_IN = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                        reliability=ReliabilityPolicy.RELIABLE)


def served_map(executor, ros_context, overrides):
    """Start the server, then a late subscriber: the latched map must still reach it."""
    executor.track(MapServerNode(context=ros_context, parameter_overrides=overrides))
    client = executor.track(rclpy.create_node('map_test_client', context=ros_context))
    maps = Collector(client, OccupancyGridMsg, 'map', LATCHED_IN)
    assert maps.wait_for(executor, timeout=15)
    assert len(maps.messages) == 1
    return maps.messages[0]


def test_without_a_file_an_empty_map_is_centred_on_the_start(executor, ros_context):
    msg = served_map(executor, ros_context, [
        Parameter('empty_map.size', value=4.0), Parameter('empty_map.resolution', value=0.1),
        Parameter('empty_map.center_x', value=1.0), Parameter('empty_map.center_y', value=-2.0)])
    assert msg.header.frame_id == 'map'
    grid = grid_from_msg(msg)
    assert grid.shape == (40, 40) and grid.resolution == pytest.approx(0.1)
    # the resolution travels as float32
    assert grid.extent == pytest.approx((-1.0, 3.0, -4.0, 0.0), abs=1e-6)
    assert not np.any(grid.values)


def test_the_default_empty_map_holds_the_readme_goal(executor, ros_context):
    grid = grid_from_msg(served_map(executor, ros_context, []))
    x0, x1, y0, y1 = grid.extent
    assert x0 < 0.0 < 3.4 < x1 and y0 < 0.0 < 3.4 < y1


def test_the_shipped_paper_map_file_is_served_as_its_grid(executor, ros_context):
    msg = served_map(executor, ros_context, [Parameter('yaml_filename', value=str(SHIPPED))])
    grid = grid_from_msg(msg)
    expected, _, _ = paper_start_goal_example()
    assert grid.shape == expected.shape and grid.origin == pytest.approx(expected.origin)
    np.testing.assert_array_equal(grid.values, expected.values)


def test_a_png_map_with_an_origin_and_negate_is_served(executor, ros_context, tmp_path):
    from PIL import Image
    grid = OccupancyGrid.from_obstacles((2.0, 1.0), 0.05, [BoxObstacle(0.5, 0.2, 1.0, 0.6)])
    yaml_path, image = save_map(grid, tmp_path / 'room.yaml', 'room.png')
    # negate: dark pixels are free; the image is inverted to match
    Image.fromarray(255 - np.asarray(Image.open(image))).save(image)
    yaml_path.write_text(yaml_path.read_text().replace('negate: 0', 'negate: 1').replace(
        '- 0.0\n- 0.0\n', '- -1.5\n- 2.0\n', 1))
    served = grid_from_msg(served_map(executor, ros_context,
                                      [Parameter('yaml_filename', value=str(yaml_path))]))
    assert served.origin == pytest.approx((-1.5, 2.0))
    np.testing.assert_array_equal(served.values == 100, grid.values == 100)


def test_parameters_are_described_and_read_only(executor, ros_context):
    node = executor.track(MapServerNode(context=ros_context))
    names = [n for n in node._parameters
             if n not in ('use_sim_time', 'start_type_description_service')]
    assert sorted(names) == ['empty_map.center_x', 'empty_map.center_y',
                             'empty_map.resolution', 'empty_map.size', 'frame_id',
                             'yaml_filename']
    for descriptor in node.describe_parameters(names):
        assert descriptor.description and descriptor.read_only, descriptor.name
    result = node.set_parameters([Parameter('yaml_filename', value=str(SHIPPED))])[0]
    assert not result.successful


def bad_files(tmp_path: Path):
    ok = tmp_path / 'ok.pgm'
    save_map(paper_start_goal_example()[0], tmp_path / 'ok.yaml', 'ok.pgm')
    cases = {
        'missing': (None, 'does not exist'),
        'not_yaml': ('image: [unclosed', 'cannot read map file'),
        'no_resolution': (f'image: {ok.name}\norigin: [0, 0, 0]\n', 'resolution'),
        'nan_resolution': (f'image: {ok.name}\nresolution: .nan\norigin: [0, 0, 0]\n',
                           'resolution'),
        'bad_origin': (f'image: {ok.name}\nresolution: 0.1\norigin: [0, 0]\n', 'origin'),
        'inf_origin': (f'image: {ok.name}\nresolution: 0.1\norigin: [.inf, 0, 0]\n', 'origin'),
        'bad_negate': (f'image: {ok.name}\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 3\n',
                       'negate'),
        'no_image': ('image: nowhere.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n',
                     'cannot read image'),
    }
    files = {}
    for name, (text, words) in cases.items():
        path = tmp_path / f'{name}.yaml'
        if text is not None:
            path.write_text(text)
        files[name] = (path, words)
    return files


@pytest.mark.parametrize('case', ['missing', 'not_yaml', 'no_resolution', 'nan_resolution',
                                  'bad_origin', 'inf_origin', 'bad_negate', 'no_image'])
def test_a_bad_map_file_stops_the_node_naming_the_file_and_field(ros_context, tmp_path, case):
    path, words = bad_files(tmp_path)[case]
    with pytest.raises(MapStartError) as error:
        MapServerNode(context=ros_context,
                      parameter_overrides=[Parameter('yaml_filename', value=str(path))])
    assert str(path) in str(error.value) and words in str(error.value)


@pytest.mark.parametrize('name, value', [('empty_map.resolution', 0.0),
                                         ('empty_map.size', float('nan')),
                                         ('empty_map.size', 1000.0), ('frame_id', '')])
def test_a_bad_empty_map_parameter_stops_the_node(ros_context, name, value):
    overrides = [Parameter(name, value=value)]
    if name == 'empty_map.size' and value == 1000.0:
        overrides.append(Parameter('empty_map.resolution', value=0.005))  # 4e10 cells
    with pytest.raises(MapStartError, match=name.split('.')[-1]):
        MapServerNode(context=ros_context, parameter_overrides=overrides)


def test_the_node_process_exits_1_with_the_error_logged(tmp_path):
    path, words = bad_files(tmp_path)['nan_resolution']
    result = subprocess.run(
        [PYTHON, '-m', 'biped_planner.nodes.map_server', '--ros-args', '-p',
         f'yaml_filename:={path}'], env=ros_environment(), capture_output=True, text=True,
        timeout=60)
    assert result.returncode == 1
    output = result.stdout + result.stderr
    assert 'no map to serve' in output and str(path) in output and words in output
    assert 'Traceback' not in output
