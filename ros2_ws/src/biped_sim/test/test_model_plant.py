"""The model plant: exact integration, pushes, noise, real vs fictitious ZMP."""
import numpy as np
import pytest

from biped_mpc.three_mass_model import three_mass_model
from biped_sim.errors import ConfigError, InputError
from biped_sim.model_plant import ModelPlant, PlantParams

MODEL = three_mass_model()


def test_steps_follow_the_discrete_model_for_any_dt():
    plant = ModelPlant(MODEL)
    rng = np.random.default_rng(0)
    state = rng.normal(size=(2, 9))
    plant.reset(state, t=1.0)
    for dt in (0.02, 0.005, 0.02, 0.1):
        jerk = rng.normal(size=(2, 3))
        discrete = MODEL.discretize(dt)
        state = state @ discrete.a.T + jerk @ discrete.b.T
        measurement = plant.step(jerk, dt)
        np.testing.assert_allclose(measurement.state, state, atol=1e-12)
        np.testing.assert_allclose(measurement.outputs, state @ MODEL.c.T, atol=1e-12)
    assert plant.t == pytest.approx(1.145)


def test_push_changes_torso_momentum_and_not_the_zmp_at_once():
    plant = ModelPlant(MODEL)
    plant.reset(np.zeros((2, 9)))
    before = plant.measure().zmp_fictitious
    for _ in range(5):
        measurement = plant.step(np.zeros((2, 3)), 0.02, external_force=np.array([300.0, -100.0]))
    np.testing.assert_allclose(measurement.state[:, 4], [300 * 0.1 / 50, -100 * 0.1 / 50])
    np.testing.assert_allclose(measurement.state[:, 3], [300 * 0.01 / 2 / 50,
                                                         -100 * 0.01 / 2 / 50])
    # the ZMP moved only because the torso moved: (m_t / M) * displacement
    np.testing.assert_allclose(measurement.zmp_fictitious - before,
                               50 / 80 * measurement.state[:, 3], atol=1e-12)


def test_real_zmp_is_the_fictitious_one_clipped_to_the_support_polygon():
    plant = ModelPlant(MODEL)
    state = np.zeros((2, 9))
    state[:, 3] = (0.2, -0.01)
    plant.set_support_polygon(np.array([-0.05, -0.04]), np.array([0.05, 0.04]))
    measurement = plant.reset(state)
    np.testing.assert_allclose(measurement.zmp_fictitious, [0.125, -0.00625])
    np.testing.assert_allclose(measurement.zmp_real, [0.05, -0.00625])


def test_noise_is_gaussian_clipped_and_reproducible():
    params = PlantParams.paper_noise(seed=3)
    plant = ModelPlant(MODEL, params)
    samples = np.array([plant.step(np.zeros((2, 3)), 0.02).outputs for _ in range(4000)])
    assert np.abs(samples).max() <= 0.05
    assert samples.std() == pytest.approx(0.05 / 3, rel=0.05)
    assert abs(samples.mean()) < 1e-3
    again = ModelPlant(MODEL, params)
    np.testing.assert_array_equal(again.step(np.zeros((2, 3)), 0.02).outputs, samples[0])


@pytest.mark.parametrize('field, value', [('noise_std', -0.1), ('noise_bound', 0.0),
                                          ('seed', -1), ('noise_std', float('nan'))])
def test_bad_parameters_raise(field, value):
    with pytest.raises(ConfigError, match=field):
        PlantParams(**{field: value})


def test_bad_inputs_raise():
    plant = ModelPlant(MODEL)
    with pytest.raises(InputError):
        plant.step(np.zeros((2, 3)), 0.0)
    with pytest.raises(InputError):
        plant.step(np.full((2, 3), np.nan), 0.02)
    with pytest.raises(InputError):
        plant.step(np.zeros((2, 3)), 0.02, external_force=np.array([np.inf, 0.0]))
    with pytest.raises(InputError):
        plant.reset(np.zeros((3, 9)))
    with pytest.raises(InputError):
        plant.set_support_polygon(np.array([0.1, 0.0]), np.array([0.0, 0.0]))
