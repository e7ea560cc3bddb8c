"""The walking state machine node: the one entry point of user intent, and the walking state.

Subscribes (user intent: no other node subscribes to these): walk_command
(biped_msgs/WalkCommand), goal_pose (geometry_msgs/PoseStamped in the map frame) and cmd_vel
(geometry_msgs/Twist). Each message is checked and answered on walk_command_status
(biped_msgs/CommandStatus; a goal_pose is answered as GOTO, a cmd_vel as OMNI); an accepted one
is forwarded to the footstep planner over the service plan_walk (biped_msgs/PlanWalk) with a
fresh request id, and a walk starts only on the footstep_plan whose request_id is that
request's (biped_planner.plan_requests); a request waits up to planner_timeout for plan_walk to
be discovered. With use_planner false (a graph without a planner), START, OMNI and cmd_vel walk
in place. cmd_vel follows the teleop convention (biped_planner.teleop_gate): a repeated velocity
keeps the walk going, a walk driven by cmd_vel stops (finishing its step) when cmd_vel has been
silent for cmd_vel_timeout, and a cmd_vel sent while it stops starts a new walk once idle.
Also subscribes: footstep_plan (transient local), odom (nav_msgs/Odometry: fall detection),
step_adjustment (biped_msgs/StepAdjustment: the reference generator's step adjuster moved
the touchdown of the step under way, which the single support follows),
reference_trajectory and controller_diagnostics (only their arrival is kept): an input that
stops is named in walking_state.stale_inputs (biped_planner.input_watch); losing the references
or the controller ends a walk.
Service: reset (std_srvs/Trigger): from Idle or Fallen, resets the simulator (its service
simulator/reset, when one exists) and starts a new epoch in Idle; refused while walking.
Publishes: walking_state (biped_msgs/WalkingState) on every transition, when the stale inputs
change and at publish_rate; walk_command_status.
"""
from functools import partial
import time

from biped_msgs.msg import CommandStatus, ControllerDiagnostics, FootstepPlan, \
    ReferenceTrajectory, StepAdjustment, WalkCommand as WalkCommandMsg, WalkingState
from biped_msgs.srv import PlanWalk
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from std_srvs.srv import Trigger

from biped_planner.errors import BipedPlannerError, CommandError
from biped_planner.fall_detector import detect_fall, FallDetectorParams
from biped_planner.input_watch import InputWatch
from biped_planner.node_support.dataclass_parameters import (
    declare_dataclass_parameters, declare_live_parameters, declare_node_parameters)
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.qos import LATCHED_IN
from biped_planner.node_support.rejection_log import RejectionLog
from biped_planner.node_support.side_call import SideCall
from biped_planner.node_support.stamps import seconds_of, time_msg_of
from biped_planner.nodes.conversions import (command_status_msg, goal_command_from_msg,
                                             plan_walk_request, received_plan, twist_of,
                                             velocity_from_twist, walk_command_from_msg,
                                             walking_state_msg)
from biped_planner.nodes.state_machine_parameters import NODE_PARAMETERS, READ_ONLY
from biped_planner.plan_requests import (PlanRequests, PlanUse, RequestKind,
                                         walk_request_refusal)
from biped_planner.pose_checks import PoseBounds, PoseStream
from biped_planner.teleop_gate import TeleopAction, TeleopGate
from biped_planner.walk_command import CommandKind, CommandLimits, start_time_of
from biped_planner.walking_state_machine import (EARLY_REASON, MOVED_REASON, Phase,
                                                 StateMachineParams, Support, WALKING_PHASES,
                                                 WalkingStateMachine)

PLAN = 'footstep_plan'
MAX_ADJUSTMENT_LEAD = 5.0  # s: an adjusted touchdown farther from the clock is not a step's
STREAMS = ('odom', 'reference_trajectory', 'controller_diagnostics')
WALK_PRODUCERS = ('reference_trajectory', 'controller_diagnostics')  # their loss ends a walk
KNOWN_COMMANDS = {int(kind) for kind in CommandKind}
PLANNER_RESEND = 1.0  # s of wall time: an unanswered plan_walk request is sent again (a request
#                       sent just after discovery can be lost: the server's side had not matched)
RESET_SETTLE = 0.5  # s: fallen odometry this soon after a reset predates it
# planner errors that say the request itself was wrong (the rest: not possible now)
INVALID_REQUEST_ERRORS = {FootstepPlan.ERROR_INVALID_COMMAND, FootstepPlan.ERROR_UNKNOWN_FRAME,
                          FootstepPlan.ERROR_GOAL_OUTSIDE_MAP, FootstepPlan.ERROR_GOAL_OCCUPIED}


