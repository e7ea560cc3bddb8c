"""One cycle of the paper's walking controller (Fig. overall) without ROS: MPC + estimator + IK.

Every control period Ts the controller takes the planner's reference window (the ZMP, hip,
feet, leg masses and bounds at t, t + Ts, ..., t + Np Ts) and what the robot measures, and
returns the 12 leg joint setpoints for the next period:

1. Kinematics: the leg forward kinematics of the measured joints places both soles relative
   to the pelvis; the pelvis pose comes either from the simulator's ground truth
   (pelvis_source='ground_truth') or from the IMU orientation and the stance feet
   (pelvis_source='imu_kinematics': pelvis = stance sole - R_imu FK(stance sole), the stance
   soles being latched where they landed; in double support the foot on the ground longest).
2. Measured outputs (eq. statespace_3lipm, y = C X, masses labelled left/right): each leg
   mass is midway between its measured sole centre and the model hip, the ZMP is the one of
   the ankle F/T sensors (the estimator's prediction while no foot touches the ground).
3. State estimation: the Kalman filter of biped_mpc.state_estimator corrects its prediction
   with the measured outputs. The MPC starts from the commanded state (feedback='prediction':
   a feed-forward pattern generator, Kajita's preview control in effect) or from its blend
   with the estimate, x = x_cmd + g (x_kalman - x_cmd) (feedback='estimator', the paper's
   loop for g = 1; g < 1 is the standard remedy when the measured ZMP of a stiff
   position-controlled robot is too noisy, with impacts, to be fed back at full gain).
4. MPC (biped_mpc.linear_mpc, both planes) on the references and bounds of
   biped_mpc.reference_adapter, sampled at t + Ts, ..., t + Np Ts.
5. Targets from the commanded next state x_cmd(k+1) = A_d x_cmd(k) + B_d u(k) (section
   "Masses Reference Trajectories" inverted): hip = torso mass; a swinging foot = 2 * leg
   mass - hip; a stance foot stays where it landed (latched at touch-down from its measured
   pose); feet heights and yaws come from the reference window at t + Ts; the pelvis is
   upright at pelvis_height above the stance soles with the mean heading of the feet.
6. Leg IK (analytic by default, Pinocchio by parameter) of the pelvis and feet targets.

Model hip and centre-of-mass offset: the reference hip is the planner's LIPM centre of mass,
and the model's torso mass moves with it. On the real robot the whole-body centre of mass
sits com_offset ahead of the pelvis (the knees bend forward: 1.4 cm for the COMAN-like robot
standing), so the controller works in model coordinates where model hip = pelvis
+ R(yaw) com_offset; the pelvis target is the torso mass minus that offset. Without it the
robot's centre of mass, and so its ZMP, would run 1.4 cm ahead of the plan.

Model parameters of the COMAN-like humanoid (biped_sim README, nominal stance): each leg
6.65 kg with its centre of mass 0.265 m high (the paper's m_1 = m_3, z_1 = z_3), the torso
(pelvis, waist, chest, arms, head) 17.65 kg at 0.672 m (m_2, z_2); total 30.95 kg with the
centre of mass 0.497 m high, which is also the LIPM height of the baseline model.

Additions (not in the paper), found necessary on the PyBullet humanoid and each switchable:

* commanded motion: the MPC's jerks integrate a commanded state, x_cmd(k+1) = A_d x_cmd(k)
  + B_d u(k), whose positions are the targets; the MPC starts from x_cmd (feedback
  'prediction') or from the blend with the Kalman estimate (feedback 'estimator'). Placing
  the robot at the next state of the estimate itself would turn every estimator correction
  into a position jump of the targets, i.e. a ZMP spike (a 1 mm jump in 20 ms is 5 m/s^2);
* torso-relative leg outputs (MpcParams.leg_outputs, 'torso_relative' in the default mpc
  parameters here): the MPC
  tracks each leg mass minus half the torso, whose reference is half the planned foot,
  instead of the leg mass against the midpoint of the planned foot and the planner's hip. The
  three-mass MPC moves its torso away from the planner's (LIPM) hip to place the ZMP; with
  the paper's absolute leg outputs every such centimetre moved the swing foot target
  2 * leg - hip by as much and pulled the stance leg mass away from the midpoint that the
  stance-leg projection below restores every cycle. On the PyBullet humanoid that cost the
  three-mass controller its turning walks (0.4 / 0.2 s steps: disk up to 0.12 m steps
  instead of 0.20 m, omnidirectional scale 0.8 instead of 1.1, push 112 N instead of 145 N;
  scripts/scenario_probe.py --leg-outputs). The LIPM's torso follows the planner's hip, so
  the baseline walks the same with either;
* stance-leg projection: a stance foot does not move, so the state of its leg mass (midway
  between that sole and the hip) is set to half the torso's position, velocity and
  acceleration plus half the sole, in the command and in the estimate (constrained
  filtering); without it the free model lets the stance leg drift and the swing foot target
  2 * leg - hip jumps by twice the drift at lift-off;
* pelvis velocity servo (pelvis_velocity_gain): the IK's pelvis target moves by the gain times
  the pelvis velocity error (mean velocity over the last two periods); the torque-controlled
  robot's stance leg is a lightly damped spring (the simulator's joint damping is capped for
  stability), and this damps its sway at the control rate;
* posture feedback (tilt_gain): the IK's pelvis leans against the measured roll and pitch;
* joint velocity feed-forward: the setpoint speeds over the period go with the setpoints, so
  the simulator's PD damps towards the motion instead of against it.

What walked on the PyBullet humanoid (torque control, leg_kp 2000 capped per joint,
leg_kd 8, setpoints ramped over the period by the runner): the defaults here (feedback
'prediction', pelvis_velocity_gain 0.05, tilt_gain 0.2), steps of 0.4 s single and 0.2 s
double support with 4 cm swing height (see biped_sim.closed_loop and its tests). Feeding the
Kalman estimate back ('estimator') walks there and on the model plant with feedback_gain 0.3;
at 0.6 and above the PyBullet robot fell: its F/T ZMP carries the impacts and the servo lag,
which the MPC answers with accelerations that excite them further.

Failures never raise from step for finite inputs: a QP that is not solved to optimality uses
the MPC's shifted previous plan (status MPC_FALLBACK); a malformed reference window or an
exception in the MPC coasts on the commanded state with zero jerk (status
REFERENCE_ERROR or MPC_ERROR); an IK target out of reach is clipped to the nearest feasible
pose (status IK_CLIPPED), an IK exception keeps the previous setpoints (status IK_ERROR).
"""
from dataclasses import dataclass
import math
import time
from typing import Any, Callable, Optional

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.leg_ik import AnalyticLegIk, IK_CLIPPED, IK_REACHABLE, LEFT, RIGHT
from biped_mpc.linear_model import (
    LEFT_LEG, N_INPUTS, N_OUTPUTS, N_PLANES, N_STATES, OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG,
    OUTPUT_ZMP, POSITION, RIGHT_LEG, state_index, TORSO)
