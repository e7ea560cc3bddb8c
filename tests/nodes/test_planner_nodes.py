"""Node-level tests of the footstep planner and the reference generator, with the state machine:
real rclpy, real DDS, sim time driven by the test. The user talks to the state machine only; it
asks the planner for plans over plan_walk."""
import math

from biped_msgs.msg import (BalanceEstimate, CommandStatus, FootstepPlan, ReferenceTrajectory,
                            StepAdjustment, WalkCommand, WalkingState)
from biped_msgs.srv import PlanWalk
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
from biped_planner.walking_state_machine import EARLY_REASON
from ros_harness import Collector, RosoutLines, SimClock, spin_until, wait_for_subscribers

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
    return make_graph(ros_context, executor)


@pytest.fixture
def adjusting_graph(ros_context, executor):
    """The graph with the reference generator's step adjuster on."""
    return make_graph(ros_context, executor, [Parameter('step_adjustment.enabled', value=True)])


def make_graph(ros_context, executor, reference_parameters=()):
    sim_time = [Parameter('use_sim_time', value=True)]
    for make in (StateMachineNode, FootstepPlannerNode, ReferenceGeneratorNode):
        extra = list(reference_parameters) if make is ReferenceGeneratorNode else []
        executor.track(make(context=ros_context, parameter_overrides=sim_time + extra))
    client = executor.track(rclpy.create_node('planner_test_client', context=ros_context))
    g = dict(client=client, executor=executor, clock=SimClock(client, executor))
    g['plans'] = Collector(client, FootstepPlan, 'footstep_plan', LATCHED)
    g['paths'] = Collector(client, Path, 'plan', LATCHED)
    g['markers'] = Collector(client, MarkerArray, 'footstep_markers', LATCHED)
    g['refs'] = Collector(client, ReferenceTrajectory, 'reference_trajectory', 10)
    g['states'] = Collector(client, WalkingState, 'walking_state', 50)
    g['statuses'] = Collector(client, CommandStatus, 'walk_command_status', 50)
    g['map'] = client.create_publisher(OccupancyGridMsg, 'map', LATCHED)
    g['odom'] = client.create_publisher(Odometry, 'odom', 10)
    g['goal'] = client.create_publisher(PoseStamped, 'goal_pose', 10)
    g['command'] = client.create_publisher(WalkCommand, 'walk_command', 10)
    g['cmd_vel'] = client.create_publisher(Twist, 'cmd_vel', 10)
    for name in ('odom', 'goal', 'command', 'cmd_vel'):
        assert wait_for_subscribers(executor, g[name], count=1, timeout=15), name
    # exactly one node takes user intent: the state machine
    for topic in ('walk_command', 'goal_pose', 'cmd_vel'):
        assert [i.node_name for i in client.get_subscriptions_info_by_topic(topic)] == \
            ['state_machine'], topic
    assert wait_for_subscribers(executor, g['clock'].publisher, count=3, timeout=15)
    grid, start, goal_pose = paper_start_goal_example()
    g['start'], g['goal_pose'] = start, goal_pose
    g['map'].publish(grid_to_msg(grid, 'map', client.get_clock().now().to_msg()))
    assert wait_for_subscribers(executor, g['map'], count=1, timeout=15)
    g['odom'].publish(odometry(start.x, start.y, start.yaw))
    g['clock'].advance(0.1)
    # the planner serves plan_walk once it knows the start pose
    g['plan_walk'] = client.create_client(PlanWalk, 'plan_walk')
    assert spin_until(executor, g['plan_walk'].service_is_ready, 15.0), 'no plan_walk'
    return g


def last_status(g, count, timeout=10.0) -> CommandStatus:
    assert g['statuses'].wait_for(g['executor'], lambda m: len(m) > count, timeout), 'no status'
    return g['statuses'].messages[-1]


def call_plan_walk(g, request):
    future = g['plan_walk'].call_async(request)
    assert spin_until(g['executor'], future.done, 10.0)
    return future.result()