class StateMachineNode(Node):
    """Thin adapter over biped_planner.walking_state_machine.WalkingStateMachine."""

    def __init__(self, **kwargs) -> None:
        super().__init__('state_machine', **kwargs)
        # Descriptions and ranges come from the dataclasses' parameter() fields.
        params = declare_dataclass_parameters(self, StateMachineParams(), {},
                                              on_change=self._on_timing_change)
        declare_live_parameters(self, FallDetectorParams(), 'fall.', '_fall_params')
        declare_live_parameters(self, CommandLimits(), 'limits.', '_limits')
        declare_live_parameters(self, PoseBounds(), 'pose_bounds.', '_bounds')
        declare_node_parameters(self, NODE_PARAMETERS, read_only=READ_ONLY)
        self._use_planner = bool(self.get_parameter('use_planner').value)
        self._reject = RejectionLog(self.get_logger().warning)
        self._map_frame = self.get_parameter('map_frame').value

        self._machine = WalkingStateMachine(params)
        self._plan = None     # biped_planner.plan_requests.ReceivedPlan the walk follows
        self._plan_id = 0     # the plan of the current or last walk (0: none)
        self._plan_step = 0   # the step being taken when the walk's plan last arrived
        self._requests = PlanRequests(self.get_parameter('planner_timeout').value)
        # request id -> (content, wall time sent or None until plan_walk is discovered), until
        # answered
        self._outgoing = {}
        sim_time = self.get_parameter('use_sim_time').value
        self._watch = InputWatch(STREAMS, (PLAN,), self.get_parameter('input_timeout').value,
                                 '/clock' if sim_time else None, ('odom',))
        self._stale = ()
        # (sim time, WalkCommand, told the planner) of a STOP with a start_time
        self._scheduled_stop = None
        # the time of the STOP stated ahead that the planner ends this walk at (walking_state's
        # stop_time: the reference generator waits for the plan it makes then), 0 when none
        self._stated_stop_time = 0.0
        self._teleop = TeleopGate()  # the walk cmd_vel drives, and its timeout
        self._odometry = PoseStream('odom', self.get_parameter('odom_frame').value)
        self._state_pub = self.create_publisher(WalkingState, 'walking_state', 10)
        self._status_pub = self.create_publisher(CommandStatus, 'walk_command_status', 10)
        self.create_subscription(WalkCommandMsg, 'walk_command', self._on_command, 10)
        self.create_subscription(PoseStamped, 'goal_pose', self._on_goal, 10)
        self.create_subscription(Twist, 'cmd_vel', self._on_cmd_vel, 10)
        self.create_subscription(FootstepPlan, PLAN, self._on_plan, LATCHED_IN)
        self.create_subscription(Odometry, 'odom', self._on_odometry, 10)
        self.create_subscription(StepAdjustment, 'step_adjustment', self._on_adjustment, 10)
        for msg_type, name in ((ReferenceTrajectory, 'reference_trajectory'),
                               (ControllerDiagnostics, 'controller_diagnostics')):
            self.create_subscription(msg_type, name, partial(self._on_stream, name), 10,
                                     raw=True)
        self._planner = self.create_client(PlanWalk, 'plan_walk')
        self._simulator_reset = SideCall(self, Trigger, 'simulator/reset')
        self.create_service(Trigger, 'reset', self._on_reset)
        update_period = 1.0 / max(1.0, self.get_parameter('update_rate').value)
        self._publish_period = 1.0 / max(0.1, self.get_parameter('publish_rate').value)
        self._last_publish = None
        self.create_timer(update_period, self._on_update)
        # Wall time: timeouts must fire when the simulated clock stands still.
        self.create_timer(0.05, self._on_watch, clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.get_logger().info('walking state machine ready (Idle)')

    def destroy_node(self) -> None:
        self._simulator_reset.destroy()
        super().destroy_node()

    @property
    def phase(self) -> Phase:
        return self._machine.status.phase

    def planner_available(self) -> bool:
        """Whether the footstep planner runs now: its service is known, or the planner is
        (discovery can show its node and plan before its service)."""
        return self._use_planner and (
            self._planner.service_is_ready() or self.count_publishers(PLAN) > 0 or
            'footstep_planner' in self.get_node_names())

    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _walking(self) -> bool:
        return self.phase in WALKING_PHASES

    def _on_timing_change(self, params: StateMachineParams) -> None:
        self._machine.set_timing(params.single_support, params.double_support)

    # --- publishing -------------------------------------------------------------------------
    def _publish(self, status, now: float) -> None:
        # stamped with the `now` its time_in_phase is counted from, not a second reading of
        # the clock (which can move meanwhile): stamp - time_in_phase is the phase's start,
        # which the planner's extensions are timed from
        self._state_pub.publish(walking_state_msg(status, now, time_msg_of(now), self._plan_id,
                                                  self._stale, self._stated_stop_time))
        self._last_publish = now

    def _publish_transitions(self, transitions, now: float) -> None:
        for status in transitions:
            self.get_logger().info(
                f'{status.phase.name} (step {status.step_index}, support '
                f'{status.support.name}): {status.reason}')
            if status.phase == Phase.SINGLE_SUPPORT and self._plan is not None and \
                    self._plan.continuous and status.step_index > self._plan_step:
                self._watch.due(PLAN, now, time.monotonic())  # the planner extends every step
            elif status.phase in (Phase.IDLE, Phase.FALLEN):
                self._stated_stop_time = 0.0
                self._watch.withdraw(PLAN)
                self._teleop.ended(drop_deferred=status.phase == Phase.FALLEN)
                self._plan = None
            self._publish(status, now)
        if transitions and transitions[-1].phase == Phase.IDLE and self._teleop.deferred:
            velocity = self._teleop.restart(now, time.monotonic(),
                                            self.get_parameter('cmd_vel_timeout').value)
            if velocity is None:
                self._answer(CommandKind.OMNI, CommandStatus.NOT_ALLOWED, 'cmd_vel fell '
                             'silent before the last walk had stopped: no new walk')
            else:  # the operator kept sending while the last walk stopped
                self._request_walk(now, CommandKind.OMNI, RequestKind.VELOCITY,
                                   velocity=twist_of(velocity))

    def _answer(self, command: int, error_code: int, error_msg: str = '') -> None:
        if error_code != CommandStatus.OK:
            self._reject(f'command {command}', error_msg)
        self._status_pub.publish(command_status_msg(
            self.get_name(), command, error_code, error_msg, self.get_clock().now().to_msg()))

    # --- user intent ------------------------------------------------------------------------
    def _on_command(self, msg: WalkCommandMsg) -> None:
        now = self._now()
        try:
            command = walk_command_from_msg(msg, self._limits, self._map_frame)
        except CommandError as error:
            self._answer(msg.command, CommandStatus.INVALID_VALUE if msg.command in
                         KNOWN_COMMANDS else CommandStatus.UNKNOWN_COMMAND, str(error))
            return
        self._publish_transitions(self._machine.update(now), now)
        kind = command.kind
        if kind == CommandKind.RESET:
            ok, text = self._reset_all()
            self._answer(kind, CommandStatus.OK if ok else CommandStatus.NOT_ALLOWED,
                         '' if ok else text)
        elif kind == CommandKind.STOP:
            try:
                stop_time = start_time_of(msg.start_time, now)
            except CommandError as error:
                self._answer(kind, CommandStatus.INVALID_VALUE, str(error))
                return
            self._drop_scheduled_stop('a new STOP came')
            if stop_time > now and self._walking():
                # a scripted trial's stop: applied at its stated time, as if it arrived then;
                # a planner ending the walk gets it now, to answer it at the step under way then
                planned = self._plan is not None and self.planner_available()
                self._scheduled_stop = (stop_time, msg, planned)
                if planned:
                    self._ask_planner_to_stop(msg)
                    self._stated_stop_time = stop_time
                    self._publish(self._machine.status, now)  # with the planner's request
                self.get_logger().info(f'STOP scheduled for t={stop_time:.3f} s')
            else:
                self._publish_transitions(self._stop(now, 'stop requested', msg), now)
            self._answer(kind, CommandStatus.OK)
        else:
            try:
                start_time = start_time_of(msg.start_time, now)
                if command.step_time > 0.0:
                    self._machine.set_step_time(command.step_time)
            except CommandError as error:
                self._answer(kind, CommandStatus.INVALID_VALUE, str(error))
                return
            if self._request_walk(now, kind, RequestKind.COMMAND, start_time=start_time,
                                  command=msg):
                self._drop_scheduled_stop(f'a {kind.name} command came')

    def _on_goal(self, msg: PoseStamped) -> None:
        """A goal pose (the RViz convention) starts a walk to it, once the planner's plan for
        it arrives."""
        try:
            goal_command_from_msg(msg, self._map_frame, self._limits)
        except CommandError as error:
            self._answer(CommandKind.GOTO, CommandStatus.INVALID_VALUE, f'goal_pose: {error}')
            return
        self._request_walk(self._now(), CommandKind.GOTO, RequestKind.GOAL, goal=msg)

    def _on_cmd_vel(self, msg: Twist) -> None:
        """Teleop: a new velocity starts or steers a walk (the planner makes the steps); a
        repeated one keeps it going (biped_planner.teleop_gate)."""
        try:
            velocity_from_twist(msg, self._limits)
        except CommandError as error:
            self._answer(CommandKind.OMNI, CommandStatus.INVALID_VALUE, str(error))
            return
        now = self._now()
        self._publish_transitions(self._machine.update(now), now)
        action = self._teleop.received(
            (msg.linear.x, msg.linear.y, msg.angular.z), now, time.monotonic(),
            self._walking(), self._machine.status.stop_requested,
            self._requests.start_pending)
        if action == TeleopAction.FORWARD:
            self._request_walk(now, CommandKind.OMNI, RequestKind.VELOCITY, velocity=msg)
        elif action == TeleopAction.DEFER:  # answered when the walk has stopped
            self.get_logger().info('cmd_vel while the walk stops: a new walk follows it once '
                                   'idle', throttle_duration_sec=2.0)

    def _request_walk(self, now: float, user_command: int, kind: RequestKind,
                      start_time: float = 0.0, **content) -> bool:
        """Start or steer a walk: through the planner (once discovered, within
        planner_timeout: whether it is discovered yet at startup must not change the walk), or
        in place without one (use_planner false). A walk that starts begins at start_time, or
        when its plan arrives if that is later.

        :return: whether the request went on (False: refused here, and answered)
        """
        walking = self._walking()
        planner = self._use_planner
        refusal = walk_request_refusal(
            self.phase, planner, user_command == CommandKind.GOTO,
            self._plan is not None and self._plan.continuous,
            self._machine.status.stop_requested)
        if refusal is not None:
            self._answer(user_command, CommandStatus.NOT_ALLOWED, refusal)
            return False
        if not planner:
            if not walking:
                self._machine.set_plan(None)  # in place, until stopped
                self._plan_id, self._plan = 0, None
            self._publish_transitions(self._machine.request_start(max(now, start_time)), now)
            self._teleop.driving = kind == RequestKind.VELOCITY
            self._answer(user_command, CommandStatus.OK)
            return True
        request, superseded = self._requests.new(kind, user_command, not walking, True,
                                                 time.monotonic(), start_time)
        if superseded is not None and superseded.answer_owed:
            self._answer(superseded.command, CommandStatus.NOT_ALLOWED,
                         f'superseded by request {request.request_id} before its plan arrived')
        self._call_planner(request, **content)
        return True

    def _call_planner(self, request, **content) -> None:
        """Send now, or once the service is discovered (within planner_timeout)."""
        if not self._planner.service_is_ready():
            self._outgoing[request.request_id] = (content, None)
            return
        future = self._planner.call_async(plan_walk_request(request.request_id, request.kind,
                                                            **content))
        self._outgoing[request.request_id] = (content, time.monotonic())
        future.add_done_callback(partial(self._on_planner_answer, request.request_id))

    def _on_planner_answer(self, request_id: int, future) -> None:
        self._outgoing.pop(request_id, None)
        now = self._now()
        result = future.result() if future.done() and future.exception() is None else None
        if result is None or not result.accepted:
            request = self._requests.refused(request_id)
            if request is not None:
                code = result.error_code if result is not None else None
                text = result.error_msg if result is not None else 'the call failed'
                self._planner_refused(request, code, text, now)
            return
        request = self._requests.accepted(request_id, result.plan_id)
        if request is None or request.starts_walk:
            return  # answered by its plan already, or still waiting for it
        if request.kind in (RequestKind.COMMAND, RequestKind.VELOCITY) and \
                request.command != CommandKind.STOP:
            self._teleop.driving = request.kind == RequestKind.VELOCITY
        if request.answer_owed:
            self._answer(request.command, CommandStatus.OK)

    def _planner_refused(self, request, code, text: str, now: float) -> None:
        """A request the planner refused, failed or did not answer in time."""
        if request.kind == RequestKind.CANCEL or request.command == CommandKind.STOP:
            self.get_logger().error(f'the planner did not end its plan ({text}): ending the '
                                    'walk after the current step')
            self._publish_transitions(self._machine.request_stop(
                now, 'stop without the planner', unplanned=True), now)
        if request.answer_owed:
            status = CommandStatus.INVALID_VALUE if code in INVALID_REQUEST_ERRORS else \
                CommandStatus.PLANNING_FAILED
            self._answer(request.command, status, f'planner (request {request.request_id}): '
                         f'{text}' + (f' (FootstepPlan error {code})' if code else ''))

    def _stop(self, now: float, reason: str, command: WalkCommandMsg = None,
              planner_told: bool = False):
        """End the walk after the current step and a closing one (the planner's stop plan);
        a walk waiting for its plan does not start.

        :param planner_told: the planner has this stop already (a STOP with a start_time)

        :return: the transitions
        """
        cancelled = self._requests.cancel_start()
        if cancelled is not None and cancelled.answer_owed:
            self._answer(cancelled.command, CommandStatus.NOT_ALLOWED, f'cancelled: {reason}')
        self._teleop.driving = False
        walking = self._walking()
        planner = self.planner_available()
        before = self._machine.status
        transitions = self._machine.request_stop(
            now, reason, unplanned=walking and self._plan is not None and not planner)
        if not transitions and self._machine.status != before:
            self._publish(self._machine.status, now)  # the stop and its reason are news now
        if planner and (walking or cancelled is not None) and not planner_told:
            self._ask_planner_to_stop(command)
        return transitions

    def _ask_planner_to_stop(self, command: WalkCommandMsg = None) -> None:
        """A STOP for the planner: the user's command (its start_time with it), or a cancel."""
        request, _ = self._requests.new(
            RequestKind.COMMAND if command is not None else RequestKind.CANCEL,
            CommandKind.STOP, False, False, time.monotonic())
        self._call_planner(request, command=command)

    def _drop_scheduled_stop(self, why: str) -> None:
        if self._scheduled_stop is not None:
            self.get_logger().info(f'scheduled STOP for t={self._scheduled_stop[0]:.3f} s '
                                   f'dropped: {why}')
            self._scheduled_stop = None
            self._stated_stop_time = 0.0

    # --- plans ------------------------------------------------------------------------------
    def _on_plan(self, msg: FootstepPlan) -> None:
        now = self._now()
        try:
            plan = received_plan(msg)
        except BipedPlannerError as error:
            self._reject(PLAN, error)
            return
        self._publish_transitions(self._machine.update(now), now)
        use, request = self._requests.use_of_plan(plan.request_id, plan.plan_id, plan.ok,
                                                  self._walking(), self._plan_id)
        if use == PlanUse.IGNORE:
            self.get_logger().info(f'plan {plan.plan_id} (request {plan.request_id}) not '
                                   'walked: it answers no pending start and is not the walk\'s',
                                   throttle_duration_sec=2.0)
            return
        if use == PlanUse.FAILED:
            self._planner_refused(request, plan.error_code, plan.error_msg, now)
            return
        self._watch.arrived(PLAN, now, time.monotonic())
        try:
            self._machine.set_timing(plan.single_support, plan.double_support)
            self._machine.set_plan(None if plan.continuous else plan.steps,
                                   None if plan.first_support is None else
                                   Support(plan.first_support), planned=True)
            transitions = self._machine.request_start(
                max(now, request.start_time)) if use == PlanUse.START else []
        except CommandError as error:
            self._reject(PLAN, f'plan {plan.plan_id} not used: {error}')
            if request is not None and request.answer_owed:
                self._answer(request.command, CommandStatus.NOT_ALLOWED, str(error))
            return
        self._plan, self._plan_id = plan, plan.plan_id
        self._plan_step = self._machine.status.step_index
        if use == PlanUse.START:
            self._teleop.driving = request.kind == RequestKind.VELOCITY
            if request.answer_owed:
                self._answer(request.command, CommandStatus.OK)
        self._publish_transitions(transitions, now)

    def _on_adjustment(self, msg: StepAdjustment) -> None:
        """The touchdown of the step under way moved (the footsteps come with the plan)."""
        now = self._now()
        if msg.plan_id != self._plan_id or not self._walking():
            self._reject('step_adjustment', f'plan {msg.plan_id} is not the walk\'s '
                         f'({self._plan_id}, {self.phase.name})')
            return
        if abs(msg.touchdown_time - now) > MAX_ADJUSTMENT_LEAD:
            self._reject('step_adjustment', f'touchdown_time {msg.touchdown_time!r} s is not '
                         f'within {MAX_ADJUSTMENT_LEAD} s of the clock ({now:.3f} s)')
            return
        if msg.kind not in (StepAdjustment.KIND_MOVED, StepAdjustment.KIND_HELD,
                            StepAdjustment.KIND_EARLY):
            self._reject('step_adjustment', f'unknown kind {msg.kind}')
            return
        held = msg.kind == StepAdjustment.KIND_HELD
        try:
            if held:
                moved = self._machine.hold_single_support(msg.step_index, msg.touchdown_time)
            else:
                moved = self._machine.retime_single_support(
                    msg.step_index, msg.touchdown_time,
                    EARLY_REASON if msg.kind == StepAdjustment.KIND_EARLY else MOVED_REASON)
        except CommandError as error:
            self._reject('step_adjustment', error)
            return
        if moved:
            what = {StepAdjustment.KIND_HELD: 'held for a late landing until',
                    StepAdjustment.KIND_EARLY: 'brought forward by an early landing to'}.get(
                        msg.kind, 'moved to')
            self.get_logger().info(f'step {msg.step_index}: touchdown {what} '
                                   f't={msg.touchdown_time:.3f} s (revision {msg.revision})')
            self._publish(self._machine.status, now)
        else:
            status = self._machine.status
            self._reject('step_adjustment', f'step {msg.step_index} is not the single support '
                         f'under way ({status.phase.name}, step {status.step_index})')
        self._publish_transitions(self._machine.update(now), now)

    # --- sensors and other inputs -----------------------------------------------------------
    def _on_stream(self, name: str, _raw) -> None:
        self._watch.arrived(name, self._now(), time.monotonic())

    def _on_odometry(self, msg: Odometry) -> None:
        stamp = seconds_of(msg.header.stamp)
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        now = self._now()
        try:
            self._odometry.check(msg.header.frame_id, stamp, (p.x, p.y, p.z),
                                 (q.x, q.y, q.z, q.w), now, self._bounds,
                                 self.get_parameter('max_stamp_ahead').value)
        except BipedPlannerError as error:
            self._reject('odom', error)
            return
        self._watch.arrived('odom', now, time.monotonic())
        if not self.get_parameter('fall_detection').value:
            return
        reason = detect_fall(p.z, (q.x, q.y, q.z, q.w), self._fall_params)
        if reason is None:
            self._odometry.reset_stamp = None  # standing since the reset: the odometry is new
        elif self._odometry.since_reset(stamp) <= RESET_SETTLE:
            return  # fallen just after a reset: measured before it (this clock may lag)
        if reason is not None:
            self._requests.cancel_start()
            # timed by the odometry that shows it, not by when this callback ran (on sim time
            # the clock can be a period on by then, more on a loaded machine), nor by the start
            # of the phase it interrupts: a walk's start_time enters Initialize at once, phased
            # in the future, and a fall before it came at the time the state was published
            self._publish_transitions(self._machine.report_fall(stamp, reason), now)

    # --- reset ------------------------------------------------------------------------------
    def _on_reset(self, request: Trigger.Request, response: Trigger.Response):
        response.success, response.message = self._reset_all()
        return response

    def _reset_all(self):
        """Reset the simulator (if any) and start a new epoch in Idle.

        :return: (success, message)
        """
        if self._walking():
            text = f'cannot reset while walking ({self.phase.name}): send STOP and wait for IDLE'
            self.get_logger().warning(text, throttle_duration_sec=1.0)
            return False, text
        simulator = 'no simulator/reset service: only the walking stack was reset'
        if self._simulator_reset.ready():
            timeout = self.get_parameter('reset_timeout').value
            result = self._simulator_reset.call(Trigger.Request(), timeout)
            if result is None or not result.success:
                text = f'simulator/reset failed: {result.message}' if result is not None else \
                    f'simulator/reset did not answer within {timeout} s'
                self.get_logger().error(text)
                return False, text
            simulator = f'simulator: {result.message}'
        now = self._now()
        self._odometry.reset(now)
        cancelled = self._requests.cancel_start()
        if cancelled is not None and cancelled.answer_owed:
            self._answer(cancelled.command, CommandStatus.NOT_ALLOWED, 'cancelled by a reset')
        if self.planner_available():
            request, _ = self._requests.new(RequestKind.CANCEL, CommandKind.RESET, False, False,
                                            time.monotonic())
            self._call_planner(request)
        transitions = self._machine.reset(now)
        self._plan_id, self._plan = 0, None
        self._teleop.ended(drop_deferred=True)
        self._publish_transitions(transitions, now)
        text = f'reset: epoch {self._machine.status.epoch}, IDLE ({simulator})'
        self.get_logger().info(text)
        return True, text

    # --- timers -----------------------------------------------------------------------------
    def _on_update(self) -> None:
        now = self._now()
        transitions = self._machine.update(now)
        self._publish_transitions(transitions, now)
        if self._scheduled_stop is not None and now >= self._scheduled_stop[0]:
            _, command, planner_told = self._scheduled_stop
            self._scheduled_stop = None
            if self._walking():
                transitions = self._stop(now, 'scheduled stop', command, planner_told)
                self._publish_transitions(transitions, now)
        if not transitions and (self._last_publish is None or now < self._last_publish or
                                now - self._last_publish >= self._publish_period):
            self._publish(self._machine.status, now)

    def _on_watch(self) -> None:
        """Wall-time checks: planner answers, the cmd_vel timeout, inputs that stopped."""
        now, wall = self._now(), time.monotonic()
        self._requests.timeout = self.get_parameter('planner_timeout').value
        for request in self._requests.expired(wall):
            self._outgoing.pop(request.request_id, None)
            self._planner_refused(request, None, 'no answer from plan_walk within '
                                  f'{self._requests.timeout} s', now)
        for request_id, (content, sent) in list(self._outgoing.items()):
            request = self._requests.get(request_id)
            if request is None:  # cancelled meanwhile
                del self._outgoing[request_id]
            elif (sent is None or wall - sent >= PLANNER_RESEND) and \
                    self._planner.service_is_ready():
                if sent is not None:
                    self.get_logger().warn(f'no answer from plan_walk to request {request_id} '
                                           f'in {PLANNER_RESEND} s: sent again')
                self._call_planner(request, **content)
        timeout = self.get_parameter('cmd_vel_timeout').value
        if self._teleop.timed_out(now, wall, timeout, self._walking()):
            self.get_logger().info(f'no cmd_vel for {timeout} s: stopping')
            self._publish_transitions(self._stop(now, f'cmd_vel timeout ({timeout} s)'), now)
        self._watch.timeout = self.get_parameter('input_timeout').value
        self._watch.clock(now, wall)
        stale = self._watch.check(now, wall)
        if stale != self._stale:
            self._on_stale_change(stale, now)

    def _on_stale_change(self, stale, now: float) -> None:
        lost = [name for name in stale if name not in self._stale]
        back = [name for name in self._stale if name not in stale]
        self._stale = stale
        if lost:
            self.get_logger().error(f'inputs stopped: {", ".join(lost)} (silent for '
                                    f'{self._watch.timeout} s)', throttle_duration_sec=1.0)
        if back:
            self.get_logger().info(f'inputs back: {", ".join(back)}')
        transitions = []
        if PLAN in lost and self._walking() and self._plan is not None:
            self.get_logger().error(f'the planner stopped extending plan {self._plan_id}: '
                                    f'ending the walk after its step {self._plan.steps}')
            self._machine.set_plan(self._plan.steps, planned=True)
        ended = [name for name in lost if name in WALK_PRODUCERS]
        if ended and self._walking():
            transitions = self._stop(now, f'{", ".join(ended)} lost: ending the walk')
        self._publish_transitions(transitions, now)
        if not transitions:
            self._publish(self._machine.status, now)


def main(args=None) -> None:
    run_node(StateMachineNode, args)


if __name__ == '__main__':
    main()
