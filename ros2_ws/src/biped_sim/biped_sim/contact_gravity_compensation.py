"""Gravity compensation of a standing or stepping humanoid, with the weight carried by its feet.

For a floating-base robot at rest the joint torques that hold it against gravity are

    tau = g_j(q) - sum_i J_i(q)^T w_i,

with g_j the joint rows of the generalised gravity vector g(q) = M g dz_com/dq (the third row
of the centre-of-mass Jacobian of a free-flyer model, scaled by the weight), J_i the 6 x n_v
Jacobian of sole i in world-aligned axes and w_i the wrench the ground applies on foot i at the
sole centre. The weight M g is split between the feet so that the total centre of pressure is
the ground projection of the centre of mass c (a minimum-norm split tips the robot):

    t = clip(((c - s_R) . (s_L - s_R)) / |s_L - s_R|^2, 0, 1),  f_L = t M g,  f_R = (1 - t) M g,

each force applied vertically at its sole centre shifted by the offset of c from the segment
s_R s_L (clipped to the scaled sole), so sum_i f_i p_i = M g c when c is above the feet. A foot
out of contact carries nothing; with one foot in contact it carries the whole weight under c.
"""

import math

import numpy as np

from biped_planner.rotations import yaw_of_matrix

from biped_sim.errors import RobotModelError

try:
    import pinocchio as pin
except ImportError as error:  # pragma: no cover - pinocchio is a hard dependency
    raise ImportError('biped_sim.contact_gravity_compensation needs pinocchio: '
                      'pip install pin') from error


def left_share(point, left, right) -> float:
    """The lever rule between two feet: the share of a vertical load at point on the left foot.

    t = clip(((p - s_R) . (s_L - s_R)) / |s_L - s_R|^2, 0, 1), 1/2 when the feet coincide.

    :param point: (2,) where the load acts, in the ground plane (m).
    :param left: left sole centre, (2,) or (3,) (m); only x and y are used.
    :param right: right sole centre (m).
    :return: t in [0, 1]; the right foot carries 1 - t.
    """
    ax, ay = left[0] - right[0], left[1] - right[1]
    length_sq = ax * ax + ay * ay
    if length_sq < 1e-12:
        return 0.5
    t = ((point[0] - right[0]) * ax + (point[1] - right[1]) * ay) / length_sq
    return min(max(t, 0.0), 1.0)


def sole_rectangle_clip(offset_x: float, offset_y: float, yaw: float, half_length: float,
                        half_width: float) -> tuple:
    """Clip a horizontal offset from a sole centre into the sole rectangle.

    :param offset_x: world x of the offset (m).
    :param offset_y: world y of the offset (m).
    :param yaw: heading of the sole (rad).
    :param half_length: half of the usable sole length (m).
    :param half_width: half of the usable sole width (m).
    :return: (x, y) clipped offset in the world (m).
    """
    c, s = math.cos(yaw), math.sin(yaw)
    local_x = min(max(c * offset_x + s * offset_y, -half_length), half_length)
    local_y = min(max(-s * offset_x + c * offset_y, -half_width), half_width)
    return c * local_x - s * local_y, s * local_x + c * local_y


