"""The A* and footstep planner node: the planner server of the walking stack.

The state machine is the one entry point of user intent (walk_command, goal_pose, cmd_vel); it
asks this node for plans over the service plan_walk (biped_msgs/PlanWalk: request id, kind,
command, goal or velocity -> accepted, plan_id, error code), the way nav2's navigator calls its
planner server. Every plan published answers a request: FootstepPlan.request_id is that
request's id, or 0 for this node's own change of a walk at a step: the extension of a
continuous (teleop) plan, or a stated STOP's plan (below); it is stamped with the start of the
walking_state phase that asked for it (the reference generator times its splice from that). A
teleop command (START, OMNI) for a walk under way whose start_time is ahead of the clock waits
here and steers the steps appended from the first step that starts at or after that time
(biped_planner.scheduled_commands): a scripted walk then does not depend on when its commands
arrived. STOP, a goal or a new walk drop the waiting ones. A STOP whose start_time is ahead
waits here too and is answered at the start of the single support under way at that time
(biped_planner.stop_step), instead of that step's extension; a START or OMNI command drops it.

Service: plan_walk (biped_msgs/PlanWalk), offered once the start pose is known (odom or
sole_poses).
Subscribes: map (nav_msgs/OccupancyGrid, transient local), sole_poses (geometry_msgs/PoseArray
from the controller: a plan starts between the feet; odom until then), walking_state
(biped_msgs/WalkingState: teleop plans stay ahead of it), step_adjustment
(biped_msgs/StepAdjustment: the reference generator's step adjuster moved a landing; the plan,
same plan_id, is republished from where the foot lands, a goal walk planned anew from there).
Publishes (transient local): footstep_plan (biped_msgs/FootstepPlan, with status and error code),
plan (nav_msgs/Path), footstep_markers (visualization_msgs/MarkerArray).
"""
from typing import Optional, Tuple
import time

from biped_msgs.msg import FootstepPlan, StepAdjustment, WalkingState
from biped_msgs.srv import PlanWalk
from geometry_msgs.msg import PoseArray
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg, Odometry, Path
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from visualization_msgs.msg import MarkerArray

from biped_planner.astar import AStarPlanner
from biped_planner.errors import (BipedPlannerError, CommandError, FrameError, GoalOccupiedError,
                                  GoalOutsideMapError, MapError, NoPathError,
                                  StartOccupiedError, StartOutsideMapError)
from biped_planner.footstep_planner import FootstepPlanner, FootstepPlannerParams
from biped_planner.node_support.liveliness import LivelinessToken
from biped_planner.node_support.dataclass_parameters import (
    declare_dataclass_parameters, declare_live_parameters, declare_node_parameters)
from biped_planner.node_support.map_messages import grid_from_msg
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.qos import LATCHED, LATCHED_IN
from biped_planner.node_support.rejection_log import RejectionLog
from biped_planner.node_support.stamps import seconds_of, time_msg_of
from biped_planner.nodes.conversions import (body_between, checked_pose2d, failed_plan_msg,
                                             feet_from_sole_poses, footstep_markers,
                                             footstep_plan_msg, footsteps_from_msgs,
                                             goal_command_from_msg, path_msg,
                                             velocity_from_twist, walk_command_from_msg)
from biped_planner.occupancy_grid import InflationParams
from biped_planner.omnidirectional_stepper import command_from_twist, StepCommand, StepperParams
from biped_planner.plan_session import LOOKAHEAD_RANGE, PlanMode, PlanSession
from biped_planner.pose2d import Pose2D
from biped_planner.pose_checks import check_pose, PoseBounds
from biped_planner.reference_session import check_footsteps
from biped_planner.scheduled_commands import ScheduledCommands
from biped_planner.standing_feet import settled_feet
from biped_planner.step_timing import StepTiming
from biped_planner.stop_step import committed_step, stop_due_at
from biped_planner.walk_command import CommandKind, CommandLimits
from biped_planner.walking_state_machine import Phase, WALKING_PHASES

MAX_ADJUSTED_STEP = 1.0  # m: farther consecutive footsteps in an adjustment are not a step's

