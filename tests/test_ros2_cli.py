"""The ros2cli stand-in: YAML to messages (nested, sequences, errors) and a real publish."""
import subprocess

from biped_msgs.msg import FootstepPlan, WalkCommand
import pytest
import rclpy

from biped_tools import ros2_cli
from biped_tools.interface_types import import_interface
from ros_harness import Collector, PYTHON, REPO, ros_environment, spin_until

CLI = str(REPO / 'scripts' / 'ros2_cli.py')


def test_fill_sets_nested_fields_sequences_of_messages_and_converts_ints_to_floats():
    plan = ros2_cli.fill(FootstepPlan(), {
        'plan_id': 4, 'single_support': 1, 'header': {'frame_id': 'map'},
        'footsteps': [{'side': 0, 'x': 0.1}, {'side': 1, 'y': -0.1}]}, None)
    assert plan.plan_id == 4 and plan.single_support == 1.0
    assert plan.header.frame_id == 'map'
    assert [(f.side, f.x, f.y) for f in plan.footsteps] == [(0, 0.1, 0.0), (1, 0.0, -0.1)]
    plain = ros2_cli.to_plain(plan)
    assert plain['footsteps'][1]['y'] == -0.1


@pytest.mark.parametrize('values, words', [
    ({'comand': 1}, "no field 'comand'"),
    ({'command': 'go'}, 'cannot take'),
    ({'header': 5}, 'expected a mapping'),
    ({'command': 300}, r'expected an integer in \[0, 255\]'),
    ({'step_time': True}, 'expected a number'),
])
def test_fill_errors_name_the_field(values, words):
    with pytest.raises(ValueError, match=words):
        ros2_cli.fill(WalkCommand(), values, None)


@pytest.mark.parametrize('name', ['biped_msgs/msg/Nope', 'nopkg/msg/X', 'just_a_name'])
def test_unknown_types_are_clear_errors(name):
    with pytest.raises(ValueError):
        import_interface(name)


def test_topic_pub_once_reaches_a_subscriber(ros_context, executor):
    node = executor.track(rclpy.create_node('cli_test_sink', context=ros_context))
    received = Collector(node, WalkCommand, 'walk_command')
    process = subprocess.Popen([PYTHON, CLI, 'topic', 'pub', '--once', 'walk_command',
                                'biped_msgs/msg/WalkCommand',
                                '{command: 3, step_length: 0.1, step_width: -0.05}'],
                               env=ros_environment(), stdout=subprocess.PIPE, text=True)
    assert spin_until(executor, lambda: received.messages, timeout=20)
    assert process.wait(timeout=20) == 0
    msg = received.messages[0]
    assert (msg.command, msg.step_length, msg.step_width) == (3, 0.1, -0.05)


def test_topic_pub_with_a_bad_field_exits_2_without_publishing():
    result = subprocess.run([PYTHON, CLI, 'topic', 'pub', '--once', '--timeout', '0.1',
                             'walk_command', 'biped_msgs/msg/WalkCommand', '{x: 1}'],
                            env=ros_environment(), capture_output=True, text=True, timeout=30)
    assert result.returncode == 2
    assert "WalkCommand has no field 'x'" in result.stderr


def fresh_shell_environment() -> dict:
    """The environment of a shell that sourced nothing: what the venv's start-up must set."""
    env = ros_environment()
    for name in ('AMENT_PREFIX_PATH', 'LD_LIBRARY_PATH', 'PYTHONPATH', 'ROS_DISTRO',
                 'ROS_VERSION', 'ROS_PYTHON_VERSION', '_ROS_WHEELS_BOOTSTRAP_COMPLETE'):
        env.pop(name, None)
    return env


def test_a_fresh_venv_python_resolves_standard_and_workspace_packages_by_the_ament_index():
    probe = ('import os, sys\n'
             'from ament_index_python import get_package_share_directory as share\n'
             'print(share("geometry_msgs")); print(share("biped_msgs"))\n'
             'print(os.environ["AMENT_PREFIX_PATH"]); print(os.environ["ROS_DISTRO"])\n'
             'print(sys.prefix)\n')
    result = subprocess.run([PYTHON, '-c', probe], env=fresh_shell_environment(),
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    geometry, biped, prefixes, distro, venv = result.stdout.split('\n')[:5]
    assert geometry == f'{venv}/share/geometry_msgs'
    assert biped == str(REPO / 'ros2_ws' / 'install' / 'biped_msgs' / 'share' / 'biped_msgs')
    # the workspace overlays the venv, as sourcing the underlay, then the workspace, orders them
    prefixes = prefixes.split(':')
    assert prefixes[-1] == venv and str(REPO / 'ros2_ws' / 'install' / 'biped_msgs') in prefixes
    assert distro == 'jazzy'


@pytest.mark.parametrize('name, words', [
    ('geometry_msgs/msg/Twist', 'Vector3  linear'),
    ('biped_msgs/msg/WalkCommand', 'uint8 command'),
    ('std_srvs/srv/Trigger', 'string message'),
])
def test_interface_show_finds_the_definition_through_the_ament_index(name, words):
    result = subprocess.run([PYTHON, CLI, 'interface', 'show', name],
                            env=fresh_shell_environment(), capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 0, result.stderr
    assert words in result.stdout


@pytest.mark.parametrize('name, code, words', [
    ('nopkg/msg/X', 1, "package 'nopkg' not found"),
    ('geometry_msgs/msg/Nope', 1, 'no '),
    ('geometry_msgs/Twist', 2, 'expected package/msg|srv|action/Type'),
])
def test_interface_show_of_an_unknown_type_is_a_clear_error(name, code, words):
    result = subprocess.run([PYTHON, CLI, 'interface', 'show', name],
                            env=fresh_shell_environment(), capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == code
    assert words in result.stderr and 'Traceback' not in result.stderr
