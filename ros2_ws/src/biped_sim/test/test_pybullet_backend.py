"""Tests of the PyBullet backend: sensors, torque-controlled standing and stepping, pushes,
terrain, obstacles, camera and bad inputs (all headless)."""

import dataclasses
import math

import numpy as np
import pybullet
import pytest

from biped_sim.backend import SimulatorBackend
from biped_sim.camera_view import CameraView
from biped_sim.errors import ConfigError, RobotModelError
from biped_sim.external_push import ExternalPush
from biped_sim.joint_servo import step_toward
from biped_sim.obstacles import BoxObstacle, DiscObstacle
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.pybullet_scenery import MAX_SHAPES_PER_BODY
from biped_sim.robot_description import coman_like
from biped_sim.terrain import generate_terrain, TerrainParams

G = 9.81
MODES = ('torque', 'position')


@pytest.fixture(scope='module')
def description():
    return coman_like()


@pytest.fixture(scope='module')
def backends(description):
    sims = {mode: PyBulletBackend(description, PyBulletConfig(control_mode=mode))
            for mode in MODES}
    yield sims
    for sim in sims.values():
        sim.close()


@pytest.fixture
def sim(backends):
    backends['torque'].reset()
    return backends['torque']


def _tilt_deg(orientation) -> float:
    rotation = np.array(pybullet.getMatrixFromQuaternion(orientation)).reshape(3, 3)
    return math.degrees(math.acos(min(1.0, rotation[2, 2])))


def _stand(sim, seconds):
    q = sim.description.nominal_leg_positions()
    readings = None
    for _ in range(int(round(seconds / 0.02))):
        readings = sim.step(q)
    return readings


def _flat_foot_leg(geometry, hip, ankle):
    """Angles of one leg with an upright pelvis and a flat, unrotated foot (closed form)."""
    a, b = geometry.thigh_length, geometry.shank_length
    r = hip - ankle
    knee = math.acos((r @ r - a * a - b * b) / (2 * a * b))
    ankle_roll = math.atan2(r[1], r[2])
    ankle_pitch = (math.atan2(-a * math.sin(knee), a * math.cos(knee) + b)
                   - math.atan2(r[0], math.hypot(r[1], r[2])))
    return [0.0, -ankle_roll, -(knee + ankle_pitch), knee, ankle_pitch, ankle_roll]


def _leg_angles(description, pelvis, left_sole, right_sole):
    g = description.leg_geometry
    angles = []
    for sign, sole in ((1.0, left_sole), (-1.0, right_sole)):
        hip = pelvis + np.array(g.hip_offset) * [1.0, sign, 1.0]
        ankle = sole - np.array(g.ankle_to_sole) * [1.0, sign, 1.0]
        angles += _flat_foot_leg(g, hip, ankle)
    return np.array(angles)


def _inside_sole(point, sole, description, margin=1e-3):
    return (abs(point[0] - sole[0]) <= description.sole_length / 2 + margin
            and abs(point[1] - sole[1]) <= description.sole_width / 2 + margin)


def test_is_a_simulator_backend(sim, description):
    assert isinstance(sim, SimulatorBackend)
    assert len(sim.joint_names) == 23
    assert sim.joint_names[:12] == description.leg_joint_names
    assert sim.total_mass == pytest.approx(30.95)
    assert sim.time_step == 0.001


def test_flat_foot_helper_reproduces_the_nominal_pose(sim, description):
    readings = sim.sensors()
    q = _leg_angles(description, readings.base.position, readings.left_sole,
                    readings.right_sole)
    assert np.allclose(q, description.nominal_leg_positions(), atol=1e-6)


def test_time_advances_by_physics_steps(sim):
    q = sim.description.nominal_leg_positions()
    assert sim.step(q, 7).time == pytest.approx(0.007)
    assert sim.step(q).time == pytest.approx(0.027)
    assert sim.reset().time == 0.0


