"""Tests of the numerical (Pinocchio damped least squares) leg IK."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.leg_ik import AnalyticLegIk, IK_CLIPPED, IK_REACHABLE
from biped_mpc.pinocchio_ik import NumericIkParams, PinocchioLegIk
from biped_planner.rotations import rotation_z as yaw_rotation
from biped_sim.robot_description import coman_like


@pytest.fixture(scope='module')
def description():
    return coman_like()


@pytest.fixture(scope='module')
def analytic(description):
    return AnalyticLegIk(description.leg_geometry)


@pytest.fixture
def numeric(description):
    return PinocchioLegIk(description.urdf_path, description.leg_joint_names,
                          description.sole_frames)


def _walking_range_joints(analytic, rng, n):
    """Random leg angles in the central part of the joint ranges, knees bent."""
    lower, upper = np.array(analytic.geometry.joint_lower), np.array(analytic.geometry.joint_upper)
    middle, half = (lower + upper) / 2, (upper - lower) / 2
    q = middle + rng.uniform(-0.5, 0.5, size=(n, 12)) * half
    q[:, [3, 9]] = rng.uniform(0.3, 1.6, size=(n, 2))
    return q


def test_limits_come_from_the_urdf(numeric, analytic):
    assert np.allclose(numeric.joint_lower, analytic.geometry.joint_lower)
    assert np.allclose(numeric.joint_upper, analytic.geometry.joint_upper)


def test_forward_kinematics_matches_the_analytic_one(numeric, analytic):
    rng = np.random.default_rng(4)
    for i, q in enumerate(_walking_range_joints(analytic, rng, 20)):
        pelvis_p, pelvis_r = rng.normal(size=3), Rotation.random(random_state=i).as_matrix()
        for got, want in zip(numeric.forward(q, pelvis_p, pelvis_r),
                             analytic.forward(q, pelvis_p, pelvis_r)):
            assert np.allclose(got, want, atol=1e-12)


def test_round_trip_from_the_bent_knee_seed(numeric, analytic):
    rng = np.random.default_rng(5)
    for i, q in enumerate(_walking_range_joints(analytic, rng, 60)):
        pelvis_p, pelvis_r = rng.normal(size=3), Rotation.random(random_state=i).as_matrix()
        targets = analytic.forward(q, pelvis_p, pelvis_r)
        numeric.reset_warm_start()
        solution = numeric.solve(pelvis_p, pelvis_r, *targets)
        assert solution.status == (IK_REACHABLE, IK_REACHABLE)
        for got, want in zip(numeric.forward(solution.q, pelvis_p, pelvis_r), targets):
            assert np.allclose(got, want, atol=1e-4)
        # Same angles as the exact solution (a bent knee has one solution in the limits).
        assert np.allclose(solution.q, q, atol=1e-6)


def test_warm_start_converges_in_few_iterations(numeric, analytic, description):
    q = description.nominal_leg_positions()
    targets = analytic.forward(q)
    numeric.solve(np.zeros(3), np.eye(3), *targets)
    numeric.solve(np.zeros(3), np.eye(3), *targets)
    assert numeric.last_iterations == (0, 0)
    numeric.solve(np.array([0.002, 0.003, -0.001]), np.eye(3), *targets)
    assert max(numeric.last_iterations) <= 3


def test_unreachable_target_is_clipped_within_limits(numeric):
    pelvis = np.array([0.0, 0.0, 0.54])
    solution = numeric.solve(pelvis, np.eye(3), [0.0, 0.07, -0.5], np.eye(3),
                             [0.0, -0.07, 0.0], yaw_rotation(1.5))
    assert solution.status == (IK_CLIPPED, IK_CLIPPED)
    assert np.all(solution.q >= numeric.joint_lower) and np.all(solution.q <= numeric.joint_upper)
    # The too-far left sole ends as low as the leg reaches, straight below the hip.
    left_p, _, _, _ = numeric.forward(solution.q, pelvis, np.eye(3))
    assert left_p[2] == pytest.approx(0.54 - 0.07 - 0.50, abs=1e-3)


def test_bad_inputs_raise(numeric, description):
    eye, zero = np.eye(3), np.zeros(3)
    with pytest.raises(InputError, match='NaN'):
        numeric.solve(zero, eye, zero, eye, [0.0, math.inf, 0.0], eye)
    with pytest.raises(InputError, match='q_init'):
        numeric.solve(zero, eye, zero, eye, zero, eye, q_init=np.zeros(3))
    with pytest.raises(InputError, match='q must be finite'):
        numeric.forward(np.full(12, np.nan))
    with pytest.raises(ConfigError, match='no_joint'):
        PinocchioLegIk(description.urdf_path, ('no_joint',) + description.leg_joint_names[1:],
                       description.sole_frames)
    with pytest.raises(ConfigError, match='12 names'):
        PinocchioLegIk(description.urdf_path, description.leg_joint_names[:6],
                       description.sole_frames)
    with pytest.raises(ConfigError, match='seed'):
        PinocchioLegIk(description.urdf_path, description.leg_joint_names,
                       description.sole_frames, seed=np.zeros(6))


@pytest.mark.parametrize('kwargs', [{'max_iterations': 0}, {'tolerance': 0.0},
                                    {'damping': -1.0}, {'max_step': math.nan}])
def test_bad_params_raise(kwargs):
    with pytest.raises(ConfigError, match=next(iter(kwargs))):
        NumericIkParams(**kwargs)
