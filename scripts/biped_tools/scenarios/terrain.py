"""Walking on uneven terrain (paper, "Walking on Uneven Terrains").

A 4 x 4 m area of square tiles of random heights (25-50 mm), the robot standing on it 0.5 m
from its near edge; tile areas of 100, 400 and 625 cm^2; the controller knows nothing of the
terrain (flat-ground references). The robot walks forward (OMNI command, fixed step) until its
pelvis is past the far edge; with `stand` it first stands that much longer on the tiles.
Reported: success per tile size and seed, and the COM height (paper Fig. uneven b).
"""
import math
import time

import numpy as np

from biped_sim.terrain_trial import PAPER_BEHIND, PAPER_SIDE
from biped_tools.scenarios.trial import (base_result, drive, graph_for, Progress, stated_start,
                                         STOP_AFTER_ARRIVAL, stop_walking, Trial, write_result)

SIDE = PAPER_SIDE       # m, the library's paper_terrain too: the same tiles for a seed
BEHIND = PAPER_BEHIND   # m of tiles behind the robot's start: it starts on them (paper)
HEIGHTS = (0.025, 0.05)  # m
MAX_HEIGHT = 0.2  # m, the highest tile a scenario lays (a step of the robot's shin)
TILE_AREAS_CM2 = (100, 400, 625)
STEP_LENGTH = 0.1       # m per step
EXIT_MARGIN = 0.3       # m past the far edge


def tile_size(area_cm2: float) -> float:
    return math.sqrt(area_cm2) / 100.0


def run(trial: Trial, area_cm2: float, seed: int, step_length: float = STEP_LENGTH,
        side: float = SIDE, heights: tuple = HEIGHTS, stand: float = 0.0) -> dict:
    """Walk across a side x side m tiled area (tiles of area_cm2, heights (min, max) in m
    drawn from seed).

    :param stand: s of sim time the robot stands on the tiles past the stated start before it
        walks (the issue's "stands 30 s": stand 30)
    """
    from biped_msgs.msg import WalkCommand
    wall0 = time.monotonic()
    # the simulator starts with the robot standing on the tiles, as in the paper
    tiles = {'simulator': [
        'terrain.kind:=1', f'terrain.side_length:={float(side)!r}',
        f'terrain.origin_x:={-BEHIND!r}', f'terrain.origin_y:={-0.5 * side!r}',
        f'terrain.tile_size:={tile_size(area_cm2)!r}',
        f'terrain.min_height:={float(heights[0])!r}',
        f'terrain.max_height:={float(heights[1])!r}', f'terrain.seed:={int(seed)}']}
    with graph_for(trial, extra=tiles) as session:
        session.watch_foot_forces()
        progress = Progress(trial)
        sim0 = session.sim_time()
        # it settles on the tiles until the stated start (the same in every run)
        walk_start = stated_start(session, trial) + stand
        session.send_command(command=WalkCommand.OMNI, step_length=step_length,
                             start_time=walk_start)
        exit_x = side - BEHIND + EXIT_MARGIN
        # from now: the walk starts at walk_start (20 s when the graph was ready after 8 s)
        budget = walk_start - session.sim_time() + (exit_x / step_length) * 0.6 * 1.5 + 10.0
        crossed = drive(session, lambda t: session.series.pelvis[-1][1] >= exit_x, budget,
                        progress)
        stood, result_stop = False, None
        if crossed:
            # stated from the first pelvis sample past the exit, not from when it was seen
            t_exit = next(sample[0] for sample in session.series.pelvis if sample[1] >= exit_x)
            result_stop = t_exit + STOP_AFTER_ARRIVAL
            stood = stop_walking(session, at=result_stop)
        result = base_result(trial, session, wall0, sim0)
        series = session.series
    pelvis = np.array(series.pelvis)
    result['start_pelvis_z'] = round(float(pelvis[0, 3]), 4)  # on the tiles: above flat 0.54 m
    result['stand_s'] = stand
    fall_at = result['fall_sim_time_s']  # the state machine's, not when the runner looked
    result['fell_standing'] = bool(result['fallen'] and fall_at < walk_start)
    if result['fallen']:  # how far it walked: before it began to fall (not where it landed)
        pelvis = pelvis[pelvis[:, 0] <= fall_at - 0.5]
    # a fall while standing walked nowhere (the samples the runner saw depend on the load)
    reached = float(pelvis[:, 1].max()) if len(pelvis) and not result['fell_standing'] \
        else 0.0
    result.update({'tile_area_cm2': area_cm2, 'side_m': side, 'seed': seed,
                   'heights_m': list(heights),
                   'step_length_m': step_length, 'distance_m': round(reached, 3),
                   'stop_stated_s': None if result_stop is None else round(result_stop - sim0, 3),
                   'terrain_fraction_crossed': round(float(np.clip(
                       (reached + BEHIND) / side, 0.0, 1.0)), 3)})
    result['success'] = bool(crossed and stood and not result['fallen'])
    result['plots'] = [str(plot(trial, series, result))]
    return write_result(trial, result)


# N of normal force on a sole's F/T sensor taken as contact in the plot: the controller's
# touchdown detector's threshold (the foot's own weight reads about 10 N)
CONTACT_FORCE = 50.0


def plot(trial: Trial, series, result: dict):
    """COM height while crossing the tiles (paper Fig. uneven b) over the feet's contact
    states (normal force of each ankle F/T reading over CONTACT_FORCE)."""
    from biped_tools.run_plots import pyplot, save_time_figure
    plt = pyplot()
    com = np.array(series.com)
    fig, (ax, contact_ax) = plt.subplots(2, 1, figsize=(10, 5.5), sharex=True,
                                         gridspec_kw={'height_ratios': [3, 1]})
    ax.plot(com[:, 0], com[:, 3], 'g-', lw=1, label='COM height')
    ax.set_ylabel('COM z (m)')
    ax.set_title(f'Uneven terrain ({trial.model}, tiles {result["tile_area_cm2"]} cm^2, seed '
                 f'{result["seed"]}): {"crossed" if result["success"] else "failed"}')
    ax.legend(loc='lower left', fontsize=8)
    for level, (name, samples, colour) in enumerate(zip(
            ('left', 'right'), series.foot_forces, ('tab:blue', 'tab:red'))):
        if not samples:
            continue
        forces = np.array(samples)
        touching = np.abs(forces[:, 1]) > CONTACT_FORCE
        contact_ax.fill_between(forces[:, 0], level + 0.1, level + 0.9, where=touching,
                                step='post', color=colour, lw=0, label=f'{name} sole')
    contact_ax.set_yticks([0.5, 1.5], ['left', 'right'])
    contact_ax.set_ylim(0, 2)
    return save_time_figure(fig, contact_ax, trial.directory / 'terrain_com_height.png',
                            'contact', f'sole in contact: F/T normal force > {CONTACT_FORCE:.0f} N')
