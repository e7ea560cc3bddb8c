"""One cycle of the paper's walking controller (Fig. overall) without ROS: MPC + estimator + IK.

Every control period Ts the controller takes the planner's reference window (the ZMP, hip,
feet, leg masses and bounds at t, t + Ts, ..., t + Np Ts) and what the robot measures, and
returns the 12 leg joint setpoints for the next period:

1. Kinematics: the leg forward kinematics of the measured joints places both soles relative
   to the pelvis; the pelvis pose comes from the simulator's ground truth
   (pelvis_source='ground_truth') or from the IMU orientation and the stance feet
   (pelvis_source='imu_kinematics': pelvis = stance sole - R_imu FK(stance sole), the stance
   soles latched where they landed, biped_mpc.stance_feet).
2. Measured outputs (eq. statespace_3lipm, y = C X, masses labelled left/right): each leg
   mass is midway between its measured sole centre and the model hip (biped_mpc.model_hip),
   the ZMP is the one of the ankle F/T sensors (the model's while no foot touches the ground).
3. State estimation: the Kalman filter (biped_mpc.state_estimator) corrects its prediction
   with the measured outputs. The MPC starts from the commanded state (feedback='prediction':
   a feed-forward pattern generator, Kajita's preview control in effect) or from its blend
   with the estimate, x = x_cmd + g (x_kalman - x_cmd) (feedback='estimator', the paper's
   loop for g = 1; g < 1 is the standard remedy when the measured ZMP of a stiff
   position-controlled robot is too noisy, with impacts, to be fed back at full gain). With
   a command leash (command_leash_along / _across, off by default; biped_mpc.command_leash)
   the commanded state is first translated into a box around the measured hip. With
   adjusted_walk_dcm_leash > 0 (5 cm by default), at each step the step adjuster moves
   (walk_adjustments grows) the commanded DCM is brought within that distance of the measured
   one through the commanded velocities.
4. MPC (biped_mpc.linear_mpc, both planes) on the references and bounds of
   biped_mpc.reference_adapter, sampled at t + Ts, ..., t + Np Ts.
5. Commanded motion: the MPC's jerks integrate the commanded state, x_cmd(k+1) = A_d x_cmd(k)
   + B_d u(k), whose positions are the targets (biped_mpc.ik_targets). Placing the robot at
   the next state of the estimate itself would turn every estimator correction into a
   position jump of the targets, i.e. a ZMP spike (a 1 mm jump in 20 ms is 5 m/s^2).
6. Leg IK (analytic by default, Pinocchio by parameter) of the pelvis and feet targets, the
   pelvis moved by the velocity servo and leaned against the measured tilt
   (biped_mpc.pelvis_feedback). The setpoint speeds over the period go with the setpoints
   (joint velocity feed-forward), so the servo damps towards the motion, not against it.

7. Balance (balance 'stabilizer', the default; biped_mpc.balance.balance_loop): before the
   estimate, the ankle F/T readings are filtered (foot inertia removed) into contact states
   (touchdown detectors, which also latch the stance feet) and the measured ZMP the Kalman
   filter uses; after the MPC, the Stabilizer compares the estimated DCM with the commanded
   state's at full gain, distributes the desired wrench between the feet in contact and moves
   the IK's sole targets (foot damping roll and pitch, force difference and vertical drift
   heights) and the swing foot's landing (stop on early contact, descend on a late one). With
   balance 'open_loop' the cycle is the feed-forward one of steps 1-6.

Stance-leg projection (not in the paper): a stance foot does not move, so the state of its leg
mass is set to half the torso's position, velocity and acceleration plus half the sole, in the
command and in the estimate (constrained filtering). docs/controller_notes.md records what each
of these additions bought on the simulated humanoid.

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

from biped_mpc.controller_io import (
    ControllerFeedback, ControllerOutput, STATUS_IK_CLIPPED, STATUS_IK_ERROR, STATUS_MPC_ERROR,
    STATUS_MPC_FALLBACK, STATUS_OK, STATUS_REFERENCE_ERROR)
from biped_mpc.balance.balance_loop import (BalanceLoop, BalanceLoopParams, BalanceResult,
                                            planned_landing, SensedFeet)
from biped_mpc.balance.stabilizer import StabilizerReference
from biped_mpc.command_leash import (
    dcm_leash_excess, leash_shift, shift_positions, shift_velocities)
from biped_mpc.controller_params import (
    BALANCE_STABILIZER, FEEDBACK_ESTIMATOR, IK_ANALYTIC, MODEL_THREE_MASS, PELVIS_GROUND_TRUTH,
    PELVIS_IMU_KINEMATICS, SWING_TARGET_PLANNED, WalkingControllerParams)
from biped_mpc.errors import ConfigError, InputError
from biped_mpc.height_continuity import HeightContinuity
from biped_mpc.ik_targets import ik_targets, IkTargets
from biped_mpc.leg_ik import AnalyticLegIk, IK_CLIPPED, IK_REACHABLE
from biped_mpc.leg_kinematics import LegKinematics, sole_pose
from biped_mpc.linear_model import (
    LEFT_LEG, N_INPUTS, N_OUTPUTS, N_PLANES, N_STATES, OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG,
    OUTPUT_ZMP, POSITION, RIGHT_LEG, state_index, TORSO)
from biped_mpc.linear_mpc import LinearMpc
from biped_mpc.lipm_model import lipm_model, LipmParams
from biped_mpc.model_hip import ModelHip
from biped_mpc.pelvis_feedback import PelvisVelocityServo, posture_correction
from biped_mpc.qp_backend import QpStatus
from biped_mpc.reference_adapter import cycle_references, CycleReferences
from biped_mpc.stance_feet import on_support, StanceFeet
from biped_mpc.state_estimator import StateEstimator
from biped_mpc.swing_attitude import attitude_correction, corrected_swing_target
from biped_mpc.swing_retarget import SwingRetarget
from biped_mpc.swing_smoothing import SwingSmoothing
from biped_mpc.swing_start import SwingStart
from biped_mpc.three_mass_model import three_mass_model
from biped_planner.rotations import (quaternion_to_matrix, rotation_x, rotation_y, rotation_z,
                                     yaw_of_matrix)
from biped_planner.sides import LEFT, RIGHT, SIDES, SUPPORT_DOUBLE


@dataclass(frozen=True)
class _Estimate:
    """The state the MPC starts from, the Kalman estimate, the measured outputs (2, 3) and the
    command leash's shift of the commanded state (2,)."""

    state: np.ndarray
    kalman: np.ndarray
    outputs: np.ndarray
    leash_shift: np.ndarray
    com: np.ndarray           # (2,) measured centre of mass (m)
    dcm: np.ndarray           # (2,) measured DCM (m)
    dcm_leash_shift: np.ndarray  # (2,) the commanded DCM moved back by the DCM leash (m)


