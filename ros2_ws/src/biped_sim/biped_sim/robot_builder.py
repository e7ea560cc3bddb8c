"""Generator of the COMAN-like humanoid URDF from primitive shapes with exact inertias.

The robot reproduces the simulated COMAN of the paper (section "Simulation using COMAN"): 0.95 m
tall, about 31 kg, 23 actuated joints (6 per leg: hip yaw, roll, pitch, knee pitch, ankle pitch,
roll; 3 in the waist; 4 per arm), an IMU link on the pelvis and a fixed force/torque joint at each
ankle. The three hip axes intersect at the hip centre and the two ankle axes at the ankle centre,
with no lateral offsets along the leg, so an exact analytic leg IK exists.

Every link is a set of primitive shapes (box, cylinder, sphere), each with its own mass. The
inertia of a link is the exact composite inertia of its shapes (parallel axis theorem), written
in its principal axes (``<inertial><origin rpy>`` with a diagonal tensor) because PyBullet reads
only the diagonal of a URDF inertia tensor.

Regenerate the committed URDF with ``python -m biped_sim.robot_builder``.
"""

from dataclasses import dataclass
from dataclasses import field
import math
from pathlib import Path
from typing import Optional, Union

import numpy as np

from biped_sim.errors import ConfigError

COMAN_LIKE_URDF = Path(__file__).resolve().parent / 'robots' / 'coman_like.urdf'


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
class RobotModel:
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
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = (math.cos(r), math.sin(r), math.cos(p), math.sin(p),
                              math.cos(y), math.sin(y))
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def matrix_to_rpy(rot: np.ndarray) -> tuple:
    """Return URDF roll-pitch-yaw angles (rad) of a rotation matrix, inverse of rpy_to_matrix."""
    pitch = math.atan2(-rot[2, 0], math.hypot(rot[0, 0], rot[1, 0]))
    roll = math.atan2(rot[2, 1], rot[2, 2])
    yaw = math.atan2(rot[1, 0], rot[0, 0])
    return roll, pitch, yaw


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


# COMAN-like dimensions (m). Straight legs: sole 0, ankle 0.06, knee 0.28, hip 0.50, pelvis
# frame 0.57, waist 0.63, shoulders 0.82, top of the head 0.95.
HIP_OFFSET = (0.0, 0.07, -0.07)
THIGH_LENGTH = 0.22
SHANK_LENGTH = 0.22
ANKLE_TO_FT = 0.02
FT_TO_SOLE = 0.04
FOOT_LENGTH = 0.20
FOOT_WIDTH = 0.10
FOOT_THICKNESS = 0.025
WAIST_OFFSET = 0.06
SHOULDER_OFFSET = (0.0, 0.155, 0.19)
UPPER_ARM_LENGTH = 0.20
IMU_OFFSET = (0.0, 0.0, 0.03)

_X, _Y, _Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
_ALONG_X = (0.0, math.pi / 2, 0.0)
_ALONG_Y = (math.pi / 2, 0.0, 0.0)
_GREY = (0.55, 0.57, 0.6, 1.0)
_DARK = (0.2, 0.22, 0.25, 1.0)
_ORANGE = (0.9, 0.45, 0.1, 1.0)
_WHITE = (0.92, 0.92, 0.92, 1.0)


