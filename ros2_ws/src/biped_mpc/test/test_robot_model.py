"""The robot model file and its leg geometry."""
import dataclasses
import math

import pytest

from biped_mpc.errors import ConfigError
from biped_mpc.robot_model import COMAN_LIKE_MODEL_FILE, LegGeometry, load_robot_model


@pytest.fixture(scope='module')
def model():
    return load_robot_model(COMAN_LIKE_MODEL_FILE)


def test_the_shipped_model_loads(model):
    assert model.name == 'coman_like'
    assert model.leg_joint_names[0] == 'l_hip_yaw_joint'
    assert model.leg_joint_names[6] == 'r_hip_yaw_joint'
    total = model.masses.left_leg_mass + model.masses.torso_mass + model.masses.right_leg_mass
    assert total == pytest.approx(30.95)
    assert model.leg_geometry.thigh_length == 0.22


def test_leg_geometry_validation(model):
    g = model.leg_geometry
    with pytest.raises(ConfigError, match='thigh_length'):
        dataclasses.replace(g, thigh_length=0.0)
    with pytest.raises(ConfigError, match='hip_offset'):
        dataclasses.replace(g, hip_offset=(0.0, 0.1))
    with pytest.raises(ConfigError, match='joint_lower'):
        dataclasses.replace(g, joint_lower=g.joint_upper)
    with pytest.raises(ConfigError, match='ankle_to_sole'):
        LegGeometry(g.hip_offset, 0.2, 0.2, (0.0, math.inf, 0.0), g.joint_lower, g.joint_upper)


@pytest.mark.parametrize('text, message', [
    ('', 'must hold a map'),
    ('[1, 2]', 'must hold a map'),
    ('name: x', "KeyError"),
    ('{{{', 'cannot read'),
])
def test_bad_model_files_are_refused(tmp_path, text, message):
    path = tmp_path / 'robot.yaml'
    path.write_text(text)
    with pytest.raises(ConfigError, match=message):
        load_robot_model(path)


def test_missing_file_is_refused(tmp_path):
    with pytest.raises(ConfigError, match='cannot read'):
        load_robot_model(tmp_path / 'none.yaml')


def test_out_of_range_values_are_refused(tmp_path, model):
    text = COMAN_LIKE_MODEL_FILE.read_text().replace('pelvis_height: 0.54', 'pelvis_height: -1')
    path = tmp_path / 'robot.yaml'
    path.write_text(text)
    with pytest.raises(ConfigError, match='pelvis_height'):
        load_robot_model(path)
