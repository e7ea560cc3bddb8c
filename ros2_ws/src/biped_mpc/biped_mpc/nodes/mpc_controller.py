"""The MPC controller node: references and sensors in, leg joint setpoints out (IK inside).

Subscribes: reference_trajectory (biped_msgs/ReferenceTrajectory), joint_states
(sensor_msgs/JointState), imu (sensor_msgs/Imu), odom
(nav_msgs/Odometry: the pelvis pose when pelvis_source is ground_truth), zmp
(geometry_msgs/PointStamped, from the ankle F/T sensors), left_foot_wrench / right_foot_wrench
(geometry_msgs/WrenchStamped: foot contacts); one control cycle runs per sensor time, once
every one of these carries it.
Publishes: joint_commands (sensor_msgs/JointState: the 12 leg setpoints, stamped with the sensor
time they answer), controller_diagnostics (biped_msgs/ControllerDiagnostics), sole_poses
(geometry_msgs/PoseArray: [left, right] soles the controller stands on, or swings to).

Lockstep: a period is computed once its reference (stamped with the same sensor time) is in, or
after reference_wait of wall time without it.
Safety: when the references are older than stale_timeout (the planner or reference generator
died or lags), the controller holds a safe stance: both feet on the ground where they are and
the hip between them, reported as HOLDING. Malformed messages are logged and skipped.
"""
import dataclasses
import math
import time

from biped_msgs.msg import ControllerDiagnostics, ReferenceTrajectory
from geometry_msgs.msg import PointStamped, Pose, PoseArray, WrenchStamped
from nav_msgs.msg import Odometry
import numpy as np
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from sensor_msgs.msg import Imu, JointState

from biped_mpc.errors import BipedMpcError
from biped_mpc.linear_mpc import MpcParams
from biped_mpc.state_estimator import EstimatorParams
from biped_mpc.walking_controller import (COMAN_LIKE_MASSES, ControllerFeedback,
                                          PELVIS_GROUND_TRUTH, quaternion_matrix,
                                          STATUS_MPC_FALLBACK, WalkingController,
                                          WalkingControllerParams)
from biped_planner.footsteps import Footstep, LEFT, RIGHT
from biped_planner.nodes.conversions import window_from_reference_msg
from biped_planner.nodes.node_runner import run_node
from biped_planner.nodes.parameters import declare_dataclass_parameters
from biped_planner.standing_reference import standing_window
from biped_planner.walking_reference import ReferenceParams
from biped_sim.robot_description import coman_like


CONTROLLER_SPECS = {
    'model': ('three_mass (the paper) or lipm (the baseline)', None),
    'feedback': ('prediction (MPC\'s own prediction, pattern generator) or estimator (Kalman)',
                 None),
    'feedback_gain': ('blend of the Kalman estimate into the prediction', (0.0, 1.0)),
    'pelvis_source': ('ground_truth (odom) or imu_kinematics (IMU + latched stance feet)', None),
    'ik': ('analytic or pinocchio', None),
    'pelvis_height': ('pelvis frame above the stance soles (m)', (0.05, 5.0)),
    'com_offset': ('whole-body COM ahead/left of the pelvis (m)', None),
    'stance_leg_projection': ('stance leg mass state projected on its latched sole', None),
    'pelvis_velocity_gain': ('pelvis velocity servo gain', (0.0, 1.0)),
    'tilt_gain': ('posture feedback against measured roll and pitch', (0.0, 5.0)),
}


SENSOR_TOPICS = ('odom', 'imu', 'zmp', 'left_foot_wrench', 'right_foot_wrench', 'joint_states')


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
        pose.orientation.z, pose.orientation.w = math.sin(target[3] / 2), math.cos(target[3] / 2)
        msg.poses.append(pose)
    return msg


