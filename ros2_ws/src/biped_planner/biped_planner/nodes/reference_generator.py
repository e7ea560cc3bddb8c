"""The reference generator node: footstep plan + walking state in, MPC references out.

Subscribes: footstep_plan (biped_msgs/FootstepPlan, transient local), walking_state
(biped_msgs/WalkingState: the walk's start time and phase), sole_poses (geometry_msgs/PoseArray
from the controller: where to stand before the first walk; odom until it arrives),
joint_commands (sensor_msgs/JointState from the controller, on sim time: see below).
Publishes: reference_trajectory (biped_msgs/ReferenceTrajectory) at the control rate, `horizon`
samples of `dt` from now: ZMP, hip, feet, masses, support polygon and landing bounds.

On sim time the controller waits for the reference of each period (lockstep). Once it has
answered period t (its joint command stamped t), the simulator steps to t + 1 / rate, so the
reference of that period is sent at once, while physics runs, instead of at its clock tick;
a tick whose reference has not gone out that way (no controller yet) still sends it.
"""
from biped_msgs.msg import FootstepPlan, ReferenceTrajectory, WalkingState
from geometry_msgs.msg import PoseArray
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.time import Time
from sensor_msgs.msg import JointState

from biped_planner.errors import BipedPlannerError
from biped_planner.footsteps import feet_beside
from biped_planner.node_support.dataclass_parameters import (declare_dataclass_parameters,
                                                             declare_node_parameters)
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.qos import LATCHED_IN
from biped_planner.node_support.reference_messages import reference_trajectory_msg
from biped_planner.nodes.conversions import (feet_from_sole_poses, footsteps_from_msgs,
                                             pose2d_from_pose)
from biped_planner.reference_params import ReferenceParams
from biped_planner.reference_session import ReferenceSession
from biped_planner.step_timing import StepTiming
from biped_planner.walking_state_machine import WALKING_PHASES


class ReferenceGeneratorNode(Node):
    """Thin adapter over biped_planner.reference_session.ReferenceSession."""

    def __init__(self, **kwargs) -> None:
        super().__init__('reference_generator', **kwargs)
        # Descriptions and ranges come from ReferenceParams' parameter() fields.
        params = declare_dataclass_parameters(self, ReferenceParams(), {})
        declare_node_parameters(self, {
            'horizon': (90, 'samples per reference (the MPC needs Np = 80)', (2, 10000)),
            'dt': (0.02, 'sample period of the references, the MPC Ts (s)', (0.001, 1.0)),
            'rate': (50.0, 'references per second without a controller to answer (Hz)',
                     (0.1, 1000.0)),
            'stance_width': (0.2, 'distance between the standing feet before a walk (m)',
                             (0.05, 1.0))})
        self._horizon = max(2, int(self.get_parameter('horizon').value))
        self._dt = float(self.get_parameter('dt').value)
        self._session = ReferenceSession(params)
        self._standing = None
        self._phase = None
        self._pub = self.create_publisher(ReferenceTrajectory, 'reference_trajectory', 10)
        self.create_subscription(FootstepPlan, 'footstep_plan', self._on_plan, LATCHED_IN)
        self.create_subscription(WalkingState, 'walking_state', self._on_state, 10)
        # Only needed until a walk's reference exists: then unsubscribed (each message costs a
        # wake-up of this process at every control period).
        self._odom_sub = self.create_subscription(Odometry, 'odom', self._on_odom, 10)
        self._soles_sub = self.create_subscription(PoseArray, 'sole_poses', self._on_soles, 10)
        self._soles_seen = False
        self._period_ns = int(round(1e9 / float(self.get_parameter('rate').value)))
        self._sent_ns = None  # stamp of the newest reference sent
        self.create_subscription(JointState, 'joint_commands', self._on_command, 10)
        self.create_timer(1.0 / float(self.get_parameter('rate').value), self._on_timer)
        self.get_logger().info(f'reference generator ready ({self._horizon} samples of '
                               f'{self._dt} s)')

    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _on_plan(self, msg: FootstepPlan) -> None:
        if msg.status != FootstepPlan.STATUS_OK:
            return
        try:
            timing = StepTiming(msg.single_support, msg.double_support)
            done = self._session.set_plan(msg.plan_id, footsteps_from_msgs(msg.footsteps),
                                          timing, self._now())
        except (BipedPlannerError, ValueError) as error:
            self.get_logger().error(f'plan {msg.plan_id} not used: {error}')
            return
        self.get_logger().info(f'plan {msg.plan_id} ({len(msg.footsteps)} footsteps): {done}')

    def _on_state(self, msg: WalkingState) -> None:
        if msg.phase in WALKING_PHASES:
            if self._session.start_walk(msg.walk_start_time) and self._phase not in \
                    WALKING_PHASES:
                self.get_logger().info(f'walk from t={msg.walk_start_time:.3f} on plan '
                                       f'{self._session.plan_id}')
        elif self._phase in WALKING_PHASES:
            self._session.end_walk()
        self._phase = msg.phase

    def _on_soles(self, msg: PoseArray) -> None:
        """Stand where the feet are: standing on feet placed around the pelvis instead would
        make the COM chase its own reference (the COM is not above the pelvis)."""
        if self._session.reference is not None:
            self._unsubscribe_standing_inputs()
            return
        try:
            self._standing = feet_from_sole_poses(msg)
            self._soles_seen = True
        except ValueError as error:
            self.get_logger().warning(f'sole_poses ignored: {error}', throttle_duration_sec=5.0)

    def _on_odom(self, msg: Odometry) -> None:
        if self._session.reference is not None or self._soles_seen:
            self._unsubscribe_standing_inputs()
            return
        try:
            self._standing = feet_beside(pose2d_from_pose(msg.pose.pose),
                                         self.get_parameter('stance_width').value)
        except BipedPlannerError:
            pass

    def _unsubscribe_standing_inputs(self) -> None:
        """odom is read until sole_poses arrive, both until a walk's reference exists (it is
        never dropped again)."""
        if self._odom_sub is not None:
            self.destroy_subscription(self._odom_sub)
            self._odom_sub = None
        if self._soles_sub is not None and self._session.reference is not None:
            self.destroy_subscription(self._soles_sub)
            self._soles_sub = None

    def _send(self, t_ns: int) -> None:
        """Publish the reference from t_ns (ns of the node's clock), if there is one."""
        window = self._session.window(t_ns * 1e-9, self._horizon, self._dt, self._standing)
        if window is not None:
            self._pub.publish(reference_trajectory_msg(window, self._session.plan_id, self._dt,
                                                       Time(nanoseconds=t_ns).to_msg()))
            self._sent_ns = t_ns

    def _on_command(self, msg: JointState) -> None:
        if not self.get_clock().ros_time_is_active:
            return
        stamp = msg.header.stamp
        t_ns = stamp.sec * 1_000_000_000 + stamp.nanosec + self._period_ns
        if self._sent_ns is None or t_ns > self._sent_ns:
            self._send(t_ns)

    def _on_timer(self) -> None:
        now_ns = self.get_clock().now().nanoseconds
        # sent ahead: this tick's reference or the next one's is out (farther ahead: the clock
        # went back, after a reset of the simulation)
        sent_ahead = self._sent_ns is not None and \
            now_ns - self._period_ns // 2 <= self._sent_ns <= now_ns + 2 * self._period_ns
        if not sent_ahead:
            self._send(now_ns)


def main(args=None) -> None:
    run_node(ReferenceGeneratorNode, args)


if __name__ == '__main__':
    main()
