"""Step location and timing adjustment QP: closed forms, an independent solver, limits."""
import math
import types

import numpy as np
import pytest
from scipy.optimize import minimize

from biped_planner.capture_point import (
    dcm_at, instantaneous_capture_point, lipm_state_at)
from biped_planner.step_adjustment import (
    SOLVERS, STATUS_BLOCKED, STATUS_FAILED, STATUS_OPTIMAL, STATUS_SATURATED, StepAdjuster,
    StepAdjustmentParams)
from biped_planner.errors import ConfigError, InputError
from biped_planner.sides import LEFT, RIGHT

PARAMS = StepAdjustmentParams()
OMEGA = PARAMS.omega
# stance left ankle at (0, 0.1), the right foot steps 0.2 m ahead, 0.4 s steps
STANCE = (0.0, 0.1, 0.0, LEFT)
NOMINAL = (0.2, -0.1)
DURATION = 0.4


def rotation(yaw):
    return np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])


def periodic_dcm(stance, nominal, duration, t):
    """DCM now on the periodic gait's path, and the offset it reaches at touchdown (world)."""
    x, y, yaw, _ = stance
    turn = rotation(yaw)
    step = turn.T @ (np.asarray(nominal) - [x, y])
    tau = math.exp(OMEGA * duration)
    offset = np.array([step[0] / (tau - 1.0), -step[1] / (1.0 + tau)])
    at_lift_off = np.array([offset[0], -offset[1]])
    return np.array([x, y]) + turn @ at_lift_off * math.exp(OMEGA * t), turn @ offset


@pytest.fixture(params=SOLVERS)
def solver(request):
    return request.param


@pytest.mark.parametrize('side', [LEFT, RIGHT])
@pytest.mark.parametrize('yaw', [0.0, 0.7, -2.5])
@pytest.mark.parametrize('t', [0.0, 0.15, 0.3])
def test_undisturbed_step_stays_nominal(solver, side, yaw, t):
    sigma = 1.0 if side == RIGHT else -1.0
    stance = (0.3, -0.2, yaw, side)
    nominal = np.array(stance[:2]) + rotation(yaw) @ [0.15, sigma * 0.2]
    xi, offset = periodic_dcm(stance, nominal, DURATION, t)
    result = StepAdjuster(StepAdjustmentParams(solver=solver)).solve(
        t, stance, nominal, DURATION, xi, stance[:2])
    assert result.status == STATUS_OPTIMAL and not result.adjusted
    assert result.active_limits == ()
    np.testing.assert_allclose(result.location, nominal, atol=1e-8)
    assert result.duration == pytest.approx(DURATION, abs=1e-9)
    assert result.remaining_time == pytest.approx(DURATION - t, abs=1e-9)
    np.testing.assert_allclose(result.dcm_offset, offset, atol=1e-8)


def test_explicit_nominal_offset(solver):
    offset, t = np.array([0.03, 0.05]), 0.1
    # the DCM that reaches nominal + offset at the nominal touchdown
    xi = dcm_at(np.add(NOMINAL, offset), STANCE[:2], OMEGA, -(DURATION - t))
    result = StepAdjuster(StepAdjustmentParams(solver=solver)).solve(
        t, STANCE, NOMINAL, DURATION, xi, STANCE[:2], nominal_offset=offset)
    assert result.status == STATUS_OPTIMAL and not result.adjusted
    np.testing.assert_allclose(result.location, NOMINAL, atol=1e-8)
    np.testing.assert_allclose(result.dcm_offset, offset, atol=1e-8)


WIDE = dict(reach_forward=5.0, reach_backward=5.0, width_min=-1.0, width_max=5.0,
            step_time_min=0.05, step_time_max=5.0)


@pytest.mark.parametrize('push', [(0.4, 0.0), (0.0, 0.5), (-0.3, -0.2), (0.6, 0.3)])
def test_step_at_the_capture_point_stops_the_pendulum(solver, push):
    """Nominal offset zero: the QP steps onto the capture point and the LIPM comes to rest."""
    params = StepAdjustmentParams(solver=solver, location_weight=1e-3, offset_weight=1e6,
                                  **WIDE)
    t, zmp = 0.1, np.array(STANCE[:2])
    com, velocity = np.array([0.02, 0.05]), np.asarray(push, dtype=float)
    xi = instantaneous_capture_point(com, velocity, OMEGA)
    result = StepAdjuster(params).solve(t, STANCE, NOMINAL, DURATION, xi, zmp,
                                        nominal_offset=(0.0, 0.0))
    assert result.status == STATUS_OPTIMAL and result.adjusted
    # exact LIPM through the rest of the step, then on the new foot
    com, velocity = lipm_state_at(com, velocity, zmp, OMEGA, result.remaining_time)
    np.testing.assert_allclose(result.location,
                               instantaneous_capture_point(com, velocity, OMEGA), atol=1e-6)
    com, velocity = lipm_state_at(com, velocity, result.location, OMEGA, 2.0)
    np.testing.assert_allclose(com, result.location, atol=2e-3)
    np.testing.assert_allclose(velocity, 0.0, atol=1e-2)


