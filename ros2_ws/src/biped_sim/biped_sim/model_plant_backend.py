"""The three-mass model plant behind the SimulatorBackend interface (the paper's MATLAB robot).

The rest of the stack (closed-loop runner, nodes) runs unchanged on this backend or on PyBullet.
The robot is biped_sim.model_plant.ModelPlant: three point masses per plane (left leg, torso,
right leg) at constant heights, driven by piecewise-constant jerks and exactly integrated, with
an external force on the torso. How joint setpoints become plant inputs:

1. Forward kinematics of the 12 leg setpoints (biped_mpc.leg_kinematics, the description's
   LegGeometry) gives each sole relative to the pelvis (position, heading).
2. A foot is on the ground when its setpoint height (pelvis at pelvis_height above the ground
   plus the relative sole height) is at most contact_height; it is then held where the plant's
   swing put it (latched at touch-down, as a real foot that does not slip).
3. The pelvis target is where the stance feet put it: latched sole minus its relative position,
   averaged over the feet on the ground (the previous target when none is); the heading
   likewise. The model hip (torso mass target) is pelvis + R(yaw) com_offset, a swinging foot's
   target is pelvis target + its relative position, and each leg mass target is midway between
   its foot target and the model hip (section "Masses Reference Trajectories").
4. Each mass follows its target trajectory with a jerk, like a stiff joint servo
   (:mod:`biped_sim.model_plant_servo`: feed-forward of the cubic through its last four
   targets plus a state feedback with every closed-loop eigenvalue at servo_pole).
5. The plant integrates each physics step with the jerks and the push force on the torso held.

Sensors are synthesised: joint positions are the leg IK of the plant's pelvis and soles (equal
to the setpoints when the plant is on its targets), velocities their finite difference, torques
zero; the base is the torso mass minus com_offset at constant height, with the heading
of the stance feet; soles: stance feet where they are held, swinging feet at 2 * leg mass -
model hip with their setpoint height; the ZMP is the plant's real ZMP (its fictitious ZMP
clipped to the box of the feet on the ground); each foot's F/T shares the weight by the lever
rule between the soles and reports the ZMP as its centre of pressure; the IMU reports the
heading, no rotation rate and the torso's acceleration plus gravity.
"""
from dataclasses import dataclass
import math
from typing import Optional

import numpy as np

from biped_mpc.leg_ik import AnalyticLegIk
from biped_mpc.leg_kinematics import LegKinematics
from biped_mpc.linear_model import N_PLANES, N_STATES, POSITION, state_index
from biped_mpc.three_mass_model import three_mass_model, ThreeMassParams
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.rotations import quaternion_from_yaw, rotation_z, yaw_of_matrix
from biped_planner.sides import LEFT, RIGHT, SIDES

from biped_sim.backend import SimulatorBackend
from biped_sim.contact_gravity_compensation import left_share
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.model_plant import ModelPlant, PlantParams, TorsoPushes
from biped_sim.model_plant_servo import MASSES, MassServo, TORSO
from biped_sim.robot_builder import COMAN_LIKE_MODEL
from biped_sim.robot_description import RobotDescription
from biped_sim.sensors import (BaseState, FootForceTorque, ImuReading, JointReadings,
                               SensorReadings)
from biped_sim.validation import finite_array, finite_number, number_tuple, substep_count

_LEG_MASS = (0, 2)  # the leg mass of each side in the plant's state layout


