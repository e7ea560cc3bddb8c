"""Conversions between biped_msgs / standard messages and biped_planner library values.

All message imports of biped_planner live in its nodes package; the library never sees a message.
"""
import math

from biped_msgs.msg import (CommandStatus, Footstep as FootstepMsg, FootstepPlan,
                            WalkCommand as WalkCommandMsg, WalkingState)
from biped_msgs.srv import PlanWalk
from geometry_msgs.msg import PoseStamped, Quaternion, Twist
from nav_msgs.msg import Path
from visualization_msgs.msg import Marker, MarkerArray

from biped_planner.errors import ConfigError, InputError
from biped_planner.footsteps import Footstep
from biped_planner.plan_requests import ReceivedPlan
from biped_planner.pose2d import Pose2D
from biped_planner.pose_checks import check_pose, PoseBounds
from biped_planner.rotations import mean_angle, quaternion_from_yaw, wrap_angle, yaw_of_quaternion
from biped_planner.sides import LEFT, RIGHT, SIDES
from biped_planner.step_timing import StepTiming
from biped_planner.walk_command import (check_command_frame, CommandLimits, goal_command,
                                        velocity_command, WalkCommand)
from biped_planner.walking_state_machine import WalkingStatus


def walk_command_from_msg(msg: WalkCommandMsg, limits: CommandLimits,
                          map_frame: str = 'map') -> WalkCommand:
    """:raises CommandError: when a field is unknown, not finite or out of range
    :raises FrameError: when a GOTO names another frame than map_frame (empty is map_frame)"""
    command = WalkCommand.from_fields(
        msg.command, (msg.goal_x, msg.goal_y, msg.goal_yaw),
        (msg.step_length, msg.step_width, msg.step_angle), msg.step_time, limits)
    check_command_frame(command, msg.header.frame_id, map_frame)
    return command


def goal_command_from_msg(msg: PoseStamped, map_frame: str, limits: CommandLimits
                          ) -> WalkCommand:
    """A GOTO command from a goal_pose (biped_planner.walk_command.goal_command).

    :raises FrameError: unless the header names map_frame
    :raises CommandError: for non-finite values, a far goal or a non-unit quaternion
    """
    p, q = msg.pose.position, msg.pose.orientation
    return goal_command(msg.header.frame_id, map_frame, (p.x, p.y, p.z), (q.x, q.y, q.z, q.w),
                        limits)


def velocity_from_twist(msg: Twist, limits: CommandLimits) -> tuple:
    """(vx, vy, wz) of a cmd_vel (biped_planner.walk_command.velocity_command).

    :raises CommandError: for non-finite values or speeds beyond the limits
    """
    return velocity_command((msg.linear.x, msg.linear.y, msg.linear.z),
                            (msg.angular.x, msg.angular.y, msg.angular.z), limits)


def twist_of(velocity) -> Twist:
    """The cmd_vel of (vx, vy, wz)."""
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.angular.z = (float(v) for v in velocity)
    return msg


def plan_walk_request(request_id: int, kind: int, command: WalkCommandMsg = None,
                      goal: PoseStamped = None, velocity: Twist = None) -> PlanWalk.Request:
    request = PlanWalk.Request()
    request.request_id = int(request_id)
    request.kind = int(kind)
    if command is not None:
        request.command = command
    if goal is not None:
        request.goal = goal
    if velocity is not None:
        request.velocity = velocity
    return request


