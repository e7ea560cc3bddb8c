"""Node-level tests of the footstep planner and the reference generator, with the state machine:
real rclpy, real DDS, sim time driven by the test."""
import math

from biped_msgs.msg import FootstepPlan, ReferenceTrajectory, WalkCommand, WalkingState
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg, Odometry, Path
import numpy as np
import pytest
import rclpy
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile
from visualization_msgs.msg import MarkerArray

from biped_planner.example_maps import paper_start_goal_example
from biped_planner.node_support.map_messages import grid_to_msg
from biped_planner.node_support.reference_messages import window_from_reference_msg
from biped_planner.nodes.footstep_planner import FootstepPlannerNode
from biped_planner.nodes.reference_generator import ReferenceGeneratorNode
from biped_planner.nodes.state_machine import StateMachineNode
from ros_harness import Collector, SimClock, spin_until, wait_for_subscribers

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


def odometry(x, y, yaw=0.0, z=0.55):
    msg = Odometry()
    msg.header.frame_id = 'map'
    msg.pose.pose.position.x, msg.pose.pose.position.y, msg.pose.pose.position.z = x, y, z
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(
        yaw / 2)
    return msg


def goal(x, y, yaw=0.0, frame='map'):
    msg = PoseStamped()
    msg.header.frame_id = frame
    msg.pose.position.x, msg.pose.position.y = x, y
    msg.pose.orientation.z, msg.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return msg


@pytest.fixture
def graph(ros_context, executor):
    sim_time = [Parameter('use_sim_time', value=True)]
    for make in (StateMachineNode, FootstepPlannerNode, ReferenceGeneratorNode):
        executor.track(make(context=ros_context, parameter_overrides=sim_time))
    client = executor.track(rclpy.create_node('planner_test_client', context=ros_context))
    g = dict(client=client, executor=executor, clock=SimClock(client, executor))
    g['plans'] = Collector(client, FootstepPlan, 'footstep_plan', LATCHED)
    g['paths'] = Collector(client, Path, 'plan', LATCHED)
    g['markers'] = Collector(client, MarkerArray, 'footstep_markers', LATCHED)
    g['refs'] = Collector(client, ReferenceTrajectory, 'reference_trajectory', 10)
    g['states'] = Collector(client, WalkingState, 'walking_state', 50)
    g['map'] = client.create_publisher(OccupancyGridMsg, 'map', LATCHED)
    g['odom'] = client.create_publisher(Odometry, 'odom', 10)
    g['goal'] = client.create_publisher(PoseStamped, 'goal_pose', 10)
    g['command'] = client.create_publisher(WalkCommand, 'walk_command', 10)
    g['cmd_vel'] = client.create_publisher(Twist, 'cmd_vel', 10)
    for name in ('odom', 'goal', 'command', 'cmd_vel'):
        assert wait_for_subscribers(executor, g[name], count=1, timeout=15), name
    assert wait_for_subscribers(executor, g['clock'].publisher, count=3, timeout=15)
    grid, start, goal_pose = paper_start_goal_example()
    g['start'], g['goal_pose'] = start, goal_pose
    g['map'].publish(grid_to_msg(grid, 'map', client.get_clock().now().to_msg()))
    assert wait_for_subscribers(executor, g['map'], count=1, timeout=15)
    g['odom'].publish(odometry(start.x, start.y, start.yaw))
    g['clock'].advance(0.1)
    return g


def latest_plan(g, timeout=10.0, count=None):
    count = len(g['plans'].messages) if count is None else count
    assert g['plans'].wait_for(g['executor'], lambda m: len(m) > count, timeout), 'no plan'
    return g['plans'].messages[-1]


def test_goto_plans_footsteps_around_obstacles_and_the_walk_gets_its_references(graph):
    g = graph
    target = g['goal_pose']
    g['goal'].publish(goal(target.x, target.y, target.yaw))
    plan = latest_plan(g)
    assert plan.status == FootstepPlan.STATUS_OK and not plan.continuous
    last_two = plan.footsteps[-2:]
    middle = np.mean([[f.x, f.y] for f in last_two], axis=0)
    assert np.hypot(*(middle - [target.x, target.y])) < 0.02
    assert g['paths'].wait_for(g['executor'], timeout=5) and len(g['paths'].messages[-1].poses)
    assert g['markers'].wait_for(g['executor'], timeout=5)
    assert len(g['markers'].messages[-1].markers) == len(plan.footsteps) + 1  # + DELETEALL
    g['command'].publish(WalkCommand(command=WalkCommand.START))
    g['clock'].advance(1.5)
    refs = [r for r in g['refs'].messages if r.plan_id == plan.plan_id]
    assert refs, 'no reference for the plan'
    window = window_from_reference_msg(refs[-1])
    assert len(window.t) == 90
    # the ZMP reference stays inside its support bounds over the whole horizon
    assert np.all(window.zmp >= window.zmp_min - 1e-9)
    assert np.all(window.zmp <= window.zmp_max + 1e-9)
    phases = {s.phase for s in g['states'].messages}
    assert WalkingState.SINGLE_SUPPORT in phases


@pytest.mark.parametrize('x, y, frame, code', [
    (1.3, 0.5, 'map', FootstepPlan.ERROR_GOAL_OCCUPIED),
    (9.0, 9.0, 'map', FootstepPlan.ERROR_GOAL_OUTSIDE_MAP),
    (3.0, 3.0, 'odom', FootstepPlan.ERROR_UNKNOWN_FRAME),
    (math.nan, 3.0, 'map', FootstepPlan.ERROR_INVALID_COMMAND),
])
def test_bad_goals_give_a_failed_plan_with_its_error_code(graph, x, y, frame, code):
    graph['goal'].publish(goal(x, y, frame=frame))
    plan = latest_plan(graph)
    assert plan.status == FootstepPlan.STATUS_FAILED
    assert plan.error_code == code
    assert plan.error_msg


