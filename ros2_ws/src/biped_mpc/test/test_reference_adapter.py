"""Reference window -> per-plane output references and bounds."""
from types import SimpleNamespace

import numpy as np
import pytest

from biped_mpc.errors import InputError
from biped_mpc.reference_adapter import outputs_from_window


def fake_window(n=6):
    inf = np.full((n, 2), np.inf)
    window = SimpleNamespace(
        zmp=np.column_stack([np.arange(n) * 0.1, np.arange(n) * -0.01]),
        hip=np.column_stack([np.arange(n) * 0.2, np.zeros(n)]),
        left_mass=np.column_stack([np.arange(n) * 0.3, np.full(n, 0.05)]),
        right_mass=np.column_stack([np.arange(n) * 0.4, np.full(n, -0.05)]),
        zmp_min=np.full((n, 2), -0.045), zmp_max=np.full((n, 2), 0.045),
        left_landing_min=-inf.copy(), left_landing_max=inf.copy(),
        right_landing_min=-inf.copy(), right_landing_max=inf.copy())
    # the left leg swings over samples 1..3 and lands after sample 3
    window.left_landing_min[1:4] = (0.75, 0.05)
    window.left_landing_max[1:4] = (0.85, 0.15)
    return window


def test_references_and_bounds_per_plane():
    window = fake_window()
    y_ref, y_min, y_max = outputs_from_window(window)
    assert y_ref.shape == y_min.shape == y_max.shape == (2, 6, 3)
    for plane in range(2):
        np.testing.assert_array_equal(y_ref[plane, :, 0], window.left_mass[:, plane])
        np.testing.assert_array_equal(y_ref[plane, :, 1], window.right_mass[:, plane])
        np.testing.assert_array_equal(y_ref[plane, :, 2], window.zmp[:, plane])
        np.testing.assert_array_equal(y_min[plane, :, 2], -0.045)
        np.testing.assert_array_equal(y_max[plane, :, 2], 0.045)
    # the right leg never swings: unbounded
    assert np.all(np.isinf(y_min[:, :, 1])) and np.all(np.isinf(y_max[:, :, 1]))


def test_landing_box_bounds_the_leg_mass_at_touch_down_only():
    window = fake_window()
    _, y_min, y_max = outputs_from_window(window)
    finite = np.isfinite(y_min[0, :, 0])
    np.testing.assert_array_equal(np.flatnonzero(finite), [3])
    hip = window.hip[3]
    np.testing.assert_allclose(y_min[:, 3, 0], 0.5 * (np.array([0.75, 0.05]) + hip))
    np.testing.assert_allclose(y_max[:, 3, 0], 0.5 * (np.array([0.85, 0.15]) + hip))


def test_torso_relative_legs_are_half_the_feet_and_half_the_landing_box():
    window = fake_window()
    y_ref, y_min, y_max = outputs_from_window(window, 'torso_relative')
    absolute = outputs_from_window(window)
    half_feet = window.left_mass - 0.5 * window.hip
    np.testing.assert_allclose(y_ref[:, :, 0], half_feet.T)
    np.testing.assert_array_equal(y_ref[:, :, 2], absolute[0][:, :, 2])
    np.testing.assert_allclose(y_min[:, 3, 0], 0.5 * np.array([0.75, 0.05]))
    np.testing.assert_allclose(y_max[:, 3, 0], 0.5 * np.array([0.85, 0.15]))
    assert np.all(np.isinf(y_min[:, :, 1]))


@pytest.mark.parametrize('legs', ['absolute', 'torso_relative'])
def test_planner_window_gives_bounds_containing_the_references(paper_reference, legs):
    for t0 in np.arange(0.0, paper_reference.t_end, 0.37):
        window = paper_reference.sample(float(t0), 81, 0.02)
        y_ref, y_min, y_max = outputs_from_window(window, legs)
        assert np.all(y_min <= y_ref + 1e-9) and np.all(y_ref <= y_max + 1e-9)
        assert np.isfinite(y_ref).all()


def test_unknown_leg_outputs_raise():
    with pytest.raises(InputError, match='leg_outputs'):
        outputs_from_window(fake_window(), 'feet')


@pytest.mark.parametrize('mutate, message', [
    (lambda w: w.zmp.__setitem__((2, 0), np.nan), 'window.zmp must be finite'),
    (lambda w: w.left_mass.__setitem__((0, 1), np.inf), 'window.left_mass must be finite'),
    (lambda w: w.zmp_min.__setitem__((1, 1), np.nan), 'window.zmp_min contains NaN'),
    (lambda w: setattr(w, 'hip', np.zeros((5, 2))), r'window.hip must have shape'),
    (lambda w: delattr(w, 'right_landing_max'), "no attribute 'right_landing_max'"),
    (lambda w: setattr(w, 'zmp_min', np.full((6, 2), 0.1)), 'lower bound above'),
    (lambda w: setattr(w, 'right_mass', [['a', 'b']] * 6), 'window.right_mass is not an array'),
    (lambda w: setattr(w, 'zmp', np.zeros((0, 2))), 'window.zmp must have shape'),
])
def test_bad_windows_raise_naming_what_is_wrong(mutate, message):
    window = fake_window()
    mutate(window)
    with pytest.raises(InputError, match=message):
        outputs_from_window(window)
