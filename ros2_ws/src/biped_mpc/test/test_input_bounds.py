"""Tests of the physical bounds of the controller's inputs."""
import math

import numpy as np
import pytest

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.input_bounds import (check_joint_angles, check_position, check_quaternion,
                                    check_reference_window, check_vector, InputBounds)
from biped_planner.footsteps import Footstep
from biped_planner.sides import LEFT, RIGHT
from biped_planner.standing_reference import standing_window
from biped_planner.walking_reference import ReferenceParams

BOUNDS = InputBounds()


@pytest.mark.parametrize('value', [(math.nan, 0, 0), (math.inf, 0, 0), (1e30, 0, 0),
                                   (0, 0, -2000.0)])
def test_positions_outside_the_workspace_are_refused(value):
    with pytest.raises(InputError):
        check_position('odom position', value, BOUNDS)


def test_a_position_inside_passes():
    assert check_position('p', (3.0, -2.0, 0.5), BOUNDS) == pytest.approx([3.0, -2.0, 0.5])


@pytest.mark.parametrize('value', [(0, 0, 0, 0), (0, 0, 0, 2.0), (math.nan, 0, 0, 1),
                                   (0, 0, 0.3, 1.0)])
def test_quaternions_that_are_not_unit_are_refused(value):
    with pytest.raises(InputError, match='q'):
        check_quaternion('q', value, BOUNDS)


def test_a_unit_quaternion_within_the_tolerance_passes():
    check_quaternion('q', (0.0, 0.0, math.sin(0.3), math.cos(0.3) * 1.005), BOUNDS)


def test_vectors_beyond_their_bound_are_refused():
    with pytest.raises(InputError, match='5000'):
        check_vector('force', (0, 0, 1e30), BOUNDS.max_force, 'N')
    with pytest.raises(InputError, match='not finite'):
        check_vector('force', (0, 0, math.inf), BOUNDS.max_force, 'N')
    check_vector('force', (0, 0, 300.0), BOUNDS.max_force, 'N')


def test_joint_angles_past_their_limits_are_refused_naming_the_joint():
    names, lower, upper = ('hip', 'knee'), (-1.0, 0.0), (1.0, 2.0)
    check_joint_angles(names, (0.5, -0.1), lower, upper, BOUNDS)  # inside the margin
    with pytest.raises(InputError, match='knee'):
        check_joint_angles(names, (0.5, -0.3), lower, upper, BOUNDS)
    with pytest.raises(InputError, match='hip'):
        check_joint_angles(names, (math.nan, 1.0), lower, upper, BOUNDS)


def window(n=5, dt=0.02, x=0.0):
    return standing_window(Footstep(LEFT, x, 0.07), Footstep(RIGHT, x, -0.07),
                           ReferenceParams(), 0.0, n, dt)


def test_reference_windows_the_controller_cannot_follow_are_refused():
    check_reference_window(window(), 0.02, BOUNDS)
    with pytest.raises(InputError, match='1 samples'):
        check_reference_window(window(n=1), 0.02, BOUNDS)
    with pytest.raises(InputError, match='apart'):
        check_reference_window(window(dt=0.05), 0.02, BOUNDS)
    with pytest.raises(InputError, match='workspace'):
        check_reference_window(window(x=1e4), 0.02, BOUNDS)
    unknown = window()
    unknown.support[2] = 7
    with pytest.raises(InputError, match=r'support\[2\] is 7'):
        check_reference_window(unknown, 0.02, BOUNDS)
    jumping = window()
    jumping.left_foot[3, 0] = 2.0
    with pytest.raises(InputError, match='jumps'):
        check_reference_window(jumping, 0.02, BOUNDS)


def test_bad_bounds_are_refused():
    with pytest.raises(ConfigError, match='workspace'):
        InputBounds(workspace=-1.0)
    assert np.isfinite(InputBounds().max_force)
