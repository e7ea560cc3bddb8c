"""Swing start: the target leaves from the latched foot and decays onto the planned swing."""
import math

import numpy as np
import pytest

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.swing_start import SwingStart
from biped_planner.sides import LEFT, RIGHT

DT = 0.02


def test_the_target_leaves_from_the_latched_foot_and_lands_on_the_planned_step():
    start = SwingStart(0.1)
    latched = [np.array([0.02, 0.11, 0.0, 0.0]), np.array([0.0, -0.07, 0.0, 0.0])]
    planned = np.array([[0.0, 0.07], [0.0, -0.07]])
    assert np.all(start.update(DT, (True, True), latched, planned) == 0.0)
    # lift-off of the left foot: its target is the latched foot, (0.02, 0.04) off the plan
    offsets = start.update(DT, (False, True), latched, planned)
    np.testing.assert_allclose(planned[LEFT] + offsets[LEFT], latched[LEFT][:2])
    assert np.all(offsets[RIGHT] == 0.0)
    for k in range(1, 20):  # the planned swing moves on; the offset decays on its own
        planned[LEFT] += [0.01, 0.0]
        offsets = start.update(DT, (False, True), latched, planned)
        np.testing.assert_allclose(offsets[LEFT], np.array([0.02, 0.04]) * math.exp(-k * DT / 0.1),
                                   atol=1e-15)
    # 0.4 s of swing: e^-3.8 of the 4.5 cm offset, 1 mm, is left at the landing
    assert np.linalg.norm(offsets[LEFT]) == pytest.approx(0.0447 * math.exp(-3.8), rel=1e-3)
    # landed and held: no offset; the next lift-off starts from the new latch
    assert np.all(start.update(DT, (True, True), latched, planned) == 0.0)


def test_without_a_time_constant_the_planned_swing_is_kept():
    start = SwingStart(0.0)
    latched = [np.array([0.05, 0.1, 0.0, 0.0]), None]
    planned = np.zeros((2, 2))
    start.update(DT, (True, True), latched, planned)
    assert np.all(start.update(DT, (False, False), latched, planned) == 0.0)


def test_a_foot_without_a_latch_has_no_offset_and_a_reset_forgets_the_swing():
    start = SwingStart(0.1)
    planned = np.zeros((2, 2))
    assert np.all(start.update(DT, (False, False), [None, None], planned) == 0.0)
    start.reset()
    latched = [np.array([0.03, 0.0, 0.0, 0.0]), None]
    start.update(DT, (True, True), latched, planned)
    start.update(DT, (False, True), latched, planned)
    start.reset()
    assert np.all(start.offsets == 0.0)


@pytest.mark.parametrize('value', [-0.1, math.nan, math.inf])
def test_a_bad_time_constant_is_refused(value):
    with pytest.raises(ConfigError):
        SwingStart(value)


@pytest.mark.parametrize('args', [
    (0.0, (True, True), [None, None], np.zeros((2, 2))),
    (DT, (True,), [None, None], np.zeros((2, 2))),
    (DT, (True, True), [None, None], np.full((2, 2), math.nan)),
    (DT, (True, True), [None, None], np.zeros(3)),
])
def test_bad_inputs_are_refused(args):
    with pytest.raises(InputError):
        SwingStart(0.1).update(*args)


def test_a_non_finite_latch_at_lift_off_is_refused():
    start = SwingStart(0.1)
    start.update(DT, (True, True), [None, None], np.zeros((2, 2)))
    with pytest.raises(InputError):
        start.update(DT, (False, True), [np.array([math.nan, 0.0, 0.0, 0.0]), None],
                     np.zeros((2, 2)))
