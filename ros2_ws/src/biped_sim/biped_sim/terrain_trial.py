"""Library trials of the PyBullet humanoid on uneven ground: the paper's tiles and an edge.

One definition of each trial for the tests and scripts/experiments/terrain_library_sweep.py:

- flat_walk: straight steps on flat ground;
- edge_stand: standing with the left sole's front half over a drop (an edge across the sole
  at its centre), the rest of both feet on a platform of edge_height;
- terrain_crossing: straight steps across the paper's tiles (tile area, heights 25-50 mm,
  a seed), the robot starting on them, blind (flat-ground references).

The references are the ones the closed-loop tests walk with (0.4 s single and 0.2 s double
support, 4 cm swing height, 0.14 m step width).
"""
from dataclasses import dataclass
import math
from typing import Optional

import numpy as np

from biped_planner.footsteps import straight_footsteps
from biped_planner.landing_hold import LandingHold, LandingHoldParams
from biped_planner.step_adjuster import OnlineStepAdjusterParams
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference

from biped_sim.closed_loop import ClosedLoopRunner
from biped_sim.errors import ConfigError
from biped_sim.push_trial import adjusted_source, HUMANOID_STEP_LIMITS
from biped_sim.reference_sources import HeldWalk
from biped_sim.terrain import generate_terrain, Terrain, TerrainParams

TIMING = StepTiming(single_support=0.4, double_support=0.2)
REFERENCE = ReferenceParams(com_height=0.497, swing_height=0.04, foot_length=0.2,
                            foot_width=0.1)
STEP_WIDTH = 0.14
T_START = 0.5
EDGE_TILE = 0.25  # m, the tiles of the edge terrain (few: contacts on many boxes are slow)


@dataclass(frozen=True)
class TrialResult:
    """What a trial measured.

    :param fallen: the run ended in a fall
    :param fall_time: when (s), NaN without a fall
    :param duration: simulated time run (s)
    :param distance: largest forward x of the centre of mass (m)
    :param max_tilt: largest pelvis tilt (deg)
    :param com_height: (n,) centre-of-mass height over the run (m)
    :param contacts: (n, 2) F/T contact flags over the run
    :param t: (n,) times (s)
    :param log: the runner's RunLog
    """

    fallen: bool
    fall_time: float
    duration: float
    distance: float
    max_tilt: float
    com_height: np.ndarray
    contacts: np.ndarray
    t: np.ndarray
    log: object


def edge_terrain(edge_height: float = 0.025) -> Terrain:
    """A platform of edge_height with a drop where x >= 0 and y >= 0 (under the left sole's
    front half when the robot stands at the origin facing +x).

    :param edge_height: height of the platform (m)
    :return: the terrain (tiles of height 0 are not built)
    """
    params = TerrainParams(tile_area=EDGE_TILE ** 2, side_length=1.0, min_height=0.0,
                           max_height=edge_height, origin=(-0.5, -0.5))
    n = int(round(1.0 / EDGE_TILE))
    centres = -0.5 + EDGE_TILE * (np.arange(n) + 0.5)
    heights = np.full((n, n), float(edge_height))
    heights[np.ix_(centres > 0.0, centres > 0.0)] = 0.0
    return Terrain(params, heights)


def lane_step_terrain(step: float, base: float = 0.0, edge: float = 0.105) -> Terrain:
    """Ground at base height with the left foot's lane (y > 0) at base + step from x = edge
    on: with the default edge the left foot's first step of 0.2 m lands wholly on the changed
    height (a raised lane, step > 0: early touchdown; a lowered one, step < 0: late
    touchdown), the right foot's lane stays at base.

    :param step: height change of the left lane (m)
    :param base: height of the rest (m), >= 0; base + step >= 0
    :param edge: x of the edge (m), 0.105 + a multiple of 0.1
    :return: the terrain (tiles of 0.1 m; height 0 is the ground plane)
    """
    side, n = 0.1, 10
    origin = edge - 0.6
    params = TerrainParams(tile_area=side ** 2, side_length=n * side, min_height=0.0,
                           max_height=max(base, base + step), origin=(origin, -0.5))
    x_centres = origin + side * (np.arange(n) + 0.5)
    y_centres = -0.5 + side * (np.arange(n) + 0.5)
    heights = np.full((n, n), float(base))
    heights[np.ix_(x_centres > edge, y_centres > 0.0)] = base + step
    return Terrain(params, heights)



