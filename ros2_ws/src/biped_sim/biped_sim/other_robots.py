"""Other humanoids for the stack, from the optional example-robot-data package.

``pip install -r requirements-robots.txt`` installs example-robot-data (URDFs and meshes of
public robots, about 130 MB to download, 440 MB installed). Each factory here returns a
:class:`RobotDescription` of one of its humanoids; the stack needs nothing else to load it.

The robots' own URDFs are not used as they are: each factory writes a copy into a cache folder
with ``package://`` mesh paths made absolute (PyBullet and Pinocchio then need no search path),
a sole frame added where the robot has none, and a small inertial (INERTIAL_FILL_MASS) given to
the links without one (PyBullet gives such links 1 kg while Pinocchio gives them none, which
would make the gravity compensation wrong by that much).

Neither robot has ankle force/torque joints in its URDF: the simulator reads their feet's
contact forces instead (RobotDescription.ft_joints == ()). Their leg_geometry is None: the leg
IK is biped_mpc.pinocchio_ik (G1's hip axes do not intersect; TALOS's do, and a LegGeometry for
the analytic IK could be added for it).

| robot | mass | height, nominal pose | leg joints: hip yaw, roll, pitch, knee, ankle pitch, roll |
|---|---|---|---|
| g1 (Unitree G1, 29 DOF) | 33.3 kg | 1.30 m | ``{side}_hip_yaw_joint`` ... (chain: pitch first) |
| talos (PAL TALOS reduced, 32 DOF) | 90.3 kg | 1.76 m | ``leg_{side}_1_joint`` ... ``_6_joint`` |

sim_config gives the torque-mode settings each robot stands and steps with
(biped_sim.weight_shift_trial checks it); docs/simulator_notes.md has the measured margins.
"""

import importlib.metadata
import os
from pathlib import Path
import tempfile
from typing import Optional
import xml.etree.ElementTree as ElementTree

from biped_sim.errors import BipedSimError, ConfigError
from biped_sim.pybullet_config import PyBulletConfig
from biped_sim.robot_description import RobotDescription

INSTALL_HINT = 'pip install -r requirements-robots.txt'
DISTRIBUTION = 'example-robot-data'
INERTIAL_FILL_MASS = 1e-3  # kg given to URDF links that have no <inertial>
_INERTIAL_FILL_INERTIA = 1e-7  # kg m^2, each principal moment of those links


class MissingRobotDataError(BipedSimError, ImportError):
    """The optional example-robot-data package is not installed."""


def example_robot_data_share() -> Path:
    """Return the folder that ``package://`` paths of example-robot-data resolve against.

    :return: <site-packages>/cmeel.prefix/share (holds the folder example-robot-data).
    :raises MissingRobotDataError: if example-robot-data is not installed.
    """
    try:
        distribution = importlib.metadata.distribution(DISTRIBUTION)
    except importlib.metadata.PackageNotFoundError as error:
        raise MissingRobotDataError('the other robots need the optional package %s: %s'
                                    % (DISTRIBUTION, INSTALL_HINT)) from error
    share = Path(distribution.locate_file('cmeel.prefix/share'))
    if not (share / DISTRIBUTION / 'robots').is_dir():
        raise MissingRobotDataError('%s %s is installed but %s has no robots: %s'
                                    % (DISTRIBUTION, distribution.version, share, INSTALL_HINT))
    return share


def _cache_dir(cache_dir: Optional[str]) -> Path:
    path = Path(cache_dir) if cache_dir else Path(tempfile.gettempdir()) / 'biped_sim_robots'
    path.mkdir(parents=True, exist_ok=True)
    return path


def _add_fill_inertial(link) -> None:
    inertial = ElementTree.SubElement(link, 'inertial')
    ElementTree.SubElement(inertial, 'mass', value=repr(INERTIAL_FILL_MASS))
    moment = repr(_INERTIAL_FILL_INERTIA)
    ElementTree.SubElement(inertial, 'inertia', ixx=moment, iyy=moment, izz=moment, ixy='0',
                           ixz='0', iyz='0')


def _prepared_urdf(name: str, source: str, extra_frames: dict, cache_dir: Optional[str]) -> str:
    """Write the robot's URDF ready for the stack and return its path.

    :param name: robot name, the file name in the cache.
    :param source: URDF path relative to the example-robot-data folder.
    :param extra_frames: new frame (link) name -> (parent link, (x, y, z) offset in the parent
        frame (m)), axes parallel to the parent's: the sole and IMU frames the robot lacks.
    :param cache_dir: folder of the written URDF; None for <tmp>/biped_sim_robots.
    :return: absolute path of the written URDF.
    """
    share = example_robot_data_share()
    tree = ElementTree.parse(share / DISTRIBUTION / source)
    root = tree.getroot()
    for mesh in root.iter('mesh'):
        filename = mesh.get('filename', '')
        if filename.startswith('package://'):
            mesh.set('filename', str(share / filename[len('package://'):]))
    for link in root.findall('link'):
        if link.find('inertial') is None:
            _add_fill_inertial(link)
    for frame, (parent, offset) in extra_frames.items():
        _add_fill_inertial(ElementTree.SubElement(root, 'link', name=frame))
        joint = ElementTree.SubElement(root, 'joint', name=frame + '_joint', type='fixed')
        ElementTree.SubElement(joint, 'parent', link=parent)
        ElementTree.SubElement(joint, 'child', link=frame)
        ElementTree.SubElement(joint, 'origin', xyz='%r %r %r' % tuple(offset), rpy='0 0 0')
    text = ElementTree.tostring(root, encoding='unicode')
    path = _cache_dir(cache_dir) / ('%s.urdf' % name)
    if not (path.is_file() and path.read_text() == text):
        # Write then rename, so a concurrent reader never sees half a file.
        handle, temporary = tempfile.mkstemp(dir=path.parent, suffix='.urdf')
        with os.fdopen(handle, 'w') as stream:
            stream.write(text)
        os.replace(temporary, path)
    return str(path)


