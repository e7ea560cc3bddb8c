"""The walking controller of one cycle: standing pose, masses to targets, fallbacks, bad input."""
import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest

from biped_mpc.controller_io import (
    ControllerFeedback, STATUS_IK_CLIPPED, STATUS_MPC_ERROR, STATUS_MPC_FALLBACK, STATUS_OK,
    STATUS_REFERENCE_ERROR)
from biped_mpc.controller_params import WalkingControllerParams
from biped_mpc.errors import ConfigError, InputError
from biped_mpc.ik_targets import feet_targets_from_masses
from biped_mpc.leg_ik import AnalyticLegIk
from biped_mpc.linear_model import LEFT_LEG, POSITION, RIGHT_LEG, state_index, TORSO
from biped_mpc.lipm_model import LipmParams
from biped_mpc.qp_backend import QpSolution, QpStatus
from biped_mpc.qp_backends import DaqpBackend
from biped_mpc.stance_feet import on_support
from biped_mpc.walking_controller import WalkingController
from biped_planner.footsteps import straight_footsteps
from biped_planner.rotations import quaternion_to_matrix, rotation_z
from biped_planner.sides import LEFT, RIGHT, SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference

PELVIS_HEIGHT = 0.54
COM_OFFSET = (0.0137, 0.0)  # m, the COMAN-like model's (robots/coman_like.yaml)
HALF_WIDTH = 0.07
N_SAMPLES = 81
DT = 0.02
T_START = 2.0  # the walk starts here: windows from t <= 0.3 s see only the standing pose


@pytest.fixture(scope='module')
def robot(coman_like_model):
    return coman_like_model


@pytest.fixture(scope='module')
def ik(robot):
    return AnalyticLegIk(robot.leg_geometry)


@pytest.fixture(scope='module')
def reference():
    params = ReferenceParams(com_height=0.497, swing_height=0.04, foot_length=0.2,
                             foot_width=0.1)
    return WalkingReference(straight_footsteps(4, 0.1, 2 * HALF_WIDTH),
                            StepTiming(single_support=0.4, double_support=0.2), params,
                            t_start=T_START)


@pytest.fixture(scope='module')
def controller(robot):
    return WalkingController(WalkingControllerParams(robot=robot))


def standing_pelvis():
    """Pelvis of a robot standing with its model hip (pelvis + COM offset) at the origin."""
    return np.array([-COM_OFFSET[0], -COM_OFFSET[1], PELVIS_HEIGHT])


def standing_feedback(ik, pelvis=None, with_position=True):
    """A robot at rest on both feet at (0, +-HALF_WIDTH), its joints from the IK."""
    pelvis = standing_pelvis() if pelvis is None else pelvis
    q = ik.solve(pelvis, np.eye(3), [0.0, HALF_WIDTH, 0.0], np.eye(3),
                 [0.0, -HALF_WIDTH, 0.0], np.eye(3)).q
    return ControllerFeedback(q, [0.0, 0.0, 0.0, 1.0], [0.0, 0.0], (True, True),
                              pelvis if with_position else None, np.zeros(3))


