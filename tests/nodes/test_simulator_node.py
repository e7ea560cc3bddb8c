"""Node-level tests of the simulator: real PyBullet, real rclpy and DDS, in process."""
import math
import time

from biped_msgs.srv import Push, SetTerrain
from builtin_interfaces.msg import Time
from geometry_msgs.msg import WrenchStamped
from nav_msgs.msg import Odometry
import pytest
import pybullet
import rclpy
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, JointState
from std_srvs.srv import Trigger

from biped_sim.nodes.simulator import SimulatorNode
from ros_harness import (Collector, domain_id_for_worker, RosoutLines, spin_until,
                         wait_for_subscribers)


@pytest.fixture
def sim(ros_context, executor):
    node = executor.track(SimulatorNode(context=ros_context, parameter_overrides=[
        Parameter('real_time_factor', value=5.0)]))
    client = executor.track(rclpy.create_node('sim_test_client', context=ros_context))
    s = dict(node=node, client=client, executor=executor)
    s['joints'] = Collector(client, JointState, 'joint_states', 100)
    s['odom'] = Collector(client, Odometry, 'odom', 100)
    s['imu'] = Collector(client, Imu, 'imu', 100)
    s['left'] = Collector(client, WrenchStamped, 'left_foot_wrench', 100)
    s['right'] = Collector(client, WrenchStamped, 'right_foot_wrench', 100)
    s['clock'] = Collector(client, Clock, '/clock', 100)
    return s


def call(s, srv_type, name, request, timeout=10.0):
    client = s['client'].create_client(srv_type, name)
    assert client.wait_for_service(timeout_sec=timeout)
    future = client.call_async(request)
    assert spin_until(s['executor'], future.done, timeout)
    return future.result()


