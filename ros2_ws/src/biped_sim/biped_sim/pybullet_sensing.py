"""The sensors of a PyBullet humanoid: encoders, IMU, ankle F/T sensors, ground truth.

The ankle F/T joints report, in PyBullet, the force and torque the parent applies on the child
link, in the child's inertial frame, about the child's centre of mass; this module turns them
into sensor-frame readings and ground reactions (see :class:`biped_sim.sensors.FootForceTorque`):
the ground reaction is the opposite of the leg's wrench on the foot minus the foot's weight
(statics, the foot's acceleration neglected). A robot without ankle F/T joints
(RobotDescription.ft_joints == ()) is read from the contact points of its feet instead: the
ground reaction is their sum, and the foot's "sensor" is a virtual one at the sole frame with no
foot mass below it. The IMU's specific force is the mean acceleration over the last control
period (the velocity difference since the last mark) minus gravity, in the IMU frame.
"""

from typing import Optional

import numpy as np

from biped_planner.rotations import cross, quaternion_to_matrix

from biped_sim.pybullet_robot_index import RobotIndex
from biped_sim.sensors import (BaseState, FootForceTorque, ImuReading, JointReadings,
                               SensorReadings)

try:
    import pybullet
except ImportError as error:  # pragma: no cover - pybullet is a hard dependency of biped_sim
    raise ImportError('biped_sim.pybullet_sensing needs pybullet (Python <= 3.11 wheels): '
                      'pip install pybullet==3.2.7') from error


