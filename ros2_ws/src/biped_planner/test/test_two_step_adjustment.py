"""Two-step adjustment QP: the unpushed optimum, closed forms, an independent solver, limits."""
import math

import numpy as np
import pytest
from scipy.optimize import minimize

from biped_planner.errors import InputError
from biped_planner.sides import LEFT, RIGHT
from biped_planner.step_adjustment import (SOLVERS, STATUS_OPTIMAL, STATUS_SATURATED,
                                           StepAdjuster, StepAdjustmentParams)
from biped_planner.two_step_adjustment import TwoStepAdjuster

# The humanoid's limits; walking in place on feet 0.14 m apart, 0.3 s steps, 0.1 s double
# support; the right foot stands, the left swings.
PARAMS = StepAdjustmentParams(com_height=0.5, reach_forward=0.3, reach_backward=0.2,
                              width_min=0.1, width_max=0.3, step_time_min=0.15,
                              step_time_max=0.45)
OMEGA = PARAMS.omega
STANCE = (0.0, -0.07, 0.0, RIGHT)
FIRST, SECOND = (0.0, 0.07), (0.0, -0.07)
DURATION, SECOND_TIME = 0.3, 0.25


def reference_dcm(t, stance=STANCE):
    """The in-place gait's DCM t into the single support (it starts 2.56 cm inside)."""
    x, y = stance[:2]
    inward = 0.0256 if stance[3] == RIGHT else -0.0256
    return np.array([x, y + inward * math.exp(OMEGA * t)])


def solve(dcm, t=0.05, solver='daqp', stance=STANCE, first=FIRST, second=SECOND, **limits):
    params = StepAdjustmentParams(**{**PARAMS.__dict__, 'solver': solver, **limits})
    return TwoStepAdjuster(params).solve(t, stance, first, DURATION, dcm, stance[:2], second,
                                         SECOND_TIME, reference_dcm(t, stance), stance[:2])


@pytest.fixture(params=SOLVERS)
def solver(request):
    return request.param


@pytest.mark.parametrize('t', [0.0, 0.05, 0.12])
def test_unpushed_walk_is_the_optimum(solver, t):
    result = solve(reference_dcm(t), t=t, solver=solver)
    assert result.status == STATUS_OPTIMAL and not result.adjusted
    np.testing.assert_allclose(result.location, FIRST, atol=1e-9)
    assert result.duration == pytest.approx(DURATION, abs=1e-9)
    # the offset at touchdown is the pendulum's, in closed form
    xi_touchdown = np.array(STANCE[:2]) + (reference_dcm(t) - STANCE[:2]) * math.exp(
        OMEGA * (DURATION - t))
    np.testing.assert_allclose(result.dcm_offset, xi_touchdown - FIRST, atol=1e-9)


def test_mirrored_stance_gives_the_mirrored_answer(solver):
    left_stance = (0.0, 0.07, 0.0, LEFT)
    push = np.array([0.01, -0.04])
    right = solve(reference_dcm(0.05) + push, solver=solver)
    left = solve(reference_dcm(0.05, left_stance) + push * [1, -1], solver=solver,
                 stance=left_stance, first=(0.0, -0.07), second=(0.0, 0.07))
    np.testing.assert_allclose(left.location, right.location * [1, -1], atol=1e-7)
    assert left.duration == pytest.approx(right.duration, abs=1e-7)
    assert left.active_limits == right.active_limits


WIDE = dict(reach_forward=5.0, reach_backward=5.0, width_min=-1.0, width_max=5.0,
            step_time_min=0.05, step_time_max=5.0)


def test_free_answer_is_the_closed_form_of_the_equality_constrained_qp(solver):
    """No bound binds: z = t + W^-1 A' (A W^-1 A')^-1 (b - A t)."""
    t, xi = 0.05, reference_dcm(0.05) + [0.03, 0.01]
    result = solve(xi, t=t, solver=solver, **WIDE)
    assert result.status == STATUS_OPTIMAL and result.adjusted
    tau2 = math.exp(OMEGA * SECOND_TIME)
    p, s = np.array(STANCE[:2]), np.array(STANCE[:2])
    tau1 = math.exp(OMEGA * (DURATION - t))
    d1, d2 = np.subtract(FIRST, s), np.subtract(SECOND, FIRST)
    beta2 = tau2 * (p - s) + tau2 * (reference_dcm(t) - p) * tau1 - tau2 * d1 - d2
    target = np.concatenate([d1, [tau1], d2, beta2])
    u, w, b = PARAMS.location_weight, PARAMS.timing_weight, PARAMS.offset_weight
    weights = np.array([u, u, w, u, u, b, b])
    spread = xi - p
    a = np.array([[tau2, 0.0, -tau2 * spread[0], 1.0, 0.0, 1.0, 0.0],
                  [0.0, tau2, -tau2 * spread[1], 0.0, 1.0, 0.0, 1.0]])
    rhs = tau2 * (p - s)
    inverse = np.diag(1.0 / weights)
    z = target + inverse @ a.T @ np.linalg.solve(a @ inverse @ a.T, rhs - a @ target)
    np.testing.assert_allclose(result.location, s + z[:2], atol=1e-7)
    assert result.remaining_time == pytest.approx(math.log(z[2]) / OMEGA, abs=1e-7)


