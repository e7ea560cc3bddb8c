"""URDF robots from primitive shapes with exact inertias: shapes, links, joints and their text.

Every link is a set of primitive shapes (box, cylinder, sphere), each with its own mass. The
inertia of a link is the exact composite inertia of its shapes (parallel axis theorem), written
in its principal axes (``<inertial><origin rpy>`` with a diagonal tensor) because PyBullet reads
only the diagonal of a URDF inertia tensor. biped_sim.robot_builder builds the COMAN-like
humanoid from these pieces.
"""

from dataclasses import dataclass
from dataclasses import field
import math
from typing import Optional, Union

import numpy as np

from biped_planner.rotations import (roll_pitch_of_matrix, rotation_x, rotation_y, rotation_z,
                                     yaw_of_matrix)

from biped_sim.errors import ConfigError


@dataclass(frozen=True)
class Box:
    """Solid box centred on its frame.

    :param size: edge lengths along x, y, z (m).
    """

    size: tuple

    def inertia(self, mass: float) -> np.ndarray:
        """Return the 3x3 inertia (kg m^2) about the centre, in the shape frame."""
        a, b, c = self.size
        return mass / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])

    def urdf(self) -> str:
        """Return the URDF geometry element."""
        return '<box size="%s"/>' % _fmt(self.size)


@dataclass(frozen=True)
class Cylinder:
    """Solid cylinder centred on its frame, axis along z.

    :param radius: radius (m).
    :param length: length along z (m).
    """

    radius: float
    length: float

    def inertia(self, mass: float) -> np.ndarray:
        """Return the 3x3 inertia (kg m^2) about the centre, in the shape frame."""
        r, h = self.radius, self.length
        side = mass * (3.0 * r * r + h * h) / 12.0
        return np.diag([side, side, 0.5 * mass * r * r])

    def urdf(self) -> str:
        """Return the URDF geometry element."""
        return '<cylinder radius="%s" length="%s"/>' % (_fmt([self.radius]), _fmt([self.length]))


@dataclass(frozen=True)
class Sphere:
    """Solid sphere centred on its frame.

    :param radius: radius (m).
    """

    radius: float

    def inertia(self, mass: float) -> np.ndarray:
        """Return the 3x3 inertia (kg m^2) about the centre."""
        return np.eye(3) * 0.4 * mass * self.radius ** 2

    def urdf(self) -> str:
        """Return the URDF geometry element."""
        return '<sphere radius="%s"/>' % _fmt([self.radius])


Geometry = Union[Box, Cylinder, Sphere]


@dataclass(frozen=True)
class Shape:
    """One solid primitive of a link: geometry, mass and pose in the link frame.

    :param geometry: the primitive.
    :param mass: mass (kg), > 0.
    :param xyz: position of the primitive centre in the link frame (m).
    :param rpy: orientation of the primitive in the link frame (rad, URDF roll-pitch-yaw).
    :param rgba: display colour.
    :param visual: whether the shape is drawn.
    :param collision: whether the shape collides.
    """

    geometry: Geometry
    mass: float
    xyz: tuple = (0.0, 0.0, 0.0)
    rpy: tuple = (0.0, 0.0, 0.0)
    rgba: tuple = (0.7, 0.7, 0.7, 1.0)
    visual: bool = True
    collision: bool = True

    def __post_init__(self):
        if not (math.isfinite(self.mass) and self.mass > 0.0):
            raise ConfigError('Shape.mass = %r kg must be finite and > 0' % (self.mass,))


@dataclass(frozen=True)
class Link:
    """A rigid link made of primitive shapes.

    :param name: URDF link name.
    :param shapes: the primitives (their masses sum to the link mass).
    """

    name: str
    shapes: tuple

    @property
    def mass(self) -> float:
        """Total mass (kg)."""
        return float(sum(s.mass for s in self.shapes))

    def composite_inertia(self) -> tuple:
        """Return (com (3,), inertia about the com (3, 3)) in the link frame (m, kg m^2).

        Each shape's inertia is rotated into the link frame, I_i' = R_i I_i R_i^T, and moved to
        the composite centre of mass with the parallel axis theorem, m_i (|d|^2 E - d d^T).
        """
        masses = np.array([s.mass for s in self.shapes])
        centres = np.array([s.xyz for s in self.shapes], dtype=float)
        com = masses @ centres / masses.sum()
        inertia = np.zeros((3, 3))
        for shape, centre in zip(self.shapes, centres):
            rot = rpy_to_matrix(shape.rpy)
            d = centre - com
            inertia += rot @ shape.geometry.inertia(shape.mass) @ rot.T
            inertia += shape.mass * (d @ d * np.eye(3) - np.outer(d, d))
        return com, inertia


@dataclass(frozen=True)
class JointLimits:
    """Limits of a revolute joint.

    :param lower: lower position limit (rad).
    :param upper: upper position limit (rad).
    :param effort: maximum torque (N m).
    :param velocity: maximum speed (rad/s).
    """

    lower: float
    upper: float
    effort: float
    velocity: float

    def __post_init__(self):
        if not self.lower < self.upper:
            raise ConfigError('JointLimits: lower = %r must be < upper = %r'
                              % (self.lower, self.upper))
        if not (self.effort > 0.0 and self.velocity > 0.0):
            raise ConfigError('JointLimits: effort = %r and velocity = %r must be > 0'
                              % (self.effort, self.velocity))


