"""The three-mass model: structure, the ZMP row against eq. zmp, parameters."""
import numpy as np
import pytest

from biped_mpc.errors import ConfigError
from biped_mpc.linear_model import LinearModel, OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG, OUTPUT_ZMP
from biped_mpc.three_mass_model import three_mass_model, ThreeMassParams


def zmp_by_eq_zmp(masses, heights, positions, accelerations, g):
    """Eq. zmp with z_k'' = 0: p = (sum m c g - sum m z c'') / (sum m g)."""
    masses, heights = np.asarray(masses), np.asarray(heights)
    return ((masses * positions * g).sum() - (masses * heights * accelerations).sum()) / (
        masses.sum() * g)


@pytest.mark.parametrize('params', [
    ThreeMassParams(),
    ThreeMassParams(left_leg_mass=12.0, torso_mass=40.0, right_leg_mass=9.0,
                    left_leg_height=0.45, torso_height=1.0, right_leg_height=0.55, gravity=9.7),
])
def test_zmp_row_matches_eq_zmp(params):
    model = three_mass_model(params)
    rng = np.random.default_rng(3)
    masses = (params.left_leg_mass, params.torso_mass, params.right_leg_mass)
    heights = (params.left_leg_height, params.torso_height, params.right_leg_height)
    for _ in range(20):
        state = rng.normal(size=9)
        positions, accelerations = state[0::3], state[2::3]
        expected = zmp_by_eq_zmp(masses, heights, positions, accelerations, params.gravity)
        assert model.c[OUTPUT_ZMP] @ state == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_paper_zmp_row_numbers():
    row = three_mass_model().zmp_row
    expected = [15 / 80, 0, -15 * 0.5 / (80 * 9.81), 50 / 80, 0, -50 * 1.2 / (80 * 9.81),
                15 / 80, 0, -15 * 0.5 / (80 * 9.81)]
    np.testing.assert_allclose(row, expected, rtol=1e-14)


def test_structure_is_three_triple_integrators_with_leg_outputs():
    model = three_mass_model()
    expected_a = np.zeros((9, 9))
    for mass in range(3):
        expected_a[3 * mass, 3 * mass + 1] = 1.0
        expected_a[3 * mass + 1, 3 * mass + 2] = 1.0
    np.testing.assert_array_equal(model.a, expected_a)
    np.testing.assert_array_equal(model.b[[2, 5, 8]], np.eye(3))
    assert np.count_nonzero(model.b) == 3
    np.testing.assert_array_equal(model.c[OUTPUT_LEFT_LEG], np.eye(9)[0])
    np.testing.assert_array_equal(model.c[OUTPUT_RIGHT_LEG], np.eye(9)[6])
    assert model.total_mass == 80.0
    assert model.com_height == pytest.approx((15 * 0.5 + 50 * 1.2 + 15 * 0.5) / 80)


def test_force_changes_only_the_torso_velocity_by_impulse_over_mass():
    model = three_mass_model()
    discrete = model.discretize(0.1)
    state = discrete.force_input * 300.0
    assert state[4] == pytest.approx(300.0 * 0.1 / 50.0)
    assert state[3] == pytest.approx(300.0 * 0.1 ** 2 / 2 / 50.0)
    assert np.count_nonzero(state) == 2


@pytest.mark.parametrize('field, value', [
    ('left_leg_mass', -15.0), ('torso_mass', 0.0), ('right_leg_mass', float('nan')),
    ('left_leg_height', -0.5), ('torso_height', float('inf')), ('right_leg_height', 0.0),
    ('gravity', 0.0), ('torso_mass', 5000.0),
])
def test_bad_parameters_raise(field, value):
    with pytest.raises(ConfigError, match=field):
        ThreeMassParams(**{field: value})


def test_linear_model_rejects_negative_mass_and_massless_torso():
    with pytest.raises(ConfigError):
        LinearModel('m', masses=(-1.0, 50.0, 15.0), heights=(0.5, 1.2, 0.5), gravity=9.81)
    with pytest.raises(ConfigError):
        LinearModel('m', masses=(1.0, 0.0, 15.0), heights=(0.5, 1.2, 0.5), gravity=9.81)
    with pytest.raises(ConfigError):
        LinearModel('m', masses=(1.0, 5.0), heights=(0.5, 1.2), gravity=9.81)