def answer_periods(executor, joints, commands, seconds: float) -> None:
    """A controller for `seconds` of wall time: each sensor period answered with its legs."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if joints.messages:
            last = joints.messages[-1]
            commands.publish(JointState(header=last.header, name=list(last.name[:12]),
                                        position=list(last.position[:12])))
        spin_until(executor, lambda: False, 0.02)


class LockstepRig:
    """A lockstep simulator that waits for a controller, with one more parameter, and a client
    that plays the controller (answer_for) and watches the clock and /rosout."""

    def __init__(self, ros_context, executor, *parameters: Parameter) -> None:
        self.node = executor.track(SimulatorNode(context=ros_context, parameter_overrides=[
            Parameter('wait_for_controller', value=True),
            Parameter('lockstep_timeout', value=0.1), *parameters]))
        self.client = executor.track(rclpy.create_node('sim_test_client', context=ros_context))
        self.executor = executor
        self.joints = Collector(self.client, JointState, 'joint_states', 100)
        self.clock = Collector(self.client, Clock, '/clock', 100)
        self.rosout = RosoutLines(self.client)
        self.commands = self.client.create_publisher(JointState, 'joint_commands', 10)
        assert wait_for_subscribers(executor, self.commands)

    def answer_for(self, seconds: float) -> None:
        answer_periods(self.executor, self.joints, self.commands, seconds)


def test_sensors_are_published_with_sim_time_and_consistent_values(sim):
    assert sim['joints'].wait_for(sim['executor'], lambda m: len(m) >= 10, timeout=15)
    joint = sim['joints'].messages[-1]
    assert len(joint.name) == 23 and len(joint.position) == 23
    stamps = [m.clock.sec + m.clock.nanosec * 1e-9 for m in sim['clock'].messages]
    steps = [round(b - a, 6) for a, b in zip(stamps, stamps[1:])]
    assert steps and all(step == pytest.approx(0.02) for step in steps)
    odom = sim['odom'].messages[-1]
    assert 0.5 < odom.pose.pose.position.z < 0.6  # standing pelvis
    imu = sim['imu'].messages[-1]
    assert imu.linear_acceleration.z == pytest.approx(9.81, abs=0.3)  # specific force, upright
    weight = sum(w.messages[-1].wrench.force.z for w in (sim['left'], sim['right']))
    assert weight > 150.0  # the legs above the F/T sensors rest on the feet


def test_lockstep_waits_for_the_controller_command(sim, ros_context):
    assert sim['joints'].wait_for(sim['executor'], timeout=15)  # real time: no controller yet
    # a watchdog far beyond the test's waits, so that a loaded machine cannot trigger it
    assert sim['node'].set_parameters([Parameter('lockstep_timeout', value=30.0)])[0].successful
    commands = sim['client'].create_publisher(JointState, 'joint_commands', 10)
    assert wait_for_subscribers(sim['executor'], commands)
    spin_until(sim['executor'], lambda: False, 0.2)
    # a controller now exists: with no answer the clock holds (until the watchdog)
    count = len(sim['clock'].messages)
    spin_until(sim['executor'], lambda: False, 0.3)
    assert len(sim['clock'].messages) - count <= 1
    last = sim['joints'].messages[-1]
    answer = JointState(header=last.header, name=list(last.name[:12]),
                        position=list(last.position[:12]))
    for _ in range(5):
        count = len(sim['clock'].messages)
        commands.publish(answer)
        assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) > count, timeout=5)
        last = sim['joints'].messages[-1]
        answer.header = last.header


def test_lockstep_starts_the_clock_once_the_awaited_topics_have_publishers(ros_context,
                                                                          executor):
    """A controller that answers does not start the clock while a node of the graph is not up
    yet: a command sent once the graph is up then meets it at the same sim time."""
    from biped_msgs.msg import FootstepPlan, WalkingState
    rig = LockstepRig(ros_context, executor,
                      Parameter('wait_for_publishers', value='walking_state, footstep_plan'))
    client, clock, rosout, answer_for = rig.client, rig.clock, rig.rosout, rig.answer_for

    answer_for(1.0)
    stamps = {(m.clock.sec, m.clock.nanosec) for m in clock.messages}
    assert stamps <= {(0, 0)}, f'the clock ran: {sorted(stamps)[-1]}'
    assert rosout.has('holds the clock', 'walking_state, footstep_plan')
    state = client.create_publisher(WalkingState, 'walking_state', 10)
    answer_for(0.5)
    assert {(m.clock.sec, m.clock.nanosec) for m in clock.messages} <= {(0, 0)}
    plan = client.create_publisher(FootstepPlan, 'footstep_plan', 10)
    answer_for(1.0)
    assert max(m.clock.sec + m.clock.nanosec * 1e-9 for m in clock.messages) >= 0.1
    del state, plan


def test_lockstep_holds_the_clock_at_hold_at_until_resumed(ros_context, executor):
    """A scripted trial gets ready while the clock holds, then resumes it: its commands then
    meet the same sim time however long it took to get ready."""
    rig = LockstepRig(ros_context, executor, Parameter('hold_at', value=0.2))
    client, clock, rosout, answer_for = rig.client, rig.clock, rig.rosout, rig.answer_for

    def latest() -> float:
        return max(m.clock.sec + m.clock.nanosec * 1e-9 for m in clock.messages)

    answer_for(1.5)  # the controller answers every period: the clock still stops at 0.2 s
    assert latest() == pytest.approx(0.2)
    assert rosout.has('holds the clock at t=0.20', 'simulator/resume')
    answer = call(dict(client=client, executor=executor), Trigger, 'simulator/resume',
                  Trigger.Request())
    assert answer.success and 'resumes at t=0.20' in answer.message
    answer_for(1.0)
    assert latest() > 0.3
    again = call(dict(client=client, executor=executor), Trigger, 'simulator/resume',
                 Trigger.Request())
    assert again.success and 'not held' in again.message


def test_a_paced_clock_runs_at_most_pace_lead_ahead_of_its_runner(ros_context, executor):
    """A scripted runner that lags behind the graph: lockstep holds the clock pace_lead ahead
    of the sim time the runner says it has acted on, says so, and runs on once the runner is
    gone (a dead runner paces nothing)."""
    rig = LockstepRig(ros_context, executor, Parameter('paced_by', value='runner_clock'),
                      Parameter('pace_lead', value=0.1))
    pace = rig.client.create_publisher(Clock, 'runner_clock', 10)
    assert wait_for_subscribers(executor, pace)

    def latest() -> float:
        return max(m.clock.sec + m.clock.nanosec * 1e-9 for m in rig.clock.messages)

    pace.publish(Clock(clock=Time(sec=0, nanosec=300_000_000)))
    rig.answer_for(1.5)  # the controller answers every period: the clock stops at 0.3 + 0.1 s
    assert latest() == pytest.approx(0.4)
    assert rig.rosout.has('holds the clock at t=0.40', 'runner_clock reaches t=0.30')
    pace.publish(Clock(clock=Time(sec=0, nanosec=500_000_000)))
    rig.answer_for(1.0)
    assert latest() == pytest.approx(0.6)
    rig.client.destroy_publisher(pace)
    rig.answer_for(1.5)
    assert latest() > 0.7


def test_push_service_moves_the_robot_and_rejects_bad_requests(sim):
    assert sim['odom'].wait_for(sim['executor'], timeout=15)
    x0 = sim['odom'].messages[-1].pose.pose.position.x
    request = Push.Request()
    request.force.x, request.duration = 150.0, 0.1
    assert call(sim, Push, 'push', request).success
    spin_until(sim['executor'], lambda: False, 0.5)
    assert sim['odom'].messages[-1].pose.pose.position.x > x0 + 0.002
    for force, duration in ((math.nan, 0.1), (10.0, -1.0), (1e6, 0.1)):
        bad = Push.Request()
        bad.force.x, bad.duration = force, duration
        response = call(sim, Push, 'push', bad)
        assert not response.success and 'push rejected' in response.message


def test_a_push_can_be_scheduled_at_a_sim_time(sim):
    assert sim['odom'].wait_for(sim['executor'], timeout=15)
    now = sim['odom'].messages[-1].header.stamp
    start = now.sec + now.nanosec * 1e-9 + 1.0
    request = Push.Request()
    request.force.x, request.duration = 150.0, 0.1
    request.start.sec, request.start.nanosec = int(start), int((start % 1.0) * 1e9)
    response = call(sim, Push, 'push', request)
    assert response.success and f't={start:.3f} s' in response.message

    def x_at(t):
        return next(m.pose.pose.position.x for m in sim['odom'].messages
                    if m.header.stamp.sec + m.header.stamp.nanosec * 1e-9 >= t - 1e-6)
    assert sim['odom'].wait_for(sim['executor'], lambda m: m[-1].header.stamp.sec +
                                m[-1].header.stamp.nanosec * 1e-9 > start + 0.5, timeout=15)
    before, after = x_at(start - 0.5), x_at(start)
    assert abs(after - before) < 0.001          # nothing happened before the scheduled start
    assert x_at(start + 0.5) > after + 0.002      # and the push moved it then


def test_reset_keeps_the_clock_going_forward(sim):
    assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) >= 5, timeout=15)
    before = sim['clock'].messages[-1].clock
    assert call(sim, Trigger, 'simulator/reset', Trigger.Request()).success
    count = len(sim['clock'].messages)
    assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) >= count + 3, timeout=15)
    stamps = [seconds(m.clock) for m in sim['clock'].messages]
    assert all(b > a for a, b in zip(stamps, stamps[1:]))   # never back, never repeated
    assert stamps[-1] > seconds(before)


def seconds(stamp):
    return stamp.sec + stamp.nanosec * 1e-9


def test_the_first_readings_after_a_reset_are_measured_on_the_standing_robot(sim):
    """PyBullet's force sensors hold the last physics step: a reset that published at once sent
    the fallen robot's foot forces with the standing pose (both feet unloaded, 8 N each)."""
    assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) >= 5, timeout=15)
    push = Push.Request()
    push.force.x, push.duration = 400.0, 0.2
    assert call(sim, Push, 'push', push).success
    assert sim['odom'].wait_for(sim['executor'], lambda m: m[-1].pose.pose.position.z < 0.3,
                                timeout=15)  # lying
    response = call(sim, Trigger, 'simulator/reset', Trigger.Request())
    assert response.success
    t_reset = float(response.message.rsplit('t=', 1)[1].split(' s')[0])

    def first_after_reset(messages):
        return next((m for m in messages if abs(seconds(m.header.stamp) - t_reset) < 1e-3),
                    None)
    assert spin_until(sim['executor'], lambda: all(
        first_after_reset(sim[side].messages) for side in ('left', 'right')), 10)
    normal = [first_after_reset(sim[side].messages).wrench.force.z
              for side in ('left', 'right')]
    weight = 31.0 * 9.81
    assert min(normal) > 0.25 * weight and 0.7 * weight < sum(normal) < 1.8 * weight


