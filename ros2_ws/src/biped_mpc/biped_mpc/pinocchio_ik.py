"""Numerical leg inverse kinematics for any URDF humanoid (Pinocchio damped least squares).

Each leg is solved on its own reduced model (the other joints locked), in the pelvis frame:
with the sole placement oMf(q) and the target oMd, the error is e = log6(oMd^-1 oMf) and the
Jacobian J = Jlog6(oMd^-1 oMf) J_f(q) (J_f in the sole's local frame), and each iteration takes

    dq = -(J^T J + lambda I)^-1 J^T e,  q <- clip(q + dq, lower, upper)

(Gauss-Newton with Levenberg damping and the steps limited to max_step). A solve starts from
the last solution (warm start) or, the first time, from a bent-knee seed: a straight knee is
singular. A target not met within tolerance after max_iterations gives the closest pose found
(the least-squares fit within the joint limits) with status IK_CLIPPED.
"""

from dataclasses import dataclass
import math
from typing import Optional

import numpy as np
from scipy.linalg import lapack

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.leg_ik import IK_CLIPPED, IK_REACHABLE, LegIkSolution
from biped_mpc.validation import check_integer, finite_array, validated_pose
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.sides import SIDES

try:
    import pinocchio as pin
except ImportError as error:  # pragma: no cover - pinocchio is a dependency of the stack
    raise ImportError('biped_mpc.pinocchio_ik needs pinocchio: pip install pin') from error

BENT_KNEE_SEED = (0.0, 0.0, -0.3, 0.6, -0.3, 0.0)  # rad, one leg in leg-joint order


@dataclass(frozen=True)
class NumericIkParams:
    """Parameters of the damped least-squares leg IK.

    :param max_iterations: Gauss-Newton iterations per leg and solve, >= 1.
    :param tolerance: norm of the 6D pose error (m, rad) below which a target is met, > 0.
    :param damping: Levenberg damping lambda (m^2), >= 0.
    :param max_step: largest joint change of one iteration (rad), > 0.
    """

    max_iterations: int = parameter(50, 'Gauss-Newton iterations per leg and solve', low=1)
    tolerance: float = parameter(1e-10, 'norm of the 6D pose error of a met target (m, rad)',
                                 low=0.0, low_open=True)
    damping: float = parameter(1e-8, 'Levenberg damping lambda (m^2)', low=0.0)
    max_step: float = parameter(0.5, 'largest joint change of one iteration (rad)', low=0.0,
                                low_open=True)

    def __post_init__(self):
        validate_fields(self, ConfigError)
        check_integer('NumericIkParams.max_iterations', self.max_iterations, 1)


class _LegModel:
    """A fixed-base reduced model of one leg (6 joints) with its sole frame."""

    def __init__(self, full: 'pin.Model', joint_names: tuple, sole_frame: str):
        keep = {full.getJointId(n) for n in joint_names}
        lock = [j for j in range(1, full.njoints) if j not in keep]
        self.model = pin.buildReducedModel(full, lock, pin.neutral(full))
        self.data = self.model.createData()
        self.q_index = np.array([self.model.joints[self.model.getJointId(n)].idx_q
                                 for n in joint_names])
        self.frame = self.model.getFrameId(sole_frame)
        self.lower = self.model.lowerPositionLimit[self.q_index].copy()
        self.upper = self.model.upperPositionLimit[self.q_index].copy()
        self.q = np.zeros(self.model.nq)

    def placement(self, q6: np.ndarray) -> 'pin.SE3':
        self.q[self.q_index] = q6
        pin.forwardKinematics(self.model, self.data, self.q)
        return pin.updateFramePlacement(self.model, self.data, self.frame)

    def jacobian(self) -> np.ndarray:
        jacobian = pin.computeFrameJacobian(self.model, self.data, self.q, self.frame,
                                            pin.ReferenceFrame.LOCAL)
        return jacobian[:, self.q_index]


