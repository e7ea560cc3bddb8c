"""Conversions between simulator readings and ROS messages (the only message imports of
biped_sim besides its nodes)."""
from geometry_msgs.msg import PointStamped, WrenchStamped
from nav_msgs.msg import Odometry
import numpy as np
from sensor_msgs.msg import Imu, JointState

from biped_planner.rotations import quaternion_to_matrix


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
