"""Tests of the other humanoids of the optional example-robot-data extra (biped_sim.other_robots):
their descriptions, torque-controlled standing, a weight shift with a lifted foot, and the
Pinocchio leg IK on their legs (all headless).

example-robot-data 6.0.0 ships URDFs and meshes but no Python module, so the tests that need it
are skipped by asking importlib.metadata for the distribution (pip install -r
requirements-robots.txt); the others always run.
"""

import dataclasses
import importlib.metadata
import math

import numpy as np
import pytest

from biped_mpc.leg_ik import AnalyticLegIk
from biped_mpc.pinocchio_ik import PinocchioLegIk
from biped_planner.rotations import tilt_of_quaternion
from biped_sim import other_robots
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.other_robots import MissingRobotDataError, ROBOTS, sim_config
from biped_sim.weight_shift_trial import WEIGHT_SHIFT_PHASES, weight_shift_trial
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like

G = 9.81
ROBOT_NAMES = sorted(ROBOTS)
# Published masses (kg) of the models: G1 29-DOF, TALOS reduced.
EXPECTED_MASS = {'g1': 33.34, 'talos': 90.27}
# Axis of each leg joint role in its own joint frame.
ROLE_AXES = ('RZ', 'RX', 'RY', 'RY', 'RY', 'RX')


def _extra_installed() -> bool:
    try:
        other_robots.example_robot_data_share()
    except MissingRobotDataError:
        return False
    return True


needs_extra = pytest.mark.skipif(not _extra_installed(),
                                 reason='example-robot-data is not installed: '
                                 + other_robots.INSTALL_HINT)


@pytest.fixture(scope='module', params=ROBOT_NAMES)
def robot(request):
    """(description, torque-controlled backend) of each robot, shared within the module."""
    if not _extra_installed():
        pytest.skip('example-robot-data is not installed: ' + other_robots.INSTALL_HINT)
    description = ROBOTS[request.param]()
    sim = PyBulletBackend(description, sim_config(request.param))
    yield description, sim
    sim.close()


@pytest.fixture(scope='module')
def pin_model():
    import pinocchio as pin
    cache = {}

    def build(description):
        if description.name not in cache:
            model = pin.buildModelFromUrdf(description.urdf_path, pin.JointModelFreeFlyer())
            cache[description.name] = (model, model.createData())
        return cache[description.name]
    return build


def _inside_sole(point, sole, description, margin=0.005):
    return (abs(point[0] - sole[0]) <= description.sole_length / 2 + margin
            and abs(point[1] - sole[1]) <= description.sole_width / 2 + margin)


# ----------------------------------------------------------------------------- always run
def test_missing_extra_raises_an_import_error_with_the_install_hint(monkeypatch):
    def missing(name):
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, 'distribution', missing)
    for factory in ROBOTS.values():
        with pytest.raises(ImportError, match='pip install -r requirements-robots.txt'):
            factory()
    with pytest.raises(MissingRobotDataError):
        other_robots.example_robot_data_share()


def test_a_description_may_have_no_ft_joints_but_not_one():
    description = coman_like()
    assert dataclasses.replace(description, ft_joints=()).ft_joints == ()
    with pytest.raises(ConfigError, match='ft_joints'):
        dataclasses.replace(description, ft_joints=('l_ankle_ft_joint',))


def test_bad_settings_raise():
    with pytest.raises(ConfigError, match='robot'):
        sim_config('asimo')
    with pytest.raises(ConfigError, match='gain_cap'):
        sim_config('g1', gain_cap=2.0)


def test_upright_tilt_is_zero_and_a_quarter_turn_is_ninety_degrees():
    assert tilt_of_quaternion((0.0, 0.0, 0.0, 1.0)) == 0.0
    assert tilt_of_quaternion((0.0, 0.0, math.sin(0.5), math.cos(0.5))) == pytest.approx(
        0.0, abs=1e-7)
    half = math.sqrt(0.5)
    assert math.degrees(tilt_of_quaternion((half, 0.0, 0.0, half))) == pytest.approx(90.0)