@dataclass(frozen=True)
class ModelPlantBackendParams:
    """Parameters of the model-plant backend; the robot's numbers default to the COMAN-like
    robot's model file (biped_mpc/robots/coman_like.yaml).

    :param masses: masses and heights of the three-mass robot (kg, m)
    :param com_offset: model hip (torso mass) relative to the pelvis in its heading frame
        (forward, left) (m), each in [-0.5, 0.5]; equal to the controller's com_offset
    :param noise: measurement noise of the plant's outputs (m); only the ZMP uses it here
    :param servo_pole: eigenvalue of each mass's tracking error per control period, [0, 1):
        0 is deadbeat (three calls of step), closer to 1 is softer and slower; a call shorter
        than the period uses servo_pole ** (its duration / period)
    """

    masses: ThreeMassParams = COMAN_LIKE_MODEL.masses
    time_step: float = parameter(0.001, 'physics step (s)', low=0.0, high=0.1, low_open=True)
    control_substeps: int = parameter(20, 'physics steps per control period', low=1)
    pelvis_height: float = parameter(COMAN_LIKE_MODEL.pelvis_height, 'height of the pelvis '
                                     'frame above the ground (m)', low=0.0, high=5.0,
                                     low_open=True)
    com_offset: tuple = parameter(COMAN_LIKE_MODEL.com_offset, 'model hip relative to the '
                                  'pelvis in its heading frame, forward and left (m)', low=-0.5,
                                  high=0.5)
    contact_height: float = parameter(0.002, 'a sole at most this high is on the ground (m)',
                                      low=0.0, high=0.1, low_open=True)
    noise: PlantParams = PlantParams()
    gravity: float = parameter(9.81, 'gravity (m/s^2)', low=0.0, high=30.0, low_open=True)
    servo_pole: float = parameter(0.5, "eigenvalue of each mass's tracking error per control "
                                  'period (1), below 1', low=0.0, high=1.0)
    feed_forward: bool = parameter(True, 'add the jerk of the cubic through the last four '
                                   'targets')

    def __post_init__(self) -> None:
        object.__setattr__(self, 'com_offset',
                           number_tuple('ModelPlantBackendParams.com_offset', self.com_offset, 2))
        validate_fields(self, ConfigError)
        if self.servo_pole >= 1.0:
            raise ConfigError(f'ModelPlantBackendParams.servo_pole must be below 1, got '
                              f'{self.servo_pole!r}')
        for name, kind in (('masses', ThreeMassParams), ('noise', PlantParams)):
            if not isinstance(getattr(self, name), kind):
                raise ConfigError(f'ModelPlantBackendParams.{name} must be {kind.__name__}, got '
                                  f'{type(getattr(self, name)).__name__}')