G1_SOLE_OFFSET = (0.035, 0.0, -0.035)  # m, sole centre in the ankle roll link frame


def g1(cache_dir: Optional[str] = None) -> RobotDescription:
    """Return the description of the Unitree G1 (29 DOF, 33.3 kg) of example-robot-data.

    Its feet touch the ground with four 5 mm spheres each, at x in [-0.05, 0.12] m and
    y = +-0.025 (heel) to +-0.03 m (toe) of the ankle roll link, 0.035 m below it: the sole frame
    is added at their centre, the usable sole taken as 0.17 x 0.05 m. The IMU is the pelvis one.
    Its hip joints go pitch, roll, yaw from the pelvis (ours yaw, roll, pitch); the leg joints
    are given by role. The nominal pose bends the knees by 0.6 rad with flat feet.

    :param cache_dir: folder of the prepared URDF; None for <tmp>/biped_sim_robots.
    :raises MissingRobotDataError: if example-robot-data is not installed.
    """
    sides = ('left', 'right')
    roles = ('hip_yaw', 'hip_roll', 'hip_pitch', 'knee', 'ankle_pitch', 'ankle_roll')
    leg_joint_names = tuple('%s_%s_joint' % (side, role) for side in sides for role in roles)
    soles = {'%s_sole' % side: ('%s_ankle_roll_link' % side, G1_SOLE_OFFSET) for side in sides}
    urdf = _prepared_urdf('g1', 'robots/g1_description/urdf/g1_29dof_rev_1_0.urdf', soles,
                          cache_dir)
    nominal = {}
    for side, sign in (('left', 1.0), ('right', -1.0)):
        nominal.update({'%s_hip_pitch_joint' % side: -0.3, '%s_knee_joint' % side: 0.6,
                        '%s_ankle_pitch_joint' % side: -0.3,
                        '%s_shoulder_roll_joint' % side: 0.2 * sign,
                        '%s_elbow_joint' % side: 0.6})
    return RobotDescription(
        name='g1', urdf_path=urdf, base_link='pelvis', leg_joint_names=leg_joint_names,
        sole_frames=tuple(soles), imu_link='imu_in_pelvis', ft_joints=(), sole_length=0.17,
        sole_width=0.05, nominal_joint_positions=nominal, leg_geometry=None)


def talos(cache_dir: Optional[str] = None) -> RobotDescription:
    """Return the description of PAL's TALOS (reduced model, 32 DOF, 90.3 kg).

    Its sole frames (left_sole_link, right_sole_link) exist, 0.107 m below the ankles; the foot
    collision meshes span x in [-0.116, 0.105] m and y +-0.067 m, the usable sole is taken as
    0.20 x 0.12 m. Its own IMU (imu_link) sits on the upper torso, upside down; the stack reads
    the IMU as the pelvis orientation, so an IMU frame pelvis_imu_link is added at the pelvis
    frame. The nominal pose bends the knees by 0.6 rad with flat feet.

    :param cache_dir: folder of the prepared URDF; None for <tmp>/biped_sim_robots.
    :raises MissingRobotDataError: if example-robot-data is not installed.
    """
    leg_joint_names = tuple('leg_%s_%d_joint' % (side, k)
                            for side in ('left', 'right') for k in range(1, 7))
    urdf = _prepared_urdf('talos', 'robots/talos_data/robots/talos_reduced.urdf',
                          {'pelvis_imu_link': ('base_link', (0.0, 0.0, 0.0))}, cache_dir)
    nominal = {}
    for side, sign in (('left', 1.0), ('right', -1.0)):
        nominal.update({'leg_%s_3_joint' % side: -0.3, 'leg_%s_4_joint' % side: 0.6,
                        'leg_%s_5_joint' % side: -0.3, 'arm_%s_2_joint' % side: 0.2 * sign,
                        'arm_%s_4_joint' % side: -0.6})
    return RobotDescription(
        name='talos', urdf_path=urdf, base_link='base_link', leg_joint_names=leg_joint_names,
        sole_frames=('left_sole_link', 'right_sole_link'), imu_link='pelvis_imu_link',
        ft_joints=(), sole_length=0.20, sole_width=0.12, nominal_joint_positions=nominal,
        leg_geometry=None)


ROBOTS = {'g1': g1, 'talos': talos}

# Torque-mode settings for each robot (PyBulletConfig fields); the defaults are sized for the
# 31 kg COMAN-like robot. G1: softer upper-body gains keep its light wrists from chattering, and
# a full gain cap keeps the ankle roll of its light feet stiffer than m g h on 5 cm wide feet.
# TALOS (90 kg) needs stiffer legs.
SIM_SETTINGS = {
    'g1': {'gain_cap': 1.0, 'upper_kp': 100.0, 'upper_kd': 1.0},
    'talos': {'leg_kp': 3000.0, 'leg_kd': 30.0},
}


def sim_config(name: str, **overrides) -> PyBulletConfig:
    """Return the PyBullet settings that stand and step a robot of this module.

    :param name: a key of ROBOTS.
    :param overrides: other PyBulletConfig fields (gui, control_mode, ...).
    :raises ConfigError: for an unknown robot or a bad field.
    """
    if name not in SIM_SETTINGS:
        raise ConfigError('robot %r is not one of %s' % (name, sorted(SIM_SETTINGS)))
    return PyBulletConfig(**{**SIM_SETTINGS[name], **overrides})
