"""Generator of the COMAN-like humanoid URDF from primitive shapes with exact inertias.

The robot reproduces the simulated COMAN of the paper (section "Simulation using COMAN"): 0.95 m
tall, about 31 kg, 23 actuated joints (6 per leg: hip yaw, roll, pitch, knee pitch, ankle pitch,
roll; 3 in the waist; 4 per arm), an IMU link on the pelvis and a fixed force/torque joint at each
ankle. The three hip axes intersect at the hip centre and the two ankle axes at the ankle centre,
with no lateral offsets along the leg, so an exact analytic leg IK exists.

The legs (hip offset, thigh and shank lengths, ankle to sole, joint limits) are the LegGeometry
of the controller's robot model, biped_mpc/robots/coman_like.yaml, so the controller and the
simulated robot share one set of numbers; the rest of the body is described here. The links are
built from the primitives of :mod:`biped_sim.urdf_model`.

Regenerate the committed URDF with ``python -m biped_sim.robot_builder``.
"""

import math
from pathlib import Path

from biped_mpc.robot_model import COMAN_LIKE_MODEL_FILE, load_robot_model

from biped_sim.urdf_model import (Box, Cylinder, Joint, JointLimits, Link, Shape, Sphere,
                                  UrdfRobot)

COMAN_LIKE_URDF = Path(__file__).resolve().parent / 'robots' / 'coman_like.urdf'
# The COMAN-like robot as the controller sees it; its legs are the URDF's.
COMAN_LIKE_MODEL = load_robot_model(COMAN_LIKE_MODEL_FILE)
COMAN_LIKE_LEGS = COMAN_LIKE_MODEL.leg_geometry

# COMAN-like dimensions (m). Straight legs: sole 0, ankle 0.06, knee 0.28, hip 0.50, pelvis
# frame 0.57, waist 0.63, shoulders 0.82, top of the head 0.95. The ankle F/T sensor sits
# FT_TO_SOLE above the sole, the rest of the ankle-to-sole distance above the sensor.
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
# N m: hip yaw, hip roll, hip pitch, knee, ankle pitch, ankle roll
_LEG_EFFORTS = (50.0, 90.0, 110.0, 110.0, 90.0, 60.0)


def _leg(side: str, sign: float) -> tuple:
    """Return (links, joints) of one leg; sign is +1 for the left leg and -1 for the right."""
    p = side + '_'
    legs = COMAN_LIKE_LEGS
    ankle_to_ft = -legs.ankle_to_sole[2] - FT_TO_SOLE
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
    first = 0 if sign > 0 else 6
    lower = legs.joint_lower[first:first + 6]
    upper = legs.joint_upper[first:first + 6]
    limits = [JointLimits(lo, hi, effort, 6.0 if k < 2 else 7.0)
              for k, (lo, hi, effort) in enumerate(zip(lower, upper, _LEG_EFFORTS))]
    hip = (legs.hip_offset[0], sign * legs.hip_offset[1], legs.hip_offset[2])
    joints = (
        Joint(p + 'hip_yaw_joint', 'pelvis', p + 'hip_yaw_link', hip, _Z, limits[0], 0.05),
        Joint(p + 'hip_roll_joint', p + 'hip_yaw_link', p + 'hip_roll_link', (0, 0, 0), _X,
              limits[1], 0.05),
        Joint(p + 'hip_pitch_joint', p + 'hip_roll_link', p + 'thigh', (0, 0, 0), _Y,
              limits[2], 0.05),
        Joint(p + 'knee_joint', p + 'thigh', p + 'shank', (0, 0, -legs.thigh_length), _Y,
              limits[3], 0.05),
        Joint(p + 'ankle_pitch_joint', p + 'shank', p + 'ankle_pitch_link',
              (0, 0, -legs.shank_length), _Y, limits[4], 0.05),
        Joint(p + 'ankle_roll_joint', p + 'ankle_pitch_link', p + 'ankle_roll_link', (0, 0, 0),
              _X, limits[5], 0.05),
        Joint(p + 'ankle_ft_joint', p + 'ankle_roll_link', p + 'foot', (0, 0, -ankle_to_ft)),
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


def build_coman_like() -> UrdfRobot:
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
    return UrdfRobot('coman_like', tuple(links), tuple(joints))


def write_urdf(model: UrdfRobot, path: Path) -> Path:
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
