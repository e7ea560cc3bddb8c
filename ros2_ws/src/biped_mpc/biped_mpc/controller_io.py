"""What the walking controller takes in and gives out each cycle, as plain numpy."""
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np

from biped_mpc.controller_params import PELVIS_GROUND_TRUTH, PELVIS_IMU_KINEMATICS
from biped_mpc.errors import InputError
from biped_mpc.linear_model import N_PLANES
from biped_mpc.validation import finite_vector
from biped_planner.rotations import tilt_of_quaternion

# Bits of ControllerOutput.status; 0 means everything nominal.
STATUS_OK = 0
STATUS_MPC_FALLBACK = 1
STATUS_MPC_ERROR = 2
STATUS_REFERENCE_ERROR = 4
STATUS_IK_CLIPPED = 8
STATUS_IK_ERROR = 16


@dataclass(frozen=True)
class ControllerFeedback:
    """What the controller knows about the robot at the start of a cycle (plain numpy).

    :param leg_joint_positions: (12,) measured leg angles, the description's leg order (rad)
    :param pelvis_orientation: (4,) pelvis orientation quaternion (x, y, z, w), from the ground
        truth or the IMU (normalised here)
    :param zmp: (2,) ZMP from the ankle F/T sensors (m); NaN when no foot is in contact
    :param contacts: (2,) left and right foot contact flags of the F/T sensors
    :param pelvis_position: (3,) pelvis position (m), or None when it is to be estimated from
        the stance feet (pelvis_source 'imu_kinematics')
    :param pelvis_linear_velocity: (3,) pelvis velocity (m/s) or None (diagnostic only)
    :param foot_wrenches: (2, 6) left and right ankle F/T readings, as a real sensor gives
        them: the force (N) and torque about the sensor origin (N m) the foot exerts on the leg,
        in the sensor frame (parallel to the sole frame); None without F/T sensors (the
        stabilizer then falls back to the feed-forward cycle)
    :raises InputError: for wrong sizes, NaN or inf (NaN allowed in zmp only)
    """

    leg_joint_positions: np.ndarray
    pelvis_orientation: np.ndarray
    zmp: np.ndarray
    contacts: tuple
    pelvis_position: Optional[np.ndarray] = None
    pelvis_linear_velocity: Optional[np.ndarray] = None
    foot_wrenches: Optional[np.ndarray] = None

    def __post_init__(self) -> None:
        object.__setattr__(self, 'leg_joint_positions', finite_vector(
            'ControllerFeedback.leg_joint_positions', self.leg_joint_positions, 12))
        quaternion = finite_vector('ControllerFeedback.pelvis_orientation',
                                   self.pelvis_orientation, 4)
        norm = float(np.linalg.norm(quaternion))
        if norm < 1e-6:
            raise InputError(f'ControllerFeedback.pelvis_orientation = {quaternion.tolist()} '
                             f'is not a rotation')
        object.__setattr__(self, 'pelvis_orientation', quaternion / norm)
        object.__setattr__(self, 'zmp', finite_vector('ControllerFeedback.zmp', self.zmp, 2,
                                                      allow_nan=True))
        contacts = tuple(bool(c) for c in np.asarray(self.contacts).reshape(-1))
        if len(contacts) != 2:
            raise InputError(f'ControllerFeedback.contacts must be 2 flags, got '
                             f'{self.contacts!r}')
        object.__setattr__(self, 'contacts', contacts)
        for name, size in (('pelvis_position', 3), ('pelvis_linear_velocity', 3)):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, finite_vector(f'ControllerFeedback.{name}',
                                                             getattr(self, name), size))
        if self.foot_wrenches is not None:
            wrenches = finite_vector('ControllerFeedback.foot_wrenches',
                                     np.asarray(self.foot_wrenches, dtype=float).reshape(-1), 12)
            object.__setattr__(self, 'foot_wrenches', wrenches.reshape(2, 6))

    def standing_still(self, max_tilt: float, max_speed: float) -> bool:
        """Both feet in contact, the pelvis tilted less than max_tilt (rad) and, when its
        velocity is known, slower than max_speed (m/s)."""
        velocity = self.pelvis_linear_velocity
        return all(self.contacts) and tilt_of_quaternion(self.pelvis_orientation) < max_tilt \
            and (velocity is None or float(np.linalg.norm(velocity)) < max_speed)

    @classmethod
    def from_readings(cls, readings, pelvis_source: str = PELVIS_GROUND_TRUTH,
                      leg_joint_count: int = 12) -> 'ControllerFeedback':
        """Build the feedback from simulator readings (duck typed biped_sim SensorReadings).

        :param readings: object with joints.position (leg joints first), base, imu, zmp,
            left_foot and right_foot (in_contact; sensor_force and sensor_torque, when the
            robot has F/T sensors)
        :param pelvis_source: 'ground_truth' (base pose and velocity) or 'imu_kinematics'
            (IMU orientation, no position: the controller estimates it)
        :param leg_joint_count: number of leading joint readings that are the legs (12)
        :return: the feedback
        :raises InputError: for an unknown source or bad readings
        """
        legs = np.asarray(readings.joints.position, dtype=float)[:leg_joint_count]
        contacts = (readings.left_foot.in_contact, readings.right_foot.in_contact)
        feet = (readings.left_foot, readings.right_foot)
        wrenches = (np.array([np.concatenate([foot.sensor_force, foot.sensor_torque])
                              for foot in feet])
                    if all(hasattr(foot, 'sensor_force') for foot in feet) else None)
        if pelvis_source == PELVIS_GROUND_TRUTH:
            return cls(legs, readings.base.orientation, readings.zmp, contacts,
                       readings.base.position, readings.base.linear_velocity, wrenches)
        if pelvis_source == PELVIS_IMU_KINEMATICS:
            return cls(legs, readings.imu.orientation, readings.zmp, contacts,
                       foot_wrenches=wrenches)
        raise InputError(f'pelvis_source must be {PELVIS_GROUND_TRUTH!r} or '
                         f'{PELVIS_IMU_KINEMATICS!r}, got {pelvis_source!r}')