def test_the_robot_can_start_standing_on_paper_tiles(ros_context, executor):
    node = executor.track(SimulatorNode(context=ros_context, parameter_overrides=[
        Parameter('real_time_factor', value=5.0), Parameter('terrain.kind', value=1),
        Parameter('terrain.origin_x', value=-0.5), Parameter('terrain.origin_y', value=-0.5),
        Parameter('terrain.side_length', value=1.0), Parameter('terrain.seed', value=4)]))
    client = executor.track(rclpy.create_node('sim_terrain_client', context=ros_context))
    odom = Collector(client, Odometry, 'odom', 100)
    feet = [Collector(client, WrenchStamped, f'{side}_foot_wrench', 100)
            for side in ('left', 'right')]
    assert odom.wait_for(executor, lambda m: len(m) >= 25, timeout=15)  # 0.5 s: settled
    # the soles rest on tiles 25-50 mm high: the pelvis stands that much above its flat 0.54 m
    assert 0.54 + 0.02 < odom.messages[-1].pose.pose.position.z < 0.54 + 0.06
    assert sum(f.messages[-1].wrench.force.z for f in feet) > 150.0  # on its feet
    assert node.get_parameter('terrain.kind').value == 1


def test_reset_and_terrain_services(sim):
    assert call(sim, Trigger, 'simulator/reset', Trigger.Request()).success
    tiles = SetTerrain.Request(kind=SetTerrain.Request.TILES, tile_size=0.2, seed=3)
    assert call(sim, SetTerrain, 'set_terrain', tiles).success
    bad = SetTerrain.Request(kind=7)
    response = call(sim, SetTerrain, 'set_terrain', bad)
    assert not response.success and 'kind 7 unknown' in response.message
    inverted = SetTerrain.Request(kind=SetTerrain.Request.TILES, min_height=0.1, max_height=0.0)
    assert not call(sim, SetTerrain, 'set_terrain', inverted).success
    assert call(sim, SetTerrain, 'set_terrain', SetTerrain.Request(kind=0)).success


