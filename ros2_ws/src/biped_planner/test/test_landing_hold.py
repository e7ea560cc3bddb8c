"""A late landing's hold: the single support of a swing that has not met the ground goes on
(WalkingReference.hold_landing, biped_planner.landing_hold); an early one ends it."""
import math

import numpy as np
import pytest

from biped_planner.errors import ConfigError, InputError
from biped_planner.footsteps import straight_footsteps
from biped_planner.landing_hold import (EARLY, HOLD, LANDING_FAILED, LANDING_LANDED, LANDING_NONE,
                                        LANDING_SEEKING, LANDING_SWINGING, LandingHold,
                                        LandingHoldParams, RESUME, RESUME_LEAD)
from biped_planner.plan_adjustment import swing_step_at
from biped_planner.reference_params import ReferenceParams
from biped_planner.reference_phases import (PHASE_DOUBLE_SUPPORT, PHASE_FINAL_SETTLE,
                                            PHASE_SINGLE_SUPPORT)
from biped_planner.sides import RIGHT, SUPPORT_DOUBLE
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import WalkingReference

TIMING = StepTiming(0.4, 0.1)
PARAMS = ReferenceParams()
# initial shift 0 .. 1 s, step 0 single support 1.0 .. 1.4 s, step 1 1.5 .. 1.9 s (right foot
# swinging to footsteps[3], stance footsteps[2]), its double support 1.9 .. 2.0 s
REFERENCE = WalkingReference(straight_footsteps(4, 0.1, 0.2), TIMING, PARAMS)
DT = 0.001


def _hold(t_now=1.92, touchdown=2.05, reference=REFERENCE):
    hip, dcm = np.array([0.13, -0.07]), np.array([0.22, -0.09])
    return reference.hold_landing(t_now, touchdown, hip, dcm), hip, dcm


def test_the_late_swing_is_found_in_its_single_support_or_the_double_support_after_it():
    phases = REFERENCE.phases
    swing = REFERENCE.swing_of_late_landing(1.6)
    assert phases[swing].kind == PHASE_SINGLE_SUPPORT and phases[swing].t_end == 1.9
    assert REFERENCE.swing_of_late_landing(1.95) == swing  # the double support after it
    assert REFERENCE.swing_of_late_landing(0.5) is None  # initial shift
    assert REFERENCE.swing_of_late_landing(-1.0) is None
    assert REFERENCE.swing_of_late_landing(REFERENCE.t_end + 1.0) is None
    held, _, _ = _hold()
    # in the hold, the swing is the phase before it
    assert held.swing_of_late_landing(2.0) == swing


@pytest.mark.parametrize('t_now', [1.8, 1.9, 1.92, 1.99])
def test_a_held_step_keeps_its_swing_then_holds_the_foot_on_its_landing(t_now):
    touchdown = 2.05
    held, hip, dcm = _hold(t_now, touchdown)
    assert held.revision == 1
    swing = held.swing_of_late_landing(t_now)
    first, hold, double = held.phases[swing:swing + 3]
    assert (first.t_begin, first.t_end) == (1.5, 1.9)
    assert (hold.kind, hold.t_begin, hold.t_end) == (PHASE_SINGLE_SUPPORT, 1.9, touchdown)
    assert (hold.support, hold.step_index, hold.swing_side) == (
        first.support, first.step_index, first.swing_side)
    assert double.kind == PHASE_DOUBLE_SUPPORT and double.t_begin == touchdown
    assert double.t_end == pytest.approx(touchdown + TIMING.double_support)
    assert held.step_timing(1).single_support == pytest.approx(touchdown - 1.5)
    assert held.t_end == pytest.approx(REFERENCE.t_end + touchdown - 1.9)
    # the swing before the planned landing is the plan's, to the sample
    before = np.arange(1.5, 1.9, 0.01)
    old, new = (r.sample(1.5, before.size, 0.01) for r in (REFERENCE, held))
    np.testing.assert_allclose(new.right_foot, old.right_foot, atol=1e-12)
    # in the hold the swinging right foot stands still on its landing, at zero height ...
    assert REFERENCE.footsteps[3].side == RIGHT
    landing = REFERENCE.footsteps[3]
    window = held.sample(1.9, int(round((touchdown - 1.9) / 0.01)), 0.01)
    np.testing.assert_allclose(window.right_foot,
                               np.tile([landing.x, landing.y, 0.0], (window.t.size, 1)),
                               atol=1e-12)
    # ... its landing box still bounds it, the ZMP stays on the stance centre in its box
    np.testing.assert_allclose(window.right_landing_min[0],
                               [landing.x - PARAMS.landing_half_length,
                                landing.y - PARAMS.landing_half_width], atol=1e-12)
    stance = REFERENCE.footsteps[2]
    np.testing.assert_allclose(window.zmp, np.tile([stance.x, stance.y], (window.t.size, 1)),
                               atol=1e-9)
    assert np.all(window.support == first.support)
    # the hip passes through the given state at t_now and the walk ends at rest between the
    # last two feet
    now_hip, now_dcm = held.lipm.state_at(t_now)
    np.testing.assert_allclose(now_hip, hip, atol=1e-9)
    np.testing.assert_allclose(now_dcm, dcm, atol=1e-9)
    feet = REFERENCE.footsteps[-2:]
    end = held.sample(held.t_end, 1, 0.01)
    np.testing.assert_allclose(end.hip[0], [0.5 * (feet[0].x + feet[1].x),
                                            0.5 * (feet[0].y + feet[1].y)], atol=1e-9)


