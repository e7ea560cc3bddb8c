"""The measured DCM: the three-mass centre of mass of a pose and its filtered velocity."""
import math

import numpy as np
import pytest

from biped_mpc.balance.measured_dcm import MeasuredDcm
from biped_mpc.errors import InputError
from biped_mpc.robot_model import COMAN_LIKE_MODEL_FILE, load_robot_model
from biped_planner.rotations import quaternion_from_yaw

ROBOT = load_robot_model(COMAN_LIKE_MODEL_FILE)
UPRIGHT = (0.0, 0.0, 0.0, 1.0)


def straight_legs_com(pelvis, yaw):
    """Centre of mass of straight legs by hand: soles under the hips, masses at mid-leg."""
    geometry, masses = ROBOT.leg_geometry, ROBOT.masses
    cos, sin = math.cos(yaw), math.sin(yaw)

    def world(forward, left):
        return np.array([pelvis[0] + cos * forward - sin * left,
                         pelvis[1] + sin * forward + cos * left])

    hip = world(geometry.hip_offset[0] + ROBOT.com_offset[0], ROBOT.com_offset[1])
    soles = [world(geometry.hip_offset[0] + geometry.ankle_to_sole[0],
                   side * (geometry.hip_offset[1] + geometry.ankle_to_sole[1]))
             for side in (1.0, -1.0)]
    total = masses.left_leg_mass + masses.torso_mass + masses.right_leg_mass
    return (masses.left_leg_mass * 0.5 * (soles[0] + hip) + masses.torso_mass * hip
            + masses.right_leg_mass * 0.5 * (soles[1] + hip)) / total


@pytest.mark.parametrize('yaw', [0.0, 0.7, -2.0])
def test_com_of_straight_legs(yaw):
    pelvis = np.array([0.3, -0.2, 0.6])
    com = MeasuredDcm(ROBOT).com(np.zeros(12), pelvis, quaternion_from_yaw(yaw))
    np.testing.assert_allclose(com, straight_legs_com(pelvis, yaw), atol=1e-12)


@pytest.mark.parametrize('time_constant', [0.0, 0.03])
def test_velocity_filter_step_response(time_constant):
    """A pelvis moving at constant v from rest: the velocity follows v (1 - (1 - b)^k)."""
    measured = MeasuredDcm(ROBOT, time_constant)
    dt, v = 0.02, np.array([0.4, -0.1])
    blend = dt / (time_constant + dt)
    for k in range(8):
        pelvis = np.array([0.0, 0.0, 0.54]) + np.append(v * k * dt, 0.0)
        com, dcm = measured.update(1.0 + k * dt, np.zeros(12), pelvis, UPRIGHT)
        expected = v * (1.0 - (1.0 - blend) ** k)
        np.testing.assert_allclose(measured.velocity, expected, atol=1e-9)
        np.testing.assert_allclose(dcm, com + expected / measured.omega, atol=1e-9)
    # omega of the robot's LIPM: its centre of mass height 0.497 m
    assert measured.omega == pytest.approx(math.sqrt(9.81 / 0.4966), rel=1e-3)


def test_rejects_bad_input():
    with pytest.raises(InputError):
        MeasuredDcm(ROBOT, -0.1)
    measured = MeasuredDcm(ROBOT)
    measured.update(1.0, np.zeros(12), [0.0, 0.0, 0.54], UPRIGHT)
    with pytest.raises(InputError):
        measured.update(1.0, np.zeros(12), [0.0, 0.0, 0.54], UPRIGHT)
    with pytest.raises(InputError):
        measured.update(1.1, np.full(12, math.nan), [0.0, 0.0, 0.54], UPRIGHT)
    measured.reset()
    assert np.all(measured.velocity == 0.0)
