"""PyBullet simulator backend: a humanoid on the ground, torque- or position-controlled.

Physics runs at a fixed step (1 kHz by default) with manual stepping. In torque mode the joints'
velocity motors are disabled and every physics step applies to every actuated joint

    tau = Kp (q_des - q) + Kd (dq_des - dq) + tau_g(q, contacts),  clipped to the effort limits,

where tau_g is the gravity compensation with the weight split between the feet to follow the
centre of mass (:mod:`biped_sim.contact_gravity_compensation`), recomputed every
gravity_compensation_period physics steps. The explicit PD gains of each joint are capped with
its joint-space inertia M_jj at the nominal pose so the discrete loop stays stable:
Kp dt^2 / M_jj <= gain_cap and Kd dt / M_jj <= gain_cap (omega dt <= 0.7 for 0.5); this cap is
what keeps explicit PD on light arm links from blowing up. In position mode every joint uses
PyBullet's implicit position motors, a robust fallback.

The ankle F/T joints report, in PyBullet, the force and torque the parent applies on the child
link, in the child's inertial frame, about the child's centre of mass; this module turns them
into sensor-frame readings and ground reactions (see :class:`biped_sim.sensors.FootForceTorque`).
A robot without ankle F/T joints (RobotDescription.ft_joints == ()) is read from the contact
points of its feet (the links below the ankle roll joints) instead: the ground reaction is their
sum, and the foot's "sensor" is a virtual one at the sole frame with no foot mass below it.
"""

from dataclasses import dataclass
import math
from typing import Optional

import numpy as np

from biped_sim.backend import SimulatorBackend
from biped_sim.camera_view import CameraView
from biped_sim.contact_gravity_compensation import ContactGravityCompensation
from biped_sim.errors import ConfigError, RobotModelError
from biped_sim.external_push import ExternalPush
from biped_sim.obstacles import as_sim_obstacle, BoxObstacle
from biped_sim.robot_description import RobotDescription
from biped_sim.sensors import (BaseState, FootForceTorque, ImuReading, JointReadings,
                               SensorReadings)
from biped_sim.terrain import Terrain

try:
    import pybullet
    import pybullet_data
except ImportError as error:  # pragma: no cover - pybullet is a hard dependency of biped_sim
    raise ImportError('biped_sim.pybullet_backend needs pybullet (Python <= 3.11 wheels): '
                      'pip install pybullet==3.2.7') from error

TORQUE_CONTROL = 'torque'
POSITION_CONTROL = 'position'
_SPAWN_CLEARANCE = 5e-4  # m between the lowest sole and the ground at reset


MAX_SHAPES_PER_BODY = 16  # createVisualShapeArray segfaults with more (PyBullet 3.2.7)


@dataclass(frozen=True)
class PyBulletConfig:
    """Parameters of the PyBullet backend.

    :param gui: open the PyBullet GUI instead of running headless (DIRECT).
    :param time_step: physics step (s), in (0, 0.01].
    :param control_substeps: physics steps per control period (20 = 50 Hz at 1 kHz), >= 1.
    :param control_mode: 'torque' (PD + gravity compensation) or 'position' (PyBullet motors).
    :param gravity: gravity acceleration (m/s^2), > 0.
    :param leg_kp: proportional gain of the leg joints in torque mode (N m/rad), >= 0.
    :param leg_kd: derivative gain of the leg joints in torque mode (N m s/rad), >= 0.
    :param upper_kp: proportional gain of the waist and arm joints in torque mode (N m/rad).
    :param upper_kd: derivative gain of the waist and arm joints in torque mode (N m s/rad).
    :param gain_cap: stability cap of the explicit PD (Kp dt^2/M_jj and Kd dt/M_jj), (0, 1].
    :param gravity_compensation: add the gravity-compensation torques in torque mode.
    :param gravity_compensation_period: physics steps between two computations of the
        gravity-compensation torques (held in between), >= 1.
    :param position_gain: PyBullet position-motor gain (position mode), (0, 1].
    :param velocity_gain: PyBullet position-motor velocity gain, [0, 1].
    :param foot_friction: lateral friction coefficient of the feet and the ground, > 0.
    :param contact_threshold: normal ground force above which a foot is in contact (N), > 0.
    :param solver_iterations: iterations of PyBullet's constraint solver, >= 1.
    """

    gui: bool = False
    time_step: float = 0.001
    control_substeps: int = 20
    control_mode: str = TORQUE_CONTROL
    gravity: float = 9.81
    leg_kp: float = 800.0
    leg_kd: float = 8.0
    upper_kp: float = 300.0
    upper_kd: float = 3.0
    gain_cap: float = 0.5
    gravity_compensation: bool = True
    gravity_compensation_period: int = 1
    position_gain: float = 0.3
    velocity_gain: float = 1.0
    foot_friction: float = 1.0
    contact_threshold: float = 15.0
    solver_iterations: int = 50

    def __post_init__(self):
        checks = (
            ('time_step', 0.0 < self.time_step <= 0.01, 'in (0, 0.01]'),
            ('gravity', self.gravity > 0.0, '> 0'),
            ('leg_kp', self.leg_kp >= 0.0, '>= 0'),
            ('leg_kd', self.leg_kd >= 0.0, '>= 0'),
            ('upper_kp', self.upper_kp >= 0.0, '>= 0'),
            ('upper_kd', self.upper_kd >= 0.0, '>= 0'),
            ('gain_cap', 0.0 < self.gain_cap <= 1.0, 'in (0, 1]'),
            ('position_gain', 0.0 < self.position_gain <= 1.0, 'in (0, 1]'),
            ('velocity_gain', 0.0 <= self.velocity_gain <= 1.0, 'in [0, 1]'),
            ('foot_friction', self.foot_friction > 0.0, '> 0'),
            ('contact_threshold', self.contact_threshold > 0.0, '> 0'),
        )
        for name, ok, allowed in checks:
            value = getattr(self, name)
            if not (math.isfinite(value) and ok):
                raise ConfigError('PyBulletConfig.%s = %r must be %s' % (name, value, allowed))
        for name in ('control_substeps', 'solver_iterations', 'gravity_compensation_period'):
            value = getattr(self, name)
            if not (isinstance(value, int) and value >= 1):
                raise ConfigError('PyBulletConfig.%s = %r must be an int >= 1' % (name, value))
        if self.control_mode not in (TORQUE_CONTROL, POSITION_CONTROL):
            raise ConfigError('PyBulletConfig.control_mode = %r must be %r or %r'
                              % (self.control_mode, TORQUE_CONTROL, POSITION_CONTROL))


