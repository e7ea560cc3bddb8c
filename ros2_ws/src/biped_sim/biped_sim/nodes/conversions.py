"""Conversions between simulator readings and ROS messages (the only message imports of
biped_sim besides its nodes)."""
import math

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PointStamped, WrenchStamped
from nav_msgs.msg import Odometry
import numpy as np
from sensor_msgs.msg import Imu, JointState

from biped_planner.rotations import quaternion_to_matrix, yaw_of_quaternion
from biped_sim.joint_limits import check_setpoints

MAX_MAP_RESOLUTION = 100.0  # m per cell
MAX_MAP_ORIGIN = 1e5  # m


def joint_state_msg(joints, stamp) -> JointState:
    msg = JointState()
    msg.header.stamp = stamp
    msg.name = list(joints.names)
    msg.position = np.asarray(joints.position, dtype=float).tolist()
    msg.velocity = np.asarray(joints.velocity, dtype=float).tolist()
    msg.effort = np.asarray(joints.torque, dtype=float).tolist()
    return msg


def imu_msg(imu, frame_id: str, stamp) -> Imu:
    msg = Imu()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    (msg.orientation.x, msg.orientation.y, msg.orientation.z,
     msg.orientation.w) = (float(v) for v in imu.orientation)
    (msg.angular_velocity.x, msg.angular_velocity.y,
     msg.angular_velocity.z) = (float(v) for v in imu.angular_velocity)
    (msg.linear_acceleration.x, msg.linear_acceleration.y,
     msg.linear_acceleration.z) = (float(v) for v in imu.linear_acceleration)
    return msg


def odometry_msg(base, frame_id: str, child_frame_id: str, stamp) -> Odometry:
    """Ground-truth pose of the pelvis in frame_id and its twist in the pelvis frame
    (child_frame_id), as nav_msgs/Odometry specifies."""
    msg = Odometry()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.child_frame_id = child_frame_id
    pose = msg.pose.pose
    pose.position.x, pose.position.y, pose.position.z = (float(v) for v in base.position)
    (pose.orientation.x, pose.orientation.y, pose.orientation.z,
     pose.orientation.w) = (float(v) for v in base.orientation)
    to_body = quaternion_to_matrix([float(v) for v in base.orientation]).T
    twist = msg.twist.twist
    twist.linear.x, twist.linear.y, twist.linear.z = (
        float(v) for v in to_body @ np.asarray(base.linear_velocity, dtype=float))
    twist.angular.x, twist.angular.y, twist.angular.z = (
        float(v) for v in to_body @ np.asarray(base.angular_velocity, dtype=float))
    return msg


def wrench_msg(foot, frame_id: str, stamp) -> WrenchStamped:
    """The ankle F/T sensor reading, in the sensor frame."""
    msg = WrenchStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z = (
        float(v) for v in foot.sensor_force)
    msg.wrench.torque.x, msg.wrench.torque.y, msg.wrench.torque.z = (
        float(v) for v in foot.sensor_torque)
    return msg


def point_msg(xyz, frame_id: str, stamp) -> PointStamped:
    msg = PointStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    values = [float(v) for v in xyz] + [0.0] * (3 - len(xyz))
    msg.point.x, msg.point.y, msg.point.z = values[:3]
    return msg


def setpoints_from_joint_state(msg: JointState, names: tuple, current: np.ndarray) -> np.ndarray:
    """Joint setpoints in the simulator's order from a JointState naming some of its joints.

    :param names: the simulator's joint order
    :param current: setpoints kept for the joints the message does not name
    :raises ValueError: for unknown joint names, mismatched lengths or non-finite values
    """
    if len(msg.name) != len(msg.position):
        raise ValueError(f'{len(msg.name)} names but {len(msg.position)} positions')
    index = {name: i for i, name in enumerate(names)}
    unknown = [name for name in msg.name if name not in index]
    if unknown:
        raise ValueError(f'unknown joints {unknown}')
    values = np.asarray(msg.position, dtype=float)
    if not np.all(np.isfinite(values)):
        raise ValueError('joint setpoints are not finite')
    setpoints = np.array(current, dtype=float)
    setpoints[[index[name] for name in msg.name]] = values
    return setpoints


