"""Closed-loop walking of the PyBullet humanoid: references -> walking controller -> physics.

Headless, a few seconds of simulated time each. The walks use the configuration that walked
(docs/simulator_notes.md): torque control with leg_kp 2000 (capped per joint),
setpoints ramped over 4 parts of the period, 0.4 s single and 0.2 s double support, 4 cm swing
height, the controller's defaults (feedback 'prediction', pelvis velocity servo, posture
feedback).
"""
import math

import numpy as np
import pytest

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.omnidirectional_stepper import OmnidirectionalStepper, StepCommand
from biped_planner.pose2d import Pose2D
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference
from biped_sim.closed_loop import ClosedLoopParams, ClosedLoopRunner
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.model_plant_backend import ModelPlantBackend, ModelPlantBackendParams
from biped_sim.reference_sources import CommandedWalk, PlannedWalk
from biped_sim.run_log import RunLog

TIMING = StepTiming(single_support=0.4, double_support=0.2)
REFERENCE = ReferenceParams(com_height=0.497, swing_height=0.04, foot_length=0.2,
                            foot_width=0.1)
STEP_WIDTH = 0.14
T_START = 0.5
PELVIS_FLOOR = 0.45  # m: the pelvis stands at 0.54 m
MAX_TILT = math.radians(10.0)


@pytest.fixture(scope='module')
def controller(robot):
    return WalkingController(WalkingControllerParams(robot=robot.controller_model))


def walk(sim, controller, n_steps, step_length, extra=1.0, **params):
    footsteps = straight_footsteps(n_steps, step_length, STEP_WIDTH)
    reference = WalkingReference(footsteps, TIMING, REFERENCE, t_start=T_START)
    runner = ClosedLoopRunner(sim, controller, reference, params=ClosedLoopParams(**params))
    runner.reset()
    log = runner.run(reference.t_end + extra)
    return log, footsteps


def assert_upright(log: RunLog) -> None:
    assert not log.fallen, f'fell at {log.fall_time} s'
    assert log.base_position[:, 2].min() > PELVIS_FLOOR
    assert log.tilt.max() < MAX_TILT


def single_support_inside(log: RunLog) -> float:
    single = log.support != 2
    return float(log.zmp_inside_support()[single].mean())


def test_standing_still_for_three_seconds(sim, controller):
    reference = WalkingReference(straight_footsteps(0, 0.0, STEP_WIDTH), TIMING, REFERENCE,
                                 t_start=100.0)
    runner = ClosedLoopRunner(sim, controller, reference)
    runner.reset()
    log = runner.run(3.0)
    assert log.t.size == 150
    assert_upright(log)
    assert log.tilt.max() < math.radians(1.0)
    assert np.all(log.contacts[10:])
    assert log.zmp_inside_support()[1:].mean() == 1.0  # no contact force before the first step
    # The centre of mass settles above the middle of the feet (the reference hip).
    np.testing.assert_allclose(log.com[-1, :2], [0.0, 0.0], atol=0.005)
    assert np.ptp(log.base_position[-50:, :2], axis=0).max() < 1e-3
    assert np.all(log.mpc_status == 0)


def test_walking_in_place_ten_steps(sim, controller):
    log, footsteps = walk(sim, controller, 10, 0.0)
    assert_upright(log)
    # Ten steps alternate single supports: 11 single support phases (with the closing step).
    starts = np.flatnonzero(np.diff((log.support != 2).astype(int)) == 1)
    assert starts.size == 11
    inside = single_support_inside(log)
    assert inside >= 0.9, f'ZMP inside the stance foot in {inside:.0%} of single support'
    np.testing.assert_allclose(log.com[-1, :2], [0.0, 0.0], atol=0.02)
    np.testing.assert_allclose(log.left_sole[-1, :2], [0.0, 0.07], atol=0.03)
    np.testing.assert_allclose(log.right_sole[-1, :2], [0.0, -0.07], atol=0.03)