class PinocchioLegIk:
    """Damped least-squares IK of both legs of any URDF humanoid (see module docstring).

    :param urdf_path: the robot's URDF; its root link is the pelvis (hip) frame.
    :param leg_joint_names: the 12 leg joints, left leg then right leg, each hip yaw, hip roll,
        hip pitch, knee, ankle pitch, ankle roll (the chain order from the pelvis).
    :param sole_frames: (left, right) sole frame names.
    :param params: iteration parameters.
    :param seed: (12,) starting angles of the first solve (rad); None bends the knees.
    :raises ConfigError: if a joint or frame is missing.
    """

    def __init__(self, urdf_path: str, leg_joint_names, sole_frames,
                 params: NumericIkParams = NumericIkParams(), seed=None):
        full = pin.buildModelFromUrdf(str(urdf_path))
        names = tuple(leg_joint_names)
        if len(names) != 12:
            raise ConfigError('leg_joint_names = %r must be 12 names' % (names,))
        missing = [n for n in names if not full.existJointName(n)]
        missing += [f for f in sole_frames if not full.existFrame(f)]
        if missing:
            raise ConfigError('not in %s: %r' % (urdf_path, missing))
        self._legs = (_LegModel(full, names[:6], sole_frames[0]),
                      _LegModel(full, names[6:], sole_frames[1]))
        self._params = params
        if seed is None:
            seed = np.tile(BENT_KNEE_SEED, 2)
        seed = np.asarray(seed, dtype=float)
        if seed.shape != (12,) or not np.all(np.isfinite(seed)):
            raise ConfigError('seed = %r must be 12 finite angles' % (seed,))
        self._seed = np.concatenate([np.clip(seed[6 * i:6 * i + 6], leg.lower, leg.upper)
                                     for i, leg in enumerate(self._legs)])
        self._warm = self._seed.copy()
        self.last_iterations = (0, 0)

    @property
    def joint_lower(self) -> np.ndarray:
        """(12,) lower joint limits from the URDF (rad)."""
        return np.concatenate([leg.lower for leg in self._legs])

    @property
    def joint_upper(self) -> np.ndarray:
        """(12,) upper joint limits from the URDF (rad)."""
        return np.concatenate([leg.upper for leg in self._legs])

    def reset_warm_start(self) -> None:
        """Start the next solve from the bent-knee seed again."""
        self._warm = self._seed.copy()

    def solve(self, pelvis_position, pelvis_rotation, left_position, left_rotation,
              right_position, right_rotation, q_init: Optional[np.ndarray] = None
              ) -> LegIkSolution:
        """Return the 12 leg angles putting the soles at their targets for a pelvis pose.

        :param pelvis_position: (3,) pelvis (root link) position in the world (m).
        :param pelvis_rotation: (3, 3) pelvis orientation.
        :param left_position: (3,) left sole target (m).
        :param left_rotation: (3, 3) left sole orientation target.
        :param right_position: (3,) right sole target (m).
        :param right_rotation: (3, 3) right sole orientation target.
        :param q_init: (12,) start angles (rad); None warm-starts from the last solution.
        :return: the solution; IK_CLIPPED for a leg whose target was not met.
        :raises InputError: for wrong shapes or NaN/inf.
        """
        p, r = validated_pose('pelvis', pelvis_position, pelvis_rotation)
        targets = (validated_pose('left sole', left_position, left_rotation),
                   validated_pose('right sole', right_position, right_rotation))
        if q_init is None:
            start = self._warm
        else:
            start = np.asarray(q_init, dtype=float)
            if start.shape != (12,) or not np.all(np.isfinite(start)):
                raise InputError('q_init = %r must be 12 finite angles' % (q_init,))
        pelvis = pin.SE3(r, p)
        q = np.empty(12)
        status, iterations = [], []
        for side in SIDES:
            target = pelvis.actInv(pin.SE3(targets[side][1], targets[side][0]))
            q_leg, leg_status, n = self._solve_leg(self._legs[side], target,
                                                   start[6 * side:6 * side + 6])
            q[6 * side:6 * side + 6] = q_leg
            status.append(leg_status)
            iterations.append(n)
        self._warm = q.copy()
        self.last_iterations = tuple(iterations)
        return LegIkSolution(q, tuple(status))

    def _solve_leg(self, leg: _LegModel, target: 'pin.SE3', start: np.ndarray) -> tuple:
        params = self._params
        q = np.minimum(np.maximum(start, leg.lower), leg.upper)
        best_q, best_error = q, math.inf
        damping = np.eye(6) * params.damping
        for iteration in range(params.max_iterations + 1):
            error_placement = target.actInv(leg.placement(q))
            error = pin.log6(error_placement).vector
            norm = math.sqrt(error @ error)
            if norm < best_error:
                best_q, best_error = q, norm
            if norm < params.tolerance or iteration == params.max_iterations:
                break
            jacobian = pin.Jlog6(error_placement) @ leg.jacobian()
            # Levenberg-damped normal equations, symmetric positive definite (LAPACK posv).
            _, step, info = lapack.dposv(jacobian.T @ jacobian + damping, jacobian.T @ error)
            if info != 0:
                break
            largest = float(np.max(np.abs(step)))
            if largest > params.max_step:
                step *= params.max_step / largest
            q = np.minimum(np.maximum(q - step, leg.lower), leg.upper)
        status = IK_REACHABLE if best_error < params.tolerance else IK_CLIPPED
        return best_q.copy(), status, iteration

    def forward(self, q, pelvis_position=(0.0, 0.0, 0.0), pelvis_rotation=np.eye(3)) -> tuple:
        """As biped_mpc.leg_ik.AnalyticLegIk.forward, by Pinocchio's kinematics."""
        q = finite_array('q', q, (12,))
        p, r = validated_pose('pelvis', pelvis_position, pelvis_rotation)
        pelvis = pin.SE3(r, p)
        out = []
        for side in SIDES:
            placement = pelvis * self._legs[side].placement(q[6 * side:6 * side + 6])
            out.extend([placement.translation.copy(), placement.rotation.copy()])
        return tuple(out)