@pytest.mark.parametrize('push', [(0.1, 0.0), (0.05, 0.08), (-0.06, -0.03)])
@pytest.mark.parametrize('weights', [(1.0, 1000.0), (1.0, 1.0), (5.0, 0.5)])
def test_fixed_timing_matches_closed_form(solver, push, weights):
    """T_min = T_max: u = (w_u u_nom + w_b (xi(T) - b_nom)) / (w_u + w_b)."""
    location_weight, offset_weight = weights
    params = StepAdjustmentParams(solver=solver, location_weight=location_weight,
                                  offset_weight=offset_weight, step_time_min=DURATION,
                                  step_time_max=DURATION, reach_forward=5.0,
                                  reach_backward=5.0, width_min=-1.0, width_max=5.0)
    t = 0.15
    xi, offset = periodic_dcm(STANCE, NOMINAL, DURATION, t)
    xi = xi + push
    result = StepAdjuster(params).solve(t, STANCE, NOMINAL, DURATION, xi, STANCE[:2])
    at_touchdown = dcm_at(xi, STANCE[:2], OMEGA, DURATION - t)
    expected = (location_weight * np.asarray(NOMINAL)
                + offset_weight * (at_touchdown - offset)) / (location_weight + offset_weight)
    np.testing.assert_allclose(result.location, expected, atol=1e-7)
    assert result.duration == pytest.approx(DURATION, abs=1e-9)
    np.testing.assert_allclose(result.location + result.dcm_offset, at_touchdown, atol=1e-7)


def reference_solution(params, t, stance, nominal, duration, xi, zmp):
    """SLSQP on (u, tau, b) in the world frame, constraints written independently."""
    x, y, yaw, side = stance
    turn = rotation(yaw)
    local = turn.T @ (np.asarray(nominal) - [x, y])
    tau_step = math.exp(OMEGA * duration)
    offset = turn @ [local[0] / (tau_step - 1.0), -local[1] / (1.0 + tau_step)]
    t_low = max(params.step_time_min - t, params.min_remaining_time)
    t_high = max(params.step_time_max - t, t_low)
    tau_nominal = math.exp(OMEGA * min(max(duration - t, t_low), t_high))
    lateral = 1.0 if side == RIGHT else -1.0

    scale = 1.0 / max(params.location_weight, params.timing_weight, params.offset_weight)
    weights = scale * np.array([params.location_weight] * 2 + [params.timing_weight]
                               + [params.offset_weight] * 2)
    target = np.concatenate([nominal, [tau_nominal], offset])
    # forward, backward, no-crossing and widest rows of the stance frame, as G u <= h
    rows = np.array([turn[:, 0], -turn[:, 0], -lateral * turn[:, 1], lateral * turn[:, 1]])
    limits = np.array([params.reach_forward, params.reach_backward, -params.width_min,
                       params.width_max]) + rows @ [x, y]
    reach = np.hstack([-rows, np.zeros((4, 3))])
    equality = np.hstack([np.eye(2), -(xi - zmp)[:, None], np.eye(2)])
    constraints = [{'type': 'eq', 'fun': lambda z: equality @ z - zmp,
                    'jac': lambda z: equality},
                   {'type': 'ineq', 'fun': lambda z: limits + reach @ z,
                    'jac': lambda z: reach}]
    bounds = [(None, None)] * 2 + [(math.exp(OMEGA * t_low), math.exp(OMEGA * t_high))] + [
        (None, None)] * 2
    result = minimize(lambda z: np.sum(weights * (z - target) ** 2), target,
                      jac=lambda z: 2.0 * weights * (z - target), method='SLSQP',
                      bounds=bounds, constraints=constraints,
                      options={'ftol': 1e-14, 'maxiter': 1000})
    assert result.success, result.message
    return result.x[:2], t + math.log(result.x[2]) / OMEGA, result.x[3:]


