"""Forward kinematics of two 6-DOF legs: sole poses from the 12 joint angles (numpy only).

The one leg kinematics of the stack (the analytic IK, the walking controller and the model-plant
simulator use it). For a leg with joints hip yaw (z), hip roll (x), hip pitch (y), knee (y),
ankle pitch (y), ankle roll (x), zero angles giving a straight leg with the foot parallel to
the pelvis, and the right leg mirroring the left one in y:

    R_hip   = R_p R_z(q0) R_x(q1) R_y(q2)            R_knee = R_hip R_y(q3)
    ankle   = p_p + R_p d_hip + R_hip (0, 0, -a) + R_knee (0, 0, -b)
    R_foot  = R_knee R_y(q4) R_x(q5)                 sole   = ankle + R_foot d_sole

with the pelvis pose (p_p, R_p), thigh a, shank b, hip offset d_hip and ankle-to-sole d_sole of
the LegGeometry. No input validation here: it would cost more than the kinematics in a 50 Hz
loop (AnalyticLegIk.forward checks its inputs and calls this).
"""
import numpy as np

from biped_mpc.robot_model import LegGeometry
from biped_planner.rotations import yaw_of_matrix
from biped_planner.sides import LEFT, RIGHT

_MIRROR = np.array([1.0, -1.0, 1.0])


class LegKinematics:
    """Sole poses of both legs of a robot with intersecting hip axes and ankle axes.

    :param geometry: leg dimensions
    """

    def __init__(self, geometry: LegGeometry) -> None:
        hip = np.array(geometry.hip_offset, dtype=float)
        sole = np.array(geometry.ankle_to_sole, dtype=float)
        self._hip = (hip, hip * _MIRROR)
        self._sole = (sole, sole * _MIRROR)
        self._thigh = np.array([0.0, 0.0, -geometry.thigh_length])
        self._shank = np.array([0.0, 0.0, -geometry.shank_length])

    def forward(self, q: np.ndarray, pelvis_position: np.ndarray,
                pelvis_rotation: np.ndarray) -> tuple:
        """Sole poses of both legs.

        :param q: (12,) leg angles, left leg then right leg (rad)
        :param pelvis_position: (3,) pelvis position (m)
        :param pelvis_rotation: (3, 3) pelvis orientation
        :return: (left position (3,), left rotation (3, 3), right position, right rotation)
        """
        # Python floats: the rotation matrices are built from them (numpy scalars cost more)
        cos, sin = np.cos(q).tolist(), np.sin(q).tolist()
        return (self._leg(LEFT, cos[:6], sin[:6], pelvis_position, pelvis_rotation)
                + self._leg(RIGHT, cos[6:], sin[6:], pelvis_position, pelvis_rotation))

    def forward_leg(self, side: int, q: np.ndarray, pelvis_position: np.ndarray,
                    pelvis_rotation: np.ndarray) -> tuple:
        """Sole pose of one leg.

        :param side: LEFT (0) or RIGHT (1)
        :param q: (6,) angles of that leg (rad)
        :param pelvis_position: (3,) pelvis position (m)
        :param pelvis_rotation: (3, 3) pelvis orientation
        :return: (position (3,), rotation (3, 3))
        """
        return self._leg(side, np.cos(q).tolist(), np.sin(q).tolist(), pelvis_position,
                         pelvis_rotation)

    def _leg(self, side: int, c: list, s: list, pelvis_position: np.ndarray,
             pelvis_rotation: np.ndarray) -> tuple:
        rz = np.array([[c[0], -s[0], 0.0], [s[0], c[0], 0.0], [0.0, 0.0, 1.0]])
        rx = np.array([[1.0, 0.0, 0.0], [0.0, c[1], -s[1]], [0.0, s[1], c[1]]])
        ry = np.array([[c[2], 0.0, s[2]], [0.0, 1.0, 0.0], [-s[2], 0.0, c[2]]])
        hip_rotation = pelvis_rotation @ rz @ rx @ ry
        knee = np.array([[c[3], 0.0, s[3]], [0.0, 1.0, 0.0], [-s[3], 0.0, c[3]]])
        knee_rotation = hip_rotation @ knee
        ankle = (pelvis_position + pelvis_rotation @ self._hip[side]
                 + hip_rotation @ self._thigh + knee_rotation @ self._shank)
        pitch = np.array([[c[4], 0.0, s[4]], [0.0, 1.0, 0.0], [-s[4], 0.0, c[4]]])
        roll = np.array([[1.0, 0.0, 0.0], [0.0, c[5], -s[5]], [0.0, s[5], c[5]]])
        foot_rotation = knee_rotation @ pitch @ roll
        return ankle + foot_rotation @ self._sole[side], foot_rotation


def sole_pose(position: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """(4,) x, y, z (m) and heading (rad) of a sole pose."""
    return np.array([position[0], position[1], position[2], yaw_of_matrix(rotation)])