def test_the_held_hip_obeys_the_pendulum_and_is_smooth():
    held, _, _ = _hold()
    t = np.arange(1.5, held.t_end, DT)
    window = held.sample(float(t[0]), t.size, DT)
    hip, zmp = window.hip, window.zmp
    acceleration = (hip[2:] - 2.0 * hip[1:-1] + hip[:-2]) / DT ** 2
    # x'' = omega^2 (x - p), the LIPM, between the knots (a difference across a knot sees
    # the jump of the ZMP's slope)
    knots = held.lipm.times
    away = np.min(np.abs(t[1:-1, None] - knots[None, :]), axis=1) > 1.5 * DT
    assert away.sum() > 0.9 * away.size
    np.testing.assert_allclose(acceleration[away],
                               held.omega ** 2 * (hip[1:-1] - zmp[1:-1])[away], atol=2e-3)
    # position and velocity are continuous at every knot
    for knot in knots[(knots > 1.5) & (knots < held.t_end)]:
        around = np.array([knot - 1e-9, knot + 1e-9])
        np.testing.assert_allclose(*held.lipm.evaluate(around)[1], atol=1e-6)
        np.testing.assert_allclose(*held.lipm.hip_velocity(around), atol=1e-5)


def test_the_foot_met_the_ground_early_in_the_hold_ends_it_then():
    held, _, _ = _hold(1.92, 2.1)
    resumed = held.hold_landing(1.97, 1.98, *held.lipm.state_at(1.97))
    assert resumed.revision == 2
    swing = resumed.swing_of_late_landing(1.97)
    hold, double = resumed.phases[swing + 1:swing + 3]
    assert (hold.t_begin, hold.t_end, double.t_begin) == (1.9, 1.98, 1.98)
    assert resumed.t_end == pytest.approx(REFERENCE.t_end + 0.08)
    # one hold: the held reference's phases are replaced, not nested
    assert sum(p.step_index == hold.step_index and p.kind == PHASE_SINGLE_SUPPORT
               for p in resumed.phases) == 2
    # the hip is continuous across the resume (the state of the held reference at 1.97)
    np.testing.assert_allclose(resumed.lipm.state_at(1.97)[0], held.lipm.state_at(1.97)[0],
                               atol=1e-9)


def test_the_last_step_held_ends_at_rest_midway():
    reference = WalkingReference(straight_footsteps(1, 0.1, 0.2), TIMING, PARAMS)
    swing = next(i for i, p in enumerate(reference.phases) if p.kind == PHASE_SINGLE_SUPPORT
                 and p.t_end == reference.phases[-1].t_begin)
    t_landing = reference.phases[swing].t_end
    held = reference.hold_landing(t_landing + 0.01, t_landing + 0.1)
    assert held.phases[-1].kind == PHASE_FINAL_SETTLE
    assert held.phases[-1].t_begin == pytest.approx(t_landing + 0.1)
    feet = reference.footsteps[-2:]
    np.testing.assert_allclose(held.sample(held.t_end + 0.5, 1, 0.01).hip[0],
                               [0.5 * (feet[0].x + feet[1].x), 0.5 * (feet[0].y + feet[1].y)],
                               atol=1e-9)
    np.testing.assert_allclose(held.lipm.hip_velocity(np.array([held.t_end])), 0.0, atol=1e-9)


