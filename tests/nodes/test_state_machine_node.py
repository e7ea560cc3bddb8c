"""Node-level tests of the walking state machine: real rclpy, real DDS, sim time from the test.

The state machine is the one entry point of user intent; where a test needs a footstep planner,
a client node plays it (FakePlanner: serves plan_walk, publishes footstep_plan).
"""
import math
import threading

from biped_msgs.msg import (CommandStatus, ControllerDiagnostics, Footstep, FootstepPlan,
                            ReferenceTrajectory, WalkCommand, WalkingState)
from biped_msgs.srv import PlanWalk
from builtin_interfaces.msg import Time
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_srvs.srv import Trigger

from biped_planner.nodes.state_machine import StateMachineNode
from ros_harness import (Collector, goal_pose_msg, SimClock, spin_until,
                         wait_for_subscribers)

TIMING = dict(initialize_duration=0.5, single_support=0.3, double_support=0.1)
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
PACE = 2.0  # simulated seconds per wall second where the node also times on the wall clock


class FakePlanner:
    """Plays the footstep planner: serves plan_walk, keeps the requests, and publishes the plan
    that make_plan(request) returns (if any) with the request's id."""

    def __init__(self, node, accept: bool = True, make_plan=None) -> None:
        self.requests = []
        self.accept = accept
        self.make_plan = make_plan
        self.plans = node.create_publisher(FootstepPlan, 'footstep_plan', LATCHED)
        self.service = node.create_service(PlanWalk, 'plan_walk', self._on_request)

    def _on_request(self, request, response):
        self.requests.append(request)
        plan = self.make_plan(request) if self.make_plan is not None else None
        if plan is not None:
            plan.request_id = request.request_id
            self.plans.publish(plan)
            response.plan_id = plan.plan_id
        response.accepted = self.accept
        return response


def feet(count, continuous=False, plan_id=1):
    """A plan in place: count footsteps alternating from the left foot."""
    steps = [Footstep(side=i % 2, x=0.0, y=0.07 if i % 2 == 0 else -0.07) for i in range(count)]
    return FootstepPlan(plan_id=plan_id, status=FootstepPlan.STATUS_OK, footsteps=steps,
                        continuous=continuous, single_support=0.4, double_support=0.2)


def make_graph(ros_context, executor, *overrides, planner=None):
    params = [Parameter('use_sim_time', value=True),
              Parameter('use_planner', value=planner is not None)] + [
        Parameter(k, value=v) for k, v in TIMING.items()] + list(overrides)
    node = executor.track(StateMachineNode(context=ros_context, parameter_overrides=params))
    client = executor.track(rclpy.create_node('test_client', context=ros_context))
    g = dict(node=node, client=client, executor=executor, clock=SimClock(client, executor))
    g['states'] = Collector(client, WalkingState, 'walking_state', 100)
    g['statuses'] = Collector(client, CommandStatus, 'walk_command_status', 100)
    g['commands'] = client.create_publisher(WalkCommand, 'walk_command', 10)
    g['goal'] = client.create_publisher(PoseStamped, 'goal_pose', 10)
    g['cmd_vel'] = client.create_publisher(Twist, 'cmd_vel', 10)
    g['odom'] = client.create_publisher(Odometry, 'odom', 10)
    if planner is not None:
        g['planner'] = FakePlanner(client, **planner)
        assert spin_until(executor, node.planner_available, 10.0), 'plan_walk not discovered'
    for name in ('commands', 'goal', 'cmd_vel', 'odom'):
        assert wait_for_subscribers(executor, g[name]), name
    assert wait_for_subscribers(executor, g['clock'].publisher)
    g['clock'].advance(0.05)
    assert g['states'].wait_for(executor, timeout=10.0), 'no walking_state published'
    return g


@pytest.fixture
def graph(ros_context, executor):
    return make_graph(ros_context, executor)


def answer_to(g, publish, timeout=5.0) -> CommandStatus:
    count = len(g['statuses'].messages)
    publish()
    assert g['statuses'].wait_for(g['executor'], lambda m: len(m) > count, timeout)
    return g['statuses'].messages[-1]