class MpcControllerNode(Node):
    """Thin adapter over biped_mpc.walking_controller.WalkingController."""

    def __init__(self, **kwargs) -> None:
        super().__init__('mpc_controller', **kwargs)
        self._robot = coman_like()
        self.declare_parameter('solver', 'daqp')
        for name, default in (('contact_force', 15.0), ('stale_timeout', 0.3),
                              ('reference_wait', 0.1),
                              ('foot_length', 0.2), ('foot_width', 0.1)):
            self.declare_parameter(name, default)
        get = lambda name: self.get_parameter(name).value  # noqa: E731
        self._params = declare_dataclass_parameters(
            self, WalkingControllerParams(robot=self._robot), CONTROLLER_SPECS,
            fixed={'robot': self._robot, 'masses': COMAN_LIKE_MASSES,
                   'mpc': MpcParams(backend=get('solver')), 'estimator': EstimatorParams()})
        self._controller = WalkingController(self._params)
        self._horizon = self._params.mpc.n_predict + 1
        self._standing_params = ReferenceParams(foot_length=float(get('foot_length')),
                                                foot_width=float(get('foot_width')))
        self._leg_names = list(self._robot.leg_joint_names)
        self._reference = None
        self._sensors = {}
        self._last_cycle = None
        self._pending = None  # (sensor stamp, wall time) of a complete period not yet computed
        self._last_output = None
        self._started = False
        self._command_pub = self.create_publisher(JointState, 'joint_commands', 10)
        self._diag_pub = self.create_publisher(ControllerDiagnostics, 'controller_diagnostics',
                                               10)
        self._soles_pub = self.create_publisher(PoseArray, 'sole_poses', 10)
        self.create_subscription(ReferenceTrajectory, 'reference_trajectory', self._on_reference,
                                 10)
        # One cycle per sensor time, once every input of that time is in: topics have no
        # ordering guarantee between them, and mixing two periods' data destabilises the loop.
        for msg_type, topic in ((Odometry, 'odom'), (Imu, 'imu'), (PointStamped, 'zmp'),
                                (WrenchStamped, 'left_foot_wrench'),
                                (WrenchStamped, 'right_foot_wrench'),
                                (JointState, 'joint_states')):
            self.create_subscription(msg_type, topic,
                                     lambda msg, topic=topic: self._on_sensor(topic, msg), 10)
        # wall clock: with sim time, a ROS timer would wait for the very clock we hold up
        self.create_timer(0.005, self._on_wait_timer,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.get_logger().info(f'{get("model")} MPC ready ({get("solver")}, Np '
                               f'{self._params.mpc.n_predict})')

    # --- inputs -----------------------------------------------------------------------------
    def _on_reference(self, msg: ReferenceTrajectory) -> None:
        try:
            self._reference = window_from_reference_msg(msg)
        except ValueError as error:
            self.get_logger().error(f'reference rejected: {error}', throttle_duration_sec=2.0)
            return
        self._try_cycle()

    def _on_sensor(self, topic: str, msg) -> None:
        self._sensors[topic] = msg
        stamps = {(m.header.stamp.sec, m.header.stamp.nanosec)
                  for m in self._sensors.values()}
        if len(self._sensors) == len(SENSOR_TOPICS) and len(stamps) == 1 and \
                stamps != {self._last_cycle}:
            self._last_cycle = stamps.pop()
            self._pending = (stamp_seconds(msg.header.stamp), time.monotonic())
            self._try_cycle()

    def _try_cycle(self, force: bool = False) -> None:
        """Run the pending period once its reference is in (or when told to stop waiting).

        Waiting for the reference of the same time puts the reference generator in the
        lockstep too: under load a lagging reference would otherwise be used shifted and padded.
        """
        if self._pending is None:
            return
        t = self._pending[0]
        fresh = self._reference is not None and self._reference.t[0] >= t - 1e-6
        if fresh or force:
            self._pending = None
            self._control_cycle()

    def _on_wait_timer(self) -> None:
        if self._pending is not None and \
                time.monotonic() - self._pending[1] > self.get_parameter('reference_wait').value:
            self._try_cycle(force=True)

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
            velocity = quaternion_matrix(np.array([q.x, q.y, q.z, q.w])) @ np.array(
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
        self._soles_pub.publish(sole_poses_msg(output, msg.header.stamp))
        if hold_reason is not None:
            status, message = ControllerDiagnostics.HOLDING, f'holding a stance: {hold_reason}'
            self.get_logger().warning(message, throttle_duration_sec=2.0)
        elif output.status & STATUS_MPC_FALLBACK:
            status, message = ControllerDiagnostics.FALLBACK, 'QP failed: shifted previous plan'
        else:
            status, message = ControllerDiagnostics.OK, ''
        self._publish_diagnostics(msg.header.stamp, output, status, message)

    def _publish_diagnostics(self, stamp, output, status: int, message: str) -> None:
        diag = ControllerDiagnostics()
        diag.header.stamp = stamp
        diag.status = status
        diag.message = message
        diag.model = self._params.model
        diag.solver = self._params.mpc.backend
        diag.dt = self._params.mpc.dt
        if output is not None:
            diag.solve_time = float(output.solve_time)
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
