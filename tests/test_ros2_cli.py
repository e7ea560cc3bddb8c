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