def send(g, timeout=5.0, **fields) -> CommandStatus:
    return answer_to(g, lambda: g['commands'].publish(WalkCommand(**fields)), timeout)


def twist(vx=0.0, vy=0.0, wz=0.0, **extra):
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.angular.z = vx, vy, wz
    for name, value in extra.items():
        part, axis = name.split('_')
        setattr(getattr(msg, part), axis, value)
    return msg


def odometry(t, z=0.55, frame='map', q=(0.0, 0.0, 0.0, 1.0), x=0.0):
    msg = Odometry()
    msg.header.frame_id = frame
    msg.header.stamp = Time(sec=int(t), nanosec=int((t - int(t)) * 1e9))  # as SimClock
    msg.pose.pose.position.x, msg.pose.pose.position.z = x, z
    o = msg.pose.pose.orientation
    o.x, o.y, o.z, o.w = q
    return msg


def run(g, seconds, every=None, publish=(), pace=PACE):
    """Advance the clock by seconds; every `every` s of it call each of publish (None: once
    at the end)."""
    step = every or seconds
    for _ in range(int(round(seconds / step))):
        g['clock'].advance(step, pace=pace)
        for action in publish:
            action()


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
    (dict(command=WalkCommand.GOTO, goal_x=1.0, header={'frame_id': 'odom'}),
     CommandStatus.INVALID_VALUE, "GOTO in frame 'odom'"),
])
def test_bad_commands_are_rejected_with_a_status_and_the_node_keeps_working(
        graph, fields, code, words):
    header = fields.pop('header', None)
    msg = WalkCommand(**fields)
    if header:
        msg.header.frame_id = header['frame_id']
    status = answer_to(graph, lambda: graph['commands'].publish(msg))
    assert not status.accepted
    assert status.error_code == code
    assert words in status.error_msg
    graph['clock'].advance(0.1)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE
    assert send(graph, command=WalkCommand.START).accepted
    graph['clock'].advance(0.1)
    assert graph['states'].messages[-1].phase == WalkingState.INITIALIZE


@pytest.mark.parametrize('goal, words', [
    (goal_pose_msg(1.0, 1.0, frame=''), "frame_id '' is not the map frame 'map'"),
    (goal_pose_msg(1.0, 1.0, frame='odom'), "'odom'"),
    (goal_pose_msg(1.0, 1.0, q=(0.0, 0.0, 0.0, 0.0)), 'not a unit quaternion'),
    (goal_pose_msg(1.0, 1.0, q=(0.0, 0.0, 0.9, 0.9)), 'not a unit quaternion'),
    (goal_pose_msg(math.nan, 1.0), 'position.x must be finite'),
    (goal_pose_msg(1e30, 1.0), 'goal_x'),
])
def test_goal_poses_are_checked_at_the_boundary(graph, goal, words):
    status = answer_to(graph, lambda: graph['goal'].publish(goal))
    assert not status.accepted and status.command == WalkCommand.GOTO
    assert status.error_code == CommandStatus.INVALID_VALUE and words in status.error_msg
    graph['clock'].advance(0.1)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE


def test_a_start_waits_for_a_planner_not_yet_discovered_and_is_refused_without_one(
        ros_context, executor):
    """use_planner: a request waits for plan_walk up to planner_timeout (discovery at
    startup), then is refused; it never silently walks in place instead."""
    g = make_graph(ros_context, executor, Parameter('use_planner', value=True),
                   Parameter('planner_timeout', value=0.5))
    status = send(g, command=WalkCommand.START)
    assert not status.accepted and status.error_code == CommandStatus.PLANNING_FAILED
    assert 'no answer from plan_walk within 0.5 s' in status.error_msg
    g['clock'].advance(0.1)
    assert all(s.phase == WalkingState.IDLE for s in g['states'].messages)


def test_a_goal_needs_a_planner(graph):
    status = answer_to(graph, lambda: graph['goal'].publish(goal_pose_msg(1.0, 1.0)))
    assert status.error_code == CommandStatus.NOT_ALLOWED
    assert 'no footstep planner' in status.error_msg
    graph['clock'].advance(0.1)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE


@pytest.mark.parametrize('bad, words', [
    (twist(vx=math.nan), 'linear.x must be finite'),
    (twist(angular_x=math.inf), 'angular.x must be finite'),
    (twist(vx=1e30), 'linear.x 1e+30 outside'),
    (twist(wz=-5.0), 'angular.z -5.0 outside'),
])
def test_bad_cmd_vel_is_answered_and_a_valid_one_walks_in_place_without_a_planner(
        graph, bad, words):
    status = answer_to(graph, lambda: graph['cmd_vel'].publish(bad))
    assert not status.accepted and status.command == WalkCommand.OMNI
    assert status.error_code == CommandStatus.INVALID_VALUE and words in status.error_msg
    graph['clock'].advance(0.1)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE
    assert answer_to(graph, lambda: graph['cmd_vel'].publish(twist(vx=0.1))).accepted
    graph['clock'].advance(0.1)
    assert graph['states'].messages[-1].phase == WalkingState.INITIALIZE


def test_a_cmd_vel_walk_stops_finishing_its_step_when_cmd_vel_falls_silent(graph):
    g = graph
    assert answer_to(g, lambda: g['cmd_vel'].publish(twist(vx=0.1))).accepted
    # a teleop at 10 Hz: the walk goes on
    run(g, 3.0, every=0.1, publish=[lambda: g['cmd_vel'].publish(twist(vx=0.1))], pace=1.0)
    last_sent = g['clock'].t
    walked = [s for s in g['states'].messages if s.phase != WalkingState.IDLE]
    assert walked and not any(s.stop_requested for s in walked)
    assert g['states'].messages[-1].phase != WalkingState.IDLE
    assert g['states'].messages[-1].step_index >= 4
    # silence: the walk stops, finishing the step it is taking
    g['states'].messages.clear()
    run(g, 3.0, every=0.1, pace=1.0)
    stop = next(s for s in g['states'].messages if 'cmd_vel timeout' in s.reason)
    stamp = lambda s: s.header.stamp.sec + s.header.stamp.nanosec * 1e-9  # noqa: E731
    assert stamp(stop) >= last_sent + 0.5 - 1e-6  # not before the timeout
    last = g['states'].messages[-1]
    assert last.phase == WalkingState.IDLE and last.reason == 'stopped after the step'
    # the step being taken when the stop came, no more: at most one single + double support
    assert stamp(last) - last.time_in_phase - stamp(stop) <= 0.3 + 0.1 + 1e-6
    assert last.step_index <= stop.step_index + 1


def test_a_cmd_vel_sent_while_the_walk_stops_starts_a_new_walk_once_idle(graph):
    """A teleop that falls silent for a moment and resumes: not refused, the robot walks on
    after the step it was closing."""
    g = graph
    assert answer_to(g, lambda: g['cmd_vel'].publish(twist(vx=0.1))).accepted
    run(g, 1.0, every=0.1, publish=[lambda: g['cmd_vel'].publish(twist(vx=0.1))], pace=1.0)
    run(g, 0.7, every=0.1, pace=1.0)  # silence: the timeout stops the walk
    assert g['states'].messages[-1].stop_requested
    statuses = len(g['statuses'].messages)
    g['states'].messages.clear()
    run(g, 2.0, every=0.1, publish=[lambda: g['cmd_vel'].publish(twist(vy=0.05))], pace=1.0)
    phases = [s.phase for s in g['states'].messages]
    idle = phases.index(WalkingState.IDLE)
    assert WalkingState.INITIALIZE in phases[idle:], 'no new walk after the stop'
    assert all(s.accepted for s in g['statuses'].messages[statuses:])


