"""The push bound of the LIPM against closed forms of its strategies and an independent root."""
import math

import pytest
from scipy.optimize import brentq

from biped_planner.errors import InputError
from biped_planner.push_capture_bound import (
    AXIS_X, AXIS_Y, PlaneSituation, PushCaptureBound, direction_bound, landing_interval)
from biped_planner.sides import LEFT, RIGHT
from biped_planner.step_adjustment import StepAdjustmentParams

LIMITS = StepAdjustmentParams(com_height=0.5, reach_forward=0.3, reach_backward=0.2,
                              width_min=0.1, width_max=0.3, step_time_min=0.15,
                              step_time_max=0.45)
OMEGA = LIMITS.omega
MASS = 30.0
PUSH = 0.1          # s
HALF = 0.05         # half the sole's width (m)
STANCE_Y = -0.07    # the right foot stands, the left has just lifted off


def right_stance(dcm: float, elapsed: float = 0.0) -> PlaneSituation:
    return PlaneSituation(AXIS_Y, dcm, (0.07, STANCE_Y), LEFT, LEFT, elapsed, HALF)


def run_away(xi: float, pole: float, duration: float) -> float:
    """The DCM after `duration` s of xi_dot = omega (xi - pole): a CoP p and a push F along
    the axis make pole = p - F / (m omega^2)."""
    return pole + (xi - pole) * math.exp(OMEGA * duration)


def test_a_push_towards_the_swing_side_is_caught_by_the_widest_step_as_the_closed_form_says():
    # The DCM on the stance sole's inner edge, the CoP held there: during the push the DCM
    # runs away from edge - F / (m omega^2); the left foot lands after step_time_min at
    # width_max and the DCM must be inside its sole then.
    edge = STANCE_Y + HALF
    expected = LIMITS.width_max * MASS * OMEGA ** 2 / (
        (math.exp(OMEGA * PUSH) - 1.0) * math.exp(OMEGA * (LIMITS.step_time_min - PUSH)))
    bound = PushCaptureBound(right_stance(edge), PUSH, MASS, LIMITS, steps=1)
    assert bound.largest(+1, tolerance=0.1) == pytest.approx(expected, abs=0.5)


def test_a_push_towards_the_stance_foot_is_caught_by_its_outward_step_as_an_independent_root():
    # The left foot lands beside the right one (width_min) after step_time_min, the right foot
    # lifts at once and lands step_time_min later at width_max outside the left: the bound is
    # the force at which the DCM then reaches that sole's outer edge (brentq on the closed form).
    start = STANCE_Y + 0.02

    def margin(force: float) -> float:
        drift = force / (MASS * OMEGA ** 2)
        left_y = STANCE_Y + LIMITS.width_min
        xi = run_away(start, STANCE_Y - HALF + drift, PUSH)
        xi = run_away(xi, STANCE_Y - HALF, LIMITS.step_time_min - PUSH)
        xi = run_away(xi, left_y - HALF, LIMITS.step_time_min)
        return xi - (left_y - LIMITS.width_max - HALF)

    expected = brentq(margin, 1.0, 1000.0)
    bound = PushCaptureBound(right_stance(start), PUSH, MASS, LIMITS, steps=2)
    assert bound.largest(-1, tolerance=0.1) == pytest.approx(expected, abs=1.0)


def test_the_swing_foot_landing_beside_the_stance_foot_adds_nothing_towards_it():
    # Towards the stance side only the stance foot's own step moves the support: one step
    # (the swing foot's, which may not cross) stops no more than the stance sole's edge does.
    start = STANCE_Y + 0.02
    one = PushCaptureBound(right_stance(start), PUSH, MASS, LIMITS, steps=1).largest(-1)
    two = PushCaptureBound(right_stance(start), PUSH, MASS, LIMITS, steps=2).largest(-1)
    drift_limit = (start - (STANCE_Y - HALF)) * MASS * OMEGA ** 2 / (
        1.0 - math.exp(-OMEGA * PUSH))   # the DCM ends the push on the outer edge
    assert one == pytest.approx(drift_limit, abs=1.5)
    assert two > one + 30.0


def test_more_steps_never_lower_the_bound_and_a_quiet_walk_is_stopped():
    situation = right_stance(STANCE_Y + 0.02, elapsed=0.075)
    bounds = [PushCaptureBound(situation, PUSH, MASS, LIMITS, steps=n).largest(-1)
              for n in (1, 2, 3)]
    assert bounds == sorted(bounds)
    assert PushCaptureBound(situation, PUSH, MASS, LIMITS).stopped(0.0)


def test_a_longer_double_support_before_each_lift_off_lowers_the_bound():
    situation = PlaneSituation(AXIS_Y, -0.02, (0.07, -0.07), None, RIGHT, 0.0, HALF)
    free = PushCaptureBound(situation, PUSH, MASS, LIMITS).largest(-1)
    slow = PushCaptureBound(situation, PUSH, MASS, LIMITS, min_double_support=0.1).largest(-1)
    assert slow < free


@pytest.mark.parametrize('axis, side, expected', [
    (AXIS_X, LEFT, (-0.2, 0.3)), (AXIS_X, RIGHT, (-0.2, 0.3)),
    (AXIS_Y, LEFT, (0.1, 0.3)), (AXIS_Y, RIGHT, (-0.3, -0.1))])
def test_landings_keep_the_reach_and_never_cross(axis, side, expected):
    assert landing_interval(axis, side, 0.0, LIMITS) == pytest.approx(expected)


def test_a_diagonal_push_is_bounded_by_the_weaker_plane_of_its_components():
    planes = ((100.0, 400.0), (150.0, 300.0))   # (x -, x +), (y -, y +)
    assert direction_bound(planes, 0.0) == pytest.approx(400.0)
    assert direction_bound(planes, math.pi) == pytest.approx(100.0)
    assert direction_bound(planes, -0.5 * math.pi) == pytest.approx(150.0)
    assert direction_bound(planes, math.radians(45.0)) == pytest.approx(
        min(400.0, 300.0) / math.cos(math.radians(45.0)))


@pytest.mark.parametrize('kwargs', [dict(duration=0.0), dict(mass=-1.0), dict(steps=0),
                                    dict(horizon=0.05), dict(min_double_support=-0.1)])
def test_bad_settings_are_refused(kwargs):
    settings = dict(duration=PUSH, mass=MASS, steps=2, horizon=1.5, min_double_support=0.0)
    settings.update(kwargs)
    with pytest.raises(InputError):
        PushCaptureBound(right_stance(0.0), settings['duration'], settings['mass'], LIMITS,
                         settings['steps'], settings['horizon'], settings['min_double_support'])


def test_non_finite_forces_and_bad_signs_are_refused():
    bound = PushCaptureBound(right_stance(0.0), PUSH, MASS, LIMITS, steps=1)
    with pytest.raises(InputError):
        bound.stopped(math.nan)
    with pytest.raises(InputError):
        bound.largest(0)
