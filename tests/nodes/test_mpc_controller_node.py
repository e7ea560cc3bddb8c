"""Node-level tests of the MPC controller with the real simulator node, in process."""
import math

from biped_msgs.msg import ControllerDiagnostics, ReferenceTrajectory
from nav_msgs.msg import Odometry
import numpy as np
import pytest
import rclpy
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState

from biped_mpc.nodes.mpc_controller import MpcControllerNode
from biped_planner.footsteps import Footstep
from biped_planner.node_support.reference_messages import reference_trajectory_msg
from biped_planner.sides import LEFT, RIGHT, SUPPORT_DOUBLE
from biped_planner.standing_reference import standing_window
from biped_planner.walking_reference import ReferenceParams
from biped_sim.nodes.simulator import SimulatorNode
from ros_harness import Collector, RosoutLines, spin_until, wait_for_subscribers


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


def test_before_its_first_reference_it_sends_the_measured_soles_of_the_sensor_time(loop):
    """The reference generator stands its first references on them (standing_from_odom off):
    the run then starts from the same feet whichever message comes first."""
    from geometry_msgs.msg import PoseArray
    g = loop
    soles = Collector(g['client'], PoseArray, 'sole_poses', 10)
    assert soles.wait_for(g['executor'], timeout=15), 'no sole_poses while waiting'
    assert not g['commands'].messages
    assert g['odom'].wait_for(g['executor'], timeout=5)
    msg = soles.messages[-1]
    assert msg.header.frame_id == 'map' and len(msg.poses) == 2
    assert seconds(msg.header.stamp) in [seconds(m.header.stamp) for m in g['odom'].messages]
    left, right = ([p.position.x, p.position.y, p.position.z] for p in msg.poses)
    # the simulator's robot stands with its soles 0.14 m apart on the ground, level
    assert abs(left[1] - right[1] - 0.14) < 0.01 and abs(left[0] - right[0]) < 0.01
    assert abs(left[2]) < 0.01 and abs(right[2]) < 0.01


def test_while_the_clock_holds_a_late_subscriber_still_gets_the_soles(ros_context, executor):
    """The simulator repeats the held period; the controller answers it with the same command
    and soles again, so a planner that subscribed late still learns where the feet are."""
    from geometry_msgs.msg import PoseArray
    executor.track(SimulatorNode(context=ros_context, parameter_overrides=[
        Parameter('lockstep_timeout', value=0.1), Parameter('hold_at', value=0.3)]))
    executor.track(MpcControllerNode(context=ros_context, parameter_overrides=[
        Parameter('use_sim_time', value=True)]))
    client = executor.track(rclpy.create_node('mpc_test_client', context=ros_context))
    g = dict(client=client, executor=executor)
    g['odom'] = Collector(client, Odometry, 'odom', 100)
    refs = client.create_publisher(ReferenceTrajectory, 'reference_trajectory', 10)
    assert wait_for_subscribers(executor, refs, timeout=15)
    assert g['odom'].wait_for(executor, timeout=15)
    for _ in range(100):  # references until the clock holds at 0.3 s
        refs.publish(standing_reference(g, sim_time(g)))
        spin_until(executor, lambda: False, 0.05)
        if sim_time(g) >= 0.3 - 1e-6:
            break
    assert sim_time(g) == pytest.approx(0.3)
    spin_until(executor, lambda: False, 1.0)  # the held period's own cycle is long done
    soles = Collector(client, PoseArray, 'sole_poses', 10)
    assert soles.wait_for(executor, timeout=5), 'no sole_poses while the clock holds'
    assert seconds(soles.messages[-1].header.stamp) == pytest.approx(0.3)


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


