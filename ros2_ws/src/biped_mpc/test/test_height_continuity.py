"""Height continuity: the lagged steps of held soles and pelvis in closed form."""
import math

import numpy as np
import pytest

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.height_continuity import HeightContinuity

DT = 0.02


def test_time_constant_zero_passes_the_targets():
    continuity = HeightContinuity(0.0)
    continuity.update(DT, (True, True), [0.0, 0.0], 0.5)
    feet, pelvis = continuity.update(DT, (True, True), [0.03, -0.01], 0.52)
    np.testing.assert_array_equal(feet, [0.03, -0.01])
    assert pelvis == 0.52


def test_a_landing_foot_starts_from_its_swing_target_and_lags_to_the_latched_height():
    tau = 0.05
    continuity = HeightContinuity(tau)
    continuity.update(DT, (False, True), [0.0475, 0.048], 0.548)  # left swinging
    for k in range(1, 8):
        feet, pelvis = continuity.update(DT, (True, True), [0.035, 0.048], 0.5415)
        decay = math.exp(-k * DT / tau)
        # closed form of the exact discretisation for a step held from the landing on
        assert feet[0] == pytest.approx(0.035 + (0.0475 - 0.035) * decay, abs=1e-12)
        assert feet[1] == pytest.approx(0.048, abs=1e-12)
        assert pelvis == pytest.approx(0.5415 + (0.548 - 0.5415) * decay, abs=1e-12)


def test_a_step_within_the_deadband_passes_and_only_the_excess_is_lagged():
    tau, band = 0.05, 0.005
    continuity = HeightContinuity(tau, band)
    continuity.update(DT, (False, True), [0.003, 0.0], 0.5)
    feet, pelvis = continuity.update(DT, (True, True), [0.0, 0.0], 0.5)  # a 3 mm landing
    np.testing.assert_array_equal(feet, [0.0, 0.0])
    assert pelvis == 0.5
    continuity = HeightContinuity(tau, band)
    continuity.update(DT, (False, True), [0.0475, 0.048], 0.548)
    for k in range(1, 6):  # 12.5 mm down: 5 mm at once, 7.5 mm through the lag
        feet, pelvis = continuity.update(DT, (True, True), [0.035, 0.048], 0.5415)
        decay = math.exp(-k * DT / tau)
        assert feet[0] == pytest.approx(0.035 + 0.0075 * decay, abs=1e-12)
        assert pelvis == pytest.approx(0.5415 + 0.0015 * decay, abs=1e-12)  # 6.5 - 5 mm
    # a step back within the band while an offset decays moves the target by the step
    before, _ = continuity.update(DT, (True, True), [0.035, 0.048], 0.5415)
    after, _ = continuity.update(DT, (True, True), [0.038, 0.048], 0.5415)
    assert after[0] - before[0] == pytest.approx(0.003 - 0.0075 * (
        math.exp(-6 * DT / tau) - math.exp(-7 * DT / tau)), abs=1e-12)


def test_a_swinging_foot_passes_and_a_held_one_restarts_from_it():
    continuity = HeightContinuity(0.05)
    continuity.update(DT, (True, True), [0.0, 0.0], 0.5)
    feet, _ = continuity.update(DT, (False, True), [0.04, 0.0], 0.5)
    assert feet[0] == 0.04
    feet, _ = continuity.update(DT, (False, True), [0.01, 0.0], 0.5)
    assert feet[0] == 0.01
    feet, _ = continuity.update(DT, (True, True), [0.02, 0.0], 0.5)
    assert feet[0] == pytest.approx(0.02 + (0.01 - 0.02) * math.exp(-DT / 0.05))


def test_reset_takes_the_next_targets_as_they_are():
    continuity = HeightContinuity(0.05)
    continuity.update(DT, (True, True), [0.0, 0.0], 0.5)
    continuity.reset()
    feet, pelvis = continuity.update(DT, (True, True), [0.02, 0.03], 0.55)
    np.testing.assert_array_equal(feet, [0.02, 0.03])
    assert pelvis == 0.55


@pytest.mark.parametrize('time_constant, deadband', [
    (-0.1, 0.0), (math.nan, 0.0), (math.inf, 0.0), (0.05, -0.001), (0.05, math.nan)])
def test_bad_settings_are_refused(time_constant, deadband):
    with pytest.raises(ConfigError):
        HeightContinuity(time_constant, deadband)


@pytest.mark.parametrize('args', [
    (0.0, (True, True), [0.0, 0.0], 0.5), (DT, (True,), [0.0, 0.0], 0.5),
    (DT, (True, True), [math.nan, 0.0], 0.5), (DT, (True, True), [0.0], 0.5),
    (DT, (True, True), [0.0, 0.0], math.inf)])
def test_bad_inputs_are_refused(args):
    with pytest.raises(InputError):
        HeightContinuity(0.05).update(*args)
