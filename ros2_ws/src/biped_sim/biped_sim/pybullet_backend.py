"""PyBullet simulator backend: a humanoid on the ground, torque- or position-controlled.

Physics runs at a fixed step (1 kHz by default) with manual stepping. The backend loads the
robot's URDF and composes the parts of the simulation, one concept each:

- :mod:`biped_sim.pybullet_config`: the parameters;
- :mod:`biped_sim.pybullet_robot_index`: the description's joints, links and feet in PyBullet;
- :mod:`biped_sim.pybullet_joint_control`: the torque law (capped explicit PD plus gravity
  compensation) or PyBullet's position motors;
- :mod:`biped_sim.pybullet_sensing`: encoders, IMU, ankle F/T sensors (or foot contacts) and
  ground truth;
- :mod:`biped_sim.pybullet_scenery`: terrain, obstacles and the camera.

Here remain the lifetime, the reset to a standing pose, the stepping and the pushes, applied
at every physics step they last as a world-frame force at a point of a link.
"""

import math
from typing import Optional

import numpy as np

from biped_planner.rotations import quaternion_to_matrix

from biped_sim.backend import SimulatorBackend
from biped_sim.camera_view import CameraView
from biped_sim.contact_gravity_compensation import ContactGravityCompensation
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.pybullet_config import PyBulletConfig
from biped_sim.pybullet_joint_control import PyBulletJointControl
from biped_sim.pybullet_robot_index import index_robot
from biped_sim.pybullet_scenery import PyBulletScenery, render
from biped_sim.pybullet_sensing import PyBulletSensing
from biped_sim.robot_description import RobotDescription
from biped_sim.sensors import SensorReadings
from biped_sim.terrain import Terrain
from biped_sim.validation import finite_array, substep_count

try:
    import pybullet
    import pybullet_data
except ImportError as error:  # pragma: no cover - pybullet is a hard dependency of biped_sim
    raise ImportError('biped_sim.pybullet_backend needs pybullet (Python <= 3.11 wheels): '
                      'pip install pybullet==3.2.7') from error

