"""Feedback on the IK's pelvis: a velocity servo on its position, a lean against its tilt.

Neither is in the paper. The torque-controlled robot's stance leg is a lightly damped spring
(the simulator caps its joint damping for stability): the velocity servo damps its sway at the
control rate. The posture feedback leans the IK's pelvis against the measured roll and pitch.
"""
import numpy as np

from biped_planner.rotations import (roll_pitch_of_matrix, rotation_x, rotation_y, rotation_z,
                                     yaw_of_matrix)


class PelvisVelocityServo:
    """The pelvis target moved by the gain times the pelvis velocity error.

    command = target + gain ((target(k) - target(k-2)) - (pelvis(k) - pelvis(k-2))) / (2 Ts),
    in x and y. The velocities are mean velocities over the last two periods (position
    differences): the instantaneous pelvis velocity carries the joint servos' vibration, and a
    one-period difference would feed back the period-2 oscillation of a delayed loop at full
    gain.

    :param gain: servo gain (s), 0 disables it
    :param dt: control period Ts (s)
    """

    def __init__(self, gain: float, dt: float) -> None:
        self._gain = gain
        self._dt = dt
        self.reset(np.zeros(3))

    def reset(self, pelvis: np.ndarray) -> None:
        """Start at rest at this pelvis position (3,) (m)."""
        # Histories of the last three cycles, oldest first: k - 2, k - 1, k.
        self._targets = (pelvis.copy(),) * 3
        self._pelvis = (pelvis.copy(),) * 3

    def command(self, pelvis_target: np.ndarray, pelvis: np.ndarray) -> np.ndarray:
        """The pelvis position (3,) the IK should use this cycle (m).

        :param pelvis_target: (3,) the pelvis target of the cycle (m)
        :param pelvis: (3,) the measured or estimated pelvis position (m)
        """
        self._targets = self._targets[1:] + (pelvis_target.copy(),)
        self._pelvis = self._pelvis[1:] + (np.asarray(pelvis, float).copy(),)
        if self._gain <= 0.0:
            return pelvis_target
        command = pelvis_target.copy()
        command[:2] += self._gain * ((pelvis_target[:2] - self._targets[0][:2])
                                     - (pelvis[:2] - self._pelvis[0][:2])) / (2.0 * self._dt)
        return command


def posture_correction(rotation: np.ndarray, gain: float) -> np.ndarray:
    """Rotation leaning the IK's pelvis against the measured roll and pitch.

    :param rotation: (3, 3) measured pelvis orientation
    :param gain: fraction of the measured roll and pitch to lean against, 0 disables it
    :return: (3, 3) R_x(-gain roll) R_y(-gain pitch), roll and pitch in the heading frame
    """
    if gain <= 0.0:
        return np.eye(3)
    tilt = rotation_z(yaw_of_matrix(rotation)).T @ rotation
    roll, pitch = roll_pitch_of_matrix(tilt)
    return rotation_x(-gain * roll) @ rotation_y(-gain * pitch)
