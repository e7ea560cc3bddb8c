"""Tests of biped_planner.swing_trajectory."""
import numpy as np
import pytest

from biped_planner.swing_trajectory import (bernstein_curve, HEIGHT_CONTROL_SCALE, swing_lift,
                                            swing_progress)

S = np.linspace(0.0, 1.0, 201)


def test_progress_is_the_quintic_bezier_with_repeated_end_points():
    curve = bernstein_curve(np.array([[0.0], [0.0], [0.0], [1.0], [1.0], [1.0]]), S)[:, 0]
    np.testing.assert_allclose(swing_progress(S), curve, atol=1e-14)


def test_lift_is_the_quintic_bezier_of_the_swing_height():
    c = HEIGHT_CONTROL_SCALE
    curve = bernstein_curve(np.array([[0.0], [0.0], [c], [c], [0.0], [0.0]]), S)[:, 0]
    np.testing.assert_allclose(swing_lift(S), curve, atol=1e-14)


def test_bernstein_curve_matches_the_bernstein_sum():
    rng = np.random.default_rng(0)
    control = rng.normal(size=(4, 2))
    binomial = np.array([1.0, 3.0, 3.0, 1.0])
    expected = sum(binomial[i] * S[:, None] ** i * (1 - S[:, None]) ** (3 - i) * control[i]
                   for i in range(4))
    np.testing.assert_allclose(bernstein_curve(control, S), expected, atol=1e-14)


def test_end_points_and_peak():
    assert swing_progress(np.array([0.0, 1.0])) == pytest.approx([0.0, 1.0])
    assert swing_lift(np.array([0.0, 0.5, 1.0])) == pytest.approx([0.0, 1.0, 0.0])
    assert np.all(np.diff(swing_progress(S)) >= 0.0)
    assert swing_lift(S).max() == pytest.approx(1.0)


@pytest.mark.parametrize('function', [swing_progress, swing_lift])
def test_zero_velocity_at_lift_off_and_touch_down(function):
    h = 1e-6
    start = (function(np.array([h])) - function(np.array([0.0]))) / h
    end = (function(np.array([1.0])) - function(np.array([1.0 - h]))) / h
    assert abs(start[0]) < 1e-4 and abs(end[0]) < 1e-4


def test_progress_has_zero_acceleration_at_the_ends():
    h = 1e-4
    values = swing_progress(np.array([0.0, h, 2 * h, 1 - 2 * h, 1 - h, 1.0]))
    assert abs(values[2] - 2 * values[1] + values[0]) / h ** 2 < 1e-2
    assert abs(values[5] - 2 * values[4] + values[3]) / h ** 2 < 1e-2