@dataclass(frozen=True)
class Joint:
    """A URDF joint (revolute or fixed).

    :param name: URDF joint name.
    :param parent: parent link name.
    :param child: child link name.
    :param xyz: joint origin in the parent link frame (m).
    :param axis: rotation axis in the joint frame (unit vector), ignored for fixed joints.
    :param limits: limits of a revolute joint; None makes the joint fixed.
    :param damping: viscous joint damping (N m s/rad).
    """

    name: str
    parent: str
    child: str
    xyz: tuple
    axis: tuple = (0.0, 0.0, 1.0)
    limits: Optional[JointLimits] = None
    damping: float = 0.0

    @property
    def is_fixed(self) -> bool:
        """True for a fixed joint."""
        return self.limits is None


@dataclass(frozen=True)
class UrdfRobot:
    """Links and joints of a robot, in URDF order (parents before children)."""

    name: str
    links: tuple
    joints: tuple = field(default_factory=tuple)

    @property
    def mass(self) -> float:
        """Total mass (kg)."""
        return float(sum(link.mass for link in self.links))

    def to_urdf(self) -> str:
        """Return the URDF text of the robot."""
        lines = ['<?xml version="1.0"?>',
                 '<!-- Generated by biped_sim/robot_builder.py: do not edit by hand. -->',
                 '<robot name="%s">' % self.name]
        for link in self.links:
            lines.extend(_link_urdf(link))
        for joint in self.joints:
            lines.extend(_joint_urdf(joint))
        lines.append('</robot>')
        return '\n'.join(lines) + '\n'


def rpy_to_matrix(rpy) -> np.ndarray:
    """Return the rotation matrix of URDF roll-pitch-yaw angles, R = Rz(y) Ry(p) Rx(r).

    :param rpy: (roll, pitch, yaw) (rad).
    :return: (3, 3) rotation matrix.
    """
    roll, pitch, yaw = rpy
    return rotation_z(yaw) @ rotation_y(pitch) @ rotation_x(roll)


def matrix_to_rpy(rot: np.ndarray) -> tuple:
    """Return URDF roll-pitch-yaw angles (rad) of a rotation matrix, inverse of rpy_to_matrix."""
    roll, pitch = roll_pitch_of_matrix(rot)
    return roll, pitch, yaw_of_matrix(rot)


def principal_axes(inertia: np.ndarray) -> tuple:
    """Diagonalise a symmetric inertia: return (moments (3,), rotation (3, 3) with det +1).

    inertia = rotation @ diag(moments) @ rotation.T. Axes close to the link axes are kept in
    place (each eigenvector goes to the link axis it is closest to) so that the URDF stays
    readable.
    """
    moments, vectors = np.linalg.eigh(inertia)
    order = np.argsort(-np.abs(vectors), axis=None)
    assigned_rows, assigned_cols, perm = set(), set(), [0, 0, 0]
    for flat in order:
        row, col = divmod(int(flat), 3)
        if row in assigned_rows or col in assigned_cols:
            continue
        perm[row] = col
        assigned_rows.add(row)
        assigned_cols.add(col)
    vectors = vectors[:, perm]
    moments = moments[perm]
    for k in range(3):
        if vectors[k, k] < 0.0:
            vectors[:, k] = -vectors[:, k]
    if np.linalg.det(vectors) < 0.0:
        vectors[:, 2] = -vectors[:, 2]
    return moments, vectors


def _fmt(values) -> str:
    return ' '.join(('%.9g' % v) if abs(v) > 1e-15 else '0' for v in values)


def _link_urdf(link: Link) -> list:
    com, inertia = link.composite_inertia()
    moments, axes = principal_axes(inertia)
    lines = ['  <link name="%s">' % link.name,
             '    <inertial>',
             '      <origin xyz="%s" rpy="%s"/>' % (_fmt(com), _fmt(matrix_to_rpy(axes))),
             '      <mass value="%s"/>' % _fmt([link.mass]),
             '      <inertia ixx="%s" ixy="0" ixz="0" iyy="%s" iyz="0" izz="%s"/>'
             % (_fmt([moments[0]]), _fmt([moments[1]]), _fmt([moments[2]])),
             '    </inertial>']
    for shape in link.shapes:
        origin = '<origin xyz="%s" rpy="%s"/>' % (_fmt(shape.xyz), _fmt(shape.rpy))
        if shape.visual:
            lines += ['    <visual>', '      ' + origin,
                      '      <geometry>%s</geometry>' % shape.geometry.urdf(),
                      '      <material name="%s_%d"><color rgba="%s"/></material>'
                      % (link.name, link.shapes.index(shape), _fmt(shape.rgba)),
                      '    </visual>']
        if shape.collision:
            lines += ['    <collision>', '      ' + origin,
                      '      <geometry>%s</geometry>' % shape.geometry.urdf(),
                      '    </collision>']
    lines.append('  </link>')
    return lines


def _joint_urdf(joint: Joint) -> list:
    kind = 'fixed' if joint.is_fixed else 'revolute'
    lines = ['  <joint name="%s" type="%s">' % (joint.name, kind),
             '    <parent link="%s"/>' % joint.parent,
             '    <child link="%s"/>' % joint.child,
             '    <origin xyz="%s" rpy="0 0 0"/>' % _fmt(joint.xyz)]
    if not joint.is_fixed:
        lim = joint.limits
        lines += ['    <axis xyz="%s"/>' % _fmt(joint.axis),
                  '    <limit lower="%s" upper="%s" effort="%s" velocity="%s"/>'
                  % (_fmt([lim.lower]), _fmt([lim.upper]), _fmt([lim.effort]),
                     _fmt([lim.velocity])),
                  '    <dynamics damping="%s" friction="0"/>' % _fmt([joint.damping])]
    lines.append('  </joint>')
    return lines
