"""The MPC controller node: references and sensors in, leg joint setpoints out (IK inside).

Subscribes: reference_trajectory (biped_msgs/ReferenceTrajectory), joint_states
(sensor_msgs/JointState), odom (nav_msgs/Odometry: the pelvis pose, when pelvis_source is
ground_truth) or imu (sensor_msgs/Imu: the pelvis orientation, when it is imu_kinematics), zmp
(geometry_msgs/PointStamped, from the ankle F/T sensors), left_foot_wrench / right_foot_wrench
(geometry_msgs/WrenchStamped: foot contacts), walking_state (biped_msgs/WalkingState: its epoch);
one control cycle runs per sensor time, once every one of these carries it. The simulator
publishes joint_states last: its arrival triggers the cycle, which then takes the newest
messages of each other sensor topic (no callback per message), and polls again for one that is
not in yet (topics have no order between them).
Publishes: joint_commands (sensor_msgs/JointState: the 12 leg setpoints, stamped with the sensor
time they answer), controller_diagnostics (biped_mpc/ControllerDiagnostics), sole_poses
(geometry_msgs/PoseArray: [left, right] soles the controller stands on, or swings to; before
its first cycle the measured ones, for the reference generator's first references),
balance_estimate (biped_msgs/BalanceEstimate: the DCM of the measured state, at the start of
each cycle, before its command, while it has a subscriber; the reference generator's step
adjuster answers it; biped_mpc.balance.measured_dcm, with the odometry's pelvis only).

A reference_trajectory whose walk_adjustments grew (the step adjuster moved a step of the walk)
brings the MPC's commanded DCM to the measured one, once (adjusted_walk_dcm_leash).

Lockstep: a period is computed once its reference (stamped with the same sensor time) is in, or
after reference_wait of wall time without it. A reference that comes before the sensors of its
time (this process was held up and its inputs queued; the clock has run on) waits for their
period; one ahead of the clock too is refused.

Safety (biped_mpc.safe_stance, biped_mpc.input_bounds):
- References older than stale_timeout (the reference generator died or lags): the controller
  finishes the step it is in along the last reference window, puts the swing foot down where
  that window lands it, brings the ZMP and hip over the middle of the feet and holds that
  stance (HOLDING, naming reference_trajectory). It walks on only with a reference that fits
  the feet it stands on.
- Sensor messages are checked at the boundary (frames, stamps that go back or run ahead of the
  clock, NaN / inf, positions outside the workspace, joints past their limits, forces beyond
  the sensors' range, quaternions that are not unit): a refused one is logged and the previous
  valid one kept; when a sensor has had no valid message for sensor_timeout the controller
  holds the safe stance (HOLDING, naming it). No joint_states for sensor_loss_timeout of wall
  time (the simulator is gone; a simulator holding its clock sends the held period again, which
  counts): HOLDING reported, naming joint_states, and why when they come but are refused. None
  at all for
  startup_sensor_patience after the start: the log says so every 5 s, with how many publishers
  joint_states has (none: no simulator found; some: their messages do not arrive).
- walking_state.epoch changed (the state machine reset the robot): once the robot stands
  still on both feet, the estimate, stance and commanded state restart from the sensors, the
  old references are dropped, and the controller stands until a reference fits its feet.
The robot comes from the model file robot_description_file (biped_mpc.robot_model; the
COMAN-like robot shipped with this package by default), its URDF for ik=pinocchio from
urdf_file.
"""
import dataclasses
import math
import time

from biped_msgs.msg import (BalanceEstimate, ControllerDiagnostics, ReferenceTrajectory,
                            WalkingState)
from builtin_interfaces.msg import Time
from geometry_msgs.msg import PointStamped, PoseArray, WrenchStamped
from nav_msgs.msg import Odometry
import numpy as np
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import QoSProfile
from sensor_msgs.msg import Imu, JointState

from biped_mpc.balance.measured_dcm import MeasuredDcm
from biped_mpc.controller_io import ControllerFeedback, STATUS_MPC_FALLBACK
from biped_mpc.controller_params import (CONTROLLER_MPC_PARAMS, PELVIS_GROUND_TRUTH,
                                         WalkingControllerParams)
