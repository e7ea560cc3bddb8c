"""The walking state machine node: walk commands and plans in, walking state out.

Subscribes: walk_command (biped_msgs/WalkCommand), footstep_plan (biped_msgs/FootstepPlan,
transient local), odom (nav_msgs/Odometry, for fall detection), cmd_vel (geometry_msgs/Twist)
and goal_pose (geometry_msgs/PoseStamped), which start a walk from Idle.
Publishes: walking_state (biped_msgs/WalkingState) on every transition and at publish_rate,
walk_command_status (biped_msgs/CommandStatus) for every command received.
"""
import math

from biped_msgs.msg import CommandStatus, FootstepPlan, WalkCommand as WalkCommandMsg, WalkingState
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from rclpy.node import Node

from biped_planner.errors import CommandError
from biped_planner.fall_detector import detect_fall, FallDetectorParams
from biped_planner.node_support.dataclass_parameters import (declare_dataclass_parameters,
                                                             declare_node_parameters)
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.qos import LATCHED_IN
from biped_planner.nodes.conversions import (command_status_msg, walk_command_from_msg,
                                             walking_state_msg)
from biped_planner.sides import SIDES
from biped_planner.walk_command import CommandKind, CommandLimits
from biped_planner.walking_state_machine import (Phase, StateMachineParams, Support,
                                                 WALKING_PHASES, WalkingStateMachine)


