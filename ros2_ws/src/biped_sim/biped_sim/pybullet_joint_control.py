"""The joint servos of the PyBullet humanoid: explicit PD plus gravity compensation, or motors.

In torque mode the joints' velocity motors are disabled and every physics step applies to every
actuated joint

    tau = Kp (q_des - q) + Kd (dq_des - dq) + tau_g(q, contacts),  clipped to the effort limits,

where tau_g is the gravity compensation with the weight split between the feet to follow the
centre of mass (:mod:`biped_sim.contact_gravity_compensation`), recomputed every
gravity_compensation_period physics steps and held in between. The explicit PD gains of each
joint are capped with its joint-space inertia M_jj at the nominal pose so the discrete loop
stays stable: Kp dt^2 / M_jj <= gain_cap and Kd dt / M_jj <= gain_cap (omega dt <= 0.7 for
0.5); this cap is what keeps explicit PD on light arm links from blowing up. In position mode
every joint uses PyBullet's implicit position motors, a robust fallback.
"""

import operator
from typing import Optional

import numpy as np

from biped_sim.contact_gravity_compensation import ContactGravityCompensation
from biped_sim.pybullet_config import PyBulletConfig, TORQUE_CONTROL
from biped_sim.pybullet_robot_index import RobotIndex
from biped_sim.pybullet_sensing import PyBulletSensing

try:
    import pybullet
except ImportError as error:  # pragma: no cover - pybullet is a hard dependency of biped_sim
    raise ImportError('biped_sim.pybullet_joint_control needs pybullet (Python <= 3.11 '
                      'wheels): pip install pybullet==3.2.7') from error

N_LEG_JOINTS = 12
_position, _velocity = operator.itemgetter(0), operator.itemgetter(1)  # of a joint state


def capped_gains(config: PyBulletConfig, inertia: np.ndarray) -> tuple:
    """Return the PD gains (Kp (n,), Kd (n,)) after the stability cap (see the module).

    :param config: the gains before the cap (legs: the first 12 joints) and the cap.
    :param inertia: (n,) joint-space inertia M_jj of each actuated joint (kg m^2).
    """
    dt, cap = config.time_step, config.gain_cap
    is_leg = np.arange(inertia.size) < N_LEG_JOINTS
    kp = np.minimum(np.where(is_leg, config.leg_kp, config.upper_kp), cap * inertia / dt ** 2)
    kd = np.minimum(np.where(is_leg, config.leg_kd, config.upper_kd), cap * inertia / dt)
    return kp, kd


class PyBulletJointControl:
    """Drives the actuated joints to their setpoints (see the module docstring).

    :param client: PyBullet physics client id.
    :param robot: PyBullet body id of the robot.
    :param index: the robot's indices.
    :param config: control mode, gains, gravity compensation settings.
    :param gravity_compensation: the robot's gravity compensation.
    :param sensing: the robot's sensors (base pose and foot contacts of the compensation).
    :param nominal: (n,) nominal joint angles, where the gains are capped (rad).
    """

    def __init__(self, client: int, robot: int, index: RobotIndex, config: PyBulletConfig,
                 gravity_compensation: ContactGravityCompensation, sensing: PyBulletSensing,
                 nominal: np.ndarray) -> None:
        self._client, self._robot, self._index, self._config = client, robot, index, config
        self._compensation = gravity_compensation
        self._sensing = sensing
        self.torque_mode = config.control_mode == TORQUE_CONTROL
        if self.torque_mode:
            pybullet.setJointMotorControlArray(
                robot, index.actuated, pybullet.VELOCITY_CONTROL,
                forces=[0.0] * len(index.actuated), physicsClientId=client)
        inertia = gravity_compensation.joint_inertia_diagonal(
            np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 0.0, 1.0]), nominal)
        self.kp, self.kd = capped_gains(config, inertia)
        self._read_with_ft = list(index.actuated) + list(index.ft_joints)
        self.reset(nominal)

    def reset(self, q_des: np.ndarray) -> None:
        """Hold the setpoints q_des at rest, with no torque applied yet."""
        n = len(self._index.actuated)
        self.q_des = np.array(q_des, dtype=float)
        self.dq_des = np.zeros(n)
        self.last_torque = np.zeros(n)
        self._gravity_torque = np.zeros(n)
        self.set_setpoints()

    def set_setpoints(self, q_des: Optional[np.ndarray] = None,
                      dq_des: Optional[np.ndarray] = None) -> None:
        """Set the setpoints of a control period (a prefix of the joints; the rest keep theirs).

        :param q_des: (k,) angles of the first k actuated joints (rad); None keeps them.
        :param dq_des: (k,) feed-forward speeds (rad/s); None is zero for every joint.
        """
        if q_des is not None:
            self.q_des[:q_des.size] = q_des
            self.dq_des[:] = 0.0
        if dq_des is not None:
            self.dq_des[:dq_des.size] = dq_des
        if not self.torque_mode:
            config = self._config
            pybullet.setJointMotorControlArray(
                self._robot, self._index.actuated, pybullet.POSITION_CONTROL,
                targetPositions=self.q_des.tolist(), targetVelocities=self.dq_des.tolist(),
                forces=self._index.effort_limit.tolist(),
                positionGains=[config.position_gain] * len(self._index.actuated),
                velocityGains=[config.velocity_gain] * len(self._index.actuated),
                physicsClientId=self._client)
        # Kp q_des + Kd dq_des is constant over the control period.
        self._pd_offset = self.kp * self.q_des + self.kd * self.dq_des

    def apply_torques(self, step_count: int) -> None:
        """Torque mode: PD to the setpoints plus gravity compensation on every joint.

        :param step_count: physics steps since the reset (paces the gravity compensation).
        """
        client, robot, config, index = self._client, self._robot, self._config, self._index
        compensate = (config.gravity_compensation
                      and step_count % config.gravity_compensation_period == 0)
        # One call reads the F/T joints too when the compensation needs them.
        read = self._read_with_ft if compensate and index.ft_joints else index.actuated
        states = pybullet.getJointStates(robot, read, physicsClientId=client)
        n = len(index.actuated)
        q = np.fromiter(map(_position, states[:n]), float, n)
        dq = np.fromiter(map(_velocity, states[:n]), float, n)
        tau = self._pd_offset - self.kp * q - self.kd * dq
        if compensate:
            position, orientation = self._sensing.base_frame_pose()
            if index.ft_joints:
                # Normal force of each foot, with the foot's z axis taken as vertical.
                normal = [-s[2][2] + m * config.gravity
                          for s, m in zip(states[n:], index.foot_mass)]
            else:
                normal = self._sensing.contact_normal_forces()
            contacts = tuple(f > config.contact_threshold for f in normal)
            self._gravity_torque = self._compensation.torques(position, orientation, q, contacts)
        if config.gravity_compensation:
            tau += self._gravity_torque
        tau = np.minimum(np.maximum(tau, -index.effort_limit), index.effort_limit)
        self.last_torque = tau
        pybullet.setJointMotorControlArray(robot, index.actuated, pybullet.TORQUE_CONTROL,
                                           forces=tau.tolist(), physicsClientId=client)