def test_fall_reported_by_odometry_and_reset(graph):
    g = graph
    send(g, command=WalkCommand.START)
    t = g['clock'].t
    g['odom'].publish(odometry(t, z=0.2))
    assert spin_until(g['executor'], lambda: g['states'].messages[-1].fallen, 5.0)
    assert g['states'].messages[-1].phase == WalkingState.FALLEN
    status = send(g, command=WalkCommand.START)
    assert not status.accepted and status.error_code == CommandStatus.NOT_ALLOWED
    assert send(g, command=WalkCommand.RESET).accepted
    g['clock'].advance(0.05)
    last = g['states'].messages[-1]
    assert last.phase == WalkingState.IDLE and last.epoch == 1
    # odometry measured before the reset (still on its way) does not make it fall again
    g['odom'].publish(odometry(t, z=0.2))
    g['clock'].advance(0.1)
    assert g['states'].messages[-1].phase == WalkingState.IDLE


def test_a_fall_before_a_scheduled_start_is_timed_by_the_odometry_that_shows_it(graph):
    """A walk sent with a start_time enters Initialize phased at that time; the robot falls
    before it, and the fallen odometry is handled a while after its stamp (a loaded machine):
    FALLEN starts at the odometry's stamp, not at the walk's start or the handling time."""
    g = graph
    t = g['clock'].t
    assert send(g, command=WalkCommand.START, start_time=t + 5.0).accepted
    g['clock'].advance(0.2)
    g['odom'].publish(odometry(t + 0.02, z=0.2))
    assert spin_until(g['executor'], lambda: g['states'].messages[-1].fallen, 5.0)
    fallen = g['states'].messages[-1]
    stamp = fallen.header.stamp.sec + fallen.header.stamp.nanosec * 1e-9
    assert fallen.phase == WalkingState.FALLEN
    assert stamp == pytest.approx(t + 0.2, abs=1e-6)
    assert stamp - fallen.time_in_phase == pytest.approx(t + 0.02, abs=1e-6)


def test_impossible_odometry_is_rejected_and_valid_odometry_still_counts(graph):
    g = graph
    t = g['clock'].t
    g['odom'].publish(odometry(t, z=0.55))
    for bad in (odometry(t + 0.01, z=math.nan), odometry(t + 0.02, z=0.2, x=1e30),
                odometry(t + 0.03, z=0.2, q=(0.0, 0.0, 0.0, 0.0)),
                odometry(t + 0.04, z=0.2, frame=''), odometry(t + 0.05, z=0.2, frame='odom'),
                odometry(t - 5.0, z=0.2)):  # a stamp that goes back
        g['odom'].publish(bad)
    g['clock'].advance(0.3)
    assert not any(s.fallen for s in g['states'].messages)
    g['odom'].publish(odometry(t + 0.5, z=0.2))
    assert spin_until(g['executor'], lambda: g['states'].messages[-1].fallen, 5.0)


def test_reset_is_refused_while_walking_and_starts_a_new_epoch_otherwise(graph):
    g = graph
    reset = g['client'].create_client(Trigger, 'reset')
    assert reset.wait_for_service(timeout_sec=10.0)

    def call():
        future = reset.call_async(Trigger.Request())
        assert spin_until(g['executor'], future.done, 10.0)
        return future.result()

    first = call()
    assert first.success and 'epoch 1' in first.message
    assert 'no simulator/reset service' in first.message
    send(g, command=WalkCommand.START)
    g['clock'].advance(0.6)
    refused = call()
    assert not refused.success and 'cannot reset while walking' in refused.message
    status = send(g, command=WalkCommand.RESET)
    assert status.error_code == CommandStatus.NOT_ALLOWED
    assert 'cannot reset while walking' in status.error_msg
    g['clock'].advance(0.1)
    assert g['states'].messages[-1].phase == WalkingState.SINGLE_SUPPORT
    assert g['states'].messages[-1].epoch == 1