def latest_plan(g, timeout=10.0, count=None):
    count = len(g['plans'].messages) if count is None else count
    assert g['plans'].wait_for(g['executor'], lambda m: len(m) > count, timeout), 'no plan'
    return g['plans'].messages[-1]


def test_goto_plans_footsteps_around_obstacles_and_the_walk_gets_its_references(graph):
    g = graph
    target = g['goal_pose']
    statuses = len(g['statuses'].messages)
    g['goal'].publish(goal(target.x, target.y, target.yaw))
    plan = latest_plan(g)
    assert plan.status == FootstepPlan.STATUS_OK and not plan.continuous
    assert plan.request_id != 0  # it answers the state machine's request
    status = last_status(g, statuses)
    assert status.accepted and status.command == WalkCommand.GOTO
    last_two = plan.footsteps[-2:]
    middle = np.mean([[f.x, f.y] for f in last_two], axis=0)
    assert np.hypot(*(middle - [target.x, target.y])) < 0.02
    assert g['paths'].wait_for(g['executor'], timeout=5) and len(g['paths'].messages[-1].poses)
    assert g['markers'].wait_for(g['executor'], timeout=5)
    assert len(g['markers'].messages[-1].markers) == len(plan.footsteps) + 1  # + DELETEALL
    g['clock'].advance(1.5)  # the goal starts the walk on its plan
    refs = [r for r in g['refs'].messages if r.plan_id == plan.plan_id]
    assert refs, 'no reference for the plan'
    window = window_from_reference_msg(refs[-1])
    assert len(window.t) == 90
    # the ZMP reference stays inside its support bounds over the whole horizon
    assert np.all(window.zmp >= window.zmp_min - 1e-9)
    assert np.all(window.zmp <= window.zmp_max + 1e-9)
    phases = {s.phase for s in g['states'].messages}
    assert WalkingState.SINGLE_SUPPORT in phases


@pytest.mark.parametrize('x, y, code', [
    (1.3, 0.5, FootstepPlan.ERROR_GOAL_OCCUPIED),
    (9.0, 9.0, FootstepPlan.ERROR_GOAL_OUTSIDE_MAP),
])
def test_bad_goals_give_a_failed_plan_with_its_error_code(graph, x, y, code):
    statuses = len(graph['statuses'].messages)
    graph['goal'].publish(goal(x, y))
    plan = latest_plan(graph)
    assert plan.status == FootstepPlan.STATUS_FAILED
    assert plan.error_code == code
    assert plan.error_msg
    status = last_status(graph, statuses)
    assert status.error_code == CommandStatus.INVALID_VALUE
    assert f'FootstepPlan error {code}' in status.error_msg
    graph['clock'].advance(0.2)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE


@pytest.mark.parametrize('x, y, frame, code', [
    (3.0, 3.0, 'odom', FootstepPlan.ERROR_UNKNOWN_FRAME),
    (3.0, 3.0, '', FootstepPlan.ERROR_UNKNOWN_FRAME),
    (math.nan, 3.0, 'map', FootstepPlan.ERROR_INVALID_COMMAND),
])
def test_goals_the_state_machine_rejects_the_planner_rejects_too(graph, x, y, frame, code):
    """The state machine answers them without asking the planner; the planner's service
    checks its requests as well, with a failed plan and its error code."""
    statuses, plans = len(graph['statuses'].messages), len(graph['plans'].messages)
    graph['goal'].publish(goal(x, y, frame=frame))
    assert last_status(graph, statuses).error_code == CommandStatus.INVALID_VALUE
    graph['clock'].advance(0.2)
    assert len(graph['plans'].messages) == plans
    response = call_plan_walk(graph, PlanWalk.Request(
        request_id=77, kind=PlanWalk.Request.KIND_GOAL, goal=goal(x, y, frame=frame)))
    assert not response.accepted and response.error_code == code and response.error_msg
    plan = latest_plan(graph, count=plans)
    assert plan.status == FootstepPlan.STATUS_FAILED and plan.error_code == code
    assert plan.request_id == 77