class ContactGravityCompensation:
    """Joint torques holding a humanoid against gravity with its weight on its feet (see module).

    :param urdf_path: the robot's URDF.
    :param joint_names: actuated joints in the caller's order (the order of q and of the torques).
    :param sole_frames: (left, right) sole frame (link) names.
    :param sole_length: sole length (m), the usable part is scaled by support_scale.
    :param sole_width: sole width (m).
    :param gravity: gravity acceleration (m/s^2).
    :param support_scale: fraction of the sole where the shifted forces may act.
    :raises RobotModelError: if a joint or sole frame is missing from the URDF.
    """

    def __init__(self, urdf_path: str, joint_names, sole_frames, sole_length: float,
                 sole_width: float, gravity: float = 9.81, support_scale: float = 0.8):
        self._model = pin.buildModelFromUrdf(str(urdf_path), pin.JointModelFreeFlyer())
        self._model.gravity.linear = np.array([0.0, 0.0, -gravity])
        self._data = self._model.createData()
        q_index, v_index = [], []
        for name in joint_names:
            if not self._model.existJointName(name):
                raise RobotModelError('joint %r is not in %s' % (name, urdf_path))
            joint = self._model.joints[self._model.getJointId(name)]
            if joint.nq != 1 or joint.nv != 1:
                raise RobotModelError('joint %r is not a 1-DOF joint' % name)
            q_index.append(joint.idx_q)
            v_index.append(joint.idx_v)
        self._q_index = np.array(q_index)
        self._v_index = np.array(v_index)
        self._sole_ids = []
        for frame in sole_frames:
            if not self._model.existFrame(frame):
                raise RobotModelError('sole frame %r is not in %s' % (frame, urdf_path))
            self._sole_ids.append(self._model.getFrameId(frame))
        self._q = pin.neutral(self._model)
        self._weight = float(sum(i.mass for i in self._model.inertias)) * gravity
        self._half_length = 0.5 * support_scale * sole_length
        self._half_width = 0.5 * support_scale * sole_width
        self._world_aligned = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    @property
    def total_mass(self) -> float:
        """Mass of the robot (kg) from the URDF."""
        return float(sum(i.mass for i in self._model.inertias))

    def _set_configuration(self, base_position, base_quaternion, joint_positions) -> np.ndarray:
        q = self._q
        q[0:3] = base_position
        q[3:7] = base_quaternion
        q[self._q_index] = joint_positions
        return q

    def joint_inertia_diagonal(self, base_position, base_quaternion,
                               joint_positions) -> np.ndarray:
        """Return the diagonal of the joint-space inertia matrix for the actuated joints.

        :param base_position: (3,) base frame position (m).
        :param base_quaternion: (4,) base orientation (x, y, z, w).
        :param joint_positions: (n,) actuated joint angles, caller's order (rad).
        :return: (n,) M_jj (kg m^2) of the floating-base mass matrix (crba).
        """
        q = self._set_configuration(base_position, base_quaternion, joint_positions)
        mass_matrix = pin.crba(self._model, self._data, q)
        return mass_matrix[self._v_index, self._v_index].copy()

    def split_weight(self, com_xy, soles, sole_yaws, contacts) -> tuple:
        """Return the vertical foot forces and their points (the COM-following split).

        :param com_xy: (2,) ground projection of the centre of mass (m).
        :param soles: (left, right) sole centre positions (3,) (m).
        :param sole_yaws: (left, right) sole headings (rad).
        :param contacts: (left, right) contact flags.
        :return: (forces (2,) N, points (2, 3) m) for left and right.
        """
        soles = [[float(v) for v in sole] for sole in soles]
        loads = self._vertical_loads(float(com_xy[0]), float(com_xy[1]), soles, sole_yaws,
                                     contacts)
        forces = np.array([load[0] for load in loads])
        points = np.array([[x, y, sole[2]] for (_, x, y), sole in zip(loads, soles)],
                          dtype=float)
        return forces, points

    def _vertical_loads(self, cx: float, cy: float, soles, sole_yaws, contacts) -> tuple:
        """split_weight on Python floats (it runs at every physics step).

        :param soles: (left, right) sole centres as lists of floats (m).
        :return: ((f, x, y) of the left foot, (f, x, y) of the right foot).
        """
        left, right = soles
        if contacts[0] and contacts[1]:
            ax, ay = left[0] - right[0], left[1] - right[1]
            t = left_share((cx, cy), left, right)
            offset_x = cx - (right[0] + t * ax)
            offset_y = cy - (right[1] + t * ay)
            loads = []
            for sole, yaw, force in ((left, sole_yaws[0], t * self._weight),
                                     (right, sole_yaws[1], (1.0 - t) * self._weight)):
                dx, dy = sole_rectangle_clip(offset_x, offset_y, yaw, self._half_length,
                                             self._half_width)
                loads.append((force, sole[0] + dx, sole[1] + dy))
            return tuple(loads)
        loads = [(0.0, left[0], left[1]), (0.0, right[0], right[1])]
        if contacts[0] or contacts[1]:
            i = 0 if contacts[0] else 1
            x, y = loads[i][1], loads[i][2]
            dx, dy = sole_rectangle_clip(cx - x, cy - y, sole_yaws[i], self._half_length,
                                         self._half_width)
            loads[i] = (self._weight, x + dx, y + dy)
        return tuple(loads)

    def torques(self, base_position, base_quaternion, joint_positions, contacts) -> np.ndarray:
        """Return the gravity-compensation torques of the actuated joints.

        :param base_position: (3,) base frame position (m).
        :param base_quaternion: (4,) base orientation (x, y, z, w).
        :param joint_positions: (n,) actuated joint angles, caller's order (rad).
        :param contacts: (left, right) whether each foot is on the ground.
        :return: (n,) torques (N m), caller's order.
        """
        model, data = self._model, self._data
        q = self._set_configuration(base_position, base_quaternion, joint_positions)
        # One kinematic pass gives the COM, its Jacobian (g(q) = M g dz_com/dq) and the joint
        # Jacobians the sole Jacobians are read from.
        generalized = pin.jacobianCenterOfMass(model, data, q, False)[2] * self._weight
        if contacts[0] or contacts[1]:
            soles, yaws = [], []
            for frame_id in self._sole_ids:
                placement = pin.updateFramePlacement(model, data, frame_id)
                soles.append(placement.translation.tolist())
                yaws.append(yaw_of_matrix(placement.rotation))
            cx, cy, _ = data.com[0].tolist()
            loads = self._vertical_loads(cx, cy, soles, yaws, contacts)
            wrench = np.zeros(6)
            for (f, x, y), sole, frame_id in zip(loads, soles, self._sole_ids):
                if f == 0.0:
                    continue
                jacobian = pin.getFrameJacobian(model, data, frame_id, self._world_aligned)
                # Wrench of a vertical force f at (x, y), about the sole centre:
                # (0, 0, f) and lever x (0, 0, f) = (lever_y f, -lever_x f, 0).
                wrench[2] = f
                wrench[3] = (y - sole[1]) * f
                wrench[4] = -(x - sole[0]) * f
                generalized -= wrench @ jacobian
        return generalized[self._v_index]
