"""The linear MPC of the paper's walking controller: one QP per plane, built once, solved each
cycle on the three-mass (or LIPM) model."""
from dataclasses import replace
import time
from typing import Callable, Optional

import numpy as np

from biped_mpc.condensed_prediction import CondensedPrediction
from biped_mpc.errors import ConfigError, InputError
from biped_mpc.linear_model import (
    LinearModel, N_INPUTS, N_OUTPUTS, N_PLANES, N_STATES, OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG,
    POSITION, state_index, TORSO)
from biped_mpc.mpc_constraints import MpcConstraints
from biped_mpc.mpc_cost import MpcCost
from biped_mpc.mpc_params import LEG_OUTPUTS_TORSO_RELATIVE, MpcParams
from biped_mpc.mpc_result import MpcResult
from biped_mpc.qp_backend import QpSolution, QpStatus
from biped_mpc.qp_backends import make_backend
from biped_mpc.validation import finite_array


class LinearMpc:
    """Linear MPC of the paper on a jerk-driven planar model, solved for both planes.

    Prediction (condensed, see CondensedPrediction): Y = Psi x(k) + Psi_u u(k-1) + Theta dU with
    dU the Nc input moves (the paper's decision z_k, increments of the jerks). The cost is
    biped_mpc.mpc_cost's (the paper's stage cost plus a terminal cost), the constraints
    biped_mpc.mpc_constraints' (ZMP and landing boxes, hard or soft). Left/right labelling of the
    legs keeps H and the row matrix constant: they are built once; each cycle only the linear
    term and the row bounds change, and each plane's backend warm-starts from its previous solve.

    The paper's literal form (hold the last of Nc = 20 moves up to Np = 80, hard constraints at
    every step) is infeasible in the first cycles of the paper's walk. The default 'spread'
    blocking keeps Nc = 20 moves but spreads them over the horizon (1 x 8, 2 x 4, 4 x 4, 8 x 3,
    24 steps), and hard constraints cover the first 40 steps (0.8 s). Soft constraints over the
    whole horizon are the other feasible form.

    Outputs y = [left leg, right leg, ZMP] (the leg rows as MpcParams.leg_outputs chooses:
    the leg mass positions of the model's C, or each leg mass minus half the torso; see
    tracked_outputs) are expected at the predicted times t(k) + i Ts, i = 1 .. Np: sample
    references at t + Ts.

    :param model: the continuous model (three_mass_model or lipm_model)
    :param params: MPC parameters
    :param clock: seconds clock bracketing the solver calls (solve time is diagnostic only)
    :raises ConfigError: for inconsistent parameters
    :raises SolverUnavailableError: if the backend's package is missing
    """

    def __init__(self, model: LinearModel, params: MpcParams = MpcParams(),
                 clock: Callable[[], float] = time.perf_counter) -> None:
        if not isinstance(model, LinearModel):
            raise ConfigError(f'model must be a LinearModel, got {type(model).__name__}')
        if not isinstance(params, MpcParams):
            raise ConfigError(f'params must be MpcParams, got {type(params).__name__}')
        self.params = params
        self.model = model
        self.discrete_model = model.discretize(params.dt)
        self.output_matrix = tracked_outputs(model, params.leg_outputs)
        self.prediction = CondensedPrediction(replace(self.discrete_model, c=self.output_matrix),
                                              params.blocks)
        self._clock = clock
        self._build()
        self.reset()

    def _build(self) -> None:
        """Build the constant QP (H, rows) once, and one backend per plane."""
        p = self.params
        pred = self.prediction
        self._n_dec = pred.n_moves * N_INPUTS
        self._cost = MpcCost(p, pred, self.discrete_model, self.output_matrix)
        self._constraints = MpcConstraints(p, pred.outputs_from_moves)
        self.n_soft = self._constraints.n_soft
        self._free_from_state = np.ascontiguousarray(pred.outputs_from_state.T)
        self._free_from_input = np.ascontiguousarray(pred.outputs_from_input.T)
        n_var = self.n_soft + self._n_dec
        hessian = np.zeros((n_var, n_var))
        hessian[self.n_soft:, self.n_soft:] = self._cost.move_hessian
        hessian[:self.n_soft, :self.n_soft] = 2.0 * p.soft_quadratic_weight * np.eye(self.n_soft)
        self._row_matrix = self._constraints.rows
        self.n_rows = self._row_matrix.shape[0]
        self._hessian = hessian
        self._linear = np.zeros((N_PLANES, n_var))
        self._linear[:, :self.n_soft] = p.soft_linear_weight
        self._backends = [
            make_backend(p.backend, hessian, self._row_matrix, np.zeros(self.n_soft),
                         np.full(self.n_soft, np.inf), self._clock)
            for _ in range(N_PLANES)]
        self.inputs_to_states = _inputs_to_states(self.discrete_model, self.prediction.n_predict)

    @property
    def hessian(self) -> np.ndarray:
        """The constant QP Hessian H over [slacks, moves] (a copy)."""
        return self._hessian.copy()

    @property
    def constraint_matrix(self) -> np.ndarray:
        """The constant QP row matrix A over [slacks, moves] (a copy)."""
        return self._row_matrix.copy()

    def reset(self, u_prev: Optional[np.ndarray] = None) -> None:
        """Forget the previous plan and the warm starts.

        :param u_prev: the jerks applied last, shape (2, 3); zeros if None
        :raises InputError: if u_prev has a wrong shape or is not finite
        """
        self._u_prev = np.zeros((N_PLANES, N_INPUTS))
        if u_prev is not None:
            self._u_prev = finite_array('u_prev', u_prev, (N_PLANES, N_INPUTS)).copy()
        self._plan_moves = np.zeros((N_PLANES, self._n_dec))
        self._plan_input = self._u_prev.copy()
        self._plan_age = np.zeros(N_PLANES, dtype=int)
        for backend in self._backends:
            backend.reset()

    def solve(self, state: np.ndarray, y_ref: np.ndarray, y_min: np.ndarray, y_max: np.ndarray,
              u_prev: Optional[np.ndarray] = None) -> MpcResult:
        """Run one MPC cycle for both planes.

        :param state: estimated states x(k) per plane, shape (2, 9)
        :param y_ref: references of y(k+1 .. k+Np), shape (2, Np, 3) (m), finite
        :param y_min: lower bounds of the outputs, shape (2, Np, 3) (m), -inf for none
        :param y_max: upper bounds of the outputs, shape (2, Np, 3) (m), +inf for none
        :param u_prev: jerks applied in the previous cycle, shape (2, 3); None uses the jerks
            this MPC returned last
        :return: the jerks to apply and the plan
        :raises InputError: for wrong shapes, NaN or inf references or states, NaN bounds or
            y_min > y_max
        """
        state, y_ref, y_min, y_max, u_prev = self._validated(state, y_ref, y_min, y_max, u_prev)
        free = state @ self._free_from_state
        free += u_prev @ self._free_from_input
        error = free - y_ref
        if not (np.isfinite(error).all() and (y_min <= y_max).all()):
            self._explain_bad_values(state, y_ref, y_min, y_max, u_prev)
        linear = self._linear
        self._cost.gradient(linear[:, self.n_soft:], error, u_prev, state, y_ref)
        lower, upper = self._constraints.bounds(free, y_min, y_max)

        jerk = np.empty((N_PLANES, N_INPUTS))
        iterations = np.zeros(N_PLANES, dtype=int)
        solutions = np.zeros((N_PLANES, self.n_soft + self._n_dec))
        statuses = []
        solve_time = 0.0
        fallback = {}
        for plane in range(N_PLANES):
            try:
                solution = self._backends[plane].solve(linear[plane], lower[plane],
                                                       upper[plane])
            except Exception:  # noqa: B902 - a solver crash must not stop the control loop
                self._backends[plane].reset()
                solution = QpSolution(np.zeros(self.n_soft + self._n_dec), QpStatus.FAILED,
                                      -1, 0.0)
            solve_time += solution.solve_time
            iterations[plane] = solution.iterations
            statuses.append(solution.status)
            if solution.status == QpStatus.OPTIMAL:
                solutions[plane] = solution.x
                jerk[plane] = u_prev[plane] + solution.x[self.n_soft:self.n_soft + N_INPUTS]
                self._plan_moves[plane] = solution.x[self.n_soft:]
                self._plan_input[plane] = u_prev[plane]
                self._plan_age[plane] = 0
            else:
                self._plan_age[plane] += 1
                fallback[plane] = self._shifted_plan(plane)
                jerk[plane] = fallback[plane][0]
        self._u_prev = jerk.copy()
        return MpcResult(jerk=jerk, status=tuple(statuses), iterations=iterations,
                         solve_time=solve_time, _solutions=solutions, _state=state,
                         _u_prev=u_prev.copy(), _error=error,
                         _fallback=fallback, _mpc=self)

    def _validated(self, state, y_ref, y_min, y_max, u_prev):
        """Shapes are checked here; values are checked on the free-response error (one pass
        that NaN or inf in the state, the references or u_prev always reach) and on the
        bounds, and explained by _explain_bad_values."""
        shape = (N_PLANES, self.prediction.n_predict, N_OUTPUTS)
        state = np.array(state, dtype=float)
        y_ref = np.asarray(y_ref, dtype=float)
        y_min = np.asarray(y_min, dtype=float)
        y_max = np.asarray(y_max, dtype=float)
        u_prev = self._u_prev if u_prev is None else np.array(u_prev, dtype=float)
        if (state.shape != (N_PLANES, N_STATES) or y_ref.shape != shape
                or y_min.shape != shape or y_max.shape != shape
                or u_prev.shape != (N_PLANES, N_INPUTS)):
            raise InputError(
                f'expected shapes state {(N_PLANES, N_STATES)}, y_ref/y_min/y_max {shape}, '
                f'u_prev {(N_PLANES, N_INPUTS)}; got {state.shape}, {y_ref.shape}, '
                f'{y_min.shape}, {y_max.shape}, {u_prev.shape}')
        return (state, y_ref.reshape(N_PLANES, -1), y_min.reshape(N_PLANES, -1),
                y_max.reshape(N_PLANES, -1), u_prev)

    @staticmethod
    def _explain_bad_values(state, y_ref, y_min, y_max, u_prev) -> None:
        for name, array in (('state', state), ('u_prev', u_prev), ('y_ref', y_ref)):
            if not np.isfinite(array).all():
                where = tuple(int(i) for i in np.argwhere(~np.isfinite(array))[0])
                raise InputError(f'{name} must be finite; {name}{list(where)} is {array[where]}')
        if not (y_min <= y_max).all():
            where = tuple(int(i) for i in np.argwhere(~(y_min <= y_max))[0])
            raise InputError(f'bounds must be non-NaN with y_min <= y_max; at plane and flat '
                             f'index {where}: y_min={y_min[where]}, y_max={y_max[where]}')

    def paper_cost(self, solution: np.ndarray, error: np.ndarray, u_prev: np.ndarray) -> float:
        """The paper's cost J (eq. costfunction) of one plane's QP solution (MpcCost.paper_cost).

        :param solution: QP variables [slacks, moves] of the plane
        :param error: free response minus reference, shape (3 Np,), of the plane
        :param u_prev: jerks applied before the plan, shape (3,)
        :return: J
        """
        return self._cost.paper_cost(solution[self.n_soft:], error, u_prev)

    def _shifted_plan(self, plane: int) -> np.ndarray:
        """The stored plan's jerks from its age on, the last one repeated, shape (Np, 3)."""
        pred = self.prediction
        inputs = (self._plan_input[plane][None, :]
                  + (pred.inputs_from_moves @ self._plan_moves[plane]).reshape(-1, N_INPUTS))
        age = min(int(self._plan_age[plane]), pred.n_predict - 1)
        return np.concatenate([inputs[age:], np.repeat(inputs[-1:], age, axis=0)])


def tracked_outputs(model: LinearModel, leg_outputs: str) -> np.ndarray:
    """The output matrix the MPC tracks and constrains (see MpcParams.leg_outputs).

    :param model: the continuous model (its C has the absolute leg rows)
    :param leg_outputs: 'absolute' or 'torso_relative'
    :return: (3, 9) rows left leg, right leg, ZMP
    """
    matrix = np.array(model.c, dtype=float)
    if leg_outputs == LEG_OUTPUTS_TORSO_RELATIVE:
        matrix[[OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG], state_index(TORSO, POSITION)] = -0.5
    matrix.setflags(write=False)
    return matrix


def _inputs_to_states(model, n_predict: int) -> np.ndarray:
    """Block lower-triangular map from u(k .. k+Np-1) to x(k+1 .. k+Np), (9 Np, 3 Np)."""
    nx, nu = model.b.shape
    blocks = [model.b]
    for _ in range(n_predict - 1):
        blocks.append(model.a @ blocks[-1])
    matrix = np.zeros((n_predict * nx, n_predict * nu))
    for i in range(n_predict):
        for j in range(i + 1):
            matrix[i * nx:(i + 1) * nx, j * nu:(j + 1) * nu] = blocks[i - j]
    return matrix