@pytest.mark.parametrize('succeeds', [True, False])
def test_reset_goes_through_the_simulators_reset(graph, ros_context, succeeds):
    g = graph
    calls = []

    def simulator_reset(request, response):
        calls.append(request)
        response.success, response.message = succeeds, 'robot reset' if succeeds else 'jammed'
        return response

    # the simulator is another process: its service must answer while the reset service waits
    simulator = rclpy.create_node('fake_simulator', context=ros_context)
    simulator.create_service(Trigger, 'simulator/reset', simulator_reset)
    spinner = SingleThreadedExecutor(context=ros_context)
    spinner.add_node(simulator)
    thread = threading.Thread(target=spinner.spin, daemon=True)
    thread.start()
    try:
        reset = g['client'].create_client(Trigger, 'reset')
        assert reset.wait_for_service(timeout_sec=10.0)
        assert spin_until(g['executor'], g['node']._simulator_reset.ready, 10.0)
        future = reset.call_async(Trigger.Request())
        assert spin_until(g['executor'], future.done, 10.0)
    finally:
        spinner.shutdown()
        thread.join(timeout=5.0)
        simulator.destroy_node()
    assert len(calls) == 1
    g['clock'].advance(0.05)
    if succeeds:
        assert future.result().success and 'simulator: robot reset' in future.result().message
        assert g['states'].messages[-1].epoch == 1
    else:
        assert not future.result().success and 'jammed' in future.result().message
        assert g['states'].messages[-1].epoch == 0


def test_losing_the_references_is_reported_and_ends_the_walk(graph):
    g = graph
    refs = g['client'].create_publisher(ReferenceTrajectory, 'reference_trajectory', 10)
    diagnostics = g['client'].create_publisher(ControllerDiagnostics, 'controller_diagnostics',
                                               10)
    assert wait_for_subscribers(g['executor'], refs)
    assert wait_for_subscribers(g['executor'], diagnostics)
    both = [lambda: refs.publish(ReferenceTrajectory()),
            lambda: diagnostics.publish(ControllerDiagnostics())]
    send(g, command=WalkCommand.START)
    run(g, 1.5, every=0.02, publish=both)
    assert g['states'].messages[-1].phase in (WalkingState.SINGLE_SUPPORT,
                                              WalkingState.DOUBLE_SUPPORT)
    assert not any(s.inputs_stale for s in g['states'].messages)
    g['states'].messages.clear()
    run(g, 2.0, every=0.02, publish=both[1:])  # the reference generator is gone
    stale = [s for s in g['states'].messages if s.inputs_stale]
    assert stale and list(stale[0].stale_inputs) == ['reference_trajectory']
    assert any('reference_trajectory lost' in s.reason for s in g['states'].messages)
    assert g['states'].messages[-1].phase == WalkingState.IDLE
    run(g, 0.2, every=0.02, publish=both)  # back
    assert spin_until(g['executor'], lambda: not g['states'].messages[-1].inputs_stale, 5.0)


def test_a_stopped_clock_is_reported_with_the_odometry(graph):
    g = graph
    run(g, 0.5, every=0.02, publish=[lambda: g['odom'].publish(odometry(g['clock'].t))])
    assert not g['states'].messages[-1].inputs_stale
    # the simulator is gone: no /clock, no odom; only wall time passes. The last odom can
    # arrive a timer period after the last /clock (a loaded machine), so the first report may
    # name /clock alone: both are named within the timeout.
    assert spin_until(g['executor'], lambda: g['states'].messages[-1].inputs_stale, 5.0)
    assert spin_until(g['executor'], lambda: list(g['states'].messages[-1].stale_inputs) == [
        'odom', '/clock'], 5.0)


def test_parameters_out_of_range_are_rejected_live(graph):
    node = graph['node']
    result = node.set_parameters([Parameter('single_support', value=-1.0)])[0]
    assert not result.successful
    result = node.set_parameters([Parameter('double_support', value=0.2)])[0]
    assert result.successful
    result = node.set_parameters([Parameter('first_support', value=5)])[0]
    assert not result.successful
    result = node.set_parameters([Parameter('map_frame', value='odom')])[0]
    assert not result.successful  # read at start only: read-only
    assert node.set_parameters([Parameter('cmd_vel_timeout', value=1.0)])[0].successful