def test_matches_independent_solver_on_random_states(solver):
    rng = np.random.default_rng(15)
    adjuster = StepAdjuster(StepAdjustmentParams(solver=solver))
    saturated = 0
    for _ in range(200):
        side = int(rng.integers(2))
        sigma = 1.0 if side == RIGHT else -1.0
        stance = (*rng.uniform(-1.0, 1.0, 2), rng.uniform(-math.pi, math.pi), side)
        duration, t = rng.uniform(0.3, 0.7), rng.uniform(0.0, 0.5)
        nominal = np.array(stance[:2]) + rotation(stance[2]) @ [
            rng.uniform(-0.1, 0.3), sigma * rng.uniform(0.12, 0.3)]
        xi, _ = periodic_dcm(stance, nominal, duration, t)
        xi = xi + rng.normal(0.0, 0.08, 2)
        zmp = np.array(stance[:2]) + rng.uniform(-0.03, 0.03, 2)
        result = adjuster.solve(t, stance, nominal, duration, xi, zmp)
        location, total, offset = reference_solution(PARAMS, t, stance, nominal, duration,
                                                     xi, zmp)
        assert result.status in (STATUS_OPTIMAL, STATUS_SATURATED)
        saturated += result.status == STATUS_SATURATED
        np.testing.assert_allclose(result.location, location, atol=1e-5)
        assert result.duration == pytest.approx(total, abs=1e-5)
        np.testing.assert_allclose(result.dcm_offset, offset, atol=1e-5)
    # the draw exercises both the free and the limited optimum
    assert 20 < saturated < 180


@pytest.mark.parametrize('yaw', [0.0, 1.2])
def test_push_towards_stance_side_stops_at_no_crossing(solver, yaw):
    params = StepAdjustmentParams(solver=solver)
    stance = (0.0, 0.1, yaw, LEFT)
    nominal = np.array(stance[:2]) + rotation(yaw) @ [0.2, -0.2]
    xi, _ = periodic_dcm(stance, nominal, DURATION, 0.1)
    xi = xi + rotation(yaw) @ [0.0, 0.25]
    result = StepAdjuster(params).solve(0.1, stance, nominal, DURATION, xi, stance[:2])
    assert result.status == STATUS_SATURATED and 'width_min' in result.active_limits
    local = rotation(yaw).T @ (result.location - stance[:2])
    assert local[1] == pytest.approx(-params.width_min, abs=1e-8)


@pytest.mark.parametrize('push, limit', [((3.0, 0.0), 'reach_forward'),
                                         ((-3.0, 0.0), 'reach_backward'),
                                         ((0.0, -3.0), 'width_max')])
def test_huge_push_saturates_reach(solver, push, limit):
    params = StepAdjustmentParams(solver=solver)
    xi, _ = periodic_dcm(STANCE, NOMINAL, DURATION, 0.1)
    result = StepAdjuster(params).solve(0.1, STANCE, NOMINAL, DURATION, xi + push,
                                        STANCE[:2])
    assert result.status == STATUS_SATURATED and limit in result.active_limits
    assert np.all(np.isfinite(result.location)) and np.all(np.isfinite(result.dcm_offset))
    local = result.location - STANCE[:2]
    assert -params.reach_backward - 1e-8 <= local[0] <= params.reach_forward + 1e-8
    assert params.width_min - 1e-8 <= -local[1] <= params.width_max + 1e-8


def test_forward_push_shortens_the_step(solver):
    """Location is the cheaper adjustment; timing takes over once the reach saturates."""
    adjuster = StepAdjuster(StepAdjustmentParams(solver=solver))
    xi, _ = periodic_dcm(STANCE, NOMINAL, DURATION, 0.1)
    results = [adjuster.solve(0.1, STANCE, NOMINAL, DURATION, xi + (push, 0.0), STANCE[:2])
               for push in (0.0, 0.002, 0.05, 0.1, 0.3)]
    durations = [result.duration for result in results]
    assert durations[0] == pytest.approx(DURATION)
    assert abs(durations[1] - DURATION) < 1e-4 and results[1].active_limits == ()
    assert durations[2] < DURATION - 0.01
    assert durations[4] == pytest.approx(PARAMS.step_time_min, abs=1e-9)
    assert 'time_min' in results[4].active_limits
    assert all(np.diff(durations) < 0.0)


def test_late_step_lands_at_once(solver):
    xi, _ = periodic_dcm(STANCE, NOMINAL, DURATION, 0.1)
    result = StepAdjuster(StepAdjustmentParams(solver=solver)).solve(
        1.0, STANCE, NOMINAL, DURATION, xi, STANCE[:2])
    assert result.remaining_time == pytest.approx(PARAMS.min_remaining_time)
    assert result.duration == pytest.approx(1.0 + PARAMS.min_remaining_time)