def test_a_request_sent_again_is_answered_without_planning_twice(graph):
    """The state machine sends an unanswered request again (its answer may have been lost):
    the planner answers the repeat with its first answer and publishes no second plan; a new
    request id is planned anew."""
    def request(request_id):
        return PlanWalk.Request(request_id=request_id, kind=PlanWalk.Request.KIND_GOAL,
                                goal=goal(graph['goal_pose'].x, graph['goal_pose'].y))
    plans = len(graph['plans'].messages)
    first = call_plan_walk(graph, request(31))
    assert first.accepted
    assert latest_plan(graph, count=plans).plan_id == first.plan_id
    plans = len(graph['plans'].messages)
    again = call_plan_walk(graph, request(31))
    assert (again.accepted, again.plan_id) == (True, first.plan_id)
    graph['clock'].advance(0.2)
    assert len(graph['plans'].messages) == plans
    new = call_plan_walk(graph, request(32))
    assert new.accepted and new.plan_id != first.plan_id
    assert latest_plan(graph, count=plans).plan_id == new.plan_id


def test_unknown_request_kinds_and_commands_are_refused_by_the_planner(graph):
    bad_kind = call_plan_walk(graph, PlanWalk.Request(request_id=5, kind=9))
    assert not bad_kind.accepted and 'unknown request kind 9' in bad_kind.error_msg
    bad_command = PlanWalk.Request(request_id=6, kind=PlanWalk.Request.KIND_COMMAND)
    bad_command.command.command = 42
    response = call_plan_walk(graph, bad_command)
    assert not response.accepted
    assert response.error_code == FootstepPlan.ERROR_INVALID_COMMAND


def test_a_malformed_map_is_rejected_and_goals_then_report_no_map(graph):
    bad = OccupancyGridMsg()
    bad.header.frame_id = 'map'
    bad.info.width, bad.info.height, bad.info.resolution = 10, 10, 0.1
    bad.info.origin.orientation.w = 1.0
    bad.data = [0] * 7  # 100 cells announced
    graph['map'].publish(bad)
    graph['clock'].advance(0.2)
    statuses = len(graph['statuses'].messages)
    graph['goal'].publish(goal(3.0, 3.0))
    plan = latest_plan(graph)
    assert plan.error_code == FootstepPlan.ERROR_NO_MAP
    status = last_status(graph, statuses)
    assert status.error_code == CommandStatus.PLANNING_FAILED and 'no valid map' in status.error_msg


def test_teleop_cmd_vel_starts_a_continuous_plan_that_grows_while_walking(graph):
    g = graph
    g['cmd_vel'].publish(Twist())  # walk in place
    first = latest_plan(g)
    assert first.status == FootstepPlan.STATUS_OK and first.continuous
    for _ in range(30):  # a teleop at 10 Hz (cmd_vel times out after 0.5 s)
        g['clock'].advance(0.1, pace=2.0)
        g['cmd_vel'].publish(Twist())
    # the clock stops here; under load the executor's backlog (a few spins per clock tick) can
    # still hold the last walking_state messages: let them in before reading them
    spin_until(g['executor'], lambda: max(s.step_index for s in g['states'].messages) >= 3, 2.0)
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


def moves_forward(start, footsteps, by=0.03) -> bool:
    """Whether a footstep is more than `by` ahead of the start pose (along its heading)."""
    return any((f.x - start.x) * math.cos(start.yaw) + (f.y - start.y) * math.sin(start.yaw) >
               by for f in footsteps)