@dataclass(frozen=True)
class ControllerOutput:
    """Joint setpoints of one cycle and diagnostics (planes x then y on the leading axis).

    :param joint_setpoints: (12,) leg joint angles for the next period (rad)
    :param joint_velocities: (12,) setpoint speeds over the period (rad/s), feed-forward
    :param status: STATUS_* bits, STATUS_OK when nominal
    :param mpc_status: QP status per plane (QpStatus values)
    :param solve_time: time in the QP solver, both planes (s)
    :param state: (2, 9) the state the MPC started from
    :param kalman_state: (2, 9) the Kalman estimate x(k|k)
    :param zmp_measured: (2,) F/T ZMP (NaN without contact) (m)
    :param zmp_estimated: (2,) ZMP of the state the MPC used (m)
    :param zmp_predicted: (2,) ZMP the MPC predicts at t + Ts (m)
    :param measured_outputs: (2, 3) measured left leg mass, right leg mass, ZMP (m)
    :param ik_status: (left, right) IK_REACHABLE or IK_CLIPPED
    :param pelvis_target: (3,) pelvis position target: torso mass minus the COM offset (m)
    :param pelvis_command: (3,) the pelvis position the IK used: the target moved by the
        pelvis servo (m)
    :param hip_target: (2,) model hip (torso mass) target (m)
    :param left_foot_target: (4,) left sole x, y, z (m), yaw (rad)
    :param right_foot_target: (4,) right sole x, y, z (m), yaw (rad)
    :param pelvis_position: (3,) the pelvis position the controller used (measured/estimated)
    :param stance: (left, right) feet latched on the ground
    :param next_state: (2, 9) the commanded state at t + Ts whose masses give the targets
    :param mpc_result: the MPC's result (plan, predictions), None when the MPC did not run
    :param zmp_desired: (2,) the stabilizer's desired ZMP: the MPC's ZMP moved by the DCM
        feedback and clamped to the feet in contact (m); NaN with balance 'open_loop'
    :param zmp_error: (2,) desired - measured (filtered F/T) ZMP (m); NaN in the air
    :param dcm_error: (2,) reference - estimated DCM (m)
    :param foot_torque_errors: (2, 2) left and right measured - desired roll and pitch ground
        torques in the sole frames (N m)
    :param foot_contacts: (left, right) contact states of the touchdown detectors
    :param ankle_offsets: (2, 2) roll and pitch offsets of the sole targets, foot damping (rad)
    :param ankle_conformance: (2, 2) roll and pitch offsets of the sole targets for the
        ground's tilt, ground conformance (rad)
    :param vertical_offsets: (2,) height offsets of the sole targets: force difference and
        vertical drift (m)
    :param landing_modes: (left, right) swing_landing modes ('swinging', 'seeking', 'landed',
        'failed'; 'support' for a foot the plan has on the ground)
    :param landing_depths: (2,) left and right: how far below its planned landing height a
        seeking swing foot's target has descended (m), 0 otherwise
    :param trunk_tilt: (2,) roll and pitch of the pelvis target about its heading frame: the
        stabilizer's hip strategy (rad)
    :param command_leash_shift: (2,) how far the command leash moved the commanded state
        towards the measured robot this cycle, world x y (m); zero while inside the leash
    :param dcm_leash_shift: (2,) how far the DCM leash of an adjusted walk moved the commanded
        DCM back towards the measured one this cycle, world x y (m); zero while inside
    :param lift_held: (left, right) the lift-off gate keeps a foot the plan lifts on the
        ground this cycle
    """

    joint_setpoints: np.ndarray
    joint_velocities: np.ndarray
    status: int
    mpc_status: tuple
    solve_time: float
    state: np.ndarray
    kalman_state: np.ndarray
    zmp_measured: np.ndarray
    zmp_estimated: np.ndarray
    zmp_predicted: np.ndarray
    measured_outputs: np.ndarray
    ik_status: tuple
    pelvis_target: np.ndarray
    pelvis_command: np.ndarray
    hip_target: np.ndarray
    left_foot_target: np.ndarray
    right_foot_target: np.ndarray
    pelvis_position: np.ndarray
    stance: tuple
    next_state: np.ndarray
    mpc_result: Any = None
    zmp_desired: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))
    zmp_error: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))
    dcm_error: np.ndarray = field(default_factory=lambda: np.full(2, np.nan))
    foot_torque_errors: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))
    foot_contacts: tuple = (False, False)
    ankle_offsets: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))
    ankle_conformance: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))
    vertical_offsets: np.ndarray = field(default_factory=lambda: np.zeros(2))
    landing_modes: tuple = ('support', 'support')
    landing_depths: np.ndarray = field(default_factory=lambda: np.zeros(2))
    trunk_tilt: np.ndarray = field(default_factory=lambda: np.zeros(2))
    command_leash_shift: np.ndarray = field(default_factory=lambda: np.zeros(2))
    dcm_leash_shift: np.ndarray = field(default_factory=lambda: np.zeros(2))
    lift_held: tuple = (False, False)

    @property
    def cost(self) -> np.ndarray:
        """The paper's cost J per plane, NaN for a plane that fell back (computed on access).

        :return: (2,) costs
        """
        if self.mpc_result is None:
            return np.full(N_PLANES, np.nan)
        return np.asarray(self.mpc_result.cost, dtype=float)
