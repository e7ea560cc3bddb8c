"""Every QP backend on small problems with known solutions."""
import numpy as np
import pytest

from biped_mpc.errors import ConfigError
from biped_mpc.qp_backend import QpStatus
from biped_mpc.qp_backends import BACKENDS, make_backend, solve_once

CONSTRAINED = [name for name in BACKENDS if name != 'unconstrained']
# min 1/2 |x - c|^2 s.t. x0 + x1 <= 1, x0 - x1 >= -inf, 0 <= x2 (variable bound)
HESSIAN = np.eye(3)
ROWS = np.array([[1.0, 1.0, 0.0], [1.0, -1.0, 0.0]])


def known_solution(target):
    """Projection of target on {x0 + x1 <= 1, x2 >= 0}."""
    x = np.array(target, dtype=float)
    excess = x[0] + x[1] - 1.0
    if excess > 0:
        x[:2] -= excess / 2.0
    x[2] = max(x[2], 0.0)
    return x


@pytest.mark.parametrize('backend', CONSTRAINED)
@pytest.mark.parametrize('target', [(2.0, 1.0, -1.0), (0.1, 0.2, 0.3), (5.0, -3.0, 2.0)])
def test_projection_has_the_closed_form_solution(backend, target):
    solver = make_backend(backend, HESSIAN, ROWS, np.array([0.0, -np.inf, -np.inf])[:1],
                          np.array([np.inf]))
    # the variable bound applies to x[0] only: reorder so that it bounds the third unknown
    del solver
    hessian = np.eye(3)
    rows = np.array([[0.0, 1.0, 1.0], [0.0, 1.0, -1.0]])
    solver = make_backend(backend, hessian, rows, np.array([0.0]), np.array([np.inf]))
    reordered = np.array([target[2], target[0], target[1]])
    solution = solver.solve(-reordered, np.array([-np.inf, -np.inf]), np.array([1.0, np.inf]))
    assert solution.status == QpStatus.OPTIMAL
    expected = known_solution(target)
    tolerance = 1e-5 if backend in ('osqp', 'casadi_osqp') else 1e-9
    np.testing.assert_allclose(solution.x, [expected[2], expected[0], expected[1]],
                               atol=tolerance)
    assert solver.violation(solution.x, np.array([-np.inf, -np.inf]),
                            np.array([1.0, np.inf])) <= tolerance
    assert solution.solve_time >= 0.0


def test_unconstrained_backend_ignores_the_rows():
    solver = make_backend('unconstrained', HESSIAN, ROWS, np.zeros(0), np.zeros(0))
    solution = solver.solve(-np.array([2.0, 1.0, -1.0]), np.full(2, -np.inf), np.array([1.0, 0.0]))
    np.testing.assert_allclose(solution.x, [2.0, 1.0, -1.0])


@pytest.mark.parametrize('backend', ['daqp', 'quadprog', 'casadi_qpoases', 'casadi_daqp', 'osqp'])
def test_infeasible_rows_give_a_status_not_an_exception(backend):
    rows = np.array([[1.0, 0.0], [1.0, 0.0]])
    solver = make_backend(backend, np.eye(2), rows, np.zeros(0), np.zeros(0))
    solution = solver.solve(np.zeros(2), np.array([1.0, -np.inf]), np.array([np.inf, 0.0]))
    assert solution.status != QpStatus.OPTIMAL
    assert np.all(solution.x == 0.0)
    # and the backend works again afterwards
    solution = solver.solve(np.zeros(2), np.array([1.0, -np.inf]), np.array([np.inf, 2.0]))
    assert solution.status == QpStatus.OPTIMAL
    assert solution.x[0] == pytest.approx(1.0, abs=1e-5)


def test_clock_brackets_the_solver_call():
    ticks = iter([10.0, 10.25])
    solver = make_backend('daqp', HESSIAN, ROWS, np.zeros(0), np.zeros(0),
                          clock=lambda: next(ticks))
    solution = solver.solve(np.zeros(3), np.full(2, -np.inf), np.full(2, np.inf))
    assert solution.solve_time == pytest.approx(0.25)


@pytest.mark.parametrize('hessian, rows', [
    (np.array([[1.0, 2.0], [0.0, 1.0]]), np.zeros((0, 2))),
    (-np.eye(2), np.zeros((0, 2))),
    (np.eye(2), np.zeros((1, 3))),
])
def test_bad_matrices_raise(hessian, rows):
    with pytest.raises(ConfigError):
        make_backend('quadprog', hessian, rows, np.zeros(0), np.zeros(0))


def test_unknown_backend_raises():
    with pytest.raises(ConfigError, match='backend'):
        make_backend('cplex', np.eye(2), np.zeros((0, 2)), np.zeros(0), np.zeros(0))


@pytest.mark.parametrize('backend', CONSTRAINED)
def test_a_solve_without_active_constraints_prints_nothing(backend, capfd):
    # OSQP's C code prints "Polishing not needed" here whatever its verbose setting
    solver = make_backend(backend, HESSIAN, ROWS, np.zeros(0), np.zeros(0))
    capfd.readouterr()  # qpOASES prints its banner once, when it is built
    print('before', flush=True)
    solution = solver.solve(-np.array([0.1, 0.2, 0.3]), np.full(2, -np.inf), np.full(2, 5.0))
    print('after', flush=True)
    assert solution.status == QpStatus.OPTIMAL
    assert capfd.readouterr().out == 'before\nafter\n'


@pytest.mark.parametrize('backend', ['daqp', 'quadprog'])
@pytest.mark.parametrize('target', [(2.0, 1.0, -1.0), (0.1, 0.2, 0.3), (5.0, -3.0, 2.0)])
def test_solve_once_has_the_closed_form_solution(backend, target):
    # the variable bound x2 >= 0 as a third row
    rows = np.vstack([ROWS, [0.0, 0.0, 1.0]])
    solution = solve_once(backend, HESSIAN, -np.array(target), rows,
                          np.array([-np.inf, -np.inf, 0.0]), np.array([1.0, np.inf, np.inf]))
    assert solution.status == QpStatus.OPTIMAL
    np.testing.assert_allclose(solution.x, known_solution(target), atol=1e-9)


@pytest.mark.parametrize('seed', range(5))
def test_solve_once_gives_the_backend_s_point_to_the_bit(seed):
    # the wrench distribution solves once per cycle: the one-shot path must not move a
    # deterministic trial by an ulp
    rng = np.random.default_rng(seed)
    factor = rng.normal(size=(12, 12))
    hessian = factor @ factor.T + 0.1 * np.eye(12)
    rows = rng.normal(size=(22, 12))
    lower = np.where(rng.random(22) < 0.3, rng.normal(size=22) - 1.0, -np.inf)
    upper = np.where(rng.random(22) < 0.5, rng.normal(size=22) + 1.0, np.inf)
    linear = rng.normal(size=12) * 10.0
    once = solve_once('daqp', hessian, linear, rows, lower, upper)
    built = make_backend('daqp', hessian, rows, np.zeros(0), np.zeros(0)).solve(linear, lower,
                                                                                upper)
    assert once.status == built.status
    np.testing.assert_array_equal(once.x, built.x)


def test_solve_once_reports_infeasible_rows():
    rows = np.array([[1.0, 0.0], [1.0, 0.0]])
    for backend in ('daqp', 'quadprog'):
        solution = solve_once(backend, np.eye(2), np.zeros(2), rows, np.array([1.0, -np.inf]),
                              np.array([np.inf, 0.0]))
        assert solution.status != QpStatus.OPTIMAL
        assert np.all(solution.x == 0.0)
