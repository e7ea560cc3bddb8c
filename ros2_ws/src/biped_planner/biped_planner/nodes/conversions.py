"""Conversions between biped_msgs / standard messages and biped_planner library values.

All message imports of biped_planner live in its nodes package; the library never sees a message.
"""
import math

from biped_msgs.msg import (CommandStatus, Footstep as FootstepMsg, FootstepPlan,
                            WalkCommand as WalkCommandMsg, WalkingState)
from geometry_msgs.msg import PoseStamped, Quaternion
from nav_msgs.msg import Path
from visualization_msgs.msg import Marker, MarkerArray

from biped_planner.footsteps import Footstep
from biped_planner.pose2d import Pose2D
from biped_planner.rotations import mean_angle, quaternion_from_yaw, wrap_angle, yaw_of_quaternion
from biped_planner.sides import LEFT, RIGHT
from biped_planner.walk_command import CommandLimits, WalkCommand
from biped_planner.walking_state_machine import WalkingStatus


def walk_command_from_msg(msg: WalkCommandMsg, limits: CommandLimits) -> WalkCommand:
    """:raises CommandError: when a field is unknown, not finite or out of range."""
    return WalkCommand.from_fields(
        msg.command, (msg.goal_x, msg.goal_y, msg.goal_yaw),
        (msg.step_length, msg.step_width, msg.step_angle), msg.step_time, limits)


def walking_state_msg(status: WalkingStatus, now: float, stamp, plan_id: int,
                      inputs_stale: bool) -> WalkingState:
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
    msg.inputs_stale = inputs_stale
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


def footstep_msgs(footsteps) -> list:
    return [FootstepMsg(side=int(f.side), x=float(f.x), y=float(f.y), yaw=float(f.yaw))
            for f in footsteps]


def footsteps_from_msgs(msgs) -> list:
    return [Footstep(int(m.side), float(m.x), float(m.y), float(m.yaw)) for m in msgs]


def footstep_plan_msg(update, single_support: float, double_support: float, frame_id: str,
                      stamp) -> FootstepPlan:
    msg = FootstepPlan()
    msg.header.frame_id = frame_id
    msg.header.stamp = stamp
    msg.plan_id = int(update.plan_id)
    msg.status = FootstepPlan.STATUS_OK
    msg.error_code = FootstepPlan.ERROR_NONE
    msg.continuous = bool(update.continuous)
    msg.single_support = float(single_support)
    msg.double_support = float(double_support)
    msg.footsteps = footstep_msgs(update.footsteps)
    return msg


def failed_plan_msg(plan_id: int, error_code: int, error_msg: str, frame_id: str,
                    stamp) -> FootstepPlan:
    msg = FootstepPlan()
    msg.header.frame_id = frame_id
    msg.header.stamp = stamp
    msg.plan_id = int(plan_id)
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


def feet_from_sole_poses(msg):
    """[left, right] Footsteps from a geometry_msgs/PoseArray of the two soles.

    :raises ValueError: unless it holds exactly two finite poses
    """
    if len(msg.poses) != 2:
        raise ValueError(f'sole_poses must hold 2 poses, got {len(msg.poses)}')
    feet = []
    for side, pose in zip((LEFT, RIGHT), msg.poses):
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