def test_malformed_joint_commands_are_rejected_and_the_node_keeps_running(sim):
    commands = sim['client'].create_publisher(JointState, 'joint_commands', 10)
    assert wait_for_subscribers(sim['executor'], commands)
    commands.publish(JointState(name=['no_such_joint'], position=[0.1]))
    commands.publish(JointState(name=['l_knee'], position=[math.nan]))
    commands.publish(JointState(name=['l_knee', 'r_knee'], position=[0.1]))
    count = len(sim['clock'].messages)
    assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) > count + 3, timeout=10)
    assert 0.5 < sim['odom'].messages[-1].pose.pose.position.z < 0.6


def test_odometry_twist_is_in_the_pelvis_frame_as_nav_msgs_specifies():
    from types import SimpleNamespace
    import numpy as np
    from biped_sim.nodes.conversions import odometry_msg
    yaw = np.pi / 2  # pelvis facing world +y, moving along world +y: forward in its own frame
    base = SimpleNamespace(position=(0.0, 0.0, 0.54),
                           orientation=(0.0, 0.0, np.sin(yaw / 2), np.cos(yaw / 2)),
                           linear_velocity=(0.0, 0.3, 0.0), angular_velocity=(0.0, 0.0, 0.2))
    msg = odometry_msg(base, 'map', 'pelvis', Odometry().header.stamp)
    twist = msg.twist.twist
    assert (twist.linear.x, twist.linear.y) == pytest.approx((0.3, 0.0), abs=1e-12)
    assert twist.angular.z == pytest.approx(0.2)
    assert (msg.header.frame_id, msg.child_frame_id) == ('map', 'pelvis')


def test_the_robot_is_a_parameter_checked_against_the_library_catalogue(ros_context):
    with pytest.raises(ValueError, match='robot'):
        SimulatorNode(context=ros_context, parameter_overrides=[
            Parameter('robot', value='banana')])


def test_the_model_plant_backend_publishes_the_leg_joints(ros_context, executor):
    node = executor.track(SimulatorNode(context=ros_context, parameter_overrides=[
        Parameter('backend', value='model'), Parameter('real_time_factor', value=5.0)]))
    client = executor.track(rclpy.create_node('sim_model_client', context=ros_context))
    joints = Collector(client, JointState, 'joint_states', 100)
    assert joints.wait_for(executor, lambda m: len(m) >= 3, timeout=15)
    assert list(joints.messages[-1].name) == list(node._backend.leg_joint_names)