def test_standing_robot_gets_the_standing_ik_pose(controller, reference, ik):
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    for k in range(3):
        out = controller.step(k * DT, reference.sample(k * DT, N_SAMPLES, DT), feedback)
    assert out.status == STATUS_OK
    assert out.mpc_status == (int(QpStatus.OPTIMAL), int(QpStatus.OPTIMAL))
    np.testing.assert_allclose(out.joint_setpoints, feedback.leg_joint_positions, atol=1e-6)
    np.testing.assert_allclose(out.pelvis_target, standing_pelvis(), atol=1e-6)
    np.testing.assert_allclose(out.left_foot_target, [0.0, HALF_WIDTH, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(out.right_foot_target, [0.0, -HALF_WIDTH, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(out.joint_velocities, 0.0, atol=1e-4)
    assert np.all(np.isfinite(out.cost)) and np.all(out.cost >= 0.0)
    assert out.stance == (True, True)


def test_measured_outputs_are_leg_midpoints_and_the_ft_zmp(controller, reference, ik):
    feedback = dataclasses.replace(standing_feedback(ik), zmp=np.array([0.01, -0.02]))
    controller.reset(0.0, feedback)
    out = controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), feedback)
    # Model hip = pelvis + COM offset = origin; left sole (0, 0.07), right (0, -0.07).
    np.testing.assert_allclose(out.measured_outputs[:, 0], [0.0, HALF_WIDTH / 2], atol=1e-9)
    np.testing.assert_allclose(out.measured_outputs[:, 1], [0.0, -HALF_WIDTH / 2], atol=1e-9)
    np.testing.assert_allclose(out.measured_outputs[:, 2], [0.01, -0.02])
    np.testing.assert_allclose(out.zmp_measured, [0.01, -0.02])


def test_without_ft_contact_the_zmp_measurement_is_the_model_prediction(controller,
                                                                       reference, ik):
    feedback = dataclasses.replace(standing_feedback(ik), zmp=np.array([np.nan, np.nan]))
    controller.reset(0.0, feedback)
    out = controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), feedback)
    assert np.all(np.isfinite(out.measured_outputs))
    np.testing.assert_allclose(out.measured_outputs[:, 2], out.zmp_estimated, atol=1e-12)


def _single_support_time(reference, support):
    phase = next(p for p in reference.phases if p.support == support)
    return 0.5 * (phase.t_begin + phase.t_end)


@pytest.mark.parametrize('support', [SUPPORT_LEFT, SUPPORT_RIGHT])
def test_masses_map_to_pelvis_and_feet_targets(robot, reference, ik, support):
    # The paper's open-loop cycle: the swing foot from the leg masses.
    controller = WalkingController(WalkingControllerParams(robot=robot, balance='open_loop',
                                                           swing_target='masses'))
    t = _single_support_time(reference, support)
    feedback = standing_feedback(ik)
    controller.reset(t, feedback)
    window = reference.sample(t, N_SAMPLES, DT)
    assert window.support[0] == window.support[1] == support
    out = controller.step(t, window, feedback)
    state = out.next_state
    torso = state[:, state_index(TORSO, POSITION)]
    np.testing.assert_allclose(out.hip_target, torso)
    # Pelvis = torso mass minus the COM offset (feet headings 0), upright at pelvis height.
    np.testing.assert_allclose(out.pelvis_target[:2], torso - np.array(COM_OFFSET),
                               atol=1e-12)
    assert out.pelvis_target[2] == pytest.approx(PELVIS_HEIGHT)
    swing, stance = ((out.right_foot_target, out.left_foot_target) if support == SUPPORT_LEFT
                     else (out.left_foot_target, out.right_foot_target))
    swing_mass = RIGHT_LEG if support == SUPPORT_LEFT else LEFT_LEG
    swing_window = window.right_foot if support == SUPPORT_LEFT else window.left_foot
    # Swing foot = 2 * leg mass - hip, height and heading from the window at t + Ts.
    np.testing.assert_allclose(swing[:2], 2.0 * state[:, state_index(swing_mass, POSITION)]
                               - torso, atol=1e-12)
    assert swing[2] == pytest.approx(swing_window[1, 2])
    assert swing[3] == pytest.approx(0.0)
    # The stance foot stays where it was measured.
    stance_y = HALF_WIDTH if support == SUPPORT_LEFT else -HALF_WIDTH
    np.testing.assert_allclose(stance, [0.0, stance_y, 0.0, 0.0], atol=1e-9)


