"""The rotations module against scipy.spatial.transform.Rotation."""
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from biped_planner import rotations

RNG = np.random.default_rng(7)
QUATERNIONS = [q / np.linalg.norm(q) for q in RNG.normal(size=(50, 4))]


@pytest.mark.parametrize('q', QUATERNIONS)
def test_matrix_equals_scipy(q):
    np.testing.assert_allclose(rotations.quaternion_to_matrix(q),
                               Rotation.from_quat(q).as_matrix(), atol=1e-12)


@pytest.mark.parametrize('q', QUATERNIONS)
def test_euler_angles_equal_scipy_zyx(q):
    yaw, pitch, roll = Rotation.from_quat(q).as_euler('ZYX')
    matrix = Rotation.from_quat(q).as_matrix()
    assert rotations.yaw_of_quaternion(q) == pytest.approx(yaw, abs=1e-9)
    assert rotations.yaw_of_quaternion(3.0 * q) == pytest.approx(yaw, abs=1e-9)
    assert rotations.yaw_of_matrix(matrix) == pytest.approx(yaw, abs=1e-9)
    assert rotations.roll_pitch_of_matrix(matrix) == pytest.approx((roll, pitch), abs=1e-9)


@pytest.mark.parametrize('q', QUATERNIONS)
def test_tilt_is_the_angle_of_the_body_z_axis(q):
    z_axis = Rotation.from_quat(q).as_matrix()[:, 2]
    assert rotations.tilt_of_quaternion(q) == pytest.approx(math.acos(z_axis[2]), abs=1e-7)


@pytest.mark.parametrize('angle', [-3.0, -0.4, 0.0, 0.7, 2.9])
def test_elementary_rotations_equal_scipy(angle):
    for axis, function in (('x', rotations.rotation_x), ('y', rotations.rotation_y),
                           ('z', rotations.rotation_z)):
        np.testing.assert_allclose(function(angle),
                                   Rotation.from_euler(axis, angle).as_matrix(), atol=1e-12)
    np.testing.assert_allclose(rotations.quaternion_from_yaw(angle),
                               Rotation.from_euler('z', angle).as_quat(canonical=False)
                               * np.sign(Rotation.from_euler('z', angle).as_quat()[3]),
                               atol=1e-12)


@pytest.mark.parametrize('angle, wrapped', [(0.0, 0.0), (math.pi, -math.pi),
                                            (3 * math.pi / 2, -math.pi / 2),
                                            (-7.0, -7.0 + 2 * math.pi)])
def test_wrap_angle(angle, wrapped):
    assert rotations.wrap_angle(angle) == pytest.approx(wrapped)


@pytest.mark.parametrize('a, b, mean', [(0.0, 1.0, 0.5), (3.0, -3.0, math.pi),
                                        (-0.2, 0.2, 0.0)])
def test_mean_angle_takes_the_short_arc(a, b, mean):
    assert rotations.wrap_angle(rotations.mean_angle(a, b) - mean) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize('seed', range(3))
def test_cross_is_numpy_s_to_the_bit(seed):
    a, b = np.random.default_rng(seed).normal(size=(2, 5, 3))
    np.testing.assert_array_equal(rotations.cross(a, b), np.cross(a, b))
    np.testing.assert_array_equal(rotations.cross(a[0], b[0]), np.cross(a[0], b[0]))
    np.testing.assert_array_equal(rotations.cross(a[0], b), np.cross(a[0], b))
    np.testing.assert_array_equal(rotations.cross(list(a[1]), tuple(b[1])), np.cross(a[1], b[1]))
