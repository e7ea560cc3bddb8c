"""Split a desired net wrench between the feet: a small QP under contact constraints."""
from dataclasses import dataclass
import enum
from typing import Optional

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.qp_backends import QpStatus, solve_once
from biped_mpc.validation import finite_array
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.sides import LEFT, RIGHT, SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT

SOLVERS = ('daqp', 'quadprog')
_ROWS_PER_FOOT = 11


class DistributionStatus(enum.IntEnum):
    """Outcome of a distribution."""

    OK = 0  # the net wrench is realised within the tolerances
    SATURATED = 1  # the demand lies outside what the contacts allow: feasible best effort
    FAILED = 2  # the QP failed: vertical force split by the ZMP ratio, zero torques


@dataclass(frozen=True)
class WrenchDistributionParams:
    """Contact model, weights and solver of the distribution QP (see WrenchDistributor)."""

    friction: float = parameter(0.7, 'friction coefficient of the QP, below the real one (1)',
                                low=0.0, high=2.0, low_open=True)
    min_force: float = parameter(15.0, 'minimum normal force of a supporting foot (N)',
                                 low=0.0, high=1000.0)
    sole_length: float = parameter(0.2, 'sole length along the foot (m)', low=0.01, high=1.0)
    sole_width: float = parameter(0.1, 'sole width across the foot (m)', low=0.01, high=1.0)
    cop_margin: float = parameter(0.01, 'distance the CoP keeps from the sole edges (m)',
                                  low=0.0, high=0.2)
    bound_yaw_torque: bool = parameter(True, 'bound |tz| by friction (L + W) / 2 fz')
    net_force_weight: float = parameter(100.0, 'weight of the net force error (1/N^2)',
                                        low=0.0, high=1e6, low_open=True)
    net_moment_weight: float = parameter(1.0, 'weight of the net moment error (1/(N m)^2)',
                                         low=0.0, high=1e6, low_open=True)
    ratio_weight: float = parameter(0.01, 'weight pulling the normal forces to the ZMP ratio '
                                    '(1/N^2)', low=0.0, high=1e6)
    force_regularization: float = parameter(1e-5, 'weight of each foot force (1/N^2)',
                                            low=0.0, high=1.0, low_open=True)
    torque_regularization: float = parameter(1e-4, 'weight of each foot torque (1/(N m)^2)',
                                             low=0.0, high=100.0, low_open=True)
    force_tolerance: float = parameter(1.0, 'net force error still reported OK (N)', low=0.0,
                                       high=1e3)
    moment_tolerance: float = parameter(0.5, 'net moment error still reported OK (N m)',
                                        low=0.0, high=1e3)
    solver: str = parameter('daqp', 'QP solver', choices=SOLVERS)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        if 2.0 * self.cop_margin >= min(self.sole_length, self.sole_width):
            raise ConfigError(f'WrenchDistributionParams.cop_margin must be below half the sole '
                              f'width, got {self.cop_margin!r}')


@dataclass(frozen=True)
class WrenchDistribution:
    """The feet's desired wrenches.

    :param wrenches: (2, 6) per side (LEFT, RIGHT): (f, tau) in the world frame, tau about the
        sole centre (N, N m); zero for a foot not in support
    :param local_wrenches: (2, 6) the same in each sole frame
    :param cops: (2, 3) CoP of each foot (m); NaN for a foot not in support
    :param net_force: (3,) the realised net force (N)
    :param net_moment: (3,) the realised net moment about the demand's point (N m)
    :param force_error: |realised - desired| net force (N)
    :param moment_error: |realised - desired| net moment (N m)
    :param left_ratio: share of the normal force the ZMP asks of the left foot, [0, 1]
    :param status: OK, SATURATED or FAILED
    :param qp_status: the solver's status
    """

    wrenches: np.ndarray
    local_wrenches: np.ndarray
    cops: np.ndarray
    net_force: np.ndarray
    net_moment: np.ndarray
    force_error: float
    moment_error: float
    left_ratio: float
    status: DistributionStatus
    qp_status: QpStatus


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def left_ratio_of_zmp(zmp, left_position, right_position) -> float:
    """Share of the normal force on the left foot implied by the ZMP between the feet.

    :param zmp: (2,) ZMP (m)
    :param left_position: (2,) or (3,) left sole centre (m)
    :param right_position: (2,) or (3,) right sole centre (m)
    :return: 1 - s clipped to [0, 1], s the ZMP's projection on the segment left -> right
    """
    left, right = np.asarray(left_position)[:2], np.asarray(right_position)[:2]
    segment = right - left
    squared = float(segment @ segment)
    if squared < 1e-12:
        return 0.5
    return min(max(1.0 - float((np.asarray(zmp) - left) @ segment) / squared, 0.0), 1.0)


