"""The robot's DCM from what the controller measures, for the step adjuster.

The centre of mass is the three-mass model's of the measured masses: the torso at the model
hip of the measured pelvis (biped_mpc.model_hip), each leg midway between its sole (leg
kinematics of the encoders) and the hip, as the controller's outputs y = C X place them. The
pelvis pose is the odometry's (the simulator's base, or a base estimator fusing IMU and leg
kinematics on a real robot). Its velocity is the finite difference of that centre of mass,
low-passed (first order): the raw 20 ms difference carries the stiff servos' vibration, which
exp(omega T) would amplify in the step adjuster's prediction.

The Kalman estimate of the three-mass state is not used: the estimator knows nothing of an
unknown push and lags it by several cycles (the model plant's finding, docs/controller_notes.md).
Pure numpy; time is an argument.
"""
import math
from typing import Optional, Tuple

import numpy as np

from biped_mpc.errors import InputError
from biped_mpc.leg_kinematics import LegKinematics
from biped_mpc.lipm_model import LipmParams
from biped_mpc.model_hip import ModelHip
from biped_mpc.robot_model import RobotModel
from biped_mpc.validation import finite_vector
from biped_planner.rotations import quaternion_to_matrix


class MeasuredDcm:
    """Horizontal centre of mass, its filtered velocity and the DCM xi = c + c_dot / omega.

    :param robot: the robot as the controller sees it (leg geometry, masses, COM offset)
    :param velocity_time_constant: time constant of the velocity low-pass (s), >= 0 (0: the
        raw difference)
    :raises InputError: for a robot without leg geometry or a negative time constant
    """

    def __init__(self, robot: RobotModel, velocity_time_constant: float = 0.03) -> None:
        if robot.leg_geometry is None:
            raise InputError('MeasuredDcm needs the robot leg geometry (leg kinematics)')
        if not math.isfinite(velocity_time_constant) or velocity_time_constant < 0.0:
            raise InputError(f'velocity_time_constant must be finite and >= 0, got '
                             f'{velocity_time_constant!r}')
        self._fk = LegKinematics(robot.leg_geometry)
        self._hip = ModelHip(robot.leg_geometry, robot.com_offset)
        masses = robot.masses
        total = masses.left_leg_mass + masses.torso_mass + masses.right_leg_mass
        self._weights = (masses.left_leg_mass / total, masses.torso_mass / total,
                         masses.right_leg_mass / total)
        lipm = LipmParams.from_three_mass(masses)
        self.omega = math.sqrt(lipm.gravity / lipm.com_height)
        self._time_constant = float(velocity_time_constant)
        self.reset()

    def reset(self) -> None:
        """Forget the previous sample (a new run)."""
        self._last: Optional[Tuple[float, np.ndarray]] = None
        self.velocity = np.zeros(2)

    def com(self, leg_joint_positions, pelvis_position, pelvis_orientation) -> np.ndarray:
        """The three-mass centre of mass of a measured pose (2,) (m).

        :param leg_joint_positions: (12,) leg angles, left leg then right leg (rad)
        :param pelvis_position: (3,) pelvis position (m)
        :param pelvis_orientation: (4,) pelvis quaternion (x, y, z, w)
        :return: (2,) horizontal centre of mass (m)
        """
        q = finite_vector('leg_joint_positions', leg_joint_positions, 12)
        pelvis = finite_vector('pelvis_position', pelvis_position, 3)
        rotation = quaternion_to_matrix(finite_vector('pelvis_orientation',
                                                      pelvis_orientation, 4))
        left, _, right, _ = self._fk.forward(q, pelvis, rotation)
        hip = self._hip.of_pelvis(pelvis, rotation)
        w_left, w_torso, w_right = self._weights
        return (w_left * 0.5 * (np.asarray(left)[:2] + hip) + w_torso * hip
                + w_right * 0.5 * (np.asarray(right)[:2] + hip))

    def update(self, t: float, leg_joint_positions, pelvis_position,
               pelvis_orientation) -> Tuple[np.ndarray, np.ndarray]:
        """Take the pose measured at t; the centre of mass and the DCM then.

        :param t: time of the measurement (s), after the previous one
        :param leg_joint_positions: (12,) leg angles (rad)
        :param pelvis_position: (3,) pelvis position (m)
        :param pelvis_orientation: (4,) pelvis quaternion (x, y, z, w)
        :return: (com (2,), dcm (2,)) (m)
        :raises InputError: for non-finite values or a time not after the previous one
        """
        if not math.isfinite(t):
            raise InputError(f't must be finite, got {t!r}')
        com = self.com(leg_joint_positions, pelvis_position, pelvis_orientation)
        if self._last is not None:
            dt = t - self._last[0]
            if dt <= 0.0:
                raise InputError(f't = {t} s is not after the previous sample '
                                 f'{self._last[0]} s')
            raw = (com - self._last[1]) / dt
            blend = dt / (self._time_constant + dt)
            self.velocity = self.velocity + blend * (raw - self.velocity)
        self._last = (float(t), com)
        return com, com + self.velocity / self.omega
