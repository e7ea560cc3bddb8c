"""Exact analytic inverse kinematics of two 6-DOF legs (Kajita-style), numpy only.

The paper's controller turns the MPC's hip and feet trajectories into joint setpoints with an
inverse kinematics that respects kinematic feasibility ("Architecture"). For a leg whose three
hip axes intersect at the hip centre H and whose two ankle axes intersect at the ankle centre A,
with joints hip yaw (z), hip roll (x), hip pitch (y), knee (y), ankle pitch (y), ankle roll (x),
thigh a, shank b, and zero angles giving a straight leg with the foot parallel to the pelvis:

    r = R_f^T (H - A)                               hip seen from the ankle, foot axes
    knee        = acos((|r|^2 - a^2 - b^2) / (2 a b))          (>= 0, bent forward)
    ankle roll  = atan(r_y / r_z)                       (the branch in (-pi/2, pi/2))
    ankle pitch = atan2(v_x, v_z) - atan2(r_x, sign(r_z) sqrt(r_y^2 + r_z^2)),
                  v = (-a sin(knee), a cos(knee) + b)
    R_z(yaw) R_x(roll) R_y(pitch) = R_p^T R_f R_x(-ankle roll) R_y(-(knee + ankle pitch))

with H = p_p + R_p d_hip (pelvis pose p_p, R_p) and A = p_s - R_f d_sole (sole pose p_s, R_f).
A target beyond reach has its ankle moved along the hip-ankle line to the nearest reachable
distance, and every angle is clipped to its joint limits; the solution then reports CLIPPED.
"""

from dataclasses import dataclass
import math

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.leg_kinematics import LegKinematics
from biped_mpc.robot_model import LegGeometry
from biped_mpc.validation import finite_array, validated_pose
from biped_planner.rotations import rotation_x, rotation_y
from biped_planner.sides import LEFT, RIGHT

IK_REACHABLE = 0
IK_CLIPPED = 1


@dataclass(frozen=True)
class LegIkSolution:
    """Joint angles of both legs and whether the targets were met.

    :param q: (12,) left hip yaw, roll, pitch, knee, ankle pitch, roll, then the right leg (rad).
    :param status: (left, right) IK_REACHABLE or IK_CLIPPED.
    """

    q: np.ndarray
    status: tuple

    @property
    def reachable(self) -> bool:
        """True when both legs reached their targets exactly."""
        return self.status[0] == IK_REACHABLE and self.status[1] == IK_REACHABLE


