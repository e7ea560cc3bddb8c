"""The online walking controller of the paper: a linear MPC on the three-mass (or LIPM) model."""
from dataclasses import dataclass, field, replace
from functools import cached_property
import math
import time
from typing import Callable, Optional

import numpy as np

from biped_mpc.condensed_prediction import CondensedPrediction, default_move_blocks
from biped_mpc.errors import ConfigError, InputError
from biped_mpc.linear_model import (
    LEFT_LEG, LinearModel, N_INPUTS, N_OUTPUTS, N_PLANES, N_STATES, OUTPUT_LEFT_LEG,
    OUTPUT_RIGHT_LEG, OUTPUT_ZMP, POSITION, RIGHT_LEG, state_index, TORSO)
from biped_mpc.qp_backends import BACKENDS, make_backend, QpSolution, QpStatus

CONSTRAINT_MODES = ('hard', 'soft', 'off')
WEIGHT_CONVENTIONS = ('matlab', 'literal')
MOVE_BLOCKINGS = ('spread', 'hold')
LEG_OUTPUTS_ABSOLUTE = 'absolute'
LEG_OUTPUTS_TORSO_RELATIVE = 'torso_relative'
LEG_OUTPUTS = (LEG_OUTPUTS_ABSOLUTE, LEG_OUTPUTS_TORSO_RELATIVE)