from biped_mpc.linear_mpc import LEG_OUTPUTS_TORSO_RELATIVE, LinearMpc, MpcParams
from biped_mpc.lipm_model import lipm_model, LipmParams
from biped_mpc.qp_backends import QpStatus
from biped_mpc.reference_adapter import outputs_from_window
from biped_mpc.state_estimator import EstimatorParams, StateEstimator
from biped_mpc.three_mass_model import three_mass_model, ThreeMassParams

MODEL_THREE_MASS = 'three_mass'
MODEL_LIPM = 'lipm'
FEEDBACK_ESTIMATOR = 'estimator'
FEEDBACK_PREDICTION = 'prediction'
PELVIS_GROUND_TRUTH = 'ground_truth'
PELVIS_IMU_KINEMATICS = 'imu_kinematics'
IK_ANALYTIC = 'analytic'
IK_PINOCCHIO = 'pinocchio'

# Support labels of the reference window (biped_planner.walking_reference).
SUPPORT_LEFT = 0
SUPPORT_RIGHT = 1
SUPPORT_DOUBLE = 2

# Bits of ControllerOutput.status; 0 means everything nominal.
STATUS_OK = 0
STATUS_MPC_FALLBACK = 1
STATUS_MPC_ERROR = 2
STATUS_REFERENCE_ERROR = 4
STATUS_IK_CLIPPED = 8
STATUS_IK_ERROR = 16

# The COMAN-like humanoid of biped_sim (README "three-mass parameters (nominal stance)").
COMAN_LIKE_MASSES = ThreeMassParams(left_leg_mass=6.65, torso_mass=17.65, right_leg_mass=6.65,
                                    left_leg_height=0.265, torso_height=0.672,
                                    right_leg_height=0.265)
COMAN_LIKE_PELVIS_HEIGHT = 0.54  # m, pelvis frame above the soles standing (hips at 0.47 m)
COMAN_LIKE_COM_OFFSET = (0.0137, 0.0)  # m, whole-body centre of mass ahead of the pelvis


def _finite_number(name: str, value, low: float, high: float, low_open: bool = False) -> None:
    ok = (isinstance(value, (int, float)) and not isinstance(value, bool)
          and math.isfinite(value) and low <= value <= high and not (low_open and value == low))
    if not ok:
        bracket = '(' if low_open else '['
        raise ConfigError(f'WalkingControllerParams.{name} must be a finite number in '
                          f'{bracket}{low}, {high}], got {value!r}')


