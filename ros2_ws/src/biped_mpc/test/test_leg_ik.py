"""Tests of the analytic leg IK: round trips, agreement with Pinocchio and PyBullet forward
kinematics of the URDF, clipping of unreachable targets and bad inputs."""

import dataclasses
import math

import numpy as np
import pinocchio as pin
import pybullet
import pytest
from scipy.spatial.transform import Rotation

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.leg_ik import AnalyticLegIk, IK_CLIPPED, IK_REACHABLE
from biped_planner.rotations import rotation_z as yaw_rotation
from biped_planner.sides import LEFT, RIGHT
from biped_sim.robot_description import coman_like


@pytest.fixture(scope='module')
def description():
    return coman_like()


@pytest.fixture(scope='module')
def ik(description):
    return AnalyticLegIk(description.leg_geometry)


def _random_joints(ik, rng, n, margin=0.05):
    lower = np.array(ik.geometry.joint_lower) + margin
    upper = np.array(ik.geometry.joint_upper) - margin
    q = rng.uniform(lower, upper, size=(n, 12))
    q[:, [3, 9]] = np.maximum(q[:, [3, 9]], 0.05)  # keep away from the straight-knee edge
    return q


def _random_pelvis(rng, seed):
    return rng.normal(size=3), Rotation.random(random_state=seed).as_matrix()


def test_round_trip_on_random_reachable_poses(ik):
    rng = np.random.default_rng(0)
    for i, q in enumerate(_random_joints(ik, rng, 300)):
        pelvis_p, pelvis_r = _random_pelvis(rng, i)
        left_p, left_r, right_p, right_r = ik.forward(q, pelvis_p, pelvis_r)
        solution = ik.solve(pelvis_p, pelvis_r, left_p, left_r, right_p, right_r)
        assert solution.reachable
        assert np.allclose(solution.q, q, atol=1e-8)
        again = ik.forward(solution.q, pelvis_p, pelvis_r)
        for got, want in zip(again, (left_p, left_r, right_p, right_r)):
            assert np.allclose(got, want, atol=1e-9, rtol=0.0)


def test_forward_kinematics_agrees_with_pinocchio(ik, description):
    model = pin.buildModelFromUrdf(description.urdf_path)
    data = model.createData()
    frames = [model.getFrameId(f) for f in description.sole_frames]
    index = [model.joints[model.getJointId(n)].idx_q for n in description.leg_joint_names]
    rng = np.random.default_rng(1)
    for q in _random_joints(ik, rng, 50):
        config = pin.neutral(model)
        config[index] = q
        pin.framesForwardKinematics(model, data, config)
        left_p, left_r, right_p, right_r = ik.forward(q)
        assert np.allclose(data.oMf[frames[0]].translation, left_p, atol=1e-12)
        assert np.allclose(data.oMf[frames[0]].rotation, left_r, atol=1e-12)
        assert np.allclose(data.oMf[frames[1]].translation, right_p, atol=1e-12)
        assert np.allclose(data.oMf[frames[1]].rotation, right_r, atol=1e-12)


def test_forward_kinematics_agrees_with_pybullet(ik, description):
    client = pybullet.connect(pybullet.DIRECT)
    try:
        robot = pybullet.loadURDF(description.urdf_path, [0.0, 0.0, 0.0], useFixedBase=True,
                                  physicsClientId=client)
        joints, links = {}, {}
        for j in range(pybullet.getNumJoints(robot, physicsClientId=client)):
            info = pybullet.getJointInfo(robot, j, physicsClientId=client)
            joints[info[1].decode()] = j
            links[info[12].decode()] = j
        rng = np.random.default_rng(2)
        for q in _random_joints(ik, rng, 20):
            for name, angle in zip(description.leg_joint_names, q):
                pybullet.resetJointState(robot, joints[name], angle, physicsClientId=client)
            expected = ik.forward(q)
            for side, frame in enumerate(description.sole_frames):
                state = pybullet.getLinkState(robot, links[frame], computeForwardKinematics=1,
                                              physicsClientId=client)
                rotation = np.array(pybullet.getMatrixFromQuaternion(state[5])).reshape(3, 3)
                assert np.allclose(state[4], expected[2 * side], atol=1e-6)
                assert np.allclose(rotation, expected[2 * side + 1], atol=1e-6)
    finally:
        pybullet.disconnect(client)


