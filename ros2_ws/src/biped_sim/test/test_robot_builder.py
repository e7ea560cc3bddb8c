"""Tests of the URDF model and the COMAN-like generator: inertias, principal axes, URDF text."""

import math
import xml.etree.ElementTree as ElementTree

import numpy as np
import pytest

from biped_sim import robot_builder
from biped_sim import urdf_model as rb
from biped_sim.errors import ConfigError


def test_box_inertia_closed_form():
    inertia = rb.Box((0.3, 0.2, 0.1)).inertia(6.0)
    assert np.allclose(np.diag(inertia), [0.5 * (0.04 + 0.01), 0.5 * (0.09 + 0.01),
                                          0.5 * (0.09 + 0.04)])


def test_cylinder_and_sphere_inertia_closed_form():
    cylinder = rb.Cylinder(0.1, 0.4).inertia(3.0)
    assert np.allclose(np.diag(cylinder), [3.0 * (0.03 + 0.16) / 12] * 2 + [1.5 * 0.01])
    assert np.allclose(rb.Sphere(0.2).inertia(5.0), np.eye(3) * 0.4 * 5.0 * 0.04)


def test_two_cubes_side_by_side_are_one_box():
    """Two 1 kg cubes of side a touching along x have the inertia of a 2a x a x a box."""
    a = 0.1
    cube = rb.Box((a, a, a))
    link = rb.Link('pair', (rb.Shape(cube, 1.0, (0.0, 0.0, 0.0)),
                            rb.Shape(cube, 1.0, (a, 0.0, 0.0))))
    com, inertia = link.composite_inertia()
    assert np.allclose(com, [a / 2, 0.0, 0.0])
    assert np.allclose(inertia, rb.Box((2 * a, a, a)).inertia(2.0))


def test_rotated_cylinder_inertia_swaps_axes():
    link = rb.Link('arm', (rb.Shape(rb.Cylinder(0.05, 0.3), 2.0, rpy=(0.0, math.pi / 2, 0.0)),))
    _, inertia = link.composite_inertia()
    expected = rb.Cylinder(0.05, 0.3).inertia(2.0)
    assert np.allclose(np.diag(inertia), [expected[2, 2], expected[1, 1], expected[0, 0]])


@pytest.mark.parametrize('rpy', [(0.1, -0.4, 2.0), (0.0, 0.0, 0.0), (-1.2, 0.3, -2.5)])
def test_rpy_round_trip(rpy):
    assert np.allclose(rb.matrix_to_rpy(rb.rpy_to_matrix(rpy)), rpy)


def test_principal_axes_reconstruct_the_tensor():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(3, 3))
    inertia = a @ a.T + np.eye(3)
    moments, axes = rb.principal_axes(inertia)
    assert np.isclose(np.linalg.det(axes), 1.0)
    assert np.allclose(axes @ np.diag(moments) @ axes.T, inertia)


def test_committed_urdf_matches_the_generator():
    urdf = robot_builder.COMAN_LIKE_URDF.read_text()
    assert urdf == robot_builder.build_coman_like().to_urdf()


def test_urdf_inertias_are_the_principal_moments():
    root = ElementTree.fromstring(robot_builder.build_coman_like().to_urdf())
    for link in root.iter('link'):
        tensor = link.find('inertial/inertia').attrib
        assert tensor['ixy'] == tensor['ixz'] == tensor['iyz'] == '0'
        moments = sorted(float(tensor[k]) for k in ('ixx', 'iyy', 'izz'))
        # Triangle inequality of principal moments of a real body.
        assert moments[0] + moments[1] >= moments[2] * (1 - 1e-6)


def test_bad_values_raise():
    with pytest.raises(ConfigError, match='mass'):
        rb.Shape(rb.Sphere(0.1), 0.0)
    with pytest.raises(ConfigError, match='mass'):
        rb.Shape(rb.Sphere(0.1), float('nan'))
    with pytest.raises(ConfigError, match='lower'):
        rb.JointLimits(1.0, 0.5, 10.0, 1.0)
    with pytest.raises(ConfigError, match='effort'):
        rb.JointLimits(-1.0, 1.0, 0.0, 1.0)
