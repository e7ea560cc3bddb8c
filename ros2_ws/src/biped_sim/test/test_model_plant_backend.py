"""The three-mass model plant as a SimulatorBackend: kinematics, servo, contacts, pushes, and
closed-loop walking with the walking controller."""
import dataclasses
import math

import numpy as np
import pytest

from biped_mpc.leg_ik import AnalyticLegIk
from biped_mpc.linear_model import POSITION, state_index
from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference
from biped_sim.backend import SimulatorBackend
from biped_sim.closed_loop import ClosedLoopParams, ClosedLoopRunner
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.model_plant import PlantParams
from biped_sim.model_plant_backend import ModelPlantBackend, ModelPlantBackendParams
from biped_sim.model_plant_servo import placement_gain
from biped_sim.robot_description import coman_like

PARAMS = ModelPlantBackendParams()
OFFSET = np.array(PARAMS.com_offset)
MASSES = np.array([6.65, 17.65, 6.65])
TORSO = state_index(1, POSITION)


@pytest.fixture(scope='module')
def robot():
    return coman_like()


@pytest.fixture(scope='module')
def ik(robot):
    return AnalyticLegIk(robot.leg_geometry)


@pytest.fixture
def plant(robot):
    return ModelPlantBackend(robot)


def setpoints(ik, pelvis, left=(0.0, 0.07, 0.0), right=(0.0, -0.07, 0.0)):
    return ik.solve(np.asarray(pelvis, float), np.eye(3), np.asarray(left, float), np.eye(3),
                    np.asarray(right, float), np.eye(3)).q


def positions(plant):
    """(2, 3) positions of the left leg, torso and right leg masses."""
    return plant.plant.state[:, [state_index(m, POSITION) for m in range(3)]]


def test_reset_stands_on_both_feet_at_rest(plant, robot):
    assert isinstance(plant, SimulatorBackend)
    readings = plant.reset()
    assert readings.time == 0.0 and plant.time_step == 0.001
    assert plant.joint_names == robot.leg_joint_names == plant.leg_joint_names
    np.testing.assert_allclose(readings.base.position, [0.0, 0.0, 0.54])
    np.testing.assert_allclose(readings.left_sole, [0.0, 0.07, 0.0], atol=1e-12)
    np.testing.assert_allclose(readings.right_sole, [0.0, -0.07, 0.0], atol=1e-12)
    np.testing.assert_allclose(readings.joints.position, robot.nominal_leg_positions(),
                               atol=1e-9)
    # Legs midway between the soles and the model hip (pelvis + COM offset); ZMP = COM at rest.
    hip = OFFSET
    expected = np.stack([0.5 * (np.array([0.0, 0.07]) + hip), hip,
                         0.5 * (np.array([0.0, -0.07]) + hip)], axis=1)
    np.testing.assert_allclose(positions(plant), expected, atol=1e-12)
    com = expected @ MASSES / MASSES.sum()
    np.testing.assert_allclose(readings.zmp, com, atol=1e-12)
    np.testing.assert_allclose(readings.com_position[:2], com, atol=1e-12)
    assert readings.left_foot.in_contact and readings.right_foot.in_contact
    weight = MASSES.sum() * 9.81
    total = readings.left_foot.ground_force[2] + readings.right_foot.ground_force[2]
    assert total == pytest.approx(weight)
    np.testing.assert_allclose(readings.imu.linear_acceleration, [0.0, 0.0, 9.81])


def test_reset_at_a_pose_and_heading(plant):
    readings = plant.reset(base_position=np.array([1.0, -0.5, 0.9]), base_yaw=0.3)
    np.testing.assert_allclose(readings.base.position, [1.0, -0.5, 0.54])
    np.testing.assert_allclose(readings.base.orientation,
                               [0.0, 0.0, math.sin(0.15), math.cos(0.15)])
    midpoint = 0.5 * (readings.left_sole + readings.right_sole)
    np.testing.assert_allclose(midpoint[:2], [1.0, -0.5], atol=1e-12)


