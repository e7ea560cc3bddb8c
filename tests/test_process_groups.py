"""How bringup --compose groups the nodes into processes (no ROS needed)."""
import pytest

from biped_tools.bringup import parse_compose
from biped_tools.node_graph import CONTROL_PATH, KNOWN_NODES, process_groups

NODES = list(KNOWN_NODES)


def test_without_composition_every_node_is_its_own_process():
    assert process_groups(NODES, []) == [[name] for name in NODES]


def test_a_group_is_one_process_at_the_place_of_its_first_node_in_start_order():
    groups = process_groups(NODES, [['mpc_controller', 'simulator']])
    assert groups[0] == ['simulator', 'mpc_controller']
    assert sorted(sum(groups, [])) == sorted(NODES)
    assert len(groups) == len(NODES) - 1


def test_the_control_path_and_all_keywords():
    assert parse_compose(['control'], NODES) == [list(CONTROL_PATH)]
    assert parse_compose(['all'], NODES) == [NODES]
    assert parse_compose(['simulator,mpc_controller', 'map_server,'], NODES) == [
        ['simulator', 'mpc_controller'], ['map_server']]
    # the control path of a graph started without some of its nodes
    assert parse_compose(['control'], ['simulator', 'mpc_controller']) == [
        ['simulator', 'mpc_controller']]


@pytest.mark.parametrize('compose, message', [
    ([['simulator', 'teleop']], "'teleop', which is not started"),
    ([['simulator'], ['simulator', 'mpc_controller']], 'in two groups'),
])
def test_a_group_naming_a_node_not_started_or_twice_is_refused(compose, message):
    with pytest.raises(ValueError, match=message):
        process_groups(NODES, compose)