# --- safety: a lost controller, refused commands and maps, the hold after a reset --------------
def answer(sim, commands, bend: float = 0.0) -> JointState:
    """A command answering the last sensor time: the 12 leg joints at the standing pose they
    started in, knees bent by bend (rad)."""
    first, last = sim['joints'].messages[0], sim['joints'].messages[-1]
    position = list(first.position[:12])
    for i, name in enumerate(first.name[:12]):
        if 'knee' in name:
            position[i] += bend
    msg = JointState(name=list(first.name[:12]), position=position)
    msg.header = last.header
    commands.publish(msg)
    return msg


def test_a_lost_controller_is_reported_and_the_servos_hold_its_last_positions(sim):
    from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
    diagnostics = Collector(sim['client'], DiagnosticArray, 'diagnostics', 100)
    commands = sim['client'].create_publisher(JointState, 'joint_commands', 10)
    assert wait_for_subscribers(sim['executor'], commands)
    assert sim['joints'].wait_for(sim['executor'], timeout=15)
    for _ in range(10):  # a controller answering in lockstep, knees bent a little more
        count = len(sim['clock'].messages)
        sent = answer(sim, commands, bend=0.05)
        assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) > count, timeout=5)
    knees = [i for i, name in enumerate(sent.name) if 'knee' in name]
    # the controller falls silent: reported, and the clock runs on
    count = len(diagnostics.messages)
    assert diagnostics.wait_for(sim['executor'], lambda m: any(
        s.level == DiagnosticStatus.ERROR and 'joint_commands' in s.message
        for d in m[count:] for s in d.status), timeout=5)
    ticks = len(sim['clock'].messages)
    spin_until(sim['executor'], lambda: False, 1.0)
    assert len(sim['clock'].messages) > ticks + 10  # real time (x5), not a period per timeout
    last = sim['joints'].messages[-1]
    held = [last.position[i] for i in knees]
    assert held == pytest.approx([sent.position[i] for i in knees], abs=0.05)
    assert 0.5 < sim['odom'].messages[-1].pose.pose.position.z < 0.6
    # it comes back (answering the sensors as they come): followed again, reported OK
    count = len(diagnostics.messages)

    def back(messages) -> bool:
        answer(sim, commands)
        return any(s.level == DiagnosticStatus.OK for d in messages[count:] for s in d.status)
    assert diagnostics.wait_for(sim['executor'], back, timeout=5)


TOKEN_PROCESS = """
import rclpy
from biped_planner.node_support.liveliness import LivelinessToken
rclpy.init()
node = rclpy.create_node('late_controller')
token = LivelinessToken(node, 'joint_commands')
rclpy.spin(node)
"""


def test_lockstep_waits_for_a_late_controller_whose_process_lives_and_not_for_a_dead_one(sim):
    """A controller late beyond lockstep_timeout but alive (DDS liveliness, asserted by its
    process) is waited for, with a WARN naming joint_commands: the clock holds, whatever the
    machine's load, and the period's sensors go out again every lockstep_timeout (for a
    controller that lost or refused them); once its process is killed, it is lost within the
    lease and the clock runs."""
    import os
    import signal
    import subprocess
    import sys
    from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
    diagnostics = Collector(sim['client'], DiagnosticArray, 'diagnostics', 100)
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain_id_for_worker()),
               ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST')
    process = subprocess.Popen([sys.executable, '-c', TOKEN_PROCESS], env=env)
    try:
        assert spin_until(sim['executor'], lambda: sim['node']._controller_process.alive, 30.0)
        commands = sim['client'].create_publisher(JointState, 'joint_commands', 10)
        assert wait_for_subscribers(sim['executor'], commands)
        assert sim['joints'].wait_for(sim['executor'], timeout=15)
        for _ in range(5):
            count = len(sim['clock'].messages)
            answer(sim, commands)
            assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) > count, timeout=5)
        # silent for 4 x lockstep_timeout, alive: reported, the clock holds, the sensors again
        count = len(diagnostics.messages)
        spin_until(sim['executor'], lambda: False, 0.1)  # the last answer's step
        held = seconds(sim['clock'].messages[-1].clock)
        states = len(sim['joints'].messages)
        spin_until(sim['executor'], lambda: False, 2.0)
        assert seconds(sim['clock'].messages[-1].clock) == held
        again = [seconds(m.header.stamp) for m in sim['joints'].messages[states:]]
        assert len(again) >= 3 and set(again) == {held}, again
        statuses = [s for d in diagnostics.messages[count:] for s in d.status]
        assert any(s.level == DiagnosticStatus.WARN and 'joint_commands' in s.message
                   for s in statuses)
        assert not any(s.level == DiagnosticStatus.ERROR for s in statuses)
        # the process dies: lost, safe mode, the clock runs in real time
        os.kill(process.pid, signal.SIGKILL)
        process.wait()
        assert diagnostics.wait_for(sim['executor'], lambda m: any(
            s.level == DiagnosticStatus.ERROR for d in m[count:] for s in d.status), timeout=5)
        ticks = len(sim['clock'].messages)
        spin_until(sim['executor'], lambda: False, 1.0)
        assert len(sim['clock'].messages) > ticks + 10
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