@pytest.mark.parametrize('push', [(0.0, -0.03), (0.0, -0.06), (0.02, -0.1), (0.05, 0.04),
                                  (-0.04, 0.0), (0.0, 0.12)])
def test_against_an_independent_solver(solver, push):
    t = 0.05
    xi = reference_dcm(t) + push
    result = solve(xi, t=t, solver=solver)
    tau2 = math.exp(OMEGA * SECOND_TIME)
    p = s = np.array(STANCE[:2])
    tau1_nominal = math.exp(OMEGA * (DURATION - t))
    d1, d2 = np.subtract(FIRST, s), np.subtract(SECOND, FIRST)
    beta2 = tau2 * (p - s) + tau2 * (reference_dcm(t) - p) * tau1_nominal - tau2 * d1 - d2
    target = np.concatenate([d1, [tau1_nominal], d2, beta2])
    u, w, b = PARAMS.location_weight, PARAMS.timing_weight, PARAMS.offset_weight
    weights = np.array([u, u, w, u, u, b, b])

    def offset(z):  # beta2 from the equality, the rest free
        xi1 = p + (xi - p) * z[2]
        xi2 = s + z[:2] + (xi1 - s - z[:2]) * tau2
        return xi2 - (s + z[:2] + z[3:5])

    def cost(z):
        full = np.concatenate([z, offset(z)])
        return float(np.sum(weights * (full - target) ** 2))

    bounds = [(-0.2, 0.3), (0.1, 0.3), (math.exp(OMEGA * 0.1), math.exp(OMEGA * 0.4)),
              (-0.2, 0.3), (-0.3, -0.1)]
    best = min((minimize(cost, start, bounds=bounds, method='L-BFGS-B',
                         options={'ftol': 1e-15, 'gtol': 1e-12})
                for start in (target[:5], [0.0, 0.2, 2.0, 0.0, -0.2])), key=lambda r: r.fun)
    np.testing.assert_allclose(result.location, s + best.x[:2], atol=2e-4)
    assert result.remaining_time == pytest.approx(math.log(best.x[2]) / OMEGA, abs=2e-4)


def test_push_towards_the_stance_foot_lands_the_first_step_sooner_than_one_step(solver):
    """The one-step answer cannot see that the stance foot must step out next."""
    t, xi = 0.05, reference_dcm(0.05) + [0.0, -0.06]
    two = solve(xi, t=t, solver=solver)
    params = StepAdjustmentParams(**{**PARAMS.__dict__, 'solver': solver})
    nominal_offset = (np.array(STANCE[:2]) + (reference_dcm(t) - STANCE[:2])
                      * math.exp(OMEGA * (DURATION - t)) - FIRST)
    one = StepAdjuster(params).solve(t, STANCE, FIRST, DURATION, xi, STANCE[:2],
                                     nominal_offset=nominal_offset)
    assert two.status == STATUS_SATURATED
    assert {'width_min', 'time_min', 'second_width_max'} <= set(two.active_limits)
    assert two.duration == pytest.approx(PARAMS.step_time_min, abs=1e-6)
    assert one.duration > two.duration + 0.05
    np.testing.assert_allclose(two.location, (0.0, -0.07 + PARAMS.width_min), atol=1e-7)


@pytest.mark.parametrize('bad', [dict(dcm=(math.nan, 0.0)), dict(dcm=(0.0,)),
                                 dict(t=-0.1), dict(t=math.inf)])
def test_bad_input_raises(bad):
    kwargs = dict(dcm=reference_dcm(0.05), t=0.05)
    kwargs.update(bad)
    with pytest.raises(InputError):
        solve(kwargs.pop('dcm'), **kwargs)


def test_bad_side_and_times_raise():
    adjuster = TwoStepAdjuster(PARAMS)
    args = [0.05, (0.0, 0.0, 0.0, 7), FIRST, DURATION, (0, 0), (0, 0), SECOND, SECOND_TIME,
            (0, 0), (0, 0)]
    with pytest.raises(InputError, match='side'):
        adjuster.solve(*args)
    args[1] = STANCE
    for index in (3, 7):
        for value in (0.0, -1.0, math.nan):
            bad = list(args)
            bad[index] = value
            with pytest.raises(InputError):
                adjuster.solve(*bad)