def test_nominal_pose_puts_the_feet_below_the_hips(ik, description):
    left_p, left_r, right_p, right_r = ik.forward(description.nominal_leg_positions())
    assert np.allclose(left_p, [0.0, 0.07, -0.54], atol=1e-12)
    assert np.allclose(right_p, [0.0, -0.07, -0.54], atol=1e-12)
    assert np.allclose(left_r, np.eye(3)) and np.allclose(right_r, np.eye(3))


def test_walking_like_targets_are_reachable(ik):
    pelvis = np.array([0.1, 0.02, 0.53])
    solution = ik.solve(pelvis, yaw_rotation(0.1), [0.2, 0.09, 0.0], yaw_rotation(0.2),
                        [-0.05, -0.07, 0.04], yaw_rotation(0.0))
    assert solution.status == (IK_REACHABLE, IK_REACHABLE)


def test_too_far_target_is_clipped_to_a_straight_leg(ik):
    pelvis = np.array([0.0, 0.0, 0.54])
    far = np.array([0.0, 0.07, -0.5])
    q, status = ik.solve_leg(LEFT, pelvis, np.eye(3), far, np.eye(3))
    assert status == IK_CLIPPED
    assert q[3] == pytest.approx(0.0, abs=1e-9)
    position, _ = ik.forward_leg(LEFT, q, pelvis, np.eye(3))
    # Nearest reachable point: straight down, the full leg length below the hip.
    assert np.allclose(position, [0.0, 0.07, 0.54 - 0.07 - 0.50], atol=1e-9)


def test_too_close_target_is_clipped_at_the_knee_limit(ik):
    q, status = ik.solve_leg(RIGHT, np.zeros(3), np.eye(3), [0.0, -0.07, -0.15], np.eye(3))
    assert status == IK_CLIPPED
    assert q[3] == pytest.approx(ik.geometry.joint_upper[9])


def test_rotation_beyond_limits_is_clipped_into_them(ik):
    q, status = ik.solve_leg(LEFT, np.array([0.0, 0.0, 0.54]), np.eye(3), [0.0, 0.07, 0.0],
                             yaw_rotation(1.5))
    assert status == IK_CLIPPED
    lower, upper = np.array(ik.geometry.joint_lower[:6]), np.array(ik.geometry.joint_upper[:6])
    assert np.all(q >= lower) and np.all(q <= upper)
    assert q[0] == pytest.approx(upper[0])


def test_geometry_from_any_object_with_its_fields(description):
    copy = description.leg_geometry
    assert dataclasses.asdict(copy) == dataclasses.asdict(description.leg_geometry)
    assert AnalyticLegIk(description.leg_geometry).geometry == copy


def test_bad_inputs_raise(ik):
    eye, zero = np.eye(3), np.zeros(3)
    with pytest.raises(InputError, match='NaN'):
        ik.solve(zero, eye, [np.nan, 0.0, 0.0], eye, zero, eye)
    with pytest.raises(InputError, match='shape'):
        ik.solve(zero, np.eye(2), zero, eye, zero, eye)
    with pytest.raises(InputError, match='side'):
        ik.solve_leg(2, zero, eye, zero, eye)
    with pytest.raises(InputError, match='6 finite'):
        ik.forward_leg(LEFT, [0.0] * 5)
    with pytest.raises(InputError, match='shape'):
        ik.forward(np.zeros(6))


def test_bad_geometry_raises(description):
    g = description.leg_geometry
    with pytest.raises(ConfigError, match='shank_length'):
        dataclasses.replace(g, shank_length=-0.2)
    with pytest.raises(ConfigError, match='hip_offset'):
        dataclasses.replace(g, hip_offset=(0.0, math.nan, 0.0))
    with pytest.raises(ConfigError, match='joint_upper'):
        dataclasses.replace(g, joint_upper=g.joint_upper[:6])
    with pytest.raises(ConfigError, match='below'):
        dataclasses.replace(g, joint_lower=g.joint_upper)