def test_a_malformed_map_is_rejected_and_goals_then_report_no_map(graph):
    bad = OccupancyGridMsg()
    bad.header.frame_id = 'map'
    bad.info.width, bad.info.height, bad.info.resolution = 10, 10, 0.1
    bad.info.origin.orientation.w = 1.0
    bad.data = [0] * 7  # 100 cells announced
    graph['map'].publish(bad)
    graph['clock'].advance(0.2)
    graph['goal'].publish(goal(3.0, 3.0))
    plan = latest_plan(graph)
    assert plan.error_code == FootstepPlan.ERROR_NO_MAP


def test_teleop_cmd_vel_starts_a_continuous_plan_that_grows_while_walking(graph):
    g = graph
    g['cmd_vel'].publish(Twist())  # walk in place
    first = latest_plan(g)
    assert first.status == FootstepPlan.STATUS_OK and first.continuous
    g['clock'].advance(3.0)
    plans = [p for p in g['plans'].messages if p.plan_id == first.plan_id]
    assert len(plans[-1].footsteps) > len(first.footsteps)
    steps = max(s.step_index for s in g['states'].messages)
    assert steps >= 3
    # keeps the lookahead: footsteps cover the step being taken plus two more
    assert len(plans[-1].footsteps) >= steps + 3 + 2
    # walking in place: every landing stays beside the start
    xy = np.array([[f.x, f.y] for f in plans[-1].footsteps])
    assert np.all(np.hypot(xy[:, 0] - g['start'].x, xy[:, 1] - g['start'].y) < 0.15)
    count = len(g['plans'].messages)
    g['command'].publish(WalkCommand(command=WalkCommand.STOP))
    stop_plan = latest_plan(g, count=count)
    assert not stop_plan.continuous
    g['clock'].advance(3.0)
    assert g['states'].messages[-1].phase == WalkingState.IDLE
    assert g['states'].messages[-1].reason == 'plan finished'


def test_non_finite_cmd_vel_is_ignored(graph):
    count = len(graph['plans'].messages)
    twist = Twist()
    twist.linear.x = math.inf
    graph['cmd_vel'].publish(twist)
    graph['clock'].advance(0.3)
    assert not spin_until(graph['executor'], lambda: len(graph['plans'].messages) > count, 0.5)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE


def state_machine_and_fake_planner(ros_context, executor, name, *overrides):
    """A state machine on sim time and a client that plays the planner: (state machine node,
    clock, walking_state collector, footstep_plan and walk_command publishers)."""
    node = executor.track(StateMachineNode(context=ros_context, parameter_overrides=[
        Parameter('use_sim_time', value=True), *overrides]))
    client = executor.track(rclpy.create_node(name, context=ros_context))
    clock = SimClock(client, executor)
    states = Collector(client, WalkingState, 'walking_state', 100)
    plans = client.create_publisher(FootstepPlan, 'footstep_plan', LATCHED)
    commands = client.create_publisher(WalkCommand, 'walk_command', 10)
    assert wait_for_subscribers(executor, commands) and wait_for_subscribers(executor, plans)
    assert wait_for_subscribers(executor, clock.publisher)
    return node, clock, states, plans, commands


def test_a_silent_planner_ends_a_teleop_walk_where_its_plan_ends(ros_context, executor):
    """Only the state machine and a fake planner's single continuous plan: no extension comes."""
    from biped_msgs.msg import Footstep
    node, clock, states, plans, commands = state_machine_and_fake_planner(
        ros_context, executor, 'silent_planner', Parameter('plan_timeout', value=1.0))
    feet = [Footstep(side=i % 2, x=0.0, y=0.07 if i % 2 == 0 else -0.07) for i in range(6)]
    commands.publish(WalkCommand(command=WalkCommand.START))
    clock.advance(0.1)
    plans.publish(FootstepPlan(plan_id=1, continuous=True, footsteps=feet, single_support=0.4,
                               double_support=0.2))
    clock.advance(6.0)
    last = states.messages[-1]
    assert last.phase == WalkingState.IDLE and last.inputs_stale
    assert last.step_index == 4  # the 4 steps of the last plan, then stop
    assert node.phase.name == 'IDLE'


def test_with_a_planner_running_a_start_waits_for_the_plan(ros_context, executor):
    """Initialize shifts the COM to the plan's first support foot: no plan, no start."""
    from biped_msgs.msg import Footstep
    _, clock, states, plans, commands = state_machine_and_fake_planner(
        ros_context, executor, 'slow_planner')
    commands.publish(WalkCommand(command=WalkCommand.START))
    clock.advance(0.5)
    assert states.messages[-1].phase == WalkingState.IDLE
    plan_time = clock.t
    feet = [Footstep(side=i % 2, y=0.07 if i % 2 == 0 else -0.07) for i in range(4)]
    plans.publish(FootstepPlan(plan_id=1, footsteps=feet, single_support=0.4,
                               double_support=0.2))
    clock.advance(0.1)
    walking = [s for s in states.messages if s.phase == WalkingState.INITIALIZE]
    assert walking, 'the plan did not start the walk'
    assert walking[0].walk_start_time >= plan_time - 1e-6