@dataclass(frozen=True)
class MpcParams:
    """Parameters of the MPC (paper Table Params and section "Online Walking Controller").

    :param dt: control period Ts (s), (0, 1]
    :param n_predict: prediction horizon Np (steps), [1, 1000]
    :param n_control: control horizon Nc (number of input moves), [1, n_predict]
    :param move_blocking: where the Nc moves act. 'hold' is the paper's literal form (moves at
        steps 0 .. Nc-1, the last one held to Np); 'spread' spreads them over the whole
        horizon (for 80/20: 8 x 1, 4 x 2, 4 x 4, 3 x 8, 24 steps), which keeps the QP feasible
        with hard constraints over the whole horizon (see SIM_AND_MPC_FACTS.md)
    :param move_blocks: explicit hold length of each move (steps), overriding move_blocking;
        empty to derive it; Nc entries summing to Np
    :param constraint_horizon: number of first predicted steps whose outputs are constrained
        (steps), [1, n_predict]. The default 40 (0.8 s, a whole single support) covers the
        part of the horizon where the spread moves last at most 8 steps; hard constraints on
        the coarse tail (constant jerk over 24 steps cannot follow a 0.8 m swing) make the QP
        infeasible in the paper's walk
    :param output_weights: alpha_1..3 of the errors of (left leg, right leg, ZMP), each >= 0
        (the paper's stance/swing weights, equal in the paper)
    :param input_rate_weights: alpha_4..6 of the input increments du of the jerks of
        (left leg, torso, right leg), each > 0
    :param input_weights: optional extra weights of the jerks themselves, summed over the
        prediction horizon, each >= 0; 0 as in the paper's table
    :param weight_convention: 'matlab': a weight w multiplies the signal before squaring,
        cost (w e)^2, as in MATLAB's MPC Toolbox that the paper's notation follows (its rate
        weight 0.1 is the toolbox default); 'literal': cost w e^2 as eq. costfunction reads.
        With the paper's 20 and 0.1 the literal form tracks too loosely for 0.8 m steps
    :param zmp_constraint: 'hard', 'soft' or 'off': ZMP inside the support polygon
        (eq. ZMPConstraints)
    :param landing_constraint: 'hard', 'soft' or 'off': swing leg inside the reachable
        rectangle (eq. SwingConstraints)
    :param soft_quadratic_weight: quadratic penalty rho on each soft group's slack epsilon
        (1/m^2), > 0
    :param soft_linear_weight: linear penalty on each soft group's slack (1/m), >= 0; large
        enough makes the penalty exact (no violation while the hard problem is feasible)
    :param terminal_cost: add the infinite-horizon cost-to-go beyond Np (LQ, from the discrete
        Riccati equation) of the terminal state's distance to the rest state of the last
        reference sample; it keeps the closed loop stable (see LinearMpc)
    :param backend: QP solver, one of qp_backends.BACKENDS
    :param leg_outputs: what the MPC tracks of each leg. 'absolute': the leg mass position
        c_l (the paper's C, its reference the midpoint of the planned foot and the planned
        hip); 'torso_relative': c_l - c_t / 2, the leg mass relative to the model's own hip,
        whose reference is half the planned foot (reference_adapter.outputs_from_window with
        the same leg_outputs). With 'torso_relative' a leg that tracks its reference keeps
        its foot, 2 c_l - c_t, on the planned foot wherever the torso moves to place the ZMP,
        and a stance leg stays midway between its sole and the hip as the geometry demands;
        with 'absolute' every centimetre the torso moves away from the planner's hip moves
        the swing foot target by as much and pulls the stance leg mass off the geometry.
        'absolute' is the default here (the paper's model-plant experiments, whose plant has
        free leg masses); the humanoid's WalkingControllerParams default to 'torso_relative'
    """

    dt: float = 0.02
    n_predict: int = 80
    n_control: int = 20
    move_blocking: str = 'spread'
    move_blocks: tuple = ()
    constraint_horizon: int = 40
    output_weights: tuple = (20.0, 20.0, 20.0)
    input_rate_weights: tuple = (0.1, 0.1, 0.1)
    input_weights: tuple = (0.0, 0.0, 0.0)
    weight_convention: str = 'matlab'
    zmp_constraint: str = 'hard'
    landing_constraint: str = 'hard'
    soft_quadratic_weight: float = 1e4
    soft_linear_weight: float = 1e3
    terminal_cost: bool = True
    backend: str = 'daqp'
    leg_outputs: str = LEG_OUTPUTS_ABSOLUTE

    def __post_init__(self) -> None:
        _check_number('dt', self.dt, 0.0, 1.0, low_open=True)
        _check_integer('n_predict', self.n_predict, 1, 1000)
        _check_integer('n_control', self.n_control, 1, self.n_predict)
        _check_choice('move_blocking', self.move_blocking, MOVE_BLOCKINGS)
        if self.move_blocks:
            blocks = tuple(self.move_blocks)
            if (len(blocks) != self.n_control or sum(blocks) != self.n_predict
                    or not all(isinstance(b, int) and b >= 1 for b in blocks)):
                raise ConfigError(f'move_blocks must be {self.n_control} integers >= 1 summing '
                                  f'to n_predict={self.n_predict}, got {self.move_blocks!r}')
        _check_integer('constraint_horizon', self.constraint_horizon, 1, self.n_predict)
        _check_weights('output_weights', self.output_weights, N_OUTPUTS, positive=False)
        _check_weights('input_rate_weights', self.input_rate_weights, N_INPUTS, positive=True)
        _check_weights('input_weights', self.input_weights, N_INPUTS, positive=False)
        _check_choice('weight_convention', self.weight_convention, WEIGHT_CONVENTIONS)
        _check_choice('zmp_constraint', self.zmp_constraint, CONSTRAINT_MODES)
        _check_choice('landing_constraint', self.landing_constraint, CONSTRAINT_MODES)
        _check_number('soft_quadratic_weight', self.soft_quadratic_weight, 0.0, 1e12,
                      low_open=True)
        _check_number('soft_linear_weight', self.soft_linear_weight, 0.0, 1e12)
        if not isinstance(self.terminal_cost, bool):
            raise ConfigError(f'terminal_cost must be a bool, got {self.terminal_cost!r}')
        _check_choice('backend', self.backend, BACKENDS)
        _check_choice('leg_outputs', self.leg_outputs, LEG_OUTPUTS)

    def quadratic_weights(self, name: str) -> np.ndarray:
        """The coefficients multiplying the squared signals in the QP cost.

        :param name: 'output_weights', 'input_rate_weights' or 'input_weights'
        :return: the weights squared ('matlab' convention) or as given ('literal'), (3,)
        """
        weights = np.asarray(getattr(self, name), dtype=float)
        return weights ** 2 if self.weight_convention == 'matlab' else weights

    @property
    def blocks(self) -> tuple:
        """Hold length of each of the Nc moves (steps), summing to Np."""
        if self.move_blocks:
            return tuple(self.move_blocks)
        if self.move_blocking == 'hold':
            return (1,) * (self.n_control - 1) + (self.n_predict - self.n_control + 1,)
        return default_move_blocks(self.n_predict, self.n_control)


