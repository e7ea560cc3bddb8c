"""Tests of the robot description and of the COMAN-like robot's mass, height and joints."""

import dataclasses
import math
import xml.etree.ElementTree as ElementTree

import numpy as np
import pinocchio as pin
import pytest

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