def test_standing_setpoints_keep_the_plant_still(plant, robot):
    plant.reset()
    before = plant.plant.state
    for _ in range(50):
        readings = plant.step(robot.nominal_leg_positions())
    assert readings.time == pytest.approx(1.0)
    np.testing.assert_allclose(plant.plant.state, before, atol=1e-12)


@pytest.mark.parametrize('pole', [0.0, 0.3, 0.5])
def test_placement_gain_puts_every_eigenvalue_at_the_pole(pole):
    h = 0.02
    a = np.array([[1.0, h, h * h / 2.0], [0.0, 1.0, h], [0.0, 0.0, 1.0]])
    b = np.array([h ** 3 / 6.0, h * h / 2.0, h])
    closed = a - np.outer(b, placement_gain(a, b, pole))
    # Characteristic polynomial (z - pole)^3.
    np.testing.assert_allclose(np.poly(closed), np.poly([pole] * 3), atol=1e-9)


def test_masses_follow_a_moved_pelvis_and_the_zmp_leads_the_other_way(plant, ik):
    readings = plant.reset()
    zmp0 = readings.zmp.copy()
    q = setpoints(ik, [0.01, 0.0, 0.54])
    first = plant.step(q)
    # To accelerate the torso forward, the ZMP moves backward (eq. zmp: -z/g c'').
    assert first.zmp[0] < zmp0[0] - 0.005
    for _ in range(60):
        readings = plant.step(q)
    hip = np.array([0.01, 0.0]) + OFFSET
    np.testing.assert_allclose(positions(plant)[:, 1], hip, atol=1e-6)
    np.testing.assert_allclose(positions(plant)[:, 0], 0.5 * (hip + [0.0, 0.07]), atol=1e-6)
    np.testing.assert_allclose(readings.base.position, [0.01, 0.0, 0.54], atol=1e-6)
    np.testing.assert_allclose(readings.joints.position, q, atol=1e-5)


def test_lifted_foot_leaves_the_ground_and_lands_again(plant, ik):
    plant.reset()
    # Stand over the right foot first so the ZMP can stay in it.
    over_right = setpoints(ik, [0.0, -0.07, 0.54] - np.append(OFFSET, 0.0))
    for _ in range(60):
        plant.step(over_right)
    lifted = setpoints(ik, [0.0, -0.07, 0.54] - np.append(OFFSET, 0.0),
                       left=(0.0, 0.07, 0.03))
    readings = plant.step(lifted)
    assert not readings.left_foot.in_contact and readings.right_foot.in_contact
    assert readings.left_sole[2] == pytest.approx(0.03, abs=1e-9)
    assert abs(readings.zmp[1] + 0.07) <= 0.05
    assert readings.left_foot.ground_force[2] == 0.0
    assert np.all(np.isnan(readings.left_foot.cop))
    readings = plant.step(over_right)
    assert readings.left_foot.in_contact
    np.testing.assert_allclose(readings.left_sole, [0.0, 0.07, 0.0], atol=1e-3)


def test_push_moves_the_torso_and_the_servo_brings_it_back(plant, robot):
    plant.reset()
    q = robot.nominal_leg_positions()
    plant.push(ExternalPush(force=(100.0, -50.0, 0.0), duration=0.1, start_time=0.2))
    torso = []
    for _ in range(50):
        plant.step(q)
        torso.append(positions(plant)[:, 1].copy())
    torso = np.array(torso) - OFFSET
    assert np.all(np.abs(torso[:10]) < 1e-12)  # before the push
    assert torso[:, 0].max() > 1e-4 and torso[:, 1].min() < -5e-5
    np.testing.assert_allclose(torso[-1], 0.0, atol=1e-6)


def test_output_noise_reaches_the_zmp_only(robot):
    noisy = ModelPlantBackend(robot, ModelPlantBackendParams(noise=PlantParams(
        noise_std=0.01, noise_bound=0.05, seed=3)))
    quiet = ModelPlantBackend(robot)
    a, b = noisy.reset(), quiet.reset()
    assert np.abs(a.zmp - b.zmp).max() > 1e-4
    np.testing.assert_allclose(a.base.position, b.base.position)


