#!/usr/bin/env python3
"""Largest push survived per direction and gait phase, step adjustment off vs on (no ROS).

The PyBullet humanoid walks in place with the paper's push timing (0.3 s single + 0.1 s double
support) and is pushed on the pelvis for 100 ms (biped_sim.push_trial: 8 directions every
45 deg, 4 phases: early and late single support on the right foot, double support, early
single support on the left foot). For each cell a bisection on the force between 0 and
--high N down to --resolution N finds the largest push walked through for 1.5 s without a fall
(the bisection assumes a stronger push is never easier). A force counts as survived when most
of --repeats runs walk through it (runs differ: PyBullet keeps some state across resets, and
near a limit the outcome is chaotic). Three-mass controller by default. Prints a Markdown
table and the minimum over directions and phases. One simulation at a time; each run is about
4 s simulated.

Usage: .venv/bin/python scripts/experiments/push_library_sweep.py [--directions 0,45,...]
           [--phases early_single,late_single,double,early_single_left] [--modes off,on]
           [--model three_mass] [--high 320] [--resolution 10] [--repeats 1]
"""
import argparse
import math
import time

from biped_mpc.controller_params import MODELS
from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_sim import push_trial
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like
from biped_tools.closed_loop_walk import LEG_KP



def largest_survived(survives, high: float, resolution: float) -> tuple:
    """Bisection of the largest force survived in [0, high] (N): (force, bounded above).

    The upper end is assumed to fall and not run; when every force tried is survived the
    result is the last one with bounded False.
    """
    low, top, fell = 0.0, high, False
    while top - low > resolution + 1e-9:
        middle = resolution * round(0.5 * (low + top) / resolution)
        if middle <= low or middle >= top:
            break
        if survives(middle):
            low = middle
        else:
            top, fell = middle, True
    return low, fell


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--directions', default='0,45,90,135,180,225,270,315',
                        help='push directions, deg from +x towards +y')
    parser.add_argument('--phases', default=','.join(push_trial.PHASES))
    parser.add_argument('--modes', default='off,on')
    parser.add_argument('--model', default='three_mass', choices=MODELS)
    parser.add_argument('--high', type=float, default=320.0, help='N, assumed to fall')
    parser.add_argument('--resolution', type=float, default=10.0, help='N')
    parser.add_argument('--repeats', type=int, default=1, help='runs per force (majority)')
    args = parser.parse_args()
    directions = [float(d) for d in args.directions.split(',')]
    phases = args.phases.split(',')
    modes = args.modes.split(',')
    robot = coman_like()
    backend = PyBulletBackend(robot, PyBulletConfig(leg_kp=LEG_KP))
    params = WalkingControllerParams(robot=robot.controller_model, model=args.model,
                                     balance='stabilizer', swing_target='planned',
                                     swing_smoothing_time_constant=push_trial.RECOVERY_SWING_LAG)
    results = {}
    wall = time.monotonic()
    for direction in directions:
        for phase in phases:
            for mode in modes:
                adjuster = push_trial.HUMANOID_ADJUSTER if mode == 'on' else None

                def survives(force):
                    walked = 0
                    for _ in range(args.repeats):
                        trial = push_trial.run_push_trial(
                            backend, WalkingController(params), robot.controller_model, force,
                            math.radians(direction), phase, adjuster)
                        walked += not trial.fallen
                        print(f'  {direction:5.0f} deg {phase:17s} {mode:3s} {force:5.0f} N: '
                              f'{"FELL at %.2f s" % trial.fall_time if trial.fallen else "ok"}'
                              f' ({trial.revisions} replans)', flush=True)
                    return 2 * walked > args.repeats

                results[direction, phase, mode] = largest_survived(survives, args.high,
                                                                   args.resolution)
    backend.close()
    print(f'\n{args.model}, walking in place 0.3 + 0.1 s, 100 ms pelvis push; largest '
          f'survived (N, majority of {args.repeats}), off / on step adjustment; '
          f'{time.monotonic() - wall:.0f} s wall\n')
    print('| direction | ' + ' | '.join(phases) + ' |')
    print('|---|' + '---|' * len(phases))

    def cell(direction, phase):
        values = []
        for mode in modes:
            force, bounded = results[direction, phase, mode]
            values.append(f'{force:.0f}' + ('' if bounded else '+'))
        return ' / '.join(values)

    for direction in directions:
        print(f'| {direction:.0f} deg | ' + ' | '.join(cell(direction, phase)
                                                      for phase in phases) + ' |')
    for mode in modes:
        worst = min((results[d, p, mode][0], d, p) for d in directions for p in phases)
        print(f'\nminimum with adjustment {mode}: {worst[0]:.0f} N ({worst[1]:.0f} deg, '
              f'{worst[2]})')


if __name__ == '__main__':
    main()
