"""Robot description: what the simulator needs to know about a humanoid, and the controller's view.

Any humanoid loads through a :class:`RobotDescription`: its URDF, the 12 leg joints in the order
(left hip yaw, hip roll, hip pitch, knee, ankle pitch, ankle roll, then the same for the right
leg), the sole frames, the IMU link, the ankle force/torque joints and a nominal standing pose.
A robot whose legs have intersecting hip and ankle axes also gives its :class:`LegGeometry`
for the exact analytic IK. A robot the walking controller drives carries its
``controller_model``, the biped_mpc RobotModel (leg geometry, masses, pelvis height) read from
the same description file the MPC node loads: the COMAN-like robot's is
biped_mpc/robots/coman_like.yaml, whose legs the URDF is built from.
"""

import dataclasses
from dataclasses import dataclass
from dataclasses import field
import math
from pathlib import Path
from types import MappingProxyType
from typing import Mapping, Optional

import numpy as np

from biped_mpc.robot_model import LegGeometry, RobotModel

from biped_sim import robot_builder
from biped_sim.errors import ConfigError

@dataclass(frozen=True)
class RobotDescription:
    """Everything the stack needs to know about a humanoid beyond its URDF.

    :param name: robot name.
    :param urdf_path: absolute path of the URDF file.
    :param base_link: the floating base (pelvis) link; its frame is the hip pose of the IK.
    :param leg_joint_names: the 12 leg joints, left leg then right leg, each in the order
        hip yaw, hip roll, hip pitch, knee, ankle pitch, ankle roll.
    :param sole_frames: (left, right) links whose frames are at the sole centres, z up.
    :param imu_link: link of the IMU.
    :param ft_joints: (left, right) fixed joints of the ankle force/torque sensors, or () for a
        robot without them (the simulator then reads the feet's contact forces instead).
    :param sole_length: length of the foot sole along its x axis (m).
    :param sole_width: width of the foot sole along its y axis (m).
    :param nominal_joint_positions: standing pose, joint name -> angle (rad); joints not listed
        stand at 0.
    :param leg_geometry: dimensions for the analytic leg IK, None if the legs do not allow it.
    :param controller_model: the robot as the walking controller sees it (same leg joints, sole
        frames and leg geometry), None for a robot without one.
    """

    name: str
    urdf_path: str
    base_link: str
    leg_joint_names: tuple
    sole_frames: tuple
    imu_link: str
    ft_joints: tuple
    sole_length: float
    sole_width: float
    nominal_joint_positions: Mapping = field(default_factory=dict)
    leg_geometry: Optional[LegGeometry] = None
    controller_model: Optional[RobotModel] = None

    def __post_init__(self):
        if not Path(self.urdf_path).is_file():
            raise ConfigError('urdf_path = %r is not a file' % (self.urdf_path,))
        if len(self.leg_joint_names) != 12 or len(set(self.leg_joint_names)) != 12:
            raise ConfigError('leg_joint_names = %r must be 12 distinct names'
                              % (self.leg_joint_names,))
        if len(self.sole_frames) != 2:
            raise ConfigError('sole_frames = %r must be (left, right)' % (self.sole_frames,))
        if len(self.ft_joints) not in (0, 2):
            raise ConfigError('ft_joints = %r must be (left, right), or () without ankle F/T '
                              'sensors' % (self.ft_joints,))
        for name in ('sole_length', 'sole_width'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError('%s = %r m must be finite and > 0' % (name, value))
        nominal = {str(k): float(v) for k, v in dict(self.nominal_joint_positions).items()}
        bad = {k: v for k, v in nominal.items() if not math.isfinite(v)}
        if bad:
            raise ConfigError('nominal_joint_positions has non-finite angles %r' % (bad,))
        object.__setattr__(self, 'nominal_joint_positions', MappingProxyType(nominal))
        object.__setattr__(self, 'leg_joint_names', tuple(self.leg_joint_names))
        object.__setattr__(self, 'sole_frames', tuple(self.sole_frames))
        object.__setattr__(self, 'ft_joints', tuple(self.ft_joints))
        model = self.controller_model
        if model is not None:
            if not isinstance(model, RobotModel):
                raise ConfigError('controller_model must be a biped_mpc RobotModel, got %r'
                                  % (model,))
            if (model.leg_joint_names, model.sole_frames, model.leg_geometry) != (
                    self.leg_joint_names, self.sole_frames, self.leg_geometry):
                raise ConfigError('controller_model %r names other leg joints, sole frames or '
                                  'leg geometry than the description' % (model.name,))

    def nominal_leg_positions(self) -> np.ndarray:
        """Return the nominal angles of the 12 leg joints (rad), leg-joint order."""
        return np.array([self.nominal_joint_positions.get(n, 0.0) for n in self.leg_joint_names])


def crouched_leg_angles(geometry: LegGeometry, hip_height: float) -> np.ndarray:
    """Return the 6 angles of a leg standing straight below its hip with the knee bent.

    The hip centre is hip_height above the sole, directly above the ankle, with the foot flat:
    hip pitch = ankle pitch = -theta and knee = 2 theta for equal thigh and shank, in general
    from the law of cosines.

    :param geometry: leg dimensions.
    :param hip_height: height of the hip centre above the sole (m).
    :return: (6,) hip yaw, hip roll, hip pitch, knee, ankle pitch, ankle roll (rad).
    :raises ConfigError: if the height cannot be reached with a bent knee.
    """
    a, b = geometry.thigh_length, geometry.shank_length
    d = hip_height + geometry.ankle_to_sole[2]
    if not (abs(a - b) < d < a + b):
        raise ConfigError('hip_height = %r m is out of the leg range (%.3f, %.3f) m'
                          % (hip_height, abs(a - b) - geometry.ankle_to_sole[2],
                             a + b - geometry.ankle_to_sole[2]))
    knee = math.pi - math.acos((a * a + b * b - d * d) / (2.0 * a * b))
    hip = -math.acos((a * a + d * d - b * b) / (2.0 * a * d))
    return np.array([0.0, 0.0, hip, knee, -(knee + hip), 0.0])


COMAN_LIKE_NOMINAL_HIP_HEIGHT = 0.47  # m, hip centre above the soles when standing crouched


def coman_like() -> RobotDescription:
    """Return the description of the COMAN-like humanoid built by robot_builder.

    Its leg geometry and controller model are biped_mpc/robots/coman_like.yaml's (the URDF's
    legs are built from it). The nominal pose stands crouched with the hip centres
    COMAN_LIKE_NOMINAL_HIP_HEIGHT above the soles (pelvis frame 0.07 m higher), feet below the
    hips, arms slightly bent.
    """
    controller_model = dataclasses.replace(robot_builder.COMAN_LIKE_MODEL,
                                           urdf_path=str(robot_builder.COMAN_LIKE_URDF))
    geometry = controller_model.leg_geometry
    leg = crouched_leg_angles(geometry, COMAN_LIKE_NOMINAL_HIP_HEIGHT)
    leg_joint_names = controller_model.leg_joint_names
    nominal = {name: float(angle) for name, angle in zip(leg_joint_names, np.tile(leg, 2))}
    nominal.update({'l_shoulder_roll_joint': 0.15, 'r_shoulder_roll_joint': -0.15,
                    'l_elbow_joint': -0.4, 'r_elbow_joint': -0.4})
    return RobotDescription(
        name='coman_like',
        urdf_path=str(robot_builder.COMAN_LIKE_URDF),
        base_link='pelvis',
        leg_joint_names=leg_joint_names,
        sole_frames=controller_model.sole_frames,
        imu_link='imu_link',
        ft_joints=('l_ankle_ft_joint', 'r_ankle_ft_joint'),
        sole_length=robot_builder.FOOT_LENGTH,
        sole_width=robot_builder.FOOT_WIDTH,
        nominal_joint_positions=nominal,
        leg_geometry=geometry,
        controller_model=controller_model)
