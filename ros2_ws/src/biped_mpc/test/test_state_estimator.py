"""Kalman filter: gains, exactness without noise, error below the noise in the walk."""
import numpy as np
import pytest

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.mpc_params import MpcParams
from biped_mpc.state_estimator import EstimatorParams, StateEstimator
from biped_mpc.three_mass_model import three_mass_model
from biped_sim.model_plant import PlantParams
from biped_sim.model_walk import run_walk, WalkSetup

MODEL = three_mass_model()
DISCRETE = MODEL.discretize(0.02)


def test_time_varying_gain_converges_to_the_steady_state_gain():
    steady = StateEstimator(DISCRETE, EstimatorParams())
    varying = StateEstimator(DISCRETE, EstimatorParams(steady_state=False))
    for _ in range(3000):
        varying.correct(np.zeros((2, 3)))
        varying.predict(np.zeros((2, 3)))
    np.testing.assert_allclose(varying.covariance, steady.covariance, rtol=1e-6, atol=1e-12)


def test_without_noise_the_estimate_follows_the_state_exactly():
    estimator = StateEstimator(DISCRETE)
    rng = np.random.default_rng(2)
    state = rng.normal(size=(2, 9))
    estimator.reset(state)
    for _ in range(50):
        jerk = rng.normal(size=(2, 3))
        estimate = estimator.correct(state @ DISCRETE.c.T)
        np.testing.assert_allclose(estimate, state, atol=1e-9)
        estimator.predict(jerk)
        state = state @ DISCRETE.a.T + jerk @ DISCRETE.b.T


def test_estimate_converges_from_a_wrong_initial_state():
    estimator = StateEstimator(DISCRETE)
    state = np.zeros((2, 9))
    state[:, [0, 3, 6]] = (0.1, 0.02, -0.1)
    estimator.reset(np.zeros((2, 9)))
    errors = []
    for _ in range(1500):
        errors.append(np.abs(estimator.correct(state @ DISCRETE.c.T) - state).max())
        estimator.predict(np.zeros((2, 3)))
    assert errors[-1] < 1e-6 < errors[0]
    assert errors[500] < 0.01 * errors[0]


def test_estimation_error_is_below_the_measurement_noise_in_the_noisy_walk(paper_reference):
    setup = WalkSetup(controller_model=MODEL, plant_model=MODEL, mpc=MpcParams(),
                      plant=PlantParams.paper_noise(seed=4), estimator=EstimatorParams(),
                      polygon_margin=(0.005, 0.004))
    log = run_walk(paper_reference, setup)
    estimated_outputs = log.estimate @ DISCRETE.c.T
    estimation_rms = np.sqrt(np.mean((estimated_outputs - log.true_outputs) ** 2, axis=0))
    noise_rms = np.sqrt(np.mean((log.measured - log.true_outputs) ** 2, axis=0))
    assert np.all(noise_rms > 0.012)
    assert np.all(estimation_rms < 0.5 * noise_rms)
    torso_rms = np.sqrt(np.mean((log.estimate[:, :, 3] - log.state[:, :, 3]) ** 2))
    assert torso_rms < noise_rms.mean()


@pytest.mark.parametrize('field, value', [
    ('measurement_std', (0.01, 0.0, 0.01)), ('measurement_std', (0.01, 0.01)),
    ('jerk_std', -1.0), ('acceleration_std', (0.1, float('nan'), 0.1)),
    ('initial_std', 0.0), ('steady_state', 1),
])
def test_bad_parameters_raise(field, value):
    with pytest.raises(ConfigError, match=field):
        EstimatorParams(**{field: value})


def test_bad_inputs_raise():
    estimator = StateEstimator(DISCRETE)
    with pytest.raises(InputError):
        estimator.correct(np.array([[np.nan, 0, 0], [0, 0, 0]]))
    with pytest.raises(InputError):
        estimator.correct(np.zeros(3))
    with pytest.raises(InputError):
        estimator.predict(np.zeros((2, 2)))
    with pytest.raises(InputError):
        estimator.reset(np.full((2, 9), np.inf))
