"""The commanded state's leash: a translation that keeps the commanded hip in a box."""
import math

import numpy as np
import pytest

from biped_mpc.command_leash import (dcm_leash_excess, leash_shift, shift_positions,
                                     shift_velocities)
from biped_mpc.errors import InputError
from biped_mpc.linear_model import (ACCELERATION, LEFT_LEG, N_STATES, POSITION, RIGHT_LEG,
                                    state_index, TORSO, VELOCITY)
from biped_mpc.linear_model import LinearModel


def state(hip, left=(0.0, 0.1), right=(0.0, -0.1)):
    command = np.zeros((2, N_STATES))
    command[:, state_index(TORSO, POSITION)] = hip
    command[:, state_index(LEFT_LEG, POSITION)] = left
    command[:, state_index(RIGHT_LEG, POSITION)] = right
    command[:, state_index(TORSO, VELOCITY)] = (0.3, -0.2)
    command[:, state_index(LEFT_LEG, ACCELERATION)] = (1.0, 2.0)
    return command


def test_a_commanded_hip_inside_the_box_is_left_alone():
    shift = leash_shift(state((0.035, -0.019)), np.zeros(2), 0.04, 0.02, 0.0)
    assert np.array_equal(shift, np.zeros(2))


def test_each_side_of_the_box_bounds_its_own_axis():
    # heading 0: x along (4 cm), y across (2 cm); 5 cm and 3 cm away
    shift = leash_shift(state((0.05, -0.03)), np.zeros(2), 0.04, 0.02, 0.0)
    assert shift == pytest.approx([0.01, -0.01])
    command = state((0.05, -0.03))
    shift_positions(command, shift)
    assert command[:, state_index(TORSO, POSITION)] == pytest.approx([0.04, -0.02])


def test_the_box_turns_with_the_heading():
    # heading 90 deg: across is world x, along is world y; the hip 3 cm off in x only
    shift = leash_shift(state((0.13, 0.5)), np.array([0.1, 0.5]), 0.04, 0.02, math.pi / 2)
    assert shift == pytest.approx([0.01, 0.0], abs=1e-12)
    # heading 45 deg, a gap straight across of 5 cm: 3 cm beyond a 2 cm side
    across = np.array([-math.sin(math.pi / 4), math.cos(math.pi / 4)])
    shift = leash_shift(state(0.05 * across), np.zeros(2), 0.04, 0.02, math.pi / 4)
    assert shift == pytest.approx(0.03 * across)


def test_a_side_of_zero_leaves_its_axis_unbounded():
    shift = leash_shift(state((0.3, -0.03)), np.zeros(2), 0.0, 0.02, 0.0)
    assert shift == pytest.approx([0.0, -0.01])
    assert np.array_equal(leash_shift(state((0.3, -0.3)), np.zeros(2), 0.0, 0.0, 0.0),
                          np.zeros(2))


def test_the_shift_translates_every_mass_and_leaves_the_motion():
    command = state((0.1, -0.05), left=(0.05, 0.12), right=(0.08, -0.2))
    before = command.copy()
    shift = leash_shift(command, np.array([0.02, 0.01]), 0.02, 0.02, 0.3)
    assert np.linalg.norm(shift) > 0.0
    shift_positions(command, shift)
    for mass in (LEFT_LEG, TORSO, RIGHT_LEG):
        index = state_index(mass, POSITION)
        assert command[:, index] == pytest.approx(before[:, index] - shift)
        for order in (VELOCITY, ACCELERATION):
            index = state_index(mass, order)
            assert np.array_equal(command[:, index], before[:, index])
    # the legs keep their offsets from the hip: the commanded robot keeps its shape
    hip = command[:, state_index(TORSO, POSITION)]
    assert command[:, state_index(LEFT_LEG, POSITION)] - hip == pytest.approx([-0.05, 0.17])


@pytest.mark.parametrize('along, across, heading', [
    (-0.01, 0.02, 0.0), (0.02, float('nan'), 0.0), (float('inf'), 0.02, 0.0),
    (0.02, 0.02, float('nan'))])
def test_bad_sizes_and_headings_are_refused(along, across, heading):
    with pytest.raises(InputError):
        leash_shift(state((0.0, 0.0)), np.zeros(2), along, across, heading)


def test_misshaped_inputs_are_refused():
    with pytest.raises(InputError):
        leash_shift(np.zeros((3, N_STATES)), np.zeros(2), 0.02, 0.02, 0.0)
    with pytest.raises(InputError):
        leash_shift(state((0.0, 0.0)), np.zeros(3), 0.02, 0.02, 0.0)


def test_a_commanded_dcm_inside_the_circle_is_left_alone():
    assert np.array_equal(dcm_leash_excess([0.03, 0.04], [0.0, 0.0], 0.05), np.zeros(2))


def test_the_dcm_excess_is_the_distance_past_the_circle_along_the_error():
    # 13 cm away along (12, 5) / 13: 8 cm past a 5 cm circle
    excess = dcm_leash_excess([0.22, 0.06], [0.1, 0.01], 0.05)
    np.testing.assert_allclose(excess, np.array([0.12, 0.05]) * 0.08 / 0.13, atol=1e-12)


def test_the_velocity_shift_moves_the_dcm_by_the_excess_and_keeps_the_positions():
    com_row = LinearModel('three_mass', (6.0, 20.0, 6.0), (0.4, 0.9, 0.4), 9.81).com_row
    omega = 5.0
    command = state((0.01, -0.02))
    before = command.copy()
    shift_velocities(command, np.array([0.03, -0.01]), omega)

    def dcm(x):
        return x @ com_row + x @ np.roll(com_row, 1) / omega
    np.testing.assert_allclose(dcm(before) - dcm(command), [0.03, -0.01], atol=1e-12)
    for mass in (LEFT_LEG, TORSO, RIGHT_LEG):
        np.testing.assert_allclose(command[:, state_index(mass, VELOCITY)]
                                   - before[:, state_index(mass, VELOCITY)], [-0.15, 0.05])
        for order in (POSITION, ACCELERATION):
            assert np.array_equal(command[:, state_index(mass, order)],
                                  before[:, state_index(mass, order)])


@pytest.mark.parametrize('radius', [0.0, -0.01, math.nan, math.inf])
def test_bad_dcm_leash_radii_are_refused(radius):
    with pytest.raises(InputError, match='radius'):
        dcm_leash_excess([0.0, 0.0], [0.1, 0.0], radius)


@pytest.mark.parametrize('commanded, measured', [([0.0, math.nan], [0.0, 0.0]),
                                                 ([0.0, 0.0], [math.inf, 0.0]),
                                                 ([0.0, 0.0, 0.0], [0.0, 0.0])])
def test_bad_dcms_are_refused(commanded, measured):
    with pytest.raises(InputError):
        dcm_leash_excess(commanded, measured, 0.05)
