"""Conversions between biped_msgs / standard messages and biped_planner library values.

All message imports of biped_planner live in its nodes package; the library never sees a message.
"""
import math

from biped_msgs.msg import (CommandStatus, Footstep as FootstepMsg, FootstepPlan,
                            ReferenceTrajectory, WalkCommand as WalkCommandMsg, WalkingState)
from geometry_msgs.msg import PoseStamped, Quaternion
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg, Path
import numpy as np
from visualization_msgs.msg import Marker, MarkerArray

from biped_planner.errors import MapError
from biped_planner.footsteps import Footstep, LEFT, RIGHT
from biped_planner.occupancy_grid import OccupancyGrid
from biped_planner.pose2d import Pose2D
from biped_planner.walk_command import CommandLimits, WalkCommand
from biped_planner.walking_reference import ReferenceWindow
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


def yaw_from_quaternion(q) -> float:
    """Heading of a quaternion message (rotation about z), rad."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def quaternion_from_yaw(yaw: float) -> Quaternion:
    return Quaternion(z=math.sin(0.5 * yaw), w=math.cos(0.5 * yaw))


def grid_from_msg(msg: OccupancyGridMsg) -> OccupancyGrid:
    """:raises MapError: for a rotated origin or malformed sizes and values."""
    q = msg.info.origin.orientation
    if abs(yaw_from_quaternion(q)) > 1e-6 or abs(q.x) > 1e-6 or abs(q.y) > 1e-6:
        raise MapError('map origin must not be rotated (yaw 0), got quaternion '
                       f'({q.x}, {q.y}, {q.z}, {q.w})')
    return OccupancyGrid.from_flat(np.frombuffer(bytes(np.asarray(msg.data, dtype=np.int8)),
                                                 dtype=np.int8),
                                   msg.info.width, msg.info.height, msg.info.resolution,
                                   (msg.info.origin.position.x, msg.info.origin.position.y))


def grid_to_msg(grid: OccupancyGrid, frame_id: str, stamp) -> OccupancyGridMsg:
    msg = OccupancyGridMsg()
    msg.header.frame_id = frame_id
    msg.header.stamp = stamp
    msg.info.resolution = float(grid.resolution)
    msg.info.height, msg.info.width = (int(v) for v in grid.shape)
    msg.info.origin.position.x, msg.info.origin.position.y = grid.origin
    msg.info.origin.orientation.w = 1.0
    msg.data = grid.values.astype(np.int8).ravel().tolist()
    return msg


def pose2d_from_pose(pose) -> Pose2D:
    return Pose2D(pose.position.x, pose.position.y, yaw_from_quaternion(pose.orientation))


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
        marker.pose.orientation = quaternion_from_yaw(step.yaw)
        marker.scale.x, marker.scale.y, marker.scale.z = foot_length, foot_width, 0.01
        marker.color.a = 0.8
        marker.color.r, marker.color.b = (1.0, 0.0) if step.side == LEFT else (0.0, 1.0)
        markers.markers.append(marker)
    return markers


UNBOUNDED = 1e9  # stands for +-inf in ReferenceTrajectory bounds (CDR carries inf, users read 1e9)


def reference_trajectory_msg(window, plan_id: int, dt: float, stamp) -> ReferenceTrajectory:
    """A ReferenceWindow as the flat arrays of biped_msgs/ReferenceTrajectory."""
    msg = ReferenceTrajectory()
    msg.header.stamp = stamp
    msg.plan_id = int(plan_id)
    msg.dt = float(dt)
    for prefix, array in (('zmp', window.zmp), ('hip', window.hip),
                          ('left_mass', window.left_mass), ('right_mass', window.right_mass),
                          ('zmp_min', window.zmp_min), ('zmp_max', window.zmp_max),
                          ('left_landing_min', window.left_landing_min),
                          ('left_landing_max', window.left_landing_max),
                          ('right_landing_min', window.right_landing_min),
                          ('right_landing_max', window.right_landing_max)):
        bounded = np.clip(array, -UNBOUNDED, UNBOUNDED)
        setattr(msg, prefix + '_x', bounded[:, 0])
        setattr(msg, prefix + '_y', bounded[:, 1])
    for side, foot, yaw in (('left', window.left_foot, window.left_yaw),
                            ('right', window.right_foot, window.right_yaw)):
        setattr(msg, side + '_foot_x', foot[:, 0])
        setattr(msg, side + '_foot_y', foot[:, 1])
        setattr(msg, side + '_foot_z', foot[:, 2])
        setattr(msg, side + '_foot_yaw', yaw)
    msg.support = window.support.astype(np.uint8)
    msg.step_index = window.step_index.astype(np.uint32)
    return msg


def window_from_reference_msg(msg: ReferenceTrajectory):
    """biped_msgs/ReferenceTrajectory back to a ReferenceWindow (+-1e9 bounds become +-inf).

    :raises ValueError: when the arrays have different lengths or are not finite
    """
    def pair(prefix: str, unbounded: bool = False) -> np.ndarray:
        array = np.column_stack((np.asarray(getattr(msg, prefix + '_x'), dtype=float),
                                 np.asarray(getattr(msg, prefix + '_y'), dtype=float)))
        if unbounded:
            array[array >= UNBOUNDED] = np.inf
            array[array <= -UNBOUNDED] = -np.inf
        return array

    n = len(msg.zmp_x)
    feet = {side: np.column_stack([np.asarray(getattr(msg, f'{side}_foot_{axis}'), dtype=float)
                                   for axis in 'xyz']) for side in ('left', 'right')}
    arrays = dict(
        zmp=pair('zmp'), hip=pair('hip'), left_mass=pair('left_mass'),
        right_mass=pair('right_mass'), zmp_min=pair('zmp_min'), zmp_max=pair('zmp_max'),
        left_landing_min=pair('left_landing_min', True),
        left_landing_max=pair('left_landing_max', True),
        right_landing_min=pair('right_landing_min', True),
        right_landing_max=pair('right_landing_max', True),
        left_foot=feet['left'], right_foot=feet['right'],
        left_yaw=np.asarray(msg.left_foot_yaw, dtype=float),
        right_yaw=np.asarray(msg.right_foot_yaw, dtype=float))
    for name, array in arrays.items():
        if len(array) != n:
            raise ValueError(f'reference {name} has {len(array)} samples, zmp has {n}')
        finite = array[np.abs(array) != np.inf] if 'landing' in name else array
        if not np.all(np.isfinite(finite)):
            raise ValueError(f'reference {name} is not finite')
    support = np.asarray(msg.support, dtype=np.uint8)
    step_index = np.asarray(msg.step_index, dtype=np.int64)
    if len(support) != n or len(step_index) != n or not np.isfinite(msg.dt) or msg.dt <= 0.0:
        raise ValueError(f'reference support/step_index/dt malformed (n={n}, dt={msg.dt})')
    t0 = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
    return ReferenceWindow(t=t0 + msg.dt * np.arange(n), support=support, step_index=step_index,
                           **arrays)


def feet_from_sole_poses(msg):
    """[left, right] Footsteps from a geometry_msgs/PoseArray of the two soles.

    :raises ValueError: unless it holds exactly two finite poses
    """
    if len(msg.poses) != 2:
        raise ValueError(f'sole_poses must hold 2 poses, got {len(msg.poses)}')
    feet = []
    for side, pose in zip((LEFT, RIGHT), msg.poses):
        values = (pose.position.x, pose.position.y, yaw_from_quaternion(pose.orientation))
        if not all(math.isfinite(v) for v in values):
            raise ValueError('sole_poses are not finite')
        feet.append(Footstep(side, *values))
    return tuple(feet)


def body_between(feet) -> Pose2D:
    """The body pose midway between two feet, with their mean heading."""
    left, right = feet
    yaw = math.atan2(math.sin(left.yaw) + math.sin(right.yaw),
                     math.cos(left.yaw) + math.cos(right.yaw))
    return Pose2D(0.5 * (left.x + right.x), 0.5 * (left.y + right.y), yaw)