@pytest.mark.parametrize('t, touchdown, state', [
    (0.5, 1.9, {}),                        # initial shift: no swing
    (1.2, 1.3, {}),                        # touchdown before the planned landing (1.4 s)
    (1.92, 1.9, {}),                       # touchdown before now
    (1.92, 1.92, {}),                      # touchdown now
    (1.92, math.nan, {}),
    (math.inf, 2.0, {}),
    (1.92, 2.0, {'hip': (0.0, 0.0)}),      # hip without dcm
    (1.92, 2.0, {'hip': (0.0, 0.0), 'dcm': (math.nan, 0.0)}),
])
def test_hold_landing_rejects(t, touchdown, state):
    with pytest.raises(ConfigError):
        REFERENCE.hold_landing(t, touchdown, **state)


# --- LandingHold: when the plan holds and resumes ------------------------------------------
HOLD_PARAMS = LandingHoldParams(enabled=True, hold_time=0.2, min_depth=0.005)
DEEP = 0.006  # m below the planned landing height: past min_depth


def right(state, depth=0.0):
    """The (modes, depths) report of the swinging right foot (step 1), the left one down."""
    return (LANDING_NONE, state), (0.0, depth)


@pytest.mark.parametrize('t, landing', [
    (1.8, LANDING_SEEKING),    # before the planned landing (1.9 s)
    (1.92, LANDING_SWINGING),  # late without a report of seeking
    (1.92, LANDING_LANDED),    # on time
    (1.92, LANDING_NONE),
    (0.5, LANDING_SEEKING),    # no swing
    (2.15, LANDING_SEEKING),   # past the longest hold
])
def test_the_plan_holds_only_a_swing_seeking_past_its_landing(t, landing):
    assert LandingHold(HOLD_PARAMS).update(t, REFERENCE, *right(landing, DEEP)) is None


def test_a_foot_still_above_the_landing_depth_threshold_is_not_held():
    # on flat ground a lagging swing meets the ground millimetres into its search
    seeking_shallow = right(LANDING_SEEKING, 0.004)
    assert LandingHold(HOLD_PARAMS).update(1.92, REFERENCE, *seeking_shallow) is None


def test_a_seeking_swing_holds_then_its_touchdown_resumes():
    hold = LandingHold(HOLD_PARAMS)
    change = hold.update(1.92, REFERENCE, *right(LANDING_SEEKING, DEEP))
    assert (change.kind, change.step) == (HOLD, 1)
    assert change.touchdown == pytest.approx(1.9 + 0.2) and change.planned_touchdown == 1.9
    held = change.reference
    swing = held.swing_of_late_landing(1.92)
    assert held.phases[swing + 1].t_end == pytest.approx(2.1)
    # the step adjuster leaves a held step alone: its swing is over
    assert swing_step_at(held, 1.95) is None and swing_step_at(held, 1.8) is not None
    # still seeking: it waits
    assert hold.update(1.96, held, *right(LANDING_SEEKING, DEEP)) is None
    resumed = hold.update(1.98, held, *right(LANDING_LANDED))
    assert (resumed.kind, resumed.step) == (RESUME, 1)
    assert resumed.touchdown == pytest.approx(1.98 + RESUME_LEAD)
    assert resumed.planned_touchdown == pytest.approx(2.1)
    assert resumed.reference.phases[swing + 1].t_end == pytest.approx(1.98 + RESUME_LEAD)
    assert resumed.reference.sample(1.99, 1, 0.01).support[0] == SUPPORT_DOUBLE
    # once resumed, the double support goes on
    assert hold.update(1.99, resumed.reference, *right(LANDING_LANDED)) is None


@pytest.mark.parametrize('landing', [LANDING_FAILED, LANDING_NONE, LANDING_SWINGING])
def test_a_hold_ends_when_the_foot_stops_seeking_for_any_reason(landing):
    hold = LandingHold(HOLD_PARAMS)
    held = hold.update(1.92, REFERENCE, *right(LANDING_SEEKING, DEEP)).reference
    assert hold.update(2.0, held, *right(landing)).kind == RESUME


def test_a_hold_that_runs_out_lets_the_plan_go_on():
    hold = LandingHold(HOLD_PARAMS)
    held = hold.update(1.92, REFERENCE, *right(LANDING_SEEKING, DEEP)).reference
    assert hold.update(2.1, held, *right(LANDING_LANDED)) is None  # the double support began
    assert held.sample(2.1, 1, 0.01).support[0] == SUPPORT_DOUBLE


