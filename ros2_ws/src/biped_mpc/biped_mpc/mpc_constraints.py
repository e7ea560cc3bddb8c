"""The MPC's constraint rows: ZMP in its support polygon, swing legs in their landing boxes.

Constraints (eq. constraints, E u + F y <= G + epsilon with E = 0) on the first
constraint_horizon predicted steps: ZMP in [zmp_min, zmp_max] (eq. ZMPConstraints) and each leg
mass in its landing box (eq. SwingConstraints; +-inf where a leg has none). Hard rows are
two-sided; each soft group (ZMP, landing) gets one scalar slack epsilon >= 0 (as MATLAB's ECR)
entering its rows as y <= y_max + epsilon and y >= y_min - epsilon, with cost
rho_q epsilon^2 + rho_l epsilon. The QP's variables are [slacks, moves].
"""
import numpy as np

from biped_mpc.linear_model import (
    N_OUTPUTS, N_PLANES, OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG, OUTPUT_ZMP)
from biped_mpc.mpc_params import MpcParams


class MpcConstraints:
    """Constant rows over [slacks, moves] and the bounds that change every cycle.

    The rows are built in segments; each segment's bounds are one (possibly strided) slice of
    the step-major flat outputs minus the free response. With both groups hard, the rows are
    all outputs of the first constraint_horizon steps: a single contiguous slice.

    :param params: constraint modes and horizon
    :param theta: (3 Np, 3 Nc) outputs from the moves of the condensed prediction
    """

    def __init__(self, params: MpcParams, theta: np.ndarray) -> None:
        n_moves = theta.shape[1]
        horizon = params.constraint_horizon
        outputs_of = {'zmp': (OUTPUT_ZMP,), 'landing': (OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG)}
        modes = {'zmp': params.zmp_constraint, 'landing': params.landing_constraint}
        soft_names = [name for name in ('zmp', 'landing') if modes[name] == 'soft']
        self.n_soft = len(soft_names)
        if modes['zmp'] == modes['landing'] == 'hard':
            selections = [(slice(0, N_OUTPUTS * horizon), None)]
        else:
            selections = [(slice(output, N_OUTPUTS * horizon, N_OUTPUTS), name)
                          for name in ('zmp', 'landing') if modes[name] != 'off'
                          for output in outputs_of[name]]
        rows, segments, start = [], [], 0
        for selection, name in selections:
            block = theta[selection]
            size = block.shape[0]
            if name is None or modes[name] == 'hard':
                sides = ((np.zeros(self.n_soft), True, True),)
            else:
                column = np.zeros(self.n_soft)
                column[soft_names.index(name)] = 1.0
                sides = ((-column, False, True), (column, True, False))
            for slack, has_lower, has_upper in sides:
                rows.append(np.hstack([np.tile(slack, (size, 1)), block]))
                segments.append((start, start + size, selection, has_lower, has_upper))
                start += size
        rows.append(np.zeros((0, self.n_soft + n_moves)))
        self._segments = tuple(segments)
        self._lower = np.full((N_PLANES, start), -np.inf)
        self._upper = np.full((N_PLANES, start), np.inf)
        self.rows = np.ascontiguousarray(np.vstack(rows))

    def bounds(self, free: np.ndarray, y_min: np.ndarray, y_max: np.ndarray) -> tuple:
        """Row bounds of both planes: the output bounds minus the free response.

        :param free: (2, 3 Np) free response of the outputs, step-major
        :param y_min: (2, 3 Np) lower output bounds
        :param y_max: (2, 3 Np) upper output bounds
        :return: (lower, upper), each (2, rows); buffers reused by the next call
        """
        lower, upper = self._lower, self._upper
        for start, stop, selection, has_lower, has_upper in self._segments:
            free_rows = free[:, selection]
            if has_lower:
                np.subtract(y_min[:, selection], free_rows, out=lower[:, start:stop])
            if has_upper:
                np.subtract(y_max[:, selection], free_rows, out=upper[:, start:stop])
        return lower, upper