def walk(robot, n_steps, step_length, **controller):
    backend = ModelPlantBackend(robot)
    # The paper's feed-forward cycle: the model plant measures no contact torques for the
    # stabilizer's foot damping.
    controller = WalkingController(WalkingControllerParams(
        robot=robot.controller_model, pelvis_velocity_gain=0.0, tilt_gain=0.0,
        balance='open_loop', swing_target='masses', **controller))
    footsteps = straight_footsteps(n_steps, step_length, 0.14)
    reference = WalkingReference(footsteps, StepTiming(0.4, 0.2), ReferenceParams(
        com_height=0.497, foot_length=0.2, foot_width=0.1), t_start=0.5)
    # The plant's servo follows its targets at the control period: no setpoint interpolation.
    runner = ClosedLoopRunner(backend, controller, reference,
                              params=ClosedLoopParams(setpoint_interpolation=1))
    runner.reset()
    log = runner.run(reference.t_end + 0.5)
    return log, backend


@pytest.mark.parametrize('feedback', [dict(feedback='prediction'),
                                      dict(feedback='estimator', feedback_gain=0.3)])
@pytest.mark.parametrize('n_steps, step_length', [(10, 0.0), (20, 0.1)])
def test_walking_controller_walks_the_model_plant(robot, feedback, n_steps, step_length):
    log, backend = walk(robot, n_steps, step_length, **feedback)
    end = n_steps * step_length
    np.testing.assert_allclose(log.com[-1, :2], [end, 0.0], atol=0.02)
    # the MPC tracks the legs loosely (swing lags its reference): feet land within 4 cm
    np.testing.assert_allclose(log.left_sole[-1, :2], [end, 0.07], atol=0.04)
    np.testing.assert_allclose(log.right_sole[-1, :2], [end, -0.07], atol=0.04)
    single = log.support != 2
    assert log.zmp_inside_support()[single].mean() >= 0.9
    # The fictitious ZMP of the masses (before clipping to the feet) stays within 2 cm of
    # the scaled support box the MPC was given.
    fictitious = backend.plant.measure().zmp_fictitious
    np.testing.assert_allclose(fictitious, log.zmp_reference[-1], atol=0.02)
    assert np.mean(log.mpc_status == 0) == 1.0


@pytest.mark.parametrize('overrides', [
    dict(time_step=0.0), dict(time_step=math.nan), dict(control_substeps=0),
    dict(control_substeps=2.0), dict(pelvis_height=-0.5), dict(com_offset=(0.0, 0.6)),
    dict(com_offset=(0.0,)), dict(contact_height=0.0), dict(gravity=math.inf),
    dict(servo_pole=1.0), dict(servo_pole=-0.1), dict(masses=None), dict(noise=0.01),
    dict(feed_forward=1)])
def test_bad_parameters_are_rejected(overrides):
    with pytest.raises(ConfigError):
        ModelPlantBackendParams(**overrides)


def test_bad_inputs_are_rejected(plant, robot):
    q = robot.nominal_leg_positions()
    for bad in (np.zeros(11), np.full(12, np.nan), np.zeros(23)):
        with pytest.raises(ConfigError):
            plant.step(bad)
    for substeps in (0, -1, 1.5, True):
        with pytest.raises(ConfigError):
            plant.step(q, n_substeps=substeps)
    with pytest.raises(ConfigError):
        plant.step(q, joint_velocities=np.full(12, np.inf))
    with pytest.raises(ConfigError):
        plant.reset(base_position=np.array([np.nan, 0.0, 0.0]))
    with pytest.raises(ConfigError):
        plant.reset(base_yaw=math.inf)
    with pytest.raises(ConfigError):
        plant.reset(joint_positions={'no_such_joint': 0.0})
    with pytest.raises(ConfigError):
        ModelPlantBackend(dataclasses.replace(robot, leg_geometry=None))
    with pytest.raises(ConfigError):
        ModelPlantBackend(robot, params={'time_step': 0.001})