def test_off_by_default_and_unknown_states_rejected():
    assert LandingHold().update(1.92, REFERENCE, *right(LANDING_SEEKING, DEEP)) is None
    with pytest.raises(InputError):
        LandingHold(HOLD_PARAMS).update(1.92, REFERENCE, *right('hovering'))
    for depth in (math.nan, -0.01, math.inf, 2.0):
        with pytest.raises(InputError):
            LandingHold(HOLD_PARAMS).update(1.92, REFERENCE, *right(LANDING_SEEKING, depth))
    with pytest.raises(ConfigError):
        LandingHoldParams(hold_time=-0.1)


# --- an early landing ends the single support --------------------------------------------
EARLY_PARAMS = LandingHoldParams(end_early=True, early_lead=0.02)


def test_a_foot_landed_before_its_time_ends_the_single_support_then():
    change = LandingHold(EARLY_PARAMS).update(1.8, REFERENCE, *right(LANDING_LANDED))
    touchdown = 1.8 + RESUME_LEAD
    assert (change.kind, change.step) == (EARLY, 1)
    assert change.touchdown == pytest.approx(touchdown) and change.planned_touchdown == 1.9
    early = change.reference
    assert early.revision == 1 and early.footsteps == REFERENCE.footsteps
    swing = early.single_support_at(1.8)
    single, double = early.phases[swing:swing + 2]
    assert (single.t_begin, single.t_end) == (1.5, pytest.approx(touchdown))
    assert double.kind == PHASE_DOUBLE_SUPPORT and double.t_begin == pytest.approx(touchdown)
    assert double.t_end == pytest.approx(touchdown + TIMING.double_support)
    # every later phase keeps its duration: the walk ends earlier by what the step saved
    assert early.t_end == pytest.approx(REFERENCE.t_end - (1.9 - touchdown))
    assert early.sample(1.805, 1, 0.01).support[0] == SUPPORT_DOUBLE
    # the hip goes on from the plan's state at the report, as a pendulum, and still ends at
    # rest between the last two feet
    for old, new in zip(REFERENCE.lipm.state_at(1.8), early.lipm.state_at(1.8)):
        np.testing.assert_allclose(new, old, atol=1e-9)
    feet = REFERENCE.footsteps[-2:]
    np.testing.assert_allclose(early.sample(early.t_end + 0.5, 1, 0.01).hip[0],
                               [0.5 * (feet[0].x + feet[1].x), 0.5 * (feet[0].y + feet[1].y)],
                               atol=1e-9)


@pytest.mark.parametrize('t, landing, params', [
    (1.8, LANDING_LANDED, LandingHoldParams()),                    # off by default
    (1.8, LANDING_LANDED, HOLD_PARAMS),                            # the hold alone
    (1.885, LANDING_LANDED, EARLY_PARAMS),                         # within early_lead: on time
    (1.8, LANDING_SWINGING, EARLY_PARAMS),
    (1.8, LANDING_NONE, EARLY_PARAMS),
    (1.95, LANDING_LANDED, EARLY_PARAMS),                          # the double support after it
    (0.5, LANDING_LANDED, EARLY_PARAMS),                           # no swing
    (1.69, LANDING_LANDED, EARLY_PARAMS),                          # before half its swing
    (1.53, LANDING_LANDED, LandingHoldParams(end_early=True, early_min_share=0.0)),  # < 50 ms
    (1.92, LANDING_SEEKING, EARLY_PARAMS),                         # late, the hold is off
])
def test_only_a_landing_early_by_more_than_the_lead_ends_the_single_support(t, landing, params):
    assert LandingHold(params).update(t, REFERENCE, *right(landing, DEEP)) is None


def test_an_early_end_happens_once_and_the_hold_still_answers_late_feet():
    hold = LandingHold(LandingHoldParams(enabled=True, hold_time=0.2, end_early=True))
    early = hold.update(1.8, REFERENCE, *right(LANDING_LANDED)).reference
    # the next reports of the landed foot are in the double support: nothing to change
    assert hold.update(1.803, early, *right(LANDING_LANDED)) is None
    # the next swing (left foot, step 2) is late: held as without end_early
    step_2 = next(p for p in early.phases if p.kind == PHASE_SINGLE_SUPPORT and
                  p.step_index == 3)
    late = hold.update(step_2.t_end + 0.01, early, (LANDING_SEEKING, LANDING_NONE), (DEEP, 0.0))
    assert late.kind == HOLD and late.planned_touchdown == pytest.approx(step_2.t_end)