def stamp_s(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


def test_a_command_stated_for_a_later_time_steers_from_the_first_step_starting_then(graph):
    """The planner holds a teleop command whose start_time is ahead and changes the steps from
    the first step that starts at or after it: the walk does not depend on when it arrived."""
    g = graph
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI))  # walk in place
    first = latest_plan(g)
    g['clock'].advance(2.0)
    assert g['states'].messages[-1].phase in (WalkingState.SINGLE_SUPPORT,
                                              WalkingState.DOUBLE_SUPPORT)
    stated = g['clock'].t + 1.5
    statuses = len(g['statuses'].messages)
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI, step_length=0.1,
                                     start_time=stated))
    assert last_status(g, statuses).error_code == CommandStatus.OK
    g['clock'].advance(4.0)
    plans = [p for p in g['plans'].messages if p.plan_id == first.plan_id]

    def forward(plan):
        return moves_forward(g['start'], plan.footsteps)
    before = [p for p in plans if stamp_s(p) < stated - 1e-6]
    assert before and not any(forward(p) for p in before)
    extensions = sorted(stamp_s(p) for p in plans if p.request_id == 0 and
                        stamp_s(p) >= stated - 1e-6)
    first_forward = next(p for p in plans if forward(p))
    assert first_forward.request_id == 0 and stamp_s(first_forward) == extensions[0]


def single_support_starts(states) -> dict:
    """{step_index: start (s)} of the single supports in walking_state messages."""
    return {s.step_index: round(stamp_s(s) - s.time_in_phase, 6) for s in states
            if s.phase == WalkingState.SINGLE_SUPPORT}


def test_a_stop_stated_for_a_later_time_ends_the_walk_after_the_step_under_way_then(graph):
    """The planner holds a STOP whose start_time is ahead and answers it at the start of the
    single support under way then, stamped with that start (request_id 0, as that step's
    extension would be): the walk stops at the same step, whenever the STOP arrived."""
    g = graph
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI))  # walk in place
    first = latest_plan(g)
    g['clock'].advance(1.2)
    singles = [s for s in g['states'].messages if s.phase == WalkingState.SINGLE_SUPPORT]
    single, step = first.single_support, first.single_support + first.double_support
    # the middle of a single support three steps on
    stated = stamp_s(singles[-1]) - singles[-1].time_in_phase + 3 * step + single / 2
    statuses = len(g['statuses'].messages)
    g['command'].publish(WalkCommand(command=WalkCommand.STOP, start_time=stated))
    assert last_status(g, statuses).error_code == CommandStatus.OK
    g['clock'].advance(4.0)
    states = g['states'].messages
    assert states[-1].phase == WalkingState.IDLE
    starts = single_support_starts(states)
    last_step = next(k for k, start in starts.items() if start <= stated < start + single)
    plans = [p for p in g['plans'].messages if p.plan_id == first.plan_id]
    stop_plans = [p for p in plans if not p.continuous]
    assert len(stop_plans) == 1
    stop_plan = stop_plans[0]
    assert stop_plan.request_id == 0 and abs(stamp_s(stop_plan) - starts[last_step]) < 1e-6
    # no extension of that step: the stop is its change of the walk
    assert not any(p.continuous and abs(stamp_s(p) - starts[last_step]) < 1e-6 for p in plans)
    # the step under way at the stated time, then the closing step
    assert len(stop_plan.footsteps) == last_step + 4
    assert max(starts) == last_step + 1 and states[-1].step_index == last_step + 2
    assert not any(s.stop_requested for s in states if stamp_s(s) < stated - 1e-6)
    # walking_state says when the walk stops, from the STOP's arrival until the walk ended (the
    # reference generator waits for the stop's plan at that step)
    told = [s for s in states if s.stop_time > 0.0]
    assert told and all(abs(s.stop_time - stated) < 1e-6 for s in told)
    assert all(s.stop_time > 0.0 for s in states[states.index(told[0]):-1]
               if s.phase != WalkingState.IDLE)
    assert states[-1].stop_time == 0.0