def step_down_terrain(height: float, edge: float, behind: float = 0.5) -> Terrain:
    """A platform of height under the robot's start that ends at x = edge: the walk steps down
    to the ground plane there, as at the far side of the paper's tiles.

    :param height: height of the platform (m), > 0
    :param edge: x of its far edge (m), > -behind
    :param behind: how far the platform reaches behind the start (m); it is as wide as long
    :return: the terrain (one tile)
    """
    side = edge + behind
    if not (height > 0.0 and side > 0.0):
        raise ConfigError(f'need a height > 0 and an edge past {-behind} m, got {height!r}, '
                          f'{edge!r}')
    params = TerrainParams(tile_area=side ** 2, side_length=side, min_height=height,
                           max_height=height, origin=(-behind, -0.5 * side))
    return Terrain(params, np.full((1, 1), float(height)))


def _both(first, second):
    """One on_cycle callback calling two."""
    def call(*args):
        first(*args)
        second(*args)
    return call


# The paper's tiled area as the graph's terrain scenario lays it out (scripts/biped_tools/
# scenarios/terrain.py uses these): the same seed gives the same tiles in both. With a 3 m side
# the library walked other tiles than the graph (100 cm^2 seed 2 stood there and fell in both
# at 4 m).
PAPER_SIDE = 4.0    # m
PAPER_BEHIND = 0.5  # m of tiles behind the robot's start


def paper_terrain(tile_area: float, seed: int, side_length: float = PAPER_SIDE,
                  heights: tuple = (0.025, 0.05)) -> Terrain:
    """The paper's tiles starting PAPER_BEHIND behind the robot, centred on its path.

    :param tile_area: area of a tile (m^2)
    :param seed: seed of the heights
    :param side_length: side of the tiled square (m)
    :param heights: (lowest, highest) tile top (m)
    :return: the terrain
    """
    return generate_terrain(TerrainParams(
        tile_area=tile_area, side_length=side_length, min_height=heights[0],
        max_height=heights[1], origin=(-PAPER_BEHIND, -0.5 * side_length), seed=seed))


def run_trial(backend, controller, n_steps: int, step_length: float, terrain=None,
              duration: float = None, t_start: float = T_START,
              on_cycle=None, landing_hold: Optional[LandingHoldParams] = None,
              adjuster: Optional[OnlineStepAdjusterParams] = None, robot=None) -> TrialResult:
    """Walk straight steps (or stand, n_steps = 0) with the controller on the backend.

    :param backend: a PyBulletBackend (its scenery is replaced by the terrain)
    :param controller: a WalkingController
    :param n_steps: number of steps
    :param step_length: step length (m)
    :param terrain: the ground (None: flat)
    :param duration: simulated time (s); None runs to the end of the plan plus 1 s
    :param t_start: start of the walk (s)
    :param on_cycle: called after every cycle as on_cycle(t, window, output, readings)
    :param landing_hold: let the plan wait for late landings (biped_planner.landing_hold);
        None walks the plan's timing
    :param adjuster: let the online step adjuster replan the steps from the measured DCM, as
        the push trials do (push_trial.adjusted_source); None walks the plan's steps
    :param robot: the RobotModel walked (needed with adjuster: the measured DCM's kinematics)
    :return: the measurements
    :raises ConfigError: for both landing_hold and adjuster, or adjuster without robot
    """
    if adjuster is not None and (landing_hold is not None or robot is None):
        raise ConfigError('the step adjuster needs the robot and no landing hold')
    backend.clear_scenery()
    if terrain is not None:
        backend.add_terrain(terrain)
    reference = WalkingReference(straight_footsteps(n_steps, step_length, STEP_WIDTH), TIMING,
                                 REFERENCE, t_start=t_start)
    source = reference if landing_hold is None else HeldWalk(reference,
                                                              LandingHold(landing_hold))
    if adjuster is not None:
        source, observe = adjusted_source(reference, robot, adjuster, HUMANOID_STEP_LIMITS)
        on_cycle = observe if on_cycle is None else _both(observe, on_cycle)
    runner = ClosedLoopRunner(backend, controller, source)
    runner.reset()
    log = runner.run(reference.t_end + 1.0 if duration is None else duration, on_cycle)
    fallen = bool(log.fallen)
    return TrialResult(fallen, float(log.fall_time) if fallen else math.nan,
                       float(log.t[-1]) if log.t.size else 0.0,
                       float(log.com[:, 0].max()) if log.t.size else 0.0,
                       float(np.degrees(log.tilt.max())) if log.t.size else 0.0,
                       log.com[:, 2].copy(), log.contacts.copy(), log.t.copy(), log)