_SPAWN_CLEARANCE = 5e-4  # m between the lowest sole and the ground at reset


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
        config, description, client = self._config, self._description, self._client
        self._dt = config.time_step
        self._terrain: Optional[Terrain] = None
        self._pushes: list = []
        self._step_count = 0
        self._period_starts = True  # the next step starts the IMU's averaging interval
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
        self._index = index_robot(client, self._robot, description, config.foot_friction,
                                  config.sole_contact_stiffness, config.sole_contact_damping)
        self._sensing = PyBulletSensing(client, self._robot, self._index, config.gravity,
                                        config.contact_threshold)
        compensation = ContactGravityCompensation(
            description.urdf_path, self._index.joint_names, description.sole_frames,
            description.sole_length, description.sole_width, config.gravity)
        self._joints = PyBulletJointControl(client, self._robot, self._index, config,
                                            compensation, self._sensing,
                                            self._nominal_positions({}))
        self._scenery = PyBulletScenery(client, config.foot_friction)
        self.reset()

    def _nominal_positions(self, overrides: dict) -> np.ndarray:
        nominal = dict(self._description.nominal_joint_positions)
        unknown = [n for n in overrides if n not in self._index.joint_names]
        if unknown:
            raise ConfigError('joint_positions names unknown joints %r' % (unknown,))
        nominal.update(overrides)
        q = np.array([nominal.get(n, 0.0) for n in self._index.joint_names], dtype=float)
        if not np.all(np.isfinite(q)):
            raise ConfigError('joint_positions %r has NaN or inf' % (overrides,))
        return q

    # ----------------------------------------------------------------------------- properties
    @property
    def joint_names(self) -> tuple:
        """Actuated joints: the 12 leg joints first, then the others in URDF order."""
        return self._index.joint_names

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
        return self._index.total_mass

    @property
    def joint_gains(self) -> tuple:
        """(Kp, Kd) of the actuated joints in torque mode after the stability cap."""
        return self._joints.kp.copy(), self._joints.kd.copy()

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
            position = finite_array('base_position', base_position, (3,))
        self._set_base_pose(position, orientation)
        for j, angle in zip(self._index.actuated, q):
            pybullet.resetJointState(robot, int(j), float(angle), 0.0, physicsClientId=client)
        if base_position is None:
            position[2] += self._ground_clearance_shift()
            self._set_base_pose(position, orientation)
        pybullet.resetBaseVelocity(robot, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0],
                                   physicsClientId=client)
        self._step_count = 0
        self._pushes = []
        self._joints.reset(q)
        self._sensing.mark_imu_velocity(0)
        self._period_starts = True
        return self.sensors()

    def _set_base_pose(self, position: np.ndarray, orientation) -> None:
        index = self._index
        com_position, com_orientation = pybullet.multiplyTransforms(
            position.tolist(), orientation, index.base_inertial_position.tolist(),
            index.base_inertial_orientation, physicsClientId=self._client)
        pybullet.resetBasePositionAndOrientation(self._robot, com_position, com_orientation,
                                                 physicsClientId=self._client)

    def _ground_clearance_shift(self) -> float:
        """Return how much to raise the base so the soles rest on the ground or terrain."""
        shift = -np.inf
        half = 0.5 * np.array([self._description.sole_length, self._description.sole_width])
        corners = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1], [0, 0]]) * half
        for link in self._index.soles:
            state = pybullet.getLinkState(self._robot, link, computeForwardKinematics=1,
                                          physicsClientId=self._client)
            position, rotation = np.array(state[4]), quaternion_to_matrix(state[5])
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
        n = substep_count(n_substeps, self._config.control_substeps)
        q_des = np.asarray(joint_setpoints, dtype=float)
        n_joints = len(self._index.joint_names)
        if q_des.shape not in ((12,), (n_joints,)):
            raise ConfigError('joint_setpoints has shape %s, expected (12,) or (%d,)'
                              % (q_des.shape, n_joints))
        if not np.all(np.isfinite(q_des)):
            raise ConfigError('joint_setpoints %r has NaN or inf' % (joint_setpoints,))
        dq_des = None
        if joint_velocities is not None:
            dq_des = finite_array('joint_velocities', joint_velocities, q_des.shape)
        if self._period_starts:
            # The IMU averages from the step after the last readout: over the whole period when
            # the period is run in parts (biped_sim.joint_servo.step_toward), not its last part.
            self._sensing.mark_imu_velocity(self._step_count)
        self._period_starts = read_sensors
        joints = self._joints
        joints.set_setpoints(q_des, dq_des)
        torque_mode = joints.torque_mode
        for _ in range(int(n)):
            if torque_mode:
                joints.apply_torques(self._step_count)
            if self._pushes:
                self._apply_pushes()
            pybullet.stepSimulation(physicsClientId=self._client)
            self._step_count += 1
        return self.sensors() if read_sensors else None

    def sensors(self) -> SensorReadings:
        """Return the readings of the current state (see biped_sim.pybullet_sensing)."""
        self._check_open()
        torque = self._joints.last_torque if self._joints.torque_mode else None
        return self._sensing.read(self.time, self._step_count, self._dt, torque)

    # ----------------------------------------------------------------------------- pushes
    def push(self, push: ExternalPush) -> None:
        """Schedule an external push, applied at every physics step it lasts.

        :param push: the push; its start_time None starts it at the next physics step.
        :raises ConfigError: if the push names an unknown link.
        """
        self._check_open()
        link_name = push.link if push.link is not None else self._description.base_link
        if link_name not in self._index.link_index:
            raise ConfigError('push link %r is not a link of %s'
                              % (link_name, self._description.name))
        start, end = push.steps(self._step_count, self._dt)
        self._pushes.append((start, end, self._index.link_index[link_name],
                             np.array(push.point), list(push.force)))

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
                position, orientation = self._sensing.base_frame_pose()
            else:
                state = pybullet.getLinkState(robot, link, computeForwardKinematics=1,
                                              physicsClientId=client)
                position, orientation = np.array(state[4]), state[5]
            world_point = position + quaternion_to_matrix(orientation) @ point
            pybullet.applyExternalForce(robot, link, force, world_point.tolist(),
                                        pybullet.WORLD_FRAME, physicsClientId=client)
        self._pushes = active

    # ----------------------------------------------------------------------------- scenery
    def add_terrain(self, terrain: Terrain, colour_bins: int = 8) -> list:
        """Build a terrain's tiles (biped_sim.pybullet_scenery); later resets stand on it.

        :param terrain: the generated terrain.
        :param colour_bins: number of height colours, >= 1.
        :return: the PyBullet body ids.
        """
        self._check_open()
        ids = self._scenery.add_terrain(terrain, colour_bins)
        self._terrain = terrain
        return ids

    def add_obstacles(self, obstacles) -> list:
        """Add static obstacles, boxes and discs (biped_sim.pybullet_scenery).

        :param obstacles: BoxObstacle, DiscObstacle or duck-typed equivalents.
        :return: the PyBullet body ids, one per obstacle.
        """
        self._check_open()
        return self._scenery.add_obstacles(obstacles)

    def clear_scenery(self) -> None:
        """Remove every terrain tile and obstacle added so far."""
        self._check_open()
        self._scenery.clear()
        self._terrain = None

    def clear_terrain(self) -> None:
        """Remove the terrain's tiles; the obstacles stay."""
        self._check_open()
        self._scenery.clear_terrain()
        self._terrain = None

    def clear_obstacles(self) -> None:
        """Remove the obstacles; the terrain's tiles stay (a new map leaves the ground under
        the feet as it is)."""
        self._check_open()
        self._scenery.clear_obstacles()

    def render(self, view: CameraView = CameraView()) -> np.ndarray:
        """Render a camera frame (no GPU needed); a view without target follows the base.

        :param view: camera placement and image size.
        :return: (height, width, 3) uint8 RGB image.
        """
        self._check_open()
        return render(self._client, view, self._sensing.base_frame_pose()[0].tolist())

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