def test_a_stated_stop_that_overtakes_the_walks_first_walking_state_is_held(graph):
    """The state machine sends a stated STOP once its walk started; the planner's walking_state
    showing that walk can come later. The planner holds the STOP for the plan it has (here
    asked for directly: no walking_state shows a walk at all) instead of ending it."""
    g = graph
    rosout = RosoutLines(g['client'])
    start = PlanWalk.Request(request_id=41, kind=PlanWalk.Request.KIND_COMMAND,
                             command=WalkCommand(command=WalkCommand.START))
    started = call_plan_walk(g, start)
    assert started.accepted
    stop = PlanWalk.Request(request_id=42, kind=PlanWalk.Request.KIND_COMMAND,
                            command=WalkCommand(command=WalkCommand.STOP,
                                                start_time=g['clock'].t + 2.0))
    plans = len(g['plans'].messages)
    assert call_plan_walk(g, stop).accepted
    assert spin_until(g['executor'], lambda: rosout.has(
        '[footstep_planner]', 'request 42: STOP at', 'answered at the start of the step'), 5.0)
    g['clock'].advance(0.2)
    assert not any(not p.continuous for p in g['plans'].messages[plans:])  # no stop plan yet
    # the plan goes on: a walk command steers it (same plan) and drops the held STOP
    steered = call_plan_walk(g, PlanWalk.Request(
        request_id=43, kind=PlanWalk.Request.KIND_COMMAND,
        command=WalkCommand(command=WalkCommand.OMNI, step_length=0.05)))
    assert steered.accepted and steered.plan_id == started.plan_id
    assert spin_until(g['executor'], lambda: rosout.has(
        '[footstep_planner]', '(request 42) dropped: request 43 walks on'), 5.0)


def test_a_stop_stated_too_late_for_its_step_stops_the_walk_at_once(graph):
    g = graph
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI))
    first = latest_plan(g)
    g['clock'].advance(1.2)
    state = g['states'].messages[-1]
    while state.phase != WalkingState.SINGLE_SUPPORT or state.time_in_phase > 0.1:
        g['clock'].advance(0.02)
        state = g['states'].messages[-1]
    # the step under way now is the one of the stated time: its start has gone by
    g['command'].publish(WalkCommand(command=WalkCommand.STOP,
                                     start_time=stamp_s(state) + 0.05))
    assert g['plans'].wait_for(g['executor'], lambda m: not m[-1].continuous, 10.0)
    stop_plan = g['plans'].messages[-1]
    assert stop_plan.plan_id == first.plan_id and not stop_plan.continuous
    assert stop_plan.request_id != 0  # the answer to the request, sent when it came
    assert len(stop_plan.footsteps) == state.step_index + 4
    g['clock'].advance(2.0)
    assert g['states'].messages[-1].phase == WalkingState.IDLE


def test_a_walk_command_drops_a_stop_stated_for_later(graph):
    g = graph
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI))
    first = latest_plan(g)
    g['clock'].advance(1.0)
    g['command'].publish(WalkCommand(command=WalkCommand.STOP, start_time=g['clock'].t + 1.5))
    g['clock'].advance(0.2)
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI, step_length=0.05))
    g['clock'].advance(4.0)
    assert g['states'].messages[-1].phase != WalkingState.IDLE
    assert any(s.stop_time > 0.0 for s in g['states'].messages)
    assert g['states'].messages[-1].stop_time == 0.0  # the generator waits for no stop plan
    plans = [p for p in g['plans'].messages if p.plan_id == first.plan_id]
    assert all(p.continuous for p in plans)


def test_a_stop_without_a_time_drops_a_stated_one_and_its_stop_time(graph):
    g = graph
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI))
    latest_plan(g)
    g['clock'].advance(1.0)
    g['command'].publish(WalkCommand(command=WalkCommand.STOP, start_time=g['clock'].t + 3.0))
    g['clock'].advance(0.2)
    assert g['states'].messages[-1].stop_time > 0.0
    g['command'].publish(WalkCommand(command=WalkCommand.STOP))
    g['clock'].advance(0.2)
    state = g['states'].messages[-1]
    assert state.stop_requested and state.stop_time == 0.0
    g['clock'].advance(2.0)
    assert g['states'].messages[-1].phase == WalkingState.IDLE


