"""Tests of the robot description and of the COMAN-like robot's mass, height and joints."""

import dataclasses
import math
import xml.etree.ElementTree as ElementTree

import numpy as np
import pinocchio as pin
import pytest

from biped_mpc.robot_model import COMAN_LIKE_MODEL_FILE, load_robot_model
from biped_sim.errors import ConfigError
from biped_sim.robot_description import coman_like, COMAN_LIKE_NOMINAL_HIP_HEIGHT
from biped_sim.robot_description import crouched_leg_angles


@pytest.fixture(scope='module')
def description():
    return coman_like()


@pytest.fixture(scope='module')
def urdf(description):
    return ElementTree.parse(description.urdf_path).getroot()


def test_mass_is_coman_like(description):
    model = pin.buildModelFromUrdf(description.urdf_path)
    assert abs(sum(i.mass for i in model.inertias) - 31.0) <= 0.5


def test_height_is_coman_like(description):
    """Straight legs: from the sole (lowest point) to the top of the head."""
    model = pin.buildModelFromUrdf(description.urdf_path)
    geometry = pin.buildGeomFromUrdf(model, description.urdf_path, pin.GeometryType.VISUAL)
    data, geometry_data = model.createData(), geometry.createData()
    pin.updateGeometryPlacements(model, data, geometry, geometry_data, pin.neutral(model))
    tops, bottoms = [], []
    for obj, placement in zip(geometry.geometryObjects, geometry_data.oMg):
        shape, z = obj.geometry, placement.translation[2]
        if hasattr(shape, 'radius') and not hasattr(shape, 'halfLength'):
            half = shape.radius
        elif hasattr(shape, 'halfLength'):
            axis = placement.rotation[2, 2]
            half = abs(axis) * shape.halfLength + math.sqrt(max(0.0, 1 - axis ** 2)) * shape.radius
        else:
            half = float(np.abs(placement.rotation[2]) @ shape.halfSide)
        tops.append(z + half)
        bottoms.append(z - half)
    assert abs(max(tops) - min(bottoms) - 0.95) <= 0.02


def test_joint_counts(urdf, description):
    kinds = {j.get('name'): j.get('type') for j in urdf.iter('joint')}
    assert sum(k == 'revolute' for k in kinds.values()) == 23
    assert all(kinds[n] == 'fixed' for n in description.ft_joints)
    assert all(kinds[n] == 'revolute' for n in description.leg_joint_names)
    links = {link.get('name') for link in urdf.iter('link')}
    assert set(description.sole_frames) | {description.imu_link} <= links


def test_limits_are_realistic(urdf):
    for joint in urdf.iter('joint'):
        if joint.get('type') != 'revolute':
            continue
        limit = joint.find('limit').attrib
        assert 10.0 <= float(limit['effort']) <= 150.0
        assert 3.0 <= float(limit['velocity']) <= 10.0
        assert float(limit['lower']) < float(limit['upper'])


def test_leg_axes_intersect(urdf, description):
    """No offsets between the hip joints or between the ankle joints."""
    origins = {j.get('name'): j.find('origin').get('xyz') for j in urdf.iter('joint')}
    for side in ('l', 'r'):
        for name in ('hip_roll', 'hip_pitch', 'ankle_roll'):
            assert origins['%s_%s_joint' % (side, name)] == '0 0 0'


def test_nominal_pose_stands_at_the_nominal_hip_height(description):
    g = description.leg_geometry
    hip, knee, ankle = description.nominal_leg_positions()[2:5]
    height = (g.thigh_length * math.cos(hip) + g.shank_length * math.cos(hip + knee)
              - g.ankle_to_sole[2])
    forward = -(g.thigh_length * math.sin(hip) + g.shank_length * math.sin(hip + knee))
    assert height == pytest.approx(COMAN_LIKE_NOMINAL_HIP_HEIGHT, abs=1e-12)
    assert forward == pytest.approx(0.0, abs=1e-12)
    assert hip + knee + ankle == pytest.approx(0.0, abs=1e-12)
    assert knee > 0.3


