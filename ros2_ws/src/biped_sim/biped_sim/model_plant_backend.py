"""The three-mass model plant behind the SimulatorBackend interface (the paper's MATLAB robot).

The rest of the stack (closed-loop runner, nodes) runs unchanged on this backend or on PyBullet.
The robot is biped_mpc.model_plant.ModelPlant: three point masses per plane (left leg, torso,
right leg) at constant heights, driven by piecewise-constant jerks and exactly integrated, with
an external force on the torso. How joint setpoints become plant inputs:

1. Forward kinematics of the 12 leg setpoints (analytic, the description's LegGeometry) gives
   each sole relative to the pelvis (position, heading).
2. A foot is on the ground when its setpoint height (pelvis at pelvis_height above the ground
   plus the relative sole height) is at most contact_height; it is then held where the plant's
   swing put it (latched at touch-down, as a real foot that does not slip).
3. The pelvis target is where the stance feet put it: latched sole minus its relative position,
   averaged over the feet on the ground (the previous target when none is); the heading
   likewise. The model hip (torso mass target) is pelvis + R(yaw) com_offset, a swinging foot's
   target is pelvis target + its relative position, and each leg mass target is midway between
   its foot target and the model hip (section "Masses Reference Trajectories").
4. Each mass follows its target trajectory with a jerk, like a stiff joint servo: the cubic
   through its last four targets (of calls of equal duration) gives the target's jerk
   (feed-forward) and its state now (position, velocity, acceleration), and a state feedback
   K with every eigenvalue of A - B K at servo_pole (Ackermann) adds K (x_target - x). A
   cubic reproduces a constant jerk exactly, so a target that keeps its jerk is followed
   without error; the MPC changes its jerk every period, which the servo follows with a lag
   of a few periods (the plant is no copy of the controller's model). The jerk that only
   reaches the next target position (position deadbeat) is not used: it makes the velocity
   oscillate with a growing factor -2 per period.
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
from biped_mpc.linear_model import N_PLANES, N_STATES, POSITION, state_index
from biped_mpc.model_plant import ModelPlant, PlantParams
from biped_mpc.three_mass_model import three_mass_model, ThreeMassParams
from biped_sim.backend import SimulatorBackend
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.robot_description import RobotDescription
from biped_sim.sensors import (BaseState, FootForceTorque, ImuReading, JointReadings,
                               SensorReadings)

LEFT = 0
RIGHT = 1
_MASSES = (0, 1, 2)  # left leg, torso, right leg in the plant's state layout
_TORSO = 1


@dataclass(frozen=True)
class ModelPlantBackendParams:
    """Parameters of the model-plant backend.

    :param masses: masses and heights of the three-mass robot (kg, m); the COMAN-like
        numbers by default
    :param time_step: physics step (s), (0, 0.1]
    :param control_substeps: physics steps per control period, >= 1
    :param pelvis_height: height of the pelvis frame above the ground (m), (0, 5]
    :param com_offset: model hip (torso mass) relative to the pelvis in its heading frame
        (forward, left) (m), each in [-0.5, 0.5]; equal to the controller's com_offset
    :param contact_height: a sole at most this high is on the ground (m), (0, 0.1]
    :param noise: measurement noise of the plant's outputs (m); only the ZMP uses it here
    :param gravity: gravity (m/s^2), (0, 30]
    :param servo_pole: eigenvalue of each mass's tracking error per control period, [0, 1):
        0 is deadbeat (three calls of step), closer to 1 is softer and slower; a call shorter
        than the period uses servo_pole ** (its duration / period)
    :param feed_forward: add the jerk of the cubic through the last four targets
    """

    masses: ThreeMassParams = ThreeMassParams(
        left_leg_mass=6.65, torso_mass=17.65, right_leg_mass=6.65, left_leg_height=0.265,
        torso_height=0.672, right_leg_height=0.265)
    time_step: float = 0.001
    control_substeps: int = 20
    pelvis_height: float = 0.54
    com_offset: tuple = (0.0137, 0.0)
    contact_height: float = 0.002
    noise: PlantParams = PlantParams()
    gravity: float = 9.81
    servo_pole: float = 0.5
    feed_forward: bool = True

    def __post_init__(self) -> None:
        for name, value, low, high in (('time_step', self.time_step, 0.0, 0.1),
                                       ('pelvis_height', self.pelvis_height, 0.0, 5.0),
                                       ('contact_height', self.contact_height, 0.0, 0.1),
                                       ('gravity', self.gravity, 0.0, 30.0)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value) or not low < value <= high:
                raise ConfigError(f'ModelPlantBackendParams.{name} must be a finite number in '
                                  f'({low}, {high}], got {value!r}')
        if isinstance(self.control_substeps, bool) or not isinstance(self.control_substeps, int) \
                or self.control_substeps < 1:
            raise ConfigError(f'ModelPlantBackendParams.control_substeps must be an int >= 1, '
                              f'got {self.control_substeps!r}')
        offset = np.asarray(self.com_offset, dtype=float)
        if offset.shape != (2,) or not np.all(np.isfinite(offset)) \
                or np.any(np.abs(offset) > 0.5):
            raise ConfigError(f'ModelPlantBackendParams.com_offset must be 2 finite numbers in '
                              f'[-0.5, 0.5] m, got {self.com_offset!r}')
        object.__setattr__(self, 'com_offset', tuple(float(v) for v in offset))
        if not isinstance(self.masses, ThreeMassParams):
            raise ConfigError(f'ModelPlantBackendParams.masses must be ThreeMassParams, got '
                              f'{type(self.masses).__name__}')
        if isinstance(self.servo_pole, bool) or not isinstance(self.servo_pole, (int, float)) \
                or not 0.0 <= self.servo_pole < 1.0:
            raise ConfigError(f'ModelPlantBackendParams.servo_pole must be in [0, 1), got '
                              f'{self.servo_pole!r}')
        if not isinstance(self.feed_forward, bool):
            raise ConfigError(f'ModelPlantBackendParams.feed_forward must be a bool, got '
                              f'{self.feed_forward!r}')
        if not isinstance(self.noise, PlantParams):
            raise ConfigError(f'ModelPlantBackendParams.noise must be PlantParams, got '
                              f'{type(self.noise).__name__}')


def placement_gain(a: np.ndarray, b: np.ndarray, pole: float) -> np.ndarray:
    """State feedback K with every eigenvalue of A - B K at pole (Ackermann's formula).

    :param a: (n, n) discrete state matrix of one mass (a triple integrator)
    :param b: (n,) discrete input vector
    :param pole: the (repeated) closed-loop eigenvalue, in [0, 1)
    :return: (n,) gain
    """
    n = a.shape[0]
    controllability = np.column_stack([np.linalg.matrix_power(a, k) @ b for k in range(n)])
    last = np.zeros(n)
    last[-1] = 1.0
    shifted = a - pole * np.eye(n)
    return last @ np.linalg.solve(controllability, np.linalg.matrix_power(shifted, n))


def _quaternion_from_yaw(yaw: float) -> np.ndarray:
    return np.array([0.0, 0.0, math.sin(0.5 * yaw), math.cos(0.5 * yaw)])


def _yaw_of(rotation: np.ndarray) -> float:
    return math.atan2(rotation[1, 0], rotation[0, 0])


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
            raise ConfigError(f'params must be ModelPlantBackendParams, got '
                              f'{type(params).__name__}')
        self._description = description
        self._params = params
        self._kinematics = AnalyticLegIk(description.leg_geometry)
        self._model = three_mass_model(params.masses)
        self._plant = ModelPlant(self._model, params.noise)
        self._step = params.time_step
        self._period = params.time_step * params.control_substeps
        self._gains = {}
        self._last_duration = self._period
        self._com_row = self._model.com_row
        self._offset = np.array(params.com_offset)
        masses = np.array([params.masses.left_leg_mass, params.masses.torso_mass,
                           params.masses.right_leg_mass])
        heights = np.array([params.masses.left_leg_height, params.masses.torso_height,
                            params.masses.right_leg_height])
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
        if not (isinstance(base_yaw, (int, float)) and math.isfinite(base_yaw)):
            raise ConfigError(f'base_yaw = {base_yaw!r} must be finite')
        position = np.zeros(3) if base_position is None else np.asarray(base_position, float)
        if position.shape != (3,) or not np.all(np.isfinite(position)):
            raise ConfigError(f'base_position = {base_position!r} must be 3 finite numbers')
        q = self._description.nominal_leg_positions()
        for name, angle in dict(joint_positions or {}).items():
            if name not in self.joint_names:
                raise ConfigError(f'joint_positions names an unknown joint {name!r}')
            if not math.isfinite(angle):
                raise ConfigError(f'joint_positions[{name!r}] = {angle!r} must be finite')
            q[self.joint_names.index(name)] = angle
        self._count = 0
        self._pushes = []
        self._q = q.copy()
        self._q_measured = q.copy()
        self._yaw = float(base_yaw)
        pelvis = np.array([position[0], position[1], self._params.pelvis_height])
        relative = self._relative_soles(q, self._yaw)
        self._held = [None, None]
        for side in (LEFT, RIGHT):
            sole = pelvis + relative[side][0]
            self._held[side] = np.array([sole[0], sole[1], self._yaw + relative[side][1]])
        hip = pelvis[:2] + self._heading(self._yaw) @ self._offset
        state = np.zeros((N_PLANES, N_STATES))
        for mass, target in zip(_MASSES, self._mass_targets(hip, pelvis, relative)):
            state[:, state_index(mass, POSITION)] = target
        self._plant.reset(state)
        self._history = np.repeat(state[None, :, [state_index(m, POSITION) for m in _MASSES]],
                                  3, axis=0)
        self._pelvis_target = pelvis
        self._set_support()
        return self.sensors()

    # ----------------------------------------------------------------------------- kinematics
    @staticmethod
    def _heading(yaw: float) -> np.ndarray:
        c, s = math.cos(yaw), math.sin(yaw)
        return np.array([[c, -s], [s, c]])

    def _relative_soles(self, q: np.ndarray, yaw: float) -> tuple:
        """Each sole relative to the pelvis (position (3,) in world axes, relative heading)."""
        c, s = math.cos(yaw), math.sin(yaw)
        rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        left_p, left_r, right_p, right_r = self._kinematics.forward(q, np.zeros(3), rotation)
        return ((np.asarray(left_p), _yaw_of(left_r) - yaw),
                (np.asarray(right_p), _yaw_of(right_r) - yaw))

    def _mass_targets(self, hip: np.ndarray, pelvis: np.ndarray, relative: tuple) -> tuple:
        """Targets (2,) of the left leg, torso and right leg masses."""
        feet = []
        for side in (LEFT, RIGHT):
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
        n = self._params.control_substeps if n_substeps is None else n_substeps
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ConfigError(f'n_substeps = {n_substeps!r} must be an int >= 1')
        q = np.asarray(joint_setpoints, dtype=float)
        if q.shape != (12,) or not np.all(np.isfinite(q)):
            raise ConfigError(f'joint_setpoints must be 12 finite angles, got {joint_setpoints!r}')
        if joint_velocities is not None:
            velocities = np.asarray(joint_velocities, dtype=float)
            if velocities.shape != (12,) or not np.all(np.isfinite(velocities)):
                raise ConfigError('joint_velocities must be 12 finite speeds')
        self._q = q.copy()
        relative = self._relative_soles(q, self._yaw)
        self._update_contacts(relative)
        pelvis = self._pelvis_from_feet(relative)
        hip = pelvis[:2] + self._heading(self._yaw) @ self._offset
        targets = np.stack(self._mass_targets(hip, pelvis, relative), axis=1)  # (2, 3)
        self._last_duration = n * self._step
        jerk = self._tracking_jerk(targets, self._last_duration)
        for _ in range(int(n)):
            force = self._push_force()
            self._plant.step(jerk, self._step, force if np.any(force) else None)
            self._count += 1
        self._pelvis_target = pelvis
        self._set_support()
        return self.sensors() if read_sensors else None

    def _update_contacts(self, relative: tuple) -> None:
        """Latch a sole that reaches the ground where its swing put it; release a lifted one."""
        state = self._plant.state
        hip = state[:, state_index(_TORSO, POSITION)]
        for side, mass in ((LEFT, 0), (RIGHT, 2)):
            if not self._on_ground(relative[side][0]):
                self._held[side] = None
            elif self._held[side] is None:
                foot = 2.0 * state[:, state_index(mass, POSITION)] - hip
                self._held[side] = np.array([foot[0], foot[1], self._yaw + relative[side][1]])

    def _pelvis_from_feet(self, relative: tuple) -> np.ndarray:
        anchors, yaws = [], []
        for side in (LEFT, RIGHT):
            if self._held[side] is not None:
                anchors.append(self._held[side][:2] - relative[side][0][:2])
                yaws.append(self._held[side][2] - relative[side][1])
        if not anchors:
            return self._pelvis_target.copy()
        self._yaw = float(math.atan2(np.mean(np.sin(yaws)), np.mean(np.cos(yaws))))
        xy = np.mean(anchors, axis=0)
        return np.array([xy[0], xy[1], self._params.pelvis_height])

    def _tracking_jerk(self, targets: np.ndarray, duration: float) -> np.ndarray:
        """Jerks (2, 3) that follow the cubic through the last four targets of each mass."""
        history = np.concatenate([self._history, targets[None]], axis=0)  # (4, 2, 3)
        self._history = history[1:]
        h = duration
        p_minus2, p_minus1, p_now, p_next = history
        jerk_ff = (p_next - 3.0 * p_now + 3.0 * p_minus1 - p_minus2) / h ** 3
        acceleration = (p_next - 2.0 * p_now + p_minus1) / h ** 2
        velocity = (p_next - p_minus1) / (2.0 * h) - jerk_ff * h ** 2 / 6.0
        if not self._params.feed_forward:
            jerk_ff = np.zeros_like(jerk_ff)
        state = self._plant.state
        jerk = np.empty((N_PLANES, 3))
        for mass in _MASSES:
            block = slice(state_index(mass, POSITION), state_index(mass, POSITION) + 3)
            target = np.stack([p_now[:, mass], velocity[:, mass], acceleration[:, mass]], axis=1)
            jerk[:, mass] = jerk_ff[:, mass] + (target - state[:, block]) @ self._gain(h)
        return jerk

    def _gain(self, duration: float) -> np.ndarray:
        """Servo gain for calls of this duration, with the pole scaled to keep its time constant.

        The pole is servo_pole per control period, servo_pole ** (duration / period) per call.
        """
        key = round(duration / self._step)
        gain = self._gains.get(key)
        if gain is None:
            discrete = self._model.discretize(duration)
            block = slice(state_index(_TORSO, POSITION), state_index(_TORSO, POSITION) + 3)
            pole = self._params.servo_pole ** (duration / self._period)
            gain = placement_gain(discrete.a[block, block], discrete.b[block, _TORSO], pole)
            self._gains[key] = gain
        return gain

    def _set_support(self) -> None:
        """Give the plant the box of the feet on the ground for its real ZMP."""
        corners = []
        half = 0.5 * np.array([self._description.sole_length, self._description.sole_width])
        for side in (LEFT, RIGHT):
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
        start = self._count if push.start_time is None else int(round(push.start_time
                                                                      / self._step))
        end = start + max(1, int(round(push.duration / self._step)))
        self._pushes.append((start, end, np.array(push.force[:2], dtype=float)))

    def _push_force(self) -> np.ndarray:
        force = np.zeros(N_PLANES)
        for start, end, value in self._pushes:
            if start <= self._count < end:
                force += value
        return force

    # ----------------------------------------------------------------------------- sensing
    def sensors(self) -> SensorReadings:
        """Synthesised readings of the current state (see the module docstring)."""
        measurement = self._plant.measure()
        state = measurement.state
        params = self._params
        hip = state[:, state_index(_TORSO, POSITION)]
        heading = self._heading(self._yaw)
        pelvis = np.array([*(hip - heading @ self._offset), params.pelvis_height])
        torso_velocity = state[:, state_index(_TORSO, POSITION) + 1]
        torso_acceleration = state[:, state_index(_TORSO, POSITION) + 2]
        relative = self._relative_soles(self._q, self._yaw)
        soles = []
        for side, mass in ((LEFT, 0), (RIGHT, 2)):
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
        orientation = _quaternion_from_yaw(self._yaw)
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
        for side in (LEFT, RIGHT):
            yaw = self._held[side][2] if self._held[side] is not None \
                else self._yaw + relative[side][1]
            foot = np.eye(3)
            foot[:2, :2] = self._heading(yaw)
            poses.extend([soles[side], foot])
        return np.asarray(self._kinematics.solve(pelvis, rotation, *poses).q, dtype=float)

    def _feet(self, zmp: np.ndarray, soles: list) -> tuple:
        """F/T readings: the weight shared by the lever rule, the ZMP as centre of pressure."""
        in_contact = [self._held[side] is not None for side in (LEFT, RIGHT)]
        share = np.array([float(c) for c in in_contact])
        if all(in_contact):
            between = soles[LEFT][:2] - soles[RIGHT][:2]
            length = float(between @ between)
            t = 0.5 if length < 1e-12 else float(np.clip((zmp - soles[RIGHT][:2]) @ between
                                                         / length, 0.0, 1.0))
            share = np.array([t, 1.0 - t])
        feet = []
        for side in (LEFT, RIGHT):
            force = np.array([0.0, 0.0, share[side] * self._weight])
            cop = np.array([zmp[0], zmp[1], soles[side][2]]) if in_contact[side] \
                else np.full(3, np.nan)
            feet.append(FootForceTorque(force.copy(), np.zeros(3), force, np.zeros(3), cop,
                                        in_contact[side]))
        return tuple(feet)
