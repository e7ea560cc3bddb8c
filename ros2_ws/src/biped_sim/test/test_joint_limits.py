"""Tests of the joint limits read from a URDF and the check of joint setpoints."""
import math

import numpy as np
import pytest

from biped_sim.errors import ConfigError, InputError
from biped_sim.joint_limits import check_setpoints, joint_limits_from_urdf
from biped_sim.robot_catalogue import load_robot


@pytest.fixture(scope='module')
def coman():
    return load_robot('coman_like')


def test_the_limits_are_the_urdf_ones(coman):
    lower, upper = joint_limits_from_urdf(coman.urdf_path, ('l_knee_joint', 'r_hip_roll_joint'))
    assert lower == pytest.approx([0.0, -0.8]) and upper == pytest.approx([2.3, 0.45])


def test_an_unknown_joint_or_file_is_a_config_error(coman, tmp_path):
    with pytest.raises(ConfigError, match='banana'):
        joint_limits_from_urdf(coman.urdf_path, ('banana',))
    with pytest.raises(ConfigError, match='cannot read'):
        joint_limits_from_urdf(str(tmp_path / 'none.urdf'), ('l_knee_joint',))


@pytest.mark.parametrize('value', [1e30, -0.2, math.nan, math.inf])
def test_setpoints_past_a_limit_and_its_margin_are_refused_naming_the_joint(value):
    with pytest.raises(InputError, match='knee'):
        check_setpoints(('hip', 'knee'), (0.0, value), (-1.0, 0.0), (1.0, 2.3), 0.1)


def test_setpoints_within_the_margin_pass_and_unbounded_joints_take_any_finite_value():
    values = check_setpoints(('hip', 'knee', 'wheel'), (1.05, -0.05, 1e6),
                             (-1.0, 0.0, -np.inf), (1.0, 2.3, np.inf), 0.1)
    assert values == pytest.approx([1.05, -0.05, 1e6])
