"""Node-level tests of the walking state machine: real rclpy, real DDS, sim time from the test."""
import math

from biped_msgs.msg import CommandStatus, FootstepPlan, Footstep, WalkCommand, WalkingState
from nav_msgs.msg import Odometry
import pytest
import rclpy
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile

from biped_planner.nodes.state_machine import StateMachineNode
from ros_harness import Collector, SimClock, spin_until, wait_for_subscribers

TIMING = dict(initialize_duration=0.5, single_support=0.3, double_support=0.1)


@pytest.fixture
def graph(ros_context, executor):
    overrides = [Parameter('use_sim_time', value=True)] + [
        Parameter(k, value=v) for k, v in TIMING.items()]
    node = executor.track(StateMachineNode(context=ros_context, parameter_overrides=overrides))
    client = executor.track(rclpy.create_node('test_client', context=ros_context))
    states = Collector(client, WalkingState, 'walking_state', 100)
    statuses = Collector(client, CommandStatus, 'walk_command_status', 100)
    commands = client.create_publisher(WalkCommand, 'walk_command', 10)
    clock = SimClock(client, executor)
    assert wait_for_subscribers(executor, commands)
    assert wait_for_subscribers(executor, clock.publisher)
    clock.advance(0.05)
    assert states.wait_for(executor, timeout=10.0), 'no walking_state published'
    return dict(node=node, client=client, states=states, statuses=statuses, commands=commands,
                clock=clock, executor=executor)


def send(graph, timeout=5.0, **fields) -> CommandStatus:
    count = len(graph['statuses'].messages)
    graph['commands'].publish(WalkCommand(**fields))
    assert graph['statuses'].wait_for(graph['executor'], lambda m: len(m) > count, timeout)
    return graph['statuses'].messages[-1]


def transitions(states):
    """The messages where the phase changed, with the time each phase began."""
    out, last = [], None
    for msg in states:
        if msg.phase != last:
            start = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9 - msg.time_in_phase
            out.append((msg.phase, msg.support_foot, round(start, 6), msg.step_index))
            last = msg.phase
    return out


def test_start_drives_idle_initialize_then_alternating_supports_with_the_timing(graph):
    assert graph['states'].messages[-1].phase == WalkingState.IDLE
    status = send(graph, command=WalkCommand.START)
    assert status.accepted and status.error_code == CommandStatus.OK
    graph['states'].messages.clear()
    graph['clock'].advance(2.0)
    seen = transitions(graph['states'].messages)
    phases = [p for p, *_ in seen]
    assert phases[:7] == [WalkingState.INITIALIZE] + [WalkingState.SINGLE_SUPPORT,
                                                      WalkingState.DOUBLE_SUPPORT] * 3
    starts = [s for _, _, s, _ in seen]
    durations = [b - a for a, b in zip(starts, starts[1:])][:6]
    assert durations == pytest.approx([0.5, 0.3, 0.1, 0.3, 0.1, 0.3], abs=1e-6)
    singles = [support for p, support, _, _ in seen if p == WalkingState.SINGLE_SUPPORT]
    assert singles[:3] == [WalkingState.SUPPORT_RIGHT, WalkingState.SUPPORT_LEFT,
                           WalkingState.SUPPORT_RIGHT]


def test_stop_finishes_the_step_then_idle(graph):
    send(graph, command=WalkCommand.START)
    graph['clock'].advance(0.6)  # in the first single support (0.5 .. 0.8 s)
    assert graph['states'].messages[-1].phase == WalkingState.SINGLE_SUPPORT
    assert send(graph, command=WalkCommand.STOP).accepted
    graph['states'].messages.clear()
    graph['clock'].advance(1.0)
    seen = [p for p, *_ in transitions(graph['states'].messages)]
    assert seen[:3] == [WalkingState.SINGLE_SUPPORT, WalkingState.DOUBLE_SUPPORT,
                        WalkingState.IDLE]
    last = graph['states'].messages[-1]
    assert last.phase == WalkingState.IDLE and last.step_index == 1


