"""F/T processing: inertia removal from first principles, low-pass closed form, hand-made CoPs."""
import math

import numpy as np
import pytest

from biped_mpc.balance.ft_filter import (
    compensate_foot_inertia, cop_of_feet, cop_of_wrench, FootWrenchFilter, FtFilterParams,
    GRAVITY, net_wrench)
from biped_mpc.errors import ConfigError, InputError
from biped_planner.rotations import rotation_x, rotation_y, rotation_z

MASS = 0.75


def sensor_reading(ground_force, contact_point, acceleration, sensor, com):
    """What the sensor reads (world frame) for a ground force at a point, from Newton-Euler.

    Force balance on the foot: m a = F_g + F_leg + m g. Moments about the centre of mass (no
    rotational inertia): (q - c) x F_g + tau_leg(s) + (s - c) x F_leg = 0. The sensor reads the
    opposite of the leg's wrench on the foot.
    """
    leg_force = MASS * (acceleration - GRAVITY) - ground_force
    leg_torque = -np.cross(contact_point - com, ground_force) - np.cross(sensor - com, leg_force)
    return -leg_force, -leg_torque


@pytest.mark.parametrize('seed', range(4))
def test_compensation_recovers_the_ground_wrench(seed):
    rng = np.random.default_rng(seed)
    sensor = rng.uniform(-0.2, 0.2, 3) + [0.0, 0.0, 0.06]
    com = sensor + rng.uniform(-0.03, 0.03, 3)
    sole = sensor - [0.0, 0.0, 0.04]
    point = sole + [rng.uniform(-0.1, 0.1), rng.uniform(-0.05, 0.05), 0.0]
    ground = rng.uniform([-30, -30, 50], [30, 30, 300])
    acceleration = rng.uniform(-20.0, 20.0, 3)
    f_s, tau_s = sensor_reading(ground, point, acceleration, sensor, com)
    force, torque = compensate_foot_inertia(f_s, tau_s, sensor, MASS, com, acceleration, sole)
    np.testing.assert_allclose(force, ground, atol=1e-12)
    np.testing.assert_allclose(torque, np.cross(point - sole, ground), atol=1e-12)


def test_foot_in_the_air_reads_38_newtons_and_compensates_to_zero():
    sensor, com = np.array([0.0, 0.1, 0.2]), np.array([0.0, 0.1, 0.1725])
    acceleration = np.array([0.0, 0.0, 41.0])
    f_s, tau_s = sensor_reading(np.zeros(3), com, acceleration, sensor, com)
    assert abs(np.linalg.norm(f_s) - 38.1) < 0.1
    force, torque = compensate_foot_inertia(f_s, tau_s, sensor, MASS, com, acceleration,
                                            sensor - [0, 0, 0.04])
    np.testing.assert_allclose(force, 0.0, atol=1e-12)
    np.testing.assert_allclose(torque, 0.0, atol=1e-12)
    # Standing still the sensor misses the foot's weight, m 9.81 N.
    f_s, _ = sensor_reading(np.array([0.0, 0.0, 150.0]), com, np.zeros(3), sensor, com)
    assert f_s[2] == pytest.approx(150.0 - MASS * 9.81)


@pytest.mark.parametrize('seed', range(4))
def test_the_cross_products_are_numpy_s_to_the_bit(seed):
    # the module computes its cross products by hand for speed: a deterministic trial must not
    # move by an ulp against np.cross
    rng = np.random.default_rng(seed)
    force, torque, sensor, com, acceleration, point = rng.normal(size=(6, 3))
    _, compensated = compensate_foot_inertia(force, torque, sensor, MASS, com, acceleration,
                                             point)
    inertial = MASS * (acceleration - GRAVITY)
    np.testing.assert_array_equal(compensated, torque + np.cross(sensor - point, force)
                                  + np.cross(com - point, inertial))
    forces, torques, points = rng.normal(size=(3, 2, 3))
    _, net = net_wrench(forces, torques, points, point)
    np.testing.assert_array_equal(net, (torques + np.cross(points - point, forces)).sum(axis=0))
    force[2] = abs(force[2]) + 1.0
    np.testing.assert_array_equal(cop_of_wrench(force, torque, point),
                                  point + np.cross([0.0, 0.0, 1.0], torque) / force[2])


def test_cop_of_one_foot_by_hand():
    sole = np.array([0.1, 0.2, 0.0])
    cop = cop_of_wrench([0.0, 0.0, 100.0], [5.0, -2.0, 0.3], sole)
    np.testing.assert_allclose(cop, [0.1 + 0.02, 0.2 + 0.05, 0.0])
    assert np.isnan(cop_of_wrench([0.0, 0.0, 0.5], [1.0, 0.0, 0.0], sole, min_force=1.0)).all()