@dataclass(frozen=True)
class WalkingControllerParams:
    """Parameters of the walking controller.

    :param robot: the humanoid, duck typed like biped_sim's RobotDescription: leg_geometry
        (for the analytic IK), urdf_path, leg_joint_names and sole_frames (for Pinocchio)
    :param model: 'three_mass' (the paper) or 'lipm' (the baseline of the same shape)
    :param masses: masses and heights of the three-mass model (kg, m); the LIPM uses their
        total mass at the height of their centre of mass
    :param mpc: MPC parameters (Ts, horizons, weights, constraints, QP backend); the default
        tracks torso-relative leg outputs (see the module docstring)
    :param estimator: Kalman filter noise model
    :param feedback: 'prediction' (the MPC starts from the commanded state) or 'estimator'
        (from its blend with the Kalman estimate)
    :param feedback_gain: g of x = x_cmd + g (x_kalman - x_cmd) with feedback='estimator',
        [0, 1]
    :param pelvis_source: 'ground_truth' (simulator base) or 'imu_kinematics' (IMU orientation,
        position from the latched stance feet)
    :param ik: 'analytic' or 'pinocchio'
    :param pelvis_height: height of the pelvis frame above the stance soles (m), (0, 5]
    :param com_offset: whole-body centre of mass relative to the pelvis in its heading frame,
        (forward, left) (m), each in [-0.5, 0.5]
    :param stance_leg_projection: put the state of each stance leg's mass midway between its
        latched sole and the torso (see the module docstring)
    :param pelvis_velocity_gain: pelvis servo damping: the IK's pelvis target moves by this
        times the pelvis velocity error (s), [0, 1]; 0 disables it
    :param tilt_gain: posture feedback: the IK's pelvis orientation leans against the measured
        pelvis roll and pitch by tilt_gain times them, [0, 5]; 0 disables it
    """

    robot: Any
    model: str = MODEL_THREE_MASS
    masses: ThreeMassParams = COMAN_LIKE_MASSES
    mpc: MpcParams = MpcParams(leg_outputs=LEG_OUTPUTS_TORSO_RELATIVE)
    estimator: EstimatorParams = EstimatorParams()
    feedback: str = FEEDBACK_PREDICTION
    feedback_gain: float = 1.0
    pelvis_source: str = PELVIS_GROUND_TRUTH
    ik: str = IK_ANALYTIC
    pelvis_height: float = COMAN_LIKE_PELVIS_HEIGHT
    com_offset: tuple = COMAN_LIKE_COM_OFFSET
    stance_leg_projection: bool = True
    pelvis_velocity_gain: float = 0.05
    tilt_gain: float = 0.2

    def __post_init__(self) -> None:
        for name in ('leg_geometry', 'urdf_path', 'leg_joint_names', 'sole_frames'):
            if not hasattr(self.robot, name):
                raise ConfigError(f'WalkingControllerParams.robot must have {name!r} (a '
                                  f'RobotDescription), got {type(self.robot).__name__}')
        for name, value, choices in (
                ('model', self.model, (MODEL_THREE_MASS, MODEL_LIPM)),
                ('feedback', self.feedback, (FEEDBACK_ESTIMATOR, FEEDBACK_PREDICTION)),
                ('pelvis_source', self.pelvis_source,
                 (PELVIS_GROUND_TRUTH, PELVIS_IMU_KINEMATICS)),
                ('ik', self.ik, (IK_ANALYTIC, IK_PINOCCHIO))):
            if value not in choices:
                raise ConfigError(f'WalkingControllerParams.{name} must be one of {choices}, '
                                  f'got {value!r}')
        if self.ik == IK_ANALYTIC and self.robot.leg_geometry is None:
            raise ConfigError('WalkingControllerParams.ik = analytic needs robot.leg_geometry; '
                              'use ik = pinocchio for this robot')
        for name, kind in (('masses', ThreeMassParams), ('mpc', MpcParams),
                           ('estimator', EstimatorParams)):
            if not isinstance(getattr(self, name), kind):
                raise ConfigError(f'WalkingControllerParams.{name} must be a {kind.__name__}, '
                                  f'got {type(getattr(self, name)).__name__}')
        _finite_number('feedback_gain', self.feedback_gain, 0.0, 1.0)
        _finite_number('pelvis_height', self.pelvis_height, 0.0, 5.0, low_open=True)
        offset = np.asarray(self.com_offset, dtype=float)
        if offset.shape != (2,) or not np.all(np.isfinite(offset)) or np.any(np.abs(offset) > 0.5):
            raise ConfigError(f'WalkingControllerParams.com_offset must be 2 finite numbers in '
                              f'[-0.5, 0.5] m, got {self.com_offset!r}')
        object.__setattr__(self, 'com_offset', tuple(float(v) for v in offset))
        if not isinstance(self.stance_leg_projection, bool):
            raise ConfigError(f'WalkingControllerParams.stance_leg_projection must be a bool, '
                              f'got {self.stance_leg_projection!r}')
        _finite_number('pelvis_velocity_gain', self.pelvis_velocity_gain, 0.0, 1.0)
        _finite_number('tilt_gain', self.tilt_gain, 0.0, 5.0)