def test_keep_out_box_moves_the_step_to_the_nearest_face(solver):
    adjuster = StepAdjuster(StepAdjustmentParams(solver=solver))
    xi, _ = periodic_dcm(STANCE, NOMINAL, DURATION, 0.1)
    free = adjuster.solve(0.1, STANCE, NOMINAL, DURATION, xi, STANCE[:2],
                          keep_out_boxes=[(1.0, 1.0, 2.0, 2.0)])
    np.testing.assert_allclose(free.location, NOMINAL, atol=1e-8)
    box = (0.17, -0.3, 0.4, 0.0)  # nearest face of the nominal step: x = 0.17
    result = adjuster.solve(0.1, STANCE, NOMINAL, DURATION, xi, STANCE[:2],
                            keep_out_boxes=[(1.0, 1.0, 2.0, 2.0), box])
    assert result.status == STATUS_SATURATED and result.active_limits == ('keep_out_1',)
    assert result.location[0] == pytest.approx(0.17, abs=1e-3) and result.location[0] < 0.17
    assert result.adjusted


def test_keep_out_boxes_side_by_side(solver):
    adjuster = StepAdjuster(StepAdjustmentParams(solver=solver))
    xi, _ = periodic_dcm(STANCE, NOMINAL, DURATION, 0.1)
    boxes = [(0.17, -0.3, 0.4, 0.0), (0.0, -0.3, 0.17, 0.0)]
    result = adjuster.solve(0.1, STANCE, NOMINAL, DURATION, xi, STANCE[:2],
                            keep_out_boxes=boxes)
    for xmin, ymin, xmax, ymax in boxes:
        assert not (xmin < result.location[0] < xmax and ymin < result.location[1] < ymax)
    assert result.status == STATUS_SATURATED


def test_unavoidable_box_is_blocked(solver):
    xi, _ = periodic_dcm(STANCE, NOMINAL, DURATION, 0.1)
    result = StepAdjuster(StepAdjustmentParams(solver=solver)).solve(
        0.1, STANCE, NOMINAL, DURATION, xi, STANCE[:2], keep_out_boxes=[(-1, -1, 1, 0.05)])
    assert result.status == STATUS_BLOCKED


def test_solver_failure_returns_the_nominal_step():
    adjuster = StepAdjuster()
    adjuster._solver = types.SimpleNamespace(solve=lambda *args: (None, 0.0, -1, {}))
    xi, _ = periodic_dcm(STANCE, NOMINAL, DURATION, 0.1)
    result = adjuster.solve(0.1, STANCE, NOMINAL, DURATION, xi + (0.3, 0.0), STANCE[:2])
    assert result.status == STATUS_FAILED and not result.adjusted
    np.testing.assert_allclose(result.location, NOMINAL)
    assert result.duration == DURATION


@pytest.mark.parametrize('changes', [
    dict(com_height=0.0), dict(gravity=-9.81), dict(location_weight=0.0),
    dict(timing_weight=math.nan), dict(offset_weight=-1.0), dict(step_time_min=0.9),
    dict(width_min=0.5), dict(reach_forward=-0.1), dict(solver='osqp'),
    dict(min_remaining_time=0.0)])
def test_params_reject(changes):
    with pytest.raises(ConfigError):
        StepAdjustmentParams(**changes)


@pytest.mark.parametrize('arguments', [
    dict(t_in_step=-0.1), dict(t_in_step=math.nan), dict(stance_foot=(0.0, 0.1, 0.0, 2)),
    dict(stance_foot=(0.0, 0.1, 0.0)), dict(nominal_next_step=(math.inf, 0.0)),
    dict(nominal_duration=0.0), dict(dcm=(0.0, math.nan)), dict(zmp=(0.0, 0.0, 0.0)),
    dict(nominal_offset=(math.nan, 0.0)), dict(keep_out_boxes=[(1.0, 0.0, 0.0, 1.0)]),
    dict(keep_out_boxes=[(0.0, 0.0, 1.0)])])
def test_solve_rejects(arguments):
    call = dict(t_in_step=0.1, stance_foot=STANCE, nominal_next_step=NOMINAL,
                nominal_duration=DURATION, dcm=(0.05, 0.1), zmp=STANCE[:2])
    call.update(arguments)
    with pytest.raises(InputError):
        StepAdjuster().solve(**call)