@pytest.mark.parametrize('mode', MODES)
def test_standing_sensors_are_consistent(backends, description, mode):
    sim = backends[mode]
    sim.reset()
    readings = _stand(sim, 1.0)
    weight = sim.total_mass * G
    left, right = readings.left_foot, readings.right_foot
    assert left.in_contact and right.in_contact
    assert left.ground_force[2] + right.ground_force[2] == pytest.approx(weight, rel=0.03)
    feet_weight = 2 * (0.7 + 0.05) * G  # below the F/T sensors
    assert left.sensor_force[2] + right.sensor_force[2] == pytest.approx(weight - feet_weight,
                                                                         rel=0.03)
    assert _inside_sole(left.cop, readings.left_sole, description)
    assert _inside_sole(right.cop, readings.right_sole, description)
    # Standing still, the ZMP is the ground projection of the centre of mass.
    assert np.allclose(readings.zmp, readings.com_position[:2], atol=0.01)
    imu = readings.imu
    assert np.allclose(imu.linear_acceleration, [0.0, 0.0, G], atol=0.05)
    assert np.allclose(imu.angular_velocity, 0.0, atol=0.01)
    assert _tilt_deg(imu.orientation) < 0.5
    assert np.allclose(imu.orientation, readings.base.orientation, atol=1e-9)


@pytest.mark.parametrize('mode', MODES)
def test_stands_five_seconds(backends, mode):
    sim = backends[mode]
    start = sim.reset()
    tilts, heights = [], []
    q = sim.description.nominal_leg_positions()
    for _ in range(250):
        readings = sim.step(q)
        tilts.append(_tilt_deg(readings.base.orientation))
        heights.append(readings.base.position[2])
    assert max(tilts) < 2.0
    assert np.max(np.abs(np.array(heights) - start.base.position[2])) < 0.005
    assert np.linalg.norm(readings.base.position[:2] - start.base.position[:2]) < 0.01


def _sole_contacts(sim):
    """(penetration depth (m), normal force (N)) of every contact point of the robot's feet."""
    return np.array([(-c[8], c[9]) for c in pybullet.getContactPoints(
        bodyA=sim._robot, physicsClientId=sim._client) if c[3] in sim._index.foot_side])


@pytest.mark.parametrize('stiffness', [3e4, 1e5])
def test_a_rubber_sole_sinks_as_its_springs_say(description, stiffness):
    """Each sole contact point is a spring: depth = normal force / stiffness, and the points
    carry the robot's weight; a rigid sole (stiffness 0) does not sink."""
    for k in (stiffness, 0.0):
        sim = PyBulletBackend(description, PyBulletConfig(leg_kp=2000.0,
                                                          sole_contact_stiffness=k))
        try:
            sim.reset()
            q = sim.description.nominal_leg_positions()
            for _ in range(100):
                sim.step(q)
            contacts = _sole_contacts(sim)
        finally:
            sim.close()
        depth, force = contacts[:, 0], contacts[:, 1]
        assert force.sum() == pytest.approx(sim._index.total_mass * G, rel=0.05)
        if k > 0.0:
            loaded = force > 5.0
            assert np.allclose(depth[loaded], force[loaded] / k, rtol=0.1, atol=2e-5)
            assert depth.max() > 0.5 * force.sum() / (len(force) * k)
        else:
            assert depth.max() < 2e-4


