"""Drive the running node graph as a user would, and keep what it publishes.

A GraphSession brings up the nodes (biped_tools.node_graph; map_server serves a map file or an
empty map around the start), records a rosbag2 of the run (biped_tools.recording), and offers
the user's actions: publish a map, send a goal, a walk command, a velocity command, push the
robot. It keeps the time series the plots and checks need
(pelvis, COM, measured ZMP, support bounds, walking state, plans, controller diagnostics).
Used by the demo, the scenario runner and the graph tests.
"""
from dataclasses import dataclass, field
from pathlib import Path
import time
from typing import Callable, List, Optional

from biped_msgs.msg import WalkCommand, WalkingState
from biped_planner.node_support.stamps import time_msg_of
from biped_planner.rotations import quaternion_from_yaw, tilt_of_quaternion, yaw_of_quaternion
from rosgraph_msgs.msg import Clock

from biped_tools.node_graph import GraphOptions, NodeGraph

RECORDED_TOPICS = ['walking_state', 'footstep_plan', 'plan', 'footstep_markers',
                   'reference_trajectory', 'controller_diagnostics', 'odom', 'zmp', 'com', 'imu',
                   'joint_states', 'joint_commands', 'left_foot_wrench', 'right_foot_wrench',
                   'walk_command', 'walk_command_status', 'cmd_vel', 'goal_pose', 'map']
ALL_NODES = ['simulator', 'map_server', 'state_machine', 'footstep_planner',
             'reference_generator', 'mpc_controller']
IDLE = WalkingState.IDLE
STEPPING = (WalkingState.SINGLE_SUPPORT, WalkingState.DOUBLE_SUPPORT)
# The nodes that take the user's commands (walk_command, goal_pose, cmd_vel): a command is sent
# once all of them subscribe, so that none misses it. The state machine is the one entry point
# (it asks the footstep planner for plans over plan_walk).
COMMAND_LISTENERS = ('state_machine',)

# Wall time for the push service's answer: under heavy load (three graphs on two cores) a
# 10 s wait ran out.
PUSH_ANSWER_TIMEOUT = 30.0


@dataclass
class RunSeries:
    """Time series of one run, each a list of tuples (sim time first)."""

    pelvis: List[tuple] = field(default_factory=list)        # t, x, y, z, tilt, yaw
    com: List[tuple] = field(default_factory=list)           # t, x, y, z
    zmp: List[tuple] = field(default_factory=list)           # t, x, y (measured, F/T)
    bounds: List[tuple] = field(default_factory=list)        # t, x_min, y_min, x_max, y_max
    zmp_reference: List[tuple] = field(default_factory=list)  # t, x, y
    states: List[tuple] = field(default_factory=list)  # t, phase, step, fallen, reason, support
    solve_times: List[float] = field(default_factory=list)   # s
    plans: list = field(default_factory=list)                 # FootstepPlan messages
    adjustments: list = field(default_factory=list)           # StepAdjustment messages
    plans_before_adjustment: list = field(default_factory=list)  # len(plans) as each came
    path: list = field(default_factory=list)                  # (x, y) of the last nav Path
    # left, right: (t, normal force) of the ankle F/T readings, once watch_foot_forces is called
    foot_forces: tuple = field(default_factory=lambda: ([], []))


def append_newer(samples: list, sample: tuple) -> None:
    """Append a sensor sample (sim time first) unless its period is in already: a lockstep
    simulator sends a held period's readings again while it waits, and a run's series must not
    depend on how long it waited."""
    if not samples or sample[0] > samples[-1][0]:
        samples.append(sample)


