"""Where a RobotDescription's joints, links and feet are in a loaded PyBullet body.

PyBullet numbers joints and links; the description names them. The index maps the names to the
numbers once, at load: the actuated joints (the 12 leg joints first, then the other revolute
joints in URDF order), the ankle F/T joints, sole and IMU links, the masses of the links and,
per foot, the links that hang below its F/T joint (or below the ankle roll joint without one).
It also sets the dynamics the backend relies on: no link damping, the feet's friction.
"""

from dataclasses import dataclass

import numpy as np

from biped_sim.errors import RobotModelError
from biped_sim.robot_description import RobotDescription

try:
    import pybullet
except ImportError as error:  # pragma: no cover - pybullet is a hard dependency of biped_sim
    raise ImportError('biped_sim.pybullet_robot_index needs pybullet (Python <= 3.11 wheels): '
                      'pip install pybullet==3.2.7') from error


@dataclass(frozen=True)
class RobotIndex:
    """PyBullet indices and masses of a loaded robot (link -1 is the base).

    :param joint_names: actuated joints, the 12 leg joints first.
    :param actuated: PyBullet joint index of each actuated joint, same order.
    :param effort_limit: (n,) effort limit of each actuated joint (N m).
    :param link_index: link name -> PyBullet link index (-1 for the base).
    :param ft_joints: (left, right) F/T joint indices, [] without F/T joints.
    :param soles: (left, right) sole link indices.
    :param imu: IMU link index.
    :param links: every link index but the base.
    :param link_mass: (n_links + 1,) masses, base first (kg).
    :param total_mass: mass of the robot (kg).
    :param base_inertial_position: (3,) base centre of mass in the base frame (m).
    :param base_inertial_orientation: (4,) base inertial axes in the base frame (x, y, z, w).
    :param base_inertial_is_identity: the base frame is its inertial frame.
    :param feet: (left, right) arrays of the link indices of each foot.
    :param foot_side: link index -> 0 (left foot) or 1 (right foot).
    :param foot_mass: (2,) mass of each foot below its sensor (kg).
    """

    joint_names: tuple
    actuated: list
    effort_limit: np.ndarray
    link_index: dict
    ft_joints: list
    soles: list
    imu: int
    links: list
    link_mass: np.ndarray
    total_mass: float
    base_inertial_position: np.ndarray
    base_inertial_orientation: tuple
    base_inertial_is_identity: bool
    feet: list
    foot_side: dict
    foot_mass: np.ndarray


def _is_descendant(link: int, ancestor: int, parents: list) -> bool:
    while link >= 0:
        if link == ancestor:
            return True
        link = parents[link]
    return False


def index_robot(client: int, robot: int, description: RobotDescription,
                foot_friction: float, sole_stiffness: float = 0.0,
                sole_damping: float = 0.0) -> RobotIndex:
    """Index a loaded robot, enable its F/T sensors and set its link dynamics.

    :param client: PyBullet physics client id.
    :param robot: PyBullet body id of the robot.
    :param description: the robot.
    :param foot_friction: lateral friction given to the links of the feet.
    :param sole_stiffness: normal stiffness of each contact point of the feet (N/m), 0: rigid
    :param sole_damping: normal damping of each contact point of the feet (N s/m)
    :return: the index.
    :raises RobotModelError: if the description names what the URDF does not have.
    """
    desc = description
    by_name, link_by_name, revolute, parents, effort = {}, {}, [], [], {}
    for j in range(pybullet.getNumJoints(robot, physicsClientId=client)):
        info = pybullet.getJointInfo(robot, j, physicsClientId=client)
        name = info[1].decode()
        by_name[name] = j
        link_by_name[info[12].decode()] = j
        parents.append(info[16])
        if info[2] in (pybullet.JOINT_REVOLUTE, pybullet.JOINT_PRISMATIC):
            revolute.append(j)
            effort[j] = info[10]
    base_name = pybullet.getBodyInfo(robot, physicsClientId=client)[0].decode()
    link_by_name[base_name] = -1
    if base_name != desc.base_link:
        raise RobotModelError('description base_link %r but the URDF root is %r'
                              % (desc.base_link, base_name))
    missing = [n for n in desc.leg_joint_names + desc.ft_joints if n not in by_name]
    missing += [n for n in desc.sole_frames + (desc.imu_link,) if n not in link_by_name]
    if missing:
        raise RobotModelError('not in %s: %r' % (desc.urdf_path, missing))
    leg = [by_name[n] for n in desc.leg_joint_names]
    actuated = leg + [j for j in revolute if j not in leg]
    names = {j: n for n, j in by_name.items()}
    ft_joints = [by_name[n] for n in desc.ft_joints]
    for j in ft_joints:
        pybullet.enableJointForceTorqueSensor(robot, j, True, physicsClientId=client)
    links = list(range(len(parents)))
    dynamics = [pybullet.getDynamicsInfo(robot, j, physicsClientId=client) for j in [-1] + links]
    link_mass = np.array([d[0] for d in dynamics])
    base_position, base_orientation = np.array(dynamics[0][3]), dynamics[0][4]
    # The foot is what hangs below the F/T sensor, or below the ankle roll joint without one.
    feet = [np.array([k for k in links if _is_descendant(k, j, parents)])
            for j in (ft_joints or [leg[5], leg[11]])]
    for k in [-1] + links:
        pybullet.changeDynamics(robot, k, linearDamping=0.0, angularDamping=0.0,
                                physicsClientId=client)
    for foot in feet:
        for k in foot:
            pybullet.changeDynamics(robot, int(k), lateralFriction=foot_friction,
                                    physicsClientId=client)
            if sole_stiffness > 0.0:
                # A rubber sole, not a rigid box: an edge under it presses into the pad instead
                # of the foot rocking on the edge line (docs/simulator_notes.md).
                pybullet.changeDynamics(robot, int(k), contactStiffness=sole_stiffness,
                                        contactDamping=sole_damping, physicsClientId=client)
    return RobotIndex(
        joint_names=tuple(names[j] for j in actuated), actuated=actuated,
        effort_limit=np.array([effort[j] for j in actuated]), link_index=link_by_name,
        ft_joints=ft_joints, soles=[link_by_name[n] for n in desc.sole_frames],
        imu=link_by_name[desc.imu_link], links=links, link_mass=link_mass,
        total_mass=float(link_mass.sum()), base_inertial_position=base_position,
        base_inertial_orientation=base_orientation,
        base_inertial_is_identity=bool(
            np.allclose(base_position, 0.0, atol=1e-12)
            and np.allclose(base_orientation, (0.0, 0.0, 0.0, 1.0), atol=1e-12)),
        feet=feet, foot_side={int(k): side for side, foot in enumerate(feet) for k in foot},
        foot_mass=np.array([link_mass[foot + 1].sum() for foot in feet]))
