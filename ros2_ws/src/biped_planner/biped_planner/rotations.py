"""Rotations of the whole stack: quaternions (x, y, z, w, the ROS order), matrices, headings.

One module so that every package converts the same way; each function is checked against
scipy.spatial.transform.Rotation in test_rotations.py.
"""
import math

import numpy as np


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b of 3-vectors or of (n, 3) rows: np.cross's products and differences, without its
    dispatch, which costs more than the product on a few vectors (sensing, F/T filtering)."""
    if np.ndim(a) == 1 and np.ndim(b) == 1 and len(a) == 3 and len(b) == 3:
        # Two 3-vectors, the controller's usual case: the same IEEE products on Python floats.
        a0, a1, a2 = a.tolist() if isinstance(a, np.ndarray) else a
        b0, b1, b2 = b.tolist() if isinstance(b, np.ndarray) else b
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def quaternion_to_matrix(quaternion) -> np.ndarray:
    """Rotation matrix of a unit quaternion.

    :param quaternion: (4,) unit quaternion (x, y, z, w)
    :return: (3, 3) rotation matrix
    """
    x, y, z, w = quaternion
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def yaw_of_quaternion(quaternion) -> float:
    """Heading (rotation about the world z axis, Z-Y-X Euler yaw) of a quaternion.

    :param quaternion: (4,) quaternion (x, y, z, w), normalised or not
    :return: yaw in (-pi, pi] (rad)
    """
    x, y, z, w = quaternion
    return math.atan2(2.0 * (w * z + x * y), w * w + x * x - y * y - z * z)


def yaw_of_matrix(rotation: np.ndarray) -> float:
    """Heading (Z-Y-X Euler yaw) of a rotation matrix (rad)."""
    return math.atan2(rotation[1, 0], rotation[0, 0])


def roll_pitch_of_matrix(rotation: np.ndarray) -> tuple:
    """(roll, pitch) of the Z-Y-X Euler angles of a rotation matrix (rad)."""
    return (math.atan2(rotation[2, 1], rotation[2, 2]),
            math.atan2(-rotation[2, 0], math.hypot(rotation[2, 1], rotation[2, 2])))


def roll_pitch_of_zxy_matrix(rotation: np.ndarray) -> np.ndarray:
    """(2,) roll and pitch (rad) of R = Rz(yaw) Rx(roll) Ry(pitch), the order in which the leg
    IK composes its sole targets (roll_pitch_of_matrix is the Z-Y-X order); yaw does not enter."""
    return np.array([math.asin(max(-1.0, min(1.0, float(rotation[2, 1])))),
                     math.atan2(-float(rotation[2, 0]), float(rotation[2, 2]))])


def quaternion_from_yaw(yaw: float) -> np.ndarray:
    """(4,) quaternion (x, y, z, w) of a rotation by yaw about z."""
    return np.array([0.0, 0.0, math.sin(0.5 * yaw), math.cos(0.5 * yaw)])


def rotation_x(angle: float) -> np.ndarray:
    """(3, 3) rotation about x by angle (rad)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rotation_y(angle: float) -> np.ndarray:
    """(3, 3) rotation about y by angle (rad)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rotation_z(angle: float) -> np.ndarray:
    """(3, 3) rotation about z by angle (rad)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def tilt_of_quaternion(quaternion) -> float:
    """Angle between the body z axis and the world z axis (rad), whatever the heading."""
    x, y, _, _ = quaternion
    return math.acos(max(-1.0, min(1.0, 1.0 - 2.0 * (x * x + y * y))))


def wrap_angle(angle: float) -> float:
    """Angle wrapped to [-pi, pi) (rad)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def mean_angle(a: float, b: float) -> float:
    """The angle midway between a and b along the shorter arc (rad)."""
    return a + 0.5 * math.atan2(math.sin(b - a), math.cos(b - a))
