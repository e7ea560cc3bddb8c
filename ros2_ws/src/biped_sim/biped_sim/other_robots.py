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

Both stand and step under torque control with the settings of sim_config (SIM_SETTINGS) and the
weight_shift_trial here (scripts/other_robot_demo.py prints the figures). TALOS is the more
robust: it also steps with the backend's default gains and with a 1.5 s weight shift; G1, on feet
5 cm wide, needs its settings and a weight shift of 2 s or more.
"""

from dataclasses import dataclass
import importlib.metadata
import math
import os
from pathlib import Path
import tempfile
from typing import Optional
import xml.etree.ElementTree as ElementTree

import numpy as np

from biped_sim.errors import BipedSimError, ConfigError
from biped_sim.pybullet_backend import PyBulletConfig
from biped_sim.robot_description import RobotDescription
from biped_sim.sensors import SensorReadings

try:
    import pinocchio as pin
except ImportError as error:  # pragma: no cover - pinocchio is a hard dependency
    raise ImportError('biped_sim.other_robots needs pinocchio: pip install pin') from error

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

# Torque-mode settings for each robot (PyBulletConfig fields). With the defaults (sized for the
# 31 kg COMAN-like robot) both still pass the weight-shift trial, but barely (largest tilt 3.0 deg
# for G1, 2.6 deg for TALOS; under 1 deg with these). G1: at the default upper-body gains its
# light wrists chatter (the foot forces alternate by +-27 N every physics step), and the gain cap
# from its light feet leaves the ankle roll stiffness (194 N m/rad) below m g h (about 205 N m/rad)
# in single support on 5 cm wide feet. TALOS (90 kg) needs stiffer legs than the defaults.
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


# Phases of the weight-shift trial, (name, duration (s)): COM over the left foot, right foot up,
# held, down, COM back to the middle, standing still.
WEIGHT_SHIFT_PHASES = (('shift', 3.0), ('lift', 0.5), ('hold', 0.5), ('down', 0.5),
                       ('back', 1.5), ('settle', 0.5))


@dataclass(frozen=True)
class WeightShiftTrial:
    """What a weight-shift trial did (see weight_shift_trial).

    :param start: readings after standing, the reference of the trial.
    :param pelvis_shift: (2,) horizontal pelvis shift that puts the centre of mass over the left
        sole centre (m).
    :param lift_height: height the right foot was lifted to (m).
    :param phases: phase name of each control step.
    :param readings: readings after each control step.
    :param ik_clipped: control steps whose leg IK did not meet its targets.
    """

    start: SensorReadings
    pelvis_shift: np.ndarray
    lift_height: float
    phases: tuple
    readings: tuple
    ik_clipped: int

    def during(self, phase: str) -> list:
        """Return the readings of one phase."""
        return [r for p, r in zip(self.phases, self.readings) if p == phase]

    def max_tilt(self) -> float:
        """Return the largest tilt of the base from upright over the trial (rad)."""
        return max(tilt(r.base.orientation) for r in self.readings)


def tilt(quaternion) -> float:
    """Return the angle between a frame's z axis and the vertical (rad).

    :param quaternion: (4,) orientation (x, y, z, w).
    """
    x, y, z, w = quaternion
    return math.acos(min(1.0, max(-1.0, 1.0 - 2.0 * (x * x + y * y))))


def _smooth(u: float) -> float:
    return 0.5 - 0.5 * math.cos(math.pi * min(max(u, 0.0), 1.0))


def _com_over_left_sole(sim, leg_ik, start: SensorReadings) -> np.ndarray:
    """Return the pelvis shift putting the centre of mass over the left sole (Newton, 4 steps).

    The centre of mass is computed with Pinocchio for the leg angles of the IK, the other
    joints at their start angles, an upright pelvis and both soles where they stand.
    """
    model = pin.buildModelFromUrdf(sim.description.urdf_path, pin.JointModelFreeFlyer())
    data = model.createData()
    q_index = [model.joints[model.getJointId(n)].idx_q for n in sim.joint_names]
    q = pin.neutral(model)
    q[q_index] = start.joints.position
    pelvis, left, right = start.base.position, start.left_sole, start.right_sole
    upright = np.eye(3)

    def com(shift):
        solution = leg_ik.solve(pelvis + [shift[0], shift[1], 0.0], upright, left, upright,
                                right, upright)
        q[0:3] = pelvis + [shift[0], shift[1], 0.0]
        q[q_index[:12]] = solution.q
        return pin.centerOfMass(model, data, q)[:2].copy()

    shift, delta = np.zeros(2), 1e-4
    for _ in range(4):
        c = com(shift)
        jacobian = np.column_stack([(com(shift + e) - c) / delta for e in np.eye(2) * delta])
        shift = shift + np.linalg.solve(jacobian, left[:2] - c)
    return shift


def weight_shift_trial(sim, leg_ik, lift_height: float = 0.03, stand_time: float = 0.5,
                       phases=WEIGHT_SHIFT_PHASES) -> WeightShiftTrial:
    """Stand, shift the centre of mass over the left foot, lift the right foot and put it down.

    The proof that a controlled robot can step, in joint space only: the pelvis moves (upright)
    so the centre of mass comes over the left sole centre, the right sole rises straight up by
    lift_height and comes down again, then the pelvis moves back; the leg IK gives the joint
    setpoints of every control step, each phase follows a cosine profile.

    :param sim: a PyBulletBackend (or any backend with reset, step, description, joint_names).
    :param leg_ik: leg IK with solve(pelvis_position, pelvis_rotation, left_position,
        left_rotation, right_position, right_rotation) -> LegIkSolution (biped_mpc.leg_ik or
        biped_mpc.pinocchio_ik), set up for sim.description.
    :param lift_height: how high the right foot rises (m), > 0.
    :param stand_time: standing time before the trial (s), >= 0.
    :param phases: (name, duration (s)) of each phase; names among shift, lift, hold, down,
        back and settle.
    :return: the trial's readings.
    :raises ConfigError: for a bad lift height, stand time or phase.
    """
    if not (math.isfinite(lift_height) and lift_height > 0.0):
        raise ConfigError('lift_height = %r m must be finite and > 0' % (lift_height,))
    if not (math.isfinite(stand_time) and stand_time >= 0.0):
        raise ConfigError('stand_time = %r s must be finite and >= 0' % (stand_time,))
    names = {name for name, _ in WEIGHT_SHIFT_PHASES}
    for name, duration in phases:
        if name not in names or not (math.isfinite(duration) and duration > 0.0):
            raise ConfigError('phase (%r, %r) must name one of %s with a duration > 0 s'
                              % (name, duration, sorted(names)))
    period = sim.time_step * sim.config.control_substeps
    nominal = sim.description.nominal_leg_positions()
    start = sim.reset()
    for _ in range(int(round(stand_time / period))):
        start = sim.step(nominal)
    shift = _com_over_left_sole(sim, leg_ik, start)
    pelvis, left, right = start.base.position, start.left_sole, start.right_sole
    upright = np.eye(3)
    names, readings, clipped = [], [], 0
    for name, duration in phases:
        n = max(1, int(round(duration / period)))
        for k in range(n):
            u = _smooth((k + 1) / n)
            moved = {'shift': u, 'back': 1.0 - u, 'settle': 0.0}.get(name, 1.0)
            lifted = {'lift': u, 'hold': 1.0, 'down': 1.0 - u}.get(name, 0.0) * lift_height
            solution = leg_ik.solve(pelvis + [moved * shift[0], moved * shift[1], 0.0], upright,
                                    left, upright, right + [0.0, 0.0, lifted], upright)
            clipped += 0 if solution.reachable else 1
            names.append(name)
            readings.append(sim.step(solution.q))
    return WeightShiftTrial(start, shift, float(lift_height), tuple(names), tuple(readings),
                            clipped)
