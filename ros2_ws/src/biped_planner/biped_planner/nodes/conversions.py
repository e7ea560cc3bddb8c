"""Conversions between biped_msgs / standard messages and biped_planner library values.

All message imports of biped_planner live in its nodes package; the library never sees a message.
"""
import array
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
# ReferenceTrajectory's float64[] fields as (ReferenceWindow field, its columns): the feet first,
# then the (N, 2) arrays, which are sent clipped to +-UNBOUNDED.
REFERENCE_FEET = (('left_foot', ('left_foot_x', 'left_foot_y', 'left_foot_z')),
                  ('left_yaw', ('left_foot_yaw',)),
                  ('right_foot', ('right_foot_x', 'right_foot_y', 'right_foot_z')),
                  ('right_yaw', ('right_foot_yaw',)))
REFERENCE_PAIRS = tuple((name, (name + '_x', name + '_y')) for name in (
    'zmp', 'hip', 'left_mass', 'right_mass', 'zmp_min', 'zmp_max', 'left_landing_min',
    'left_landing_max', 'right_landing_min', 'right_landing_max'))
REFERENCE_ARRAYS = REFERENCE_FEET + REFERENCE_PAIRS
REFERENCE_COLUMNS = tuple(column for _, columns in REFERENCE_ARRAYS for column in columns)
REFERENCE_ROW_ARRAY = tuple(name for name, columns in REFERENCE_ARRAYS for _ in columns)
FIRST_PAIR_COLUMN = sum(len(columns) for _, columns in REFERENCE_FEET)
FIRST_LANDING_COLUMN = REFERENCE_COLUMNS.index('left_landing_min_x')  # landing bounds last


def reference_trajectory_msg(window, plan_id: int, dt: float, stamp) -> ReferenceTrajectory:
    """A ReferenceWindow as the flat arrays of biped_msgs/ReferenceTrajectory."""
    msg = ReferenceTrajectory()
    msg.header.stamp = stamp
    msg.plan_id = int(plan_id)
    msg.dt = float(dt)
    n = len(window.t)
    table = np.empty((len(REFERENCE_COLUMNS), n))
    row = 0
    for name, columns in REFERENCE_ARRAYS:
        table[row:row + len(columns)] = np.reshape(getattr(window, name), (n, -1)).T
        row += len(columns)
    np.clip(table[FIRST_PAIR_COLUMN:], -UNBOUNDED, UNBOUNDED, out=table[FIRST_PAIR_COLUMN:])
    # Copied as bytes: the message setters convert anything but an array.array element by
    # element (10 us a field, 36 fields a message).
    for column, values in zip(REFERENCE_COLUMNS, table):
        setattr(msg, column, array.array('d', values.tobytes()))
    msg.support = array.array('B', np.asarray(window.support, dtype=np.uint8).tobytes())
    msg.step_index = array.array('I', np.asarray(window.step_index, dtype=np.uint32).tobytes())
    return msg


def window_from_reference_msg(msg: ReferenceTrajectory):
    """biped_msgs/ReferenceTrajectory back to a ReferenceWindow (+-1e9 bounds become +-inf).

    :raises ValueError: when the arrays have different lengths or are not finite
    """
    n = len(msg.zmp_x)
    fields = [getattr(msg, column) for column in REFERENCE_COLUMNS]
    for row, values in enumerate(fields):
        if len(values) != n:
            raise ValueError(f'reference {REFERENCE_ROW_ARRAY[row]} has {len(values)} samples, '
                             f'zmp has {n}')
    # float64[] fields are array.array('d'): their buffers joined make the table in one copy
    table = np.frombuffer(b''.join(fields), dtype=float).reshape(len(fields), n).copy()
    landing = table[FIRST_LANDING_COLUMN:]  # +-inf: the leg is in stance
    landing[landing >= UNBOUNDED] = np.inf
    landing[landing <= -UNBOUNDED] = -np.inf
    valid = np.isfinite(table)
    valid[FIRST_LANDING_COLUMN:] = ~np.isnan(landing)
    if not valid.all():
        row = int(np.argmin(valid.all(axis=1)))
        raise ValueError(f'reference {REFERENCE_ROW_ARRAY[row]} is not finite')
    arrays, row = {}, 0
    for name, columns in REFERENCE_ARRAYS:
        arrays[name] = table[row] if len(columns) == 1 else table[row:row + len(columns)].T
        row += len(columns)
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
