"""Ankle force/torque processing: the foot's own inertia removed, low-pass, centres of pressure."""
from dataclasses import dataclass
import math
from typing import Optional, Tuple

import numpy as np

from biped_mpc.errors import ConfigError
from biped_mpc.validation import check_period, finite_array
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.rotations import cross

GRAVITY = np.array([0.0, 0.0, -9.81])


def compensate_foot_inertia(sensor_force, sensor_torque, sensor_position, foot_mass: float,
                            foot_com, foot_acceleration, point,
                            gravity=GRAVITY) -> Tuple[np.ndarray, np.ndarray]:
    """Ground reaction wrench on a foot from its ankle sensor, the foot's inertia removed.

    Newton on the foot below the sensor (mass m, centre of mass c, acceleration a), with f_s,
    tau_s the wrench the foot exerts on the leg at the sensor origin s (the sensor reading, so
    the leg exerts -f_s on the foot) and g the gravity vector (0, 0, -9.81):

        m a = F_g - f_s + m g          =>   F_g = f_s + m (a - g)

    and, neglecting the foot's rotational inertia, the moments about a point p:

        tau_g(p) = tau_s + (s - p) x f_s + (c - p) x m (a - g).

    Standing still, F_g = f_s + m 9.81 z: the sensor misses the foot's weight. In the air
    (F_g = 0) the sensor reads f_s = -m (a - g): |f_s| = 38 N for 0.75 kg accelerated at 41 m/s^2
    upwards, which a raw reading would take for a contact.

    :param sensor_force: (3,) f_s in the world frame (N)
    :param sensor_torque: (3,) tau_s about the sensor origin, world frame (N m)
    :param sensor_position: (3,) sensor origin s (m)
    :param foot_mass: m, mass below the sensor (kg)
    :param foot_com: (3,) c (m)
    :param foot_acceleration: (3,) a of the foot's centre of mass (m/s^2)
    :param point: (3,) p, where the torque is expressed (m)
    :param gravity: (3,) g (m/s^2)
    :return: F_g (3,) (N) and tau_g(p) (3,) (N m), world frame
    """
    inertial = foot_mass * (np.asarray(foot_acceleration, dtype=float) - gravity)
    point = np.asarray(point, dtype=float)
    force = np.asarray(sensor_force, dtype=float) + inertial
    torque = (np.asarray(sensor_torque, dtype=float)
              + cross(np.asarray(sensor_position, dtype=float) - point,
                       np.asarray(sensor_force, dtype=float))
              + cross(np.asarray(foot_com, dtype=float) - point, inertial))
    return force, torque


def cop_of_wrench(force, torque, point, normal=(0.0, 0.0, 1.0),
                  min_force: float = 1e-6) -> np.ndarray:
    """Centre of pressure of a wrench on the plane through point with the given normal.

    p_cop = p + n x tau(p) / (n . f): the point of the plane about which the moment has no
    component in the plane (for n = z: x = p_x - tau_y / f_z, y = p_y + tau_x / f_z).

    :param force: (3,) force (N)
    :param torque: (3,) torque about point (N m)
    :param point: (3,) a point of the plane (m)
    :param normal: (3,) unit normal of the plane
    :param min_force: smallest normal force with a defined CoP (N)
    :return: (3,) the CoP (m); NaN when n . f < min_force
    """
    normal = np.asarray(normal, dtype=float)
    pressure = float(normal @ np.asarray(force, dtype=float))
    if pressure < min_force:
        return np.full(3, np.nan)
    return np.asarray(point, dtype=float) + cross(normal, np.asarray(torque, dtype=float)) / \
        pressure


def net_wrench(forces, torques, points, point) -> Tuple[np.ndarray, np.ndarray]:
    """Sum of wrenches, each given about its own point, expressed about one point.

    :param forces: (k, 3) forces (N)
    :param torques: (k, 3) torques, row i about points[i] (N m)
    :param points: (k, 3) the points (m)
    :param point: (3,) where the net torque is expressed (m)
    :return: net force (3,) (N) and net torque about point (3,) (N m)
    """
    forces = np.asarray(forces, dtype=float).reshape(-1, 3)
    arms = np.asarray(points, dtype=float).reshape(-1, 3) - np.asarray(point, dtype=float)
    torque = np.asarray(torques, dtype=float).reshape(-1, 3) + cross(arms, forces)
    return forces.sum(axis=0), torque.sum(axis=0)


def cop_of_feet(forces, torques, points, point, normal=(0.0, 0.0, 1.0),
                min_force: float = 1e-6) -> np.ndarray:
    """Centre of pressure of several feet (the measured ZMP) on a plane through point.

    :param forces: (k, 3) ground reaction forces of the feet (N)
    :param torques: (k, 3) their torques about points (N m)
    :param points: (k, 3) the feet's reference points, e.g. sole centres (m)
    :param point: (3,) a point of the plane (m)
    :param normal: (3,) unit normal of the plane
    :param min_force: smallest total normal force with a defined CoP (N)
    :return: (3,) the CoP (m), NaN below min_force
    """
    force, torque = net_wrench(forces, torques, points, point)
    return cop_of_wrench(force, torque, point, normal, min_force)