def test_walking_forward_twenty_steps_of_ten_centimetres(sim, controller):
    log, footsteps = walk(sim, controller, 20, 0.1)
    assert_upright(log)
    inside = single_support_inside(log)
    assert inside >= 0.9, f'ZMP inside the stance foot in {inside:.0%} of single support'
    final = 0.5 * np.array([footsteps[-1].x + footsteps[-2].x,
                            footsteps[-1].y + footsteps[-2].y])
    np.testing.assert_allclose(final, [2.0, 0.0])
    np.testing.assert_allclose(log.com[-1, :2], final, atol=0.03)
    np.testing.assert_allclose(log.left_sole[-1, :2], [2.0, 0.07], atol=0.03)
    np.testing.assert_allclose(log.right_sole[-1, :2], [2.0, -0.07], atol=0.03)
    # The measured ZMP follows the reference: within the foot half-length on average.
    error = np.abs(log.zmp_measured - log.zmp_reference)
    assert np.nanmean(error[:, 0]) < 0.05 and np.nanmean(error[:, 1]) < 0.03
    assert np.mean(log.mpc_status == 0) > 0.99


def test_push_passes_through_to_the_backend(sim, controller):
    reference = WalkingReference(straight_footsteps(0, 0.0, STEP_WIDTH), TIMING, REFERENCE,
                                 t_start=100.0)
    runner = ClosedLoopRunner(sim, controller, reference)
    runner.reset()
    calm = runner.run(0.6)
    runner.reset()
    runner.push(ExternalPush(force=(60.0, 0.0, 0.0), duration=0.1, start_time=0.2))
    pushed = runner.run(0.6)
    # 60 N for 0.1 s on 31 kg is 0.19 m/s of centre-of-mass velocity if nothing resisted;
    # the stiff joints hold the robot, which still leans a few millimetres forward.
    lean = pushed.com[:, 0] - calm.com[:, 0]
    assert np.all(np.abs(lean[pushed.t < 0.2]) < 5e-4)  # resets replay a run closely
    assert lean.max() > 0.002
    assert not pushed.fallen


def test_fall_is_detected_and_ends_the_run(sim, controller):
    reference = WalkingReference(straight_footsteps(0, 0.0, STEP_WIDTH), TIMING, REFERENCE,
                                 t_start=100.0)
    runner = ClosedLoopRunner(sim, controller, reference)
    runner.reset()
    runner.push(ExternalPush(force=(0.0, 600.0, 0.0), duration=0.2, start_time=0.1))
    log = runner.run(3.0)
    assert log.fallen
    assert log.t.size < 150
    assert 0.1 < log.fall_time < 3.0


def test_commanded_walk_keeps_its_plan_ahead_and_moves_forward(robot):
    backend = ModelPlantBackend(robot, ModelPlantBackendParams())
    controller = WalkingController(WalkingControllerParams(robot=robot.controller_model,
                                                           pelvis_velocity_gain=0.0))

    def command(t):
        return StepCommand(0.1 if t > 2.0 else 0.0, 0.0, 0.0)

    source = CommandedWalk(OmnidirectionalStepper(Pose2D(0.0, 0.0, 0.0)), TIMING, REFERENCE,
                           command, WalkingReference, steps_ahead=2, t_start=T_START)
    runner = ClosedLoopRunner(backend, controller, source)
    runner.reset()
    ahead = []
    runner.run(6.0, on_cycle=lambda t, window, output, readings: ahead.append(
        source.reference.n_steps - int(window.step_index[0])))
    assert min(ahead) >= 2
    # Walking in place until 2 s, then 0.1 m steps (lag filtered): the robot has moved on.
    assert runner.readings.com_position[0] > 0.3


def test_zmp_inside_support_against_hand_made_cases():
    n = 4
    log = RunLog(
        t=np.arange(n) * 0.02, base_position=np.zeros((n, 3)),
        base_orientation=np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)), com=np.zeros((n, 3)),
        zmp_measured=np.array([[0.09, 0.07], [0.11, 0.07], [0.05, 0.0], [np.nan, np.nan]]),
        zmp_reference=np.zeros((n, 2)), zmp_min=np.zeros((n, 2)), zmp_max=np.zeros((n, 2)),
        hip_reference=np.zeros((n, 2)), left_sole=np.tile([0.0, 0.07, 0.0], (n, 1)),
        right_sole=np.tile([0.1, -0.07, 0.0], (n, 1)), feet_yaw=np.zeros((n, 2)),
        contacts=np.array([[True, False], [True, False], [True, True], [True, True]]),
        support=np.zeros(n, dtype=np.uint8), solve_time=np.zeros(n),
        mpc_status=np.zeros((n, 2), dtype=int), controller_status=np.zeros(n, dtype=int),
        time_references=np.zeros(n), time_controller=np.zeros(n), time_physics=np.zeros(n))
    # Left foot alone spans x in [-0.1, 0.1]: 0.09 in, 0.11 out. Both feet: the hull of the
    # left box and the right box 0.1 ahead contains (0.05, 0); no ZMP is outside.
    np.testing.assert_array_equal(log.zmp_inside_support(), [True, False, True, False])
    np.testing.assert_array_equal(log.zmp_inside_support(margin=0.02),
                                  [True, True, True, False])
    assert log.tilt.max() == 0.0