class PyBulletSensing:
    """Reads the sensors of a robot loaded in PyBullet (see the module docstring).

    :param client: PyBullet physics client id.
    :param robot: PyBullet body id of the robot.
    :param index: the robot's indices and masses.
    :param gravity: gravity acceleration (m/s^2).
    :param contact_threshold: normal ground force above which a foot is in contact (N).
    """

    def __init__(self, client: int, robot: int, index: RobotIndex, gravity: float,
                 contact_threshold: float) -> None:
        self._client = client
        self._robot = robot
        self._index = index
        self._gravity_vector = np.array([0.0, 0.0, -gravity])
        self._contact_threshold = contact_threshold
        self._imu_mark = (np.zeros(3), 0)

    def base_frame_pose(self) -> tuple:
        """Return the base link frame (position (3,), quaternion (4,)) from its inertial pose."""
        index, client = self._index, self._client
        com_position, com_orientation = pybullet.getBasePositionAndOrientation(
            self._robot, physicsClientId=client)
        if index.base_inertial_is_identity:
            return np.array(com_position), np.array(com_orientation)
        inv_position, inv_orientation = pybullet.invertTransform(
            index.base_inertial_position.tolist(), index.base_inertial_orientation,
            physicsClientId=client)
        position, orientation = pybullet.multiplyTransforms(
            com_position, com_orientation, inv_position, inv_orientation,
            physicsClientId=client)
        return np.array(position), np.array(orientation)

    def imu_frame_state(self) -> tuple:
        """Return the IMU frame (position, quaternion, linear velocity, angular velocity)."""
        state = pybullet.getLinkState(self._robot, self._index.imu, computeLinkVelocity=1,
                                      computeForwardKinematics=1, physicsClientId=self._client)
        com, frame = np.array(state[0]), np.array(state[4])
        angular = np.array(state[7])
        linear = np.array(state[6]) + cross(angular, frame - com)
        return frame, np.array(state[5]), linear, angular

    def mark_imu_velocity(self, step_count: int) -> None:
        """Start the interval over which the IMU averages its acceleration (a control period).

        :param step_count: physics steps since the reset.
        """
        self._imu_mark = (self.imu_frame_state()[2], step_count)

    def read(self, time: float, step_count: int, time_step: float,
             torque: Optional[np.ndarray] = None) -> SensorReadings:
        """Return the readings of the current state.

        :param time: simulated time (s).
        :param step_count: physics steps since the reset.
        :param time_step: physics step (s).
        :param torque: (n,) torques applied by the backend (torque mode); None reads the motors.
        """
        client, robot, index = self._client, self._robot, self._index
        states = pybullet.getJointStates(robot, index.actuated, physicsClientId=client)
        position = np.array([s[0] for s in states])
        velocity = np.array([s[1] for s in states])
        torque = np.array([s[3] for s in states]) if torque is None else torque.copy()
        joints = JointReadings(index.joint_names, position, velocity, torque)

        links = pybullet.getLinkStates(robot, index.links, computeLinkVelocity=1,
                                       computeForwardKinematics=1, physicsClientId=client)
        com_positions = np.array([s[0] for s in links])
        com_velocities = np.array([s[6] for s in links])
        base_com, _ = pybullet.getBasePositionAndOrientation(robot, physicsClientId=client)
        base_linear, base_angular = pybullet.getBaseVelocity(robot, physicsClientId=client)
        base_com, base_linear = np.array(base_com), np.array(base_linear)
        base_angular = np.array(base_angular)
        masses = index.link_mass
        com = (masses[0] * base_com + masses[1:] @ com_positions) / index.total_mass
        com_velocity = (masses[0] * base_linear + masses[1:] @ com_velocities) / index.total_mass

        frame_position, frame_orientation = self.base_frame_pose()
        frame_velocity = base_linear + cross(base_angular, frame_position - base_com)
        base = BaseState(frame_position, frame_orientation, frame_velocity, base_angular)

        _, imu_orientation, imu_velocity, imu_angular = self.imu_frame_state()
        imu_rotation = quaternion_to_matrix(imu_orientation)
        mark_velocity, mark_step = self._imu_mark
        elapsed = (step_count - mark_step) * time_step
        acceleration = ((imu_velocity - mark_velocity) / elapsed if elapsed > 0.0
                        else np.zeros(3))
        imu = ImuReading(imu_orientation, imu_rotation.T @ imu_angular,
                         imu_rotation.T @ (acceleration - self._gravity_vector))

        if index.ft_joints:
            ft_states = pybullet.getJointStates(robot, index.ft_joints, physicsClientId=client)
            feet = [self._foot_reading(i, ft_states[i][2], links) for i in (0, 1)]
        else:
            feet = self._contact_foot_readings(links)
        normal = np.array([f.ground_force[2] if f.in_contact else 0.0 for f in feet])
        if normal.sum() > 0.0:
            zmp = (normal[0] * np.nan_to_num(feet[0].cop[:2])
                   + normal[1] * np.nan_to_num(feet[1].cop[:2])) / normal.sum()
        else:
            zmp = np.full(2, np.nan)
        soles = [np.array(links[k][4]) for k in index.soles]
        return SensorReadings(time, joints, imu, feet[0], feet[1], zmp, base, soles[0],
                              soles[1], com, com_velocity)

    def _foot_reading(self, side: int, raw_wrench, links) -> FootForceTorque:
        """Turn PyBullet's F/T joint reaction into sensor readings and the ground reaction."""
        index = self._index
        child = index.ft_joints[side]
        child_com = np.array(links[child][0])
        child_inertial_rotation = quaternion_to_matrix(links[child][1])
        sensor_origin = np.array(links[child][4])
        sensor_rotation = quaternion_to_matrix(links[child][5])
        # Wrench of the leg on the foot, world axes, about the foot's centre of mass.
        force_on_foot = child_inertial_rotation @ np.asarray(raw_wrench[:3])
        torque_on_foot = child_inertial_rotation @ np.asarray(raw_wrench[3:])
        torque_at_sensor = torque_on_foot + cross(child_com - sensor_origin, force_on_foot)
        sensor_force = sensor_rotation.T @ -force_on_foot
        sensor_torque = sensor_rotation.T @ -torque_at_sensor

        sole = index.soles[side]
        sole_position = np.array(links[sole][4])
        sole_rotation = quaternion_to_matrix(links[sole][5])
        foot = index.feet[side]
        weights = index.link_mass[foot + 1][:, None] * self._gravity_vector
        centres = np.array([links[k][0] for k in foot])
        ground_force = -force_on_foot - weights.sum(axis=0)
        ground_torque = (-(torque_on_foot + cross(child_com - sole_position, force_on_foot))
                         - cross(centres - sole_position, weights).sum(axis=0))
        return self._ground_reading(sensor_force, sensor_torque, ground_force, ground_torque,
                                    sole_position, sole_rotation)

    def _ground_reading(self, sensor_force, sensor_torque, ground_force, ground_torque,
                        sole_position, sole_rotation) -> FootForceTorque:
        """Complete a foot reading with its contact flag and centre of pressure."""
        local_force = sole_rotation.T @ ground_force
        local_torque = sole_rotation.T @ ground_torque
        in_contact = bool(local_force[2] > self._contact_threshold)
        if in_contact:
            local_cop = np.array([-local_torque[1] / local_force[2],
                                  local_torque[0] / local_force[2], 0.0])
            cop = sole_position + sole_rotation @ local_cop
        else:
            cop = np.full(3, np.nan)
        return FootForceTorque(sensor_force, sensor_torque, ground_force, ground_torque, cop,
                               in_contact)

    def _foot_contacts(self) -> list:
        """Return per foot the contact points (n, 3) and the forces on the foot (n, 3), world.

        getContactPoints with bodyA = the robot reports the normal on the other body pointing to
        the robot, but not its friction on the robot: against the static ground, terrain and
        obstacles the reported friction is the one on the other body (PyBullet keeps its internal
        pair order), so the robot feels its opposite (a test pushes a robot to check the sign).
        """
        points, forces = ([], []), ([], [])
        for contact in pybullet.getContactPoints(bodyA=self._robot,
                                                 physicsClientId=self._client):
            side = self._index.foot_side.get(contact[3])
            if side is None or contact[2] == self._robot:
                continue
            points[side].append(contact[5])
            forces[side].append(contact[9] * np.asarray(contact[7])
                                - contact[10] * np.asarray(contact[11])
                                - contact[12] * np.asarray(contact[13]))
        return [(np.array(p, dtype=float).reshape(-1, 3), np.array(f, dtype=float).reshape(-1, 3))
                for p, f in zip(points, forces)]

    def contact_normal_forces(self) -> list:
        """Return the vertical ground force on each foot from its contact points (N)."""
        normal = [0.0, 0.0]
        for contact in pybullet.getContactPoints(bodyA=self._robot,
                                                 physicsClientId=self._client):
            side = self._index.foot_side.get(contact[3])
            if side is not None and contact[2] != self._robot:
                normal[side] += contact[9] * contact[7][2]
        return normal

    def _contact_foot_readings(self, links) -> list:
        """Foot readings of a robot without F/T joints: a virtual sensor at each sole frame."""
        feet = []
        for side, (points, forces) in enumerate(self._foot_contacts()):
            sole = self._index.soles[side]
            sole_position = np.array(links[sole][4])
            sole_rotation = quaternion_to_matrix(links[sole][5])
            ground_force = forces.sum(axis=0)
            ground_torque = cross(points - sole_position, forces).sum(axis=0)
            feet.append(self._ground_reading(
                sole_rotation.T @ ground_force, sole_rotation.T @ ground_torque, ground_force,
                ground_torque, sole_position, sole_rotation))
        return feet
