"""The A* and footstep planner node: map, goals and commands in, footstep plans out.

Subscribes: map (nav_msgs/OccupancyGrid, transient local), goal_pose (geometry_msgs/PoseStamped),
walk_command (biped_msgs/WalkCommand), cmd_vel (geometry_msgs/Twist), sole_poses
(geometry_msgs/PoseArray from the controller: a plan starts between the feet; odom until then),
walking_state (biped_msgs/WalkingState: teleop plans stay ahead of it).
Publishes (transient local): footstep_plan (biped_msgs/FootstepPlan, with status and error code),
plan (nav_msgs/Path), footstep_markers (visualization_msgs/MarkerArray); and
walk_command_status (biped_msgs/CommandStatus) for the commands it acts on.
"""
import math

from biped_msgs.msg import CommandStatus, FootstepPlan, WalkCommand as WalkCommandMsg, WalkingState
from geometry_msgs.msg import PoseArray, PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg, Odometry, Path
from rclpy.node import Node
from visualization_msgs.msg import MarkerArray

from biped_planner.astar import AStarPlanner
from biped_planner.errors import (BipedPlannerError, CommandError, GoalOccupiedError,
                                  GoalOutsideMapError, MapError, NoPathError,
                                  StartOccupiedError, StartOutsideMapError)
from biped_planner.footstep_planner import FootstepPlanner, FootstepPlannerParams
from biped_planner.node_support.dataclass_parameters import (declare_dataclass_parameters,
                                                             declare_node_parameters)
from biped_planner.node_support.map_messages import grid_from_msg
from biped_planner.node_support.node_runner import run_node
from biped_planner.node_support.qos import LATCHED, LATCHED_IN
from biped_planner.nodes.conversions import (body_between, command_status_msg, failed_plan_msg,
                                             feet_from_sole_poses, footstep_markers,
                                             footstep_plan_msg, path_msg, pose2d_from_pose,
                                             walk_command_from_msg)
from biped_planner.occupancy_grid import InflationParams
from biped_planner.omnidirectional_stepper import command_from_twist, StepCommand, StepperParams
from biped_planner.plan_session import LOOKAHEAD_RANGE, PlanMode, PlanSession
from biped_planner.pose2d import Pose2D
from biped_planner.step_timing import StepTiming
from biped_planner.walk_command import CommandKind, CommandLimits
from biped_planner.walking_state_machine import WALKING_PHASES