@dataclass(frozen=True)
class _MpcStep:
    """The jerks (2, 3) applied this cycle and the MPC's report."""

    jerk: np.ndarray
    result: Any
    mpc_status: tuple
    solve_time: float
    status: int


@dataclass(frozen=True)
class _IkStep:
    """The joint setpoints (12,), the pelvis position the IK used and the IK's report."""

    q: np.ndarray
    pelvis_command: np.ndarray
    ik_status: tuple
    status: int


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
        robot = params.robot
        if params.model == MODEL_THREE_MASS:
            self.model = three_mass_model(robot.masses)
        else:
            self.model = lipm_model(LipmParams.from_three_mass(robot.masses))
        self.mpc = LinearMpc(self.model, params.mpc, clock)
        self.discrete_model = self.mpc.discrete_model
        self._a_t = np.ascontiguousarray(self.discrete_model.a.T)
        self._b_t = np.ascontiguousarray(self.discrete_model.b.T)
        self._zmp_row = self.model.zmp_row
        self.estimator = StateEstimator(self.discrete_model, params.estimator)
        if params.ik == IK_ANALYTIC:
            self.ik = AnalyticLegIk(robot.leg_geometry)
        else:
            from biped_mpc.pinocchio_ik import PinocchioLegIk
            self.ik = PinocchioLegIk(robot.urdf_path, robot.leg_joint_names, robot.sole_frames)
        # Kinematics of the measured joints always uses the analytic model when it exists.
        geometry = robot.leg_geometry
        self._fk = LegKinematics(geometry) if geometry is not None else self.ik
        self._model_hip = ModelHip(geometry, robot.com_offset)
        self._stance = StanceFeet(relatch_followers=params.pelvis_source
                                  == PELVIS_IMU_KINEMATICS)
        self._n_predict = params.mpc.n_predict
        self._dt = params.mpc.dt
        self._servo = PelvisVelocityServo(params.pelvis_velocity_gain, self._dt)
        self._swing_start = SwingStart(params.swing_start_time_constant)
        self._swing_smoothing = SwingSmoothing(params.swing_smoothing_time_constant)
        self._swing_retarget = SwingRetarget() if params.swing_retarget else None
        self._height_continuity = HeightContinuity(params.height_continuity_time_constant,
                                                   params.height_continuity_deadband)
        self._swinging = [False, False]
        lipm = LipmParams.from_three_mass(robot.masses)
        self._omega = math.sqrt(lipm.gravity / lipm.com_height)
        self._com_height = lipm.com_height
        self._com_row = self.model.com_row
        self._com_velocity_row = np.roll(self._com_row, 1)
        self._balance = (BalanceLoop(BalanceLoopParams.from_controller(
            params, lipm.mass, lipm.com_height))
                         if params.balance == BALANCE_STABILIZER else None)
        self._reset_done = False
        # Set by the caller each cycle: steps of the walk the step adjuster has moved so far.
        # Each new one means the plan was moved for the measured DCM, and the commanded DCM is
        # brought to it once.
        self.walk_adjustments = 0
        self._answered_adjustments = 0

    def reset(self, t: float, feedback: ControllerFeedback) -> None:
        """Start from a standing robot: both feet latched where they are, masses at rest.

        With pelvis_source 'imu_kinematics' the pelvis position of this feedback anchors the
        feet in the world (the start pose is known); without it the pelvis is taken at
        (0, 0, pelvis_height).

        :param t: time (s)
        :param feedback: the robot now
        :raises InputError: if t is not finite or feedback is not a ControllerFeedback
        """
        self._check_arguments(t, feedback)
        rotation = quaternion_to_matrix(feedback.pelvis_orientation)
        pelvis = self._start_pelvis(feedback)
        soles = self._soles(feedback.leg_joint_positions, pelvis, rotation)
        self._stance.reset(soles)
        hip = self._model_hip.of_pelvis(pelvis, rotation)
        outputs = self._measured_outputs(soles, hip, np.full(2, np.nan), None)
        state = np.zeros((N_PLANES, N_STATES))
        state[:, state_index(LEFT_LEG, POSITION)] = outputs[:, OUTPUT_LEFT_LEG]
        state[:, state_index(TORSO, POSITION)] = hip
        state[:, state_index(RIGHT_LEG, POSITION)] = outputs[:, OUTPUT_RIGHT_LEG]
        self.estimator.reset(state)
        self.mpc.reset()
        self._command = state
        self._pelvis = pelvis
        self._servo.reset(pelvis)
        self._swing_start.reset()
        self._swing_smoothing.reset()
        if self._swing_retarget is not None:
            self._swing_retarget.reset()
        self._height_continuity.reset()
        if self._balance is not None:
            self._balance.reset(soles)
        self._com_history = []
        self._answered_adjustments = self.walk_adjustments  # those before the reset are done
        self._last_q = feedback.leg_joint_positions.copy()
        self._reset_done = True

    def standing_soles(self, feedback: ControllerFeedback) -> np.ndarray:
        """Where reset would latch the feet: [left, right] sole x, y, z (m), yaw (rad) of the
        measured joints, the pelvis placed as reset places it. Before the first cycle the
        reference generator stands the references there, so they start on the feet.

        :raises InputError: if feedback is not a ControllerFeedback
        """
        self._check_arguments(0.0, feedback)
        rotation = quaternion_to_matrix(feedback.pelvis_orientation)
        soles = self._soles(feedback.leg_joint_positions, self._start_pelvis(feedback), rotation)
        return np.array([sole_pose(*soles[side]) for side in SIDES])

    def _start_pelvis(self, feedback: ControllerFeedback) -> np.ndarray:
        """The measured pelvis, or (0, 0, pelvis_height) without one (imu_kinematics)."""
        return (feedback.pelvis_position.copy() if feedback.pelvis_position is not None
                else np.array([0.0, 0.0, self.params.robot.pelvis_height]))

    @property
    def balance_loop(self) -> Optional[BalanceLoop]:
        """The stabilizer's loop (balance 'stabilizer'), None with balance 'open_loop'."""
        return self._balance

    @property
    def latched_feet(self) -> list:
        """[left, right] sole x, y, z (m), yaw (rad) of the feet latched on the ground, None
        for a foot that is not (biped_mpc.stance_feet)."""
        return [None if latch is None else np.array(latch, dtype=float)
                for latch in self._stance.latched]

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
        self._check_arguments(t, feedback)
        if not self._reset_done:
            raise InputError('call reset before step')
        rotation = quaternion_to_matrix(feedback.pelvis_orientation)
        pelvis = self._pelvis_position(feedback, rotation)
        soles = self._soles(feedback.leg_joint_positions, pelvis, rotation)
        references = self._references(window)
        sensed = None
        if self._balance is not None and feedback.foot_wrenches is not None:
            sensed = self._balance.sense(t, self._dt, feedback.foot_wrenches, soles,
                                         window if references is not None else None)
        self._stance.update(None if references is None else references.support_now, soles,
                            feedback.contacts if sensed is None else sensed.contacts)
        estimate = self._estimate(soles, pelvis, rotation,
                                  feedback.zmp if sensed is None else sensed.zmp)
        mpc = self._solve_mpc(estimate.state, references)
        command = self._command.copy()
        next_state = self._advance(mpc.jerk)
        targets = self._targets(t, window, next_state, references, soles)
        balance = None
        if sensed is not None:
            balance = self._stabilize(t, targets, sensed, soles, pelvis, command, estimate,
                                      references)
            targets = balance.targets
        ik = self._solve_ik(targets, pelvis, rotation)
        status = (STATUS_OK if references is not None else STATUS_REFERENCE_ERROR) \
            | mpc.status | ik.status
        return self._output(status, feedback, pelvis, estimate, mpc, next_state, targets, ik,
                            sensed, balance)

    # ------------------------------------------------------------------ steps of the cycle
    @staticmethod
    def _check_arguments(t, feedback) -> None:
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t):
            raise InputError(f't must be a finite number (s), got {t!r}')
        if not isinstance(feedback, ControllerFeedback):
            raise InputError(f'feedback must be a ControllerFeedback, got '
                             f'{type(feedback).__name__}')

    def _pelvis_position(self, feedback: ControllerFeedback, rotation: np.ndarray) -> np.ndarray:
        """The measured pelvis, or the one hanging from the anchor foot by the leg kinematics."""
        if self.params.pelvis_source == PELVIS_GROUND_TRUTH and \
                feedback.pelvis_position is not None:
            pelvis = feedback.pelvis_position
        elif self._stance.anchor is None:
            pelvis = self._pelvis.copy()
        else:
            side = self._stance.anchor
            relative = self._soles(feedback.leg_joint_positions, np.zeros(3), rotation)
            pelvis = self._stance.latched[side][:3] - relative[side][0]
        self._pelvis = pelvis
        return pelvis

    def _soles(self, q: np.ndarray, pelvis: np.ndarray, rotation: np.ndarray) -> tuple:
        """World poses ((position, rotation) left, (position, rotation) right) of the soles."""
        left_p, left_r, right_p, right_r = self._fk.forward(q, pelvis, rotation)
        return (np.asarray(left_p), np.asarray(left_r)), (np.asarray(right_p),
                                                           np.asarray(right_r))

    def _references(self, window) -> Optional[CycleReferences]:
        """The cycle's references, None for a malformed window (the cycle then coasts)."""
        try:
            return cycle_references(window, self.params.mpc.leg_outputs, self._n_predict)
        except (InputError, AttributeError, TypeError, ValueError, IndexError):
            return None

    @staticmethod
    def _measured_outputs(soles: tuple, hip: np.ndarray, zmp: np.ndarray,
                          zmp_fallback: Optional[np.ndarray]) -> np.ndarray:
        """Measured outputs (2, 3): leg masses midway between soles and hip, the F/T ZMP."""
        outputs = np.empty((N_PLANES, N_OUTPUTS))
        outputs[:, OUTPUT_LEFT_LEG] = 0.5 * (soles[LEFT][0][:2] + hip)
        outputs[:, OUTPUT_RIGHT_LEG] = 0.5 * (soles[RIGHT][0][:2] + hip)
        if np.all(np.isfinite(zmp)):
            outputs[:, OUTPUT_ZMP] = zmp
        elif zmp_fallback is not None:
            outputs[:, OUTPUT_ZMP] = zmp_fallback
        else:
            outputs[:, OUTPUT_ZMP] = hip
        return outputs

    def _estimate(self, soles: tuple, pelvis: np.ndarray, rotation: np.ndarray,
                  zmp: np.ndarray) -> _Estimate:
        """Kalman correction with the measured outputs; the state the MPC starts from."""
        params = self.params
        command = self._command
        hip = self._model_hip.of_pelvis(pelvis, rotation)
        shift = np.zeros(2)
        if params.command_leash_along > 0.0 or params.command_leash_across > 0.0:
            shift = leash_shift(command, hip, params.command_leash_along,
                                params.command_leash_across, yaw_of_matrix(rotation))
            shift_positions(command, shift)
        if params.stance_leg_projection:
            self._stance.project_legs(command)
        outputs = self._measured_outputs(soles, hip, zmp, command @ self._zmp_row)
        com, dcm = self._measured_dcm(outputs, hip)
        dcm_shift = np.zeros(2)
        if self.walk_adjustments < self._answered_adjustments:  # a new walk
            self._answered_adjustments = 0
        if self.walk_adjustments > self._answered_adjustments and \
                params.adjusted_walk_dcm_leash > 0.0 and len(self._com_history) > 1:
            # Once per adjustment: leashed every cycle, the command follows the robot, the
            # servos follow the command, and a robot tipping over is chased (traced in the
            # graph: 0.6 m of DCM in 0.2 s). After the stance-leg projection, so that the MPC
            # and the stabilizer start from the DCM on the leash.
            self._answered_adjustments = self.walk_adjustments
            dcm_shift = dcm_leash_excess(self._dcm_of(command), dcm,
                                         params.adjusted_walk_dcm_leash)
            shift_velocities(command, dcm_shift, self._omega)
        kalman = self.estimator.correct(outputs)
        if params.stance_leg_projection:
            # Constrained filtering: the estimate is projected on the stance-leg constraint too
            # (with the default steady-state gain, reset only replaces the state).
            self._stance.project_legs(kalman)
            self.estimator.reset(kalman)
        if params.feedback == FEEDBACK_ESTIMATOR:
            state = command + params.feedback_gain * (kalman - command)
            if params.stance_leg_projection:
                self._stance.project_legs(state)
        else:
            state = command.copy()
        return _Estimate(state, kalman, outputs, shift, com, dcm, dcm_shift)

    def _dcm_of(self, state: np.ndarray) -> np.ndarray:
        """The DCM (2,) of a model state (2, 9): centre of mass + its velocity / omega."""
        return state @ self._com_row + state @ self._com_velocity_row / self._omega

    def _measured_dcm(self, outputs: np.ndarray, hip: np.ndarray) -> tuple:
        """The measured centre of mass and DCM (2,) each, once per cycle.

        The centre of mass is the model's of the measured masses (legs midway between soles
        and hip, the torso at the model hip); its velocity is the mean over the last two
        periods, as the pelvis servo's (the one-period difference carries the servos'
        vibration).
        """
        masses = self.model.masses
        com = (masses[LEFT_LEG] * outputs[:, OUTPUT_LEFT_LEG] + masses[TORSO] * hip
               + masses[RIGHT_LEG] * outputs[:, OUTPUT_RIGHT_LEG]) / sum(masses)
        self._com_history = (self._com_history + [com])[-3:]
        velocity = ((com - self._com_history[0]) / ((len(self._com_history) - 1) * self._dt)
                    if len(self._com_history) > 1 else np.zeros(2))
        return com, com + velocity / self._omega

    def _solve_mpc(self, state: np.ndarray, references: Optional[CycleReferences]) -> _MpcStep:
        """The MPC's jerks; zero jerks (coasting) without references or when the MPC fails."""
        if references is None:
            return _MpcStep(np.zeros((N_PLANES, N_INPUTS)), None,
                            (int(QpStatus.FAILED),) * N_PLANES, 0.0, STATUS_OK)
        try:
            result = self.mpc.solve(state, references.y_ref, references.y_min, references.y_max)
        except Exception:  # noqa: B902 - the control loop must go on with a safe fallback
            self.mpc.reset()
            return _MpcStep(np.zeros((N_PLANES, N_INPUTS)), None,
                            (int(QpStatus.FAILED),) * N_PLANES, 0.0, STATUS_MPC_ERROR)
        return _MpcStep(result.jerk, result, tuple(int(s) for s in result.status),
                        result.solve_time, STATUS_OK if result.ok else STATUS_MPC_FALLBACK)

    def _advance(self, jerk: np.ndarray) -> np.ndarray:
        """The commanded state at t + Ts: the jerks drive it, smooth whatever the estimate does."""
        next_state = self._command @ self._a_t + jerk @ self._b_t
        self.estimator.predict(jerk)
        self._command = next_state
        return next_state

    def _targets(self, t: float, window, next_state: np.ndarray,
                 references: Optional[CycleReferences], soles: tuple) -> IkTargets:
        """Pelvis and soles targets; without references the feet stay where they are."""
        if references is not None:
            feet_next, support_next = references.feet_next, references.support_next
        else:
            feet_next = np.array([sole_pose(*soles[side]) for side in SIDES])
            feet_next[:, 2] = [0.0 if latch is None else latch[2]
                               for latch in self._stance.latched]
            support_next = SUPPORT_DOUBLE
        planned = self.params.swing_target == SWING_TARGET_PLANNED
        self._swinging = [not held for held in self._stance.held(support_next)]
        targets = ik_targets(next_state, feet_next, support_next, self._stance,
                             self._model_hip, self.params.robot.pelvis_height, planned,
                             next_state @ self._zmp_row if self.params.pelvis_ground_at_zmp
                             else None)
        if planned:
            feet = (targets.left_foot, targets.right_foot)
            offsets = self._swing_start.update(
                self._dt, self._stance.held(support_next), self._stance.latched,
                np.array([feet[side][:2] for side in SIDES]))
            for side in SIDES:
                feet[side][:2] += offsets[side]
            if self._swing_retarget is not None and references is not None:
                for side, offset in enumerate(self._retarget_offsets(t, window, references,
                                                                     support_next)):
                    feet[side][:2] += offset
            smoothed = self._swing_smoothing.update(
                self._dt, self._stance.held(support_next), np.array([f[:3] for f in feet]))
            for side in SIDES:
                feet[side][:3] = smoothed[side]
        heights, targets.pelvis[2] = self._height_continuity.update(
            self._dt, self._stance.held(support_next),
            [targets.left_foot[2], targets.right_foot[2]], float(targets.pelvis[2]))
        targets.left_foot[2], targets.right_foot[2] = heights
        return targets

    def _retarget_offsets(self, t: float, window, references: CycleReferences,
                          support_next: int) -> np.ndarray:
        """The swing retarget's offsets of the targets at t + Ts (the window is valid: its
        references were read from it)."""
        feet = (np.asarray(window.left_foot, dtype=float),
                np.asarray(window.right_foot, dtype=float))
        after = min(2, feet[LEFT].shape[0] - 1)
        planned_after = np.array([feet[side][after, :2] for side in SIDES])
        if not np.all(np.isfinite(planned_after)):  # only samples 0 and 1 were checked
            planned_after = references.feet_next[:, :2]
        landings = [planned_landing(window, side, t, self._dt) for side in SIDES]
        return self._swing_retarget.update(
            t + self._dt, self._dt, self._stance.held(support_next), references.feet_next[:, :2],
            planned_after, [None if landing is None else landing[0] for landing in landings])

    def _stabilize(self, t: float, targets: IkTargets, sensed: SensedFeet, soles: tuple,
                   pelvis: np.ndarray, command: np.ndarray, estimate: _Estimate,
                   references: Optional[CycleReferences]) -> BalanceResult:
        """The stabilizer on the targets: the commanded state's DCM against the measured one.

        The measured DCM is the one of _measured_dcm. The Kalman estimate is not used here: it
        reads the ZMP the stabilizer itself moves, and fed back through the foot damping it
        oscillated standing.
        """
        reference = StabilizerReference(zmp=command @ self._zmp_row, dcm=self._dcm_of(command))
        com = np.array([estimate.com[0], estimate.com[1], self._com_height])
        planned = None
        if self.params.stabilizer_planned_support and references is not None:
            planned = tuple(on_support(side, references.support_now) for side in SIDES)
        return self._balance.update(t, self._dt, targets, sensed, soles, pelvis, reference,
                                    com, estimate.dcm, planned)

    def _solve_ik(self, targets: IkTargets, pelvis: np.ndarray, rotation: np.ndarray) -> _IkStep:
        """Joint setpoints of the targets, the pelvis moved by the servo and the posture lean."""
        pelvis_command = self._servo.command(targets.pelvis, pelvis)
        ik_status = (IK_REACHABLE, IK_REACHABLE)
        try:
            trunk = targets.trunk_tilt
            pelvis_rotation = rotation_z(targets.yaw) @ rotation_x(trunk[0]) @ \
                rotation_y(trunk[1]) @ posture_correction(rotation, self.params.tilt_gain)
            tilts = targets.foot_tilts
            correction = attitude_correction(pelvis_rotation, rotation,
                                             self.params.swing_attitude_gain)
            soles = []
            for side, foot in enumerate((targets.left_foot, targets.right_foot)):
                sole = (foot[:3], rotation_z(foot[3]) @ rotation_x(tilts[side, 0])
                        @ rotation_y(tilts[side, 1]))
                if self._swinging[side]:
                    sole = corrected_swing_target(*sole, pelvis_command, correction)
                soles.extend(sole)
            solution = self.ik.solve(pelvis_command, pelvis_rotation, *soles)
            q = np.array(solution.q, dtype=float)
            ik_status = tuple(int(s) for s in solution.status)
            if not np.all(np.isfinite(q)):
                raise InputError('IK returned non-finite angles')
        except Exception:  # noqa: B902 - keep the last setpoints rather than stop the loop
            return _IkStep(self._last_q, pelvis_command, ik_status, STATUS_IK_ERROR)
        return _IkStep(q, pelvis_command, ik_status,
                       STATUS_IK_CLIPPED if IK_CLIPPED in ik_status else STATUS_OK)

    def _output(self, status: int, feedback: ControllerFeedback, pelvis: np.ndarray,
                estimate: _Estimate, mpc: _MpcStep, next_state: np.ndarray,
                targets: IkTargets, ik: _IkStep, sensed: Optional[SensedFeet],
                balance: Optional[BalanceResult]) -> ControllerOutput:
        """The setpoints with their feed-forward speeds, and the cycle's diagnostics."""
        velocities = (ik.q - self._last_q) / self._dt
        self._last_q = ik.q.copy()
        terms = {}
        if balance is not None:
            diagnostics = balance.stabilizer.diagnostics
            terms = dict(zmp_desired=balance.stabilizer.zmp.copy(),
                         zmp_error=diagnostics.zmp_error.copy(),
                         dcm_error=diagnostics.dcm_error.copy(),
                         foot_torque_errors=diagnostics.torque_errors.copy(),
                         foot_contacts=tuple(sensed.contacts),
                         ankle_offsets=balance.stabilizer.ankle_offsets.copy(),
                         ankle_conformance=balance.conformance.copy(),
                         vertical_offsets=balance.stabilizer.vertical_offsets.copy(),
                         landing_modes=balance.landing_modes,
                         landing_depths=np.array(balance.landing_depths),
                         trunk_tilt=targets.trunk_tilt.copy(),
                         lift_held=balance.lift_held)
        return ControllerOutput(
            joint_setpoints=ik.q.copy(), joint_velocities=velocities, status=status,
            mpc_status=mpc.mpc_status, solve_time=mpc.solve_time, state=estimate.state,
            kalman_state=estimate.kalman, zmp_measured=feedback.zmp.copy(),
            zmp_estimated=estimate.state @ self._zmp_row,
            zmp_predicted=next_state @ self._zmp_row, measured_outputs=estimate.outputs,
            ik_status=ik.ik_status, pelvis_target=targets.pelvis,
            pelvis_command=ik.pelvis_command,
            hip_target=next_state[:, state_index(TORSO, POSITION)].copy(),
            left_foot_target=targets.left_foot, right_foot_target=targets.right_foot,
            pelvis_position=np.asarray(pelvis, dtype=float).copy(),
            stance=self._stance.standing, next_state=next_state.copy(),
            mpc_result=mpc.result, command_leash_shift=estimate.leash_shift,
            dcm_leash_shift=estimate.dcm_leash_shift, **terms)
