"""Sensor readings of a simulated humanoid, one frozen dataclass per sensor.

Frames: world x forward, y left, z up. Quaternions are (x, y, z, w). All arrays are numpy float
arrays in SI units (m, s, rad, N, N m).
"""

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class JointReadings:
    """Encoders and torques of the actuated joints.

    :param names: joint names, the order of every array.
    :param position: (n,) joint angles (rad).
    :param velocity: (n,) joint speeds (rad/s).
    :param torque: (n,) torques the actuators applied over the last physics step (N m).
    """

    names: tuple
    position: np.ndarray
    velocity: np.ndarray
    torque: np.ndarray


@dataclass(frozen=True)
class ImuReading:
    """An IMU as a real one reports it.

    :param orientation: (4,) orientation of the IMU frame in the world, quaternion (x, y, z, w).
    :param angular_velocity: (3,) angular velocity in the IMU frame (rad/s).
    :param linear_acceleration: (3,) specific force in the IMU frame, acceleration minus gravity
        (m/s^2): (0, 0, +9.81) when upright and still. It is the mean acceleration over the last
        control period (the velocity difference over it), as a real IMU's anti-aliasing filter.
    """

    orientation: np.ndarray
    angular_velocity: np.ndarray
    linear_acceleration: np.ndarray


@dataclass(frozen=True)
class FootForceTorque:
    """An ankle force/torque sensor and what it says about the ground contact of its foot.

    :param sensor_force: (3,) force the foot exerts on the leg at the sensor, in the sensor frame
        (N): +z carries the weight above the sensor when standing.
    :param sensor_torque: (3,) torque the foot exerts on the leg about the sensor origin, in the
        sensor frame (N m).
    :param ground_force: (3,) ground reaction force on the foot in the world frame (N): the
        sensor force plus the weight of the foot below the sensor (statics, foot acceleration
        neglected).
    :param ground_torque: (3,) ground reaction torque about the sole centre, world frame (N m).
    :param cop: (3,) centre of pressure of this foot in the world, on its sole plane (m); NaN when
        the foot is not in contact.
    :param in_contact: True when the normal ground force exceeds the contact threshold.
    """

    sensor_force: np.ndarray
    sensor_torque: np.ndarray
    ground_force: np.ndarray
    ground_torque: np.ndarray
    cop: np.ndarray
    in_contact: bool


@dataclass(frozen=True)
class BaseState:
    """Ground-truth pose and twist of the floating base (pelvis) frame.

    :param position: (3,) position in the world (m).
    :param orientation: (4,) quaternion (x, y, z, w).
    :param linear_velocity: (3,) velocity of the frame origin in the world frame (m/s).
    :param angular_velocity: (3,) angular velocity in the world frame (rad/s).
    """

    position: np.ndarray
    orientation: np.ndarray
    linear_velocity: np.ndarray
    angular_velocity: np.ndarray


@dataclass(frozen=True)
class SensorReadings:
    """Everything a simulator backend measures at one instant.

    :param time: simulated time (s).
    :param joints: joint encoders and torques.
    :param imu: the pelvis IMU.
    :param left_foot: left ankle F/T sensor.
    :param right_foot: right ankle F/T sensor.
    :param zmp: (2,) measured ZMP: the centre of pressure of both feet, weighted by their normal
        forces (m, world x y); NaN when neither foot is in contact.
    :param base: ground-truth base state.
    :param left_sole: (3,) ground-truth left sole centre position (m).
    :param right_sole: (3,) ground-truth right sole centre position (m).
    :param com_position: (3,) ground-truth whole-body centre of mass (m).
    :param com_velocity: (3,) ground-truth centre-of-mass velocity (m/s).
    """

    time: float
    joints: JointReadings
    imu: ImuReading
    left_foot: FootForceTorque
    right_foot: FootForceTorque
    zmp: np.ndarray
    base: BaseState
    left_sole: np.ndarray
    right_sole: np.ndarray
    com_position: np.ndarray
    com_velocity: np.ndarray