@dataclass(frozen=True)
class FtFilterParams:
    """Foot below the ankle sensor and filter settings (see FootWrenchFilter)."""

    foot_mass: float = parameter(0.75, 'mass of the foot below the F/T sensor (kg)', low=0.0,
                                 high=20.0)
    foot_com: tuple = parameter((0.0, 0.0, -0.0275),
                                'foot centre of mass in the sensor frame (m)', low=-1.0,
                                high=1.0)
    cutoff_frequency: float = parameter(15.0, 'low-pass cut-off of wrench and CoP (Hz)',
                                        low=0.0, high=1000.0, low_open=True)
    cop_min_force: float = parameter(10.0, 'normal force below which a foot has no CoP (N)',
                                     low=0.0, high=1000.0, low_open=True)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        if len(self.foot_com) != 3:
            raise ConfigError(f'FtFilterParams.foot_com must have 3 elements, got '
                              f'{self.foot_com!r}')


@dataclass(frozen=True)
class FootWrench:
    """One foot's ground reaction after compensation and filtering.

    :param force: (3,) filtered ground reaction force, world frame (N)
    :param torque: (3,) filtered torque about the sole centre, world frame (N m)
    :param local_force: (3,) force in the sole frame (N)
    :param local_torque: (3,) torque about the sole centre in the sole frame (N m): x is the
        roll torque, y the pitch torque
    :param normal_force: local_force[2] (N)
    :param cop: (3,) filtered centre of pressure on the sole plane, world (m); NaN when the
        normal force is below cop_min_force
    :param raw_force: (3,) compensated, unfiltered force, world (N)
    :param raw_torque: (3,) compensated, unfiltered torque about the sole centre, world (N m)
    """

    force: np.ndarray
    torque: np.ndarray
    local_force: np.ndarray
    local_torque: np.ndarray
    normal_force: float
    cop: np.ndarray
    raw_force: np.ndarray
    raw_torque: np.ndarray


class FootWrenchFilter:
    """One foot: sensor wrench -> ground reaction about the sole centre, low-passed, and CoP.

    Each update removes the foot's gravity and inertia (compensate_foot_inertia), expresses the
    wrench about the sole centre, and low-passes it with the exact first-order discretisation
    y_k = y_k-1 + (1 - exp(-2 pi f_c dt)) (u_k - y_k-1) (first sample taken as is). The CoP of
    the compensated sample is low-passed the same way while the normal force stays above
    cop_min_force, restarted from the sample after a gap, and NaN during one.
    """

    def __init__(self, params: FtFilterParams = FtFilterParams()) -> None:
        """Create the filter, empty.

        :param params: foot data and filter settings
        """
        self.params = params
        self.reset()

    def reset(self) -> None:
        """Forget the filter states: the next sample is taken as is."""
        self._wrench: Optional[np.ndarray] = None
        self._cop: Optional[np.ndarray] = None

    def update(self, dt: float, sensor_force, sensor_torque, sensor_position, sensor_rotation,
               sole_position, sole_rotation, foot_acceleration=(0.0, 0.0, 0.0)) -> FootWrench:
        """Process one sample.

        :param dt: time since the previous sample (s), > 0
        :param sensor_force: (3,) force the foot exerts on the leg, sensor frame (N)
        :param sensor_torque: (3,) its torque about the sensor origin, sensor frame (N m)
        :param sensor_position: (3,) sensor origin in the world (m)
        :param sensor_rotation: (3, 3) sensor frame in the world
        :param sole_position: (3,) sole centre in the world (m)
        :param sole_rotation: (3, 3) sole frame in the world
        :param foot_acceleration: (3,) acceleration of the foot, world (m/s^2); zero neglects
            the inertial force (the gravity part is still removed)
        :return: the filtered ground reaction
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        check_period(dt)
        rotation = finite_array('sensor_rotation', sensor_rotation, (3, 3))
        sole_rotation = finite_array('sole_rotation', sole_rotation, (3, 3))
        sensor_position = finite_array('sensor_position', sensor_position, (3,))
        sole_position = finite_array('sole_position', sole_position, (3,))
        p = self.params
        force, torque = compensate_foot_inertia(
            rotation @ finite_array('sensor_force', sensor_force, (3,)),
            rotation @ finite_array('sensor_torque', sensor_torque, (3,)), sensor_position,
            p.foot_mass, sensor_position + rotation @ np.asarray(p.foot_com, dtype=float),
            finite_array('foot_acceleration', foot_acceleration, (3,)), sole_position)
        gain = 1.0 - math.exp(-2.0 * math.pi * p.cutoff_frequency * dt)
        sample = np.concatenate([force, torque])
        self._wrench = sample if self._wrench is None else (
            self._wrench + gain * (sample - self._wrench))
        raw_cop = cop_of_wrench(force, torque, sole_position, sole_rotation[:, 2],
                                p.cop_min_force)
        if np.isnan(raw_cop[0]):
            self._cop = None
        else:
            self._cop = raw_cop if self._cop is None else self._cop + gain * (raw_cop - self._cop)
        filtered_force, filtered_torque = self._wrench[:3].copy(), self._wrench[3:].copy()
        local_force = sole_rotation.T @ filtered_force
        return FootWrench(filtered_force, filtered_torque, local_force,
                          sole_rotation.T @ filtered_torque, float(local_force[2]),
                          np.full(3, np.nan) if self._cop is None else self._cop.copy(),
                          force, torque)