def _vector(name: str, value, size: int, allow_nan: bool = False) -> np.ndarray:
    array = np.array(value, dtype=float).reshape(-1) if value is not None else None
    if array is None or array.shape != (size,):
        raise InputError(f'ControllerFeedback.{name} must have {size} numbers, got {value!r}')
    bad = np.isinf(array) if allow_nan else ~np.isfinite(array)
    if np.any(bad):
        raise InputError(f'ControllerFeedback.{name} = {array.tolist()} must be finite'
                         + (' (NaN allowed)' if allow_nan else ''))
    return array


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
    :raises InputError: for wrong sizes, NaN or inf (NaN allowed in zmp only)
    """

    leg_joint_positions: np.ndarray
    pelvis_orientation: np.ndarray
    zmp: np.ndarray
    contacts: tuple
    pelvis_position: Optional[np.ndarray] = None
    pelvis_linear_velocity: Optional[np.ndarray] = None

    def __post_init__(self) -> None:
        object.__setattr__(self, 'leg_joint_positions',
                           _vector('leg_joint_positions', self.leg_joint_positions, 12))
        quaternion = _vector('pelvis_orientation', self.pelvis_orientation, 4)
        norm = float(np.linalg.norm(quaternion))
        if norm < 1e-6:
            raise InputError(f'ControllerFeedback.pelvis_orientation = {quaternion.tolist()} '
                             f'is not a rotation')
        object.__setattr__(self, 'pelvis_orientation', quaternion / norm)
        object.__setattr__(self, 'zmp', _vector('zmp', self.zmp, 2, allow_nan=True))
        contacts = tuple(bool(c) for c in np.asarray(self.contacts).reshape(-1))
        if len(contacts) != 2:
            raise InputError(f'ControllerFeedback.contacts must be 2 flags, got '
                             f'{self.contacts!r}')
        object.__setattr__(self, 'contacts', contacts)
        for name, size in (('pelvis_position', 3), ('pelvis_linear_velocity', 3)):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _vector(name, getattr(self, name), size))

    @classmethod
    def from_readings(cls, readings, pelvis_source: str = PELVIS_GROUND_TRUTH,
                      leg_joint_count: int = 12) -> 'ControllerFeedback':
        """Build the feedback from simulator readings (duck typed biped_sim SensorReadings).

        :param readings: object with joints.position (leg joints first), base, imu, zmp,
            left_foot.in_contact and right_foot.in_contact
        :param pelvis_source: 'ground_truth' (base pose and velocity) or 'imu_kinematics'
            (IMU orientation, no position: the controller estimates it)
        :param leg_joint_count: number of leading joint readings that are the legs (12)
        :return: the feedback
        :raises InputError: for an unknown source or bad readings
        """
        legs = np.asarray(readings.joints.position, dtype=float)[:leg_joint_count]
        contacts = (readings.left_foot.in_contact, readings.right_foot.in_contact)
        if pelvis_source == PELVIS_GROUND_TRUTH:
            return cls(legs, readings.base.orientation, readings.zmp, contacts,
                       readings.base.position, readings.base.linear_velocity)
        if pelvis_source == PELVIS_IMU_KINEMATICS:
            return cls(legs, readings.imu.orientation, readings.zmp, contacts)
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

    @property
    def cost(self) -> np.ndarray:
        """The paper's cost J per plane, NaN for a plane that fell back (computed on access).

        :return: (2,) costs
        """
        if self.mpc_result is None:
            return np.full(N_PLANES, np.nan)
        return np.asarray(self.mpc_result.cost, dtype=float)


def quaternion_matrix(quaternion: np.ndarray) -> np.ndarray:
    """Rotation matrix of a unit quaternion (x, y, z, w).

    :param quaternion: (4,) unit quaternion
    :return: (3, 3) rotation
    """
    x, y, z, w = quaternion
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _yaw_matrix(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _mean_angle(a: float, b: float) -> float:
    return a + 0.5 * math.atan2(math.sin(b - a), math.cos(b - a))


def feet_targets_from_masses(hip: np.ndarray, left_mass: np.ndarray,
                             right_mass: np.ndarray) -> tuple:
    """Invert the paper's mass references: a leg mass is midway between its foot and the hip.

    :param hip: (..., 2) model hip (torso mass) (m)
    :param left_mass: (..., 2) left leg mass (m)
    :param right_mass: (..., 2) right leg mass (m)
    :return: (left foot, right foot), each (..., 2) = 2 * leg mass - hip (m)
    """
    hip = np.asarray(hip, dtype=float)
    return 2.0 * np.asarray(left_mass) - hip, 2.0 * np.asarray(right_mass) - hip


class _LegForwardKinematics:
    """Sole poses of both legs (the equations of AnalyticLegIk.forward_leg, without its input
    validation, which costs more than the kinematics in a 50 Hz loop)."""

    def __init__(self, geometry) -> None:
        mirror = np.array([1.0, -1.0, 1.0])
        hip = np.array(geometry.hip_offset, dtype=float)
        sole = np.array(geometry.ankle_to_sole, dtype=float)
        self._hip = (hip, hip * mirror)
        self._sole = (sole, sole * mirror)
        self._thigh = np.array([0.0, 0.0, -geometry.thigh_length])
        self._shank = np.array([0.0, 0.0, -geometry.shank_length])

    def forward(self, q: np.ndarray, pelvis_position: np.ndarray,
                pelvis_rotation: np.ndarray) -> tuple:
        """(left position, left rotation, right position, right rotation) of 12 angles."""
        cos, sin = np.cos(q), np.sin(q)
        poses = []
        for side in (LEFT, RIGHT):
            c, s = cos[6 * side:6 * side + 6], sin[6 * side:6 * side + 6]
            rz = np.array([[c[0], -s[0], 0.0], [s[0], c[0], 0.0], [0.0, 0.0, 1.0]])
            rx = np.array([[1.0, 0.0, 0.0], [0.0, c[1], -s[1]], [0.0, s[1], c[1]]])
            ry = np.array([[c[2], 0.0, s[2]], [0.0, 1.0, 0.0], [-s[2], 0.0, c[2]]])
            hip_rotation = pelvis_rotation @ rz @ rx @ ry
            knee = np.array([[c[3], 0.0, s[3]], [0.0, 1.0, 0.0], [-s[3], 0.0, c[3]]])
            knee_rotation = hip_rotation @ knee
            ankle = (pelvis_position + pelvis_rotation @ self._hip[side]
                     + hip_rotation @ self._thigh + knee_rotation @ self._shank)
            pitch = np.array([[c[4], 0.0, s[4]], [0.0, 1.0, 0.0], [-s[4], 0.0, c[4]]])
            roll = np.array([[1.0, 0.0, 0.0], [0.0, c[5], -s[5]], [0.0, s[5], c[5]]])
            foot_rotation = knee_rotation @ pitch @ roll
            poses.extend([ankle + foot_rotation @ self._sole[side], foot_rotation])
        return tuple(poses)


class WalkingController:
    """The paper's controller for one cycle: estimator, MPC on both planes, masses to IK.

    See the module docstring for the cycle. Build once (the MPC's QP matrices, the Riccati
    terminal cost and the Kalman gain are computed here, 10 to 50 ms), then reset and step.

    :param params: controller parameters
    :param clock: seconds clock for the diagnostic solve time (never used for control)
    :raises ConfigError: for inconsistent parameters
    """

    def __init__(self, params: WalkingControllerParams,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        if not isinstance(params, WalkingControllerParams):
            raise ConfigError(f'params must be WalkingControllerParams, got '
                              f'{type(params).__name__}')
        self.params = params
        if params.model == MODEL_THREE_MASS:
            self.model = three_mass_model(params.masses)
        else:
            self.model = lipm_model(LipmParams.from_three_mass(params.masses))
        self.mpc = LinearMpc(self.model, params.mpc, clock)
        self.discrete_model = self.mpc.discrete_model
        self._a_t = np.ascontiguousarray(self.discrete_model.a.T)
        self._b_t = np.ascontiguousarray(self.discrete_model.b.T)
        self._zmp_row = self.model.zmp_row
        self.estimator = StateEstimator(self.discrete_model, params.estimator)
        robot = params.robot
        if params.ik == IK_ANALYTIC:
            self.ik = AnalyticLegIk(robot.leg_geometry)
        else:
            from biped_mpc.pinocchio_ik import PinocchioLegIk
            self.ik = PinocchioLegIk(robot.urdf_path, robot.leg_joint_names, robot.sole_frames)
        # Kinematics of the measured joints always uses the analytic model when it exists.
        geometry = robot.leg_geometry
        self._fk = _LegForwardKinematics(geometry) if geometry is not None else self.ik
        self._hip_centre = (np.array([geometry.hip_offset[0], 0.0, geometry.hip_offset[2]])
                            if geometry is not None else np.zeros(3))
        self._com_offset = np.array(params.com_offset + (0.0,))
        # Model hip minus pelvis in the heading frame: hip centres plus the COM offset.
        self._pelvis_to_hip = self._com_offset + np.array([self._hip_centre[0], 0.0, 0.0])
        self._n_predict = params.mpc.n_predict
        self._dt = params.mpc.dt
        self._reset_done = False

    # ----------------------------------------------------------------------------- reset
    def reset(self, t: float, feedback: ControllerFeedback) -> None:
        """Start from a standing robot: both feet latched where they are, masses at rest.

        With pelvis_source 'imu_kinematics' the pelvis position of this feedback anchors the
        feet in the world (the start pose is known); without it the pelvis is taken at
        (0, 0, pelvis_height).

        :param t: time (s)
        :param feedback: the robot now
        :raises InputError: if t is not finite or feedback is not a ControllerFeedback
        """
        self._check_time(t)
        if not isinstance(feedback, ControllerFeedback):
            raise InputError(f'feedback must be a ControllerFeedback, got '
                             f'{type(feedback).__name__}')
        rotation = quaternion_matrix(feedback.pelvis_orientation)
        pelvis = (feedback.pelvis_position.copy() if feedback.pelvis_position is not None
                  else np.array([0.0, 0.0, self.params.pelvis_height]))
        soles = self._soles(feedback.leg_joint_positions, pelvis, rotation)
        self._latched = [self._pose_of(soles, side) for side in (LEFT, RIGHT)]
        self._anchors = [LEFT, RIGHT]
        outputs, hip = self._outputs(soles, pelvis, rotation, np.full(2, np.nan), None)
        state = np.zeros((N_PLANES, N_STATES))
        state[:, state_index(LEFT_LEG, POSITION)] = outputs[:, OUTPUT_LEFT_LEG]
        state[:, state_index(TORSO, POSITION)] = hip
        state[:, state_index(RIGHT_LEG, POSITION)] = outputs[:, OUTPUT_RIGHT_LEG]
        self.estimator.reset(state)
        self.mpc.reset()
        self._command = state
        self._pelvis = pelvis
        self._pelvis_history = (pelvis.copy(),) * 3
        self._pelvis_targets = (pelvis.copy(),) * 3
        self._last_q = feedback.leg_joint_positions.copy()
        self._reset_done = True

    @staticmethod
    def _check_time(t) -> None:
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t):
            raise InputError(f't must be a finite number (s), got {t!r}')

    # ----------------------------------------------------------------------------- kinematics
    def _soles(self, q: np.ndarray, pelvis: np.ndarray, rotation: np.ndarray) -> tuple:
        """World poses (position, rotation) of both soles for a pelvis pose."""
        left_p, left_r, right_p, right_r = self._fk.forward(q, pelvis, rotation)
        return (np.asarray(left_p), np.asarray(left_r)), (np.asarray(right_p),
                                                           np.asarray(right_r))

    @staticmethod
    def _pose_of(soles: tuple, side: int) -> np.ndarray:
        position, rotation = soles[side]
        return np.array([position[0], position[1], position[2],
                         math.atan2(rotation[1, 0], rotation[0, 0])])

    def _model_hip(self, pelvis: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        hip = pelvis + rotation @ self._hip_centre + _yaw_matrix(yaw) @ self._com_offset
        return hip[:2]

    def _outputs(self, soles, pelvis, rotation, zmp, zmp_fallback) -> tuple:
        """Measured outputs (2, 3) and the measured model hip (2,)."""
        hip = self._model_hip(pelvis, rotation)
        outputs = np.empty((N_PLANES, N_OUTPUTS))
        outputs[:, OUTPUT_LEFT_LEG] = 0.5 * (soles[LEFT][0][:2] + hip)
        outputs[:, OUTPUT_RIGHT_LEG] = 0.5 * (soles[RIGHT][0][:2] + hip)
        if np.all(np.isfinite(zmp)):
            outputs[:, OUTPUT_ZMP] = zmp
        elif zmp_fallback is not None:
            outputs[:, OUTPUT_ZMP] = zmp_fallback
        else:
            outputs[:, OUTPUT_ZMP] = hip
        return outputs, hip

    def _pelvis_from_feet(self, q: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """Pelvis position from the anchor foot (see _update_latches) and the leg kinematics."""
        if not self._anchors:
            return self._pelvis.copy()
        side = self._anchors[0]
        return self._latched[side][:3] - self._soles(q, np.zeros(3), rotation)[side][0]

    # ----------------------------------------------------------------------------- step
    def step(self, t: float, window, feedback: ControllerFeedback) -> ControllerOutput:
        """Run one control cycle.

        :param t: time of the feedback and of window sample 0 (s)
        :param window: reference window (duck typed ReferenceWindow) with samples at t,
            t + Ts, ...; at least Np + 1 samples are used (a shorter window repeats its last)
        :param feedback: the robot now
        :return: joint setpoints for the next period and diagnostics
        :raises InputError: if t is not finite, feedback is not a ControllerFeedback, or step
            is called before reset
        """
        self._check_time(t)
        if not isinstance(feedback, ControllerFeedback):
            raise InputError(f'feedback must be a ControllerFeedback, got '
                             f'{type(feedback).__name__}')
        if not self._reset_done:
            raise InputError('call reset before step')
        params = self.params
        status = STATUS_OK
        q = feedback.leg_joint_positions
        rotation = quaternion_matrix(feedback.pelvis_orientation)
        if params.pelvis_source == PELVIS_GROUND_TRUTH and feedback.pelvis_position is not None:
            pelvis = feedback.pelvis_position
        else:
            pelvis = self._pelvis_from_feet(q, rotation)
        self._pelvis = pelvis
        soles = self._soles(q, pelvis, rotation)

        try:
            references = self._references(window)
        except (InputError, AttributeError, TypeError, ValueError, IndexError):
            references = None
            status |= STATUS_REFERENCE_ERROR
        support_now = references[4][0] if references is not None else None
        self._update_latches(support_now, soles, feedback.contacts)

        command = self._command
        if params.stance_leg_projection:
            self._project_stance_legs(command)
        outputs, _ = self._outputs(soles, pelvis, rotation, feedback.zmp,
                                   command @ self._zmp_row)
        kalman = self.estimator.correct(outputs)
        if params.stance_leg_projection:
            # Constrained filtering: the estimate is projected on the stance-leg constraint too
            # (with the default steady-state gain, reset only replaces the state).
            self._project_stance_legs(kalman)
            self.estimator.reset(kalman)
        if params.feedback == FEEDBACK_ESTIMATOR:
            state = command + params.feedback_gain * (kalman - command)
            if params.stance_leg_projection:
                self._project_stance_legs(state)
        else:
            state = command.copy()

        mpc_status = (int(QpStatus.FAILED),) * N_PLANES
        solve_time = 0.0
        result = None
        jerk = np.zeros((N_PLANES, N_INPUTS))
        if references is not None:
            y_ref, y_min, y_max = references[:3]
            try:
                result = self.mpc.solve(state, y_ref, y_min, y_max)
                jerk = result.jerk
                mpc_status = tuple(int(s) for s in result.status)
                solve_time = result.solve_time
                if not result.ok:
                    status |= STATUS_MPC_FALLBACK
            except Exception:  # noqa: B902 - the control loop must go on with a safe fallback
                result = None
                status |= STATUS_MPC_ERROR
                self.mpc.reset()
        # The jerks drive the commanded motion, which stays smooth whatever the estimate does.
        next_state = command @ self._a_t + jerk @ self._b_t
        self.estimator.predict(jerk)
        self._command = next_state

        zmp_measured = feedback.zmp.copy()
        targets = self._targets(next_state, references, soles)
        pelvis_target, left_target, right_target, yaw = targets
        pelvis_command = self._pelvis_servo(pelvis_target, pelvis)
        ik_status = (IK_REACHABLE, IK_REACHABLE)
        q_next = self._last_q
        try:
            pelvis_rotation = _yaw_matrix(yaw) @ self._posture_correction(rotation)
            solution = self.ik.solve(pelvis_command, pelvis_rotation, left_target[:3],
                                     _yaw_matrix(left_target[3]), right_target[:3],
                                     _yaw_matrix(right_target[3]))
            q_next = np.array(solution.q, dtype=float)
            ik_status = tuple(int(s) for s in solution.status)
            if not np.all(np.isfinite(q_next)):
                raise InputError('IK returned non-finite angles')
            if IK_CLIPPED in ik_status:
                status |= STATUS_IK_CLIPPED
        except Exception:  # noqa: B902 - keep the last setpoints rather than stop the loop
            q_next = self._last_q
            status |= STATUS_IK_ERROR
        velocities = (q_next - self._last_q) / self._dt
        self._last_q = q_next.copy()
        hip_target = next_state[:, state_index(TORSO, POSITION)].copy()
        return ControllerOutput(
            joint_setpoints=q_next.copy(), joint_velocities=velocities, status=status,
            mpc_status=mpc_status, solve_time=solve_time, state=state,
            kalman_state=kalman, zmp_measured=zmp_measured,
            zmp_estimated=state @ self._zmp_row, zmp_predicted=next_state @ self._zmp_row,
            measured_outputs=outputs, ik_status=ik_status, pelvis_target=pelvis_target,
            pelvis_command=pelvis_command,
            hip_target=hip_target, left_foot_target=left_target, right_foot_target=right_target,
            pelvis_position=np.asarray(pelvis, dtype=float).copy(),
            stance=tuple(latch is not None for latch in self._latched),
            next_state=next_state.copy(), mpc_result=result)

    def _references(self, window) -> tuple:
        """MPC references of samples 1 .. Np, and the support, feet and yaw of samples 0, 1."""
        y_ref, y_min, y_max = outputs_from_window(window, self.params.mpc.leg_outputs)
        n = y_ref.shape[1]
        index = np.minimum(np.arange(1, self._n_predict + 1), n - 1)
        support = np.asarray(window.support)
        left_foot = np.asarray(window.left_foot, dtype=float)
        right_foot = np.asarray(window.right_foot, dtype=float)
        left_yaw = np.asarray(window.left_yaw, dtype=float)
        right_yaw = np.asarray(window.right_yaw, dtype=float)
        if n < 2 or support.shape[0] != n or left_foot.shape != (n, 3) \
                or right_foot.shape != (n, 3) or left_yaw.shape != (n,) \
                or right_yaw.shape != (n,):
            raise InputError('the reference window needs at least 2 samples of support, feet '
                             'and yaws')
        feet_next = np.array([[*left_foot[1], left_yaw[1]], [*right_foot[1], right_yaw[1]]])
        if not np.all(np.isfinite(feet_next)):
            raise InputError('the reference window has non-finite feet')
        return (y_ref[:, index], y_min[:, index], y_max[:, index], feet_next,
                (int(support[0]), int(support[1])))

    def _update_latches(self, support_now, soles, contacts) -> None:
        """Latch a foot where it is on touch-down, release it when the reference lifts it.

        With pelvis_source 'imu_kinematics' the pelvis is estimated from the foot that has been
        on the ground longest (the anchor); a foot that lands later is latched again at every
        cycle from that estimate until the anchor lifts off, so it is anchored where it settled
        (a foot that lands tilted and then rolls flat moves its sole centre by millimetres,
        which would accumulate into the pelvis estimate at every step).
        """
        if support_now is None:
            return
        for side, own in ((LEFT, SUPPORT_LEFT), (RIGHT, SUPPORT_RIGHT)):
            if support_now not in (own, SUPPORT_DOUBLE):
                self._latched[side] = None
                if side in self._anchors:
                    self._anchors.remove(side)
            elif contacts[side] and (self._latched[side] is None or (
                    self.params.pelvis_source == PELVIS_IMU_KINEMATICS
                    and self._anchors and self._anchors[0] != side)):
                self._latched[side] = self._pose_of(soles, side)
                if side not in self._anchors:
                    self._anchors.append(side)

    def _pelvis_servo(self, pelvis_target: np.ndarray, pelvis: np.ndarray) -> np.ndarray:
        """The pelvis target moved by the pelvis velocity error (see the module docstring).

        The velocities are mean velocities over the last two periods (position differences):
        the instantaneous pelvis velocity carries the joint servos' vibration, and a one-period
        difference would feed back the period-2 oscillation of a delayed loop at full gain.
        """
        # Histories of the last three cycles, oldest first: k - 2, k - 1, k.
        self._pelvis_targets = self._pelvis_targets[1:] + (pelvis_target.copy(),)
        self._pelvis_history = self._pelvis_history[1:] + (np.asarray(pelvis, float).copy(),)
        gain = self.params.pelvis_velocity_gain
        if gain <= 0.0:
            return pelvis_target
        command = pelvis_target.copy()
        command[:2] += gain * ((pelvis_target[:2] - self._pelvis_targets[0][:2])
                               - (pelvis[:2] - self._pelvis_history[0][:2])) / (2.0 * self._dt)
        return command

    def _posture_correction(self, rotation: np.ndarray) -> np.ndarray:
        """Rotation leaning the IK's pelvis against the measured roll and pitch."""
        gain = self.params.tilt_gain
        if gain <= 0.0:
            return np.eye(3)
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        tilt = _yaw_matrix(yaw).T @ rotation
        roll = -gain * math.atan2(tilt[2, 1], tilt[2, 2])
        pitch = -gain * math.atan2(-tilt[2, 0], math.hypot(tilt[2, 1], tilt[2, 2]))
        c, s = math.cos(roll), math.sin(roll)
        roll_matrix = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
        c, s = math.cos(pitch), math.sin(pitch)
        pitch_matrix = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
        return roll_matrix @ pitch_matrix

    def _project_stance_legs(self, state: np.ndarray) -> None:
        """Put each stance leg's mass midway between its latched sole and the torso.

        A stance foot does not move, so its leg mass (midway between the sole and the hip) has
        half the torso's velocity and acceleration; the free model lets it drift from there,
        and at lift-off the swing foot target 2 * leg - hip would jump by twice the drift.
        """
        torso = slice(state_index(TORSO, POSITION), state_index(TORSO, POSITION) + 3)
        for side, mass in ((LEFT, LEFT_LEG), (RIGHT, RIGHT_LEG)):
            latch = self._latched[side]
            if latch is None:
                continue
            leg = slice(state_index(mass, POSITION), state_index(mass, POSITION) + 3)
            state[:, leg] = 0.5 * state[:, torso]
            state[:, state_index(mass, POSITION)] += 0.5 * latch[:2]

    def _targets(self, next_state: np.ndarray, references, soles) -> tuple:
        """Pelvis (3,), left and right sole (x, y, z, yaw) targets and the pelvis yaw."""
        hip = next_state[:, state_index(TORSO, POSITION)]
        legs = (next_state[:, state_index(LEFT_LEG, POSITION)],
                next_state[:, state_index(RIGHT_LEG, POSITION)])
        swing_feet = feet_targets_from_masses(hip, legs[LEFT], legs[RIGHT])
        if references is not None:
            feet_next, support_next = references[3], references[4][1]
        else:
            feet_next = np.array([self._pose_of(soles, LEFT), self._pose_of(soles, RIGHT)])
            feet_next[:, 2] = [0.0 if latch is None else latch[2] for latch in self._latched]
            support_next = SUPPORT_DOUBLE
        held = [self._latched[side] is not None and support_next in (own, SUPPORT_DOUBLE)
                for side, own in ((LEFT, SUPPORT_LEFT), (RIGHT, SUPPORT_RIGHT))]
        grounds = [self._latched[side][2] for side in (LEFT, RIGHT) if held[side]]
        ground = float(np.mean(grounds)) if grounds else 0.0
        targets = [self._latched[side].copy() if held[side] else
                   np.array([swing_feet[side][0], swing_feet[side][1],
                             feet_next[side][2] + ground, feet_next[side][3]])
                   for side in (LEFT, RIGHT)]
        yaw = _mean_angle(float(feet_next[LEFT][3]), float(feet_next[RIGHT][3]))
        heading = _yaw_matrix(yaw)
        pelvis_xy = hip - (heading @ self._pelvis_to_hip)[:2]
        pelvis = np.array([pelvis_xy[0], pelvis_xy[1], ground + self.params.pelvis_height])
        return pelvis, targets[LEFT], targets[RIGHT], yaw