def test_crouched_leg_angles_out_of_range(description):
    with pytest.raises(ConfigError, match='hip_height'):
        crouched_leg_angles(description.leg_geometry, 0.6)


def test_description_validation(description):
    with pytest.raises(ConfigError, match='urdf_path'):
        dataclasses.replace(description, urdf_path='/nonexistent.urdf')
    with pytest.raises(ConfigError, match='leg_joint_names'):
        dataclasses.replace(description, leg_joint_names=description.leg_joint_names[:11])
    with pytest.raises(ConfigError, match='sole_frames'):
        dataclasses.replace(description, sole_frames=('l_sole',))
    with pytest.raises(ConfigError, match='sole_width'):
        dataclasses.replace(description, sole_width=-0.1)
    with pytest.raises(ConfigError, match='nominal_joint_positions'):
        dataclasses.replace(description, nominal_joint_positions={'l_knee_joint': math.nan})


def test_controller_model_is_the_yaml_robot_with_this_urdf(description):
    model = description.controller_model
    assert model == dataclasses.replace(load_robot_model(COMAN_LIKE_MODEL_FILE),
                                        urdf_path=description.urdf_path)
    assert model.leg_geometry == description.leg_geometry
    assert model.leg_joint_names == description.leg_joint_names
    with pytest.raises(ConfigError, match='controller_model'):
        dataclasses.replace(description, sole_frames=('l_sole', 'l_sole'))


def test_the_yaml_three_masses_are_the_urdf_masses_at_the_nominal_stance(description):
    """Legs: the links below each hip yaw joint; torso: everything else (the paper's m_1..3).

    The masses are the URDF's exactly; the heights, the pelvis height and the centre-of-mass
    offset are rounded in the YAML (to 0.1 mm, within 0.3 %), so they are checked within 1 %.
    """
    model = description.controller_model
    robot = pin.buildModelFromUrdf(description.urdf_path, pin.JointModelFreeFlyer())
    data = robot.createData()
    q = pin.neutral(robot)
    for name, angle in description.nominal_joint_positions.items():
        q[robot.joints[robot.getJointId(name)].idx_q] = angle
    q[2] = model.pelvis_height
    pin.forwardKinematics(robot, data, q)
    pin.updateFramePlacements(robot, data)
    for sole in description.sole_frames:
        assert data.oMf[robot.getFrameId(sole)].translation[2] == pytest.approx(0.0, abs=1e-9)

    def mass_and_height(joints):
        mass = sum(robot.inertias[j].mass for j in joints)
        com = sum(robot.inertias[j].mass * data.oMi[j].act(robot.inertias[j].lever)
                  for j in joints) / mass
        return mass, com[2]

    legs = [[j for j in range(1, robot.njoints)
             if robot.getJointId(f'{side}_hip_yaw_joint') in robot.supports[j]]
            for side in ('l', 'r')]
    torso = [j for j in range(1, robot.njoints) if j not in legs[0] + legs[1]]
    masses = model.masses
    for joints, mass, height in ((legs[0], masses.left_leg_mass, masses.left_leg_height),
                                 (torso, masses.torso_mass, masses.torso_height),
                                 (legs[1], masses.right_leg_mass, masses.right_leg_height)):
        urdf_mass, urdf_height = mass_and_height(joints)
        assert mass == pytest.approx(urdf_mass, rel=1e-9)
        assert height == pytest.approx(urdf_height, rel=0.01)
    com = pin.centerOfMass(robot, data, q)
    assert model.com_offset[0] == pytest.approx(com[0], rel=0.01)
    assert model.com_offset[1] == pytest.approx(com[1], abs=1e-9)


def test_robots_load_by_name_from_the_catalogue():
    from biped_sim.robot_catalogue import load_robot, ROBOTS
    assert {'coman_like', 'g1', 'talos'} <= set(ROBOTS)
    assert load_robot('coman_like').name == 'coman_like'
    with pytest.raises(ConfigError, match='banana'):
        load_robot('banana')
