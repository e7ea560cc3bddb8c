"""Which clock bringup gives the nodes (no ROS needed)."""
from biped_tools.bringup import build_parser, follows_sim_time
from biped_tools.node_graph import KNOWN_NODES

WORKSTATION = ['map_server', 'state_machine', 'footstep_planner', 'reference_generator',
               'mpc_controller']


def clock(argv, nodes):
    return follows_sim_time(build_parser().parse_args(argv), nodes)


def test_beside_the_simulator_the_nodes_follow_its_clock():
    assert clock([], list(KNOWN_NODES))
    assert clock(['--nodes', 'simulator'], ['simulator'])


def test_without_the_simulator_the_wall_clock_unless_sim_time_is_asked_for():
    assert not clock([], WORKSTATION)
    assert clock(['--sim-time'], WORKSTATION)
