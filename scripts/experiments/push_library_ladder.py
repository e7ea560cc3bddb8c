#!/usr/bin/env python3
"""Push table of the PyBullet humanoid without ROS, the graph scenario's force ladder.

Like `scripts/scenarios.py push-directions` (8 directions x 4 phases, walking in place or
forward at 0.1 m steps, 100 ms pelvis pushes), but each force of the ladder is a fresh trial
(biped_sim.push_trial) and a cell's figure is the largest force walked through before the first
fall. Every trial gets a fresh simulator, so a cell's figure does not depend on the cells run
before it (a subset of directions gives the same rows as the whole table), and the run is
deterministic: two settings can be compared cell by cell in a few minutes (about 1.3 s per
trial on a quiet core). Settings are overridden per group: `ctl.NAME=VALUE`
(WalkingControllerParams), `adj.NAME=VALUE` (OnlineStepAdjusterParams, from
push_trial.HUMANOID_ADJUSTER), `qp.NAME=VALUE` (StepAdjustmentParams, from
push_trial.HUMANOID_STEP_LIMITS) and `sim.NAME=VALUE` (PyBulletConfig, e.g.
sim.sole_contact_stiffness=1e5).

Usage: .venv/bin/python scripts/experiments/push_library_ladder.py [--adjustment off]
           [--gait forward] [--directions 0,90] [--phases early_single,double] [--forces 80,110,140]
           [--schedule [--offsets=-0.01,0,0.01] [--grounded]] [qp.offset_weight=100.0 ...]
"""
import argparse
import ast
from dataclasses import replace
import math
import statistics
import time

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_sim import push_trial
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like
from biped_tools.closed_loop_walk import LEG_KP

GROUPS = ('ctl', 'adj', 'qp', 'sim')
GAITS = {'in_place': 0.0, 'forward': 0.1}   # step length (m)


def overrides(settings) -> dict:
    """{'ctl': {...}, 'adj': {...}, 'qp': {...}, 'sim': {...}} from GROUP.NAME=VALUE strings."""
    groups = {group: {} for group in GROUPS}
    for setting in settings:
        key, _, text = setting.partition('=')
        group, _, name = key.partition('.')
        if group not in groups or not name or not text:
            raise SystemExit(f'expected GROUP.NAME=VALUE with GROUP in {GROUPS}, got '
                             f'{setting!r}')
        try:
            value = ast.literal_eval(text)
        except (ValueError, SyntaxError):
            value = text
        groups[group][name] = value
    return groups


