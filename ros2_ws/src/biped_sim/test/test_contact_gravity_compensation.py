"""Tests of the gravity compensation with the weight split between the feet."""

import math

import numpy as np
import pinocchio as pin
import pytest

from biped_sim.contact_gravity_compensation import ContactGravityCompensation
from biped_sim.contact_gravity_compensation import sole_rectangle_clip
from biped_sim.errors import RobotModelError
from biped_sim.robot_description import coman_like

G = 9.81


@pytest.fixture(scope='module')
def description():
    return coman_like()


@pytest.fixture(scope='module')
def compensation(description):
    return ContactGravityCompensation(description.urdf_path, _joint_names(description),
                                      description.sole_frames, description.sole_length,
                                      description.sole_width, G)


def _joint_names(description):
    model = pin.buildModelFromUrdf(description.urdf_path)
    others = [n for n in model.names[1:] if n not in description.leg_joint_names]
    return description.leg_joint_names + tuple(others)


def _configuration(description, names, yaw=0.3, leg_override=None):
    q = np.array([description.nominal_joint_positions.get(n, 0.0) for n in names])
    if leg_override is not None:
        q[:12] = leg_override
    base = np.array([0.4, -0.2, 0.54])
    quaternion = pin.Quaternion(pin.utils.rpyToMatrix(0.0, 0.0, yaw)).coeffs()
    return base, quaternion, q


def _pinocchio_at(description, names, base, quaternion, q):
    """Pinocchio's free-flyer model of the URDF, its data and the configuration, with the frames
    placed (forward kinematics)."""
    model = pin.buildModelFromUrdf(description.urdf_path, pin.JointModelFreeFlyer())
    data = model.createData()
    config = pin.neutral(model)
    config[:3], config[3:7] = base, quaternion
    for name, angle in zip(names, q):
        config[model.joints[model.getJointId(name)].idx_q] = angle
    pin.framesForwardKinematics(model, data, config)
    return model, data, config


def _rnea_with_contacts(description, names, base, quaternion, q, forces, points):
    """Independent check: inverse dynamics at rest with the split forces as external forces."""
    model, data, config = _pinocchio_at(description, names, base, quaternion, q)
    model.gravity.linear = np.array([0.0, 0.0, -G])
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    for frame, force, point in zip(description.sole_frames, forces, points):
        joint = model.frames[model.getFrameId(frame)].parentJoint
        world = pin.Force(np.array([0.0, 0.0, force]), np.cross(point, [0.0, 0.0, force]))
        fext[joint] = fext[joint] + data.oMi[joint].actInv(world)
    zero = np.zeros(model.nv)
    tau = pin.rnea(model, data, config, zero, zero, fext)
    order = [model.joints[model.getJointId(n)].idx_v for n in names]
    return tau[:6], tau[order]


def test_both_feet_balance_gravity_and_match_inverse_dynamics(description, compensation):
    names = _joint_names(description)
    base, quaternion, q = _configuration(description, names)
    tau = compensation.torques(base, quaternion, q, (True, True))
    model, data, config = _pinocchio_at(description, names, base, quaternion, q)
    com = pin.centerOfMass(model, data, config)
    soles = [data.oMf[model.getFrameId(f)] for f in description.sole_frames]
    forces, points = compensation.split_weight(
        com[:2], [s.translation for s in soles],
        [math.atan2(s.rotation[1, 0], s.rotation[0, 0]) for s in soles], (True, True))
    base_wrench, joint_torques = _rnea_with_contacts(description, names, base, quaternion, q,
                                                     forces, points)
    assert np.allclose(joint_torques, tau, atol=1e-9)
    # The split balances the whole weight: no residual force or moment on the base.
    assert np.allclose(base_wrench, 0.0, atol=1e-8)
    assert forces.sum() == pytest.approx(compensation.total_mass * G)


def test_one_foot_carries_everything(description, compensation):
    names = _joint_names(description)
    base, quaternion, q = _configuration(description, names, yaw=0.0)
    tau = compensation.torques(base, quaternion, q, (True, False))
    forces, _ = compensation.split_weight(np.zeros(2), [np.array([0.0, 0.07, 0.0]),
                                                        np.array([0.0, -0.07, 0.0])],
                                          [0.0, 0.0], (True, False))
    assert forces[0] == pytest.approx(compensation.total_mass * G) and forces[1] == 0.0
    free = compensation.torques(base, quaternion, q, (False, False))
    assert not np.allclose(tau[:6], free[:6])
    assert np.allclose(tau[6:12], free[6:12])  # the unloaded leg only holds itself


def test_no_contact_is_plain_gravity(description, compensation):
    names = _joint_names(description)
    base, quaternion, q = _configuration(description, names)
    model = pin.buildModelFromUrdf(description.urdf_path, pin.JointModelFreeFlyer())
    model.gravity.linear = np.array([0.0, 0.0, -G])
    config = pin.neutral(model)
    config[:3], config[3:7] = base, quaternion
    for name, angle in zip(names, q):
        config[model.joints[model.getJointId(name)].idx_q] = angle
    g = pin.computeGeneralizedGravity(model, model.createData(), config)
    order = [model.joints[model.getJointId(n)].idx_v for n in names]
    assert np.allclose(compensation.torques(base, quaternion, q, (False, False)), g[order])


def test_split_follows_the_centre_of_mass(compensation):
    weight = compensation.total_mass * G
    left, right = np.array([0.0, 0.1, 0.0]), np.array([0.0, -0.1, 0.0])
    for com_y, share in ((0.0, 0.5), (0.05, 0.75), (0.1, 1.0), (0.3, 1.0), (-0.1, 0.0)):
        forces, points = compensation.split_weight(np.array([0.02, com_y]), (left, right),
                                                   (0.0, 0.0), (True, True))
        assert forces[0] == pytest.approx(share * weight)
        assert forces.sum() == pytest.approx(weight)
        if abs(com_y) <= 0.1:
            # Total centre of pressure at the centre of mass.
            assert forces @ points[:, :2] / weight == pytest.approx([0.02, com_y])


def test_sole_rectangle_clip():
    assert sole_rectangle_clip(0.3, 0.01, 0.0, 0.08, 0.04) == pytest.approx((0.08, 0.01))
    x, y = sole_rectangle_clip(0.0, 0.3, math.pi / 2, 0.08, 0.04)
    assert (x, y) == pytest.approx((0.0, 0.08))


def test_missing_names_raise(description):
    with pytest.raises(RobotModelError, match='no_such_joint'):
        ContactGravityCompensation(description.urdf_path, ('no_such_joint',),
                                   description.sole_frames, 0.2, 0.1)
    with pytest.raises(RobotModelError, match='no_sole'):
        ContactGravityCompensation(description.urdf_path, description.leg_joint_names,
                                   ('no_sole', 'r_sole'), 0.2, 0.1)
