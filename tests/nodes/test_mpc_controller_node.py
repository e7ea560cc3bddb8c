"""Node-level tests of the MPC controller with the real simulator node, in process."""
from biped_msgs.msg import ControllerDiagnostics, ReferenceTrajectory
from nav_msgs.msg import Odometry
import pytest
import rclpy
from rclpy.parameter import Parameter
from sensor_msgs.msg import JointState

from biped_mpc.nodes.mpc_controller import MpcControllerNode
from biped_planner.footsteps import Footstep
from biped_planner.node_support.reference_messages import reference_trajectory_msg
from biped_planner.sides import LEFT, RIGHT
from biped_planner.standing_reference import standing_window
from biped_planner.walking_reference import ReferenceParams
from biped_sim.nodes.simulator import SimulatorNode
from ros_harness import Collector, spin_until, wait_for_subscribers


@pytest.fixture
def loop(ros_context, executor):
    sim_time = Parameter('use_sim_time', value=True)
    executor.track(SimulatorNode(context=ros_context))
    executor.track(MpcControllerNode(context=ros_context, parameter_overrides=[sim_time]))
    client = executor.track(rclpy.create_node('mpc_test_client', context=ros_context))
    g = dict(client=client, executor=executor)
    g['diag'] = Collector(client, ControllerDiagnostics, 'controller_diagnostics', 100)
    g['commands'] = Collector(client, JointState, 'joint_commands', 100)
    g['odom'] = Collector(client, Odometry, 'odom', 100)
    g['refs'] = client.create_publisher(ReferenceTrajectory, 'reference_trajectory', 10)
    assert wait_for_subscribers(executor, g['refs'], timeout=15)
    return g


def standing_reference(g, t: float) -> ReferenceTrajectory:
    left, right = Footstep(LEFT, 0.0, 0.07), Footstep(RIGHT, 0.0, -0.07)
    window = standing_window(left, right, ReferenceParams(foot_length=0.2, foot_width=0.1), t,
                             90, 0.02)
    sec = int(t)
    from builtin_interfaces.msg import Time
    return reference_trajectory_msg(window, 0, 0.02, Time(sec=sec, nanosec=int((t - sec) * 1e9)))


def sim_time(g) -> float:
    stamp = g['odom'].messages[-1].header.stamp
    return stamp.sec + stamp.nanosec * 1e-9


def test_waits_without_reference_then_controls_and_holds_a_stance_when_it_goes_stale(loop):
    g = loop
    assert g['diag'].wait_for(g['executor'], timeout=15)
    assert g['diag'].messages[-1].status == ControllerDiagnostics.WAITING
    assert not g['commands'].messages
    # references at the control rate, as the reference generator publishes them
    for _ in range(50):
        assert g['odom'].wait_for(g['executor'], timeout=5)
        g['refs'].publish(standing_reference(g, sim_time(g)))
        count = len(g['commands'].messages)
        g['commands'].wait_for(g['executor'], lambda m: len(m) > count, timeout=5)
    assert g['commands'].messages, 'no joint command'
    assert len(g['commands'].messages[-1].name) == 12
    ok = [d for d in g['diag'].messages if d.status == ControllerDiagnostics.OK]
    assert len(ok) > 20
    assert all(d.solve_time < 0.05 for d in ok)
    # the cycle's own latency covers the solve (and is not a wall clock reading)
    assert all(d.solve_time < d.cycle_latency < 1.0 for d in ok)
    assert 0.5 < g['odom'].messages[-1].pose.pose.position.z < 0.6  # still standing
    # no more references: the controller holds a stance and says so
    assert g['diag'].wait_for(g['executor'], lambda m: m[-1].status ==
                              ControllerDiagnostics.HOLDING, timeout=10)
    assert 'old' in g['diag'].messages[-1].message
    spin_until(g['executor'], lambda: False, 1.0)
    assert 0.5 < g['odom'].messages[-1].pose.pose.position.z < 0.6


def test_a_malformed_reference_is_rejected_and_control_goes_on(loop):
    g = loop
    assert g['odom'].wait_for(g['executor'], timeout=15)
    bad = standing_reference(g, sim_time(g))
    bad.hip_x = bad.hip_x[:10]
    g['refs'].publish(bad)
    spin_until(g['executor'], lambda: False, 0.3)
    assert all(d.status == ControllerDiagnostics.WAITING for d in g['diag'].messages)
    for _ in range(10):
        g['refs'].publish(standing_reference(g, sim_time(g)))
        count = len(g['commands'].messages)
        g['commands'].wait_for(g['executor'], lambda m: len(m) > count, timeout=5)
    assert g['diag'].messages[-1].status == ControllerDiagnostics.OK