def test_stop_drops_a_command_stated_for_later(graph):
    g = graph
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI))
    first = latest_plan(g)
    g['clock'].advance(1.0)
    g['command'].publish(WalkCommand(command=WalkCommand.OMNI, step_length=0.1,
                                     start_time=g['clock'].t + 2.0))
    g['clock'].advance(0.2)
    g['command'].publish(WalkCommand(command=WalkCommand.STOP))
    g['clock'].advance(4.0)
    assert g['states'].messages[-1].phase == WalkingState.IDLE
    plans = [p for p in g['plans'].messages if p.plan_id == first.plan_id]
    assert not any(moves_forward(g['start'], p.footsteps) for p in plans)


def test_non_finite_cmd_vel_is_rejected(graph):
    count = len(graph['plans'].messages)
    statuses = len(graph['statuses'].messages)
    twist = Twist()
    twist.linear.x = math.inf
    graph['cmd_vel'].publish(twist)
    status = last_status(graph, statuses)
    assert status.error_code == CommandStatus.INVALID_VALUE and 'linear.x' in status.error_msg
    graph['clock'].advance(0.3)
    assert not spin_until(graph['executor'], lambda: len(graph['plans'].messages) > count, 0.5)
    assert graph['states'].messages[-1].phase == WalkingState.IDLE


def test_a_step_index_no_walk_can_have_neither_hangs_nor_derails_the_planner(graph):
    """walking_state with step_index 2**32 - 1 once sent the planner into an endless loop."""
    g = graph
    g['cmd_vel'].publish(Twist())
    first = latest_plan(g)
    g['clock'].advance(0.1)
    bogus = g['client'].create_publisher(WalkingState, 'walking_state', 10)
    assert wait_for_subscribers(g['executor'], bogus, count=3)
    for phase in (WalkingState.SINGLE_SUPPORT, 77):
        bogus.publish(WalkingState(phase=phase, step_index=4294967295))
    g['clock'].advance(0.1)
    # the planner still answers, at once, and still keeps its plan
    response = call_plan_walk(g, PlanWalk.Request(
        request_id=99, kind=PlanWalk.Request.KIND_VELOCITY, velocity=Twist()))
    assert response.accepted and response.plan_id == first.plan_id


def walk_in_place_with_estimates(g):
    """Start walking in place with a balance_estimate publisher and a step_adjustment
    collector; (adjustments, estimates, the walked plan)."""
    adjustments = Collector(g['client'], StepAdjustment, 'step_adjustment', 10)
    estimates = g['client'].create_publisher(BalanceEstimate, 'balance_estimate', 10)
    assert wait_for_subscribers(g['executor'], estimates, count=1, timeout=15)
    g['cmd_vel'].publish(Twist())  # walk in place
    return adjustments, estimates, latest_plan(g)


def early_right_single_support(reference) -> bool:
    """A reference that starts early in a single support on the right foot (at least 0.2 s of
    it ahead): its own support column says so, whatever walking_state lags."""
    ahead = list(reference.support[:10])
    return len(ahead) == 10 and all(s == ReferenceTrajectory.SUPPORT_RIGHT for s in ahead)


def reference_early_in_right_single_support(g):
    """Walk on until the newest reference starts early in a right single support; it."""
    for _ in range(200):
        g['clock'].advance(0.02, pace=2.0)
        g['cmd_vel'].publish(Twist())
        refs = g['refs'].messages
        if refs and early_right_single_support(refs[-1]):
            return refs[-1]
    raise AssertionError('no single support on the right foot')