def test_joint_commands_past_the_limits_or_ahead_of_the_clock_are_refused(sim):
    from builtin_interfaces.msg import Time
    rosout = RosoutLines(sim['client'])
    commands = sim['client'].create_publisher(JointState, 'joint_commands', 10)
    assert wait_for_subscribers(sim['executor'], commands)
    assert sim['joints'].wait_for(sim['executor'], timeout=15)
    stamp = sim['joints'].messages[-1].header.stamp
    commands.publish(JointState(name=['l_knee_joint'], position=[1e30]))
    commands.publish(JointState(name=['l_knee_joint'], position=[-1.0]))  # limit 0, margin 0.1
    commands.publish(JointState(name=['l_knee_joint'], position=[0.5], velocity=[math.inf]))
    ahead = JointState(name=['l_knee_joint'], position=[0.5])
    ahead.header.stamp = Time(sec=stamp.sec + 100, nanosec=stamp.nanosec)
    commands.publish(ahead)
    spin_until(sim['executor'], lambda: False, 1.0)
    for words in (('joint_commands rejected', 'l_knee_joint', 'outside'),
                  ('joint_commands rejected', 'not finite'),
                  ('joint_commands rejected', 'ahead of the simulation')):
        assert rosout.has(*words), words
    knee = dict(zip(sim['joints'].messages[-1].name, sim['joints'].messages[-1].position))
    assert knee['l_knee_joint'] > 0.1  # none of them was followed
    assert 0.5 < sim['odom'].messages[-1].pose.pose.position.z < 0.6


@pytest.mark.parametrize('field, value, words', [
    ('resolution', math.nan, 'resolution'), ('resolution', math.inf, 'resolution'),
    ('origin_x', math.nan, 'origin'), ('origin_x', math.inf, 'origin'),
    ('frame_id', 'odom', 'frame_id'), ('size', 5, 'cells')])
def test_a_malformed_map_is_refused_and_the_simulator_runs_on(sim, field, value, words):
    from nav_msgs.msg import OccupancyGrid
    from rclpy.qos import DurabilityPolicy, QoSProfile
    rosout = RosoutLines(sim['client'])
    grid = OccupancyGrid()
    grid.header.frame_id = 'map'
    grid.info.resolution, grid.info.width, grid.info.height = 0.1, 4, 4
    grid.info.origin.orientation.w = 1.0
    grid.data = [100] * 16
    if field == 'resolution':
        grid.info.resolution = value
    elif field == 'origin_x':
        grid.info.origin.position.x = value
    elif field == 'frame_id':
        grid.header.frame_id = value
    else:
        grid.data = [100] * value
    publisher = sim['client'].create_publisher(OccupancyGrid, 'map', QoSProfile(
        depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    assert wait_for_subscribers(sim['executor'], publisher)
    publisher.publish(grid)
    assert spin_until(sim['executor'], lambda: rosout.has('map rejected', words), 10)
    count = len(sim['clock'].messages)
    assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) > count + 3, timeout=10)


def test_after_a_reset_the_servos_hold_the_standing_pose_while_the_controller_restarts(sim):
    commands = sim['client'].create_publisher(JointState, 'joint_commands', 10)
    assert wait_for_subscribers(sim['executor'], commands)
    assert sim['node'].set_parameters([Parameter('reset_hold', value=1.0)])[0].successful
    assert sim['joints'].wait_for(sim['executor'], timeout=15)
    assert call(sim, Trigger, 'simulator/reset', Trigger.Request()).success
    count = len(sim['joints'].messages)
    assert sim['joints'].wait_for(sim['executor'], lambda m: len(m) > count, timeout=5)
    standing = list(sim['joints'].messages[-1].position[:12])
    for _ in range(15):  # a controller that has not restarted yet: knees 0.4 rad more bent
        count = len(sim['clock'].messages)
        answer(sim, commands, bend=0.4)
        assert sim['clock'].wait_for(sim['executor'], lambda m: len(m) > count, timeout=5)
    now = sim['joints'].messages[-1]
    assert list(now.position[:12]) == pytest.approx(standing, abs=0.02)  # held
    assert 0.5 < sim['odom'].messages[-1].pose.pose.position.z < 0.6


