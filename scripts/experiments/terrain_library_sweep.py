#!/usr/bin/env python3
"""Library closed loop on PyBullet: flat walk, standing on an edge, the paper's 9 terrains.

Runs biped_sim.terrain_trial for the three-mass controller and the LIPM baseline, each with
the stabilizer (balance 'stabilizer') and open loop (both with the planned swing target), and
prints one table row per trial: fell or not, when, how far the centre of mass went, the
largest pelvis tilt.
Every trial gets a fresh simulator: the tile runs depend on what the simulator ran before.

    .venv/bin/python scripts/experiments/terrain_library_sweep.py [--steps 24] [--edge 30]
        [--areas 100 400 625] [--seeds 1 2 3] [--balance stabilizer open_loop]
        [--no-flat] [--no-edge] [--heights 0.025 0.05] [--set ankle_damping_gain=0.02 ...]
        [--sim sole_contact_stiffness=1e5 ...]
"""
import argparse
import dataclasses
import time

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.landing_hold import LandingHoldParams
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.push_trial import HUMANOID_ADJUSTER
from biped_sim.robot_description import coman_like
from biped_sim.terrain_trial import edge_terrain, paper_terrain, run_trial


def parse_override(text: str) -> tuple:
    name, _, value = text.partition('=')
    if value.lower() in ('true', 'false'):
        return name, value.lower() == 'true'
    try:
        return name, float(value)
    except ValueError:
        return name, value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--steps', type=int, default=24, help='steps of 0.1 m per crossing')
    parser.add_argument('--edge', type=float, default=30.0, help='s standing on the edge')
    parser.add_argument('--areas', type=float, nargs='*', default=[100, 400, 625],
                        help='tile areas (cm^2)')
    parser.add_argument('--seeds', type=int, nargs='+', default=[1, 2, 3])
    parser.add_argument('--models', nargs='+', default=['three_mass', 'lipm'])
    parser.add_argument('--balance', nargs='+', default=['stabilizer', 'open_loop'])
    parser.add_argument('--heights', type=float, nargs=2, default=[0.025, 0.05],
                        metavar=('LOW', 'HIGH'), help='tile top heights (m); the paper: 0.025 '
                        '0.05; a narrower spread measures how much unevenness a controller '
                        'takes')
    parser.add_argument('--no-flat', action='store_true', help='skip the flat walk')
    parser.add_argument('--no-edge', action='store_true', help='skip standing on the edge')
    parser.add_argument('--landing-hold', type=float, default=None, metavar='SECONDS',
                        help='let the plan wait this long at most for a late landing '
                        '(biped_planner.landing_hold); default: the plan\'s timing')
    parser.add_argument('--end-early', action='store_true',
                        help='end the single support when a swing foot lands before its time '
                        '(biped_planner.landing_hold end_early; needs the controller\'s '
                        'contact_aware_landing, --set contact_aware_landing=true)')
    parser.add_argument('--adjust', action='store_true',
                        help='the online step adjuster replans the steps from the measured '
                        'DCM (the push trials\' and the graph\'s settings)')
    parser.add_argument('--set', nargs='*', default=[], metavar='FIELD=VALUE',
                        help='WalkingControllerParams fields to override (numbers, true/false)')
    parser.add_argument('--sim', nargs='*', default=[], metavar='FIELD=VALUE',
                        help='PyBulletConfig fields to override (e.g. the rubber soles, '
                        'sole_contact_stiffness=1e5)')
    args = parser.parse_args()
    overrides = dict(parse_override(text) for text in args.set)
    hold = None
    if args.landing_hold is not None or args.end_early:
        hold = LandingHoldParams(enabled=args.landing_hold is not None,
                                 hold_time=args.landing_hold or 0.0, end_early=args.end_early)
    sim_overrides = dict(parse_override(text) for text in args.sim)
    robot = coman_like()
    trials = [] if args.no_flat else [('flat', None, args.steps)]
    trials += [] if args.no_edge else [('edge 25 mm', edge_terrain(0.025), 0)]
    trials += [(f'tiles {area:g} cm2 seed {seed}',
                paper_terrain(area * 1e-4, seed, heights=tuple(args.heights)), args.steps)
               for area in args.areas for seed in args.seeds]
    print('| trial | model | balance | fell | fall time (s) | COM x reached (m) | '
          'max tilt (deg) | wall (s) |')
    print('|---|---|---|---|---|---|---|---|')
    for name, terrain, steps in trials:
        for model in args.models:
            for balance in args.balance:
                backend = PyBulletBackend(robot, PyBulletConfig(
                    **{'leg_kp': 2000.0, **sim_overrides}))
                controller = WalkingController(dataclasses.replace(WalkingControllerParams(
                    robot=robot.controller_model, model=model, balance=balance,
                    swing_target='planned'), **overrides))
                wall = time.monotonic()
                try:
                    if steps:
                        result = run_trial(backend, controller, steps, 0.1, terrain,
                                           landing_hold=hold, robot=robot.controller_model,
                                           adjuster=HUMANOID_ADJUSTER if args.adjust else None)
                    else:
                        result = run_trial(backend, controller, 0, 0.0, terrain,
                                           duration=args.edge, t_start=1e3)
                finally:
                    backend.close()
                print(f'| {name} | {model} | {balance} | {"yes" if result.fallen else "no"} | '
                      f'{result.fall_time:.2f} | {result.distance:.2f} | '
                      f'{result.max_tilt:.1f} | {time.monotonic() - wall:.0f} |', flush=True)


if __name__ == '__main__':
    main()
