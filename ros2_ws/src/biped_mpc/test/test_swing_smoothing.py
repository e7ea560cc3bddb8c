"""SwingSmoothing against the closed form of a first-order lag."""
import math

import numpy as np
import pytest

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.swing_smoothing import SwingSmoothing

DT = 0.02


def test_a_swinging_foot_follows_a_step_of_its_target_as_a_first_order_lag():
    smoothing = SwingSmoothing(0.07)
    start = np.array([[0.0, 0.1, 0.0], [0.0, -0.1, 0.0]])
    smoothing.update(DT, (True, True), start)
    step = start.copy()
    step[1] += (0.2, 0.0, 0.04)  # the right foot's target jumps; it swings
    for n in range(1, 16):
        out = smoothing.update(DT, (True, False), step)
        share = 1.0 - math.exp(-n * DT / 0.07)  # of the jump covered after n periods
        np.testing.assert_allclose(out[1], start[1] + share * (step[1] - start[1]), atol=1e-12)
        np.testing.assert_array_equal(out[0], start[0])  # the held foot's target as it is


def test_a_held_foot_restarts_the_lag_from_its_target():
    smoothing = SwingSmoothing(0.07)
    targets = np.zeros((2, 3))
    smoothing.update(DT, (False, False), targets)
    moved = targets + 0.1
    smoothing.update(DT, (False, False), moved)
    np.testing.assert_array_equal(smoothing.update(DT, (True, True), moved), moved)
    assert not np.array_equal(smoothing.update(DT, (False, False), moved + 0.1), moved + 0.1)


def test_time_constant_zero_passes_the_target_exactly():
    smoothing = SwingSmoothing(0.0)
    targets = np.array([[0.1234567, 0.3, 0.01], [0.7, -0.1, 0.033]])
    smoothing.update(DT, (False, False), targets * 0.5)
    np.testing.assert_array_equal(smoothing.update(DT, (False, False), targets), targets)


@pytest.mark.parametrize('time_constant', [-0.1, math.nan, math.inf, '0.1'])
def test_a_bad_time_constant_is_refused(time_constant):
    with pytest.raises(ConfigError):
        SwingSmoothing(time_constant)


@pytest.mark.parametrize('dt, held, targets', [
    (0.0, (True, True), np.zeros((2, 3))), (math.nan, (True, True), np.zeros((2, 3))),
    (DT, (True,), np.zeros((2, 3))), (DT, (True, True), np.zeros((2, 2))),
    (DT, (True, True), np.full((2, 3), math.inf))])
def test_bad_inputs_are_refused(dt, held, targets):
    with pytest.raises(InputError):
        SwingSmoothing(0.07).update(dt, held, targets)