@pytest.mark.parametrize('support', [SUPPORT_LEFT, SUPPORT_RIGHT])
def test_a_planned_swing_target_aims_at_the_planned_trajectory(robot, reference, ik, support):
    controller = WalkingController(WalkingControllerParams(robot=robot, swing_target='planned'))
    t = _single_support_time(reference, support)
    feedback = standing_feedback(ik)
    controller.reset(t, feedback)
    window = reference.sample(t, N_SAMPLES, DT)
    out = controller.step(t, window, feedback)
    swing = out.right_foot_target if support == SUPPORT_LEFT else out.left_foot_target
    swing_window = window.right_foot if support == SUPPORT_LEFT else window.left_foot
    # The planned sole at t + Ts, not 2 * leg mass - hip (which lags it).
    np.testing.assert_allclose(swing[:3], swing_window[1], atol=1e-12)
    # Forward kinematics of the setpoints from the commanded pelvis reaches the targets.
    left_p, _, right_p, _ = ik.forward(out.joint_setpoints, out.pelvis_command, np.eye(3))
    np.testing.assert_allclose(left_p, out.left_foot_target[:3], atol=1e-9)
    np.testing.assert_allclose(right_p, out.right_foot_target[:3], atol=1e-9)
    assert out.stance == ((True, False) if support == SUPPORT_LEFT else (False, True))


def test_a_retargeted_swing_keeps_its_target_when_the_plan_moves_its_landing(robot, reference,
                                                                            ik):
    controller = WalkingController(WalkingControllerParams(
        robot=robot, balance='open_loop', swing_target='planned', swing_retarget=True,
        swing_start_time_constant=0.0, swing_smoothing_time_constant=0.0))
    t = _single_support_time(reference, SUPPORT_LEFT)   # the right foot swings
    feedback = standing_feedback(ik)
    controller.reset(t, feedback)
    first = reference.sample(t, N_SAMPLES, DT)
    controller.step(t, first, feedback)
    later = reference.sample(t + DT, N_SAMPLES, DT)
    moved = dataclasses.replace(later, right_foot=later.right_foot + [0.05, 0.0, 0.0])
    out = controller.step(t + DT, moved, feedback)
    # the target the first window planned for t + 2 Ts, not the moved plan's 5 cm ahead
    np.testing.assert_allclose(out.right_foot_target[:2], first.right_foot[2][:2], atol=1e-12)
    nan_later = dataclasses.replace(moved, right_foot=moved.right_foot.copy())
    nan_later.right_foot[5:] = np.nan   # only samples 0 and 1 are the cycle's
    out = controller.step(t + 2 * DT, nan_later, feedback)
    assert np.all(np.isfinite(out.right_foot_target))


def test_feet_targets_invert_the_mass_references():
    rng = np.random.default_rng(3)
    hip, left, right = rng.normal(size=(3, 5, 2))
    left_mass, right_mass = 0.5 * (left + hip), 0.5 * (right + hip)
    left_foot, right_foot = feet_targets_from_masses(hip, left_mass, right_mass)
    np.testing.assert_allclose(left_foot, left)
    np.testing.assert_allclose(right_foot, right)


def test_stance_leg_state_is_midway_between_its_sole_and_the_torso(controller, reference, ik):
    t = _single_support_time(reference, SUPPORT_LEFT)
    feedback = standing_feedback(ik)
    controller.reset(t, feedback)
    out = controller.step(t, reference.sample(t, N_SAMPLES, DT), feedback)
    torso = slice(state_index(TORSO, POSITION), state_index(TORSO, POSITION) + 3)
    left = slice(state_index(LEFT_LEG, POSITION), state_index(LEFT_LEG, POSITION) + 3)
    expected = 0.5 * out.state[:, torso]
    expected[:, 0] += 0.5 * np.array([0.0, HALF_WIDTH])
    np.testing.assert_allclose(out.state[:, left], expected, atol=1e-12)


def test_imu_kinematics_finds_the_pelvis_from_the_stance_feet(robot, reference, ik):
    controller = WalkingController(WalkingControllerParams(robot=robot,
                                                           pelvis_source='imu_kinematics'))
    controller.reset(0.0, standing_feedback(ik))
    moved = standing_pelvis() + np.array([0.01, -0.005, 0.0])
    feedback = standing_feedback(ik, pelvis=moved, with_position=False)
    out = controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), feedback)
    np.testing.assert_allclose(out.pelvis_position, moved, atol=1e-9)


@pytest.mark.parametrize('overrides', [dict(model='lipm'), dict(ik='pinocchio'),
                                       dict(feedback='estimator', feedback_gain=0.3),
                                       dict(tilt_gain=0.5)])