def _leg(side: str, sign: float) -> tuple:
    """Return (links, joints) of one leg; sign is +1 for the left leg and -1 for the right."""
    p = side + '_'
    links = (
        Link(p + 'hip_yaw_link', (Shape(Cylinder(0.035, 0.04), 0.4, (0, 0, 0.02), rgba=_DARK),)),
        Link(p + 'hip_roll_link', (Shape(Box((0.07, 0.06, 0.06)), 0.6, rgba=_GREY),)),
        Link(p + 'thigh', (Shape(Cylinder(0.05, 0.18), 2.6, (0, 0, -0.11), rgba=_WHITE),)),
        Link(p + 'shank', (Shape(Cylinder(0.045, 0.18), 1.8, (0, 0, -0.11), rgba=_WHITE),)),
        Link(p + 'ankle_pitch_link', (Shape(Box((0.05, 0.05, 0.04)), 0.3, rgba=_DARK),)),
        Link(p + 'ankle_roll_link',
             (Shape(Box((0.06, 0.06, 0.02)), 0.2, (0, 0, -0.01), rgba=_DARK),)),
        Link(p + 'foot', (
            Shape(Box((FOOT_LENGTH, FOOT_WIDTH, FOOT_THICKNESS)), 0.7,
                  (0, 0, -FT_TO_SOLE + FOOT_THICKNESS / 2), rgba=_ORANGE),)),
        # The sole pad: the bottom 4 mm of the foot; its frame is the sole centre.
        Link(p + 'sole', (Shape(Box((FOOT_LENGTH, FOOT_WIDTH, 0.004)), 0.05, (0, 0, 0.002),
                                visual=False, collision=False),)),
    )
    roll_lim = (-0.45, 0.8) if sign > 0 else (-0.8, 0.45)
    yaw_lim = (-0.6, 0.9) if sign > 0 else (-0.9, 0.6)
    hip = (HIP_OFFSET[0], sign * HIP_OFFSET[1], HIP_OFFSET[2])
    joints = (
        Joint(p + 'hip_yaw_joint', 'pelvis', p + 'hip_yaw_link', hip, _Z,
              JointLimits(*yaw_lim, 50.0, 6.0), 0.05),
        Joint(p + 'hip_roll_joint', p + 'hip_yaw_link', p + 'hip_roll_link', (0, 0, 0), _X,
              JointLimits(*roll_lim, 90.0, 6.0), 0.05),
        Joint(p + 'hip_pitch_joint', p + 'hip_roll_link', p + 'thigh', (0, 0, 0), _Y,
              JointLimits(-1.9, 0.6, 110.0, 7.0), 0.05),
        Joint(p + 'knee_joint', p + 'thigh', p + 'shank', (0, 0, -THIGH_LENGTH), _Y,
              JointLimits(0.0, 2.3, 110.0, 7.0), 0.05),
        Joint(p + 'ankle_pitch_joint', p + 'shank', p + 'ankle_pitch_link',
              (0, 0, -SHANK_LENGTH), _Y, JointLimits(-1.0, 0.75, 90.0, 7.0), 0.05),
        Joint(p + 'ankle_roll_joint', p + 'ankle_pitch_link', p + 'ankle_roll_link', (0, 0, 0),
              _X, JointLimits(-0.5, 0.5, 60.0, 7.0), 0.05),
        Joint(p + 'ankle_ft_joint', p + 'ankle_roll_link', p + 'foot', (0, 0, -ANKLE_TO_FT)),
        Joint(p + 'sole_joint', p + 'foot', p + 'sole', (0, 0, -FT_TO_SOLE)),
    )
    return links, joints