def test_a_step_adjustment_reaches_the_plan_the_state_machine_and_the_references(
        adjusting_graph):
    """A balance estimate whose DCM strays 15 cm to the left in a single support on the right
    foot: the reference generator moves the left landing out, says so on step_adjustment, and
    its references carry it (a higher plan_revision, walk_adjustments); the planner republishes
    the plan with it (same plan_id) and steps on from it; the state machine follows the
    touchdown."""
    g = adjusting_graph
    adjustments, estimates, first = walk_in_place_with_estimates(g)

    def newest_early_reference():
        refs = g['refs'].messages
        return refs[-1] if refs and early_right_single_support(refs[-1]) else None
    reference = reference_early_in_right_single_support(g)
    step = reference.step_index[0] - 1  # the reference counts k + 1 during step k
    plans = len(g['plans'].messages)
    omega = math.sqrt(9.81 / 0.5)
    for _ in range(10):  # one estimate a period, early in that support, until it is answered
        hip = np.array([reference.hip_x[0], reference.hip_y[0]])
        velocity = (np.array([reference.hip_x[1], reference.hip_y[1]]) - hip) / reference.dt
        estimate = BalanceEstimate(omega=omega)
        estimate.header.frame_id = 'map'
        estimate.header.stamp = reference.header.stamp
        estimate.com.x, estimate.com.y = float(hip[0]), float(hip[1])
        dcm = hip + velocity / omega + [0.0, 0.15]
        estimate.dcm.x, estimate.dcm.y = float(dcm[0]), float(dcm[1])
        estimates.publish(estimate)
        if adjustments.wait_for(g['executor'], lambda m: len(m) >= 1, 1.0):
            break
        g['clock'].advance(0.02)
        reference = newest_early_reference() or reference
    assert adjustments.messages, 'no adjustment'
    adjusted = adjustments.messages[0]
    assert adjusted.plan_id == first.plan_id and adjusted.step_index == step
    landing = adjusted.footsteps[adjusted.step_index + 2]
    planned = [p for p in g['plans'].messages if p.plan_id == first.plan_id][-1]
    assert landing.side == 0 and landing.y > planned.footsteps[step + 2].y + 0.02
    # the planner republishes the adjusted plan, same id
    republished = latest_plan(g, count=plans)
    assert republished.plan_id == first.plan_id
    # stamped with the adjustment (spliced in, and awaited in lockstep, at that time plus
    # extension_delay), not with when the planner handled it
    assert republished.header.stamp == adjusted.header.stamp and republished.request_id == 0
    assert republished.footsteps[adjusted.step_index + 2].y == pytest.approx(landing.y)
    # the references carry it
    g['clock'].advance(0.1, pace=2.0)
    newest = g['refs'].messages[-1]
    assert newest.plan_revision >= 1
    assert newest.walk_adjustments == len(adjustments.messages) >= 1  # the controller's leash
    window = window_from_reference_msg(newest)
    assert window.left_foot[-1, 1] == pytest.approx(landing.y, abs=0.05)
    # the state machine's single support ends at the adjusted touchdown
    g['clock'].advance(0.6, pace=2.0)
    ends = [s for s in g['states'].messages if s.phase == WalkingState.DOUBLE_SUPPORT and
            s.step_index == adjusted.step_index]
    assert ends, 'the adjusted step never landed'
    double_start = ends[0].header.stamp.sec + ends[0].header.stamp.nanosec * 1e-9 - \
        ends[0].time_in_phase
    assert double_start == pytest.approx(adjusted.touchdown_time, abs=0.011)


@pytest.fixture
def early_landing_graph(ros_context, executor):
    """The graph with the reference generator's early landing on."""
    return make_graph(ros_context, executor, [Parameter('landing_hold.end_early', value=True)])


