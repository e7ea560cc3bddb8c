"""The stabilized controller on uneven ground in PyBullet (biped_sim.terrain_trial).

Standing 30 s with the left sole's front half over a 25 mm drop, and on two of the paper's
terrains whose start puts both soles on tile edges; crossings of the paper's tiles, where the
stabilizer still falls (docs/simulator_notes.md) but walks further than the open loop.
"""
import math

import numpy as np
import pytest

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.terrain_trial import edge_terrain, paper_terrain, run_trial


def test_standing_thirty_seconds_with_a_sole_half_over_an_edge(sim, robot):
    controller = WalkingController(WalkingControllerParams(
        robot=robot.controller_model, balance='stabilizer', swing_target='planned'))
    result = run_trial(sim, controller, 0, 0.0, edge_terrain(0.025), duration=30.0,
                       t_start=1e3)
    assert not result.fallen
    assert result.duration == pytest.approx(30.0, abs=0.05)
    assert result.max_tilt < 2.0
    # Both feet stay on the platform (the left one on its rear half), the pelvis at rest.
    assert np.all(result.contacts[-250:])
    assert np.ptp(result.log.base_position[-250:, :2], axis=0).max() < 0.005


@pytest.mark.parametrize('area_cm2, seed', [(625, 1), (100, 2)])
def test_standing_thirty_seconds_on_the_papers_tiles(sim, robot, area_cm2, seed):
    """Both soles start on tile edges: 625 cm^2 seed 1 has the heels on a 50 mm tile and the
    toes over 27 and 41 mm ones, the centre of mass ahead of the edges. The soles tip onto the
    lower tiles; foot damping lets them while the body stays upright (with 0.01 rad/(N m s),
    0.2 rad/s and 0.15 rad the robot fell there after 2.1 s, and with 0.01 at 1 rad/s too)."""
    controller = WalkingController(WalkingControllerParams(
        robot=robot.controller_model, balance='stabilizer', swing_target='planned'))
    result = run_trial(sim, controller, 0, 0.0, paper_terrain(area_cm2 * 1e-4, seed),
                       duration=30.0, t_start=1e3)
    assert not result.fallen
    assert result.duration == pytest.approx(30.0, abs=0.05)
    assert result.max_tilt < 8.0
    assert np.ptp(result.log.base_position[-250:, :2], axis=0).max() < 0.005  # at rest


def test_the_stabilizer_walks_further_on_tiles_than_the_open_loop(robot):
    """Mean COM x reached on one terrain of each tile size, a fresh simulator per trial (on a
    shared one a trial depends on the one before it)."""
    reached = {}
    for balance in ('stabilizer', 'open_loop'):
        distances = []
        for area_cm2, seed in ((100, 1), (400, 1), (625, 2)):
            backend = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
            try:
                controller = WalkingController(WalkingControllerParams(
                    robot=robot.controller_model, balance=balance, swing_target='planned'))
                result = run_trial(backend, controller, 24, 0.1,
                                   paper_terrain(area_cm2 * 1e-4, seed))
            finally:
                backend.close()
            distances.append(0.0 if math.isnan(result.distance) else result.distance)
        reached[balance] = float(np.mean(distances))
    assert reached['stabilizer'] > reached['open_loop'] + 0.1


@pytest.mark.parametrize('area_cm2, seed', [(100, 2), (625, 3)])
def test_the_library_walks_the_tiles_the_graph_scenario_lays(area_cm2, seed):
    """paper_terrain and the simulator node's terrain.* parameters as scripts/scenarios.py
    terrain sets them give the same tiles for a seed."""
    from biped_sim.nodes.simulator_parameters import terrain_from
    from biped_sim.terrain_trial import PAPER_BEHIND, PAPER_SIDE
    node = terrain_from(1, PAPER_SIDE, -PAPER_BEHIND, -0.5 * PAPER_SIDE,
                        math.sqrt(area_cm2) / 100.0, 0.025, 0.05, seed)
    np.testing.assert_array_equal(paper_terrain(area_cm2 * 1e-4, seed).heights, node.heights)


@pytest.mark.parametrize('ground, lag', [('zmp', 0.0), ('mean', 0.05), ('mean', 0.0)])
def test_a_landing_on_a_lower_tile_does_not_kick_the_robot_off_the_ground(robot, ground, lag):
    """400 cm^2 seed 5: at 2.04 s the left foot lands on a tile 13 mm below the right one.
    With the pelvis above the mean of the held feet, latched at once (lag 0), the stiff left
    leg extended 8 mm in a period and the robot hopped: both soles unloaded for 4 periods, the
    centre of mass 19 mm up (docs/controller_notes.md, "Touchdowns that kick"); with the height
    continuity's lag it stays on the ground; with the pelvis above the ground under the ZMP
    (the default) it rises 4 mm and leaves the ground for 2 periods at most."""
    backend = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
    loads, heights = [], []

    def on_cycle(t, window, output, readings):
        if 2.0 <= t <= 2.3:  # the landing and the next lift-off
            loads.append(max(readings.left_foot.ground_force[2],
                             readings.right_foot.ground_force[2]))
            heights.append(readings.com_position[2])

    try:
        controller = WalkingController(WalkingControllerParams(
            robot=robot.controller_model, swing_target='planned',
            height_continuity_time_constant=lag, pelvis_ground_at_zmp=ground == 'zmp'))
        run_trial(backend, controller, 24, 0.1, paper_terrain(0.04, 5), duration=3.0,
                  on_cycle=on_cycle)
    finally:
        backend.close()
    airborne = int(np.sum(np.array(loads) < 20.0))  # periods with both soles below 20 N
    rise = max(heights) - heights[0]
    if ground == 'zmp':
        assert airborne <= 2
        assert rise < 0.006
    elif lag > 0.0:
        assert airborne == 0
        assert rise < 0.006
    else:
        assert airborne >= 3
        assert rise > 0.015
