"""The swing foot's attitude correction against the rigid-body placement it undoes."""
import math

import numpy as np
import pytest

from biped_mpc.swing_attitude import attitude_correction, corrected_swing_target
from biped_planner.rotations import rotation_x, rotation_y, rotation_z

PELVIS = np.array([0.1, -0.02, 0.55])


def placed(target, target_rotation, commanded, actual):
    """Where the sole lands when the IK solves for the commanded pelvis and the pelvis is at
    the actual orientation: the leg's pelvis-frame pose is kept, the pelvis is not."""
    relative = commanded.T @ (target - PELVIS)
    return PELVIS + actual @ relative, actual @ commanded.T @ target_rotation


def test_gain_zero_leaves_the_target_as_it_is():
    commanded = rotation_z(0.3) @ rotation_x(-0.02)
    measured = rotation_z(0.3) @ rotation_x(0.1)
    np.testing.assert_array_equal(attitude_correction(commanded, measured, 0.0), np.eye(3))


@pytest.mark.parametrize('roll, pitch, lean', [(0.12, 0.0, 0.2), (-0.05, 0.08, 0.2),
                                               (0.0, -0.1, 0.0), (0.2, 0.15, 1.0)])
def test_full_gain_puts_the_sole_on_its_target_for_the_measured_attitude(roll, pitch, lean):
    yaw = 0.4
    # Z-Y-X angles: both headings are yaw exactly, the heading the correction keeps
    measured = rotation_z(yaw) @ rotation_y(pitch) @ rotation_x(roll)
    # the posture feedback leans the IK's pelvis against the measured tilt
    commanded = rotation_z(yaw) @ rotation_y(-lean * pitch) @ rotation_x(-lean * roll)
    target = np.array([0.2, 0.08, 0.03])
    target_rotation = rotation_z(yaw + 0.1)
    correction = attitude_correction(commanded, measured, 1.0)
    position, rotation = corrected_swing_target(target, target_rotation, PELVIS, correction)
    landed, landed_rotation = placed(position, rotation, commanded, measured)
    np.testing.assert_allclose(landed, target, atol=1e-12)
    np.testing.assert_allclose(landed_rotation, target_rotation, atol=1e-12)
    # uncorrected, the same sole misses its target
    missed, _ = placed(target, target_rotation, commanded, measured)
    assert np.linalg.norm(missed - target) > 1e-3


def test_a_body_rolled_over_its_stance_edge_holds_the_uncorrected_swing_foot_up():
    # Closed form: pelvis rolled by phi, IK pelvis leaned to -0.2 phi; a sole 0.1 m to the
    # pelvis' left and 0.5 m below is rotated by 1.2 phi about the pelvis' x axis.
    phi = math.radians(7.0)
    measured, commanded = rotation_x(phi), rotation_x(-0.2 * phi)
    target = PELVIS + np.array([0.0, 0.1, -0.5])
    missed, _ = placed(target, np.eye(3), commanded, measured)
    angle = 1.2 * phi
    expected_z = PELVIS[2] + 0.1 * math.sin(angle) - 0.5 * math.cos(angle)
    assert missed[2] == pytest.approx(expected_z, abs=1e-12)
    assert missed[2] - target[2] > 0.01  # the sole hangs over a centimetre above its target


def test_a_partial_gain_corrects_that_fraction_of_the_attitude_difference():
    measured, commanded = rotation_x(0.1), rotation_x(-0.02)
    correction = attitude_correction(commanded, measured, 0.5)
    # C = R_cmd R_att' with R_att rolled halfway from -0.02 to 0.1
    np.testing.assert_allclose(correction, rotation_x(-0.02) @ rotation_x(0.04).T, atol=1e-12)