@pytest.mark.parametrize('mode', MODES)
def test_weight_shift_lift_foot_and_put_it_down(backends, description, mode):
    """The proof that the controlled robot can step: COM over the left foot, right foot up
    3 cm and down again, COM back to the middle."""
    sim = backends[mode]
    sim.reset()
    start = _stand(sim, 0.5)
    pelvis0, left, right = start.base.position, start.left_sole, start.right_sole
    shift = left[1] - pelvis0[1]

    def smooth(u):
        return 0.5 - 0.5 * math.cos(math.pi * min(max(u, 0.0), 1.0))

    phases = [('shift', 1.5), ('lift', 0.5), ('hold', 0.5), ('down', 0.5), ('back', 1.5)]
    lifted_readings, tilts, heights = [], [], []
    for name, duration in phases:
        n = int(round(duration / 0.02))
        for k in range(n):
            u = smooth((k + 1) / n)
            y = {'shift': u, 'back': 1.0 - u}.get(name, 1.0) * shift
            lift = {'lift': u, 'hold': 1.0, 'down': 1.0 - u}.get(name, 0.0) * 0.03
            q = _leg_angles(description, pelvis0 + [0.0, y, 0.0], left, right + [0, 0, lift])
            readings = sim.step(q)
            tilts.append(_tilt_deg(readings.base.orientation))
            heights.append(readings.base.position[2])
            if name == 'hold':
                lifted_readings.append(readings)
    assert max(tilts) < 3.0
    assert min(heights) > pelvis0[2] - 0.01
    for readings in lifted_readings:
        assert readings.right_sole[2] > 0.027
        assert readings.left_foot.in_contact and not readings.right_foot.in_contact
        assert _inside_sole(readings.zmp, readings.left_sole, description)
        assert readings.left_foot.ground_force[2] == pytest.approx(sim.total_mass * G,
                                                                   rel=0.03)
    final = _stand(sim, 0.3)
    assert final.left_foot.in_contact and final.right_foot.in_contact
    assert np.linalg.norm(final.right_sole - right) < 0.01


@pytest.mark.parametrize('direction', [(1.0, 0.0, 0.0), (0.0, -1.0, 0.0)])
def test_push_moves_the_base_in_its_direction(sim, direction):
    direction = np.array(direction)
    start = _stand(sim, 0.3).base.position
    sim.push(ExternalPush(tuple(80.0 * direction), duration=0.1))
    moves = np.array([_stand(sim, 0.02).base.position - start for _ in range(15)])
    along = moves @ direction
    across = moves @ np.cross(direction, [0.0, 0.0, 1.0])
    assert along.max() > 0.004
    assert np.abs(across).max() < 0.2 * along.max()


def test_scheduled_push_waits_for_its_start(sim):
    start = _stand(sim, 0.1)
    sim.push(ExternalPush((100.0, 0.0, 0.0), 0.1, point=(0.0, 0.0, 0.05), start_time=0.5))
    before = _stand(sim, 0.3)
    assert abs(before.base.position[0] - start.base.position[0]) < 1e-3
    after = _stand(sim, 0.4)
    assert after.base.position[0] - start.base.position[0] > 0.005


def test_the_imu_averages_over_a_whole_period_run_in_parts(sim):
    # In free fall, a push in the first quarter of a period run in four parts: the IMU reads the
    # period's mean acceleration, the centre of mass's velocity change over 20 ms, not the last
    # part's (zero, in free fall). The IMU sits above the centre of mass and the push also turns
    # the body: 0.91 against 0.81 m/s^2.
    before = sim.reset(base_position=np.array([0.0, 0.0, 1.5]))
    sim.push(ExternalPush((100.0, 0.0, 0.0), 0.005))
    q = sim.description.nominal_leg_positions()
    after = step_toward(sim, q, q, substeps=20, parts=4)
    mean_acceleration = (after.com_velocity[0] - before.com_velocity[0]) / 0.02
    assert mean_acceleration > 0.5
    assert after.imu.linear_acceleration[0] == pytest.approx(mean_acceleration, abs=0.2)


def test_imu_reads_zero_specific_force_in_free_fall(sim):
    readings = sim.reset(base_position=np.array([0.0, 0.0, 1.5]))
    assert np.allclose(readings.imu.linear_acceleration, [0.0, 0.0, G], atol=1e-9)
    readings = sim.step(sim.description.nominal_leg_positions(), 50)
    assert np.allclose(readings.imu.linear_acceleration, 0.0, atol=0.1)
    assert not readings.left_foot.in_contact and not readings.right_foot.in_contact
    assert np.all(np.isnan(readings.zmp))
    # Free fall from rest: z = z0 - g t^2 / 2 for the centre of mass.
    assert readings.com_velocity[2] == pytest.approx(-G * 0.05, rel=0.01)


