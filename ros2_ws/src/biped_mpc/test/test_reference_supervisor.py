"""Tests of what the controller follows: the references, or the safe stance and back."""
import numpy as np
import pytest

from biped_mpc.reference_supervisor import ReferenceSupervisor
from biped_mpc.safe_stance import SafeStanceParams
from biped_planner.footsteps import Footstep, straight_footsteps
from biped_planner.sides import LEFT, RIGHT, SUPPORT_DOUBLE
from biped_planner.standing_reference import standing_window
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference

DT, N = 0.02, 81
PARAMS = ReferenceParams(com_height=0.497, foot_length=0.2, foot_width=0.1)
LATCHED = [np.array([0.0, 0.07, 0.0, 0.0]), np.array([0.0, -0.07, 0.0, 0.0])]


def standing(t, x=0.0):
    return standing_window(Footstep(LEFT, x, 0.07), Footstep(RIGHT, x, -0.07), PARAMS, t, 90,
                           DT)


def supervisor():
    return ReferenceSupervisor(SafeStanceParams(), DT, N)


def test_nothing_to_follow_before_a_reference():
    window, reason = supervisor().window(0.0, 0.3, '', LATCHED, None)
    assert window is None and 'waiting' in reason


def test_a_fresh_reference_is_followed_from_now():
    s = supervisor()
    s.set_reference(standing(1.0))
    window, reason = s.window(1.1, 0.3, '', LATCHED, None)
    assert reason is None and window.t[0] == pytest.approx(1.1) and len(window.t) == N


def test_a_stale_reference_finishes_the_step_and_names_the_lost_input():
    walk = WalkingReference(straight_footsteps(6, 0.1, 0.14), StepTiming(0.4, 0.2), PARAMS)
    t = walk.t_start + 1.0 + 0.6 + 0.02  # early in the single support of step 1
    s = supervisor()
    s.set_reference(walk.sample(t, 90, DT))
    window, reason = s.window(t + 0.32, 0.3, '', LATCHED, None)
    assert 'reference_trajectory lost' in reason and '0.32 s old' in reason
    assert s.hold.finishing and window.support[0] != SUPPORT_DOUBLE  # still finishing
    assert any('holding a stance' in event for event in s.take_events())


def test_stale_sensors_hold_too_and_a_fitting_reference_ends_the_hold():
    s = supervisor()
    s.set_reference(standing(0.0))
    _, reason = s.window(0.02, 0.3, 'sensors stale: odom 0.2 s old', LATCHED, None)
    assert reason.startswith('sensors stale')
    s.set_reference(standing(0.04, x=0.3))  # fresh, but of other feet
    _, reason = s.window(0.04, 0.3, '', LATCHED, None)
    assert 'does not fit' in reason
    s.set_reference(standing(0.06))
    window, reason = s.window(0.06, 0.3, '', LATCHED, None)
    assert reason is None and s.hold is None


def test_after_a_reset_it_stands_on_the_measured_feet_and_drops_the_references():
    s = supervisor()
    s.set_reference(standing(0.0, x=2.0))
    s.stand(*LATCHED, 0.5, 'reset (epoch 1)')
    assert s.reference is None
    window, reason = s.window(0.52, 0.3, '', LATCHED, None)
    assert reason == 'reset (epoch 1)'
    np.testing.assert_allclose(window.zmp[0], [0.0, 0.0])