class WrenchDistributor:
    """Desired net wrench -> per-foot wrenches, by a QP over x = (w_L, w_R), w = (f, tau).

    Each foot's wrench is in the world frame with its torque about its own sole centre p_i;
    the net wrench about the point p is sum (f_i, tau_i + (p_i - p) x f_i) = A x. Cost
    (lipm_walking_controller's Stabilizer::distributeWrench, with our weights):

        (A x - w_d)' W (A x - w_d) + x' R x + w_r ((1 - r) f_zL - r f_zR)^2

    W = diag(net force, net moment weights), R the small force / torque regularisation, r the
    left share of the ZMP's position between the sole centres (left_ratio_of_zmp). Each foot's
    constraints in its sole frame (local f, tau): f_z >= min_force; friction pyramid
    |f_x|, |f_y| <= mu f_z; CoP inside the sole shrunk by cop_margin,
    |tau_x| <= (W/2 - m) f_z and |tau_y| <= (L/2 - m) f_z; optionally |tau_z| <= mu (L + W)/2
    f_z; on a partial foothold (partial_foothold) also n . cop <= d - m for each of its cuts,
    which the caller passes only while the cut sole shrunk by m is not empty. The
    constraints are then always feasible; a demand outside them (ZMP outside the support,
    too little vertical force, too much shear) comes back as the nearest realisable wrench in
    the W metric, with status SATURATED. The force weight is far above the moment weight so
    that a ZMP demanded outside the support does not buy a smaller moment error with less
    vertical force (the error of a given ZMP offset d grows as F d): the weight keeps the
    vertical force (0.02 % lower for d = 0.15 m) and puts the ZMP on the support's edge.
    In single support the stance foot takes the whole wrench (6 variables), the other foot
    nothing. The QP (12 variables, 22 rows) is built and solved each call: about 0.2 ms.
    """

    def __init__(self, params: WrenchDistributionParams = WrenchDistributionParams()) -> None:
        """Create the distributor.

        :param params: contact model, weights, solver
        """
        self.params = params

    def reset(self) -> None:
        """Nothing is kept between cycles; present for the uniform interface."""

    def _foot_rows(self, rotation: np.ndarray) -> tuple:
        p = self.params
        n_x, n_y, n_z = rotation[:, 0], rotation[:, 1], rotation[:, 2]
        half_w = 0.5 * p.sole_width - p.cop_margin
        half_l = 0.5 * p.sole_length - p.cop_margin
        yaw = p.friction * 0.5 * (p.sole_length + p.sole_width)
        # filled in place: eleven small concatenations cost more than the QP's setup
        rows = np.zeros((_ROWS_PER_FOOT, 6))
        rows[0, :3] = n_z
        for first, sign in ((1, 1.0), (6, -1.0)):
            rows[first, :3] = sign * n_x - p.friction * n_z
            rows[first + 1, :3] = sign * n_y - p.friction * n_z
            rows[first + 2, :3], rows[first + 2, 3:] = -half_w * n_z, sign * n_x
            rows[first + 3, :3], rows[first + 3, 3:] = -half_l * n_z, sign * n_y
            rows[first + 4, :3], rows[first + 4, 3:] = -yaw * n_z, sign * n_z
        lower = np.full(_ROWS_PER_FOOT, -np.inf)
        upper = np.zeros(_ROWS_PER_FOOT)
        lower[0], upper[0] = p.min_force, np.inf
        if not p.bound_yaw_torque:
            upper[[5, 10]] = np.inf
        return rows, lower, upper

    def _cut_rows(self, rotation: np.ndarray, cuts) -> np.ndarray:
        # n . cop <= d - margin with cop = (-tau_y, tau_x) / f_z in the sole frame, times f_z
        rows = np.zeros((len(cuts), 6))
        for row, (n_x, n_y, d) in zip(rows, cuts):
            row[:3] = -(d - self.params.cop_margin) * rotation[:, 2]
            row[3:] = n_y * rotation[:, 0] - n_x * rotation[:, 1]
        return rows

    def update(self, support: int, net_force, net_moment, point, feet_positions,
               feet_rotations: Optional[np.ndarray] = None, zmp=None,
               footholds=None) -> WrenchDistribution:
        """Distribute one desired net wrench.

        :param support: SUPPORT_LEFT, SUPPORT_RIGHT or SUPPORT_DOUBLE
        :param net_force: (3,) desired net force on the robot from the ground (N)
        :param net_moment: (3,) desired net moment about point (N m)
        :param point: (3,) the point of net_moment, e.g. the desired ZMP on the ground (m)
        :param feet_positions: (2, 3) sole centres, LEFT then RIGHT (m)
        :param feet_rotations: (2, 3, 3) sole frames in the world; None for flat, yaw 0
        :param zmp: (2,) ZMP giving the force ratio; None for point[:2]
        :param footholds: (left, right) cuts of each sole (partial_foothold.Cut list, sole
            frame): the foot's CoP also keeps cop_margin inside each; None: whole soles
        :return: the feet's wrenches and the status
        :raises InputError: for a non-finite or misshaped input or an unknown support
        """
        if support not in (SUPPORT_LEFT, SUPPORT_RIGHT, SUPPORT_DOUBLE):
            raise InputError(f'support must be one of '
                             f'{(SUPPORT_LEFT, SUPPORT_RIGHT, SUPPORT_DOUBLE)}, got {support!r}')
        desired = np.concatenate([finite_array('net_force', net_force, (3,)),
                                  finite_array('net_moment', net_moment, (3,))])
        point = finite_array('point', point, (3,))
        positions = finite_array('feet_positions', feet_positions, (2, 3))
        rotations = (np.array([np.eye(3), np.eye(3)]) if feet_rotations is None
                     else finite_array('feet_rotations', feet_rotations, (2, 3, 3)))
        zmp = point[:2] if zmp is None else finite_array('zmp', zmp, (2,))
        p = self.params
        ratio = left_ratio_of_zmp(zmp, positions[LEFT], positions[RIGHT])
        sides = {SUPPORT_LEFT: (LEFT,), SUPPORT_RIGHT: (RIGHT,)}.get(support, (LEFT, RIGHT))
        k = len(sides)
        cuts = [[] if footholds is None else list(footholds[side]) for side in sides]
        net_map = np.zeros((6, 6 * k))
        rows = np.zeros((_ROWS_PER_FOOT * k + sum(map(len, cuts)), 6 * k))
        lower, upper = [], []
        first = _ROWS_PER_FOOT * k
        for i, side in enumerate(sides):
            net_map[:, 6 * i:6 * i + 6] = np.eye(6)
            net_map[3:, 6 * i:6 * i + 3] = _skew(positions[side] - point)
            foot_rows, foot_lower, foot_upper = self._foot_rows(rotations[side])
            rows[_ROWS_PER_FOOT * i:_ROWS_PER_FOOT * (i + 1), 6 * i:6 * i + 6] = foot_rows
            lower.append(foot_lower)
            upper.append(foot_upper)
        for i, side in enumerate(sides):
            if cuts[i]:
                rows[first:first + len(cuts[i]), 6 * i:6 * i + 6] = self._cut_rows(
                    rotations[side], cuts[i])
                lower.append(np.full(len(cuts[i]), -np.inf))
                upper.append(np.zeros(len(cuts[i])))
                first += len(cuts[i])
        weight = np.diag([p.net_force_weight] * 3 + [p.net_moment_weight] * 3)
        regularization = np.diag(([p.force_regularization] * 3
                                  + [p.torque_regularization] * 3) * k)
        hessian = 2.0 * (net_map.T @ weight @ net_map + regularization)
        if k == 2:
            pressure = np.zeros(12)
            pressure[:3] = (1.0 - ratio) * rotations[LEFT][:, 2]
            pressure[6:9] = -ratio * rotations[RIGHT][:, 2]
            hessian += 2.0 * p.ratio_weight * np.outer(pressure, pressure)
        solution = solve_once(p.solver, hessian, -2.0 * net_map.T @ weight @ desired, rows,
                              np.concatenate(lower), np.concatenate(upper))
        wrenches = np.zeros((2, 6))
        status = DistributionStatus.OK
        if solution.status == QpStatus.OPTIMAL:
            for i, side in enumerate(sides):
                wrenches[side] = solution.x[6 * i:6 * i + 6]
        else:
            status = DistributionStatus.FAILED
            shares = {LEFT: ratio, RIGHT: 1.0 - ratio} if k == 2 else {sides[0]: 1.0}
            for side, share in shares.items():
                wrenches[side, :3] = rotations[side][:, 2] * max(share * desired[2], p.min_force)
        return self._result(wrenches, sides, positions, rotations, point, desired, ratio, status,
                            solution.status)

    def _result(self, wrenches, sides, positions, rotations, point, desired, ratio, status,
                qp_status) -> WrenchDistribution:
        local = np.zeros((2, 6))
        cops = np.full((2, 3), np.nan)
        net = np.zeros(6)
        for side in sides:
            local[side, :3] = rotations[side].T @ wrenches[side, :3]
            local[side, 3:] = rotations[side].T @ wrenches[side, 3:]
            if local[side, 2] > 0.0:
                cops[side] = positions[side] + rotations[side] @ np.array(
                    [-local[side, 4] / local[side, 2], local[side, 3] / local[side, 2], 0.0])
            net[:3] += wrenches[side, :3]
            net[3:] += wrenches[side, 3:] + _skew(positions[side] - point) @ wrenches[side, :3]
        force_error = float(np.linalg.norm(net[:3] - desired[:3]))
        moment_error = float(np.linalg.norm(net[3:] - desired[3:]))
        if status == DistributionStatus.OK and (force_error > self.params.force_tolerance or
                                                moment_error > self.params.moment_tolerance):
            status = DistributionStatus.SATURATED
        return WrenchDistribution(wrenches, local, cops, net[:3], net[3:], force_error,
                                  moment_error, ratio, status, qp_status)