from biped_mpc.deadline_monitor import DeadlineMonitor
from biped_mpc.errors import BipedMpcError, InputError
from biped_mpc.input_bounds import check_reference_window, InputBounds
from biped_mpc.mpc_params import MpcParams
from biped_mpc.nodes.conversions import (deadline_terms, diagnostics_msg, landing_of,
                                         sole_poses_msg)
from biped_mpc.nodes.sensor_intake import SensorFrames, SensorIntake
from biped_mpc.robot_model import COMAN_LIKE_MODEL_FILE, load_robot_model
from biped_mpc.reference_supervisor import ReferenceSupervisor
from biped_mpc.safe_stance import SafeStanceParams
from biped_mpc.state_estimator import EstimatorParams
from biped_mpc.walking_controller import WalkingController
from biped_planner.node_support.dataclass_parameters import (declare_dataclass_parameters,
                                                             declare_node_parameters)
from biped_planner.node_support.latest_message_reader import LatestMessageReader
from biped_planner.node_support.liveliness import LivelinessToken, LivelinessWatch
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.reference_messages import window_from_reference_msg
from biped_planner.node_support.rejection_log import RejectionLog
from biped_planner.node_support.walking_state_checks import walking_state_problem
from biped_planner.parameter_fields import field_specs
from biped_planner.rotations import tilt_of_quaternion

MPC_FIELDS = field_specs(MpcParams)
SENSOR_POLL_PERIOD = 0.0005  # s of wall time between takes while a sensor is not in yet
SENSOR_POLL_TIMEOUT = 0.1  # s of wall time after joint_states: then use the previous data
WATCHDOG_PERIOD = 0.1  # s of wall time between checks that joint_states still come
UNANSWERED_FACTOR = 3.0  # times sensor_loss_timeout while the newest period is unanswered
STILL_SPEED = 0.2  # m/s: below this (and on both feet, upright) the robot stands still
STILL_TILT = 0.2  # rad
SENSOR_TYPES = {'odom': Odometry, 'imu': Imu, 'zmp': PointStamped,
                'left_foot_wrench': WrenchStamped, 'right_foot_wrench': WrenchStamped,
                'joint_states': JointState}
FRAME_FIELDS = {f.name: f.default for f in dataclasses.fields(SensorFrames)}