def received_plan(msg: FootstepPlan) -> ReceivedPlan:
    """What the state machine needs of a footstep plan.

    :raises InputError: for an unknown status, a footstep that is not finite or has an unknown
        side, or (in an OK plan) support durations that are not finite and positive
    """
    if msg.status not in (FootstepPlan.STATUS_OK, FootstepPlan.STATUS_FAILED):
        raise InputError(f'footstep_plan {msg.plan_id}: unknown status {msg.status}')
    if msg.status != FootstepPlan.STATUS_OK:
        return ReceivedPlan(msg.plan_id, msg.request_id, False, error_code=msg.error_code,
                            error_msg=msg.error_msg)
    for index, step in enumerate(msg.footsteps):
        if step.side not in SIDES:
            raise InputError(f'footstep_plan {msg.plan_id}: footsteps[{index}].side '
                             f'{step.side} is neither LEFT (0) nor RIGHT (1)')
        if not all(math.isfinite(v) for v in (step.x, step.y, step.z, step.yaw)):
            raise InputError(f'footstep_plan {msg.plan_id}: footsteps[{index}] is not finite')
    try:
        StepTiming(float(msg.single_support), float(msg.double_support))
    except ConfigError as error:
        raise InputError(f'footstep_plan {msg.plan_id}: {error}') from None
    first = msg.footsteps[0].side if msg.footsteps else None
    return ReceivedPlan(msg.plan_id, msg.request_id, True, bool(msg.continuous),
                        max(0, len(msg.footsteps) - 2), first, float(msg.single_support),
                        float(msg.double_support))


def walking_state_msg(status: WalkingStatus, now: float, stamp, plan_id: int,
                      stale_inputs=(), stop_time: float = 0.0) -> WalkingState:
    msg = WalkingState()
    msg.header.stamp = stamp
    msg.phase = int(status.phase)
    msg.support_foot = int(status.support)
    msg.step_index = int(status.step_index)
    msg.time_in_phase = float(status.time_in_phase(now))
    msg.phase_duration = float(status.phase_duration)
    msg.walk_start_time = float(status.walk_start)
    msg.plan_id = int(plan_id)
    msg.fallen = status.fallen
    msg.stop_requested = status.stop_requested
    msg.stop_time = float(stop_time)
    msg.inputs_stale = bool(stale_inputs)
    msg.stale_inputs = [str(name) for name in stale_inputs]
    msg.epoch = int(status.epoch) % 2 ** 32
    msg.reason = status.reason
    return msg


def command_status_msg(node_name: str, command: int, error_code: int, error_msg: str,
                       stamp) -> CommandStatus:
    msg = CommandStatus()
    msg.header.stamp = stamp
    msg.node = node_name
    msg.command = max(0, min(255, int(command)))
    msg.accepted = error_code == CommandStatus.OK
    msg.error_code = error_code
    msg.error_msg = error_msg
    return msg


def yaw_of_msg(q) -> float:
    """Heading of a geometry_msgs/Quaternion (rad), biped_planner.rotations.yaw_of_quaternion."""
    return yaw_of_quaternion((q.x, q.y, q.z, q.w))


def quaternion_msg_from_yaw(yaw: float) -> Quaternion:
    """geometry_msgs/Quaternion of a rotation by yaw about z."""
    x, y, z, w = (float(v) for v in quaternion_from_yaw(yaw))
    return Quaternion(x=x, y=y, z=z, w=w)


def pose2d_from_pose(pose) -> Pose2D:
    return Pose2D(pose.position.x, pose.position.y, yaw_of_msg(pose.orientation))


def checked_pose2d(name: str, pose, bounds: PoseBounds) -> Pose2D:
    """The planar pose of a measured geometry_msgs/Pose (biped_planner.pose_checks).

    :raises InputError: when it is not finite, beyond the workspace or not a unit quaternion
    """
    p, q = pose.position, pose.orientation
    check_pose(name, (p.x, p.y, p.z), (q.x, q.y, q.z, q.w), bounds)
    return pose2d_from_pose(pose)


def footstep_msgs(footsteps) -> list:
    return [FootstepMsg(side=int(f.side), x=float(f.x), y=float(f.y), yaw=float(f.yaw))
            for f in footsteps]


def footsteps_from_msgs(msgs) -> list:
    return [Footstep(int(m.side), float(m.x), float(m.y), float(m.yaw)) for m in msgs]