def _rotation(quaternion) -> np.ndarray:
    x, y, z, w = quaternion
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product of 3-vectors (or rows of (n, 3) arrays); much faster than np.cross."""
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def _finite_array(name: str, value, shape: tuple) -> np.ndarray:
    array = np.asarray(value, dtype=float)
    if array.shape != shape:
        raise ConfigError('%s has shape %s, expected %s' % (name, array.shape, shape))
    if not np.all(np.isfinite(array)):
        raise ConfigError('%s = %r has NaN or inf' % (name, value))
    return array


class PyBulletBackend(SimulatorBackend):
    """A humanoid described by a RobotDescription, simulated by PyBullet (see module docstring).

    :param description: the robot.
    :param config: simulator parameters.
    :raises RobotModelError: if the description does not match the URDF.
    """

    def __init__(self, description: RobotDescription, config: PyBulletConfig = PyBulletConfig()):
        self._description = description
        self._config = config
        self._client = pybullet.connect(pybullet.GUI if config.gui else pybullet.DIRECT)
        if self._client < 0:
            raise ConfigError('could not connect to PyBullet (gui=%r)' % config.gui)
        self._closed = False
        try:
            self._build()
        except Exception:
            self.close()
            raise

    def _build(self) -> None:
        config, description = self._config, self._description
        self._dt = config.time_step
        self._gravity_vector = np.array([0.0, 0.0, -config.gravity])
        self._terrain: Optional[Terrain] = None
        self._scenery: list = []
        self._pushes: list = []
        self._step_count = 0
        client = self._client
        pybullet.setGravity(0.0, 0.0, -config.gravity, physicsClientId=client)
        pybullet.setTimeStep(config.time_step, physicsClientId=client)
        pybullet.setPhysicsEngineParameter(numSolverIterations=config.solver_iterations,
                                           physicsClientId=client)
        pybullet.setRealTimeSimulation(0, physicsClientId=client)
        pybullet.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=client)
        self._ground = pybullet.loadURDF('plane.urdf', physicsClientId=client)
        pybullet.changeDynamics(self._ground, -1, lateralFriction=config.foot_friction,
                                physicsClientId=client)
        self._robot = pybullet.loadURDF(description.urdf_path, [0.0, 0.0, 1.0],
                                        flags=pybullet.URDF_USE_INERTIA_FROM_FILE,
                                        physicsClientId=client)
        self._index_joints()
        self._gravity_compensation = ContactGravityCompensation(
            description.urdf_path, self._joint_names, description.sole_frames,
            description.sole_length, description.sole_width, config.gravity)
        self._setup_motors()
        self._kp, self._kd = self._capped_gains()
        self.reset()

    # ----------------------------------------------------------------------------- set up
    def _index_joints(self) -> None:
        client, robot, desc = self._client, self._robot, self._description
        by_name, link_by_name, revolute, parents, effort = {}, {}, [], [], {}
        for j in range(pybullet.getNumJoints(robot, physicsClientId=client)):
            info = pybullet.getJointInfo(robot, j, physicsClientId=client)
            name = info[1].decode()
            by_name[name] = j
            link_by_name[info[12].decode()] = j
            parents.append(info[16])
            if info[2] in (pybullet.JOINT_REVOLUTE, pybullet.JOINT_PRISMATIC):
                revolute.append(j)
                effort[j] = info[10]
        base_name = pybullet.getBodyInfo(robot, physicsClientId=client)[0].decode()
        link_by_name[base_name] = -1
        if base_name != desc.base_link:
            raise RobotModelError('description base_link %r but the URDF root is %r'
                                  % (desc.base_link, base_name))
        missing = [n for n in desc.leg_joint_names + desc.ft_joints if n not in by_name]
        missing += [n for n in desc.sole_frames + (desc.imu_link,) if n not in link_by_name]
        if missing:
            raise RobotModelError('not in %s: %r' % (desc.urdf_path, missing))
        leg = [by_name[n] for n in desc.leg_joint_names]
        upper = [j for j in revolute if j not in leg]
        self._actuated_index = np.array(leg + upper)
        self._actuated_list = leg + upper
        names = {j: n for n, j in by_name.items()}
        self._joint_names = tuple(names[j] for j in self._actuated_index)
        self._effort_limit = np.array([effort[j] for j in self._actuated_index])
        self._link_index = link_by_name
        self._ft_index = [by_name[n] for n in desc.ft_joints]
        # The foot is what hangs below the F/T sensor, or below the ankle roll joint without one.
        foot_roots = self._ft_index or [leg[5], leg[11]]
        self._sole_index = [link_by_name[n] for n in desc.sole_frames]
        self._imu_index = link_by_name[desc.imu_link]
        for j in self._ft_index:
            pybullet.enableJointForceTorqueSensor(robot, j, True, physicsClientId=client)
        n_links = len(parents)
        self._all_links = list(range(n_links))
        dynamics = [pybullet.getDynamicsInfo(robot, j, physicsClientId=client)
                    for j in [-1] + self._all_links]
        self._link_mass = np.array([d[0] for d in dynamics])
        self._total_mass = float(self._link_mass.sum())
        self._base_inertial_position = np.array(dynamics[0][3])
        self._base_inertial_orientation = dynamics[0][4]
        self._base_inertial_is_identity = bool(
            np.allclose(self._base_inertial_position, 0.0, atol=1e-12)
            and np.allclose(self._base_inertial_orientation, (0.0, 0.0, 0.0, 1.0), atol=1e-12))
        # Links of each foot (below its F/T joint or ankle roll joint) and their masses.
        self._below_ft = []
        for j in foot_roots:
            subtree = [k for k in self._all_links if self._is_descendant(k, j, parents)]
            self._below_ft.append(np.array(subtree))
        self._foot_side = {int(k): side for side, sub in enumerate(self._below_ft) for k in sub}
        for k in self._all_links:
            pybullet.changeDynamics(robot, k, linearDamping=0.0, angularDamping=0.0,
                                    physicsClientId=client)
        pybullet.changeDynamics(robot, -1, linearDamping=0.0, angularDamping=0.0,
                                physicsClientId=client)
        for subtree in self._below_ft:
            for k in subtree:
                pybullet.changeDynamics(robot, int(k), lateralFriction=self._config.foot_friction,
                                        physicsClientId=client)
        self._ft_subtree_mass = np.array([self._link_mass[sub + 1].sum()
                                          for sub in self._below_ft])

    @staticmethod
    def _is_descendant(link: int, ancestor: int, parents: list) -> bool:
        while link >= 0:
            if link == ancestor:
                return True
            link = parents[link]
        return False

    def _setup_motors(self) -> None:
        client, robot = self._client, self._robot
        if self._config.control_mode == TORQUE_CONTROL:
            pybullet.setJointMotorControlArray(
                robot, self._actuated_list, pybullet.VELOCITY_CONTROL,
                forces=[0.0] * len(self._actuated_list), physicsClientId=client)

    def _capped_gains(self) -> tuple:
        nominal = self._nominal_positions({})
        base_position = np.array([0.0, 0.0, 1.0])
        inertia = self._gravity_compensation.joint_inertia_diagonal(
            base_position, np.array([0.0, 0.0, 0.0, 1.0]), nominal)
        cap, config = self._config.gain_cap, self._config
        is_leg = np.arange(len(self._joint_names)) < 12
        kp = np.minimum(np.where(is_leg, config.leg_kp, config.upper_kp),
                        cap * inertia / self._dt ** 2)
        kd = np.minimum(np.where(is_leg, config.leg_kd, config.upper_kd),
                        cap * inertia / self._dt)
        return kp, kd

    def _nominal_positions(self, overrides: dict) -> np.ndarray:
        nominal = dict(self._description.nominal_joint_positions)
        unknown = [n for n in overrides if n not in self._joint_names]
        if unknown:
            raise ConfigError('joint_positions names unknown joints %r' % (unknown,))
        nominal.update(overrides)
        q = np.array([nominal.get(n, 0.0) for n in self._joint_names], dtype=float)
        if not np.all(np.isfinite(q)):
            raise ConfigError('joint_positions %r has NaN or inf' % (overrides,))
        return q

    # ----------------------------------------------------------------------------- properties
    @property
    def joint_names(self) -> tuple:
        """Actuated joints: the 12 leg joints first, then the others in URDF order."""
        return self._joint_names

    @property
    def leg_joint_names(self) -> tuple:
        """The 12 leg joints (the first 12 of joint_names)."""
        return self._description.leg_joint_names

    @property
    def time(self) -> float:
        """Simulated time since the last reset (s)."""
        return self._step_count * self._dt

    @property
    def time_step(self) -> float:
        """Physics step (s)."""
        return self._dt

    @property
    def description(self) -> RobotDescription:
        """The simulated robot."""
        return self._description

    @property
    def config(self) -> PyBulletConfig:
        """The simulator parameters."""
        return self._config

    @property
    def total_mass(self) -> float:
        """Mass of the robot in the simulation (kg)."""
        return self._total_mass

    @property
    def joint_gains(self) -> tuple:
        """(Kp, Kd) of the actuated joints in torque mode after the stability cap."""
        return self._kp.copy(), self._kd.copy()

    @property
    def client_id(self) -> int:
        """PyBullet physics client id, for direct PyBullet queries."""
        return self._client

    @property
    def robot_id(self) -> int:
        """PyBullet body id of the robot."""
        return self._robot

    # ----------------------------------------------------------------------------- reset
    def reset(self, base_position: Optional[np.ndarray] = None, base_yaw: float = 0.0,
              joint_positions: Optional[dict] = None) -> SensorReadings:
        """Put the robot in a standing pose at rest and the time to 0.

        :param base_position: (3,) base frame position (m); None stands the soles on the
            ground (or on the terrain) below the base at x = y = 0.
        :param base_yaw: heading of the base (rad).
        :param joint_positions: joint name -> angle (rad) overriding the nominal pose.
        :return: the readings in the new state.
        :raises ConfigError: for non-finite values or unknown joint names.
        """
        self._check_open()
        client, robot = self._client, self._robot
        if not math.isfinite(base_yaw):
            raise ConfigError('base_yaw = %r must be finite' % (base_yaw,))
        q = self._nominal_positions(dict(joint_positions or {}))
        orientation = pybullet.getQuaternionFromEuler([0.0, 0.0, base_yaw])
        if base_position is None:
            position = np.array([0.0, 0.0, 1.0])
        else:
            position = _finite_array('base_position', base_position, (3,))
        self._set_base_pose(position, orientation)
        for j, angle in zip(self._actuated_index, q):
            pybullet.resetJointState(robot, int(j), float(angle), 0.0, physicsClientId=client)
        if base_position is None:
            position[2] += self._ground_clearance_shift()
            self._set_base_pose(position, orientation)
        pybullet.resetBaseVelocity(robot, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0],
                                   physicsClientId=client)
        self._step_count = 0
        self._pushes = []
        self._q_des = q
        self._dq_des = np.zeros_like(q)
        self._last_torque = np.zeros(len(self._joint_names))
        self._gravity_torque = np.zeros(len(self._joint_names))
        self._apply_position_motors()
        self._imu_velocity_mark = (self._imu_frame_state()[2], 0)
        return self.sensors()

    def _set_base_pose(self, position: np.ndarray, orientation) -> None:
        com_position, com_orientation = pybullet.multiplyTransforms(
            position.tolist(), orientation, self._base_inertial_position.tolist(),
            self._base_inertial_orientation, physicsClientId=self._client)
        pybullet.resetBasePositionAndOrientation(self._robot, com_position, com_orientation,
                                                 physicsClientId=self._client)

    def _ground_clearance_shift(self) -> float:
        """Return how much to raise the base so the soles rest on the ground or terrain."""
        shift = -np.inf
        half = 0.5 * np.array([self._description.sole_length, self._description.sole_width])
        corners = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1], [0, 0]]) * half
        for link in self._sole_index:
            state = pybullet.getLinkState(self._robot, link, computeForwardKinematics=1,
                                          physicsClientId=self._client)
            position, rotation = np.array(state[4]), _rotation(state[5])
            points = position + corners @ rotation[:, :2].T
            ground = 0.0
            if self._terrain is not None:
                ground = float(np.max(self._terrain.height_at(points[:, 0], points[:, 1])))
            shift = max(shift, ground + _SPAWN_CLEARANCE - float(np.min(points[:, 2])))
        return shift

    # ----------------------------------------------------------------------------- stepping
    def step(self, joint_setpoints: np.ndarray, n_substeps: Optional[int] = None,
             joint_velocities: Optional[np.ndarray] = None,
             read_sensors: bool = True) -> Optional[SensorReadings]:
        """Track joint setpoints for n_substeps physics steps and return the readings.

        :param joint_setpoints: (len(joint_names),) angles of all actuated joints, or (12,)
            leg angles only (the other joints keep their setpoints) (rad).
        :param n_substeps: physics steps to run, >= 1; None runs config.control_substeps.
        :param joint_velocities: optional feed-forward joint speeds, same shape (rad/s).
        :param read_sensors: read the sensors at the end (False: return None, to save the
            readout of an intermediate part of a period).
        :return: the readings at the end of the last physics step.
        :raises ConfigError: for a wrong shape, NaN/inf or n_substeps < 1.
        """
        self._check_open()
        n = self._config.control_substeps if n_substeps is None else n_substeps
        if not (isinstance(n, (int, np.integer)) and n >= 1):
            raise ConfigError('n_substeps = %r must be an int >= 1' % (n_substeps,))
        q_des = np.asarray(joint_setpoints, dtype=float)
        if q_des.shape not in ((12,), (len(self._joint_names),)):
            raise ConfigError('joint_setpoints has shape %s, expected (12,) or (%d,)'
                              % (q_des.shape, len(self._joint_names)))
        if not np.all(np.isfinite(q_des)):
            raise ConfigError('joint_setpoints %r has NaN or inf' % (joint_setpoints,))
        self._q_des[:q_des.size] = q_des
        self._dq_des[:] = 0.0
        if joint_velocities is not None:
            dq_des = _finite_array('joint_velocities', joint_velocities, q_des.shape)
            self._dq_des[:dq_des.size] = dq_des
        self._imu_velocity_mark = (self._imu_frame_state()[2], self._step_count)
        self._apply_position_motors()
        # Kp q_des + Kd dq_des is constant over the control period.
        self._pd_offset = self._kp * self._q_des + self._kd * self._dq_des
        torque_mode = self._config.control_mode == TORQUE_CONTROL
        for _ in range(int(n)):
            if torque_mode:
                self._apply_torques()
            if self._pushes:
                self._apply_pushes()
            pybullet.stepSimulation(physicsClientId=self._client)
            self._step_count += 1
        return self.sensors() if read_sensors else None

    def _apply_position_motors(self) -> None:
        """In position mode, send the setpoints to PyBullet's position motors."""
        if self._config.control_mode == TORQUE_CONTROL:
            return
        pybullet.setJointMotorControlArray(
            self._robot, self._actuated_list, pybullet.POSITION_CONTROL,
            targetPositions=self._q_des.tolist(), targetVelocities=self._dq_des.tolist(),
            forces=self._effort_limit.tolist(),
            positionGains=[self._config.position_gain] * len(self._actuated_list),
            velocityGains=[self._config.velocity_gain] * len(self._actuated_list),
            physicsClientId=self._client)

    def _apply_torques(self) -> None:
        """Torque mode: PD to the setpoints plus gravity compensation on every joint."""
        client, robot, config = self._client, self._robot, self._config
        states = pybullet.getJointStates(robot, self._actuated_list, physicsClientId=client)
        q = np.array([s[0] for s in states])
        dq = np.array([s[1] for s in states])
        tau = self._pd_offset - self._kp * q - self._kd * dq
        if config.gravity_compensation:
            if self._step_count % config.gravity_compensation_period == 0:
                position, orientation = self._base_frame_pose()
                if self._ft_index:
                    ft = pybullet.getJointStates(robot, self._ft_index, physicsClientId=client)
                    # Normal force of each foot, with the foot's z axis taken as vertical.
                    normal = [-s[2][2] + m * config.gravity
                              for s, m in zip(ft, self._ft_subtree_mass)]
                else:
                    normal = self._contact_normal_forces()
                contacts = tuple(f > config.contact_threshold for f in normal)
                self._gravity_torque = self._gravity_compensation.torques(
                    position, orientation, q, contacts)
            tau += self._gravity_torque
        tau = np.minimum(np.maximum(tau, -self._effort_limit), self._effort_limit)
        self._last_torque = tau
        pybullet.setJointMotorControlArray(robot, self._actuated_list, pybullet.TORQUE_CONTROL,
                                           forces=tau.tolist(), physicsClientId=client)

    def _base_frame_pose(self) -> tuple:
        """Return the base link frame (position (3,), quaternion (4,)) from its inertial pose."""
        com_position, com_orientation = pybullet.getBasePositionAndOrientation(
            self._robot, physicsClientId=self._client)
        if self._base_inertial_is_identity:
            return np.array(com_position), np.array(com_orientation)
        inv_position, inv_orientation = pybullet.invertTransform(
            self._base_inertial_position.tolist(), self._base_inertial_orientation,
            physicsClientId=self._client)
        position, orientation = pybullet.multiplyTransforms(
            com_position, com_orientation, inv_position, inv_orientation,
            physicsClientId=self._client)
        return np.array(position), np.array(orientation)

    # ----------------------------------------------------------------------------- pushes
    def push(self, push: ExternalPush) -> None:
        """Schedule an external push, applied at every physics step it lasts.

        :param push: the push; its start_time None starts it at the next physics step.
        :raises ConfigError: if the push names an unknown link.
        """
        self._check_open()
        link_name = push.link if push.link is not None else self._description.base_link
        if link_name not in self._link_index:
            raise ConfigError('push link %r is not a link of %s'
                              % (link_name, self._description.name))
        start = self._step_count if push.start_time is None else int(
            round(push.start_time / self._dt))
        end = start + max(1, int(round(push.duration / self._dt)))
        self._pushes.append((start, end, self._link_index[link_name], np.array(push.point),
                             list(push.force)))

    def _apply_pushes(self) -> None:
        client, robot, now = self._client, self._robot, self._step_count
        active = []
        for start, end, link, point, force in self._pushes:
            if now >= end:
                continue
            active.append((start, end, link, point, force))
            if now < start:
                continue
            if link < 0:
                position, orientation = self._base_frame_pose()
            else:
                state = pybullet.getLinkState(robot, link, computeForwardKinematics=1,
                                              physicsClientId=client)
                position, orientation = np.array(state[4]), state[5]
            world_point = position + _rotation(orientation) @ point
            pybullet.applyExternalForce(robot, link, force, world_point.tolist(),
                                        pybullet.WORLD_FRAME, physicsClientId=client)
        self._pushes = active

    # ----------------------------------------------------------------------------- sensing
    def _imu_frame_state(self) -> tuple:
        """Return the IMU frame (position, quaternion, linear velocity, angular velocity)."""
        state = pybullet.getLinkState(self._robot, self._imu_index, computeLinkVelocity=1,
                                      computeForwardKinematics=1, physicsClientId=self._client)
        com, frame = np.array(state[0]), np.array(state[4])
        angular = np.array(state[7])
        linear = np.array(state[6]) + _cross(angular, frame - com)
        return frame, np.array(state[5]), linear, angular

    def sensors(self) -> SensorReadings:
        """Return the readings of the current state (see biped_sim.sensors)."""
        self._check_open()
        client, robot = self._client, self._robot
        states = pybullet.getJointStates(robot, self._actuated_list, physicsClientId=client)
        position = np.array([s[0] for s in states])
        velocity = np.array([s[1] for s in states])
        torque = np.array([s[3] for s in states])
        if self._config.control_mode == TORQUE_CONTROL:
            torque = self._last_torque.copy()
        joints = JointReadings(self._joint_names, position, velocity, torque)

        links = pybullet.getLinkStates(robot, self._all_links, computeLinkVelocity=1,
                                       computeForwardKinematics=1, physicsClientId=client)
        com_positions = np.array([s[0] for s in links])
        com_velocities = np.array([s[6] for s in links])
        base_com, base_orientation = pybullet.getBasePositionAndOrientation(
            robot, physicsClientId=client)
        base_linear, base_angular = pybullet.getBaseVelocity(robot, physicsClientId=client)
        base_com, base_linear = np.array(base_com), np.array(base_linear)
        base_angular = np.array(base_angular)
        masses = self._link_mass
        com = (masses[0] * base_com + masses[1:] @ com_positions) / self._total_mass
        com_velocity = (masses[0] * base_linear + masses[1:] @ com_velocities) / self._total_mass

        frame_position, frame_orientation = self._base_frame_pose()
        frame_velocity = base_linear + _cross(base_angular, frame_position - base_com)
        base = BaseState(frame_position, frame_orientation, frame_velocity, base_angular)

        imu_position, imu_orientation, imu_velocity, imu_angular = self._imu_frame_state()
        imu_rotation = _rotation(imu_orientation)
        mark_velocity, mark_step = self._imu_velocity_mark
        elapsed = (self._step_count - mark_step) * self._dt
        acceleration = ((imu_velocity - mark_velocity) / elapsed if elapsed > 0.0
                        else np.zeros(3))
        imu = ImuReading(imu_orientation, imu_rotation.T @ imu_angular,
                         imu_rotation.T @ (acceleration - self._gravity_vector))

        if self._ft_index:
            ft_states = pybullet.getJointStates(robot, self._ft_index, physicsClientId=client)
            feet = [self._foot_reading(i, ft_states[i][2], links) for i in (0, 1)]
        else:
            feet = self._contact_foot_readings(links)
        normal = np.array([f.ground_force[2] if f.in_contact else 0.0 for f in feet])
        if normal.sum() > 0.0:
            zmp = (normal[0] * np.nan_to_num(feet[0].cop[:2])
                   + normal[1] * np.nan_to_num(feet[1].cop[:2])) / normal.sum()
        else:
            zmp = np.full(2, np.nan)
        soles = [np.array(links[k][4]) for k in self._sole_index]
        return SensorReadings(self.time, joints, imu, feet[0], feet[1], zmp, base, soles[0],
                              soles[1], com, com_velocity)

    def _foot_reading(self, side: int, raw_wrench, links) -> FootForceTorque:
        """Turn PyBullet's F/T joint reaction into sensor readings and the ground reaction."""
        child = self._ft_index[side]
        child_com = np.array(links[child][0])
        child_inertial_rotation = _rotation(links[child][1])
        sensor_origin = np.array(links[child][4])
        sensor_rotation = _rotation(links[child][5])
        # Wrench of the leg on the foot, world axes, about the foot's centre of mass.
        force_on_foot = child_inertial_rotation @ np.asarray(raw_wrench[:3])
        torque_on_foot = child_inertial_rotation @ np.asarray(raw_wrench[3:])
        torque_at_sensor = torque_on_foot + _cross(child_com - sensor_origin, force_on_foot)
        sensor_force = sensor_rotation.T @ -force_on_foot
        sensor_torque = sensor_rotation.T @ -torque_at_sensor

        sole = self._sole_index[side]
        sole_position = np.array(links[sole][4])
        sole_rotation = _rotation(links[sole][5])
        subtree = self._below_ft[side]
        weights = self._link_mass[subtree + 1][:, None] * self._gravity_vector
        centres = np.array([links[k][0] for k in subtree])
        ground_force = -force_on_foot - weights.sum(axis=0)
        ground_torque = (-(torque_on_foot + _cross(child_com - sole_position, force_on_foot))
                         - _cross(centres - sole_position, weights).sum(axis=0))
        return self._ground_reading(sensor_force, sensor_torque, ground_force, ground_torque,
                                    sole_position, sole_rotation)

    def _ground_reading(self, sensor_force, sensor_torque, ground_force, ground_torque,
                        sole_position, sole_rotation) -> FootForceTorque:
        """Complete a foot reading with its contact flag and centre of pressure."""
        local_force = sole_rotation.T @ ground_force
        local_torque = sole_rotation.T @ ground_torque
        in_contact = bool(local_force[2] > self._config.contact_threshold)
        if in_contact:
            local_cop = np.array([-local_torque[1] / local_force[2],
                                  local_torque[0] / local_force[2], 0.0])
            cop = sole_position + sole_rotation @ local_cop
        else:
            cop = np.full(3, np.nan)
        return FootForceTorque(sensor_force, sensor_torque, ground_force, ground_torque, cop,
                               in_contact)

    def _foot_contacts(self) -> list:
        """Return per foot the contact points (n, 3) and the forces on the foot (n, 3), world.

        getContactPoints with bodyA = the robot reports the normal on the other body pointing to
        the robot, but not its friction on the robot: against the static ground, terrain and
        obstacles the reported friction is the one on the other body (PyBullet keeps its internal
        pair order), so the robot feels its opposite (a test pushes a robot to check the sign).
        """
        points, forces = ([], []), ([], [])
        for contact in pybullet.getContactPoints(bodyA=self._robot,
                                                 physicsClientId=self._client):
            side = self._foot_side.get(contact[3])
            if side is None or contact[2] == self._robot:
                continue
            points[side].append(contact[5])
            forces[side].append(contact[9] * np.asarray(contact[7])
                                - contact[10] * np.asarray(contact[11])
                                - contact[12] * np.asarray(contact[13]))
        return [(np.array(p, dtype=float).reshape(-1, 3), np.array(f, dtype=float).reshape(-1, 3))
                for p, f in zip(points, forces)]

    def _contact_normal_forces(self) -> list:
        """Return the vertical ground force on each foot from its contact points (N)."""
        normal = [0.0, 0.0]
        for contact in pybullet.getContactPoints(bodyA=self._robot,
                                                 physicsClientId=self._client):
            side = self._foot_side.get(contact[3])
            if side is not None and contact[2] != self._robot:
                normal[side] += contact[9] * contact[7][2]
        return normal

    def _contact_foot_readings(self, links) -> list:
        """Foot readings of a robot without F/T joints: a virtual sensor at each sole frame."""
        feet = []
        for side, (points, forces) in enumerate(self._foot_contacts()):
            sole = self._sole_index[side]
            sole_position = np.array(links[sole][4])
            sole_rotation = _rotation(links[sole][5])
            ground_force = forces.sum(axis=0)
            ground_torque = _cross(points - sole_position, forces).sum(axis=0)
            feet.append(self._ground_reading(
                sole_rotation.T @ ground_force, sole_rotation.T @ ground_torque, ground_force,
                ground_torque, sole_position, sole_rotation))
        return feet

    # ----------------------------------------------------------------------------- scenery
    def add_terrain(self, terrain: Terrain, colour_bins: int = 8) -> list:
        """Build the tiles of a terrain as static boxes, coloured by height.

        Tiles are grouped by height into colour_bins colours, blue for the lowest to red for the
        highest, as static bodies of at most MAX_SHAPES_PER_BODY tiles (one compound shape each). Later resets stand the robot
        on the terrain.

        :param terrain: the generated terrain.
        :param colour_bins: number of height colours, >= 1.
        :return: the PyBullet body ids.
        """
        self._check_open()
        if not (isinstance(colour_bins, int) and colour_bins >= 1):
            raise ConfigError('colour_bins = %r must be an int >= 1' % (colour_bins,))
        heights = terrain.heights.ravel()
        centres = terrain.tile_centres()
        low, high = terrain.params.min_height, terrain.params.max_height
        span = max(high - low, 1e-9)
        bins = np.minimum(((heights - low) / span * colour_bins).astype(int), colour_bins - 1)
        half_side = 0.5 * terrain.tile_side
        ids = []
        for b in range(colour_bins):
            members = np.flatnonzero(bins == b)
            if members.size == 0:
                continue
            level = (b + 0.5) / colour_bins
            colour = [level, 0.3, 1.0 - level, 1.0]
            # createVisualShapeArray crashes PyBullet 3.2.7 beyond 16 shapes: bodies of 16.
            for chunk in np.array_split(members, -(-members.size // MAX_SHAPES_PER_BODY)):
                half_extents = [[half_side, half_side, 0.5 * heights[k]] for k in chunk]
                frames = [[centres[k, 0], centres[k, 1], 0.5 * heights[k]] for k in chunk]
                ids.append(self._static_compound(half_extents, frames, colour))
        self._terrain = terrain
        self._scenery.extend(ids)
        return ids

    def _static_compound(self, half_extents: list, frames: list, colour: list) -> int:
        client = self._client
        count = len(half_extents)
        collision = pybullet.createCollisionShapeArray(
            shapeTypes=[pybullet.GEOM_BOX] * count, halfExtents=half_extents,
            collisionFramePositions=frames, physicsClientId=client)
        visual = pybullet.createVisualShapeArray(
            shapeTypes=[pybullet.GEOM_BOX] * count, halfExtents=half_extents,
            visualFramePositions=frames, rgbaColors=[colour] * count, physicsClientId=client)
        body = pybullet.createMultiBody(0.0, collision, visual, [0.0, 0.0, 0.0],
                                        physicsClientId=client)
        pybullet.changeDynamics(body, -1, lateralFriction=self._config.foot_friction,
                                physicsClientId=client)
        return body

    def add_obstacles(self, obstacles) -> list:
        """Add static obstacles from a planner-like list of boxes and discs.

        :param obstacles: BoxObstacle, DiscObstacle or duck-typed equivalents
            (biped_sim.obstacles.as_sim_obstacle).
        :return: the PyBullet body ids, one per obstacle.
        """
        self._check_open()
        client, ids = self._client, []
        for item in obstacles:
            obstacle = as_sim_obstacle(item)
            if isinstance(obstacle, BoxObstacle):
                half = [0.5 * obstacle.size_x, 0.5 * obstacle.size_y, 0.5 * obstacle.height]
                collision = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=half,
                                                          physicsClientId=client)
                visual = pybullet.createVisualShape(pybullet.GEOM_BOX, halfExtents=half,
                                                    rgbaColor=[0.6, 0.4, 0.3, 1.0],
                                                    physicsClientId=client)
                yaw = obstacle.yaw
            else:
                collision = pybullet.createCollisionShape(
                    pybullet.GEOM_CYLINDER, radius=obstacle.radius, height=obstacle.height,
                    physicsClientId=client)
                visual = pybullet.createVisualShape(
                    pybullet.GEOM_CYLINDER, radius=obstacle.radius, length=obstacle.height,
                    rgbaColor=[0.3, 0.5, 0.6, 1.0], physicsClientId=client)
                yaw = 0.0
            body = pybullet.createMultiBody(
                0.0, collision, visual, [obstacle.x, obstacle.y, 0.5 * obstacle.height],
                pybullet.getQuaternionFromEuler([0.0, 0.0, yaw]), physicsClientId=client)
            ids.append(body)
        self._scenery.extend(ids)
        return ids

    def clear_scenery(self) -> None:
        """Remove every terrain tile and obstacle added so far."""
        self._check_open()
        for body in self._scenery:
            pybullet.removeBody(body, physicsClientId=self._client)
        self._scenery = []
        self._terrain = None

    # ----------------------------------------------------------------------------- camera
    def render(self, view: CameraView = CameraView()) -> np.ndarray:
        """Render a camera frame with the tiny software renderer (no GPU needed).

        :param view: camera placement and image size.
        :return: (height, width, 3) uint8 RGB image.
        """
        self._check_open()
        client = self._client
        target = view.target
        if target is None:
            target = self._base_frame_pose()[0].tolist()
        view_matrix = pybullet.computeViewMatrixFromYawPitchRoll(
            target, view.distance, view.yaw, view.pitch, 0.0, 2, physicsClientId=client)
        projection = pybullet.computeProjectionMatrixFOV(
            view.fov, view.width / view.height, 0.02, 50.0, physicsClientId=client)
        image = pybullet.getCameraImage(view.width, view.height, view_matrix, projection,
                                        renderer=pybullet.ER_TINY_RENDERER,
                                        physicsClientId=client)[2]
        rgba = np.asarray(image, dtype=np.uint8).reshape(view.height, view.width, 4)
        return rgba[:, :, :3].copy()

    # ----------------------------------------------------------------------------- lifetime
    def _check_open(self) -> None:
        if self._closed:
            raise ConfigError('the PyBullet backend is closed')

    def close(self) -> None:
        """Disconnect from PyBullet; the backend is unusable afterwards."""
        if not self._closed:
            pybullet.disconnect(physicsClientId=self._client)
            self._closed = True

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown may have unloaded pybullet
            pass