def test_variants_keep_the_standing_pose(robot, reference, ik, overrides, coman_like_urdf):
    robot = dataclasses.replace(robot, urdf_path=coman_like_urdf)
    controller = WalkingController(WalkingControllerParams(robot=robot, **overrides))
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    for k in range(3):
        out = controller.step(k * DT, reference.sample(k * DT, N_SAMPLES, DT), feedback)
    assert out.status == STATUS_OK
    np.testing.assert_allclose(out.joint_setpoints, feedback.leg_joint_positions, atol=1e-6)


def test_tilt_feedback_leans_the_pelvis_against_the_measured_tilt(robot, reference, ik):
    controller = WalkingController(WalkingControllerParams(robot=robot, tilt_gain=1.0))
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    roll = 0.02
    tilted = dataclasses.replace(feedback, pelvis_orientation=np.array(
        [math.sin(roll / 2), 0.0, 0.0, math.cos(roll / 2)]))
    out = controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), tilted)
    # The setpoints put the soles at their targets for a pelvis rolled by -roll.
    c, s = math.cos(-roll), math.sin(-roll)
    leaned = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    left_p, _, right_p, _ = ik.forward(out.joint_setpoints, out.pelvis_command, leaned)
    np.testing.assert_allclose(left_p, out.left_foot_target[:3], atol=1e-9)
    np.testing.assert_allclose(right_p, out.right_foot_target[:3], atol=1e-9)


def test_the_command_leash_brings_the_commanded_hip_to_a_pushed_robot(robot, reference, ik):
    """A robot pushed 5 cm sideways: with a 2 cm leash across the heading the commanded hip
    is moved 3 cm towards it (and the servos pull by 2 cm), without it the command stays."""
    pushed = standing_pelvis() + np.array([0.0, -0.05, 0.0])
    hips = {}
    for across in (0.0, 0.02):
        controller = WalkingController(WalkingControllerParams(
            robot=robot, command_leash_along=0.04, command_leash_across=across))
        controller.reset(0.0, standing_feedback(ik))
        out = controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT),
                              standing_feedback(ik, pelvis=pushed))
        hips[across] = out.hip_target
        expected = [0.0, 0.03] if across else [0.0, 0.0]
        np.testing.assert_allclose(out.command_leash_shift, expected, atol=1e-9)
    # standing still, the MPC moves the commanded hip by micrometres in one period
    assert hips[0.0][1] == pytest.approx(0.0, abs=1e-3)
    assert hips[0.02][1] == pytest.approx(-0.03, abs=1e-3)


def test_a_step_adjustment_brings_the_commanded_dcm_to_the_measured_one_once(robot, reference,
                                                                              ik):
    """A robot pushed sideways at 0.5 m/s: at the walk's first step adjustment the MPC starts
    from a DCM on the 5 cm circle around the measured one (through the velocities, the
    positions as without); without one the command keeps its own DCM, 9.6 cm from the
    measured one; the next cycle, with no new adjustment, the command runs on its own."""
    moved = np.array([0.0, -0.01, 0.0])
    lipm = LipmParams.from_three_mass(robot.masses)
    omega = math.sqrt(lipm.gravity / lipm.com_height)
    outs = {}
    for adjustments in (0, 1):
        controller = WalkingController(WalkingControllerParams(robot=robot,
                                                               adjusted_walk_dcm_leash=0.05))
        controller.reset(0.0, standing_feedback(ik))
        controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), standing_feedback(ik))
        controller.walk_adjustments = adjustments
        outs[adjustments] = controller.step(DT, reference.sample(DT, N_SAMPLES, DT),
                                            standing_feedback(ik, standing_pelvis() + moved))
        after = controller.step(2 * DT, reference.sample(2 * DT, N_SAMPLES, DT),
                                standing_feedback(ik, standing_pelvis() + 2 * moved))
        np.testing.assert_allclose(after.dcm_leash_shift, 0.0)
    masses = controller.model.masses
    # the measured centre of mass: legs midway between their soles and the moved hip
    com = (masses[1] + 0.5 * (masses[0] + masses[2])) / sum(masses) * moved[:2]
    measured = com + (com / DT) / omega
    row = controller.model.com_row

    def dcm(state):
        return state @ row + state @ np.roll(row, 1) / omega
    assert np.linalg.norm(dcm(outs[0].state) - measured) > 0.08
    np.testing.assert_allclose(outs[0].dcm_leash_shift, 0.0)
    assert np.linalg.norm(dcm(outs[1].state) - measured) == pytest.approx(0.05, abs=1e-9)
    assert np.linalg.norm(outs[1].dcm_leash_shift) == pytest.approx(
        np.linalg.norm(dcm(outs[0].state) - measured) - 0.05, abs=1e-6)
    for mass in (LEFT_LEG, TORSO, RIGHT_LEG):
        column = state_index(mass, POSITION)
        np.testing.assert_allclose(outs[1].state[:, column], outs[0].state[:, column],
                                   atol=1e-12)