class AnalyticLegIk:
    """Closed-form IK of both legs (see the module docstring for the equations).

    :param geometry: leg dimensions.
    """

    def __init__(self, geometry):
        if not isinstance(geometry, LegGeometry):
            raise ConfigError(f'geometry must be a LegGeometry, got {type(geometry).__name__}')
        self._geometry = geometry
        self._kinematics = LegKinematics(geometry)
        g = self._geometry
        mirror = np.array([1.0, -1.0, 1.0])
        self._hip = (np.array(g.hip_offset), np.array(g.hip_offset) * mirror)
        self._sole = (np.array(g.ankle_to_sole), np.array(g.ankle_to_sole) * mirror)
        self._lower = np.array(g.joint_lower).reshape(2, 6)
        self._upper = np.array(g.joint_upper).reshape(2, 6)
        a, b = g.thigh_length, g.shank_length
        knee_low = max(self._lower[:, 3].max(), 0.0)
        knee_high = min(self._upper[:, 3].min(), math.pi)
        # Reachable hip-ankle distances for the knee range (law of cosines).
        self._reach_max = math.sqrt(a * a + b * b + 2 * a * b * math.cos(knee_low))
        self._reach_min = math.sqrt(a * a + b * b + 2 * a * b * math.cos(knee_high))

    @property
    def geometry(self) -> LegGeometry:
        """The leg dimensions."""
        return self._geometry

    def solve(self, pelvis_position, pelvis_rotation, left_position, left_rotation,
              right_position, right_rotation) -> LegIkSolution:
        """Return the 12 leg angles putting the soles at their targets for a pelvis pose.

        :param pelvis_position: (3,) pelvis (base) frame position in the world (m).
        :param pelvis_rotation: (3, 3) pelvis orientation.
        :param left_position: (3,) left sole centre target (m).
        :param left_rotation: (3, 3) left sole orientation target.
        :param right_position: (3,) right sole centre target (m).
        :param right_rotation: (3, 3) right sole orientation target.
        :return: the solution; status IK_CLIPPED for a leg whose target was out of reach or
            of its joint limits (its angles then give the nearest feasible pose).
        :raises InputError: for wrong shapes or NaN/inf.
        """
        p, r = validated_pose('pelvis', pelvis_position, pelvis_rotation)
        left = validated_pose('left sole', left_position, left_rotation)
        right = validated_pose('right sole', right_position, right_rotation)
        q_left, s_left = self._solve_leg(LEFT, p, r, *left)
        q_right, s_right = self._solve_leg(RIGHT, p, r, *right)
        return LegIkSolution(np.concatenate([q_left, q_right]), (s_left, s_right))

    def solve_leg(self, side: int, pelvis_position, pelvis_rotation, sole_position,
                  sole_rotation) -> tuple:
        """Return (q (6,), status) of one leg; see solve.

        :param side: LEFT (0) or RIGHT (1).
        :raises InputError: for a bad side, wrong shapes or NaN/inf.
        """
        if side not in (LEFT, RIGHT):
            raise InputError('side = %r must be LEFT (0) or RIGHT (1)' % (side,))
        p, r = validated_pose('pelvis', pelvis_position, pelvis_rotation)
        s, rs = validated_pose('sole', sole_position, sole_rotation)
        return self._solve_leg(side, p, r, s, rs)

    def _solve_leg(self, side: int, pelvis_p: np.ndarray, pelvis_r: np.ndarray,
                   sole_p: np.ndarray, sole_r: np.ndarray) -> tuple:
        g = self._geometry
        a, b = g.thigh_length, g.shank_length
        hip = pelvis_p + pelvis_r @ self._hip[side]
        ankle = sole_p - sole_r @ self._sole[side]
        r = sole_r.T @ (hip - ankle)
        clipped = False
        distance = math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
        if distance > self._reach_max or distance < self._reach_min:
            target = min(max(distance, self._reach_min), self._reach_max)
            r = (r * (target / distance) if distance > 1e-12
                 else np.array([0.0, 0.0, target]))
            distance = target
            clipped = True
        cos_knee = (distance * distance - a * a - b * b) / (2.0 * a * b)
        knee = math.acos(min(max(cos_knee, -1.0), 1.0))
        # The ankle roll branch in (-pi/2, pi/2): the hip may sit below the ankle in foot axes.
        if r[2] >= 0.0:
            ankle_roll = math.atan2(r[1], r[2])
        else:
            ankle_roll = math.atan2(-r[1], -r[2])
        wz = math.copysign(math.sqrt(r[1] * r[1] + r[2] * r[2]), r[2])
        ankle_pitch = (math.atan2(-a * math.sin(knee), a * math.cos(knee) + b)
                       - math.atan2(r[0], wz))
        hip_r = (pelvis_r.T @ sole_r @ rotation_x(-ankle_roll)
                 @ rotation_y(-(knee + ankle_pitch)))
        hip_roll = math.asin(min(max(hip_r[2, 1], -1.0), 1.0))
        hip_yaw = math.atan2(-hip_r[0, 1], hip_r[1, 1])
        hip_pitch = math.atan2(-hip_r[2, 0], hip_r[2, 2])
        q = np.array([hip_yaw, hip_roll, hip_pitch, knee, ankle_pitch, ankle_roll])
        q_clipped = np.minimum(np.maximum(q, self._lower[side]), self._upper[side])
        if clipped or np.any(q_clipped != q):
            return q_clipped, IK_CLIPPED
        return q, IK_REACHABLE

    def forward_leg(self, side: int, q, pelvis_position=(0.0, 0.0, 0.0),
                    pelvis_rotation=np.eye(3)) -> tuple:
        """Return the sole pose (position (3,), rotation (3, 3)) of one leg's angles (checked
        inputs, then biped_mpc.leg_kinematics).

        :param side: LEFT (0) or RIGHT (1).
        :param q: (6,) angles of that leg (rad).
        :param pelvis_position: (3,) pelvis position (m).
        :param pelvis_rotation: (3, 3) pelvis orientation.
        :raises InputError: for a bad side, wrong shapes or NaN/inf.
        """
        if side not in (LEFT, RIGHT):
            raise InputError('side = %r must be LEFT (0) or RIGHT (1)' % (side,))
        q = np.asarray(q, dtype=float)
        if q.shape != (6,) or not np.all(np.isfinite(q)):
            raise InputError('q = %r must be 6 finite angles' % (q,))
        p, r = validated_pose('pelvis', pelvis_position, pelvis_rotation)
        return self._kinematics.forward_leg(side, q, p, r)

    def forward(self, q, pelvis_position=(0.0, 0.0, 0.0), pelvis_rotation=np.eye(3)) -> tuple:
        """Return (left position, left rotation, right position, right rotation) of 12 angles.

        :param q: (12,) leg angles, left then right (rad).
        :param pelvis_position: (3,) pelvis position (m).
        :param pelvis_rotation: (3, 3) pelvis orientation.
        :raises InputError: for wrong shapes or NaN/inf.
        """
        q = finite_array('q', q, (12,))
        left = self.forward_leg(LEFT, q[:6], pelvis_position, pelvis_rotation)
        right = self.forward_leg(RIGHT, q[6:], pelvis_position, pelvis_rotation)
        return left + right