def _arm(side: str, sign: float) -> tuple:
    """Return (links, joints) of one arm; sign is +1 for the left arm and -1 for the right."""
    p = side + '_'
    links = (
        Link(p + 'shoulder_pitch_link',
             (Shape(Cylinder(0.03, 0.05), 0.3, rpy=_ALONG_Y, rgba=_DARK),)),
        Link(p + 'shoulder_roll_link', (Shape(Box((0.05, 0.05, 0.05)), 0.3, rgba=_GREY),)),
        Link(p + 'upper_arm', (Shape(Cylinder(0.03, 0.15), 1.0, (0, 0, -0.1), rgba=_WHITE),)),
        Link(p + 'forearm', (Shape(Cylinder(0.025, 0.17), 0.65, (0, 0, -0.1), rgba=_WHITE),
                             Shape(Sphere(0.03), 0.15, (0, 0, -0.2), rgba=_DARK))),
    )
    roll_lim = (-0.3, 1.6) if sign > 0 else (-1.6, 0.3)
    yaw_lim = (-1.5, 1.5)
    shoulder = (SHOULDER_OFFSET[0], sign * SHOULDER_OFFSET[1], SHOULDER_OFFSET[2])
    joints = (
        Joint(p + 'shoulder_pitch_joint', 'torso', p + 'shoulder_pitch_link', shoulder, _Y,
              JointLimits(-2.0, 1.2, 30.0, 6.0), 0.05),
        Joint(p + 'shoulder_roll_joint', p + 'shoulder_pitch_link', p + 'shoulder_roll_link',
              (0, 0, 0), _X, JointLimits(*roll_lim, 30.0, 6.0), 0.05),
        Joint(p + 'shoulder_yaw_joint', p + 'shoulder_roll_link', p + 'upper_arm', (0, 0, 0),
              _Z, JointLimits(*yaw_lim, 20.0, 6.0), 0.05),
        Joint(p + 'elbow_joint', p + 'upper_arm', p + 'forearm', (0, 0, -UPPER_ARM_LENGTH), _Y,
              JointLimits(-2.2, 0.0, 20.0, 6.0), 0.05),
    )
    return links, joints


def build_coman_like() -> RobotModel:
    """Return the COMAN-like humanoid: 23 actuated joints, 2 ankle F/T joints, IMU, soles."""
    torso_top = 0.23
    head_top = 0.32
    links = [
        Link('pelvis', (Shape(Box((0.12, 0.22, 0.08)), 3.4, rgba=_GREY),)),
        Link('imu_link', (Shape(Box((0.03, 0.03, 0.01)), 0.05, rgba=_ORANGE, collision=False),)),
        Link('waist_yaw_link', (Shape(Cylinder(0.04, 0.03), 0.3, (0, 0, -0.015), rgba=_DARK),)),
        Link('waist_pitch_link', (Shape(Box((0.05, 0.06, 0.03)), 0.3, rgba=_DARK),)),
        Link('torso', (
            Shape(Box((0.14, 0.24, 0.21)), 7.6, (0, 0, 0.125), rgba=_WHITE),
            Shape(Cylinder(0.025, 0.03), 0.2, (0, 0, torso_top + 0.015), rgba=_DARK),
            Shape(Sphere(0.065), 1.0, (0, 0, head_top - 0.065), rgba=_GREY))),
    ]
    joints = [
        Joint('imu_joint', 'pelvis', 'imu_link', IMU_OFFSET),
        Joint('waist_yaw_joint', 'pelvis', 'waist_yaw_link', (0, 0, WAIST_OFFSET), _Z,
              JointLimits(-0.8, 0.8, 80.0, 5.0), 0.05),
        Joint('waist_pitch_joint', 'waist_yaw_link', 'waist_pitch_link', (0, 0, 0), _Y,
              JointLimits(-0.3, 0.8, 80.0, 5.0), 0.05),
        Joint('waist_roll_joint', 'waist_pitch_link', 'torso', (0, 0, 0), _X,
              JointLimits(-0.5, 0.5, 80.0, 5.0), 0.05),
    ]
    for side, sign in (('l', 1.0), ('r', -1.0)):
        leg_links, leg_joints = _leg(side, sign)
        links.extend(leg_links)
        joints.extend(leg_joints)
    for side, sign in (('l', 1.0), ('r', -1.0)):
        arm_links, arm_joints = _arm(side, sign)
        links.extend(arm_links)
        joints.extend(arm_joints)
    return RobotModel('coman_like', tuple(links), tuple(joints))


def write_urdf(model: RobotModel, path: Path) -> Path:
    """Write a robot's URDF to path (directories created) and return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(model.to_urdf())
    return path


def main() -> None:
    """Regenerate the committed COMAN-like URDF."""
    model = build_coman_like()
    print('wrote %s (%.2f kg)' % (write_urdf(model, COMAN_LIKE_URDF), model.mass))


if __name__ == '__main__':
    main()