def _check_number(name, value, low, high, low_open=False):
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or value > high or value < low or (low_open and value == low):
        bracket = '(' if low_open else '['
        raise ConfigError(f'{name} must be a finite number in {bracket}{low}, {high}], '
                          f'got {value!r}')


def _check_integer(name, value, low, high):
    if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
        raise ConfigError(f'{name} must be an integer in [{low}, {high}], got {value!r}')


def _check_choice(name, value, choices):
    if value not in choices:
        raise ConfigError(f'{name} must be one of {choices}, got {value!r}')


def _check_weights(name, value, size, positive):
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        array = None
    bad = (array is None or array.shape != (size,) or not np.all(np.isfinite(array))
           or np.any(array <= 0.0 if positive else array < 0.0))
    if bad:
        relation = '> 0' if positive else '>= 0'
        raise ConfigError(f'{name} must be {size} finite numbers {relation}, got {value!r}')


@dataclass(frozen=True)
class MpcResult:
    """Outcome of one MPC cycle for both planes (index 0 = x, 1 = y).

    The plan (moves, slacks, predicted inputs, states, outputs) and the cost are computed on
    first access, so that the control loop pays only for the jerks it applies.

    :param jerk: the jerks to apply now, u(k) per plane, shape (2, 3) (m/s^3)
    :param status: QP status per plane; anything but OPTIMAL means the plane used the fallback
        (the previous plan shifted by the cycles since it was computed)
    :param iterations: solver iterations per plane
    :param solve_time: time in the solver calls of both planes (s), a diagnostic only
    """

    jerk: np.ndarray
    status: tuple
    iterations: np.ndarray
    solve_time: float
    _solutions: np.ndarray = field(repr=False)
    _state: np.ndarray = field(repr=False)
    _u_prev: np.ndarray = field(repr=False)
    _error: np.ndarray = field(repr=False)
    _fallback: dict = field(repr=False)
    _mpc: 'LinearMpc' = field(repr=False)

    @property
    def ok(self) -> bool:
        """True when both planes were solved to optimality."""
        return all(s == QpStatus.OPTIMAL for s in self.status)

    @cached_property
    def cost(self) -> np.ndarray:
        """The paper's cost J (eq. costfunction) per plane, nan for a fallback plane, (2,)."""
        return np.array([
            np.nan if plane in self._fallback else self._mpc.paper_cost(
                self._solutions[plane], self._error[plane], self._u_prev[plane])
            for plane in range(N_PLANES)])

    @cached_property
    def moves(self) -> np.ndarray:
        """The input increments du of the plan per plane, shape (2, Nc, 3) (m/s^3)."""
        n_soft = self._mpc.n_soft
        return self._solutions[:, n_soft:].reshape(N_PLANES, -1, N_INPUTS).copy()

    @cached_property
    def slack(self) -> np.ndarray:
        """Soft-constraint slacks epsilon per plane, shape (2, soft groups) (m)."""
        return self._solutions[:, :self._mpc.n_soft].copy()

    @cached_property
    def predicted_inputs(self) -> np.ndarray:
        """Jerks u(k .. k+Np-1) of the plan, shape (2, Np, 3) (m/s^3)."""
        s = self._mpc.prediction.inputs_from_moves
        planned = (self._u_prev[:, None, :]
                   + (self.moves.reshape(N_PLANES, -1) @ s.T).reshape(N_PLANES, -1, N_INPUTS))
        for plane, sequence in self._fallback.items():
            planned[plane] = sequence
        return planned

    @cached_property
    def predicted_states(self) -> np.ndarray:
        """States x(k+1 .. k+Np) of the plan, shape (2, Np, 9)."""
        p = self._mpc.prediction
        flat = (self._state @ p.states_from_state.T
                + self.predicted_inputs.reshape(N_PLANES, -1) @ self._mpc.inputs_to_states.T)
        return flat.reshape(N_PLANES, p.n_predict, N_STATES)

    @cached_property
    def predicted_outputs(self) -> np.ndarray:
        """Outputs y(k+1 .. k+Np): left leg, right leg, ZMP, shape (2, Np, 3) (m)."""
        return self.predicted_states @ self._mpc.output_matrix.T