def test_upper_body_tracks_its_setpoints(sim):
    q = np.array([sim.description.nominal_joint_positions.get(n, 0.0) for n in sim.joint_names])
    elbow = sim.joint_names.index('l_elbow_joint')
    waist = sim.joint_names.index('waist_yaw_joint')
    q[elbow], q[waist] = -1.0, 0.2
    for _ in range(50):
        readings = sim.step(q)
    assert readings.joints.position[elbow] == pytest.approx(-1.0, abs=0.03)
    assert readings.joints.position[waist] == pytest.approx(0.2, abs=0.03)
    assert np.all(np.abs(readings.joints.torque) <= 150.0)


def test_terrain_is_built_as_generated(description):
    terrain = generate_terrain(TerrainParams(tile_area=0.04, side_length=1.0,
                                             origin=(-0.5, -0.5), seed=5))
    with PyBulletBackend(description) as sim:
        ids = sim.add_terrain(terrain)
        assert 1 <= len(ids) <= 8
        centres = terrain.tile_centres()
        starts = np.column_stack([centres, np.ones(len(centres))])
        ends = np.column_stack([centres, -np.ones(len(centres))])
        hits = pybullet.rayTestBatch(starts.tolist(), ends.tolist(),
                                     physicsClientId=sim.client_id)
        heights = np.array([hit[3][2] for hit in hits])
        robot_hits = sum(hit[0] == sim.robot_id for hit in hits)
        assert robot_hits > 0  # the robot stands on the terrain; compare the other tiles
        free = np.array([hit[0] != sim.robot_id for hit in hits])
        assert np.allclose(heights[free], terrain.heights.ravel()[free], atol=1e-6)
        readings = sim.reset()
        ground = [terrain.height_at(s[0], s[1]) for s in (readings.left_sole,
                                                          readings.right_sole)]
        assert min(readings.left_sole[2], readings.right_sole[2]) >= min(ground) - 1e-9
        assert max(readings.left_sole[2], readings.right_sole[2]) <= max(ground) + 0.05
        sim.clear_scenery()
        hit = pybullet.rayTest([0.4, 0.4, 1.0], [0.4, 0.4, -1.0],
                               physicsClientId=sim.client_id)[0]
        assert hit[3][2] == pytest.approx(0.0, abs=1e-6)


def test_obstacles_appear_as_bodies(description):
    with PyBulletBackend(description) as sim:
        before = pybullet.getNumBodies(physicsClientId=sim.client_id)
        ids = sim.add_obstacles([BoxObstacle(1.0, 0.5, 0.4, 0.2, 0.0, 0.3),
                                 DiscObstacle(-1.0, 0.0, 0.25)])
        assert len(ids) == 2
        assert pybullet.getNumBodies(physicsClientId=sim.client_id) == before + 2
        low, high = pybullet.getAABB(ids[0], physicsClientId=sim.client_id)
        assert np.allclose(low, [0.8, 0.4, 0.0], atol=0.01)
        assert np.allclose(high, [1.2, 0.6, 0.3], atol=0.01)
        hit = pybullet.rayTest([-2.0, 0.0, 0.2], [0.0, 0.0, 0.2],
                               physicsClientId=sim.client_id)[0]
        assert hit[0] == ids[1] and hit[3][0] == pytest.approx(-1.25, abs=1e-3)


def test_render_returns_an_rgb_frame(sim):
    image = sim.render(CameraView(width=64, height=48))
    assert image.shape == (48, 64, 3) and image.dtype == np.uint8
    assert image.std() > 5.0  # not a blank frame