PLANNING_ERRORS = [
    (StartOutsideMapError, FootstepPlan.ERROR_START_OUTSIDE_MAP),
    (GoalOutsideMapError, FootstepPlan.ERROR_GOAL_OUTSIDE_MAP),
    (StartOccupiedError, FootstepPlan.ERROR_START_OCCUPIED),
    (GoalOccupiedError, FootstepPlan.ERROR_GOAL_OCCUPIED),
    (NoPathError, FootstepPlan.ERROR_NO_PATH),
    (MapError, FootstepPlan.ERROR_MALFORMED_MAP),
    (FrameError, FootstepPlan.ERROR_UNKNOWN_FRAME),
    (CommandError, FootstepPlan.ERROR_INVALID_COMMAND),
]
PHASES = {int(phase) for phase in Phase}
SUPPORTS = {WalkingState.SUPPORT_LEFT, WalkingState.SUPPORT_RIGHT, WalkingState.SUPPORT_DOUBLE}
MAX_RESOLUTION = 100.0  # m: a map cell larger than this is no map of a walking robot
ODOM_ONLY_AFTER = 1.0  # s of wall time after the first odom: no sole_poses publisher: odom
ODOM_FALLBACK_AFTER = 5.0  # s: sole_poses announced but none arrived: plan from odom
REPEAT_WINDOW = 15.0  # s of wall time: a request identical to the last one is its resending
Failure = Optional[Tuple[int, str]]  # (FootstepPlan error code, message), None: success


def error_code_of(error: BipedPlannerError) -> int:
    return next((code for kind, code in PLANNING_ERRORS if isinstance(error, kind)),
                FootstepPlan.ERROR_INTERNAL)