def test_an_early_landing_ends_the_single_support_in_the_references_and_the_state_machine(
        early_landing_graph):
    """The controller reports the left swing foot landed late in its swing, before its planned
    time: the
    reference generator ends the single support then (step_adjustment kind EARLY, the plan's
    footsteps), its references are in double support from that time, the state machine starts
    the double support then, and the planner keeps its plan."""
    g = early_landing_graph
    adjustments, estimates, first = walk_in_place_with_estimates(g)
    reference = reference_early_in_right_single_support(g)
    step = reference.step_index[0] - 1
    support = list(reference.support)
    planned_touchdown = seconds_of_stamp(reference.header.stamp) + reference.dt * next(
        i for i, s in enumerate(support) if s != ReferenceTrajectory.SUPPORT_RIGHT)
    # past half the swing (landing_hold.early_min_share) by two periods: after 10 the report
    # came exactly at the half (1 ms to spare), and a collector one reference behind dated it
    # before it, which is no early landing (fresh-clone CI 2026-12-06, 'no early end')
    for _ in range(12):
        g['clock'].advance(0.02, pace=2.0)
    reference = g['refs'].messages[-1]
    assert reference.support[0] == ReferenceTrajectory.SUPPORT_RIGHT
    plans = len(g['plans'].messages)
    estimate = BalanceEstimate(omega=math.sqrt(9.81 / 0.5), landing_modes=['landed', 'none'],
                               landing_depths=[0.0, 0.0])
    estimate.header.frame_id = 'map'
    estimate.header.stamp = reference.header.stamp
    estimate.com.x, estimate.com.y = reference.hip_x[0], reference.hip_y[0]
    estimate.dcm.x, estimate.dcm.y = reference.hip_x[0], reference.hip_y[0]
    estimates.publish(estimate)
    for _ in range(3):  # the reference of the next period answers it
        g['clock'].advance(0.02)
        if adjustments.wait_for(g['executor'], lambda m: len(m) >= 1, 1.0):
            break
    assert adjustments.messages, 'no early end'
    early = adjustments.messages[0]
    t_report = seconds_of_stamp(reference.header.stamp)
    assert early.kind == StepAdjustment.KIND_EARLY
    assert (early.plan_id, early.step_index) == (first.plan_id, step)
    assert early.touchdown_time == pytest.approx(t_report + 0.001)
    # the window's first sample off the right foot is at most one sample after the touchdown
    assert planned_touchdown - reference.dt - 1e-6 <= early.planned_touchdown_time <= \
        planned_touchdown + 1e-6
    assert planned_touchdown - early.touchdown_time > 0.05
    walked = [p for p in g['plans'].messages if p.plan_id == first.plan_id][-1]
    assert [(f.x, f.y) for f in early.footsteps] == [(f.x, f.y) for f in walked.footsteps][
        :len(early.footsteps)]
    # the references are in double support from the touchdown on: read in the window of the
    # first reference that carries the early end (the newest one can be past the 0.1 s double
    # support already, when the clock ran on while the test waited for the early end)
    g['clock'].advance(0.06, pace=2.0)
    revised = next((r for r in g['refs'].messages if r.plan_revision >= 1), None)
    assert revised is not None, 'no reference carries the early end'
    start = seconds_of_stamp(revised.header.stamp)
    in_double = [s for i, s in enumerate(revised.support)
                 if early.touchdown_time <= start + i * revised.dt < early.touchdown_time + 0.09]
    assert in_double and all(s == ReferenceTrajectory.SUPPORT_DOUBLE for s in in_double), \
        (start, early.touchdown_time, list(revised.support[:10]))
    # the state machine's double support starts at the early touchdown
    g['clock'].advance(0.2, pace=2.0)
    ends = [s for s in g['states'].messages if s.phase == WalkingState.DOUBLE_SUPPORT and
            s.step_index == step]
    assert ends, 'the early step never landed'
    assert any(s.phase == WalkingState.SINGLE_SUPPORT and s.step_index == step and
               s.reason == EARLY_REASON for s in g['states'].messages)
    double_start = seconds_of_stamp(ends[0].header.stamp) - ends[0].time_in_phase
    assert double_start == pytest.approx(early.touchdown_time, abs=0.011)
    # the planner keeps its plan: nothing republished for the early landing
    assert all(p.header.stamp != early.header.stamp for p in g['plans'].messages[plans:])


def seconds_of_stamp(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9