def test_bad_inputs_raise(sim):
    q = sim.description.nominal_leg_positions()
    with pytest.raises(ConfigError, match='shape'):
        sim.step(np.zeros(5))
    with pytest.raises(ConfigError, match='NaN'):
        sim.step(np.full(12, np.nan))
    with pytest.raises(ConfigError, match='n_substeps'):
        sim.step(q, 0)
    with pytest.raises(ConfigError, match='joint_velocities'):
        sim.step(q, 1, joint_velocities=np.full(12, np.inf))
    with pytest.raises(ConfigError, match='no_link'):
        sim.push(ExternalPush((1.0, 0.0, 0.0), link='no_link'))
    with pytest.raises(ConfigError, match='unknown joints'):
        sim.reset(joint_positions={'no_joint': 0.0})
    with pytest.raises(ConfigError, match='base_position'):
        sim.reset(base_position=[0.0, np.nan, 1.0])
    with pytest.raises(ConfigError, match='base_yaw'):
        sim.reset(base_yaw=np.inf)
    with pytest.raises(ConfigError, match='colour_bins'):
        sim.add_terrain(generate_terrain(TerrainParams()), colour_bins=0)


def test_description_not_matching_the_urdf_raises(description):
    with pytest.raises(RobotModelError, match='no_imu'):
        PyBulletBackend(dataclasses.replace(description, imu_link='no_imu'))
    with pytest.raises(RobotModelError, match='base_link'):
        PyBulletBackend(dataclasses.replace(description, base_link='torso'))


def test_closed_backend_refuses_work(description):
    sim = PyBulletBackend(description)
    sim.close()
    with pytest.raises(ConfigError, match='closed'):
        sim.sensors()


@pytest.mark.parametrize('kwargs, field', [
    ({'time_step': 0.0}, 'time_step'),
    ({'time_step': 0.1}, 'time_step'),
    ({'control_substeps': 0}, 'control_substeps'),
    ({'control_mode': 'velocity'}, 'control_mode'),
    ({'leg_kp': -1.0}, 'leg_kp'),
    ({'gain_cap': 2.0}, 'gain_cap'),
    ({'gravity_compensation_period': 0}, 'gravity_compensation_period'),
    ({'foot_friction': math.nan}, 'foot_friction'),
    ({'contact_threshold': 0.0}, 'contact_threshold'),
    ({'sole_contact_stiffness': -1.0}, 'sole_contact_stiffness'),
    ({'sole_contact_damping': math.inf}, 'sole_contact_damping'),
])
def test_bad_config_raises(kwargs, field):
    with pytest.raises(ConfigError, match=field):
        PyBulletConfig(**kwargs)


@pytest.mark.parametrize('kwargs, field', [
    ({'width': 8}, 'width'),
    ({'distance': 0.0}, 'distance'),
    ({'pitch': 90.0}, 'pitch'),
    ({'fov': 180.0}, 'fov'),
    ({'target': (0.0, 1.0)}, 'target'),
])
def test_bad_camera_view_raises(kwargs, field):
    with pytest.raises(ConfigError, match=field):
        CameraView(**kwargs)


@pytest.mark.parametrize('tile_area', [0.01, 0.04, 0.0625])
def test_the_papers_4m_terrains_build_and_the_robot_stands_on_them(description, tile_area):
    # 400 to 1600 tiles: more than PyBullet takes in one visual shape array
    terrain = generate_terrain(TerrainParams(tile_area=tile_area, side_length=4.0,
                                             origin=(-2.0, -2.0), seed=2))
    with PyBulletBackend(description) as sim:
        ids = sim.add_terrain(terrain)
        assert len(ids) >= terrain.heights.size / MAX_SHAPES_PER_BODY
        readings = sim.reset()
        for _ in range(25):
            readings = sim.step(description.nominal_leg_positions())
        soles = min(readings.left_sole[2], readings.right_sole[2])
        assert terrain.params.min_height - 0.005 < soles < terrain.params.max_height + 0.005