def test_weight_shift_trial_steps_the_coman_like_robot_with_its_analytic_ik():
    description = coman_like()
    with PyBulletBackend(description, PyBulletConfig()) as sim:
        trial = weight_shift_trial(sim, AnalyticLegIk(description.leg_geometry))
        assert trial.ik_clipped == 0
        assert math.degrees(trial.max_tilt()) < 2.0
        assert all(r.right_sole[2] > 0.027 and not r.right_foot.in_contact
                   for r in trial.during('hold'))
        final = trial.readings[-1]
        assert final.left_foot.in_contact and final.right_foot.in_contact
        assert len(trial.readings) == round(sum(d for _, d in WEIGHT_SHIFT_PHASES)
                                            / 0.02)


# ----------------------------------------------------------------------------- with the extra
@needs_extra
def test_description_matches_the_urdf(robot, pin_model):
    import pinocchio as pin
    description, sim = robot
    model, data = pin_model(description)
    for k, name in enumerate(description.leg_joint_names):
        assert model.existJointName(name), name
        joint = model.joints[model.getJointId(name)]
        assert joint.shortname() == 'JointModel' + ROLE_AXES[k % 6], name
    for frame in description.sole_frames + (description.imu_link,):
        assert model.existFrame(frame), frame
    mass = sum(inertia.mass for inertia in model.inertias)
    assert mass == pytest.approx(EXPECTED_MASS[description.name], rel=0.01)
    # Links without <inertial> got a tiny mass in both simulators, not 1 kg in PyBullet only.
    assert sim.total_mass == pytest.approx(mass, abs=1e-6)
    assert sim.joint_names[:12] == description.leg_joint_names
    # Nominal pose: feet flat and parallel to the pelvis, centre of mass between the feet.
    q = pin.neutral(model)
    for name, angle in description.nominal_joint_positions.items():
        q[model.joints[model.getJointId(name)].idx_q] = angle
    pin.framesForwardKinematics(model, data, q)
    soles = [data.oMf[model.getFrameId(f)] for f in description.sole_frames]
    for sole in soles:
        assert np.allclose(sole.rotation, np.eye(3), atol=1e-6)
    assert soles[0].translation[2] == pytest.approx(soles[1].translation[2], abs=1e-9)
    com = pin.centerOfMass(model, data, q)
    assert soles[1].translation[1] < com[1] < soles[0].translation[1]
    assert abs(com[0] - soles[0].translation[0]) < description.sole_length / 2


@needs_extra
def test_reset_stands_the_soles_on_the_ground(robot):
    description, sim = robot
    readings = sim.reset()
    assert readings.left_sole[2] == pytest.approx(5e-4, abs=1e-6)
    assert readings.right_sole[2] == pytest.approx(5e-4, abs=1e-6)
    assert readings.left_sole[1] > 0.05 and readings.right_sole[1] < -0.05


@needs_extra
def test_stands_three_seconds_under_torque_control(robot):
    description, sim = robot
    start = sim.reset()
    q = description.nominal_leg_positions()
    tilts, heights = [], []
    for _ in range(150):
        readings = sim.step(q)
        tilts.append(math.degrees(tilt_of_quaternion(readings.base.orientation)))
        heights.append(readings.base.position[2])
    assert max(tilts) < 3.0
    assert np.max(np.abs(np.array(heights) - start.base.position[2])) < 0.005
    assert np.linalg.norm(readings.base.position[:2] - start.base.position[:2]) < 0.01
    # Without F/T joints the feet are read from their contact points.
    left, right = readings.left_foot, readings.right_foot
    assert left.in_contact and right.in_contact
    weight = sim.total_mass * G
    assert left.ground_force[2] + right.ground_force[2] == pytest.approx(weight, rel=0.03)
    # The virtual sensor at the sole frame reads the ground reaction in that frame.
    assert np.linalg.norm(left.sensor_force) == pytest.approx(np.linalg.norm(left.ground_force))
    assert left.sensor_force[2] == pytest.approx(left.ground_force[2], rel=1e-3)
    assert _inside_sole(left.cop, readings.left_sole, description)
    assert _inside_sole(right.cop, readings.right_sole, description)
    assert np.allclose(readings.zmp, readings.com_position[:2], atol=0.01)
    # The IMU frame is aligned with the pelvis: +g up when still.
    assert np.allclose(readings.imu.linear_acceleration, [0.0, 0.0, G], atol=0.1)