def test_failed_qp_falls_back_to_the_previous_plan(controller, reference, ik, monkeypatch):
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), feedback)

    def infeasible(self, linear, lower, upper):
        return QpSolution(np.zeros(self.n_variables), QpStatus.INFEASIBLE, 3, 0.0)

    monkeypatch.setattr(DaqpBackend, 'solve', infeasible)
    out = controller.step(DT, reference.sample(DT, N_SAMPLES, DT), feedback)
    assert out.status & STATUS_MPC_FALLBACK
    assert out.mpc_status == (int(QpStatus.INFEASIBLE), int(QpStatus.INFEASIBLE))
    assert np.all(np.isnan(out.cost))
    assert np.all(np.isfinite(out.joint_setpoints))
    np.testing.assert_allclose(out.joint_setpoints, feedback.leg_joint_positions, atol=1e-5)


def test_mpc_exception_coasts_with_zero_jerk(controller, reference, ik, monkeypatch):
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)

    def broken(*args, **kwargs):
        raise RuntimeError('solver crashed')

    monkeypatch.setattr(controller.mpc, 'solve', broken)
    out = controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), feedback)
    assert out.status & STATUS_MPC_ERROR
    np.testing.assert_allclose(out.next_state, out.state @ controller.discrete_model.a.T)
    np.testing.assert_allclose(out.joint_setpoints, feedback.leg_joint_positions, atol=1e-9)


def test_malformed_window_is_a_status_not_an_exception(controller, reference, ik):
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    window = reference.sample(0.0, N_SAMPLES, DT)
    swapped = dataclasses.replace(window, zmp_min=window.zmp_max, zmp_max=window.zmp_min)
    out = controller.step(0.0, swapped, feedback)
    assert out.status & STATUS_REFERENCE_ERROR
    assert out.mpc_result is None
    np.testing.assert_allclose(out.joint_setpoints, feedback.leg_joint_positions, atol=1e-9)
    out = controller.step(0.0, SimpleNamespace(), feedback)
    assert out.status & STATUS_REFERENCE_ERROR


def test_unreachable_target_is_clipped(robot, reference, ik):
    """A pelvis 0.9 m above the soles is beyond the 0.5 m legs: clipped, not an error."""
    controller = WalkingController(WalkingControllerParams(
        robot=dataclasses.replace(robot, pelvis_height=0.9)))
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    out = controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), feedback)
    assert out.status & STATUS_IK_CLIPPED
    assert np.all(np.isfinite(out.joint_setpoints))
    np.testing.assert_allclose(out.joint_setpoints[[3, 9]], 0.0, atol=1e-9)  # straight knees