# --- safety: lost references, bad sensors, a reset ---------------------------------------------
def seconds(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


@pytest.fixture
def walk_loop(ros_context, executor, request):
    """Simulator + controller, the controller waiting 10 ms of wall time for a reference (the
    test plays the reference generator, and then stops). Indirect parametrization: more
    controller parameters as {name: value}, the simulator's under the key 'simulator'."""
    overrides = dict(getattr(request, 'param', {}))
    simulator = executor.track(SimulatorNode(context=ros_context, parameter_overrides=[
        Parameter(name, value=value) for name, value in overrides.pop('simulator', {}).items()]))
    controller = executor.track(MpcControllerNode(context=ros_context, parameter_overrides=[
        Parameter('use_sim_time', value=True), Parameter('reference_wait', value=0.01)]
        + [Parameter(name, value=value) for name, value in overrides.items()]))
    client = executor.track(rclpy.create_node('mpc_walk_client', context=ros_context))
    from geometry_msgs.msg import PoseArray, WrenchStamped
    g = dict(client=client, executor=executor, rosout=RosoutLines(client), simulator=simulator,
             controller=controller)
    g['diag'] = Collector(client, ControllerDiagnostics, 'controller_diagnostics', 100)
    g['commands'] = Collector(client, JointState, 'joint_commands', 100)
    g['odom'] = Collector(client, Odometry, 'odom', 100)
    g['soles'] = Collector(client, PoseArray, 'sole_poses', 100)
    g['feet'] = [Collector(client, WrenchStamped, f'{side}_foot_wrench', 100)
                 for side in ('left', 'right')]
    g['clock'] = Collector(client, Clock, '/clock', 100)
    g['refs'] = client.create_publisher(ReferenceTrajectory, 'reference_trajectory', 10)
    assert wait_for_subscribers(executor, g['refs'], timeout=15)
    return g


def clock_time(g) -> float:
    """The simulator's time (its /clock: the tests publish odometry of their own)."""
    return seconds(g['clock'].messages[-1].clock)


def play_references(g, source, until: float, walk_adjustments: int = 0) -> None:
    """Publish source(t) for every sensor time t (as the reference generator does) until t."""
    from builtin_interfaces.msg import Time
    while True:
        count = len(g['clock'].messages)
        assert g['clock'].wait_for(g['executor'], lambda m: len(m) > count, timeout=5)
        t = clock_time(g)
        if t >= until:
            return
        window = source(t)
        g['refs'].publish(reference_trajectory_msg(window, 1, 0.02, Time(
            sec=int(t), nanosec=int(round((t - int(t)) * 1e9))),
            walk_adjustments=walk_adjustments))


def spin_sim_time(g, seconds_of_sim: float, timeout: float = 60.0) -> None:
    end = clock_time(g) + seconds_of_sim
    assert g['clock'].wait_for(g['executor'], lambda m: seconds(m[-1].clock) >= end,
                               timeout=timeout)


def stands_on_both_feet(g) -> bool:
    return min(f.messages[-1].wrench.force.z for f in g['feet']) > 50.0 and \
        0.5 < g['odom'].messages[-1].pose.pose.position.z < 0.6


def test_references_lost_mid_step_the_controller_finishes_the_step_and_stands(walk_loop):
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.step_timing import StepTiming
    from biped_planner.walking_reference import WalkingReference
    g = walk_loop
    assert g['clock'].wait_for(g['executor'], timeout=15)
    params = ReferenceParams(com_height=0.497, foot_length=0.2, foot_width=0.1)
    play_references(g, lambda t: standing_window(Footstep(LEFT, 0.0, 0.07), Footstep(
        RIGHT, 0.0, -0.07), params, t, 90, 0.02), clock_time(g) + 0.5)
    footsteps = straight_footsteps(10, 0.1, 0.14)
    walk = WalkingReference(footsteps, StepTiming(0.4, 0.2), params, t_start=clock_time(g))
    # the references stop in the middle of the single support of step 3
    single = walk.t_start + 1.0 + 3 * 0.6 + 0.2
    play_references(g, lambda t: walk.sample(t, 90, 0.02), single)
    t_lost = clock_time(g)
    assert walk.sample(t_lost, 1, 0.02).support[0] != SUPPORT_DOUBLE  # a foot is in the air
    spin_sim_time(g, 3.0)
    holding = [d for d in g['diag'].messages if d.status == ControllerDiagnostics.HOLDING]
    assert holding and 'reference_trajectory' in holding[-1].message
    # 0.3 s (stale_timeout) after the last reference, not before
    assert seconds(holding[0].header.stamp) - t_lost == pytest.approx(0.3, abs=0.05)
    assert stands_on_both_feet(g)
    # the swing foot went down where the reference landed it: on the next footstep
    landed = sorted((p.position.x, p.position.y) for p in g['soles'].messages[-1].poses)
    planned = sorted((f.x, f.y) for f in footsteps[4:6])
    assert np.ravel(landed) == pytest.approx(np.ravel(planned), abs=0.02)
    # and the robot stands there: the COM over the middle of the feet
    pelvis = g['odom'].messages[-1].pose.pose.position
    assert abs(pelvis.y) < 0.03


def walk_with_a_landing_moved_mid_swing(g):
    """A replan early in a single support moves the landing 8 cm ahead (more than
    touchdown_gate_distance); the references go on 0.5 s past its touchdown. Returns the
    side of the moved foot ('left' or 'right')."""
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.plan_adjustment import moved_landings, swing_step_at
    from biped_planner.step_timing import StepTiming
    from biped_planner.walking_reference import WalkingReference
    assert g['clock'].wait_for(g['executor'], timeout=15)
    params = ReferenceParams(com_height=0.497, foot_length=0.2, foot_width=0.1)
    play_references(g, lambda t: standing_window(Footstep(LEFT, 0.0, 0.07), Footstep(
        RIGHT, 0.0, -0.07), params, t, 90, 0.02), clock_time(g) + 0.5)
    walk = WalkingReference(straight_footsteps(10, 0.1, 0.14), StepTiming(0.4, 0.2), params,
                            t_start=clock_time(g))
    t_replan = walk.t_start + 1.0 + 3 * 0.6 + 0.1  # early in the single support of step 3
    play_references(g, lambda t: walk.sample(t, 90, 0.02), t_replan)
    assert not g['rosout'].has('touchdown is not confirmed')
    t_now = clock_time(g)
    swing = swing_step_at(walk, t_now)
    landings = moved_landings(walk.footsteps, swing.step + 2,
                              (swing.landing.x + 0.08, swing.landing.y))
    moved = walk.adjust_step(t_now, landings, swing.touchdown)
    play_references(g, lambda t: moved.sample(t, 90, 0.02), swing.touchdown + 0.5)
    return 'left' if swing.landing.side == LEFT else 'right'


def test_a_foot_landing_where_a_replan_moved_it_is_confirmed(walk_loop):
    """The touchdown gate follows the plan (touchdown_gate_follows_plan, the default)."""
    side = walk_with_a_landing_moved_mid_swing(walk_loop)
    assert not walk_loop['rosout'].has('touchdown is not confirmed'), walk_loop['rosout'].lines
    assert walk_loop['diag'].messages[-1].foot_contacts[('left', 'right').index(side)]


@pytest.mark.parametrize('walk_loop', [{'touchdown_gate_follows_plan': False}], indirect=True)
def test_a_landing_moved_past_a_gate_held_at_lift_off_is_reported_in_the_log(walk_loop):
    """With the gate held at the landing planned at lift-off, the loaded foot is farther than
    touchdown_gate_distance from it, is never confirmed, and the node says so."""
    side = walk_with_a_landing_moved_mid_swing(walk_loop)
    assert walk_loop['rosout'].has(f'{side} foot', 'touchdown is not confirmed'), \
        walk_loop['rosout'].lines
    assert not walk_loop['diag'].messages[-1].foot_contacts[('left', 'right').index(side)]


@pytest.mark.parametrize('walk_loop', [{'adjusted_walk_dcm_leash': 0.001}], indirect=True)
def test_a_step_adjustment_on_the_references_brings_the_commanded_dcm_once(walk_loop):
    """walk_adjustments growing on reference_trajectory (0 -> 1) moves the commanded DCM once
    onto the leash (here 1 mm, which any walk exceeds), and controller_diagnostics shows the
    shift of that cycle; 0 leaves it off."""
    from biped_planner.footsteps import straight_footsteps
    from biped_planner.step_timing import StepTiming
    from biped_planner.walking_reference import WalkingReference
    g = walk_loop
    assert g['clock'].wait_for(g['executor'], timeout=15)
    params = ReferenceParams(com_height=0.497, foot_length=0.2, foot_width=0.1)
    walk = WalkingReference(straight_footsteps(6, 0.1, 0.14), StepTiming(0.4, 0.2), params,
                            t_start=clock_time(g) + 0.2)
    play_references(g, lambda t: walk.sample(t, 90, 0.02), walk.t_start + 1.5)
    before = len(g['diag'].messages)
    assert before > 50 and not any(np.any(d.dcm_leash_shift) for d in g['diag'].messages)
    play_references(g, lambda t: walk.sample(t, 90, 0.02), walk.t_start + 2.5,
                    walk_adjustments=1)
    shifts = [np.hypot(*d.dcm_leash_shift) for d in g['diag'].messages[before:]]
    assert len(shifts) > 30 and sum(shift > 0.0 for shift in shifts) == 1, shifts
    assert stands_on_both_feet(g) or g['odom'].messages[-1].pose.pose.position.z > 0.5


def test_bad_sensor_messages_are_refused_the_previous_kept_and_the_robot_stands(walk_loop):
    from geometry_msgs.msg import PointStamped, WrenchStamped
    g = walk_loop
    assert g['clock'].wait_for(g['executor'], timeout=15)
    stand = window_of
    play_references(g, stand, clock_time(g) + 0.3)
    client = g['client']
    publishers = {name: client.create_publisher(msg_type, name, 10) for name, msg_type in (
        ('odom', Odometry), ('joint_states', JointState), ('zmp', PointStamped),
        ('left_foot_wrench', WrenchStamped))}
    for publisher in publishers.values():
        assert wait_for_subscribers(g['executor'], publisher, timeout=15)

    def bad_messages(t):
        from builtin_interfaces.msg import Time
        stamp = Time(sec=int(t), nanosec=int(round((t - int(t)) * 1e9)))
        odom = Odometry()
        odom.header.stamp, odom.header.frame_id, odom.child_frame_id = stamp, 'map', 'pelvis'
        odom.pose.pose.position.x, odom.pose.pose.orientation.w = 1e30, 1.0
        far = Odometry()
        far.header.stamp, far.header.frame_id, far.child_frame_id = stamp, 'odom', 'pelvis'
        far.pose.pose.orientation.w = 1.0
        joints = JointState(name=list(g['commands'].messages[-1].name), position=[1e30] * 12)
        joints.header.stamp = stamp
        zmp = PointStamped()
        zmp.header.stamp, zmp.header.frame_id = stamp, 'map'
        zmp.point.x = math.inf
        wrench = WrenchStamped()
        wrench.header.stamp, wrench.header.frame_id = stamp, 'l_ankle_ft'
        wrench.wrench.force.z = 1e30
        old = Odometry()
        old.header.frame_id, old.child_frame_id = 'map', 'pelvis'  # stamp 0: goes back
        old.pose.pose.orientation.w = 1.0
        return [('odom', odom), ('odom', far), ('odom', old), ('joint_states', joints),
                ('zmp', zmp), ('left_foot_wrench', wrench)]

    def stand_and_inject(t):
        for name, msg in bad_messages(t):
            publishers[name].publish(msg)
        return stand(t)

    play_references(g, stand_and_inject, clock_time(g) + 1.0)
    play_references(g, stand, clock_time(g) + 0.5)
    lines = g['rosout']
    for words in (('odom rejected', 'workspace'), ('odom rejected', "'odom'"),
                  ('odom rejected', 'goes back'), ('joint_states rejected', 'outside'),
                  ('zmp rejected', 'not finite'), ('left_foot_wrench rejected', 'magnitude')):
        assert lines.has(*words), words
    assert stands_on_both_feet(g)
    last = g['diag'].messages[-1]
    assert last.status == ControllerDiagnostics.OK, last.message


def test_malformed_references_are_refused(walk_loop):
    from builtin_interfaces.msg import Time
    g = walk_loop
    assert g['clock'].wait_for(g['executor'], timeout=15)
    t = clock_time(g)
    stamp = Time(sec=int(t), nanosec=int(round((t - int(t)) * 1e9)))
    good = standing_reference(g, t)
    empty = ReferenceTrajectory()
    empty.header.stamp, empty.dt = stamp, 0.02
    other_dt = standing_reference(g, t)
    other_dt.dt = 0.05
    far = standing_reference(g, t)
    far.left_foot_x = [1e6] * len(far.left_foot_x)
    ahead = standing_reference(g, t + 5.0)
    for msg in (empty, other_dt, far, ahead):
        g['refs'].publish(msg)
    spin_until(g['executor'], lambda: False, 0.5)
    for words in (('reference_trajectory rejected', '0 samples'),
                  ('reference_trajectory rejected', 'apart'),
                  ('reference_trajectory rejected', 'workspace'),
                  ('reference_trajectory rejected', 'ahead of the sensors', 'of the clock')):
        assert g['rosout'].has(*words), words
    g['refs'].publish(good)
    assert g['commands'].wait_for(g['executor'], timeout=10)  # controls on the good one


def test_diagnostics_count_the_periods_and_the_late_ones_against_the_deadline(walk_loop):
    g = walk_loop
    assert g['clock'].wait_for(g['executor'], timeout=15)
    play_references(g, window_of, clock_time(g) + 1.0)
    counted = [d for d in g['diag'].messages if d.periods > 0]
    assert len(counted) >= 40
    last = counted[-1]
    assert last.command_deadline == pytest.approx(0.02)
    assert [d.periods for d in counted] == sorted(d.periods for d in counted)  # a count
    assert 0 <= last.late_periods <= last.periods
    assert 0.0 < last.latency_p50 <= last.latency_p99 <= last.latency_max
    # the cycles' own latencies: the median of those published lies within their range
    latencies = [d.cycle_latency for d in counted]
    assert min(latencies) <= last.latency_p50 <= max(latencies)


def test_a_new_epoch_seen_while_stepping_does_not_restart_the_controller(walk_loop):
    """A walking_state with another epoch in a double support (a stray or fuzzed message) is
    not a reset: the robot standing still is not enough; the same epoch in Idle is one."""
    from biped_msgs.msg import WalkingState
    g = walk_loop
    assert g['clock'].wait_for(g['executor'], timeout=15)
    play_references(g, window_of, clock_time(g) + 0.3)
    states = g['client'].create_publisher(WalkingState, 'walking_state', 10)
    assert wait_for_subscribers(g['executor'], states, timeout=15)
    states.publish(WalkingState(epoch=0))
    play_references(g, window_of, clock_time(g) + 0.3)
    states.publish(WalkingState(epoch=1, phase=WalkingState.DOUBLE_SUPPORT))
    play_references(g, window_of, clock_time(g) + 1.0)
    assert g['rosout'].has('epoch 1 not used yet')
    assert not g['rosout'].has('restarted from the sensors')
    states.publish(WalkingState(epoch=1))
    spin_sim_time(g, 1.0)
    assert g['rosout'].has('epoch 1', 'restarted from the sensors')


def pushed_over(g):
    """Stand on the played references in epoch 0, then a 400 N push fells the robot; the
    walking_state publisher, for the next epoch."""
    from biped_msgs.msg import WalkingState
    from biped_msgs.srv import Push
    assert g['clock'].wait_for(g['executor'], timeout=15)
    play_references(g, window_of, clock_time(g) + 0.3)
    states = g['client'].create_publisher(WalkingState, 'walking_state', 10)
    assert wait_for_subscribers(g['executor'], states, timeout=15)
    states.publish(WalkingState(epoch=0))
    push = Push.Request()
    push.force.x, push.duration = 400.0, 0.2
    assert call(g, Push, 'push', push).success
    play_references(g, window_of, clock_time(g) + 1.5)
    assert g['odom'].messages[-1].pose.pose.position.z < 0.3  # fallen
    return states


def test_a_new_epoch_restarts_the_controller_from_the_sensors_after_a_reset(walk_loop):
    from biped_msgs.msg import WalkingState
    from std_srvs.srv import Trigger
    g = walk_loop
    params = ReferenceParams(foot_length=0.2, foot_width=0.1)
    stand = window_of
    states = pushed_over(g)
    assert call(g, Trigger, 'simulator/reset', Trigger.Request()).success
    states.publish(WalkingState(epoch=1))
    # no reference comes now: the controller stands on its feet by itself
    spin_sim_time(g, 2.0)
    assert any('reset (epoch 1)' in d.message for d in g['diag'].messages
               if d.status == ControllerDiagnostics.HOLDING)
    assert stands_on_both_feet(g)
    assert g['rosout'].has('epoch 1', 'restarted from the sensors')
    # a reference of other feet does not fit the stance: refused while it stands
    away = lambda t: standing_window(Footstep(LEFT, 0.5, 0.07), Footstep(  # noqa: E731
        RIGHT, 0.5, -0.07), params, t, 90, 0.02)
    play_references(g, away, clock_time(g) + 0.3)
    assert 'does not fit' in g['diag'].messages[-1].message
    play_references(g, stand, clock_time(g) + 0.5)
    assert g['diag'].messages[-1].status == ControllerDiagnostics.OK
    assert stands_on_both_feet(g)


@pytest.mark.parametrize('walk_loop', [{'reference_hung_timeout': 60.0}], indirect=True)
def test_a_reset_while_a_period_waits_for_its_reference_sends_the_measured_soles(walk_loop):
    """The reference generator restarts with the reset and stands its references only where
    sole_poses put the feet, which a cycle sends: a period waiting for that reference waited
    until reference_hung_timeout (and a lockstep simulator with it) before the first soles."""
    from biped_msgs.msg import WalkingState
    from std_srvs.srv import Trigger
    from biped_planner.node_support.liveliness import LivelinessToken
    g = walk_loop
    states = pushed_over(g)
    # from now the test is a live reference generator that is late: it is waited for
    token = LivelinessToken(g['client'], 'reference_trajectory')  # noqa: F841 - kept alive
    response = call(g, Trigger, 'simulator/reset', Trigger.Request())
    assert response.success
    t_reset = float(response.message.rsplit('t=', 1)[1].split(' s')[0])
    count = len(g['soles'].messages)
    states.publish(WalkingState(epoch=1))  # and no reference from now on

    def after_reset(messages):
        return [m for m in messages[count:] if seconds(m.header.stamp) >= t_reset - 1e-6]
    assert g['soles'].wait_for(g['executor'], lambda m: after_reset(m), timeout=10)
    soles = after_reset(g['soles'].messages)[0].poses
    assert abs(soles[0].position.x) < 0.03 and abs(soles[1].position.x) < 0.03
    assert soles[0].position.y > 0.03 and soles[1].position.y < -0.03  # the start pose
    assert abs(soles[0].position.z) < 0.01 and abs(soles[1].position.z) < 0.01
    assert spin_until(g['executor'], lambda: g['rosout'].has('epoch 1', 'restarted from the '
                                                             'sensors'), 5)


def test_a_period_waiting_for_a_live_generator_sends_its_soles_again(walk_loop):
    """A reference generator that restarted (a reset) subscribes to sole_poses anew and stands
    only where they put the feet: the controller waiting for it must not wait for a cycle."""
    from biped_planner.node_support.liveliness import LivelinessToken
    g = walk_loop
    assert g['clock'].wait_for(g['executor'], timeout=15)
    play_references(g, window_of, clock_time(g) + 0.3)
    token = LivelinessToken(g['client'], 'reference_trajectory')  # noqa: F841 - kept alive
    spin_until(g['executor'], lambda: False, 0.2)
    last = seconds(g['soles'].messages[-1].header.stamp)
    count = len(g['soles'].messages)
    assert g['soles'].wait_for(g['executor'], lambda m: len(m) >= count + 2, timeout=5)
    assert all(seconds(m.header.stamp) == last for m in g['soles'].messages[count:])
    assert clock_time(g) <= last + 0.02 + 1e-9  # the lockstep clock waits meanwhile


def test_a_lost_simulator_is_reported(walk_loop):
    g = walk_loop
    assert g['clock'].wait_for(g['executor'], timeout=15)
    play_references(g, window_of, clock_time(g) + 0.3)
    g['executor'].remove_node(g['simulator'])  # silent from now on (destroyed at teardown)
    count = len(g['diag'].messages)
    assert g['diag'].wait_for(g['executor'], lambda m: any(
        d.status == ControllerDiagnostics.HOLDING and 'joint_states' in d.message
        for d in m[count:]), timeout=10)


@pytest.mark.parametrize('walk_loop', [{'simulator': {'hung_controller_timeout': 0.3}}],
                         indirect=True)
def test_a_controller_held_up_while_the_simulator_ran_on_answers_again_at_once(walk_loop):
    """A CI failure of 2026-12-07: the controller's process was held up for longer than the
    simulator waits; the simulator gave it up and ran on in real time, and the controller's next
    joint_states was 0.34 s newer than its last. It refused them as a jump for NEW_TIMELINE
    messages and reported the simulator lost. Its clock has run through the gap: it answers the
    newest period it is sent, and the simulator is back in lockstep."""
    # alive but silent, the controller is lost at once
    g, executor = walk_loop, walk_loop['executor']
    simulator, controller = g['simulator'], g['controller']
    assert g['clock'].wait_for(executor, timeout=15)
    play_references(g, window_of, clock_time(g) + 0.3)
    executor.remove_node(controller)  # held up: nothing of it runs, DDS queues its inputs
    t_held = clock_time(g)
    play_references(g, window_of, t_held + 1.0)  # the simulator ran on without it
    assert g['rosout'].has('[simulator]', 'controller lost')
    t_back = clock_time(g)
    count = len(g['commands'].messages)
    executor.add_node(controller)
    play_references(g, window_of, t_back + 0.5)
    # the first answer to a period it was sent while held up (not the one it held then)
    answered = [seconds(m.header.stamp) for m in g['commands'].messages[count:]]
    newer = [t for t in answered if t > t_held + 0.1]
    assert newer and newer[0] <= t_back + 0.1, (t_held, t_back, answered[:5])
    assert g['rosout'].has('[simulator]', 'joint_commands arrive again')
    assert simulator.get_parameter('lockstep').value
    # the references the test sent for the clock's newest times came before the queued
    # sensors of those times: kept for their periods, not refused as ahead of the sensors
    assert not g['rosout'].has('reference_trajectory rejected'), g['rosout'].lines


@pytest.mark.parametrize('walk_loop', [{'simulator': {'hold_at': 0.3}}], indirect=True)
def test_a_simulator_holding_its_clock_is_not_reported_lost(walk_loop):
    """Held at hold_at (as a scripted trial holds it), the simulator sends its sensors of the
    held time again every lockstep_timeout: each repeat is a sign of life, and no HOLDING
    'simulator lost' comes (each start that waited for publishers reported one before, 0.5 s
    into the hold)."""
    g, executor = walk_loop, walk_loop['executor']
    assert g['clock'].wait_for(executor, timeout=15)
    play_references(g, window_of, 0.3)
    spin_until(executor, lambda: False, 2.5)  # five of its repeats
    assert clock_time(g) == pytest.approx(0.3, abs=1e-6)
    assert g['diag'].messages and \
        not any('simulator lost' in d.message for d in g['diag'].messages)


def test_refused_joint_states_are_reported_as_refused_not_as_a_lost_simulator(walk_loop):
    """A live simulator whose joint_states the controller refuses (here stamped 5 s ahead of
    the clock) is not a lost one: the hold says which and why."""
    g = walk_loop
    states = Collector(g['client'], JointState, 'joint_states', 10)
    assert g['clock'].wait_for(g['executor'], timeout=15)
    play_references(g, window_of, clock_time(g) + 0.3)
    assert states.wait_for(g['executor'], timeout=5)
    g['executor'].remove_node(g['simulator'])  # silent from now on (destroyed at teardown)
    ahead = states.messages[-1]
    ahead.header.stamp.sec += 5
    publisher = g['client'].create_publisher(JointState, 'joint_states', 10)
    count = len(g['diag'].messages)

    def refused_reported():
        publisher.publish(ahead)
        return any(d.status == ControllerDiagnostics.HOLDING and 'refused' in d.message and
                   'ahead of the clock' in d.message for d in g['diag'].messages[count:])
    assert spin_until(g['executor'], refused_reported, 10.0)
    assert not any('simulator lost' in d.message for d in g['diag'].messages[count:])


def window_of(t):
    return standing_window(Footstep(LEFT, 0.0, 0.07), Footstep(RIGHT, 0.0, -0.07),
                           ReferenceParams(foot_length=0.2, foot_width=0.1), t, 90, 0.02)


def call(g, srv_type, name, request, timeout=10.0):
    client = g['client'].create_client(srv_type, name)
    assert client.wait_for_service(timeout_sec=timeout)
    future = client.call_async(request)
    assert spin_until(g['executor'], future.done, timeout)
    return future.result()


def test_a_controller_that_never_gets_joint_states_says_so_and_whether_a_publisher_exists(
        ros_context, executor):
    executor.track(MpcControllerNode(context=ros_context, parameter_overrides=[
        Parameter('use_sim_time', value=True), Parameter('startup_sensor_patience', value=0.3)]))
    client = executor.track(rclpy.create_node('silent_simulator', context=ros_context))
    rosout = RosoutLines(client)
    assert spin_until(executor, lambda: rosout.has('[mpc_controller]', 'no joint_states in',
                                                   'no simulator found'), 10.0), \
        rosout.lines[-5:]
    silent = client.create_publisher(JointState, 'joint_states', 10)  # never publishes
    assert wait_for_subscribers(executor, silent, timeout=15)
    assert spin_until(executor, lambda: rosout.has('[mpc_controller]', '1 publisher(s), none '
                                                   'of whose messages arrived'), 10.0), \
        rosout.lines[-5:]