def checked_command(msg: JointState, names: tuple, current: np.ndarray, limits: tuple,
                    margin: float, max_velocity: float) -> tuple:
    """The setpoints and feed-forward speeds of a joint command, checked.

    :param names: the simulator's joint order
    :param current: setpoints kept for the joints the message does not name
    :param limits: (lower, upper) position limits in that order (rad)
    :param margin: how far past a limit a setpoint may be (rad)
    :param max_velocity: largest feed-forward speed (rad/s)
    :return: (setpoints, velocities), both in the simulator's order
    :raises ValueError: for no joint, unknown joints, mismatched lengths, values that are not
        finite, setpoints past the limits or speeds above max_velocity
    """
    if not msg.name:
        raise ValueError('it names no joint')
    setpoints = setpoints_from_joint_state(msg, names, current)
    check_setpoints(names, setpoints, *limits, margin)
    velocities = np.zeros(len(names))
    if len(msg.velocity) and len(msg.velocity) != len(msg.name):
        raise ValueError(f'{len(msg.name)} names but {len(msg.velocity)} velocities')
    if len(msg.velocity):
        velocities = setpoints_from_joint_state(
            JointState(name=msg.name, position=msg.velocity), names, velocities)
        fastest = float(np.max(np.abs(velocities)))
        if fastest > max_velocity:
            raise ValueError(f'a joint speed of {fastest:.4g} rad/s (> {max_velocity})')
    return setpoints, velocities


def occupied_cells_from_map(msg, frame_id: str):
    """The occupied cells of a nav_msgs/OccupancyGrid, checked.

    :param frame_id: the frame the map must be in
    :return: ((rows, cols) bool array of cells >= 50, resolution (m), origin (x, y) (m))
    :raises ValueError: naming what is malformed: frame, resolution, origin (not finite, rotated
        or not a unit quaternion), data size or cell values outside [-1, 100]
    """
    info = msg.info
    if msg.header.frame_id != frame_id:
        raise ValueError(f'frame_id {msg.header.frame_id!r}, expected {frame_id!r}')
    if not (math.isfinite(info.resolution) and 0.0 < info.resolution <= MAX_MAP_RESOLUTION):
        raise ValueError(f'resolution {info.resolution!r} must be in (0, {MAX_MAP_RESOLUTION}] m')
    p, q = info.origin.position, info.origin.orientation
    origin = (p.x, p.y, p.z)
    if not all(math.isfinite(v) and abs(v) <= MAX_MAP_ORIGIN for v in origin):
        raise ValueError(f'origin {origin} must be finite, within {MAX_MAP_ORIGIN} m')
    quaternion = (q.x, q.y, q.z, q.w)
    if not all(math.isfinite(v) for v in quaternion) or \
            abs(math.sqrt(sum(v * v for v in quaternion)) - 1.0) > 0.01:
        raise ValueError(f'origin orientation {quaternion} is not a unit quaternion')
    if abs(yaw_of_quaternion(quaternion)) > 1e-6 or abs(q.x) + abs(q.y) > 1e-6:
        raise ValueError('a rotated map origin is not supported (obstacles are axis-aligned)')
    if info.width < 1 or info.height < 1:
        raise ValueError(f'{info.width} x {info.height} cells: a map has at least one')
    values = np.asarray(msg.data, dtype=np.int16)
    if values.size != info.width * info.height:
        raise ValueError(f'{values.size} cells for {info.width} x {info.height}')
    if values.size and (values.min() < -1 or values.max() > 100):
        raise ValueError('cell values must be in [-1, 100]')
    return values.reshape(info.height, info.width) >= 50, info.resolution, origin[:2]


def diagnostics_msg(stamp, name: str, hardware_id: str, level: bytes, message: str,
                    values: dict) -> DiagnosticArray:
    """A diagnostic_msgs/DiagnosticArray with one status."""
    status = DiagnosticStatus(level=level, name=name, message=message, hardware_id=hardware_id,
                              values=[KeyValue(key=k, value=str(v)) for k, v in values.items()])
    msg = DiagnosticArray(status=[status])
    msg.header.stamp = stamp
    return msg
