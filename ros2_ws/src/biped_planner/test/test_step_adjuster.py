"""Online step adjuster: closed forms of the capture point, scipy, revisions, the off switch."""
from dataclasses import replace
import math

import numpy as np
import pytest
from scipy.optimize import minimize

from biped_planner.step_adjuster import OnlineStepAdjuster, OnlineStepAdjusterParams
from biped_planner.step_adjustment import StepAdjustmentParams
from biped_planner.errors import ConfigError, InputError
from biped_planner.footsteps import straight_footsteps
from biped_planner.plan_adjustment import swing_step_at
from biped_planner.reference_params import ReferenceParams
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import WalkingReference

# step 1: single support 1.5 .. 1.9 s on the left foot (0.1, 0.1), the right foot lands at
# (0.2, -0.1)
REFERENCE = WalkingReference(straight_footsteps(4, 0.1, 0.2), StepTiming(0.4, 0.1),
                             ReferenceParams())
T = 1.6
OMEGA = ReferenceParams().omega
WIDE = dict(reach_forward=5.0, reach_backward=5.0, width_min=-1.0, width_max=5.0)
# the offset held, the step fixed in time: the landing absorbs the whole DCM error
STIFF_OFFSET = StepAdjustmentParams(location_weight=1e-3, offset_weight=1e6, step_time_min=0.4,
                                    step_time_max=0.4, **WIDE)
BARE = OnlineStepAdjusterParams(dcm_deadband=0.0, ankle_authority=0.0, location_threshold=1e-6,
                                timing_threshold=1e-6)


def state_with_error(error, t=T):
    """(com, dcm) with the DCM off the reference's by error, the COM on its hip."""
    hip, dcm = REFERENCE.lipm.state_at(t)
    return hip, dcm + np.asarray(error, dtype=float)


def landing(reference, index=3):
    step = reference.footsteps[index]
    return np.array([step.x, step.y])


def test_off_switch_leaves_the_plan():
    adjuster = OnlineStepAdjuster(OnlineStepAdjusterParams(enabled=False))
    output = adjuster.update(T, REFERENCE, *state_with_error((0.3, 0.2)))
    assert output.reference is REFERENCE and not output.applied
    assert output.adjustment is None and output.revision == adjuster.revision == 0


@pytest.mark.parametrize('params', [OnlineStepAdjusterParams(), BARE])
def test_on_plan_no_change(params):
    output = OnlineStepAdjuster(params).update(T, REFERENCE, *state_with_error((0.0, 0.0)))
    assert not output.applied and output.reference is REFERENCE
    np.testing.assert_allclose(output.adjustment.location, landing(REFERENCE), atol=1e-7)
    assert output.adjustment.duration == pytest.approx(0.4, abs=1e-7)


@pytest.mark.parametrize('error', [(0.05, 0.0), (0.0, -0.04), (-0.03, 0.06)])
@pytest.mark.parametrize('t', [1.52, 1.6, 1.68])
def test_landing_moves_with_the_capture_point(error, t):
    """Under the stance ZMP a DCM error e grows to e exp(omega (T - t)) at touchdown."""
    output = OnlineStepAdjuster(BARE, STIFF_OFFSET).update(t, REFERENCE,
                                                           *state_with_error(error, t))
    growth = math.exp(OMEGA * (1.9 - t))
    assert output.applied and output.revision == 1
    np.testing.assert_allclose(output.adjustment.location - landing(REFERENCE),
                               np.asarray(error) * growth, atol=2e-5)
    np.testing.assert_allclose(landing(output.reference), output.adjustment.location,
                               atol=1e-12)


def test_ankle_takes_what_the_foot_can():
    half = swing_step_at(REFERENCE, T).zmp_half_size
    growth = math.exp(OMEGA * (1.9 - T))
    ratio = growth / (growth - 1.0)
    params = OnlineStepAdjusterParams(dcm_deadband=0.0, ankle_authority=1.0,
                                      location_threshold=0.0, timing_threshold=0.0)
    adjuster = OnlineStepAdjuster(params, STIFF_OFFSET)
    # an error the ankle cancels by shifting the ZMP inside the foot: no step change
    inside = 0.9 * half / ratio
    output = adjuster.update(T, REFERENCE, *state_with_error(inside))
    np.testing.assert_allclose(output.adjustment.location, landing(REFERENCE), atol=2e-5)
    # beyond it, the ZMP at the edge d: the landing moves by d + (e - d) exp(omega T_rem)
    beyond = 2.0 * half
    output = adjuster.update(T, REFERENCE, *state_with_error(beyond))
    np.testing.assert_allclose(output.adjustment.location - landing(REFERENCE),
                               half + (beyond - half) * growth, atol=2e-5)