class StateMachineNode(Node):
    """Thin adapter over biped_planner.walking_state_machine.WalkingStateMachine."""

    def __init__(self, **kwargs) -> None:
        super().__init__('state_machine', **kwargs)
        # Descriptions and ranges come from the dataclasses' parameter() fields.
        params = declare_dataclass_parameters(self, StateMachineParams(), {},
                                              on_change=self._on_timing_change)
        self._fall_params = declare_dataclass_parameters(
            self, FallDetectorParams(), {}, prefix='fall.',
            on_change=lambda p: setattr(self, '_fall_params', p))
        self._limits = declare_dataclass_parameters(
            self, CommandLimits(), {}, prefix='limits.',
            on_change=lambda p: setattr(self, '_limits', p))
        declare_node_parameters(self, {
            'publish_rate': (50.0, 'walking_state messages per second besides transitions (Hz)',
                             (0.1, 1000.0)),
            'update_rate': (200.0, 'timer checking phase ends (Hz)', (1.0, 10000.0)),
            'fall_detection': (True, 'detect and report falls', None),
            # A teleop plan is republished every step; silence this long: the planner is gone.
            'plan_timeout': (2.0, 'a teleop plan silent this long ends the walk (s)',
                             (0.1, 60.0))})

        self._machine = WalkingStateMachine(params)
        self._plan_id = 0
        self._continuous_plan = None  # (arrival time, steps in it) of a teleop plan
        self._stale = False
        # A start waits for its plan when a planner runs: Initialize shifts the COM to the first
        # support foot, which the plan names, and the walk's references start with the plan.
        self._start_pending = None  # clock time of the start request
        self._unwalked_plan = None  # plan_id of an OK plan no walk has started on yet
        self._state_pub = self.create_publisher(WalkingState, 'walking_state', 10)
        self._status_pub = self.create_publisher(CommandStatus, 'walk_command_status', 10)
        self.create_subscription(WalkCommandMsg, 'walk_command', self._on_command, 10)
        self.create_subscription(FootstepPlan, 'footstep_plan', self._on_plan, LATCHED_IN)
        self.create_subscription(Odometry, 'odom', self._on_odometry, 10)
        self.create_subscription(Twist, 'cmd_vel', self._on_cmd_vel, 10)
        self.create_subscription(PoseStamped, 'goal_pose', self._on_goal, 10)
        update_period = 1.0 / max(1.0, self.get_parameter('update_rate').value)
        self._publish_period = 1.0 / max(0.1, self.get_parameter('publish_rate').value)
        self._last_publish = None
        self.create_timer(update_period, self._on_update)
        self.get_logger().info('walking state machine ready (Idle)')

    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _on_timing_change(self, params: StateMachineParams) -> None:
        self._machine.set_timing(params.single_support, params.double_support)

    def _publish(self, status, now: float) -> None:
        self._state_pub.publish(walking_state_msg(
            status, now, self.get_clock().now().to_msg(), self._plan_id, inputs_stale=self._stale))
        self._last_publish = now

    def _publish_transitions(self, transitions, now: float) -> None:
        for status in transitions:
            self.get_logger().info(
                f'{status.phase.name} (step {status.step_index}, support '
                f'{status.support.name}): {status.reason}')
            self._publish(status, now)

    def _answer(self, command: int, error_code: int, error_msg: str = '') -> None:
        if error_code != CommandStatus.OK:
            self.get_logger().warning(f'walk command {command} rejected: {error_msg}')
        self._status_pub.publish(command_status_msg(
            self.get_name(), command, error_code, error_msg, self.get_clock().now().to_msg()))

    def _on_command(self, msg: WalkCommandMsg) -> None:
        now = self._now()
        try:
            command = walk_command_from_msg(msg, self._limits)
        except CommandError as error:
            unknown = msg.command not in {k.value for k in CommandKind}
            self._answer(msg.command, CommandStatus.UNKNOWN_COMMAND if unknown
                         else CommandStatus.INVALID_VALUE, str(error))
            return
        try:
            transitions = self._machine.update(now)
            if command.step_time > 0.0:
                self._machine.set_step_time(command.step_time)
            if command.kind == CommandKind.STOP:
                transitions += self._machine.request_stop(now)
            elif command.kind == CommandKind.RESET:
                transitions += self._machine.reset(now)
            else:
                if command.kind == CommandKind.START and self._unwalked_plan is None:
                    # START walks in place (or along a plan that arrives): no step limit.
                    self._machine.set_plan(None)
                transitions += self._request_start(now)
        except CommandError as error:
            self._answer(msg.command, CommandStatus.NOT_ALLOWED, str(error))
            return
        self._publish_transitions(transitions, now)
        self._answer(msg.command, CommandStatus.OK)

    def _on_plan(self, msg: FootstepPlan) -> None:
        now = self._now()
        transitions = self._machine.update(now)
        if msg.status != FootstepPlan.STATUS_OK:
            if self._start_pending is not None:
                self.get_logger().warning(f'plan failed ({msg.error_code}): {msg.error_msg}; '
                                          'not starting')
                self._start_pending = None
            # Only a walk still waiting for its plan stops; a running walk keeps its plan.
            if self._machine.status.phase == Phase.INITIALIZE:
                self.get_logger().warning(f'plan failed ({msg.error_code}): {msg.error_msg}; '
                                          'back to Idle')
                transitions += self._machine.request_stop(now)
        else:
            if msg.plan_id != self._plan_id and self._machine.status.phase == Phase.IDLE:
                self._unwalked_plan = msg.plan_id
            self._plan_id = msg.plan_id
            steps = None if msg.continuous else max(0, len(msg.footsteps) - 2)
            self._continuous_plan = (now, max(0, len(msg.footsteps) - 2)) if msg.continuous \
                else None
            self._stale = False
            first = Support(msg.footsteps[0].side) if msg.footsteps and \
                msg.footsteps[0].side in SIDES else None
            try:
                self._machine.set_plan(steps, first, planned=True)
                if msg.single_support > 0.0 and msg.double_support > 0.0:
                    self._machine.set_timing(msg.single_support, msg.double_support)
            except CommandError as error:
                self.get_logger().warning(f'plan {msg.plan_id} ignored: {error}')
            if self._start_pending is not None:
                self._start_pending = None
                transitions += self._start_walk(now)
        self._publish_transitions(transitions, now)

    def _on_goal(self, msg: PoseStamped) -> None:
        """A goal pose (the RViz convention) starts a walk; the planner plans it, and a failed
        plan sends the walk back to Idle during Initialize."""
        p = msg.pose.position
        if all(math.isfinite(v) for v in (p.x, p.y)):
            self._start_from_idle()

    def _on_cmd_vel(self, msg: Twist) -> None:
        """Teleop: a velocity command starts a walk from Idle (the planner makes the steps)."""
        if all(math.isfinite(v) for v in (msg.linear.x, msg.linear.y, msg.angular.z)):
            self._start_from_idle()

    def _start_from_idle(self) -> None:
        if self._machine.status.phase == Phase.IDLE:
            now = self._now()
            self._publish_transitions(self._request_start(now), now)

    def _request_start(self, now: float):
        """Start now when there is no planner or its plan is in; else when the plan arrives."""
        planner_runs = self.count_publishers('footstep_plan') > 0
        if self._machine.status.phase != Phase.IDLE or not planner_runs or \
                self._unwalked_plan is not None:
            self._start_pending = None
            return self._start_walk(now)
        if self._start_pending is None:
            self.get_logger().info('start requested: waiting for the footstep plan')
        self._start_pending = now
        return []

    def _start_walk(self, now: float):
        transitions = self._machine.request_start(now)
        if transitions:
            self._unwalked_plan = None
        return transitions

    def _on_odometry(self, msg: Odometry) -> None:
        if not self.get_parameter('fall_detection').value:
            return
        q = msg.pose.pose.orientation
        reason = detect_fall(msg.pose.pose.position.z, (q.x, q.y, q.z, q.w), self._fall_params)
        if reason is not None:
            now = self._now()
            self._publish_transitions(self._machine.report_fall(now, reason), now)

    def _check_plan_alive(self, now: float) -> None:
        """End a teleop walk where its last plan ends when the planner falls silent."""
        if self._continuous_plan is None or self.phase not in WALKING_PHASES:
            return
        arrived, steps = self._continuous_plan
        if now - arrived > self.get_parameter('plan_timeout').value:
            self.get_logger().error(f'no footstep plan for {now - arrived:.1f} s: the planner is '
                                    f'silent; ending the walk after step {steps}')
            self._machine.set_plan(steps, planned=True)
            self._continuous_plan = None
            self._stale = True

    def _on_update(self) -> None:
        now = self._now()
        self._check_plan_alive(now)
        transitions = self._machine.update(now)
        self._publish_transitions(transitions, now)
        if not transitions and (self._last_publish is None or now < self._last_publish or
                                now - self._last_publish >= self._publish_period):
            self._publish(self._machine.status, now)

    @property
    def phase(self) -> Phase:
        return self._machine.status.phase


def main(args=None) -> None:
    run_node(StateMachineNode, args)


if __name__ == '__main__':
    main()