@pytest.mark.parametrize('fields, code, words', [
    (dict(command=WalkCommand.OMNI, step_time=math.nan), CommandStatus.INVALID_VALUE,
     'step_time must be finite'),
    (dict(command=WalkCommand.START, step_time=-0.5), CommandStatus.INVALID_VALUE,
     'step_time -0.5'),
    (dict(command=7), CommandStatus.UNKNOWN_COMMAND, 'unknown command 7'),
    (dict(command=WalkCommand.OMNI, step_length=2.0), CommandStatus.INVALID_VALUE,
     'step_length 2.0 outside'),
    (dict(command=WalkCommand.GOTO, goal_x=math.inf), CommandStatus.INVALID_VALUE, 'goal_x'),
])
def test_bad_commands_are_rejected_with_a_status_and_the_node_keeps_working(
        graph, fields, code, words):
    status = send(graph, **fields)
    assert not status.accepted
    assert status.error_code == code
    assert words in status.error_msg
    graph['clock'].advance(0.1)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE
    assert send(graph, command=WalkCommand.START).accepted
    graph['clock'].advance(0.1)
    assert graph['states'].messages[-1].phase == WalkingState.INITIALIZE


def test_a_footstep_plan_sets_the_number_of_steps_and_first_support(graph):
    qos = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    plans = graph['client'].create_publisher(FootstepPlan, 'footstep_plan', qos)
    steps = [Footstep(side=Footstep.LEFT, x=0.0, y=0.1), Footstep(side=Footstep.RIGHT, y=-0.1),
             Footstep(side=Footstep.RIGHT, x=0.1, y=-0.1), Footstep(side=Footstep.LEFT, x=0.2,
                                                                      y=0.1)]
    plans.publish(FootstepPlan(plan_id=3, status=FootstepPlan.STATUS_OK, footsteps=steps,
                               single_support=0.2, double_support=0.1))
    assert wait_for_subscribers(graph['executor'], plans)
    graph['clock'].advance(0.05)
    send(graph, command=WalkCommand.GOTO, goal_x=0.2)
    graph['states'].messages.clear()
    graph['clock'].advance(1.5)
    seen = transitions(graph['states'].messages)
    singles = [support for p, support, _, _ in seen if p == WalkingState.SINGLE_SUPPORT]
    assert singles == [WalkingState.SUPPORT_LEFT, WalkingState.SUPPORT_RIGHT]
    assert seen[-1][0] == WalkingState.IDLE
    assert graph['states'].messages[-1].plan_id == 3
    assert graph['states'].messages[-1].reason == 'plan finished'


def test_fall_reported_by_odometry_and_reset(graph):
    odom = graph['client'].create_publisher(Odometry, 'odom', 10)
    assert wait_for_subscribers(graph['executor'], odom)
    send(graph, command=WalkCommand.START)
    fallen = Odometry()
    fallen.pose.pose.position.z = 0.2
    fallen.pose.pose.orientation.w = 1.0
    odom.publish(fallen)
    assert spin_until(graph['executor'], lambda: graph['states'].messages[-1].fallen, 5.0)
    assert graph['states'].messages[-1].phase == WalkingState.FALLEN
    status = send(graph, command=WalkCommand.START)
    assert not status.accepted and status.error_code == CommandStatus.NOT_ALLOWED
    assert send(graph, command=WalkCommand.RESET).accepted
    graph['clock'].advance(0.05)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE


def test_parameters_out_of_range_are_rejected_live(graph):
    node = graph['node']
    result = node.set_parameters([Parameter('single_support', value=-1.0)])[0]
    assert not result.successful
    result = node.set_parameters([Parameter('double_support', value=0.2)])[0]
    assert result.successful
    result = node.set_parameters([Parameter('first_support', value=5)])[0]
    assert not result.successful