# --- with a planner (played by the test) ------------------------------------------------------
def test_a_footstep_plan_sets_the_number_of_steps_and_first_support(ros_context, executor):
    plan = FootstepPlan(plan_id=3, status=FootstepPlan.STATUS_OK, footsteps=[
        Footstep(side=Footstep.LEFT, x=0.0, y=0.1), Footstep(side=Footstep.RIGHT, y=-0.1),
        Footstep(side=Footstep.RIGHT, x=0.1, y=-0.1), Footstep(side=Footstep.LEFT, x=0.2,
                                                                y=0.1)],
        single_support=0.2, double_support=0.1)
    g = make_graph(ros_context, executor, planner=dict(make_plan=lambda request: plan))
    stale = feet(6, plan_id=2)  # a plan that answers no request of this walk: never walked
    g['planner'].plans.publish(stale)
    g['clock'].advance(0.3)
    assert g['states'].messages[-1].phase == WalkingState.IDLE
    assert send(g, command=WalkCommand.GOTO, goal_x=0.2).accepted
    request = g['planner'].requests[-1]
    assert request.kind == PlanWalk.Request.KIND_COMMAND and request.command.goal_x == 0.2
    g['states'].messages.clear()
    g['clock'].advance(1.5)
    seen = transitions(g['states'].messages)
    singles = [support for p, support, _, _ in seen if p == WalkingState.SINGLE_SUPPORT]
    assert singles == [WalkingState.SUPPORT_LEFT, WalkingState.SUPPORT_RIGHT]
    assert seen[-1][0] == WalkingState.IDLE
    assert g['states'].messages[-1].plan_id == 3
    assert g['states'].messages[-1].reason == 'plan finished'


def test_with_a_planner_running_a_start_waits_for_the_plan_of_its_request(ros_context,
                                                                          executor):
    """Initialize shifts the COM to the plan's first support foot: no plan, no start; and only
    the plan made for this request starts it."""
    g = make_graph(ros_context, executor, planner=dict(make_plan=None))
    g['commands'].publish(WalkCommand(command=WalkCommand.START))
    assert spin_until(executor, lambda: g['planner'].requests, 5.0)
    request_id = g['planner'].requests[-1].request_id
    g['clock'].advance(0.5)
    assert g['states'].messages[-1].phase == WalkingState.IDLE
    for stale in (0, request_id + 1):
        plan = feet(4)
        plan.request_id = stale
        g['planner'].plans.publish(plan)
    g['clock'].advance(0.3)
    assert g['states'].messages[-1].phase == WalkingState.IDLE
    plan_time = g['clock'].t
    plan = feet(4, plan_id=2)
    plan.request_id = request_id
    g['planner'].plans.publish(plan)
    g['clock'].advance(0.1)
    walking = [s for s in g['states'].messages if s.phase == WalkingState.INITIALIZE]
    assert walking, 'the plan did not start the walk'
    assert walking[0].walk_start_time >= plan_time - 1e-6 and walking[0].plan_id == 2


def test_a_silent_planner_ends_a_teleop_walk_where_its_plan_ends(ros_context, executor):
    """The fake planner answers the start with one continuous plan and never extends it."""
    g = make_graph(ros_context, executor, Parameter('input_timeout', value=0.5),
                   planner=dict(make_plan=lambda request: feet(6, continuous=True)))
    assert send(g, command=WalkCommand.START).accepted
    run(g, 6.0, every=0.05)
    last = g['states'].messages[-1]
    assert last.phase == WalkingState.IDLE and last.inputs_stale
    assert list(last.stale_inputs) == ['footstep_plan']
    assert last.step_index == 4  # the 4 steps of the last plan, then stop
    assert g['node'].phase.name == 'IDLE'


def test_a_refused_request_is_answered_with_the_planners_reason(ros_context, executor):
    g = make_graph(ros_context, executor, planner=dict(accept=False))
    status = send(g, command=WalkCommand.OMNI, step_length=0.1)
    assert status.error_code == CommandStatus.PLANNING_FAILED and 'planner' in status.error_msg
    g['clock'].advance(0.2)
    assert g['states'].messages[-1].phase == WalkingState.IDLE