def test_deadband_and_thresholds_ignore_small_errors():
    adjuster = OnlineStepAdjuster(OnlineStepAdjusterParams(dcm_deadband=0.05))
    assert not adjuster.update(T, REFERENCE, *state_with_error((0.049, -0.049))).applied
    assert adjuster.update(T, REFERENCE, *state_with_error((0.15, 0.0))).applied


def test_revision_and_no_drift():
    adjuster = OnlineStepAdjuster(BARE)
    com, dcm = state_with_error((0.06, -0.03))
    first = adjuster.update(T, REFERENCE, com, dcm)
    assert first.applied and first.reference.revision == 1 and adjuster.revision == 1
    # the later landings moved with the adjusted one
    shift = landing(first.reference) - landing(REFERENCE)
    for index in range(4, len(REFERENCE.footsteps)):
        np.testing.assert_allclose(landing(first.reference, index) - landing(REFERENCE, index),
                                   shift, atol=1e-12)
    # the replanned hip passes through the estimate, so the same estimate changes nothing
    np.testing.assert_allclose(first.reference.lipm.state_at(T)[1], dcm, atol=1e-9)
    second = adjuster.update(T, first.reference, com, dcm)
    assert not second.applied and second.revision == 1
    np.testing.assert_allclose(second.adjustment.location, first.adjustment.location,
                               atol=1e-6)
    # a new walk starts counting again
    adjuster.reset()
    assert adjuster.revision == 0


def test_frozen_before_touchdown_and_idle_in_double_support():
    adjuster = OnlineStepAdjuster(OnlineStepAdjusterParams(freeze_time=0.2))
    for t in (1.75, 1.95):
        output = adjuster.update(t, REFERENCE, *state_with_error((0.3, 0.0), t))
        assert not output.applied and output.adjustment is None


def test_keep_out_box_is_respected():
    box = (0.25, -0.4, 0.6, 0.2)
    output = OnlineStepAdjuster(BARE, keep_out_boxes=[box]).update(
        T, REFERENCE, *state_with_error((0.05, 0.0)))
    x, y = output.adjustment.location
    assert not (box[0] < x < box[2] and box[1] < y < box[3])
    assert 'keep_out_0' in output.adjustment.active_limits


def test_matches_scipy_on_random_errors():
    """The whole cycle (ankle shift, deadband, QP) against SLSQP on the same problem."""
    params = OnlineStepAdjusterParams(location_threshold=0.0, timing_threshold=0.0)
    qp = StepAdjustmentParams()
    swing = swing_step_at(REFERENCE, T)
    stance = np.array([swing.stance.x, swing.stance.y])
    nominal = landing(REFERENCE)
    offset = swing.dcm_at_touchdown - nominal
    weights = np.array([qp.location_weight] * 2 + [qp.timing_weight] + [qp.offset_weight] * 2)
    weights = weights / weights.max()
    t_low = max(qp.step_time_min - (T - 1.5), qp.min_remaining_time)
    bounds = [(None, None)] * 2 + [(math.exp(OMEGA * t_low),
                                    math.exp(OMEGA * (qp.step_time_max - (T - 1.5))))] + [
        (None, None)] * 2
    rng = np.random.default_rng(15)
    for _ in range(20):
        error = rng.uniform(-0.15, 0.15, 2)
        output = OnlineStepAdjuster(params, qp).update(T, REFERENCE, *state_with_error(error))
        growth = math.exp(OMEGA * (1.9 - T))
        shrunk = np.sign(error) * np.maximum(np.abs(error) - params.dcm_deadband, 0.0)
        zmp = swing.zmp + np.clip(shrunk * growth / (growth - 1.0),
                                  -params.ankle_authority * swing.zmp_half_size,
                                  params.ankle_authority * swing.zmp_half_size)
        dcm = swing.dcm + shrunk
        target = np.concatenate([nominal, [growth], offset])
        # right foot swings: stance frame = world; no crossing: y <= stance_y - width_min
        constraints = [
            {'type': 'eq', 'fun': lambda z: z[:2] + z[3:] - zmp - (dcm - zmp) * z[2]},
            {'type': 'ineq', 'fun': lambda z: np.array([
                qp.reach_forward - (z[0] - stance[0]), qp.reach_backward + (z[0] - stance[0]),
                (stance[1] - z[1]) - qp.width_min, qp.width_max - (stance[1] - z[1])])}]
        best = minimize(lambda z: np.sum(weights * (z - target) ** 2), target, method='SLSQP',
                        bounds=bounds, constraints=constraints,
                        options={'ftol': 1e-14, 'maxiter': 500})
        assert best.success, best.message
        np.testing.assert_allclose(output.adjustment.location, best.x[:2], atol=1e-5)
        assert output.adjustment.duration == pytest.approx(
            (T - 1.5) + math.log(best.x[2]) / OMEGA, abs=1e-5)


