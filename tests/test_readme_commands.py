"""Every `ros2 ...` command of the README's Usage section, checked line by line: the arguments
parse as ros2cli's do, the interface type exists, the YAML fills a message of that type (the
field names and value types are right), and the topic or service is one the graph serves."""
import re
import shlex

import pytest
import yaml

from biped_tools import ros2_cli
from biped_tools.interface_types import import_interface
from ros_harness import REPO

# the names the graph's nodes subscribe to or serve (tests/graph and the node docstrings)
GRAPH_TOPICS = {'walk_command', 'goal_pose', 'cmd_vel', 'walking_state', 'footstep_plan',
                'map', 'odom', 'joint_states', 'reference_trajectory', 'step_adjustment',
                'balance_estimate'}
GRAPH_SERVICES = {'reset', 'push', 'set_terrain', 'plan_walk', 'simulator/resume'}


def usage_commands() -> list:
    text = (REPO / 'README.md').read_text()
    usage = text[text.index('## Usage'):text.index('## Library usage')]
    # whole commands (with an interface type), not a flag quoted in the prose
    return sorted(set(re.findall(r'`(ros2 (?:topic|service|interface) [^`]*/(?:msg|srv)/[^`]*)`',
                                 usage)))


COMMANDS = usage_commands()


def test_the_usage_section_has_the_commands_a_user_needs():
    verbs = {' '.join(shlex.split(c)[1:3]) for c in COMMANDS}
    assert {'topic pub', 'topic echo', 'service call', 'interface show'} <= verbs
    assert len(COMMANDS) >= 10


@pytest.mark.parametrize('command', COMMANDS)
def test_each_usage_command_parses_and_fills_its_interface(command):
    argv = shlex.split(command)[1:]
    args = ros2_cli.build_parser().parse_args(argv)
    if args.group == 'interface':
        assert import_interface(args.type, kind=args.type.split('/')[1]) is not None
        return
    if args.group == 'topic':
        assert args.topic in GRAPH_TOPICS, args.topic
        cls = import_interface(args.type, kind='msg')
        values = yaml.safe_load(args.values) if getattr(args, 'values', '') else None
        message = ros2_cli.fill(cls(), values, None)
    else:
        assert args.service in GRAPH_SERVICES, args.service
        cls = import_interface(args.type, kind='srv')
        values = yaml.safe_load(args.values) if args.values else None
        message = ros2_cli.fill(cls.Request(), values, None)
    # every value given reached the message (fill refuses unknown fields; this checks values)
    plain = ros2_cli.to_plain(message)

    def contains(given, filled) -> bool:
        if isinstance(given, dict):
            return all(contains(v, filled[k]) for k, v in given.items())
        return given == pytest.approx(filled)
    assert values is None or contains(values, plain)