class MpcControllerNode(Node):
    """Thin adapter over biped_mpc.walking_controller.WalkingController."""

    def __init__(self, **kwargs) -> None:
        super().__init__('mpc_controller', **kwargs)
        declare_node_parameters(self, {
            'robot_description_file': (str(COMAN_LIKE_MODEL_FILE), 'robot model file (YAML, '
                                       'biped_mpc.robot_model): legs, masses, pelvis height',
                                       None),
            'urdf_file': ('', 'the robot\'s URDF, for ik pinocchio only', None),
            'solver': (CONTROLLER_MPC_PARAMS.backend, MPC_FIELDS['backend'].description,
                       MPC_FIELDS['backend'].choices),
            'leg_outputs': (CONTROLLER_MPC_PARAMS.leg_outputs,
                            MPC_FIELDS['leg_outputs'].description,
                            MPC_FIELDS['leg_outputs'].choices),
            'contact_force': (15.0, 'foot normal force above which it is in contact (N)',
                              (0.0, 1000.0)),
            'stale_timeout': (0.3, 'references older than this make it hold a stance (s)',
                              (0.02, 10.0)),
            'reference_wait': (0.1, 'wall time a period waits for its reference (s); longer, up '
                               'to reference_hung_timeout, while the reference generator\'s '
                               'process is alive (DDS liveliness of reference_trajectory/alive)',
                               (0.0, 5.0)),
            'command_deadline': (0.02, 'latency budget of a period, joint_states in to command '
                                 'out; later ones are counted in controller_diagnostics (s)',
                                 (0.0001, 1.0)),
            'reference_hung_timeout': (1.0, 'a live reference generator that has sent nothing for '
                                       'this wall time is not waited for beyond reference_wait '
                                       '(s)', (0.0, 600.0)),
            'sensor_timeout': (0.1, 'a sensor without a valid message for this long makes it '
                               'hold a stance (s)', (0.0, 10.0)),
            'sensor_loss_timeout': (1.0, 'wall time without joint_states after which it reports '
                                    'the simulator lost (s); a simulator holding its clock sends '
                                    'the held period again every lockstep_timeout (0.5 s)',
                                    (0.05, 60.0)),
            'startup_sensor_patience': (10.0, 'wall time after the start without any '
                                        'joint_states after which the log says no cycle runs '
                                        'for want of them (s)', (0.1, 600.0)),
            'foot_length': (0.2, 'sole length, for the standing stance (m)', (0.01, 1.0)),
            'foot_width': (0.1, 'sole width, for the standing stance (m)', (0.01, 1.0)),
            **{f'frames.{name}': (value, f'expected frame_id of the {name} data', None)
               for name, value in FRAME_FIELDS.items()}},
            read_only=('robot_description_file', 'urdf_file', 'solver', 'leg_outputs',
                       'reference_wait', 'command_deadline', 'foot_length', 'foot_width',
                       *(f'frames.{name}' for name in FRAME_FIELDS)))
        get = lambda name: self.get_parameter(name).value  # noqa: E731
        self._robot = load_robot_model(get('robot_description_file'))
        if get('urdf_file'):
            self._robot = dataclasses.replace(self._robot, urdf_path=get('urdf_file'))
        self._params = declare_dataclass_parameters(
            self, WalkingControllerParams(robot=self._robot), {},
            fixed={'robot': self._robot,
                   'mpc': dataclasses.replace(CONTROLLER_MPC_PARAMS, backend=get('solver'),
                                              leg_outputs=get('leg_outputs')),
                   'estimator': EstimatorParams()})
        hold_params = declare_dataclass_parameters(
            self, SafeStanceParams(), {}, prefix='hold.',
            fixed={'foot_length': float(get('foot_length')),
                   'foot_width': float(get('foot_width'))},
            on_change=lambda p: setattr(self._supervisor, 'params', p))
        bounds = declare_dataclass_parameters(self, InputBounds(), {}, prefix='bounds.',
                                              on_change=self._on_bounds)
        self._controller = WalkingController(self._params)
        self._reject = RejectionLog(self.get_logger().error)
        self._dt = self._params.mpc.dt
        self._horizon = self._params.mpc.n_predict + 1
        self._leg_names = list(self._robot.leg_joint_names)
        geometry = self._robot.leg_geometry
        lower = geometry.joint_lower if geometry else (-np.pi,) * 12
        upper = geometry.joint_upper if geometry else (np.pi,) * 12
        self._intake = SensorIntake(
            bounds, SensorFrames(**{name: get(f'frames.{name}') for name in FRAME_FIELDS}),
            self._leg_names, lower, upper, self._sim_now)
        self._supervisor = ReferenceSupervisor(hold_params, self._dt, self._horizon)
        self._epoch = None  # walking_state.epoch applied (None: none seen yet)
        self._epoch_pending = None
        self._stepping = False  # the newest valid walking_state is in a single or double support
        # the pelvis from odom or from the IMU: the other one is not read, so not subscribed
        unread = 'imu' if self._params.pelvis_source == PELVIS_GROUND_TRUTH else 'odom'
        self._sensor_topics = tuple(topic for topic in SENSOR_TYPES if topic != unread)
        self._period = None  # stamp (sec, nanosec) of the newest joint_states
        self._poll_deadline = None
        self._joint_states_arrival = None
        self._joint_states_heard = None  # wall time of the newest valid one, a repeat too
        self._joint_states_refused = -math.inf  # wall time of the newest refused joint_states
        self._created = time.monotonic()
        self._last_cycle = None
        self._pending = None  # sensor time (s) of a complete period not yet computed
        # (reference, walk_adjustments) that starts ahead of the sensors handled so far but not
        # of the clock, for the period of its time
        self._early_reference = None
        self._last_output = None
        self._last_command = None
        self._last_soles = None  # the sole_poses of the last cycle
        self._started = False
        self._command_pub = self.create_publisher(JointState, 'joint_commands', 10)
        self._alive = LivelinessToken(self, 'joint_commands')  # lockstep waits while it lives
        self._diag_pub = self.create_publisher(ControllerDiagnostics, 'controller_diagnostics',
                                               10)
        self._soles_pub = self.create_publisher(PoseArray, 'sole_poses', 10)
        self._balance_pub = self.create_publisher(BalanceEstimate, 'balance_estimate', 10)
        self._balance = MeasuredDcm(self._robot) if geometry is not None else None
        self._balance_time = None
        self.create_subscription(ReferenceTrajectory, 'reference_trajectory', self._on_reference,
                                 10)
        # One cycle per sensor time, once every input of that time is in: mixing two periods'
        # data destabilises the loop. Depth 5: a refused message must not push out a valid one.
        self._readers = {topic: LatestMessageReader(self, SENSOR_TYPES[topic], topic,
                                                    QoSProfile(depth=5))
                         for topic in self._sensor_topics if topic != 'joint_states'}
        self._state_reader = LatestMessageReader(self, WalkingState, 'walking_state',
                                                 QoSProfile(depth=10))
        self.create_subscription(JointState, 'joint_states', self._on_joint_states, 10)
        # Wall-clock timers (with sim time, a ROS timer would wait for the very clock we hold
        # up). This one runs while a period's sensor messages are not all in.
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._poll_timer = self.create_timer(SENSOR_POLL_PERIOD, self._take_sensors,
                                             clock=steady)
        self._poll_timer.cancel()
        # One-shot, armed while a period waits for its reference.
        self._wait_timer = self.create_timer(float(get('reference_wait')), self._on_wait_timer,
                                             clock=steady)
        self._wait_timer.cancel()
        self._reference_arrival = None  # wall time the last valid reference arrived
        self._deadlines = DeadlineMonitor(float(get('command_deadline')))
        self._reference_process = LivelinessWatch(self, 'reference_trajectory')
        self.create_timer(WATCHDOG_PERIOD, self._on_watchdog, clock=steady)
        self.get_logger().info(f'{get("model")} MPC ready ({get("solver")}, Np '
                               f'{self._params.mpc.n_predict})')

    def _on_bounds(self, bounds: InputBounds) -> None:
        self._intake.bounds = bounds

    def _sim_now(self):
        """Now on the node's clock when it follows /clock (the sensors' time base), else None."""
        clock = self.get_clock()
        return clock.now().nanoseconds * 1e-9 if clock.ros_time_is_active else None

    # --- inputs -----------------------------------------------------------------------------
    def _on_reference(self, msg: ReferenceTrajectory) -> None:
        try:
            world = self.get_parameter('frames.world').value
            if msg.header.frame_id not in ('', world):
                raise InputError(f'frame_id {msg.header.frame_id!r}, expected {world!r}')
            reference = window_from_reference_msg(msg)
            check_reference_window(reference, self._dt, self._intake.bounds)
            t0 = float(reference.t[0])
            if self._period is not None and t0 > stamp_seconds_of(self._period) + 1.5 * self._dt:
                now = self._sim_now()
                if now is None or t0 > now + 1e-6:
                    raise InputError(f'it starts at t={t0:.3f} s, ahead of the sensors '
                                     f'(t={stamp_seconds_of(self._period):.3f} s) and of the '
                                     f'clock')
                # The clock has run on and the sensors of that time are still queued (this
                # process was held up): kept until their period, not refused.
                self._early_reference = (reference, msg.walk_adjustments)
                return
            self._check_not_older(t0)
        except (ValueError, BipedMpcError) as error:
            self._reject('reference_trajectory', error)
            return
        self._use_reference(reference, msg.walk_adjustments)

    def _check_not_older(self, t0: float) -> None:
        current = self._supervisor.reference
        if current is not None and t0 < current.t[0] - 1e-9:
            raise InputError(f'it starts at t={t0:.3f} s, before the one in use '
                             f'({current.t[0]:.3f} s)')

    def _use_reference(self, reference, walk_adjustments: int) -> None:
        early = self._early_reference
        if early is not None and early[0].t[0] <= reference.t[0] + 1e-9:
            self._early_reference = None  # superseded
        self._supervisor.set_reference(reference)
        self._controller.walk_adjustments = walk_adjustments
        self._reference_arrival = time.monotonic()
        self._try_cycle()

    def _take_early_reference(self) -> None:
        """The reference kept for a period the sensors had not reached, once they have."""
        early = self._early_reference
        if early is None or self._pending is None or \
                early[0].t[0] > self._pending + 1.5 * self._dt:
            return
        self._early_reference = None
        try:
            self._check_not_older(float(early[0].t[0]))
        except BipedMpcError as error:
            self._reject('reference_trajectory', error)
            return
        self._use_reference(*early)

    def _accept(self, topic: str, msg) -> bool:
        """Check a sensor message; :return: whether it was kept (a refused joint_states does
        not start a period: the simulator's own is checked like any other)."""
        usable, why = self._intake.accept(topic, msg)
        if why is not None:
            self._reject(topic, why)
        return usable

    def _on_joint_states(self, msg: JointState) -> None:
        if not self._accept('joint_states', msg):
            self._joint_states_refused = time.monotonic()
            return
        self._joint_states_heard = time.monotonic()
        period = (msg.header.stamp.sec, msg.header.stamp.nanosec)
        if period == self._last_cycle and self._answered(period):
            # The simulator sent this period again: its answer was lost (at start-up, before
            # DDS matched the two), or its clock holds (hold_at); the same command and soles
            # again, not a second cycle (a planner that subscribed late then learns the feet).
            self._command_pub.publish(self._last_command)
            if self._last_soles is not None:
                self._soles_pub.publish(self._last_soles)
            return
        self._period = period
        self._joint_states_arrival = time.monotonic()  # for the cycle latency diagnostic
        self._poll_deadline = self._joint_states_arrival + SENSOR_POLL_TIMEOUT
        self._take_sensors()

    def _take_sensors(self) -> None:
        """Start the period of the newest joint_states once every sensor has sent its message
        of that time (or after SENSOR_POLL_TIMEOUT: then with the previous valid ones)."""
        for topic, reader in self._readers.items():
            for msg in reader.take_all():
                self._accept(topic, msg)
        if self._period is None:
            return
        late = [topic for topic in self._sensor_topics
                if not self._intake.has_period(topic, self._period)]
        if late and time.monotonic() <= self._poll_deadline:
            if self._poll_timer.is_canceled():
                self._poll_timer.reset()
            return
        self._poll_timer.cancel()
        if self._period == self._last_cycle:
            return
        if late:
            self.get_logger().warning(
                f'period t={stamp_seconds_of(self._period):.3f} s: no {", ".join(late)} of that '
                f'time within {SENSOR_POLL_TIMEOUT} s of joint_states; using the previous',
                throttle_duration_sec=1.0)
        self._last_cycle = self._period
        self._pending = stamp_seconds_of(self._period)
        self._take_early_reference()
        self._try_cycle()
        if self._pending is not None:
            self._wait_timer.reset()  # from now: run it after reference_wait without it

    def _try_cycle(self, force: bool = False) -> None:
        """Run the pending period once its reference is in (or when told to stop waiting).

        Waiting for the reference of the same time puts the reference generator in the
        lockstep too: under load a lagging reference would otherwise be used shifted and padded.
        """
        if self._pending is None:
            return
        reference = self._supervisor.reference
        fresh = reference is not None and reference.t[0] >= self._pending - 1e-6
        if fresh or force:
            self._pending = None
            self._wait_timer.cancel()
            self._control_cycle()
        elif not self._started or self._restarted_while_waiting():
            self._publish_standing_soles()

    def _restarted_while_waiting(self) -> bool:
        """A reset of the robot while a period waits for its reference: the reference
        generator restarted too and stands its references only where sole_poses put the feet,
        which a cycle sends. Restart from the sensors now (once the robot stands still), so the
        soles go out instead of both waiting for reference_hung_timeout (the simulator's
        lockstep waited 1 s). :return: whether the controller stands after a reset with no
        reference yet (the supervisor dropped its reference)."""
        self._take_epoch()
        if self._epoch_pending is not None:
            try:
                feedback = self._feedback()
            except (KeyError, BipedMpcError, ValueError):
                return False  # the cycle reports it
            if not self._stale_sensors(self._pending):
                self._check_epoch(self._pending, feedback)
        return self._epoch_pending is None and self._supervisor.reference is None

    def _resend_soles(self) -> None:
        """While a period waits for a live reference generator: the soles again. One that
        restarted (a reset) after this controller had restarted subscribes to sole_poses anew
        and would otherwise wait for the next cycle, which waits for it. Nothing while a reset
        is not applied yet: the last soles are then the fallen robot's."""
        if not self._started or self._restarted_while_waiting():
            self._publish_standing_soles()
        elif self._epoch_pending is None and self._last_soles is not None:
            self._soles_pub.publish(self._last_soles)

    def _publish_standing_soles(self) -> None:
        """Before the first cycle (and after a reset): the measured soles of the pending
        period, where the reference generator stands its first references. Taken from odom
        instead, they would depend on which message came first, and a run on tiles would start
        differently."""
        try:
            soles = self._controller.standing_soles(self._feedback())
        except (KeyError, BipedMpcError, ValueError):
            return  # a sensor without a valid message yet: the cycle reports it
        self._soles_pub.publish(sole_poses_msg(
            soles, Time(sec=self._last_cycle[0], nanosec=self._last_cycle[1]),
            self.get_parameter('frames.world').value))

    def _on_wait_timer(self) -> None:
        """reference_wait is over: a live reference generator that is producing is slow, not
        gone, and the period keeps waiting for it (so a loaded machine does not change the run);
        one that has sent nothing for reference_hung_timeout is not waited for."""
        since = math.inf if self._reference_arrival is None else \
            time.monotonic() - self._reference_arrival
        if self._pending is not None and self._reference_process.alive and \
                since < self.get_parameter('reference_hung_timeout').value:
            self.get_logger().warning(
                f'period t={self._pending:.3f} s waits for reference_trajectory: the reference '
                f'generator is alive but late ({since:.1f} s since its last)',
                throttle_duration_sec=2.0)
            self._resend_soles()
            return  # the timer fires again in reference_wait
        self._wait_timer.cancel()
        self._try_cycle(force=True)

    def _on_watchdog(self) -> None:
        """Report the simulator lost when joint_states stop (no cycle runs without them), why
        when they come but are refused, and say so when none has come since the start."""
        if self._joint_states_heard is None:
            waited = time.monotonic() - self._created
            if waited >= self.get_parameter('startup_sensor_patience').value:
                publishers = self.count_publishers('joint_states')
                why = 'no simulator found' if publishers == 0 else \
                    f'{publishers} publisher(s), none of whose messages arrived'
                self.get_logger().warning(f'no joint_states in {waited:.1f} s since the start '
                                          f'({why}): no control cycle runs until they come',
                                          throttle_duration_sec=5.0)
            return
        silent = time.monotonic() - self._joint_states_heard
        timeout = self.get_parameter('sensor_loss_timeout').value
        # unanswered, a simulator in lockstep waits for this controller: give it longer
        if silent < (timeout if self._answered(self._period) else UNANSWERED_FACTOR * timeout):
            return
        if time.monotonic() - self._joint_states_refused < timeout:
            message = (f'holding a stance: sensors stale: joint_states refused for {silent:.1f} '
                       f's ({self._intake.why_stale("joint_states")})')
        else:
            message = (f'holding a stance: sensors stale: no joint_states for {silent:.1f} s '
                       f'(simulator lost)')
        self.get_logger().error(message, throttle_duration_sec=5.0)
        self._diag_pub.publish(diagnostics_msg(
            self.get_clock().now().to_msg(), ControllerDiagnostics.HOLDING, message,
            self._params))

    def destroy_node(self) -> None:
        for reader in (*self._readers.values(), self._state_reader):
            reader.destroy()
        super().destroy_node()

    def _feedback(self) -> ControllerFeedback:
        """The newest valid sensor messages as the controller's feedback.

        :raises KeyError: naming a sensor without a valid message yet
        :raises BipedMpcError, ValueError: for sensor data the controller cannot use
        """
        return self._intake.feedback(self._params.pelvis_source,
                                     self.get_parameter('contact_force').value)

    def _stale_sensors(self, t: float) -> str:
        """Why the sensors cannot be trusted at t (the stale ones), '' when they can."""
        return self._intake.stale(self._sensor_topics, t,
                                  self.get_parameter('sensor_timeout').value)

    # --- control cycle ----------------------------------------------------------------------
    def _control_cycle(self) -> None:
        t = stamp_seconds_of(self._last_cycle)
        stamp = Time(sec=self._last_cycle[0], nanosec=self._last_cycle[1])
        try:
            feedback = self._feedback()
        except KeyError as error:
            self._hold_joints(stamp, f'no valid {error.args[0]} yet')
            return
        except (BipedMpcError, ValueError) as error:
            self._hold_joints(stamp, f'sensor data unusable: {error}')
            return
        stale = self._stale_sensors(t)
        if not stale:
            self._publish_balance(t, stamp, feedback)
        if not stale and self._started:
            self._check_epoch(t, feedback)
        feet_now = None if self._last_output is None else \
            (self._last_output.left_foot_target, self._last_output.right_foot_target)
        window, hold_reason = self._supervisor.window(
            t, self.get_parameter('stale_timeout').value, stale,
            self._controller.latched_feet, feet_now)
        for event in self._supervisor.take_events():
            self.get_logger().warning(event)
        if window is None:
            self._wait_unanswered(stamp, hold_reason)
            return
        try:
            if not self._started:
                self._controller.reset(t, feedback)
                self._started = True
                self._take_epoch()
            output = self._controller.step(t, window, feedback)
        except BipedMpcError as error:
            self.get_logger().error(f'control cycle failed: {error}', throttle_duration_sec=2.0)
            self._hold_joints(stamp, f'control cycle failed: {error}')
            return
        self._last_output = output
        if self._controller.balance_loop is not None:
            for event in self._controller.balance_loop.take_events():
                self.get_logger().warning(event)
        command = JointState()
        command.header.stamp = stamp
        command.name = self._leg_names
        command.position = np.asarray(output.joint_setpoints, dtype=float).tolist()
        command.velocity = np.asarray(output.joint_velocities, dtype=float).tolist()
        self._command_pub.publish(command)
        self._last_command = command
        latency = time.monotonic() - self._joint_states_arrival
        self._deadlines.record(latency)
        self._last_soles = sole_poses_msg(
            (output.left_foot_target, output.right_foot_target), stamp,
            self.get_parameter('frames.world').value)
        self._soles_pub.publish(self._last_soles)
        if hold_reason is not None:
            status, message = ControllerDiagnostics.HOLDING, f'holding a stance: {hold_reason}'
        elif output.status & STATUS_MPC_FALLBACK:
            status, message = ControllerDiagnostics.FALLBACK, 'QP failed: shifted previous plan'
        else:
            status, message = ControllerDiagnostics.OK, ''
        diagnostics = diagnostics_msg(stamp, status, message, self._params, output, latency)
        deadline_terms(diagnostics, self._deadlines)
        self._diag_pub.publish(diagnostics)

    def _publish_balance(self, t: float, stamp, feedback: ControllerFeedback) -> None:
        """The measured state's COM and DCM, for the step adjuster (needs the pelvis position:
        with pelvis_source imu_kinematics there is none). Not computed while nobody subscribes
        (the step adjuster is off by default): about 0.1 ms of the cycle."""
        if self._balance is None or feedback.pelvis_position is None:
            return
        if self._balance_pub.get_subscription_count() == 0:
            self._balance_time = None
            self._balance.reset()  # a subscriber that comes later gets a fresh velocity filter
            return
        if self._balance_time is not None and t <= self._balance_time:
            self._balance.reset()  # the clock went back: a reset simulation
        self._balance_time = t
        try:
            com, dcm = self._balance.update(t, feedback.leg_joint_positions,
                                            feedback.pelvis_position,
                                            feedback.pelvis_orientation)
        except BipedMpcError as error:
            self.get_logger().error(f'no balance estimate: {error}', throttle_duration_sec=2.0)
            return
        msg = BalanceEstimate(omega=float(self._balance.omega))
        msg.header.stamp = stamp
        msg.header.frame_id = self.get_parameter('frames.world').value
        msg.com.x, msg.com.y = float(com[0]), float(com[1])
        msg.dcm.x, msg.dcm.y = float(dcm[0]), float(dcm[1])
        msg.zmp.x, msg.zmp.y = float(feedback.zmp[0]), float(feedback.zmp[1])
        msg.landing_modes, msg.landing_depths = landing_of(self._last_output)
        self._balance_pub.publish(msg)

    def _hold_joints(self, stamp, why: str) -> None:
        """No cycle can run: the last setpoints again (the period is answered), or WAITING."""
        message = f'holding the joints: {why}'
        self.get_logger().error(message, throttle_duration_sec=2.0)
        if self._last_command is None:
            self._wait_unanswered(stamp, why)
            return
        command = JointState(name=list(self._last_command.name),
                             position=list(self._last_command.position))
        command.header.stamp = stamp
        self._command_pub.publish(command)
        self._diag_pub.publish(diagnostics_msg(stamp, ControllerDiagnostics.HOLDING, message,
                                               self._params))

    def _wait_unanswered(self, stamp, why: str) -> None:
        """WAITING, the period left unanswered: the simulator's repeat of it runs again."""
        self._last_cycle = None
        self._diag_pub.publish(diagnostics_msg(stamp, ControllerDiagnostics.WAITING, why,
                                               self._params))

    def _answered(self, period) -> bool:
        """The last command sent answers this period ((sec, nanosec) of its joint_states)."""
        return self._last_command is not None and period is not None and (
            self._last_command.header.stamp.sec,
            self._last_command.header.stamp.nanosec) == period

    # --- reset (walking_state.epoch) --------------------------------------------------------
    def _take_epoch(self) -> None:
        """Read the newest valid walking_state's epoch: a change is applied when it can be, a
        return to the applied epoch cancels it."""
        for msg in self._state_reader.take_all():
            why = walking_state_problem(msg)
            if why is not None:
                self._reject('walking_state', why)
                continue
            self._stepping = msg.phase in (WalkingState.SINGLE_SUPPORT,
                                           WalkingState.DOUBLE_SUPPORT)
            if self._epoch is None:
                self._epoch = msg.epoch  # the epoch the controller started in
            elif msg.epoch == self._epoch:
                self._epoch_pending = None
            elif msg.epoch != self._epoch_pending:
                self._epoch_pending = msg.epoch
                if msg.phase != WalkingState.IDLE:
                    self._reject('walking_state', f'epoch {msg.epoch} not used yet: a reset '
                                 f'comes in Idle; it applies once the robot stands still')

    def _check_epoch(self, t: float, feedback: ControllerFeedback) -> None:
        """After a reset of the robot (a new epoch), restart from the sensors once it stands
        still on both feet: a fallen robot's data would be a wrong start. Never while the state
        machine steps: walking in place, a double support is as slow as standing, and a stray
        walking_state with another epoch made the controller restart mid-walk and the robot
        fall (bad-input suite, 'epoch + 1 while walking')."""
        self._take_epoch()
        if self._epoch_pending is None or self._stepping:
            return
        if not feedback.standing_still(STILL_TILT, STILL_SPEED):
            speed = feedback.pelvis_linear_velocity
            self.get_logger().info(
                f'epoch {self._epoch_pending} waits for the robot to stand still at t={t:.2f} s: '
                f'contacts {feedback.contacts}, tilt '
                f'{math.degrees(tilt_of_quaternion(feedback.pelvis_orientation)):.1f} deg, speed '
                f'{"unknown" if speed is None else f"{np.linalg.norm(speed):.2f} m/s"}',
                throttle_duration_sec=1.0)
            return
        epoch, self._epoch_pending = self._epoch_pending, None
        self._epoch = epoch
        self._controller.reset(t, feedback)
        self._early_reference = None  # of the robot before the reset
        self._supervisor.stand(*self._controller.latched_feet, t,
                               f'reset (epoch {epoch}): standing until a reference fits the feet')
        self.get_logger().info(f'epoch {epoch}: estimate, stance and commands restarted from '
                               f'the sensors at t={t:.2f} s; old references dropped')


def stamp_seconds_of(stamp) -> float:
    """Seconds of a (sec, nanosec) stamp."""
    return stamp[0] + stamp[1] * 1e-9


def main(args=None) -> None:
    run_node(MpcControllerNode, args)


if __name__ == '__main__':
    main()
