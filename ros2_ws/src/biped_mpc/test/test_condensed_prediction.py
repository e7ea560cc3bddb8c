"""Condensed prediction against step-by-step simulation; move blocking."""
import numpy as np
import pytest

from biped_mpc.condensed_prediction import CondensedPrediction, default_move_blocks, move_starts
from biped_mpc.errors import ConfigError
from biped_mpc.three_mass_model import three_mass_model


@pytest.mark.parametrize('blocks', [(1, 1, 1, 1, 1), (1, 2, 3, 6), (12,)])
def test_prediction_matches_simulation(blocks):
    model = three_mass_model().discretize(0.02)
    prediction = CondensedPrediction(model, blocks)
    rng = np.random.default_rng(7)
    x0, u_prev = rng.normal(size=9), rng.normal(size=3)
    moves = rng.normal(size=3 * len(blocks))
    starts = move_starts(blocks)
    x, u = x0.copy(), u_prev.copy()
    states, outputs, inputs = [], [], []
    for i in range(sum(blocks)):
        for j, start in enumerate(starts):
            if start == i:
                u = u + moves[3 * j:3 * j + 3]
        inputs.append(u.copy())
        x = model.a @ x + model.b @ u
        states.append(x.copy())
        outputs.append(model.c @ x)
    p = prediction
    np.testing.assert_allclose(
        p.states_from_state @ x0 + p.states_from_input @ u_prev + p.states_from_moves @ moves,
        np.concatenate(states), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(
        p.outputs_from_state @ x0 + p.outputs_from_input @ u_prev + p.outputs_from_moves @ moves,
        np.concatenate(outputs), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(np.tile(u_prev, sum(blocks)) + p.inputs_from_moves @ moves,
                               np.concatenate(inputs), atol=1e-12)


def test_default_blocks_of_the_paper_horizons():
    assert default_move_blocks(80, 20) == (1,) * 8 + (2,) * 4 + (4,) * 4 + (8,) * 3 + (24,)


@pytest.mark.parametrize('n_predict, n_control', [(80, 20), (20, 20), (10, 3), (25, 20),
                                                  (40, 10), (1, 1), (200, 7)])
def test_default_blocks_cover_the_horizon(n_predict, n_control):
    blocks = default_move_blocks(n_predict, n_control)
    assert len(blocks) == n_control
    assert sum(blocks) == n_predict
    assert min(blocks) >= 1


@pytest.mark.parametrize('n_predict, n_control', [(10, 11), (10, 0)])
def test_bad_horizons_raise(n_predict, n_control):
    with pytest.raises(ConfigError):
        default_move_blocks(n_predict, n_control)


def test_bad_blocks_raise():
    model = three_mass_model().discretize(0.02)
    with pytest.raises(ConfigError):
        CondensedPrediction(model, (1, 0, 2))
    with pytest.raises(ConfigError):
        CondensedPrediction(model, ())