def test_cop_of_both_feet_by_hand():
    # Left: 100 N with its CoP 2 cm ahead of its sole centre; right: 300 N with its CoP 1 cm
    # outwards (-y) of its centre. Torques about each sole centre: (cop_y f, -cop_x f, 0).
    points = np.array([[0.0, 0.1, 0.0], [0.0, -0.1, 0.0]])
    forces = np.array([[0.0, 0.0, 100.0], [0.0, 0.0, 300.0]])
    torques = np.array([[0.0, -2.0, 0.0], [-3.0, 0.0, 0.0]])
    cop = cop_of_feet(forces, torques, points, np.zeros(3))
    np.testing.assert_allclose(cop, [100 * 0.02 / 400, (100 * 0.1 + 300 * -0.11) / 400, 0.0])
    force, torque = net_wrench(forces, torques, points, np.zeros(3))
    np.testing.assert_allclose(force, [0.0, 0.0, 400.0])
    np.testing.assert_allclose(torque, [100 * 0.1 - 300 * 0.1 - 3.0, -2.0, 0.0])


def test_filter_step_response_follows_the_first_order_closed_form():
    params = FtFilterParams(cutoff_frequency=5.0, foot_mass=0.0)
    ft = FootWrenchFilter(params)
    eye = np.eye(3)
    first = ft.update(0.01, [0, 0, 100.0], [0, 0, 0], [0, 0, 0.04], eye, [0, 0, 0], eye)
    np.testing.assert_allclose(first.force, [0, 0, 100.0])
    decay = math.exp(-2.0 * math.pi * 5.0 * 0.01)
    for k in range(1, 30):
        result = ft.update(0.01, [0, 0, 300.0], [4.0, 0, 0], [0, 0, 0.04], eye, [0, 0, 0], eye)
        assert result.normal_force == pytest.approx(300.0 - 200.0 * decay ** k)
        assert result.local_torque[0] == pytest.approx(4.0 * (1.0 - decay ** k))
        np.testing.assert_allclose(result.raw_force, [0, 0, 300.0])
    # The CoP of every sample is y = 4 / 300 = 1.33 cm; after the first (y = 0) it filters to it.
    assert result.cop[1] == pytest.approx(4.0 / 300.0 * (1.0 - decay ** 29))


def test_filter_in_a_rotated_sole_frame_and_cop_gap():
    rotation = rotation_z(0.5) @ rotation_y(0.1) @ rotation_x(-0.05)
    ft = FootWrenchFilter(FtFilterParams(foot_mass=0.0, cop_min_force=20.0))
    local_force, local_torque = np.array([5.0, -3.0, 200.0]), np.array([2.0, -4.0, 0.1])
    sole = np.array([0.3, -0.1, 0.02])
    result = ft.update(0.02, local_force, local_torque, sole, rotation, sole, rotation)
    np.testing.assert_allclose(result.local_force, local_force, atol=1e-12)
    np.testing.assert_allclose(result.local_torque, local_torque, atol=1e-12)
    np.testing.assert_allclose(rotation.T @ (result.cop - sole), [0.02, 0.01, 0.0], atol=1e-12)
    gap = ft.update(0.02, [0, 0, 1.0], [0, 0, 0], sole, rotation, sole, rotation)
    assert np.isnan(gap.cop).all()


def test_reset_takes_the_next_sample_as_is():
    ft = FootWrenchFilter()
    eye = np.eye(3)
    ft.update(0.02, [0, 0, 100.0], [0, 0, 0], [0, 0, 0.04], eye, [0, 0, 0], eye)
    ft.reset()
    result = ft.update(0.02, [0, 0, 300.0], [0, 0, 0], [0, 0, 0.04], eye, [0, 0, 0], eye)
    assert result.normal_force == pytest.approx(300.0 + MASS * 9.81)


@pytest.mark.parametrize('change', [{'foot_mass': -1.0}, {'cutoff_frequency': 0.0},
                                    {'foot_com': (0.0, 0.0)}, {'cop_min_force': math.inf}])
def test_bad_parameters_are_refused(change):
    with pytest.raises(ConfigError):
        FtFilterParams(**change)


@pytest.mark.parametrize('index, value', [(0, 0.0), (1, [0, 0, math.nan]), (4, np.eye(2))])
def test_bad_inputs_are_refused(index, value):
    args = [0.02, [0, 0, 1.0], [0, 0, 0], [0, 0, 0], np.eye(3), [0, 0, 0], np.eye(3)]
    args[index] = value
    with pytest.raises(InputError):
        FootWrenchFilter().update(*args)