def stamp_seconds(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


VELOCITY_PERIOD = 0.1  # s of sim time between repeated cmd_vel messages (10 Hz teleop)
DISCOVERY_WAIT = 0.5  # s of wall time to hear another graph's /clock on the domain before starting
PACE_TOPIC = 'runner_clock'  # a paced session's sim time, read by the simulator (paced_by)
PACE_REPEAT = 0.2  # s of wall time after which a paced session sends its sim time again


def close_client(executor, node, context) -> None:
    """Tear down a client's ROS side: its node off the executor and destroyed, the executor
    shut down (each if it was made), then its context."""
    import rclpy
    if node is not None:
        if executor is not None:
            executor.remove_node(node)
        node.destroy_node()
    if executor is not None:
        executor.shutdown()
    rclpy.try_shutdown(context=context)


class GraphSession:
    """The whole graph, a recorder, and a client node acting for the user."""

    def __init__(self, domain_id: int, bag_dir: Optional[Path] = None, nodes=None,
                 overrides=None, backend: str = 'pybullet', gui: bool = False,
                 keep_going: bool = False, map_file: Optional[Path] = None,
                 compose=(), hold_at: Optional[float] = None,
                 pace_lead: Optional[float] = None, log=print) -> None:
        """:param map_file: the map map_server serves (nav2 YAML + image); None: an empty map
            around the simulator's start pose
        :param compose: groups of nodes each run in one process (NodeGraph)
        :param hold_at: the lockstep clock holds at this sim time (s) until resume_clock, so a
            scripted trial starts at the same sim time however long bring-up takes; None: it
            runs on
        :param pace_lead: the lockstep clock runs at most this far (s) ahead of the sim time
            this session has acted on (simulator paced_by: PACE_TOPIC), so a scripted trial's
            decisions meet the same sim time on a loaded machine; None: not paced"""
        self.log = log
        self.domain_id = domain_id
        self.hold_at = hold_at
        given = {node: list(values) for node, values in (overrides or {}).items()}
        if hold_at is not None:
            given.setdefault('simulator', []).append(f'hold_at:={hold_at}')
        if pace_lead is not None:
            given.setdefault('simulator', []).extend([f'paced_by:={PACE_TOPIC}',
                                                      f'pace_lead:={float(pace_lead)!r}'])
        self.pace_lead = pace_lead
        # a scenario holds the clock back to here (s) while it waits for something it needs
        # before a stated time (paced sessions only); None: the newest sim time
        self.pace_limit: Optional[float] = None
        self._pace_pub, self._paced = None, None  # the last pace sent: (sim time, wall time)
        self.graph = NodeGraph(GraphOptions(
            nodes=list(ALL_NODES if nodes is None else nodes), overrides=given,
            domain_id=domain_id, backend=backend, gui=gui, use_sim_time=True,
            keep_going=keep_going, map_file=map_file,
            compose=[list(group) for group in compose]),
            log=log)
        self.map = None  # the last map received on `map` (an OccupancyGrid)
        self.bag_dir = bag_dir
        self.series = RunSeries()
        self.recorder = None
        self.summary = None
        self.walk_start_time = 0.0  # of the last walking_state: the gait is timed from it
        self.walking_state = None  # the last walking_state message
        self.node = None
        self.executor = None
        self._context = None

    # --- life cycle -------------------------------------------------------------------------
    def __enter__(self) -> 'GraphSession':
        self.start()
        return self

    def __exit__(self, *exc) -> bool:
        self.stop()
        return False

    def start(self, timeout: float = 60.0) -> None:
        """Start the nodes, wait until they are up (timeout s), then the client and recorder.

        On a failure (a node dies while starting, a timeout), what was started is stopped
        again before the error propagates: the node processes run in sessions of their own
        and would otherwise outlive this process and talk into the next graph on the domain.
        """
        try:
            self._start(timeout)
        except BaseException:
            self.stop()
            raise

    def _start(self, timeout: float) -> None:
        import rclpy
        from biped_planner.node_support.node_runner import make_executor
        self._context = rclpy.Context()
        rclpy.init(args=[], context=self._context, domain_id=self.domain_id)
        self.node = rclpy.create_node('graph_session', context=self._context, parameter_overrides=[
            rclpy.parameter.Parameter('use_sim_time', value=True)])
        self.executor = make_executor(context=self._context)
        self.executor.add_node(self.node)
        self._check_domain_free()
        self.graph.start()
        self.graph.wait_until_up(timeout)
        self._make_endpoints()
        if self.bag_dir is not None:
            from biped_tools.recording import BagRecorder
            self.recorder = BagRecorder(self.node, self.bag_dir, topics=RECORDED_TOPICS,
                                        log=lambda text: None)

    def _check_domain_free(self) -> None:
        """Refuse a domain where another graph's simulator runs: its /clock reaches this
        session's clock (a run killed without its cleanup leaves its nodes walking, and their
        messages would mix into this run's). Node names alone are no evidence: a node that
        was just destroyed stays in the discovery data for a while."""
        deadline = time.monotonic() + DISCOVERY_WAIT
        clock = self.node.get_clock()
        while time.monotonic() < deadline:
            self._spin_once(0.05)
            if clock.now().nanoseconds > 0:
                others = sorted(set(self.graph.options.nodes) & set(self.node.get_node_names()))
                raise RuntimeError(f'ROS domain {self.domain_id} already has a clock running '
                                   f'(another graph\'s simulator; nodes seen: {others}): stop '
                                   'it, or use another domain')

    def stop(self) -> None:
        if self._context is None:
            self.graph.stop()
            return
        try:
            if self.recorder is not None:
                self.summary = self.recorder.close(self.executor)
                self.log('[session] ' + self.summary.lines()[0])
        finally:
            close_client(self.executor, self.node, self._context)
            self._context = None
            self.graph.stop()

    def _make_endpoints(self) -> None:
        from biped_msgs.msg import (ControllerDiagnostics, FootstepPlan, ReferenceTrajectory,
                                    StepAdjustment)
        from biped_msgs.srv import Push, SetTerrain
        from geometry_msgs.msg import PointStamped, PoseStamped, Twist
        from nav_msgs.msg import OccupancyGrid, Odometry, Path as PathMsg
        from rclpy.qos import DurabilityPolicy, QoSProfile
        latched = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        node, s = self.node, self.series
        self.map_pub = node.create_publisher(OccupancyGrid, 'map', QoSProfile(
            depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))

        def on_map(m):
            from biped_planner.node_support.map_messages import grid_from_msg
            try:
                self.map = grid_from_msg(m)
            except ValueError as error:  # a malformed map (the bad-input tests send them)
                self.log(f'[session] map ignored: {error}')

        node.create_subscription(OccupancyGrid, 'map', on_map, latched)
        if self.pace_lead is not None:
            self._pace_pub = node.create_publisher(Clock, PACE_TOPIC, 10)
        self.goal_pub = node.create_publisher(PoseStamped, 'goal_pose', 10)
        self.command_pub = node.create_publisher(WalkCommand, 'walk_command', 10)
        self.cmd_vel_pub = node.create_publisher(Twist, 'cmd_vel', 10)
        self._velocity, self._velocity_timer = None, None
        self.push_client = node.create_client(Push, 'push')
        self.terrain_client = node.create_client(SetTerrain, 'set_terrain')

        def on_odom(m):
            o = m.pose.pose.orientation
            q = (o.x, o.y, o.z, o.w)
            p = m.pose.pose.position
            append_newer(s.pelvis, (stamp_seconds(m.header.stamp), p.x, p.y, p.z,
                                    tilt_of_quaternion(q), yaw_of_quaternion(q)))

        def on_reference(m):
            if len(m.zmp_x):
                t = stamp_seconds(m.header.stamp)
                s.bounds.append((t, m.zmp_min_x[0], m.zmp_min_y[0], m.zmp_max_x[0],
                                 m.zmp_max_y[0]))
                s.zmp_reference.append((t, m.zmp_x[0], m.zmp_y[0]))

        node.create_subscription(Odometry, 'odom', on_odom, 50)
        node.create_subscription(PointStamped, 'com', lambda m: append_newer(s.com, (
            stamp_seconds(m.header.stamp), m.point.x, m.point.y, m.point.z)), 50)
        node.create_subscription(PointStamped, 'zmp', lambda m: append_newer(s.zmp, (
            stamp_seconds(m.header.stamp), m.point.x, m.point.y)), 50)
        self._reference_sub = node.create_subscription(ReferenceTrajectory,
                                                       'reference_trajectory', on_reference, 50)

        def on_walking_state(m):
            s.states.append((stamp_seconds(m.header.stamp), m.phase, m.step_index, m.fallen,
                             m.reason, m.support_foot, m.time_in_phase))
            self.walk_start_time = m.walk_start_time
            self.walking_state = m

        node.create_subscription(WalkingState, 'walking_state', on_walking_state, 50)
        node.create_subscription(ControllerDiagnostics, 'controller_diagnostics',
                                 lambda m: s.solve_times.append(m.solve_time), 50)
        node.create_subscription(FootstepPlan, 'footstep_plan', s.plans.append, latched)

        def on_adjustment(m):
            s.adjustments.append(m)
            s.plans_before_adjustment.append(len(s.plans))

        node.create_subscription(StepAdjustment, 'step_adjustment', on_adjustment, 50)
        node.create_subscription(PathMsg, 'plan', lambda m: setattr(s, 'path', [
            (p.pose.position.x, p.pose.position.y) for p in m.poses]), latched)

    def watch_foot_forces(self) -> None:
        """Keep the normal force of each ankle F/T reading (series.foot_forces) from now on.
        Not by default: two more 50 Hz readers cost the simulator's publisher in every run."""
        from geometry_msgs.msg import WrenchStamped
        for side, topic in enumerate(('left_foot_wrench', 'right_foot_wrench')):
            samples = self.series.foot_forces[side]
            self.node.create_subscription(WrenchStamped, topic, lambda m, samples=samples: (
                append_newer(samples, (stamp_seconds(m.header.stamp), m.wrench.force.z))), 50)

    # --- waiting ----------------------------------------------------------------------------
    def _spin_once(self, timeout: float) -> None:
        """One turn of the executor. rclpy's EventsExecutor (experimental in Jazzy) was seen to
        raise a pybind11 conversion error for one event in a long CI run (a publisher made and
        destroyed per command nearby): that event is lost, the session goes on and says so."""
        try:
            self.executor.spin_once(timeout_sec=timeout)
        except RuntimeError as error:
            if 'Unable to convert call argument' not in str(error):
                raise
            self.log(f'[session] executor event dropped: {error}')

    def spin_until(self, predicate: Callable[[], bool], timeout: float,
                   what: str = 'condition') -> bool:
        """Spin until predicate() holds (True) or timeout s of wall time pass (False)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.graph.check_alive()
            if predicate():
                return True
            self._publish_pace()  # what the predicate saw is acted on
            self._spin_once(0.02)
        return predicate()

    def _publish_pace(self) -> None:
        """Tell a paced simulator the sim time this session has acted on (held at pace_limit)."""
        if self._pace_pub is None:
            return
        paced = self.sim_time() if self.pace_limit is None else \
            min(self.sim_time(), self.pace_limit)
        now = time.monotonic()
        # the same again after a while: a message sent before DDS matched the simulator's
        # subscription is lost, and the clock would wait for it for ever
        if self._paced is None or paced > self._paced[0] or now - self._paced[1] > PACE_REPEAT:
            self._paced = (paced, now)
            self._pace_pub.publish(Clock(clock=time_msg_of(paced)))

    def subscriber_nodes(self, topic: str) -> set:
        """Names of the nodes that subscribe to topic, as discovered so far."""
        return {info.node_name for info in self.node.get_subscriptions_info_by_topic(topic)}

    def wait_for_nodes_on(self, topic: str, nodes, timeout: float = 15.0) -> None:
        """Wait until each named node subscribes to topic (counting subscribers is not enough:
        this session's own recorder subscribes too, and discovery takes up to seconds)."""
        def subscribed() -> bool:
            return set(nodes) <= self.subscriber_nodes(topic)
        if not self.spin_until(subscribed, timeout):
            raise TimeoutError(f'{sorted(nodes)} not subscribed to {topic} after {timeout} s')

    def sim_time(self) -> float:
        return self.series.pelvis[-1][0] if self.series.pelvis else 0.0

    def wait_sim_time(self, seconds: float, timeout: float) -> bool:
        end = self.sim_time() + seconds
        return self.spin_until(lambda: self.sim_time() >= end, timeout)

    def recording_odometry(self) -> bool:
        """Whether the bag (if any) has odometry: from then on the run is recorded whole (the
        recorder subscribes once it discovers a publisher, later than this session's own
        subscriptions)."""
        if self.recorder is None:
            return True
        odom = self.recorder.records.get('/odom')
        return odom is not None and odom.count > 0

    def wait_until_ready(self, timeout: float = 60.0) -> None:
        """Every node talks: the controller answers, references flow, the map is served, the
        bag records. With the clock held (hold_at) the references wait for the clock, so there
        the reference generator's publisher reaching this session counts instead."""
        clock_held = self.hold_at is not None
        serving = 'map_server' in self.graph.options.nodes
        ok = self.spin_until(lambda: len(self.series.solve_times) > 5 and self.series.pelvis
                             and self.series.states
                             and (self.series.bounds or clock_held and
                                  self._reference_sub.get_publisher_count() > 0)
                             and (self.map is not None or not serving)
                             and self.recording_odometry() and self.planner_knows_the_feet(),
                             timeout)
        if not ok:
            raise TimeoutError(f'graph not ready after {timeout} s (controller cycles: '
                               f'{len(self.series.solve_times)}, states: '
                               f'{len(self.series.states)}, references: '
                               f'{len(self.series.bounds)}, map: {self.map is not None}, '
                               f'odometry recorded: {self.recording_odometry()}, planner '
                               f'has sole_poses: {self.planner_knows_the_feet()}; '
                               f'{self._discovery_report()})')

    def _discovery_report(self) -> str:
        """What DDS discovery shows this session: which nodes, and the publishers of the
        topics a start waits for (a node that is up but undiscovered has none)."""
        nodes = sorted(set(self.node.get_node_names()) - {self.node.get_name()})
        topics = ('walking_state', 'joint_states', 'joint_commands', 'reference_trajectory',
                  'sole_poses', 'map')
        counts = ', '.join(f'{topic} {self.node.count_publishers(topic)}' for topic in topics)
        return f'nodes seen: {", ".join(nodes) or "none"}; publishers seen: {counts}'

    def planner_knows_the_feet(self) -> bool:
        """The planner plans from the controller's sole_poses, not from odom's pelvis (1-2 cm
        off): it reads odom until they arrive, then drops that subscription. A command sent
        before that would start from another place on a loaded machine."""
        nodes = self.graph.options.nodes
        if 'footstep_planner' not in nodes or 'mpc_controller' not in nodes:
            return True
        return 'footstep_planner' in self.subscriber_nodes('/sole_poses') and \
            'footstep_planner' not in self.subscriber_nodes('/odom')

    def phase(self) -> Optional[int]:
        return self.series.states[-1][1] if self.series.states else None

    def fallen(self) -> bool:
        return any(state[3] for state in self.series.states)

    # --- user actions -----------------------------------------------------------------------
    def publish_map(self, grid) -> None:
        """Publish a map over map_server's: the nodes take the last map they receive. (A map
        known before the start is better served by map_server: GraphSession(map_file=...).)"""
        from biped_planner.node_support.map_messages import grid_to_msg
        self.map_pub.publish(grid_to_msg(grid, 'map', self.node.get_clock().now().to_msg()))
        self.wait_for_nodes_on('/map', ('footstep_planner', 'simulator'))

    def send_goal(self, x: float, y: float, yaw: float) -> None:
        self.stop_velocity()
        from geometry_msgs.msg import PoseStamped
        msg = PoseStamped()
        msg.header.frame_id = 'map'
        msg.header.stamp = self.node.get_clock().now().to_msg()
        msg.pose.position.x, msg.pose.position.y = x, y
        _, _, msg.pose.orientation.z, msg.pose.orientation.w = map(float, quaternion_from_yaw(yaw))
        self.wait_for_nodes_on('/goal_pose', COMMAND_LISTENERS)
        self.goal_pub.publish(msg)

    def plan_answering(self, send: Callable[[], None], retries: int = 5):
        """Send a goal (send() publishes it) and return the plan that answers it, None when
        none came. The planner serves plan_walk once it knows the robot's pose; the map can
        come a moment later (both latched): a goal before it is refused with NO_MAP, and is
        sent again 0.5 s later, up to retries times."""
        from biped_msgs.msg import FootstepPlan
        plan = None
        for _ in range(retries):
            count = len(self.series.plans)
            send()
            self.spin_until(lambda: len(self.series.plans) > count, 20.0)
            plan = self.series.plans[-1] if len(self.series.plans) > count else None
            if plan is None or plan.error_code != FootstepPlan.ERROR_NO_MAP:
                return plan
            self.log('[session] the planner has no map yet: goal sent again in 0.5 s')
            self.spin_until(lambda: False, 0.5)
        return plan

    def wait_for_command_listeners(self) -> None:
        """Wait until every node that takes walk commands subscribes to walk_command."""
        self.wait_for_nodes_on('/walk_command', COMMAND_LISTENERS)

    def send_command(self, **fields) -> None:
        self.stop_velocity()
        self.wait_for_command_listeners()
        self.command_pub.publish(WalkCommand(**fields))

    def send_velocity(self, vx: float = 0.0, vy: float = 0.0, wz: float = 0.0) -> None:
        """Teleop: publish this velocity now and every VELOCITY_PERIOD (sim time) until the
        next command, as a teleop does (the state machine stops a walk whose cmd_vel falls
        silent)."""
        from geometry_msgs.msg import Twist
        msg = Twist()
        msg.linear.x, msg.linear.y, msg.angular.z = vx, vy, wz
        self.wait_for_nodes_on('/cmd_vel', COMMAND_LISTENERS)
        self._velocity = msg
        self.cmd_vel_pub.publish(msg)
        if self._velocity_timer is None:
            self._velocity_timer = self.node.create_timer(
                VELOCITY_PERIOD, lambda: self.cmd_vel_pub.publish(self._velocity))

    def stop_velocity(self) -> None:
        """Stop repeating the last send_velocity (the walk then stops after cmd_vel_timeout)."""
        if self._velocity_timer is not None:
            self.node.destroy_timer(self._velocity_timer)
            self._velocity_timer = None

    def push(self, fx: float, fy: float = 0.0, duration: float = 0.1,
             at: Optional[float] = None, timeout: float = PUSH_ANSWER_TIMEOUT) -> bool:
        """Push the pelvis; at: sim time it begins (None: at once).

        :return: the simulator's answer: True applied (or scheduled), False refused
        :raises TimeoutError: no service, or no answer within timeout s of wall time (the
            push may have been applied: a lost answer is not a refusal)
        """
        from biped_msgs.srv import Push
        request = Push.Request()
        request.force.x, request.force.y, request.duration = fx, fy, duration
        if at is not None:
            request.start.sec = int(at)
            request.start.nanosec = int(round((at - int(at)) * 1e9))
        if not self.push_client.wait_for_service(timeout_sec=10.0):
            raise TimeoutError('push service not available')
        future = self.push_client.call_async(request)
        if not self.spin_until(future.done, timeout):
            raise TimeoutError(f'the push service did not answer in {timeout:.0f} s; the push '
                               f'may have been applied')
        return future.result().success

    def resume_clock(self, timeout: float = 30.0) -> str:
        """Let a clock held at the simulator's hold_at run on (simulator/resume).

        :return: the simulator's answer
        :raises TimeoutError: no service, or no answer within timeout s of wall time
        """
        from std_srvs.srv import Trigger
        client = self.node.create_client(Trigger, 'simulator/resume')
        try:
            if not client.wait_for_service(timeout_sec=timeout):
                raise TimeoutError('simulator/resume service not available')
            future = client.call_async(Trigger.Request())
            if not self.spin_until(future.done, timeout):
                raise TimeoutError(f'simulator/resume did not answer in {timeout:.0f} s')
            return future.result().message
        finally:
            self.node.destroy_client(client)

    def set_terrain(self, **fields) -> bool:
        from biped_msgs.srv import SetTerrain
        if not self.terrain_client.wait_for_service(timeout_sec=10.0):
            raise TimeoutError('set_terrain service not available')
        future = self.terrain_client.call_async(SetTerrain.Request(**fields))
        self.spin_until(future.done, 30.0)
        return future.done() and future.result().success
