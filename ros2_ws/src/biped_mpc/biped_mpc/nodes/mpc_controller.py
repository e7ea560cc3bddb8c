"""The MPC controller node: references and sensors in, leg joint setpoints out (IK inside).

Subscribes: reference_trajectory (biped_msgs/ReferenceTrajectory), joint_states
(sensor_msgs/JointState), odom (nav_msgs/Odometry: the pelvis pose, when pelvis_source is
ground_truth) or imu (sensor_msgs/Imu: the pelvis orientation, when it is imu_kinematics), zmp
(geometry_msgs/PointStamped, from the ankle F/T sensors), left_foot_wrench / right_foot_wrench
(geometry_msgs/WrenchStamped: foot contacts); one control cycle runs per sensor time, once
every one of these carries it. The simulator publishes joint_states last: its arrival triggers
the cycle, which then takes the newest message of each other sensor topic (no callback per
message), and polls again for one that is not in yet (topics have no order between them).
Publishes: joint_commands (sensor_msgs/JointState: the 12 leg setpoints, stamped with the sensor
time they answer), controller_diagnostics (biped_msgs/ControllerDiagnostics), sole_poses
(geometry_msgs/PoseArray: [left, right] soles the controller stands on, or swings to).

Lockstep: a period is computed once its reference (stamped with the same sensor time) is in, or
after reference_wait of wall time without it.
Safety: when the references are older than stale_timeout (the planner or reference generator
died or lags), the controller holds a safe stance: both feet on the ground where they are and
the hip between them, reported as HOLDING. Malformed messages are logged and skipped.
The robot comes from the model file robot_description_file (biped_mpc.robot_model; the
COMAN-like robot shipped with this package by default), its URDF for ik=pinocchio from
urdf_file.
"""
import dataclasses
import math
import time

from biped_msgs.msg import ControllerDiagnostics, ReferenceTrajectory
from geometry_msgs.msg import PointStamped, Pose, PoseArray, WrenchStamped
from nav_msgs.msg import Odometry
import numpy as np
from rcl_interfaces.msg import SetParametersResult
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from sensor_msgs.msg import Imu, JointState

from biped_mpc.controller_io import ControllerFeedback, STATUS_MPC_FALLBACK
from biped_mpc.controller_params import (CONTROLLER_MPC_PARAMS, PELVIS_GROUND_TRUTH,
                                         WalkingControllerParams)
from biped_mpc.errors import BipedMpcError
from biped_mpc.mpc_params import MpcParams
from biped_mpc.nodes.latest_message_reader import LatestMessageReader
from biped_mpc.robot_model import COMAN_LIKE_MODEL_FILE, load_robot_model
from biped_mpc.state_estimator import EstimatorParams
from biped_mpc.walking_controller import WalkingController
from biped_planner.footsteps import Footstep
from biped_planner.node_support.dataclass_parameters import (declare_dataclass_parameters,
                                                             declare_node_parameters)
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.reference_messages import window_from_reference_msg
from biped_planner.parameter_fields import field_specs
from biped_planner.rotations import quaternion_from_yaw, quaternion_to_matrix
from biped_planner.sides import LEFT, RIGHT
from biped_planner.standing_reference import standing_window
from biped_planner.walking_reference import ReferenceParams

MPC_FIELDS = field_specs(MpcParams)
READ_AT_START = ('reference_wait', 'robot_description_file', 'urdf_file')

SENSOR_POLL_PERIOD = 0.0005  # s of wall time between takes while a sensor is not in yet
SENSOR_POLL_TIMEOUT = 0.1  # s of wall time after joint_states: then stop polling for the rest
SENSOR_TYPES = {'odom': Odometry, 'imu': Imu, 'zmp': PointStamped,
                'left_foot_wrench': WrenchStamped, 'right_foot_wrench': WrenchStamped,
                'joint_states': JointState}


