"""Tests of biped_planner.reference_table: bulk sampling agrees with the LIPM it tabulates."""
import numpy as np

from biped_planner.footsteps import straight_footsteps
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import WalkingReference


def test_sampled_zmp_and_hip_are_those_of_the_lipm_and_hold_outside_the_plan():
    reference = WalkingReference(straight_footsteps(3, 0.1, 0.2), StepTiming(0.4, 0.1))
    t0, n, dt = reference.t_start - 0.5, 2000, 0.003
    window = reference.sample(t0, n, dt)
    zmp, hip = reference.lipm.evaluate(t0 + dt * np.arange(n))
    np.testing.assert_allclose(window.zmp, zmp, atol=1e-12)
    np.testing.assert_allclose(window.hip, hip, atol=1e-12)
    before = window.t < reference.t_start
    after = window.t > reference.t_end
    assert before.any() and after.any()
    np.testing.assert_allclose(window.hip[before], np.tile(window.hip[0], (before.sum(), 1)),
                               atol=1e-12)
    np.testing.assert_allclose(window.hip[after], np.tile(window.hip[-1], (after.sum(), 1)),
                               atol=1e-12)


def test_long_windows_match_short_ones():
    reference = WalkingReference(straight_footsteps(2, 0.1, 0.2), StepTiming(0.4, 0.1))
    long = reference.sample(0.0, 3000, 0.001)
    short = reference.sample(0.0, 90, 0.001)
    for name in ('zmp', 'hip', 'left_foot', 'right_yaw', 'support', 'step_index'):
        np.testing.assert_array_equal(getattr(long, name)[:90], getattr(short, name))