@pytest.mark.parametrize('changes', [dict(ankle_authority=1.5), dict(dcm_deadband=-0.1),
                                     dict(freeze_time=math.nan)])
def test_params_reject(changes):
    with pytest.raises(ConfigError):
        OnlineStepAdjusterParams(**changes)


@pytest.mark.parametrize('com, dcm', [((math.nan, 0.0), (0.0, 0.0)),
                                      ((0.0, 0.0), (0.0, 0.0, 0.0))])
def test_update_rejects(com, dcm):
    with pytest.raises(InputError):
        OnlineStepAdjuster().update(T, REFERENCE, com, dcm)


def test_replans_are_limited_per_step_and_spaced():
    """Errors that keep growing are answered twice at most, replan_interval apart."""
    params = OnlineStepAdjusterParams(dcm_deadband=0.0, ankle_authority=0.0,
                                      location_threshold=0.01, timing_threshold=0.01,
                                      max_replans_per_step=2, replan_interval=0.05,
                                      freeze_time=0.05)
    adjuster = OnlineStepAdjuster(params, STIFF_OFFSET)
    reference, applied = REFERENCE, []
    for k in range(12):
        t = 1.52 + 0.02 * k
        output = adjuster.update(t, reference, *state_with_error((0.02 + 0.02 * k, 0.0), t))
        reference = output.reference
        if output.applied:
            applied.append(t)
    assert len(applied) == 2 and applied[0] == pytest.approx(1.52)
    assert applied[1] - applied[0] >= 0.05 - 1e-9
    assert adjuster.revision == 2
    # the next step starts counting again
    t = 2.02
    output = adjuster.update(t, reference, *state_with_error((0.0, 0.2), t))
    assert output.applied and adjuster.revision == 3


@pytest.mark.parametrize('shift', [(0.02, 0.0), (0.0, -0.03)])
def test_measured_zmp_is_held_in_the_prediction(shift):
    """xi(T) = p + (xi - p) tau: a ZMP moved by s moves the landing by s (1 - tau)."""
    swing = swing_step_at(REFERENCE, T)
    com, dcm = state_with_error((0.05, 0.02))
    on_stance = OnlineStepAdjuster(BARE, STIFF_OFFSET).update(T, REFERENCE, com, dcm,
                                                              swing.zmp)
    predicted = OnlineStepAdjuster(BARE, STIFF_OFFSET).update(T, REFERENCE, com, dcm)
    np.testing.assert_allclose(on_stance.adjustment.location, predicted.adjustment.location,
                               atol=1e-9)
    moved = OnlineStepAdjuster(BARE, STIFF_OFFSET).update(T, REFERENCE, com, dcm,
                                                          swing.zmp + np.asarray(shift))
    growth = math.exp(OMEGA * (1.9 - T))
    np.testing.assert_allclose(moved.adjustment.location - on_stance.adjustment.location,
                               np.asarray(shift) * (1.0 - growth), atol=2e-5)
    # a NaN ZMP (no foot in contact) falls back to the prediction
    nan = OnlineStepAdjuster(BARE, STIFF_OFFSET).update(T, REFERENCE, com, dcm,
                                                        (math.nan, math.nan))
    np.testing.assert_allclose(nan.adjustment.location, predicted.adjustment.location)