def stamp_seconds(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


def window_from(window, start: int, n: int):
    """Samples start .. start + n - 1 of a window, the last sample repeated past its end."""
    last = len(window.t) - 1
    index = np.minimum(np.arange(start, start + n), last)
    return dataclasses.replace(window, **{f.name: getattr(window, f.name)[index]
                                          for f in dataclasses.fields(window)})


def sole_poses_msg(output, stamp) -> PoseArray:
    """The soles the controller stands on or moves to: [left, right], x y z and yaw (map)."""
    msg = PoseArray()
    msg.header.stamp = stamp
    msg.header.frame_id = 'map'
    for target in (output.left_foot_target, output.right_foot_target):
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = (float(v) for v in target[:3])
        _, _, pose.orientation.z, pose.orientation.w = (
            float(v) for v in quaternion_from_yaw(target[3]))
        msg.poses.append(pose)
    return msg


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
            'reference_wait': (0.1, 'wall time a period waits for its reference (s)',
                               (0.0, 5.0)),
            'foot_length': (0.2, 'sole length, for the standing stance (m)', (0.01, 1.0)),
            'foot_width': (0.1, 'sole width, for the standing stance (m)', (0.01, 1.0))})
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
        self._controller = WalkingController(self._params)
        self._horizon = self._params.mpc.n_predict + 1
        self._standing_params = ReferenceParams(foot_length=float(get('foot_length')),
                                                foot_width=float(get('foot_width')))
        self._leg_names = list(self._robot.leg_joint_names)
        self._reference = None
        self._reference_start = None  # the reference's first self._horizon samples
        self._sensors = {}
        # the pelvis from odom or from the IMU: the other one is not read, so not subscribed
        unread = 'imu' if self._params.pelvis_source == PELVIS_GROUND_TRUTH else 'odom'
        self._sensor_topics = tuple(topic for topic in SENSOR_TYPES if topic != unread)
        self._poll_deadline = None
        self._joint_states_arrival = None
        self._last_cycle = None
        self._pending = None  # sensor time (s) of a complete period not yet computed
        self._last_output = None
        self._started = False
        self._command_pub = self.create_publisher(JointState, 'joint_commands', 10)
        self._diag_pub = self.create_publisher(ControllerDiagnostics, 'controller_diagnostics',
                                               10)
        self._soles_pub = self.create_publisher(PoseArray, 'sole_poses', 10)
        self.create_subscription(ReferenceTrajectory, 'reference_trajectory', self._on_reference,
                                 10)
        # One cycle per sensor time, once every input of that time is in: mixing two periods'
        # data destabilises the loop.
        self._readers = {topic: LatestMessageReader(self, SENSOR_TYPES[topic], topic)
                         for topic in self._sensor_topics if topic != 'joint_states'}
        self.create_subscription(JointState, 'joint_states', self._on_joint_states, 10)
        # Wall-clock timers (with sim time, a ROS timer would wait for the very clock we hold
        # up). This one runs while a period's sensor messages are not all in.
        self._poll_timer = self.create_timer(SENSOR_POLL_PERIOD, self._take_sensors, clock=Clock(
            clock_type=ClockType.STEADY_TIME))
        self._poll_timer.cancel()
        # One-shot, armed while a period waits for its reference.
        self._wait_timer = self.create_timer(float(get('reference_wait')), self._on_wait_timer,
                                             clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._wait_timer.cancel()
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(f'{get("model")} MPC ready ({get("solver")}, Np '
                               f'{self._params.mpc.n_predict})')

    # --- inputs -----------------------------------------------------------------------------
    def _on_reference(self, msg: ReferenceTrajectory) -> None:
        try:
            self._reference = window_from_reference_msg(msg)
        except ValueError as error:
            self.get_logger().error(f'reference rejected: {error}', throttle_duration_sec=2.0)
            return
        # the horizon from its first sample, cut now: references come ahead of their period
        self._reference_start = window_from(self._reference, 0, self._horizon)
        self._try_cycle()

    def _on_joint_states(self, msg: JointState) -> None:
        self._sensors['joint_states'] = msg
        self._joint_states_arrival = time.monotonic()  # for the cycle latency diagnostic
        self._poll_deadline = self._joint_states_arrival + SENSOR_POLL_TIMEOUT
        self._take_sensors()

    def _take_sensors(self) -> None:
        """Start the period of the newest joint_states once every sensor carries its time."""
        for topic, reader in self._readers.items():
            msg = reader.take()
            if msg is not None:
                self._sensors[topic] = msg
        stamps = {(m.header.stamp.sec, m.header.stamp.nanosec)
                  for m in self._sensors.values()}
        if len(self._sensors) == len(self._sensor_topics) and len(stamps) == 1:
            self._poll_timer.cancel()
            if stamps != {self._last_cycle}:
                self._last_cycle = stamps.pop()
                self._pending = stamp_seconds(self._sensors['joint_states'].header.stamp)
                self._try_cycle()
                if self._pending is not None:
                    self._wait_timer.reset()  # from now: run it after reference_wait without it
        elif time.monotonic() > self._poll_deadline:
            self._poll_timer.cancel()  # a sensor is silent: the period is not computed
            t = self._sensors['joint_states'].header.stamp
            late = [topic for topic in self._sensor_topics if topic not in self._sensors
                    or self._sensors[topic].header.stamp != t]
            self.get_logger().warning(
                f'period t={stamp_seconds(t):.3f} s skipped: no {", ".join(late)} of that time '
                f'within {SENSOR_POLL_TIMEOUT} s of joint_states', throttle_duration_sec=1.0)
        elif self._poll_timer.is_canceled():
            self._poll_timer.reset()

    def _try_cycle(self, force: bool = False) -> None:
        """Run the pending period once its reference is in (or when told to stop waiting).

        Waiting for the reference of the same time puts the reference generator in the
        lockstep too: under load a lagging reference would otherwise be used shifted and padded.
        """
        if self._pending is None:
            return
        fresh = self._reference is not None and self._reference.t[0] >= self._pending - 1e-6
        if fresh or force:
            self._pending = None
            self._wait_timer.cancel()
            self._control_cycle()

    def _on_wait_timer(self) -> None:
        self._wait_timer.cancel()
        self._try_cycle(force=True)

    def _on_set_parameters(self, parameters) -> SetParametersResult:
        fixed = [p.name for p in parameters if p.name in READ_AT_START]
        if fixed:
            return SetParametersResult(successful=False,
                                       reason=f'{", ".join(fixed)} read at start only')
        return SetParametersResult(successful=True)

    def destroy_node(self) -> None:
        for reader in self._readers.values():
            reader.destroy()
        super().destroy_node()

    # --- control cycle ----------------------------------------------------------------------
    def _feedback(self) -> ControllerFeedback:
        sensors = self._sensors
        joints = sensors['joint_states']
        position = dict(zip(joints.name, joints.position))
        legs = [position[name] for name in self._leg_names]
        threshold = self.get_parameter('contact_force').value
        contacts = tuple(sensors[topic].wrench.force.z > threshold
                         for topic in ('left_foot_wrench', 'right_foot_wrench'))
        zmp = (sensors['zmp'].point.x, sensors['zmp'].point.y)
        if self._params.pelvis_source == PELVIS_GROUND_TRUTH:
            pose, twist = sensors['odom'].pose.pose, sensors['odom'].twist.twist
            q = pose.orientation
            # nav_msgs/Odometry gives the twist in the pelvis frame; the controller wants world
            velocity = quaternion_to_matrix(np.array([q.x, q.y, q.z, q.w])) @ np.array(
                [twist.linear.x, twist.linear.y, twist.linear.z])
            return ControllerFeedback(
                legs, (q.x, q.y, q.z, q.w), zmp, contacts,
                (pose.position.x, pose.position.y, pose.position.z), velocity)
        q = sensors['imu'].orientation
        return ControllerFeedback(legs, (q.x, q.y, q.z, q.w), zmp, contacts)

    def _window(self, t: float):
        """(window from t, status): the reference, or a standing one when it is stale."""
        stale = self.get_parameter('stale_timeout').value
        reference = self._reference
        if reference is not None:
            age = t - reference.t[0]
            dt = reference.t[1] - reference.t[0] if len(reference.t) > 1 else 0.02
            if -dt <= age <= stale:
                start = max(0, int(round(age / dt)))
                if start == 0:
                    return self._reference_start, None
                return window_from(reference, start, self._horizon), None
        if self._last_output is None:
            return None, 'waiting for a reference'
        feet = []
        for side, target in ((LEFT, self._last_output.left_foot_target),
                             (RIGHT, self._last_output.right_foot_target)):
            feet.append(Footstep(side, float(target[0]), float(target[1]), float(target[3])))
        why = 'no reference' if reference is None else \
            f'reference {t - reference.t[0]:.2f} s old (> {stale} s)'
        return standing_window(feet[0], feet[1], self._standing_params, t, self._horizon,
                               self._params.mpc.dt), why

    def _control_cycle(self) -> None:
        msg = self._sensors['joint_states']
        t = stamp_seconds(msg.header.stamp)
        try:
            feedback = self._feedback()
        except (KeyError, BipedMpcError, ValueError) as error:
            self.get_logger().error(f'sensor data rejected: {error}', throttle_duration_sec=2.0)
            return
        window, hold_reason = self._window(t)
        if window is None:
            self._publish_diagnostics(msg.header.stamp, None, ControllerDiagnostics.WAITING,
                                      hold_reason)
            return
        try:
            if not self._started:
                self._controller.reset(t, feedback)
                self._started = True
            output = self._controller.step(t, window, feedback)
        except BipedMpcError as error:
            self.get_logger().error(f'control cycle failed: {error}', throttle_duration_sec=2.0)
            return
        self._last_output = output
        command = JointState()
        command.header.stamp = msg.header.stamp
        command.name = self._leg_names
        command.position = np.asarray(output.joint_setpoints, dtype=float).tolist()
        command.velocity = np.asarray(output.joint_velocities, dtype=float).tolist()
        self._command_pub.publish(command)
        latency = time.monotonic() - self._joint_states_arrival
        self._soles_pub.publish(sole_poses_msg(output, msg.header.stamp))
        if hold_reason is not None:
            status, message = ControllerDiagnostics.HOLDING, f'holding a stance: {hold_reason}'
            self.get_logger().warning(message, throttle_duration_sec=2.0)
        elif output.status & STATUS_MPC_FALLBACK:
            status, message = ControllerDiagnostics.FALLBACK, 'QP failed: shifted previous plan'
        else:
            status, message = ControllerDiagnostics.OK, ''
        self._publish_diagnostics(msg.header.stamp, output, status, message, latency)

    def _publish_diagnostics(self, stamp, output, status: int, message: str,
                             latency: float = 0.0) -> None:
        diag = ControllerDiagnostics()
        diag.header.stamp = stamp
        diag.status = status
        diag.message = message
        diag.model = self._params.model
        diag.solver = self._params.mpc.backend
        diag.dt = self._params.mpc.dt
        if output is not None:
            diag.solve_time = float(output.solve_time)
            diag.cycle_latency = float(latency)
            cost = np.asarray(output.cost, dtype=float)
            diag.cost = float(np.nansum(cost)) if np.any(np.isfinite(cost)) else math.nan
            diag.state_x = np.asarray(output.state[0], dtype=float).tolist()
            diag.state_y = np.asarray(output.state[1], dtype=float).tolist()
            diag.zmp_measured_x, diag.zmp_measured_y = (float(v) for v in output.zmp_measured)
            diag.zmp_estimated_x, diag.zmp_estimated_y = (
                float(v) for v in output.zmp_estimated)
            diag.predicted_zmp_x = [float(output.zmp_predicted[0])]
            diag.predicted_zmp_y = [float(output.zmp_predicted[1])]
        self._diag_pub.publish(diag)


def main(args=None) -> None:
    run_node(MpcControllerNode, args)


if __name__ == '__main__':
    main()