PLANNING_ERRORS = [
    (StartOutsideMapError, FootstepPlan.ERROR_START_OUTSIDE_MAP),
    (GoalOutsideMapError, FootstepPlan.ERROR_GOAL_OUTSIDE_MAP),
    (StartOccupiedError, FootstepPlan.ERROR_START_OCCUPIED),
    (GoalOccupiedError, FootstepPlan.ERROR_GOAL_OCCUPIED),
    (NoPathError, FootstepPlan.ERROR_NO_PATH),
    (MapError, FootstepPlan.ERROR_MALFORMED_MAP),
    (CommandError, FootstepPlan.ERROR_INVALID_COMMAND),
]


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
        self._limits = declare_dataclass_parameters(
            self, CommandLimits(), {}, prefix='limits.',
            on_change=lambda p: setattr(self, '_limits', p))
        # The step timing written into every plan.
        self._timing = declare_dataclass_parameters(
            self, StepTiming(), {}, on_change=lambda p: setattr(self, '_timing', p))
        declare_node_parameters(self, {
            'map_frame': ('map', 'frame of the map, goals and plans', None),
            'teleop_lookahead': (2, 'teleop steps planned beyond the one being taken',
                                 LOOKAHEAD_RANGE),
            'foot_length': (0.2, 'sole length, for the markers (m)', (0.01, 1.0)),
            'foot_width': (0.1, 'sole width, for the markers (m)', (0.01, 1.0))})
        self._frame = self.get_parameter('map_frame').value
        self._session = PlanSession(FootstepPlanner(planner_params), stepper_params,
                                    lookahead=self.get_parameter('teleop_lookahead').value)
        self._astar = None
        self._pose = None
        self._state = None
        self._plan_pub = self.create_publisher(FootstepPlan, 'footstep_plan', LATCHED)
        self._path_pub = self.create_publisher(Path, 'plan', LATCHED)
        self._marker_pub = self.create_publisher(MarkerArray, 'footstep_markers', LATCHED)
        self._status_pub = self.create_publisher(CommandStatus, 'walk_command_status', 10)
        self.create_subscription(OccupancyGridMsg, 'map', self._on_map, LATCHED_IN)
        self.create_subscription(PoseStamped, 'goal_pose', self._on_goal, 10)
        self.create_subscription(WalkCommandMsg, 'walk_command', self._on_command, 10)
        self.create_subscription(Twist, 'cmd_vel', self._on_cmd_vel, 10)
        # odom is read until sole_poses arrive, then unsubscribed (a message every period)
        self._odom_sub = self.create_subscription(Odometry, 'odom', self._on_odom, 10)
        self.create_subscription(PoseArray, 'sole_poses', self._on_soles, 10)
        self._soles_seen = False
        self.create_subscription(WalkingState, 'walking_state', self._on_state, 10)
        self.get_logger().info('footstep planner ready (waiting for map and odom)')

    # --- inputs -----------------------------------------------------------------------------
    def _on_map(self, msg: OccupancyGridMsg) -> None:
        if msg.header.frame_id not in ('', self._frame):
            self.get_logger().error(f'map in frame {msg.header.frame_id!r} ignored: expected '
                                    f'{self._frame!r}')
            self._astar = None
            return
        try:
            self._astar = AStarPlanner(grid_from_msg(msg), self._inflation)
        except BipedPlannerError as error:
            self._astar = None
            self.get_logger().error(f'map rejected: {error}')
            return
        self.get_logger().info(f'map {msg.info.width} x {msg.info.height} cells of '
                               f'{msg.info.resolution} m')

    def _on_soles(self, msg: PoseArray) -> None:
        """Plans start between the feet (the pelvis is not above their midpoint)."""
        if self._walking():
            return
        try:
            self._pose = body_between(feet_from_sole_poses(msg))
            self._soles_seen = True
        except (ValueError, BipedPlannerError) as error:
            self.get_logger().warning(f'sole_poses ignored: {error}', throttle_duration_sec=5.0)

    def _on_odom(self, msg: Odometry) -> None:
        if self._soles_seen:
            if self._odom_sub is not None:
                self.destroy_subscription(self._odom_sub)
                self._odom_sub = None
            return
        try:
            self._pose = pose2d_from_pose(msg.pose.pose)
        except BipedPlannerError:
            self.get_logger().warning('odometry with a non-finite pose ignored',
                                      throttle_duration_sec=5.0)

    def _on_state(self, msg: WalkingState) -> None:
        previous = self._state
        self._state = msg
        if msg.phase == WalkingState.IDLE and previous is not None and \
                previous.phase in WALKING_PHASES:
            self._session.walk_finished()
        elif msg.phase in (WalkingState.SINGLE_SUPPORT, WalkingState.DOUBLE_SUPPORT):
            self._publish(self._session.on_step(msg.step_index))

    def _on_goal(self, msg: PoseStamped) -> None:
        if msg.header.frame_id not in ('', self._frame):
            self._fail(FootstepPlan.ERROR_UNKNOWN_FRAME,
                       f'goal_pose in frame {msg.header.frame_id!r}: only {self._frame!r} '
                       'is known (no tf here)')
            return
        try:
            goal = pose2d_from_pose(msg.pose)
        except BipedPlannerError as error:
            self._fail(FootstepPlan.ERROR_INVALID_COMMAND, f'goal_pose: {error}')
            return
        self._goto(goal)

    def _on_command(self, msg: WalkCommandMsg) -> None:
        try:
            command = walk_command_from_msg(msg, self._limits)
        except CommandError:
            return  # the state machine answers invalid commands
        kind = command.kind
        error = None
        if kind == CommandKind.GOTO:
            error = self._goto(Pose2D(*command.goal))
        elif kind == CommandKind.START and self._session.mode == PlanMode.GOTO:
            pass  # walk the goal plan already published
        elif kind in (CommandKind.OMNI, CommandKind.START):
            error = self._teleop(StepCommand(*command.step), command.step_time)
        elif kind == CommandKind.STOP:
            self._stop()
        else:
            return
        self._status_pub.publish(command_status_msg(
            self.get_name(), msg.command, CommandStatus.OK if error is None else
            CommandStatus.INVALID_VALUE, error or '', self.get_clock().now().to_msg()))

    def _on_cmd_vel(self, msg: Twist) -> None:
        values = (msg.linear.x, msg.linear.y, msg.angular.z)
        if not all(math.isfinite(v) for v in values):
            self.get_logger().warning(f'cmd_vel {values} is not finite: ignored',
                                      throttle_duration_sec=2.0)
            return
        step_time = self._step_time()
        self._teleop(command_from_twist(*values, step_time), 0.0)

    # --- planning ---------------------------------------------------------------------------
    def _step_time(self) -> float:
        return self._timing.step_time

    def _walking(self) -> bool:
        return self._state is not None and self._state.phase in WALKING_PHASES

    def _goto(self, goal: Pose2D):
        if self._astar is None:
            return self._fail(FootstepPlan.ERROR_NO_MAP, 'no valid map received on map')
        if self._pose is None:
            return self._fail(FootstepPlan.ERROR_NO_POSE, 'no odometry received on odom')
        if self._walking():
            return self._fail(FootstepPlan.ERROR_INVALID_COMMAND,
                              'GOTO while walking: send STOP first, then the goal')
        try:
            update = self._session.goto(self._astar, self._pose, goal)
        except BipedPlannerError as error:
            code = next((c for kind, c in PLANNING_ERRORS if isinstance(error, kind)),
                        FootstepPlan.ERROR_INTERNAL)
            return self._fail(code, str(error))
        self._path_pub.publish(path_msg(update.path, self._frame,
                                        self.get_clock().now().to_msg()))
        self.get_logger().info(f'plan {update.plan_id}: {len(update.footsteps) - 2} steps to '
                               f'({goal.x:.2f}, {goal.y:.2f})')
        self._publish(update)
        return None

    def _teleop(self, command: StepCommand, step_time: float):
        if self._pose is None and self._session.mode != PlanMode.TELEOP:
            return self._fail(FootstepPlan.ERROR_NO_POSE, 'no odometry received on odom')
        step = self._state.step_index if self._walking() else 0
        try:
            update = self._session.teleop(command, step_time or self._step_time(),
                                          self._pose or Pose2D(0.0, 0.0), step)
        except BipedPlannerError as error:
            return self._fail(FootstepPlan.ERROR_INVALID_COMMAND, str(error))
        self._publish(update)
        return None

    def _stop(self) -> None:
        step = self._state.step_index if self._state is not None else 0
        self._publish(self._session.stop(step, self._walking()))

    def _publish(self, update) -> None:
        if update is None:
            return
        stamp = self.get_clock().now().to_msg()
        self._plan_pub.publish(footstep_plan_msg(
            update, self._timing.single_support, self._timing.double_support, self._frame,
            stamp))
        self._marker_pub.publish(footstep_markers(
            update.footsteps, self.get_parameter('foot_length').value,
            self.get_parameter('foot_width').value, self._frame, stamp))

    def _fail(self, code: int, message: str) -> str:
        self.get_logger().error(f'planning failed ({code}): {message}')
        self._plan_pub.publish(failed_plan_msg(self._session.plan_id, code, message,
                                               self._frame, self.get_clock().now().to_msg()))
        return message


def main(args=None) -> None:
    run_node(FootstepPlannerNode, args)


if __name__ == '__main__':
    main()