def test_a_planner_that_does_not_answer_is_reported(ros_context, executor):
    g = make_graph(ros_context, executor, Parameter('planner_timeout', value=0.3),
                   Parameter('use_planner', value=True))
    # a planner on the graph that never answers: its node is never spun
    silent = rclpy.create_node('silent_planner', context=ros_context)
    try:
        silent.create_service(PlanWalk, 'plan_walk', lambda request, response: response)
        assert spin_until(executor, g['node'].planner_available, 10.0)
        status = send(g, command=WalkCommand.START, timeout=10.0)
        assert not status.accepted and 'no answer from plan_walk' in status.error_msg
        g['clock'].advance(0.2)
        assert g['states'].messages[-1].phase == WalkingState.IDLE
    finally:
        silent.destroy_node()


def stamp_of(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


def test_a_stop_with_a_start_time_applies_then_as_if_it_arrived_then(graph):
    send(graph, command=WalkCommand.START)
    graph['clock'].advance(0.6)  # in the first single support
    state = graph['states'].messages[-1]
    assert state.phase == WalkingState.SINGLE_SUPPORT
    # the middle of the single support two steps later (0.3 + 0.1 s steps)
    stop_time = stamp_of(state) - state.time_in_phase + 2 * 0.4 + 0.15
    assert send(graph, command=WalkCommand.STOP, start_time=stop_time).accepted
    graph['states'].messages.clear()
    run(graph, 2.0, every=0.05)
    states = graph['states'].messages
    idle = [s for s in states if s.phase == WalkingState.IDLE]
    assert idle, 'the scheduled stop did not end the walk'
    # stamps and stop_time go through float seconds: equal times can differ in the last bits
    before = [s for s in states if stamp_of(s) < stop_time - 1e-6]
    assert before and all(s.phase != WalkingState.IDLE and not s.stop_requested
                          for s in before), 'the walk stopped before the stated time'
    # as a STOP arriving at stop_time: the step under way then is finished, then Idle
    at_stop = next(s for s in states if stamp_of(s) >= stop_time - 1e-6)
    assert at_stop.phase == WalkingState.SINGLE_SUPPORT and at_stop.stop_requested
    assert idle[0].step_index == at_stop.step_index + 1  # as test_stop_finishes_the_step...


def test_a_command_before_a_scheduled_stop_drops_it(graph):
    send(graph, command=WalkCommand.START)
    graph['clock'].advance(0.6)
    now = stamp_of(graph['states'].messages[-1])
    assert send(graph, command=WalkCommand.STOP, start_time=now + 0.5).accepted
    assert send(graph, command=WalkCommand.START).accepted  # walk on: the stop is dropped
    run(graph, 1.5, every=0.05)
    assert all(s.phase != WalkingState.IDLE for s in graph['states'].messages[-10:])


@pytest.mark.parametrize('start_time, words', [
    (math.nan, 'start_time must be a finite time'),
    (-1.0, 'start_time must be a finite time'),
    (1e6, 'more than 60 s'),
])
def test_a_stop_with_a_bad_start_time_is_refused_and_the_walk_goes_on(graph, start_time,
                                                                       words):
    send(graph, command=WalkCommand.START)
    graph['clock'].advance(0.6)
    status = send(graph, command=WalkCommand.STOP, start_time=start_time)
    assert status.error_code == CommandStatus.INVALID_VALUE and words in status.error_msg
    run(graph, 0.5, every=0.05)
    assert graph['states'].messages[-1].phase != WalkingState.IDLE


def test_a_refused_stop_keeps_the_scheduled_one(graph):
    send(graph, command=WalkCommand.START)
    graph['clock'].advance(0.6)
    state = graph['states'].messages[-1]
    stop_time = stamp_of(state) - state.time_in_phase + 0.4 + 0.15
    assert send(graph, command=WalkCommand.STOP, start_time=stop_time).accepted
    refused = send(graph, command=WalkCommand.STOP, start_time=math.nan)
    assert refused.error_code == CommandStatus.INVALID_VALUE
    run(graph, 1.5, every=0.05)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE
