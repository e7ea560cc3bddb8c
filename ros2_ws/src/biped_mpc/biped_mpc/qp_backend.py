"""The interface of the MPC's QP solvers: the problem, the result, the abstract backend.

Every backend solves

    minimise   1/2 z' H z + f' z
    subject to lower <= A z <= upper              (rows; +-inf allowed)
               variable_lower <= z[:nb] <= variable_upper   (first nb variables only)

where H, A and the variable bounds are fixed when the backend is built and f, lower and upper
change every call. Backends keep their own warm start between calls. A failed or infeasible
solve is a status, never an exception. The solve time covers the solver call only and is
measured with the clock given at construction (time.perf_counter by default). The solvers are
in biped_mpc.qp_backends.
"""
import abc
import contextlib
from dataclasses import dataclass
import enum
import os
import sys
import time
from typing import Callable

import numpy as np

from biped_mpc.errors import ConfigError, SolverUnavailableError


class QpStatus(enum.IntEnum):
    """Outcome of one QP solve."""

    OPTIMAL = 0
    INFEASIBLE = 1
    ITERATION_LIMIT = 2
    INACCURATE = 3
    FAILED = 4


@dataclass(frozen=True)
class QpSolution:
    """Result of one QP solve.

    :param x: the solution (n,); zeros unless status is OPTIMAL
    :param status: the outcome
    :param iterations: solver iterations (-1 when the solver does not report them)
    :param solve_time: time spent in the solver call (s), a diagnostic
    """

    x: np.ndarray
    status: QpStatus
    iterations: int
    solve_time: float


class QpBackend(abc.ABC):
    """A QP solver with fixed H, A and variable bounds, and per-call f and row bounds.

    :param hessian: H, symmetric positive definite, shape (n, n)
    :param constraints: A, shape (m, n), m >= 0
    :param variable_lower: lower bounds of the first nb variables, shape (nb,)
    :param variable_upper: upper bounds of the first nb variables, shape (nb,)
    :param clock: returns seconds; brackets the solver call to measure the solve time
    :raises ConfigError: if the shapes disagree or H is not positive definite
    """

    name = 'abstract'
    exact = True

    def __init__(self, hessian: np.ndarray, constraints: np.ndarray,
                 variable_lower: np.ndarray, variable_upper: np.ndarray,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        hessian = np.ascontiguousarray(hessian, dtype=float)
        constraints = np.ascontiguousarray(constraints, dtype=float)
        n = hessian.shape[0]
        if hessian.shape != (n, n) or not np.allclose(hessian, hessian.T, rtol=1e-10,
                                                       atol=1e-12 * np.abs(hessian).max()):
            raise ConfigError(f'hessian must be a symmetric square matrix, got {hessian.shape}')
        if constraints.ndim != 2 or constraints.shape[1] != n:
            raise ConfigError(f'constraints must have {n} columns, got {constraints.shape}')
        self.variable_lower = np.asarray(variable_lower, dtype=float).reshape(-1)
        self.variable_upper = np.asarray(variable_upper, dtype=float).reshape(-1)
        if self.variable_lower.shape != self.variable_upper.shape or self.variable_lower.size > n:
            raise ConfigError(f'variable bounds must have the same length, at most {n}, got '
                              f'{self.variable_lower.size} and {self.variable_upper.size}')
        try:
            self._cholesky = np.linalg.cholesky(hessian)
        except np.linalg.LinAlgError as error:
            raise ConfigError('hessian must be positive definite') from error
        self.hessian = hessian
        self.constraints = constraints
        self.n_variables = n
        self.n_rows = constraints.shape[0]
        self.n_bounded = self.variable_lower.size
        self._clock = clock
        self._setup()

    def _setup(self) -> None:
        """Build solver workspaces once (subclasses)."""

    def reset(self) -> None:
        """Forget the warm start (after a failure or a discontinuity)."""
        self._setup()

    @abc.abstractmethod
    def solve(self, linear: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> QpSolution:
        """Solve with the linear cost term f and the row bounds of this call.

        :param linear: f, shape (n,)
        :param lower: row lower bounds, shape (m,), -inf allowed
        :param upper: row upper bounds, shape (m,), +inf allowed
        :return: the solution and its status
        """

    def _failure(self, status: QpStatus, iterations: int, solve_time: float) -> QpSolution:
        return QpSolution(np.zeros(self.n_variables), status, iterations, solve_time)

    def violation(self, x: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> float:
        """Largest violation of the rows and variable bounds by x (0 if feasible).

        :param x: a candidate solution (n,)
        :param lower: row lower bounds (m,)
        :param upper: row upper bounds (m,)
        :return: max(0, lower - A x, A x - upper, bound violations)
        """
        worst = row_violation(self.constraints, x, lower, upper) if self.n_rows else 0.0
        if self.n_bounded:
            bounded = x[:self.n_bounded]
            worst = max(worst, np.maximum(self.variable_lower - bounded,
                                          bounded - self.variable_upper).max())
        return float(worst)


def row_violation(constraints: np.ndarray, x: np.ndarray, lower: np.ndarray,
                  upper: np.ndarray) -> float:
    """Largest violation of the row bounds lower <= A x <= upper by x (0 if feasible).

    :param constraints: A (m, n)
    :param x: a candidate solution (n,)
    :param lower: row lower bounds (m,), -inf allowed
    :param upper: row upper bounds (m,), +inf allowed
    """
    rows = constraints @ x
    return float(max(np.maximum(lower - rows, rows - upper).max(initial=0.0), 0.0))


@contextlib.contextmanager
def c_stdout_silenced():
    """Discard what the solver writes to standard output meanwhile.

    OSQP prints "Polishing not needed - no active set detected at optimal point" on every
    solve without an active constraint, whatever its verbose setting (osqp/osqp issue #785),
    which at 50 Hz buries a node's log. The osqp package writes it through Python's
    sys.stdout, CasADi's plugin to file descriptor 1: both are silenced. Output of other
    threads to standard output during the solve is lost too, a price only the OSQP backends
    pay.
    """
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, 'w') as devnull:
            os.dup2(devnull.fileno(), 1)
            with contextlib.redirect_stdout(devnull):
                yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)


def import_solver(module: str, package: str):
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as error:
        raise SolverUnavailableError(
            f'the {module!r} QP backend needs the Python package {package!r}: '
            f'pip install {package}') from error
