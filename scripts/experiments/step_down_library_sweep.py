#!/usr/bin/env python3
"""Library closed loop on PyBullet: walk blind off a platform, as off the far side of the tiles.

The robot starts on a platform 25-50 mm high (the paper's tile heights) and walks 10 steps of
0.1 m with flat-ground references; the platform ends at x = edge, so one step comes down onto
the ground plane late, and with 0.2 m soles on 0.1 m steps some sole always lands across the
edge. The edges sweep two step periods, so every way a sole can meet the edge is tried.
Every trial gets a fresh simulator. Prints one row per trial and a map per model and height
('.' walked on past edge + 0.2 m, 'X' fell) with the count walked through.

    .venv/bin/python scripts/experiments/step_down_library_sweep.py [--heights 0.025 0.0375
        0.05] [--edges 0.30 0.48 0.02] [--steps 10] [--models three_mass lipm]
        [--set contact_aware_landing=true ...]
"""
import argparse
import dataclasses
import time

import numpy as np

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.landing_hold import LandingHoldParams
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.push_trial import HUMANOID_ADJUSTER
from biped_sim.robot_description import coman_like
from biped_sim.terrain_trial import run_trial, step_down_terrain
from terrain_library_sweep import parse_override  # same folder: run as a script

# m past the edge the centre of mass must reach, standing at the end, for a walk through
WALKED_PAST = 0.2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--heights', type=float, nargs='+', default=[0.025, 0.0375, 0.05],
                        help='platform heights (m)')
    parser.add_argument('--edges', type=float, nargs=3, default=[0.30, 0.48, 0.02],
                        metavar=('FIRST', 'LAST', 'STEP'), help='edge positions x (m)')
    parser.add_argument('--steps', type=int, default=10, help='steps of 0.1 m')
    parser.add_argument('--models', nargs='+', default=['three_mass'])
    parser.add_argument('--landing-hold', type=float, default=None, metavar='SECONDS',
                        help='let the plan wait this long at most for a late landing '
                        '(biped_planner.landing_hold); default: the plan\'s timing')
    parser.add_argument('--adjust', action='store_true',
                        help='the online step adjuster replans the steps from the measured '
                        'DCM (the push trials\' and the graph\'s settings)')
    parser.add_argument('--set', nargs='*', default=[], metavar='FIELD=VALUE',
                        help='WalkingControllerParams fields to override (numbers, true/false)')
    args = parser.parse_args()
    overrides = dict(parse_override(text) for text in args.set)
    hold = None if args.landing_hold is None else LandingHoldParams(
        enabled=True, hold_time=args.landing_hold)
    first, last, step = args.edges
    edges = np.round(np.arange(first, last + 0.5 * step, step), 4)
    robot = coman_like()
    print('| model | height (m) | edge x (m) | fell | fall time (s) | COM x reached (m) | '
          'max tilt (deg) | wall (s) |')
    print('|---|---|---|---|---|---|---|---|')
    maps = []
    for model in args.models:
        for height in args.heights:
            marks = ''
            for edge in edges:
                backend = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
                controller = WalkingController(dataclasses.replace(WalkingControllerParams(
                    robot=robot.controller_model, model=model, balance='stabilizer',
                    swing_target='planned'), **overrides))
                wall = time.monotonic()
                try:
                    result = run_trial(backend, controller, args.steps, 0.1,
                                       step_down_terrain(height, float(edge)),
                                       landing_hold=hold, robot=robot.controller_model,
                                       adjuster=HUMANOID_ADJUSTER if args.adjust else None)
                finally:
                    backend.close()
                walked = not result.fallen and result.distance > edge + WALKED_PAST
                marks += '.' if walked else 'X'
                print(f'| {model} | {height:g} | {edge:.2f} | '
                      f'{"yes" if result.fallen else "no"} | {result.fall_time:.2f} | '
                      f'{result.distance:.2f} | {result.max_tilt:.1f} | '
                      f'{time.monotonic() - wall:.0f} |', flush=True)
            maps.append(f'{model} {height * 1000:4.1f} mm: {marks}  '
                        f'{marks.count(".")} of {len(marks)}')
    print(f'\nedges {edges[0]:.2f} .. {edges[-1]:.2f} m:')
    print('\n'.join(maps))


if __name__ == '__main__':
    main()