@needs_extra
def test_contact_forces_balance_a_steady_push(robot):
    """The ground's friction on the feet opposes a steady sideways push (its sign).

    The robot sways under the push with a period near 1 s (TALOS's 25-step means range from 10 to
    37 N for a 27 N push), so the mean is taken over 4 s of sway after the first second.
    """
    description, sim = robot
    sim.reset()
    force = 0.03 * sim.total_mass * G
    sim.push(ExternalPush(force=(force, -force, 0.0), duration=6.0, start_time=0.0))
    q = description.nominal_leg_positions()
    readings = [sim.step(q) for _ in range(250)][50:]
    ground = np.mean([r.left_foot.ground_force + r.right_foot.ground_force for r in readings],
                     axis=0)
    assert ground[:2] == pytest.approx([-force, force], abs=0.4 * force)
    assert math.degrees(tilt_of_quaternion(readings[-1].base.orientation)) < 3.0


@needs_extra
def test_weight_shift_lift_foot_and_put_it_down(robot):
    """COM over the left foot, right foot up 3 cm and down again, COM back to the middle."""
    description, sim = robot
    leg_ik = PinocchioLegIk(description.urdf_path, description.leg_joint_names,
                            description.sole_frames, seed=description.nominal_leg_positions())
    trial = weight_shift_trial(sim, leg_ik, lift_height=0.03)
    start = trial.start
    assert trial.ik_clipped == 0
    assert math.degrees(trial.max_tilt()) < 3.0
    assert min(r.base.position[2] for r in trial.readings) > start.base.position[2] - 0.01
    held = trial.during('hold')
    assert len(held) == 25
    weight = sim.total_mass * G
    for readings in held:
        assert readings.right_sole[2] > 0.025
        assert readings.left_foot.in_contact and not readings.right_foot.in_contact
        assert _inside_sole(readings.zmp, readings.left_sole, description)
        assert readings.left_foot.ground_force[2] == pytest.approx(weight, rel=0.1)
    final = trial.readings[-1]
    assert final.left_foot.in_contact and final.right_foot.in_contact
    assert np.linalg.norm(final.right_sole - start.right_sole) < 0.01
    assert np.linalg.norm(final.left_sole - start.left_sole) < 0.01


@needs_extra
def test_weight_shift_trial_rejects_bad_input(robot):
    description, sim = robot
    with pytest.raises(ConfigError, match='lift_height'):
        weight_shift_trial(sim, None, lift_height=-0.01)
    with pytest.raises(ConfigError, match='stand_time'):
        weight_shift_trial(sim, None, stand_time=math.nan)
    with pytest.raises(ConfigError, match='jump'):
        weight_shift_trial(sim, None, phases=(('jump', 1.0),))


@needs_extra
def test_pinocchio_ik_round_trip_on_the_legs(robot):
    description, _ = robot
    ik = PinocchioLegIk(description.urdf_path, description.leg_joint_names,
                        description.sole_frames, seed=description.nominal_leg_positions())
    nominal = description.nominal_leg_positions()
    pelvis, upright = np.array([0.0, 0.0, 0.8]), np.eye(3)
    left, left_rotation, right, right_rotation = ik.forward(nominal, pelvis, upright)
    solution = ik.solve(pelvis, upright, left, left_rotation, right, right_rotation)
    assert solution.reachable
    assert np.allclose(solution.q, nominal, atol=1e-6)
    rng = np.random.default_rng(3)
    lower, upper = ik.joint_lower, ik.joint_upper
    for _ in range(20):
        q = np.clip(nominal + rng.uniform(-0.2, 0.2, 12), lower + 0.05, upper - 0.05)
        q[[3, 9]] = np.clip(q[[3, 9]], 0.3, None)  # knees bent: away from the singularity
        targets = ik.forward(q, pelvis, upright)
        solution = ik.solve(pelvis, upright, *targets, q_init=nominal)
        assert solution.reachable
        reached = ik.forward(solution.q, pelvis, upright)
        for got, want in zip(reached, targets):
            assert np.allclose(got, want, atol=1e-8)
