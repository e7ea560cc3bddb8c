"""Exact discretisation against the matrix exponential of the augmented matrix."""
import numpy as np
import pytest
from scipy.linalg import expm

from biped_mpc.discretization import discretize_exact
from biped_mpc.errors import ConfigError
from biped_mpc.lipm_model import lipm_model
from biped_mpc.three_mass_model import three_mass_model, ThreeMassParams


def expm_discretization(a, b, dt):
    n, m = b.shape
    augmented = np.zeros((n + m, n + m))
    augmented[:n, :n] = a
    augmented[:n, n:] = b
    exponential = expm(augmented * dt)
    return exponential[:n, :n], exponential[:n, n:]


@pytest.mark.parametrize('dt', [0.001, 0.02, 0.1, 0.7])
@pytest.mark.parametrize('model', [three_mass_model(), lipm_model(),
                                   three_mass_model(ThreeMassParams(left_leg_mass=7.0,
                                                                    torso_height=0.9))])
def test_model_discretisation_matches_expm(model, dt):
    discrete = model.discretize(dt)
    a_ref, b_ref = expm_discretization(model.a, np.column_stack([model.b, model.force_input]), dt)
    np.testing.assert_allclose(discrete.a, a_ref, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(discrete.b, b_ref[:, :3], rtol=1e-12, atol=1e-16)
    np.testing.assert_allclose(discrete.force_input, b_ref[:, 3], rtol=1e-12, atol=1e-16)
    np.testing.assert_array_equal(discrete.c, model.c)


def test_triple_integrator_closed_form():
    dt = 0.02
    a_d, b_d = discretize_exact(np.diag([1.0, 1.0], k=1), np.array([[0.0], [0.0], [1.0]]), dt)
    np.testing.assert_allclose(a_d, [[1, dt, dt ** 2 / 2], [0, 1, dt], [0, 0, 1]], atol=1e-16)
    np.testing.assert_allclose(b_d[:, 0], [dt ** 3 / 6, dt ** 2 / 2, dt], atol=1e-18)


def test_non_nilpotent_matrix_uses_the_exponential():
    a_d, b_d = discretize_exact(np.array([[-2.0]]), np.array([[1.0]]), 0.3)
    assert a_d[0, 0] == pytest.approx(np.exp(-0.6), rel=1e-12)
    assert b_d[0, 0] == pytest.approx((1.0 - np.exp(-0.6)) / 2.0, rel=1e-12)


@pytest.mark.parametrize('a, b, dt', [
    (np.zeros((2, 3)), np.zeros((2, 1)), 0.1),
    (np.zeros((2, 2)), np.zeros((3, 1)), 0.1),
    (np.full((2, 2), np.nan), np.zeros((2, 1)), 0.1),
    (np.zeros((2, 2)), np.zeros((2, 1)), 0.0),
    (np.zeros((2, 2)), np.zeros((2, 1)), -0.1),
    (np.zeros((2, 2)), np.zeros((2, 1)), float('nan')),
])
def test_bad_arguments_raise(a, b, dt):
    with pytest.raises(ConfigError):
        discretize_exact(a, b, dt)