class ModelPlantBackend(SimulatorBackend):
    """The three-mass model plant as a simulated robot (see the module docstring).

    :param description: the robot (leg joints and LegGeometry for the forward kinematics)
    :param params: backend parameters
    :raises ConfigError: if the description has no leg geometry
    """

    def __init__(self, description: RobotDescription,
                 params: ModelPlantBackendParams = ModelPlantBackendParams()) -> None:
        if description.leg_geometry is None:
            raise ConfigError(f'{description.name} has no leg_geometry: the model-plant backend '
                              f'needs the analytic leg kinematics')
        if not isinstance(params, ModelPlantBackendParams):
            raise ConfigError(f'params must be ModelPlantBackendParams, not {params!r}')
        self._description = description
        self._params = params
        self._kinematics = LegKinematics(description.leg_geometry)
        self._ik = AnalyticLegIk(description.leg_geometry)
        self._model = three_mass_model(params.masses)
        self._plant = ModelPlant(self._model, params.noise)
        self._step = params.time_step
        self._period = params.time_step * params.control_substeps
        self._pushes = TorsoPushes(self._step)
        self._servo = MassServo(self._model, self._period, self._step, params.servo_pole,
                                params.feed_forward)
        self._last_duration = self._period
        self._com_row = self._model.com_row
        self._offset = np.array(params.com_offset)
        m = params.masses
        masses = np.array([m.left_leg_mass, m.torso_mass, m.right_leg_mass])
        heights = np.array([m.left_leg_height, m.torso_height, m.right_leg_height])
        self._weight = float(masses.sum()) * params.gravity
        self._com_height = float(masses @ heights / masses.sum())
        self.reset()

    # ----------------------------------------------------------------------------- properties
    @property
    def joint_names(self) -> tuple:
        """The 12 leg joints (the model has no upper body joints)."""
        return self._description.leg_joint_names

    @property
    def leg_joint_names(self) -> tuple:
        """The 12 leg joints."""
        return self._description.leg_joint_names

    @property
    def time(self) -> float:
        """Simulated time since the last reset (s)."""
        return self._count * self._step

    @property
    def time_step(self) -> float:
        """Physics step (s)."""
        return self._step

    @property
    def description(self) -> RobotDescription:
        """The robot."""
        return self._description

    @property
    def plant(self) -> ModelPlant:
        """The underlying model plant (its true state, for tests and plots)."""
        return self._plant

    # ----------------------------------------------------------------------------- reset
    def reset(self, base_position: Optional[np.ndarray] = None, base_yaw: float = 0.0,
              joint_positions: Optional[dict] = None) -> SensorReadings:
        """Stand still with the feet on the ground below the nominal (or given) leg pose.

        :param base_position: (3,) pelvis position; only x and y are used (the pelvis height
            is params.pelvis_height); None puts it at the origin
        :param base_yaw: heading of the pelvis (rad)
        :param joint_positions: leg joint name -> angle overriding the nominal pose
        :return: the readings
        :raises ConfigError: for non-finite values or unknown joints
        """
        finite_number('base_yaw', base_yaw)
        position = (np.zeros(3) if base_position is None
                    else finite_array('base_position', base_position, (3,)))
        q = self._description.nominal_leg_positions()
        for name, angle in dict(joint_positions or {}).items():
            if name not in self.joint_names:
                raise ConfigError(f'joint_positions names an unknown joint {name!r}')
            if not math.isfinite(angle):
                raise ConfigError(f'joint_positions[{name!r}] = {angle!r} must be finite')
            q[self.joint_names.index(name)] = angle
        self._count = 0
        self._pushes.clear()
        self._q = q.copy()
        self._q_measured = q.copy()
        self._yaw = float(base_yaw)
        pelvis = np.array([position[0], position[1], self._params.pelvis_height])
        relative = self._relative_soles(q, self._yaw)
        self._held = [None, None]
        for side in SIDES:
            sole = pelvis + relative[side][0]
            self._held[side] = np.array([sole[0], sole[1], self._yaw + relative[side][1]])
        hip = pelvis[:2] + self._heading(self._yaw) @ self._offset
        state = np.zeros((N_PLANES, N_STATES))
        for mass, target in zip(MASSES, self._mass_targets(hip, pelvis, relative)):
            state[:, state_index(mass, POSITION)] = target
        self._plant.reset(state)
        self._servo.reset(state[:, [state_index(m, POSITION) for m in MASSES]])
        self._pelvis_target = pelvis
        self._set_support()
        return self.sensors()

    # ----------------------------------------------------------------------------- kinematics
    @staticmethod
    def _heading(yaw: float) -> np.ndarray:
        """(2, 2) rotation of the heading yaw in the ground plane."""
        return rotation_z(yaw)[:2, :2]

    def _relative_soles(self, q: np.ndarray, yaw: float) -> tuple:
        """Each sole relative to the pelvis (position (3,) in world axes, relative heading)."""
        left_p, left_r, right_p, right_r = self._kinematics.forward(q, np.zeros(3),
                                                                    rotation_z(yaw))
        return ((np.asarray(left_p), yaw_of_matrix(left_r) - yaw),
                (np.asarray(right_p), yaw_of_matrix(right_r) - yaw))

    def _mass_targets(self, hip: np.ndarray, pelvis: np.ndarray, relative: tuple) -> tuple:
        """Targets (2,) of the left leg, torso and right leg masses."""
        feet = []
        for side in SIDES:
            if self._held[side] is not None and self._on_ground(relative[side][0]):
                feet.append(self._held[side][:2])
            else:
                feet.append(pelvis[:2] + relative[side][0][:2])
        return 0.5 * (feet[LEFT] + hip), hip, 0.5 * (feet[RIGHT] + hip)

    def _on_ground(self, relative_sole: np.ndarray) -> bool:
        return bool(self._params.pelvis_height + relative_sole[2] <= self._params.contact_height)

    # ----------------------------------------------------------------------------- stepping
    def step(self, joint_setpoints: np.ndarray, n_substeps: Optional[int] = None,
             joint_velocities: Optional[np.ndarray] = None,
             read_sensors: bool = True) -> Optional[SensorReadings]:
        """Drive the masses towards the pose of the leg setpoints for n_substeps steps.

        :param joint_setpoints: (12,) leg angles (rad)
        :param n_substeps: physics steps, >= 1; None runs a control period
        :param joint_velocities: ignored (the plant follows positions), same shape if given
        :param read_sensors: read the sensors at the end (False: return None, to save the
            readout of an intermediate part of a period).
        :return: the readings at the end
        :raises ConfigError: for a wrong shape, NaN/inf or n_substeps < 1
        """
        n = substep_count(n_substeps, self._params.control_substeps)
        q = finite_array('joint_setpoints', joint_setpoints, (12,))
        if joint_velocities is not None:
            finite_array('joint_velocities', joint_velocities, (12,))
        self._q = q.copy()
        relative = self._relative_soles(q, self._yaw)
        self._update_contacts(relative)
        pelvis = self._pelvis_from_feet(relative)
        hip = pelvis[:2] + self._heading(self._yaw) @ self._offset
        targets = np.stack(self._mass_targets(hip, pelvis, relative), axis=1)  # (2, 3)
        self._last_duration = n * self._step
        jerk = self._servo.jerk(targets, self._plant.state, self._last_duration)
        for _ in range(int(n)):
            force = self._pushes.force(self._count)
            self._plant.step(jerk, self._step, force if np.any(force) else None)
            self._count += 1
        self._pelvis_target = pelvis
        self._set_support()
        return self.sensors() if read_sensors else None

    def _update_contacts(self, relative: tuple) -> None:
        """Latch a sole that reaches the ground where its swing put it; release a lifted one."""
        state = self._plant.state
        hip = state[:, state_index(TORSO, POSITION)]
        for side, mass in zip(SIDES, _LEG_MASS):
            if not self._on_ground(relative[side][0]):
                self._held[side] = None
            elif self._held[side] is None:
                foot = 2.0 * state[:, state_index(mass, POSITION)] - hip
                self._held[side] = np.array([foot[0], foot[1], self._yaw + relative[side][1]])

    def _pelvis_from_feet(self, relative: tuple) -> np.ndarray:
        anchors, yaws = [], []
        for side in SIDES:
            if self._held[side] is not None:
                anchors.append(self._held[side][:2] - relative[side][0][:2])
                yaws.append(self._held[side][2] - relative[side][1])
        if not anchors:
            return self._pelvis_target.copy()
        self._yaw = float(math.atan2(np.mean(np.sin(yaws)), np.mean(np.cos(yaws))))
        xy = np.mean(anchors, axis=0)
        return np.array([xy[0], xy[1], self._params.pelvis_height])

    def _set_support(self) -> None:
        """Give the plant the box of the feet on the ground for its real ZMP."""
        corners = []
        half = 0.5 * np.array([self._description.sole_length, self._description.sole_width])
        for side in SIDES:
            held = self._held[side]
            if held is None:
                continue
            c, s = abs(math.cos(held[2])), abs(math.sin(held[2]))
            extent = np.array([half[0] * c + half[1] * s, half[0] * s + half[1] * c])
            corners.extend([held[:2] - extent, held[:2] + extent])
        if corners:
            corners = np.array(corners)
            self._plant.set_support_polygon(corners.min(axis=0), corners.max(axis=0))
        else:
            self._plant.set_support_polygon(np.full(2, -np.inf), np.full(2, np.inf))

    # ----------------------------------------------------------------------------- pushes
    def push(self, push: ExternalPush) -> None:
        """Schedule a push; its horizontal force acts on the torso mass (link is ignored).

        :param push: the push
        """
        self._pushes.add(push, self._count)

    # ----------------------------------------------------------------------------- sensing
    def sensors(self) -> SensorReadings:
        """Synthesised readings of the current state (see the module docstring)."""
        measurement = self._plant.measure()
        state = measurement.state
        params = self._params
        hip = state[:, state_index(TORSO, POSITION)]
        heading = self._heading(self._yaw)
        pelvis = np.array([*(hip - heading @ self._offset), params.pelvis_height])
        torso_velocity = state[:, state_index(TORSO, POSITION) + 1]
        torso_acceleration = state[:, state_index(TORSO, POSITION) + 2]
        relative = self._relative_soles(self._q, self._yaw)
        soles = []
        for side, mass in zip(SIDES, _LEG_MASS):
            if self._held[side] is not None:
                xy = self._held[side][:2]
            else:
                xy = 2.0 * state[:, state_index(mass, POSITION)] - hip
            soles.append(np.array([xy[0], xy[1], params.pelvis_height + relative[side][0][2]]))
        zmp = np.asarray(measurement.zmp_real, dtype=float)
        if params.noise.noise_std > 0.0:
            zmp = zmp + (measurement.outputs[:, 2] - measurement.true_outputs[:, 2])
        feet = self._feet(zmp, soles)
        if not (feet[0].in_contact or feet[1].in_contact):
            zmp = np.full(2, np.nan)
        orientation = quaternion_from_yaw(self._yaw)
        yaw_rotation = np.eye(3)
        yaw_rotation[:2, :2] = heading
        acceleration = np.array([torso_acceleration[0], torso_acceleration[1], params.gravity])
        imu = ImuReading(orientation, np.zeros(3), yaw_rotation.T @ acceleration)
        q = self._measured_joints(pelvis, soles, relative)
        joints = JointReadings(self.joint_names, q, (q - self._q_measured) / self._last_duration,
                               np.zeros(12))
        self._q_measured = q
        base = BaseState(pelvis, orientation, np.array([*torso_velocity, 0.0]), np.zeros(3))
        com = np.array([*(state @ self._com_row), self._com_height])
        com_velocity = np.array([*(state @ np.roll(self._com_row, 1)), 0.0])
        return SensorReadings(self.time, joints, imu, feet[LEFT], feet[RIGHT], zmp, base,
                              soles[LEFT], soles[RIGHT], com, com_velocity)

    def _measured_joints(self, pelvis: np.ndarray, soles: list, relative: tuple) -> np.ndarray:
        """Leg angles of the plant's pose: IK of the pelvis and the soles where they are."""
        rotation = np.eye(3)
        rotation[:2, :2] = self._heading(self._yaw)
        poses = []
        for side in SIDES:
            yaw = self._held[side][2] if self._held[side] is not None \
                else self._yaw + relative[side][1]
            foot = np.eye(3)
            foot[:2, :2] = self._heading(yaw)
            poses.extend([soles[side], foot])
        return np.asarray(self._ik.solve(pelvis, rotation, *poses).q, dtype=float)

    def _feet(self, zmp: np.ndarray, soles: list) -> tuple:
        """F/T readings: the weight shared by the lever rule, the ZMP as centre of pressure."""
        in_contact = [self._held[side] is not None for side in SIDES]
        share = np.array([float(c) for c in in_contact])
        if all(in_contact):
            t = float(left_share(zmp, soles[LEFT], soles[RIGHT]))
            share = np.array([t, 1.0 - t])
        feet = []
        for side in SIDES:
            force = np.array([0.0, 0.0, share[side] * self._weight])
            cop = np.array([zmp[0], zmp[1], soles[side][2]]) if in_contact[side] \
                else np.full(3, np.nan)
            feet.append(FootForceTorque(force.copy(), np.zeros(3), force, np.zeros(3), cop,
                                        in_contact[side]))
        return tuple(feet)