def test_pelvis_servo_moves_the_command_by_the_velocity_error(robot, reference, ik):
    """command = target + gain (target motion - pelvis motion) over two periods / (2 Ts)."""
    gain = 0.05
    controller = WalkingController(WalkingControllerParams(robot=robot,
                                                           pelvis_velocity_gain=gain))
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    controller.step(0.0, reference.sample(0.0, N_SAMPLES, DT), feedback)
    moved = standing_pelvis() + np.array([0.002, -0.001, 0.0])
    controller.step(DT, reference.sample(DT, N_SAMPLES, DT), standing_feedback(ik, pelvis=moved))
    out = controller.step(2 * DT, reference.sample(2 * DT, N_SAMPLES, DT),
                          standing_feedback(ik, pelvis=moved))
    # The standing target stays at the reset pelvis; the pelvis moved over the last two periods.
    np.testing.assert_allclose(out.pelvis_target, standing_pelvis(), atol=1e-9)
    expected = gain * (0.0 - (moved[:2] - standing_pelvis()[:2])) / (2 * DT)
    np.testing.assert_allclose(out.pelvis_command[:2] - out.pelvis_target[:2], expected,
                               atol=1e-8)
    assert out.pelvis_command[2] == out.pelvis_target[2]


def test_short_window_repeats_its_last_sample(controller, reference, ik):
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    out = controller.step(0.0, reference.sample(0.0, 10, DT), feedback)
    assert out.status == STATUS_OK


@pytest.mark.parametrize('overrides', [
    dict(robot=object()), dict(model='pendulum'), dict(feedback='kalman'),
    dict(pelvis_source='gps'), dict(ik='numeric'), dict(feedback_gain=-0.1),
    dict(feedback_gain=1.5), dict(feedback_gain=math.nan), dict(pelvis_velocity_gain=-0.01),
    dict(pelvis_velocity_gain=2.0), dict(tilt_gain=-1.0), dict(tilt_gain=6.0), dict(mpc=None),
    dict(estimator={}), dict(stance_leg_projection=1)])
def test_bad_parameters_are_rejected(robot, overrides):
    kwargs = dict(robot=robot)
    kwargs.update(overrides)
    with pytest.raises(ConfigError):
        WalkingControllerParams(**kwargs)


@pytest.mark.parametrize('overrides', [
    dict(pelvis_height=0.0), dict(pelvis_height=math.inf), dict(com_offset=(1.0, 0.0)),
    dict(com_offset=(math.nan, 0.0)), dict(com_offset=(0.0,)), dict(masses=(1.0, 2.0, 3.0))])
def test_bad_robot_models_are_rejected(robot, overrides):
    """The robot's masses, pelvis height and COM offset come from its model and are checked
    there."""
    with pytest.raises(ConfigError):
        WalkingControllerParams(robot=dataclasses.replace(robot, **overrides))


def test_analytic_ik_needs_a_leg_geometry_and_pinocchio_a_urdf(robot, coman_like_urdf):
    without = dataclasses.replace(robot, leg_geometry=None, urdf_path=coman_like_urdf)
    with pytest.raises(ConfigError):
        WalkingControllerParams(robot=without)
    WalkingControllerParams(robot=without, ik='pinocchio')
    with pytest.raises(ConfigError, match='urdf_path'):
        WalkingControllerParams(robot=dataclasses.replace(robot, urdf_path=''), ik='pinocchio')


def test_controller_needs_its_parameters():
    with pytest.raises(ConfigError):
        WalkingController(SimpleNamespace())


GOOD = dict(leg_joint_positions=np.zeros(12), pelvis_orientation=[0.0, 0.0, 0.0, 1.0],
            zmp=[0.0, 0.0], contacts=(True, True))


@pytest.mark.parametrize('overrides', [
    dict(leg_joint_positions=np.zeros(11)), dict(leg_joint_positions=np.full(12, np.nan)),
    dict(pelvis_orientation=[0.0, 0.0, 1.0]), dict(pelvis_orientation=[0.0, 0.0, 0.0, 0.0]),
    dict(pelvis_orientation=[np.inf, 0.0, 0.0, 1.0]), dict(zmp=[np.inf, 0.0]), dict(zmp=[0.0]),
    dict(contacts=(True,)), dict(pelvis_position=[0.0, 0.0]),
    dict(pelvis_position=[0.0, np.nan, 0.5]), dict(pelvis_linear_velocity=[np.inf, 0.0, 0.0])])