class FootstepPlannerNode(Node):
    """Thin adapter over biped_planner.plan_session.PlanSession."""

    def __init__(self, **kwargs) -> None:
        super().__init__('footstep_planner', **kwargs)
        # Descriptions and ranges come from the dataclasses' parameter() fields.
        planner_params = declare_dataclass_parameters(
            self, FootstepPlannerParams(), {}, prefix='path.',
            fixed={'limits': FootstepPlannerParams().limits})
        self._inflation = declare_dataclass_parameters(self, InflationParams(), {},
                                                       prefix='inflation.')
        stepper_params = declare_dataclass_parameters(
            self, StepperParams(), {}, prefix='teleop.',
            fixed={'limits': StepperParams().limits})
        declare_live_parameters(self, CommandLimits(), 'limits.', '_limits')
        declare_live_parameters(self, PoseBounds(), 'pose_bounds.', '_bounds')
        # The step timing written into every plan.
        self._timing = declare_dataclass_parameters(
            self, StepTiming(), {}, on_change=lambda p: setattr(self, '_timing', p))
        declare_node_parameters(self, {
            'map_frame': ('map', 'frame of the map, goals and plans', None),
            'teleop_lookahead': (2, 'teleop steps planned beyond the one being taken',
                                 LOOKAHEAD_RANGE),
            'foot_length': (0.2, 'sole length, for the markers (m)', (0.01, 1.0)),
            'foot_width': (0.1, 'sole width, for the markers (m)', (0.01, 1.0))},
            read_only=('map_frame', 'teleop_lookahead'))
        self._frame = self.get_parameter('map_frame').value
        self._reject = RejectionLog(self.get_logger().warning)
        self._session = PlanSession(FootstepPlanner(planner_params), stepper_params,
                                    lookahead=self.get_parameter('teleop_lookahead').value)
        self._astar = None
        self._pose = None
        self._feet = None  # the standing feet the pose is between (sole_poses)
        self._measured_feet = None  # the newest sole_poses, walking or not
        self._state = None
        self._scheduled = ScheduledCommands()  # teleop commands stated for a later step
        self._stated_stop = None  # (time s, request id) of a STOP stated for a later step
        self._single_support_start = None  # s, the walk's newest single support's start
        self._plan_pub = self.create_publisher(FootstepPlan, 'footstep_plan', LATCHED)
        # the reference generator waits for this process's extensions in lockstep while alive
        self._alive = LivelinessToken(self, 'footstep_plan')
        self._path_pub = self.create_publisher(Path, 'plan', LATCHED)
        self._marker_pub = self.create_publisher(MarkerArray, 'footstep_markers', LATCHED)
        self.create_subscription(OccupancyGridMsg, 'map', self._on_map, LATCHED_IN)
        # odom is read until sole_poses arrive, then unsubscribed (a message every period)
        self._odom_sub = self.create_subscription(Odometry, 'odom', self._on_odom, 10)
        self.create_subscription(PoseArray, 'sole_poses', self._on_soles, 10)
        self._soles_seen = False
        self.create_subscription(WalkingState, 'walking_state', self._on_state, 10)
        self.create_subscription(StepAdjustment, 'step_adjustment', self._on_adjustment, 10)
        # plan_walk is offered once the robot's pose is known: a caller that finds the service
        # (the state machine waits for it) is never refused for a start not yet received. The
        # pose is where the feet are (sole_poses); odom's pelvis, 1-2 cm off their middle, only
        # without a controller, so that a plan does not depend on which came first
        self._service = None
        self._odom_since = None  # wall time of the first odom
        self._offer_timer = self.create_timer(0.1, self._offer_plan_walk,
                                              clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._last_served = None  # (request, response, wall time) of the last plan_walk call
        self.get_logger().info('footstep planner ready (plan_walk once odom or sole_poses '
                               'arrive)')

    # --- inputs -----------------------------------------------------------------------------
    def _on_map(self, msg: OccupancyGridMsg) -> None:
        """A new map replaces the old one; a bad one leaves no map (goals then fail NO_MAP)."""
        info = msg.info
        try:
            if msg.header.frame_id != self._frame:
                raise MapError(f'frame {msg.header.frame_id!r}, expected {self._frame!r}')
            if not 0.0 < info.resolution <= MAX_RESOLUTION:  # NaN fails too
                raise MapError(f'resolution {info.resolution} must be in (0, {MAX_RESOLUTION}] m')
            p, q = info.origin.position, info.origin.orientation
            check_pose('map origin', (p.x, p.y, p.z), (q.x, q.y, q.z, q.w), self._bounds)
            self._astar = AStarPlanner(grid_from_msg(msg), self._inflation)
        except (BipedPlannerError, ValueError) as error:
            self._astar = None
            self._reject('map', error)
            return
        self.get_logger().info(f'map {msg.info.width} x {msg.info.height} cells of '
                               f'{msg.info.resolution} m')

    def _on_soles(self, msg: PoseArray) -> None:
        """Plans start between the feet (the pelvis is not above their midpoint); while
        walking, the plan being walked says where the feet go."""
        try:
            if msg.header.frame_id != self._frame:
                raise MapError(f'frame {msg.header.frame_id!r}, expected {self._frame!r}')
            measured = feet_from_sole_poses(msg, self._bounds)
        except (ValueError, BipedPlannerError) as error:
            self._reject('sole_poses', error)
            return
        self._measured_feet = measured
        if not self._walking():
            self._feet = settled_feet(self._feet, measured)
            self._pose = body_between(self._feet)
            self._soles_seen = True
            self._drop_odom()
            self._offer_plan_walk()

    def _drop_odom(self) -> None:
        """The feet are known: odom is not read again (a message every period). Dropped at
        once, not at the next odom: a clock held at its start sends none for a while."""
        if self._odom_sub is not None:
            self.destroy_subscription(self._odom_sub)
            self._odom_sub = None

    def _on_odom(self, msg: Odometry) -> None:
        if self._soles_seen:
            self._drop_odom()
            return
        try:
            if msg.header.frame_id != self._frame:
                raise MapError(f'frame {msg.header.frame_id!r}, expected {self._frame!r}')
            self._pose = checked_pose2d('odom', msg.pose.pose, self._bounds)
        except BipedPlannerError as error:
            self._reject('odom', error)
            return
        if self._odom_since is None:
            self._odom_since = time.monotonic()
        self._offer_plan_walk()

    def _stand_where_the_walk_ended(self) -> None:
        """The feet held from before the walk are stale now: the next plan starts where the
        feet landed (a goal can come in the very period the walk ends, before the next
        sole_poses; a plan from the old feet would make the references jump back to them)."""
        if self._measured_feet is not None:
            self._feet = tuple(self._measured_feet)
            self._pose = body_between(self._feet)

    def _offer_plan_walk(self) -> None:
        """Offer plan_walk once the feet are known (sole_poses), or odom's pose without them:
        no controller publishes sole_poses ODOM_ONLY_AFTER after odom came, or none arrived
        in ODOM_FALLBACK_AFTER."""
        if self._service is not None:
            return
        if not self._soles_seen:
            waited = -1.0 if self._odom_since is None else time.monotonic() - self._odom_since
            if not (waited >= ODOM_FALLBACK_AFTER or waited >= ODOM_ONLY_AFTER and
                    self.count_publishers('sole_poses') == 0):
                return
        self._offer_timer.cancel()
        self._service = self.create_service(PlanWalk, 'plan_walk', self._on_plan_walk)
        self.get_logger().info('plan_walk served: the start pose is known (from ' +
                               ('sole_poses)' if self._soles_seen else 'odom: no sole_poses)'))

    def _on_state(self, msg: WalkingState) -> None:
        if msg.phase not in PHASES or msg.support_foot not in SUPPORTS:
            self._reject('walking_state', f'phase {msg.phase} or support_foot '
                         f'{msg.support_foot} unknown')
            return
        previous = self._state
        self._state = msg
        if msg.phase not in WALKING_PHASES and previous is not None and \
                previous.phase in WALKING_PHASES:
            self._drop_stated_stop('the walk ended')
            self._single_support_start = None
        if msg.phase == WalkingState.IDLE and previous is not None and \
                previous.phase in WALKING_PHASES:
            self._session.walk_finished()
            self._drop_scheduled('the walk ended')
            self._stand_where_the_walk_ended()
        elif msg.phase in (WalkingState.SINGLE_SUPPORT, WalkingState.DOUBLE_SUPPORT):
            # stamped with the start of the phase that asked for it, not with when this
            # callback ran: the reference generator times the extension from it
            phase_start = seconds_of(msg.header.stamp) - msg.time_in_phase
            stamp = None  # an implausible state's own timing: now
            if 0.0 <= msg.time_in_phase <= msg.phase_duration + 1.0 and \
                    0.0 <= phase_start <= self.get_clock().now().nanoseconds * 1e-9 + 1.0:
                stamp = time_msg_of(phase_start)
                self._apply_scheduled(phase_start)
                if msg.phase == WalkingState.SINGLE_SUPPORT:
                    self._single_support_start = phase_start
                    if self._stated_stop_due(phase_start):
                        self._answer_stated_stop(msg.step_index, stamp)
                        return
            try:
                self._publish(self._session.on_step(msg.step_index), stamp=stamp)
            except BipedPlannerError as error:
                self._reject('walking_state', error)

    def _on_adjustment(self, msg: StepAdjustment) -> None:
        if msg.kind in (StepAdjustment.KIND_HELD, StepAdjustment.KIND_EARLY):
            return  # a late or early landing moves a touchdown, no footstep: the plan stands
        try:
            if msg.kind != StepAdjustment.KIND_MOVED:
                raise ValueError(f'unknown kind {msg.kind}')
            if msg.header.frame_id != self._frame:
                raise FrameError(f'frame_id {msg.header.frame_id!r}, expected {self._frame!r}')
            footsteps = footsteps_from_msgs(msg.footsteps)
            check_footsteps(footsteps, self._bounds.workspace, MAX_ADJUSTED_STEP)
            update = self._session.adopt_adjustment(msg.plan_id, msg.step_index, footsteps)
        except (BipedPlannerError, ValueError) as error:
            self._reject('step_adjustment', error)
            return
        if update is None:
            self._reject('step_adjustment', f'plan {msg.plan_id} is not the current plan '
                         f'({self._session.plan_id})')
            return
        self.get_logger().info(f'plan {update.plan_id}: step {msg.step_index} adjusted '
                               f'(revision {msg.revision}), {len(update.footsteps) - 2} steps')
        if update.path:
            self._path_pub.publish(path_msg(update.path, self._frame,
                                            self.get_clock().now().to_msg()))
        # stamped with the adjustment, not with when it was handled: the reference generator
        # splices it in (and in lockstep waits for it) at that time + its extension_delay
        self._publish(update, stamp=msg.header.stamp)

    # --- the plan_walk service --------------------------------------------------------------
    def _on_plan_walk(self, request: PlanWalk.Request, response: PlanWalk.Response):
        if self._last_served is not None and self._last_served[0] == request and \
                time.monotonic() - self._last_served[2] < REPEAT_WINDOW:
            return self._last_served[1]  # sent again (its answer was lost): served once
        try:
            failure = self._serve(request)
        except BipedPlannerError as error:  # a library error not caught below: still answered
            failure = self._fail(error_code_of(error), str(error), request.request_id)
        response.plan_id = int(self._session.plan_id)
        response.accepted = failure is None
        response.error_code, response.error_msg = failure or (FootstepPlan.ERROR_NONE, '')
        self._last_served = (request, response, time.monotonic())
        return response

    def _serve(self, request: PlanWalk.Request) -> Failure:
        rid = request.request_id
        try:
            start_time = 0.0
            if request.kind == PlanWalk.Request.KIND_COMMAND:
                command = walk_command_from_msg(request.command, self._limits, self._frame)
                start_time = request.command.start_time
            elif request.kind == PlanWalk.Request.KIND_GOAL:
                command = goal_command_from_msg(request.goal, self._frame, self._limits)
            elif request.kind == PlanWalk.Request.KIND_VELOCITY:
                velocity = velocity_from_twist(request.velocity, self._limits)
                return self._teleop(command_from_twist(*velocity, self._timing.step_time), 0.0,
                                    rid)
            elif request.kind == PlanWalk.Request.KIND_CANCEL:
                return self._stop(rid)
            else:
                return self._fail(FootstepPlan.ERROR_INVALID_COMMAND,
                                  f'unknown request kind {request.kind}', rid)
        except CommandError as error:
            return self._fail(error_code_of(error), str(error), rid)
        if command.kind == CommandKind.GOTO:
            return self._goto(Pose2D(*command.goal), rid)
        if command.kind in (CommandKind.START, CommandKind.OMNI):
            self._drop_stated_stop(f'request {rid} walks on')
            return self._teleop(StepCommand(*command.step), command.step_time, rid, start_time)
        if command.kind == CommandKind.STOP:
            return self._stop(rid, start_time)
        return self._stop(rid)  # RESET: the state machine resets, the plan ends

    # --- planning ---------------------------------------------------------------------------
    def _walking(self) -> bool:
        return self._state is not None and self._state.phase in WALKING_PHASES

    def _goto(self, goal: Pose2D, request_id: int) -> Failure:
        if self._astar is None:
            return self._fail(FootstepPlan.ERROR_NO_MAP, 'no valid map received on map',
                              request_id)
        if self._pose is None:
            return self._fail(FootstepPlan.ERROR_NO_POSE, 'no odometry received on odom',
                              request_id)
        if self._walking():
            return self._fail(FootstepPlan.ERROR_INVALID_COMMAND,
                              'GOTO while walking: send STOP first, then the goal', request_id)
        self._drop_scheduled('a goal was given')
        self._drop_stated_stop('a goal was given')
        try:
            update = self._session.goto(self._astar, self._pose, goal)
        except BipedPlannerError as error:
            return self._fail(error_code_of(error), str(error), request_id)
        self._path_pub.publish(path_msg(update.path, self._frame,
                                        self.get_clock().now().to_msg()))
        self.get_logger().info(f'plan {update.plan_id} (request {request_id}): '
                               f'{len(update.footsteps) - 2} steps to ({goal.x:.2f}, '
                               f'{goal.y:.2f})')
        self._publish(update, request_id)
        return None

    def _teleop(self, command: StepCommand, step_time: float, request_id: int,
                start_time: float = 0.0) -> Failure:
        step_time = step_time or self._timing.step_time
        if self._walking() and self._session.mode == PlanMode.TELEOP and \
                start_time > self.get_clock().now().nanoseconds * 1e-9:
            try:
                self._scheduled.add(start_time, (command, step_time))
            except BipedPlannerError as error:
                return self._fail(FootstepPlan.ERROR_INVALID_COMMAND, str(error), request_id)
            self.get_logger().info(f'request {request_id}: steers the steps from the first '
                                   f'that starts at or after t={start_time:.3f} s')
            return None
        if self._walking() and start_time > 0.0:
            self.get_logger().warning(f'request {request_id} for t={start_time:.3f} s came '
                                      'after that time: it steers from now (a run that may '
                                      'differ from one on a quieter machine)')
        if not self._walking():
            self._drop_scheduled('a new walk starts')
            self._drop_stated_stop('a new walk starts')
        if self._pose is None and self._session.mode != PlanMode.TELEOP:
            return self._fail(FootstepPlan.ERROR_NO_POSE, 'no odometry received on odom',
                              request_id)
        if self._walking() and self._session.mode != PlanMode.TELEOP:
            return self._fail(FootstepPlan.ERROR_INVALID_COMMAND,
                              'the walk follows a goal plan or is stopping: send STOP and wait '
                              'for IDLE before a teleop command', request_id)
        step = self._state.step_index if self._walking() else 0
        try:
            update = self._session.teleop(command, step_time, self._pose or Pose2D(0.0, 0.0),
                                          step)
        except BipedPlannerError as error:
            return self._fail(error_code_of(error), str(error), request_id)
        self._publish(update, request_id)
        return None

    def _apply_scheduled(self, step_start: float) -> None:
        """Steer by the commands whose time came, before the step starting at step_start is
        planned on."""
        for command, step_time in self._scheduled.due(step_start):
            if self._session.set_command(command, step_time):
                self.get_logger().info(
                    f'scheduled command {command} from the step starting at t={step_start:.3f} s')

    def _drop_scheduled(self, why: str) -> None:
        dropped = self._scheduled.clear()
        if dropped:
            self.get_logger().info(f'{dropped} scheduled command(s) dropped: {why}')

    def _stop(self, request_id: int, start_time: float = 0.0) -> Failure:
        """End the walk after the step under way, or after the one under way at start_time
        (s) when that is ahead (answered then, see _answer_stated_stop)."""
        self._drop_stated_stop(f'request {request_id} stops the walk')
        # held whenever a walk has its plan: the state machine sends it once the walk started,
        # and this node can have that walking_state still on its way
        if start_time > 0.0 and self._session.mode != PlanMode.NONE:
            seen = self._single_support_start
            if seen is None or not stop_due_at(seen, start_time, self._timing.single_support):
                self._stated_stop = (start_time, request_id)
                self.get_logger().info(f'request {request_id}: STOP at t={start_time:.3f} s, '
                                       'answered at the start of the step under way then')
                return None
            self.get_logger().warning(f'request {request_id}: STOP for t={start_time:.3f} s '
                                      'came after the start of the step under way then: the '
                                      'walk stops from now (a run that may differ from one on '
                                      'a quieter machine)')
        self._drop_scheduled('stop requested')
        step = self._committed_step()
        try:
            self._publish(self._session.stop(step, self._walking()), request_id)
        except BipedPlannerError as error:
            return self._fail(error_code_of(error), str(error), request_id)
        return None

    def _stated_stop_due(self, single_support_start: float) -> bool:
        return self._stated_stop is not None and stop_due_at(
            single_support_start, self._stated_stop[0], self._timing.single_support)

    def _answer_stated_stop(self, step_index: int, stamp) -> None:
        """The step starting now is the last before the closing one: the plan that says so
        is this step's change of the walk (request_id 0, stamped with the step's start), which
        the reference generator splices in, and waits for, as an extension."""
        stop_time, request_id = self._stated_stop
        self._stated_stop = None
        self._drop_scheduled('the walk stops')
        try:
            update = self._session.stop(step_index, True)
        except BipedPlannerError as error:
            self._fail(error_code_of(error), str(error), request_id)
            return
        self.get_logger().info(f'request {request_id}: the STOP at t={stop_time:.3f} s ends '
                               f'the walk after step {step_index} and a closing step')
        self._publish(update, stamp=stamp)

    def _drop_stated_stop(self, why: str) -> None:
        if self._stated_stop is not None:
            self.get_logger().info(f'the STOP at t={self._stated_stop[0]:.3f} s (request '
                                   f'{self._stated_stop[1]}) dropped: {why}')
            self._stated_stop = None

    def _committed_step(self) -> int:
        """The last step the walk takes before a stop's closing step (0 standing)."""
        state = self._state
        if state is None or state.phase not in WALKING_PHASES:
            return 0
        return committed_step(state.step_index, state.phase == WalkingState.DOUBLE_SUPPORT,
                              state.phase_duration - state.time_in_phase)

    def _publish(self, update, request_id: int = 0, stamp=None) -> None:
        if update is None:
            return
        stamp = stamp if stamp is not None else self.get_clock().now().to_msg()
        self._plan_pub.publish(footstep_plan_msg(
            update, self._timing.single_support, self._timing.double_support, self._frame,
            stamp, request_id))
        self._marker_pub.publish(footstep_markers(
            update.footsteps, self.get_parameter('foot_length').value,
            self.get_parameter('foot_width').value, self._frame, stamp))

    def _fail(self, code: int, message: str, request_id: int) -> Failure:
        self.get_logger().error(f'request {request_id} failed ({code}): {message}')
        self._plan_pub.publish(failed_plan_msg(self._session.plan_id, code, message,
                                               self._frame, self.get_clock().now().to_msg(),
                                               request_id))
        return code, message


def main(args=None) -> None:
    run_node(FootstepPlannerNode, args)


if __name__ == '__main__':
    main()
