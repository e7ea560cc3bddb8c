"""The QP solvers of the MPC behind the interface of biped_mpc.qp_backend.

Backends (BACKENDS): 'daqp' (daqp.Model, dual active set, warm-started; the default),
'quadprog' (Goldfarb-Idnani, exact reference, cold), 'casadi_qpoases' (CasADi conic with
qpOASES), 'casadi_osqp' and 'osqp' (ADMM, warm-started, approximate), 'casadi_daqp' (CasADi
conic with DAQP, cold), 'unconstrained' (ignores every constraint: the unconstrained optimum
-H^-1 f, a lower bound of the solve time and the closed form of tests).
"""
import contextlib
import time
from typing import Callable

import numpy as np

from biped_mpc.errors import ConfigError
from biped_mpc.qp_backend import (c_stdout_silenced, import_solver, QpBackend, QpSolution,
                                  QpStatus, row_violation)

# Infinite bounds go to DAQP as +-1e9, far outside any bound this MPC produces: given +-inf,
# its warm-started solves returned infeasible points as optimal (33 of 440 cycles of the
# paper's walk in daqp 0.11, each then caught by the check below and solved again cold).
_DAQP_INFINITY = 1e9
_DAQP_OPTIMAL = (1, 2)
_DAQP_INFEASIBLE = -1
_DAQP_ITERATION_LIMIT = -4
# A DAQP solution reported optimal is checked against the rows; beyond this violation (m) it is
# solved again from a cold start, and reported INACCURATE if that fails too.
_FEASIBILITY_TOLERANCE = 1e-6


class UnconstrainedBackend(QpBackend):
    """The unconstrained optimum z = -H^-1 f; every constraint is ignored."""

    name = 'unconstrained'

    def _setup(self):
        self._negative_inverse = -np.linalg.inv(self.hessian)

    def solve(self, linear, lower, upper):
        start = self._clock()
        x = self._negative_inverse @ linear
        return QpSolution(x, QpStatus.OPTIMAL, 0, self._clock() - start)


class DaqpBackend(QpBackend):
    """daqp.Model: set up once, then only f and the bounds are updated; warm-started."""

    name = 'daqp'

    def _setup(self):
        daqp = import_solver('daqp', 'daqp')
        self._negative_inverse = -np.linalg.inv(self.hessian)
        if self.n_bounded + self.n_rows == 0:
            return
        self._model = daqp.Model()
        self._upper = np.empty(self.n_bounded + self.n_rows)
        self._lower = np.empty(self.n_bounded + self.n_rows)
        self._upper[:self.n_bounded] = np.clip(self.variable_upper, -_DAQP_INFINITY,
                                               _DAQP_INFINITY)
        self._lower[:self.n_bounded] = np.clip(self.variable_lower, -_DAQP_INFINITY,
                                               _DAQP_INFINITY)
        self._upper[self.n_bounded:] = _DAQP_INFINITY
        self._lower[self.n_bounded:] = -_DAQP_INFINITY
        sense = np.zeros(self.n_bounded + self.n_rows, dtype=np.int32)
        self._model.setup(self.hessian, np.zeros(self.n_variables), self.constraints,
                          self._upper.copy(), self._lower.copy(), sense)
        self._first = True

    def solve(self, linear, lower, upper):
        if self.n_bounded + self.n_rows == 0:
            start = self._clock()
            x = self._negative_inverse @ linear
            return QpSolution(x, QpStatus.OPTIMAL, 0, self._clock() - start)
        # Row bounds are finite or +inf (upper) / -inf (lower): one-sided clipping suffices.
        np.minimum(upper, _DAQP_INFINITY, out=self._upper[self.n_bounded:])
        np.maximum(lower, -_DAQP_INFINITY, out=self._lower[self.n_bounded:])
        elapsed = 0.0
        iterations = 0
        for attempt in range(2):
            start = self._clock()
            self._model.update(f=linear, bupper=self._upper, blower=self._lower)
            x, _, exitflag, info = self._model.solve()
            elapsed += self._clock() - start
            iterations += int(info.get('iterations', -1))
            if exitflag not in _DAQP_OPTIMAL:
                break
            x = np.asarray(x, dtype=float)
            if self.violation(x, lower, upper) <= _FEASIBILITY_TOLERANCE:
                return QpSolution(x, QpStatus.OPTIMAL, iterations, elapsed)
            self.reset()
        else:
            self.reset()
            return self._failure(QpStatus.INACCURATE, iterations, elapsed)
        self.reset()
        return self._failure(_daqp_failure(exitflag), iterations, elapsed)


class QuadprogBackend(QpBackend):
    """quadprog (Goldfarb-Idnani dual active set), cold-started: the exact reference.

    The Cholesky factor of H is computed once and passed in factorised form; rows whose bound
    is infinite are dropped each call.
    """

    name = 'quadprog'

    def _setup(self):
        self._quadprog = import_solver('quadprog', 'quadprog')
        self._r_inverse = np.linalg.inv(self._cholesky.T)
        bounded = np.eye(self.n_variables)[:self.n_bounded]
        self._all_rows = np.vstack([bounded, self.constraints])
        self._bounds_lower = self.variable_lower
        self._bounds_upper = self.variable_upper

    def solve(self, linear, lower, upper):
        lower = np.concatenate([self._bounds_lower, lower])
        upper = np.concatenate([self._bounds_upper, upper])
        finite_lower = np.isfinite(lower)
        finite_upper = np.isfinite(upper)
        rows = np.vstack([self._all_rows[finite_lower], -self._all_rows[finite_upper]])
        rhs = np.concatenate([lower[finite_lower], -upper[finite_upper]])
        start = self._clock()
        if rhs.size == 0:
            x = self._r_inverse @ (self._r_inverse.T @ -linear)
            return QpSolution(x, QpStatus.OPTIMAL, 0, self._clock() - start)
        try:
            x, _, _, iterations, _, _ = self._quadprog.solve_qp(
                self._r_inverse, -linear, rows.T.copy(), rhs, 0, True)
        except ValueError as error:
            elapsed = self._clock() - start
            infeasible = 'inconsistent' in str(error)
            return self._failure(QpStatus.INFEASIBLE if infeasible else QpStatus.FAILED, -1,
                                 elapsed)
        return QpSolution(x, QpStatus.OPTIMAL, int(iterations[0]), self._clock() - start)


class OsqpBackend(QpBackend):
    """OSQP (ADMM) called directly, set up once, warm-started, polished; approximate.

    Without polishing, OSQP's 1e-6 tolerances (in its scaled space) leave jerk moves off by
    up to several m/s^3 on this ill-conditioned QP; polishing brings them to the active-set
    solution in most cycles.
    """

    name = 'osqp'
    exact = False

    def _setup(self):
        osqp = import_solver('osqp', 'osqp')
        from scipy import sparse

        self._osqp = osqp
        bounded = np.eye(self.n_variables)[:self.n_bounded]
        rows = sparse.csc_matrix(np.vstack([bounded, self.constraints]))
        self._solver = osqp.OSQP()
        self._solver.setup(P=sparse.triu(sparse.csc_matrix(self.hessian), format='csc'),
                           q=np.zeros(self.n_variables), A=rows,
                           l=np.concatenate([self.variable_lower, np.full(self.n_rows, -np.inf)]),
                           u=np.concatenate([self.variable_upper, np.full(self.n_rows, np.inf)]),
                           verbose=False, eps_abs=1e-6, eps_rel=1e-6, max_iter=10000,
                           polishing=True, polish_refine_iter=10, warm_starting=True)

    def solve(self, linear, lower, upper):
        status_enum = self._osqp.SolverStatus
        start = self._clock()
        self._solver.update(q=linear, l=np.concatenate([self.variable_lower, lower]),
                            u=np.concatenate([self.variable_upper, upper]))
        with c_stdout_silenced():
            result = self._solver.solve(raise_error=False)
        elapsed = self._clock() - start
        status = result.info.status_val
        iterations = int(result.info.iter)
        if status == status_enum.OSQP_SOLVED:
            return QpSolution(np.asarray(result.x, dtype=float), QpStatus.OPTIMAL, iterations,
                              elapsed)
        mapped = {status_enum.OSQP_PRIMAL_INFEASIBLE: QpStatus.INFEASIBLE,
                  status_enum.OSQP_PRIMAL_INFEASIBLE_INACCURATE: QpStatus.INFEASIBLE,
                  status_enum.OSQP_MAX_ITER_REACHED: QpStatus.ITERATION_LIMIT,
                  status_enum.OSQP_SOLVED_INACCURATE: QpStatus.INACCURATE}
        self.reset()
        return self._failure(mapped.get(status, QpStatus.FAILED), iterations, elapsed)


class CasadiBackend(QpBackend):
    """CasADi's conic interface with a dense plugin; the primal-dual solution is fed back as x0.

    qpOASES hot-starts inside CasADi on repeated calls of the same conic function.
    """

    plugin = 'qpoases'
    exact = True
    # the plugin's C code prints on fd 1 whatever its options say
    prints_to_stdout = False

    def _setup(self):
        casadi = import_solver('casadi', 'casadi')
        options = {'error_on_fail': False}
        options.update(self._plugin_options())
        sparsity = {'h': casadi.Sparsity.dense(self.n_variables, self.n_variables),
                    'a': casadi.Sparsity.dense(self.n_rows, self.n_variables)}
        self._solver = casadi.conic(f'mpc_{self.plugin}', self.plugin, sparsity, options)
        self._h = casadi.DM(self.hessian)
        self._a = casadi.DM(self.constraints)
        self._lbx = casadi.DM(np.concatenate(
            [self.variable_lower, np.full(self.n_variables - self.n_bounded, -np.inf)]))
        self._ubx = casadi.DM(np.concatenate(
            [self.variable_upper, np.full(self.n_variables - self.n_bounded, np.inf)]))
        self._x0 = np.zeros(self.n_variables)
        self._lam_a0 = np.zeros(self.n_rows)
        self._lam_x0 = np.zeros(self.n_variables)

    def _plugin_options(self) -> dict:
        return {}

    def solve(self, linear, lower, upper):
        start = self._clock()
        with c_stdout_silenced() if self.prints_to_stdout else contextlib.nullcontext():
            result = self._solver(h=self._h, g=linear, a=self._a, lba=lower, uba=upper,
                                  lbx=self._lbx, ubx=self._ubx, x0=self._x0,
                                  lam_a0=self._lam_a0, lam_x0=self._lam_x0)
        elapsed = self._clock() - start
        stats = self._solver.stats()
        iterations = int(stats.get('iter_count', -1))
        if stats.get('success', False):
            x = np.asarray(result['x'], dtype=float).reshape(-1)
            self._x0 = x
            self._lam_a0 = np.asarray(result['lam_a'], dtype=float).reshape(-1)
            self._lam_x0 = np.asarray(result['lam_x'], dtype=float).reshape(-1)
            return QpSolution(x, QpStatus.OPTIMAL, iterations, elapsed)
        text = str(stats.get('return_status', '')).lower()
        unified = str(stats.get('unified_return_status', ''))
        self.reset()
        if 'infeasib' in text or 'INFEASIBLE' in unified:
            status = QpStatus.INFEASIBLE
        elif 'max' in text and 'iter' in text or 'LIMITED' in unified:
            status = QpStatus.ITERATION_LIMIT
        else:
            status = QpStatus.FAILED
        return self._failure(status, iterations, elapsed)


class CasadiQpoasesBackend(CasadiBackend):
    """CasADi conic 'qpoases' (online active set, hot start, exact)."""

    name = 'casadi_qpoases'
    plugin = 'qpoases'

    def _plugin_options(self):
        return {'printLevel': 'none', 'sparse': False, 'nWSR': 5000}


class CasadiOsqpBackend(CasadiBackend):
    """CasADi conic 'osqp' (ADMM, warm-started from the previous primal-dual pair)."""

    name = 'casadi_osqp'
    plugin = 'osqp'
    exact = False
    prints_to_stdout = True

    def _plugin_options(self):
        return {'warm_start_primal': True, 'warm_start_dual': True,
                'osqp': {'verbose': False, 'eps_abs': 1e-6, 'eps_rel': 1e-6,
                         'max_iter': 10000, 'polish': True, 'polish_refine_iter': 10}}


class CasadiDaqpBackend(CasadiBackend):
    """CasADi conic 'daqp' (dual active set, cold start on each call, exact)."""

    name = 'casadi_daqp'
    plugin = 'daqp'