def test_bad_feedback_is_rejected(overrides):
    kwargs = dict(GOOD)
    kwargs.update(overrides)
    with pytest.raises(InputError):
        ControllerFeedback(**kwargs)


def test_feedback_normalises_the_quaternion_and_allows_a_missing_zmp():
    feedback = ControllerFeedback(**dict(GOOD, pelvis_orientation=[0.0, 0.0, 0.0, 2.0],
                                         zmp=[np.nan, np.nan]))
    np.testing.assert_allclose(feedback.pelvis_orientation, [0.0, 0.0, 0.0, 1.0])
    np.testing.assert_allclose(quaternion_to_matrix(feedback.pelvis_orientation), np.eye(3))


def _readings():
    joints = SimpleNamespace(position=np.arange(23, dtype=float) * 0.01)
    base = SimpleNamespace(position=np.array([0.1, 0.2, 0.5]),
                           orientation=np.array([0.0, 0.0, 0.0, 1.0]),
                           linear_velocity=np.array([0.3, 0.0, 0.0]))
    imu = SimpleNamespace(orientation=np.array([0.0, 0.0, math.sin(0.1), math.cos(0.1)]))
    return SimpleNamespace(joints=joints, base=base, imu=imu, zmp=np.array([0.05, 0.0]),
                           left_foot=SimpleNamespace(in_contact=True),
                           right_foot=SimpleNamespace(in_contact=False))


def test_feedback_from_readings_by_source():
    truth = ControllerFeedback.from_readings(_readings(), 'ground_truth')
    np.testing.assert_allclose(truth.leg_joint_positions, np.arange(12) * 0.01)
    np.testing.assert_allclose(truth.pelvis_position, [0.1, 0.2, 0.5])
    assert truth.contacts == (True, False)
    imu = ControllerFeedback.from_readings(_readings(), 'imu_kinematics')
    assert imu.pelvis_position is None
    np.testing.assert_allclose(imu.pelvis_orientation, [0.0, 0.0, math.sin(0.1),
                                                        math.cos(0.1)])
    with pytest.raises(InputError):
        ControllerFeedback.from_readings(_readings(), 'lidar')


def test_step_rejects_bad_calls(robot, reference, ik):
    controller = WalkingController(WalkingControllerParams(robot=robot))
    feedback = standing_feedback(ik)
    window = reference.sample(0.0, N_SAMPLES, DT)
    with pytest.raises(InputError):
        controller.step(0.0, window, feedback)  # before reset
    with pytest.raises(InputError):
        controller.reset(math.nan, feedback)
    with pytest.raises(InputError):
        controller.reset(0.0, 'feedback')
    controller.reset(0.0, feedback)
    with pytest.raises(InputError):
        controller.step(math.inf, window, feedback)
    with pytest.raises(InputError):
        controller.step(0.0, window, feedback.leg_joint_positions)


def test_support_labels_put_their_feet_on_the_ground():
    assert on_support(LEFT, SUPPORT_LEFT) and not on_support(RIGHT, SUPPORT_LEFT)
    assert on_support(RIGHT, SUPPORT_RIGHT) and not on_support(LEFT, SUPPORT_RIGHT)
    assert on_support(LEFT, SUPPORT_DOUBLE) and on_support(RIGHT, SUPPORT_DOUBLE)


def test_yaw_of_feet_turns_the_pelvis(controller, reference, ik):
    feedback = standing_feedback(ik)
    controller.reset(0.0, feedback)
    window = reference.sample(0.0, N_SAMPLES, DT)
    turned = dataclasses.replace(window, left_yaw=np.full(N_SAMPLES, 0.2),
                                 right_yaw=np.full(N_SAMPLES, 0.2))
    out = controller.step(0.0, turned, feedback)
    # Both feet are latched (standing): they keep heading 0, the pelvis turns to 0.2.
    _, left_r, _, _ = ik.forward(out.joint_setpoints, out.pelvis_command, rotation_z(0.2))
    np.testing.assert_allclose(left_r, np.eye(3), atol=1e-9)