def footstep_plan_msg(update, single_support: float, double_support: float, frame_id: str,
                      stamp, request_id: int = 0) -> FootstepPlan:
    msg = FootstepPlan()
    msg.header.frame_id = frame_id
    msg.header.stamp = stamp
    msg.plan_id = int(update.plan_id)
    msg.request_id = int(request_id)
    msg.status = FootstepPlan.STATUS_OK
    msg.error_code = FootstepPlan.ERROR_NONE
    msg.continuous = bool(update.continuous)
    msg.single_support = float(single_support)
    msg.double_support = float(double_support)
    msg.footsteps = footstep_msgs(update.footsteps)
    return msg


def failed_plan_msg(plan_id: int, error_code: int, error_msg: str, frame_id: str,
                    stamp, request_id: int = 0) -> FootstepPlan:
    msg = FootstepPlan()
    msg.header.frame_id = frame_id
    msg.header.stamp = stamp
    msg.plan_id = int(plan_id)
    msg.request_id = int(request_id)
    msg.status = FootstepPlan.STATUS_FAILED
    msg.error_code = error_code
    msg.error_msg = error_msg
    return msg


def path_msg(points, frame_id: str, stamp) -> Path:
    msg = Path()
    msg.header.frame_id = frame_id
    msg.header.stamp = stamp
    for x, y in points:
        pose = PoseStamped()
        pose.header = msg.header
        pose.pose.position.x, pose.pose.position.y = float(x), float(y)
        pose.pose.orientation.w = 1.0
        msg.poses.append(pose)
    return msg


def footstep_markers(footsteps, foot_length: float, foot_width: float, frame_id: str,
                     stamp) -> MarkerArray:
    """Footsteps as flat cubes (left red, right blue), replacing the previous markers."""
    markers = MarkerArray()
    clear = Marker()
    clear.action = Marker.DELETEALL
    markers.markers.append(clear)
    for index, step in enumerate(footsteps):
        marker = Marker()
        marker.header.frame_id = frame_id
        marker.header.stamp = stamp
        marker.ns = 'footsteps'
        marker.id = index
        marker.type = Marker.CUBE
        marker.action = Marker.ADD
        marker.pose.position.x, marker.pose.position.y = float(step.x), float(step.y)
        marker.pose.position.z = 0.005
        marker.pose.orientation = quaternion_msg_from_yaw(step.yaw)
        marker.scale.x, marker.scale.y, marker.scale.z = foot_length, foot_width, 0.01
        marker.color.a = 0.8
        marker.color.r, marker.color.b = (1.0, 0.0) if step.side == LEFT else (0.0, 1.0)
        markers.markers.append(marker)
    return markers


def feet_from_sole_poses(msg, bounds: PoseBounds = PoseBounds()):
    """[left, right] Footsteps from a geometry_msgs/PoseArray of the two soles.

    :raises ValueError: unless it holds exactly two finite poses within the bounds (an
        InputError when a pose is out of bounds)
    """
    if len(msg.poses) != 2:
        raise ValueError(f'sole_poses must hold 2 poses, got {len(msg.poses)}')
    feet = []
    for side, pose in zip((LEFT, RIGHT), msg.poses):
        p, q = pose.position, pose.orientation
        check_pose(f'sole_poses[{side}]', (p.x, p.y, p.z), (q.x, q.y, q.z, q.w), bounds)
        values = (pose.position.x, pose.position.y, yaw_of_msg(pose.orientation))
        if not all(math.isfinite(v) for v in values):
            raise ValueError('sole_poses are not finite')
        feet.append(Footstep(side, *values))
    return tuple(feet)


def body_between(feet) -> Pose2D:
    """The body pose midway between two feet, with their mean heading."""
    left, right = feet
    yaw = mean_angle(left.yaw, right.yaw)  # exactly the feet's heading when they agree
    return Pose2D(0.5 * (left.x + right.x), 0.5 * (left.y + right.y),
                  yaw if -math.pi < yaw <= math.pi else wrap_angle(yaw))