@pytest.mark.parametrize('error', [(0.05, 0.0), (0.0, -0.04), (-0.03, 0.06)])
def test_a_replan_with_the_footsteps_dcm_takes_the_estimate_as_its_own(error):
    """A step placed at the capture point of the estimated DCM asks, run back from the new plan,
    for most of that DCM now (not all: the double support starts on the unmoved stance foot),
    so the replanned reference comes to the estimate without being given it. The default
    replan keeps the plan's own DCM and bends the ZMP of the next double support."""
    com, dcm = state_with_error(error)
    own_dcm = REFERENCE.lipm.state_at(T)[1]
    bent = OnlineStepAdjuster(replace(BARE, replan_hip_from_estimate=False),
                              STIFF_OFFSET).update(T, REFERENCE, com, dcm)
    straight = OnlineStepAdjuster(
        replace(BARE, replan_hip_from_estimate=False, replan_dcm_from_footsteps=True),
        STIFF_OFFSET).update(T, REFERENCE, com, dcm)
    assert bent.applied and straight.applied
    np.testing.assert_allclose(landing(straight.reference), landing(bent.reference),
                               atol=1e-12)
    np.testing.assert_allclose(bent.reference.lipm.state_at(T)[1], own_dcm, atol=1e-9)
    assert bent.reference.start_correction > 0.01
    moved = straight.reference.lipm.state_at(T)[1] - own_dcm
    error = np.asarray(error)
    share = float(np.dot(moved, error) / np.dot(error, error))
    assert 0.7 < share < 1.0
    assert np.linalg.norm(moved - share * error) < 0.1 * np.linalg.norm(error)
    np.testing.assert_allclose(straight.reference.lipm.state_at(T)[0], com, atol=1e-9)
    assert straight.reference.start_correction < 1e-3


def gate_boundary(tolerance, axis=0):
    """The DCM error along an axis at which the capture gate opens at T: with the ZMP held at
    the box's edge h, the DCM at touchdown misses the plan's by (e - h) g + h = tolerance."""
    half = float(swing_step_at(REFERENCE, T).zmp_half_size[axis])
    growth = math.exp(OMEGA * (1.9 - T))
    return half + (tolerance - half) / growth


@pytest.mark.parametrize('tolerance', [0.0, 0.03])
def test_capture_gate_opens_where_the_stance_ankle_no_longer_catches_the_dcm(tolerance):
    gated = replace(BARE, capture_gate=True, capture_tolerance=tolerance)
    boundary = gate_boundary(tolerance)
    # just inside: the ankle's whole box brings the DCM within the tolerance, the plan stays
    # (the ungated adjuster moves it)
    inside = state_with_error((boundary - 1e-4, 0.0))
    output = OnlineStepAdjuster(gated, STIFF_OFFSET).update(T, REFERENCE, *inside)
    assert not output.applied and output.adjustment is None and output.reference is REFERENCE
    assert OnlineStepAdjuster(BARE, STIFF_OFFSET).update(T, REFERENCE, *inside).applied
    # just outside: the gate lets the adjuster answer, and with the answer of the ungated one
    outside = state_with_error((boundary + 1e-4, 0.0))
    output = OnlineStepAdjuster(gated, STIFF_OFFSET).update(T, REFERENCE, *outside)
    ungated = OnlineStepAdjuster(BARE, STIFF_OFFSET).update(T, REFERENCE, *outside)
    assert output.applied
    np.testing.assert_allclose(output.adjustment.location, ungated.adjustment.location,
                               atol=1e-12)


def test_capture_gate_watches_each_axis():
    gated = replace(BARE, capture_gate=True, capture_tolerance=0.03)
    boundary = gate_boundary(0.03, axis=1)
    inside = OnlineStepAdjuster(gated).update(
        T, REFERENCE, *state_with_error((0.0, -boundary + 1e-4)))
    assert not inside.applied and inside.adjustment is None
    lateral = OnlineStepAdjuster(gated).update(
        T, REFERENCE, *state_with_error((0.0, -boundary - 1e-3)))
    assert lateral.applied and lateral.adjustment.location[1] < landing(REFERENCE)[1]