def cell(args, robot, params, adjuster, limits, forces, direction, phase,
         offset: float = 0.0, sim_settings=None) -> tuple:
    """The largest force of the ladder walked through at one direction and phase (N), the
    scheduled pushes started `offset` s later in their phase, and (schedule only, else the
    same) the largest walked through with a foot loaded (push_trial.MAX_FLIGHT)."""
    def simulator():
        # a fresh simulator per trial: PyBullet's contact state carries over a reset, and a
        # cell's figure depended on the trials run before it
        return PyBulletBackend(robot, PyBulletConfig(**{'leg_kp': LEG_KP,
                                                        **(sim_settings or {})}))

    if args.schedule:
        backend = simulator()
        try:
            result = push_trial.run_push_schedule(
                backend, WalkingController(params), robot.controller_model, forces,
                math.radians(direction), phase, adjuster, limits,
                step_length=GAITS[args.gait], phase_offset=offset)
            return result.largest_withstood, result.largest_grounded()
        finally:
            backend.close()
    best = 0.0
    for force in forces:
        backend = simulator()
        try:
            trial = push_trial.run_push_trial(
                backend, WalkingController(params), robot.controller_model, force,
                math.radians(direction), phase, adjuster, limits, step_length=GAITS[args.gait])
        finally:
            backend.close()
        if trial.fallen:
            break
        best = force
    return best, best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--adjustment', choices=('on', 'off'), default='on')
    parser.add_argument('--gait', choices=tuple(GAITS), default='in_place',
                        help='walking in place or forward at 0.1 m steps (the graph scenario)')
    parser.add_argument('--directions', default='0,45,90,135,180,225,270,315',
                        help='deg from +x towards +y')
    parser.add_argument('--phases', default=','.join(push_trial.PHASES))
    parser.add_argument('--forces', default='80,110,140,170,200,230', help='N, in order')
    parser.add_argument('--schedule', action='store_true',
                        help="one walk per cell pushed every 3 s with the growing forces, as "
                             "the graph's push-directions does (default: a fresh walk per force)")
    parser.add_argument('--offsets', default='0',
                        help="with --schedule: s added to the pushes' start in their phase, one "
                             "walk each, a cell the median (--offsets=-0.015,0,0.015: a cell's "
                             "figure changes with the instant within its phase)")
    parser.add_argument('--grounded', action='store_true',
                        help='with --schedule: beside each cell, in brackets, the largest push '
                             'walked through with both feet unloaded for no more than '
                             f'{push_trial.MAX_FLIGHT} s (a bounce is no recovery)')
    parser.add_argument('settings', nargs='*', help='GROUP.NAME=VALUE')
    args = parser.parse_args()
    settings = overrides(args.settings)
    directions = [float(d) for d in args.directions.split(',')]
    phases = args.phases.split(',')
    forces = [float(f) for f in args.forces.split(',')]
    offsets = [float(o) for o in args.offsets.split(',')]
    if offsets != [0.0] and not args.schedule:  # fresh walks take no offset
        raise SystemExit('--offsets needs --schedule')
    if args.grounded and not args.schedule:
        raise SystemExit('--grounded needs --schedule')
    robot = coman_like()
    params = WalkingControllerParams(robot=robot.controller_model,
                                     **{'model': 'three_mass', 'balance': 'stabilizer',
                                        'swing_target': 'planned',
                                        'swing_smoothing_time_constant':
                                            push_trial.RECOVERY_SWING_LAG, **settings['ctl']})
    adjuster = (replace(push_trial.HUMANOID_ADJUSTER, **settings['adj'])
                if args.adjustment == 'on' else None)
    limits = replace(push_trial.HUMANOID_STEP_LIMITS, **settings['qp'])
    wall = time.monotonic()
    print(f'{params.model}, {args.gait.replace("_", " ")}, adjustment {args.adjustment}, '
          f'{"one walk pushed every 3 s" if args.schedule else "a fresh walk per force"}'
          f'{f", median over push offsets {offsets} s" if len(offsets) > 1 else ""}, settings '
          f'{args.settings or "default"}: largest push walked through (N)\n')
    print('| direction | ' + ' | '.join(phases) + ' |')
    print('|---|' + '---|' * len(phases))
    withstood, grounded = [], []
    for direction in directions:
        row, row_grounded = [], []
        for phase in phases:
            figures = [cell(args, robot, params, adjuster, limits, forces, direction, phase,
                            offset, settings['sim']) for offset in offsets]
            row.append(statistics.median(f[0] for f in figures))
            row_grounded.append(statistics.median(f[1] for f in figures))
        withstood += row
        grounded += row_grounded
        print(f'| {direction:.0f} deg | ' + ' | '.join(
            f'{f:.0f} ({g:.0f})' if args.grounded else f'{f:.0f}'
            for f, g in zip(row, row_grounded)) + ' |', flush=True)
    print(f'\nminimum {min(withstood):.0f} N, sum {sum(withstood):.0f} N over '
          f'{len(withstood)} cells, {sum(f < 150.0 for f in withstood)} below 150 N; '
          f'{time.monotonic() - wall:.0f} s wall')
    if args.grounded:
        print(f'on the ground (in brackets): minimum {min(grounded):.0f} N, sum '
              f'{sum(grounded):.0f} N, {sum(f < 150.0 for f in grounded)} below 150 N')


if __name__ == '__main__':
    main()