_BACKEND_CLASSES = {cls.name: cls for cls in (
    DaqpBackend, QuadprogBackend, CasadiQpoasesBackend, CasadiOsqpBackend, CasadiDaqpBackend,
    OsqpBackend, UnconstrainedBackend)}
BACKENDS = tuple(_BACKEND_CLASSES)


def make_backend(name: str, hessian: np.ndarray, constraints: np.ndarray,
                 variable_lower: np.ndarray, variable_upper: np.ndarray,
                 clock: Callable[[], float] = time.perf_counter) -> QpBackend:
    """Build the backend called name.

    :param name: one of BACKENDS
    :param hessian: H (n, n), positive definite
    :param constraints: A (m, n)
    :param variable_lower: lower bounds of the first nb variables (nb,)
    :param variable_upper: upper bounds of the first nb variables (nb,)
    :param clock: seconds clock bracketing the solver call
    :return: the backend, ready to solve
    :raises ConfigError: for an unknown name or bad matrices
    :raises SolverUnavailableError: if the solver's package is not installed
    """
    if name not in _BACKEND_CLASSES:
        raise ConfigError(f'qp backend must be one of {BACKENDS}, got {name!r}')
    return _BACKEND_CLASSES[name](hessian, constraints, variable_lower, variable_upper, clock)


def solve_once(name: str, hessian: np.ndarray, linear: np.ndarray, constraints: np.ndarray,
               lower: np.ndarray, upper: np.ndarray,
               clock: Callable[[], float] = time.perf_counter) -> QpSolution:
    """Solve a QP with row constraints only once, with nothing kept for a next solve.

    For a QP rebuilt every cycle (the wrench distribution's), a backend's checks and
    factorisations (symmetry, Cholesky, H^-1) cost more than the solve. 'daqp' gets only the
    solver calls of DaqpBackend and its checks (finite stand-ins for infinite bounds, the rows
    checked against the solution; a cold start solved again would give the same point, so a
    violation is reported INACCURATE at once); every other backend is built and solved once.

    :param name: one of BACKENDS
    :param hessian: H (n, n), symmetric positive definite
    :param linear: f (n,)
    :param constraints: A (m, n)
    :param lower: row lower bounds (m,), -inf allowed
    :param upper: row upper bounds (m,), +inf allowed
    :param clock: seconds clock bracketing the solver call
    :return: the solution and its status
    :raises ConfigError: for an unknown name (other backends: bad matrices)
    :raises SolverUnavailableError: if the solver's package is not installed
    """
    if name != DaqpBackend.name:
        return make_backend(name, hessian, constraints, np.zeros(0), np.zeros(0),
                            clock).solve(linear, lower, upper)
    daqp = import_solver('daqp', 'daqp')
    constraints = np.ascontiguousarray(constraints, dtype=float)
    n_rows, n_variables = constraints.shape
    # the calls of DaqpBackend's setup and first solve, so that both give the same x to the bit
    model = daqp.Model()
    model.setup(np.ascontiguousarray(hessian, dtype=float), np.zeros(n_variables), constraints,
                np.full(n_rows, _DAQP_INFINITY), np.full(n_rows, -_DAQP_INFINITY),
                np.zeros(n_rows, dtype=np.int32))
    start = clock()
    model.update(f=np.asarray(linear, dtype=float), bupper=np.minimum(upper, _DAQP_INFINITY),
                 blower=np.maximum(lower, -_DAQP_INFINITY))
    x, _, exitflag, info = model.solve()
    elapsed = clock() - start
    iterations = int(info.get('iterations', -1))
    if exitflag in _DAQP_OPTIMAL:
        x = np.asarray(x, dtype=float)
        if row_violation(constraints, x, lower, upper) <= _FEASIBILITY_TOLERANCE:
            return QpSolution(x, QpStatus.OPTIMAL, iterations, elapsed)
        return QpSolution(np.zeros(len(linear)), QpStatus.INACCURATE, iterations, elapsed)
    return QpSolution(np.zeros(len(linear)), _daqp_failure(exitflag), iterations, elapsed)


def _daqp_failure(exitflag: int) -> QpStatus:
    """The status of a DAQP exit flag that is not optimal."""
    return {_DAQP_INFEASIBLE: QpStatus.INFEASIBLE,
            _DAQP_ITERATION_LIMIT: QpStatus.ITERATION_LIMIT}.get(exitflag, QpStatus.FAILED)