def test_a_late_command_with_a_bad_value_is_refused_for_its_value(sim):
    """A second publisher's bad command can arrive after the controller's next one: the log
    names the bad value, not only the stamp that went back."""
    rosout = RosoutLines(sim['client'])
    commands = sim['client'].create_publisher(JointState, 'joint_commands', 10)
    assert wait_for_subscribers(sim['executor'], commands)
    assert sim['joints'].wait_for(sim['executor'], timeout=15)
    first = sim['joints'].messages[-1].header.stamp
    answer = JointState(name=['l_knee_joint'], position=[0.5])
    answer.header.stamp = first
    commands.publish(answer)  # answers the period: the clock moves on
    assert spin_until(sim['executor'], lambda: sim['joints'].messages[-1].header.stamp != first,
                      10)
    newer = sim['joints'].messages[-1].header.stamp
    answer.header.stamp = newer
    commands.publish(answer)
    assert spin_until(sim['executor'], lambda: sim['joints'].messages[-1].header.stamp != newer,
                      10)
    late = JointState(name=['l_knee_joint'], position=[math.nan])
    late.header.stamp = first  # before the last answered command
    commands.publish(late)
    assert spin_until(sim['executor'], lambda: rosout.has('joint_commands rejected',
                                                          'not finite'), 10)


def test_a_map_leaves_the_tiles_under_the_feet_alone(ros_context, executor):
    """The latched map arrives at a moment that depends on the machine's load: rebuilt
    then, the tiles under the standing feet were new bodies and the contact solver started
    over (a tile trial crossed on a loaded machine where it fell on a quiet one). An unchanged
    map rebuilds nothing, a changed one only the obstacles."""
    from nav_msgs.msg import OccupancyGrid
    from rclpy.qos import DurabilityPolicy, QoSProfile
    node = executor.track(SimulatorNode(context=ros_context, parameter_overrides=[
        Parameter('real_time_factor', value=5.0), Parameter('terrain.kind', value=1),
        Parameter('terrain.origin_x', value=-0.5), Parameter('terrain.origin_y', value=-0.5),
        Parameter('terrain.side_length', value=1.0), Parameter('terrain.seed', value=4)]))
    client = executor.track(rclpy.create_node('sim_map_client', context=ros_context))
    rosout = RosoutLines(client)
    tiles = list(node._backend._scenery.bodies)
    assert tiles
    publisher = client.create_publisher(OccupancyGrid, 'map', QoSProfile(
        depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    assert wait_for_subscribers(executor, publisher)
    grid = OccupancyGrid()
    grid.header.frame_id = 'map'
    grid.info.resolution, grid.info.width, grid.info.height = 0.1, 4, 4
    grid.info.origin.position.x = 2.0
    grid.info.origin.orientation.w = 1.0
    grid.data = [0] * 16
    publisher.publish(grid)
    assert spin_until(executor, lambda: rosout.has('0 obstacle boxes from the map',
                                                   'unchanged'), 10)
    assert node._backend._scenery.bodies == tiles  # the same bodies
    grid.data = [100] + [0] * 15
    publisher.publish(grid)
    assert spin_until(executor, lambda: rosout.has('1 obstacle boxes from the map'), 10)
    bodies = node._backend._scenery.bodies
    assert bodies[:len(tiles)] == tiles and len(bodies) == len(tiles) + 1  # the tiles kept
    grid.data = [0] * 15 + [100]  # the obstacle moved to the grid's far corner
    publisher.publish(grid)

    def obstacle_x():
        body = node._backend._scenery.bodies[-1]
        return pybullet.getBasePositionAndOrientation(
            body, physicsClientId=node._backend._client)[0][0]
    assert obstacle_x() == pytest.approx(2.05, abs=1e-6)
    assert spin_until(executor, lambda: abs(obstacle_x() - 2.35) < 1e-6, 10)  # float32
    assert node._backend._scenery.bodies[:len(tiles)] == tiles  # the tiles kept again