def test_the_longest_flight_counts_cycles_in_a_row_without_a_foot_on_the_ground():
    log = RunLog.empty(10)
    log.t[:] = np.arange(10) * 0.02
    on = [True, False, False, True, False, False, False, True, False, True]  # a foot down
    log.contacts[:, 1] = on
    assert log.longest_flight() == pytest.approx(0.06)      # cycles 4-6
    assert log.longest_flight(0.0, 0.08) == pytest.approx(0.04)  # cycles 1-2
    assert log.longest_flight(0.14) == pytest.approx(0.02)  # cycle 8
    log.contacts[:, 0] = True
    assert log.longest_flight() == 0.0


def test_setpoints_are_sent_as_a_ramp_over_the_period(robot):
    backend = ModelPlantBackend(robot)
    controller = WalkingController(WalkingControllerParams(robot=robot.controller_model))
    reference = WalkingReference(straight_footsteps(2, 0.1, STEP_WIDTH), TIMING, REFERENCE,
                                 t_start=0.0)
    runner = ClosedLoopRunner(backend, controller, reference,
                              params=ClosedLoopParams(setpoint_interpolation=4))
    runner.reset()
    calls, outputs = [], []
    step = backend.step

    def spy(setpoints, n_substeps=None, joint_velocities=None, read_sensors=True):
        calls.append((np.array(setpoints), n_substeps, read_sensors))
        return step(setpoints, n_substeps, joint_velocities, read_sensors)

    backend.step = spy
    runner.run(0.04, on_cycle=lambda t, window, output, readings: outputs.append(output))
    # First cycle: no previous setpoints, one call; second: four calls of 5 physics steps
    # on the straight line from the first setpoints to the second.
    assert [n for _, n, _ in calls] == [20, 5, 5, 5, 5]
    # only the end of a period is read out: intermediate sensor readouts would be wasted
    assert [read for _, _, read in calls] == [True, False, False, False, True]
    first, second = outputs[0].joint_setpoints, outputs[1].joint_setpoints
    for part, (setpoints, _, _) in enumerate(calls[1:], start=1):
        np.testing.assert_allclose(setpoints, first + (second - first) * part / 4, atol=1e-12)
    np.testing.assert_allclose(calls[-1][0], second)


@pytest.mark.parametrize('overrides', [
    dict(control_period=0.0), dict(control_period=math.nan), dict(fall_height=-1.0),
    dict(fall_tilt=0.0), dict(fall_tilt=4.0), dict(pelvis_source='gps'),
    dict(setpoint_interpolation=0), dict(setpoint_interpolation=21),
    dict(setpoint_interpolation=2.0), dict(setpoint_interpolation=True)])
def test_bad_runner_parameters_are_rejected(overrides):
    with pytest.raises(ConfigError):
        ClosedLoopParams(**overrides)


def test_runner_rejects_bad_setups(robot):
    backend = ModelPlantBackend(robot)
    controller = WalkingController(WalkingControllerParams(robot=robot.controller_model))
    reference = WalkingReference(straight_footsteps(0, 0.0, STEP_WIDTH), TIMING, REFERENCE)
    with pytest.raises(ConfigError):
        ClosedLoopRunner(backend, controller, reference,
                         params=ClosedLoopParams(control_period=0.0215))
    with pytest.raises(ConfigError):
        ClosedLoopRunner(backend, controller, reference, params={'control_period': 0.02})
    with pytest.raises(ConfigError):
        PlannedWalk(object())
    runner = ClosedLoopRunner(backend, controller, reference)
    for duration in (-1.0, math.inf, True):
        with pytest.raises(ConfigError):
            runner.run(duration)
    assert runner.run(0.0).t.size == 0
