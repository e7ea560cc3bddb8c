"""The robot as the controller sees it: leg geometry, joint and frame names, the model's masses.

Data, described once per robot in a YAML file (robots/<name>.yaml beside this module for the
robots shipped here); the simulator builds its URDF from the same leg geometry, and the MPC
node loads the file named by its robot_description_file parameter.
"""
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import yaml

from biped_mpc.errors import ConfigError
from biped_mpc.three_mass_model import ThreeMassParams
from biped_mpc.validation import check_positive, number_tuple

ROBOTS_DIR = Path(__file__).resolve().parent / 'robots'
COMAN_LIKE_MODEL_FILE = ROBOTS_DIR / 'coman_like.yaml'


@dataclass(frozen=True)
class LegGeometry:
    """Leg dimensions of a robot with intersecting hip axes and intersecting ankle axes.

    Zero joint angles put the leg straight down with the foot parallel to the pelvis; the right
    leg mirrors the left one in y. The analytic IK and the leg kinematics need these.

    :param hip_offset: left hip centre in the pelvis frame (m); the right one mirrors y.
    :param thigh_length: hip centre to knee axis (m), > 0.
    :param shank_length: knee axis to ankle centre (m), > 0.
    :param ankle_to_sole: left sole centre from the ankle centre, foot frame (m); right mirrors y.
    :param joint_lower: (12,) lower joint limits, left leg then right leg (rad).
    :param joint_upper: (12,) upper joint limits (rad), above joint_lower.
    """

    hip_offset: tuple
    thigh_length: float
    shank_length: float
    ankle_to_sole: tuple
    joint_lower: tuple
    joint_upper: tuple

    def __post_init__(self):
        for name, size in (('hip_offset', 3), ('ankle_to_sole', 3), ('joint_lower', 12),
                           ('joint_upper', 12)):
            object.__setattr__(self, name, number_tuple(name, getattr(self, name), size))
        check_positive('thigh_length', self.thigh_length)
        check_positive('shank_length', self.shank_length)
        if not all(lo < hi for lo, hi in zip(self.joint_lower, self.joint_upper)):
            raise ConfigError('joint_lower %r must be below joint_upper %r'
                              % (self.joint_lower, self.joint_upper))


@dataclass(frozen=True)
class RobotModel:
    """What the walking controller needs to know about a humanoid.

    :param name: robot name
    :param leg_joint_names: the 12 leg joints, left leg then right leg, each hip yaw, hip roll,
        hip pitch, knee, ankle pitch, ankle roll
    :param sole_frames: (left, right) frames at the sole centres, z up
    :param leg_geometry: dimensions for the analytic IK, None when the legs do not allow it
    :param masses: the three-mass model of the robot (kg, m)
    :param pelvis_height: pelvis frame above the soles when standing (m)
    :param com_offset: whole-body centre of mass ahead of and left of the pelvis (m)
    :param urdf_path: the robot's URDF, needed by the Pinocchio IK only ('' without it)
    """

    name: str
    leg_joint_names: tuple
    sole_frames: tuple
    leg_geometry: Optional[LegGeometry]
    masses: ThreeMassParams
    pelvis_height: float
    com_offset: tuple = (0.0, 0.0)
    urdf_path: str = ''

    def __post_init__(self):
        object.__setattr__(self, 'leg_joint_names', tuple(self.leg_joint_names))
        object.__setattr__(self, 'sole_frames', tuple(self.sole_frames))
        if len(self.leg_joint_names) != 12 or len(set(self.leg_joint_names)) != 12:
            raise ConfigError('leg_joint_names = %r must be 12 distinct names'
                              % (self.leg_joint_names,))
        if len(self.sole_frames) != 2:
            raise ConfigError('sole_frames = %r must be (left, right)' % (self.sole_frames,))
        if not isinstance(self.masses, ThreeMassParams):
            raise ConfigError('masses must be ThreeMassParams, got %r' % (self.masses,))
        check_positive('pelvis_height', self.pelvis_height, 5.0)
        offset = number_tuple('com_offset', self.com_offset, 2)
        if any(abs(v) > 0.5 for v in offset):
            raise ConfigError('com_offset = %r m must be within 0.5 m' % (self.com_offset,))
        object.__setattr__(self, 'com_offset', offset)


def load_robot_model(path) -> RobotModel:
    """Read a robot model file (YAML: the fields of RobotModel, masses and leg_geometry as maps).

    :param path: the file
    :return: the model
    :raises ConfigError: when the file is missing, not YAML, or its values are refused
    """
    try:
        data = yaml.safe_load(Path(path).read_text())
    except (OSError, yaml.YAMLError) as error:
        raise ConfigError(f'cannot read robot model file {path}: {error}') from error
    if not isinstance(data, dict):
        raise ConfigError(f'robot model file {path} must hold a map, got {type(data).__name__}')
    try:
        geometry = data.get('leg_geometry')
        return RobotModel(
            name=str(data['name']), leg_joint_names=tuple(data['leg_joint_names']),
            sole_frames=tuple(data['sole_frames']),
            leg_geometry=LegGeometry(**geometry) if geometry is not None else None,
            masses=ThreeMassParams(**data['masses']), pelvis_height=data['pelvis_height'],
            com_offset=tuple(data.get('com_offset', (0.0, 0.0))),
            urdf_path=str(data.get('urdf_path', '')))
    except (KeyError, TypeError, ValueError) as error:
        raise ConfigError(f'robot model file {path}: {error!r}') from error