class LinearMpc:
    """Linear MPC of the paper on a jerk-driven planar model, solved for both planes.

    Prediction (condensed, see CondensedPrediction): Y = Psi x(k) + Psi_u u(k-1) + Theta dU with
    dU the Nc input moves (the paper's decision z_k, increments of the jerks). Cost
    (eq. costfunction): J = sum_{i=1}^{Np} sum_o a_o (y_o(k+i) - r_o(k+i))^2
    + sum_{moves} sum_j b_j du_j^2 (+ optional jerk weights) with a = alpha_1..3^2 and
    b = alpha_4..6^2 in MATLAB's convention (alpha = 20 and 0.1 in the paper), or a = alpha and
    b = alpha with weight_convention='literal'. The paper writes d_4..6 as the squared jerks
    while its decision is the increments du; we weight the increments (as MATLAB's MPC does
    with its default rate weight 0.1, the paper's value) and offer input_weights for the jerks.

    Constraints (eq. constraints, E u + F y <= G + epsilon with E = 0) on the first
    constraint_horizon predicted steps: ZMP in [zmp_min, zmp_max] (eq. ZMPConstraints) and each
    leg mass in its landing box (eq. SwingConstraints; +-inf where a leg has none). Hard rows
    are two-sided; each soft group (ZMP, landing) gets one scalar slack epsilon >= 0 (as
    MATLAB's ECR) entering its rows as y <= y_max + epsilon and y >= y_min - epsilon, with cost
    rho_q epsilon^2 + rho_l epsilon. Left/right labelling of the legs keeps H and the row
    matrix constant: they are built once; each cycle only the linear term and the row bounds
    change, and each plane's backend warm-starts from its previous solve.

    Terminal cost (not in the paper, on by default): the ZMP output hides the torso's unstable
    mode (c_t - (z_t/g) c_t'' = 0 has the solution e^{sqrt(g/z_t) t}), so a finite-horizon
    cost on the outputs alone lets the plan diverge in its tail, and the closed loop drifts
    (the legs ran away by metres in the paper's walk). The cost-to-go of the same stage cost
    beyond Np, from the discrete Riccati equation of the increment form, penalises the
    terminal state's distance to the rest state of the last reference sample; unconstrained,
    this makes the MPC Kajita's preview controller (infinite-horizon LQ with preview).

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
        move_hessian = self._build_cost()
        rows = self._build_constraints()
        p = self.params
        n_var = self.n_soft + self._n_dec
        hessian = np.zeros((n_var, n_var))
        hessian[self.n_soft:, self.n_soft:] = move_hessian
        hessian[:self.n_soft, :self.n_soft] = 2.0 * p.soft_quadratic_weight * np.eye(self.n_soft)
        self._row_matrix = np.ascontiguousarray(rows)
        self.n_rows = self._row_matrix.shape[0]
        self._hessian = hessian
        self._linear = np.zeros((N_PLANES, n_var))
        self._linear[:, :self.n_soft] = p.soft_linear_weight
        self._backends = [
            make_backend(p.backend, hessian, self._row_matrix, np.zeros(self.n_soft),
                         np.full(self.n_soft, np.inf), self._clock)
            for _ in range(N_PLANES)]
        self.inputs_to_states = _inputs_to_states(self.discrete_model, self.prediction.n_predict)

    def _build_cost(self) -> np.ndarray:
        """Stage and terminal cost: the Hessian over the moves and the gradient maps."""
        p = self.params
        pred = self.prediction
        n_predict = pred.n_predict
        self._n_dec = pred.n_moves * N_INPUTS
        weights = np.tile(p.quadratic_weights('output_weights'), n_predict)
        rate = np.tile(p.quadratic_weights('input_rate_weights'), pred.n_moves)
        jerk = np.tile(p.quadratic_weights('input_weights'), n_predict)
        theta = pred.outputs_from_moves
        s = pred.inputs_from_moves
        move_hessian = 2.0 * (theta.T @ (weights[:, None] * theta) + np.diag(rate)
                              + s.T @ (jerk[:, None] * s))
        # f = 2 Theta' W (free - ref) + 2 S' Wj (1 (x) u_prev)
        self._gradient_from_error = np.ascontiguousarray(2.0 * (weights[:, None] * theta))
        stacked_input = np.tile(np.eye(N_INPUTS), (n_predict, 1))
        self._gradient_from_input = 2.0 * (s.T @ (jerk[:, None] * stacked_input)).T
        self._has_input_weights = bool(np.any(jerk))
        self._jerk_weights = jerk
        self._weights = weights
        self._free_from_state = np.ascontiguousarray(pred.outputs_from_state.T)
        self._free_from_input = np.ascontiguousarray(pred.outputs_from_input.T)
        self._theta = theta
        self._rate = rate
        self._terminal_gain = None
        if p.terminal_cost:
            terminal_hessian, self._terminal_gain = self._terminal_terms(weights, rate, jerk)
            move_hessian = move_hessian + terminal_hessian
        return move_hessian

    def _build_constraints(self) -> np.ndarray:
        """Constraint rows over [slacks, moves], their segments and the bound buffers."""
        p = self.params
        theta = self._theta
        n_dec = self._n_dec
        # Constraint rows in segments; each segment's bounds are one (possibly strided) slice of
        # the step-major flat outputs minus the free response. With both groups hard, the rows
        # are all outputs of the first constraint_horizon steps: a single contiguous slice.
        horizon = p.constraint_horizon
        outputs_of = {'zmp': (OUTPUT_ZMP,), 'landing': (OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG)}
        modes = {'zmp': p.zmp_constraint, 'landing': p.landing_constraint}
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
        rows.append(np.zeros((0, self.n_soft + n_dec)))
        self._segments = tuple(segments)
        self._lower = np.full((N_PLANES, start), -np.inf)
        self._upper = np.full((N_PLANES, start), np.inf)
        return np.vstack(rows)

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
            self._u_prev = _checked_input(u_prev).copy()
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
        linear[:, self.n_soft:] = error @ self._gradient_from_error
        if self._has_input_weights:
            linear[:, self.n_soft:] += u_prev @ self._gradient_from_input
        if self._terminal_gain is not None:
            terminal = np.concatenate([state, u_prev, y_ref[:, -N_OUTPUTS:]], axis=1)
            linear[:, self.n_soft:] += terminal @ self._terminal_gain
        lower, upper = self._lower, self._upper
        for start, stop, selection, has_lower, has_upper in self._segments:
            free_rows = free[:, selection]
            if has_lower:
                np.subtract(y_min[:, selection], free_rows, out=lower[:, start:stop])
            if has_upper:
                np.subtract(y_max[:, selection], free_rows, out=upper[:, start:stop])

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
        """The paper's cost J (eq. costfunction) of one plane's QP solution.

        Stage terms only: neither the slack penalty nor the terminal cost is included.

        :param solution: QP variables [slacks, moves] of the plane
        :param error: free response minus reference, shape (3 Np,), of the plane
        :param u_prev: jerks applied before the plan, shape (3,)
        :return: J
        """
        moves = solution[self.n_soft:]
        output_error = error + self._theta @ moves
        value = float(output_error @ (self._weights * output_error))
        value += float(moves @ (self._rate * moves))
        if self._has_input_weights:
            jerks = np.tile(u_prev, self.prediction.n_predict) + (
                self.prediction.inputs_from_moves @ moves)
            value += float(jerks @ (self._jerk_weights * jerks))
        return value

    def _terminal_terms(self, weights, rate, jerk) -> tuple:
        """Hessian and gradient map of the terminal cost (xi_N - xi_r)' (P - Q) (xi_N - xi_r).

        xi = [x; u_prev] is the state of the increment form (xi+ = [A B; 0 I] xi + [B; I] du),
        P the stabilising solution of its discrete Riccati equation with the stage weights
        Q = diag(C' W C, W_jerk) with C the tracked outputs, R = W_du, and xi_r the rest state
        of the last reference sample r_N: velocities, accelerations and jerks zero, and the
        three positions whose outputs equal r_N. P - Q leaves out the stage cost of the
        last step, already in the sum.
        """
        from scipy.linalg import solve_discrete_are

        model = self.discrete_model
        pred = self.prediction
        nx, nu = N_STATES, N_INPUTS
        a_aug = np.block([[model.a, model.b], [np.zeros((nu, nx)), np.eye(nu)]])
        b_aug = np.vstack([model.b, np.eye(nu)])
        q_aug = np.zeros((nx + nu, nx + nu))
        q_aug[:nx, :nx] = (self.output_matrix.T @ np.diag(weights[:N_OUTPUTS])
                            @ self.output_matrix)
        q_aug[nx:, nx:] = np.diag(jerk[:nu])
        # A tiny regularisation keeps the Riccati solver well posed when a weight is zero.
        riccati = solve_discrete_are(a_aug, b_aug, q_aug + 1e-9 * np.eye(nx + nu),
                                     np.diag(rate[:nu]))
        terminal = riccati - q_aug
        terminal = 0.5 * (terminal + terminal.T)
        last = slice((pred.n_predict - 1) * nx, pred.n_predict * nx)
        last_input = slice((pred.n_predict - 1) * nu, pred.n_predict * nu)
        from_state = np.vstack([pred.states_from_state[last], np.zeros((nu, nx))])
        from_input = np.vstack([pred.states_from_input[last], np.eye(nu)])
        from_moves = np.vstack([pred.states_from_moves[last], pred.inputs_from_moves[last_input]])
        # Rest state: velocities and accelerations zero, the three positions those whose
        # outputs are the reference (C restricted to the positions is invertible).
        positions = [state_index(mass, POSITION) for mass in (LEFT_LEG, TORSO, RIGHT_LEG)]
        rest = np.zeros((nx + nu, N_OUTPUTS))
        rest[positions] = np.linalg.inv(self.output_matrix[:, positions])
        hessian = 2.0 * from_moves.T @ terminal @ from_moves
        # gradient = 2 G' P_t (F_x x + F_u u_prev - S r_N) = [x, u_prev, r_N] @ gain
        gain = 2.0 * np.vstack([from_state.T, from_input.T, -rest.T]) @ terminal @ from_moves
        return 0.5 * (hessian + hessian.T), np.ascontiguousarray(gain)

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


def _checked_input(u_prev) -> np.ndarray:
    array = np.array(u_prev, dtype=float)
    if array.shape != (N_PLANES, N_INPUTS) or not np.isfinite(array).all():
        raise InputError(f'u_prev must be finite with shape {(N_PLANES, N_INPUTS)}, '
                         f'got {u_prev!r}')
    return array
