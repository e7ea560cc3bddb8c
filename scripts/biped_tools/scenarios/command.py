"""The paper's COMAN experiments through the node graph, for the three-mass MPC and the LIPM
baseline: one sub-command per scenario, `summary` for the table tb:summary, `video` for a clip.

Every trial brings up the node graph (lockstep sim time), records a rosbag2 of the run, and writes
result.json and its plots to output/scenarios/<scenario>/<model>/<setting>/.

  scenarios.py disk [--step-length 0.15 | --sweep [--repeats 3]] [--laps 1]
  scenarios.py omni [--scale 1.0 | --sweep [--repeats 3]] [--duration 36]
  scenarios.py push [--forces 80 100 ...] [--repeats 3]   (default: the paper's schedule to a
                                                           fall, three runs, the median)
  scenarios.py push-directions [--directions 0 45 ...] [--phases early_single ...]
               [--gaits in_place forward] [--adjustment off on] [--forces 80 110 ...]
               [--repeats 1]
  scenarios.py terrain [--tile-areas 100 400 625] [--seeds 1 2 3] [--side 4] [--stand 30]
                       [--heights 0.0 0.05]
  scenarios.py goal
  scenarios.py summary [--seeds 1 2 3] [--jobs 2] [--repeats 3]   (all of them, both models,
                                                                  the table)
  scenarios.py video push --model three_mass         (an animated GIF from the sim camera;
                                                      push-adjusted: with step adjustment)
Common: --model three_mass|lipm|both (default both), --out DIR, --domain-id N, --no-bag.
A limit (largest step length, scale or push) is confirmed by --repeats runs at it and at the
setting above it, judged by the median (biped_tools.scenarios.sweep).
"""
import argparse
import json
from pathlib import Path
import signal
import time

from biped_tools.bringup import parse_overrides
from biped_tools.paths import OUTPUT
from biped_tools.scenarios import (disk, omni, push, push_directions, start_goal, summary,
                                   terrain)
from biped_tools.scenarios.sweep import check_repeats, run_name
from biped_tools.scenarios.trial import TrialFactory

MODELS = ('lipm', 'three_mass')


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument('--model', choices=MODELS + ('both',), default='both')
    common.add_argument('--out', type=Path, default=OUTPUT / 'scenarios')
    common.add_argument('--domain-id', type=int, default=50,
                        help='first ROS domain; trials use the next ones (up to +9)')
    common.add_argument('--no-bag', action='store_true', help='do not record bags')
    common.add_argument('--node-log', action='store_true',
                        help="print the nodes' log lines, prefixed with the node's name "
                        '(not in summary)')
    common.add_argument('-p', '--param', action='append', default=[],
                        metavar='NODE:NAME:=VALUE', help='override one parameter of a node of '
                        'every trial, as in bringup.py (e.g. mpc_controller:balance:=stabilizer)')
    def repeats(default: int) -> argparse.ArgumentParser:
        option = argparse.ArgumentParser(add_help=False)
        option.add_argument('--repeats', type=positive_odd, default=default,
                            help='runs at each limit found and at the setting above it (of a '
                            'push schedule or cell: runs of it), judged by the median (odd; '
                            f'default {default})')
        return option
    sub = parser.add_subparsers(dest='scenario', required=True)
    p = sub.add_parser('disk', parents=[common, repeats(3)], help='walk around a disk')
    p.add_argument('--step-length', type=float, default=0.15)
    p.add_argument('--laps', type=float, default=1.0)
    p.add_argument('--sweep', action='store_true', help='largest step length in 0.08..0.25 m')
    p = sub.add_parser('omni', parents=[common, repeats(3)], help='omnidirectional setpoints')
    p.add_argument('--scale', type=float, default=1.0)
    p.add_argument('--duration', type=float, default=omni.DURATION)
    p.add_argument('--sweep', action='store_true', help='largest command scale in 0.5..1.5')
    p = sub.add_parser('push', parents=[common, repeats(3)], help='pushes while walking in place')
    p.add_argument('--forces', type=float, nargs='+', default=None,
                   help='N, one push each 8 s (default 80, 100, 120, 130, ... up to a fall)')
    p = sub.add_parser('push-directions', parents=[common, repeats(1)],
                       help='pushes from 8 directions at 4 phases, step adjustment off / on')
    p.add_argument('--directions', type=float, nargs='+',
                   default=list(push_directions.DIRECTIONS_DEG), help='deg from +x towards +y')
    p.add_argument('--phases', nargs='+', choices=tuple(push_directions.PHASES),
                   default=list(push_directions.PHASES))
    p.add_argument('--gaits', nargs='+', choices=tuple(push_directions.GAITS),
                   default=list(push_directions.GAITS))
    p.add_argument('--adjustment', nargs='+', choices=('off', 'on'), default=['off', 'on'])
    p.add_argument('--forces', type=float, nargs='+', default=None,
                   help='N, one push per interval until a fall (default 80, 100, ... 320)')
    p.add_argument('--interval', type=float, default=push_directions.INTERVAL,
                   help='s of sim time between pushes')
    p = sub.add_parser('terrain', parents=[common], help='cross uneven tiles')
    p.add_argument('--tile-areas', type=float, nargs='+', default=list(terrain.TILE_AREAS_CM2))
    p.add_argument('--seeds', type=int, nargs='+', default=[1, 2, 3])
    p.add_argument('--side', type=float, default=terrain.SIDE)
    p.add_argument('--stand', type=float, default=0.0,
                   help='s the robot stands on the tiles before it walks (issue: 30)')
    p.add_argument('--heights', type=float, nargs=2, default=list(terrain.HEIGHTS),
                   metavar=('MIN', 'MAX'), help='m, tile heights (the paper: 0.025 0.05; the '
                   'harder set: 0.0 0.05)')
    sub.add_parser('goal', parents=[common], help='START -> GOAL around obstacles')
    p = sub.add_parser('summary', parents=[common, repeats(3)],
                       help='every scenario, both models, table')
    p.add_argument('--seeds', type=int, nargs='+', default=[1, 2, 3])
    p.add_argument('--jobs', type=int, default=1,
                   help='independent parts run side by side, each graph on its own domains')
    p = sub.add_parser('video', parents=[common], help='a GIF of one scenario from the camera')
    p.add_argument('which', choices=('disk', 'omni', 'push', 'push-adjusted', 'terrain'))
    p.add_argument('--fps', type=float, default=12.5)
    return parser


def positive_odd(text: str) -> int:
    value = int(text)  # a ValueError here: argparse's own "invalid positive_odd value"
    try:
        return check_repeats(value)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from error


def models_of(args):
    return MODELS if args.model == 'both' else (args.model,)


def log(line: str) -> None:
    print(line, flush=True)


def trials_for(args, model: str) -> TrialFactory:
    return TrialFactory(args.out, model, args.domain_id, record=not args.no_bag, log=log,
                        overrides=parse_overrides(args.param),
                        node_log=log if getattr(args, 'node_log', False) else None)


def run_scenario(args) -> int:
    results = []
    for model in models_of(args):
        trial = trials_for(args, model)
        if args.scenario == 'disk' and args.sweep:
            best, tried = disk.largest_step_length(trial, args.repeats)
            results.append({'model': model, 'largest_step_length_m': best,
                            'tried': summary.tried_keys(tried), 'success': best is not None})
        elif args.scenario == 'disk':
            results.append(disk.run(trial('disk', f'{args.step_length:.2f}'), args.step_length,
                                    args.laps))
        elif args.scenario == 'omni' and args.sweep:
            best, tried = omni.largest_scale(trial, args.duration, args.repeats)
            results.append({'model': model, 'largest_scale': best,
                            'tried': summary.tried_keys(tried), 'success': best is not None})
        elif args.scenario == 'omni':
            results.append(omni.run(trial('omni', f'{args.scale:.2f}'), args.scale,
                                    args.duration))
        elif args.scenario == 'push':
            pushed = push.repeated(trial, args.forces or push.forces(), args.repeats)
            results.append({'model': model, **pushed, 'success': all(
                r['success'] for r in pushed['runs'])})
        elif args.scenario == 'push-directions':
            cells = [push_directions.median_run([push_directions.run(
                trial('push_directions', run_name(f'{gait}_{phase}_{direction:g}deg_{setting}',
                                                  k)),
                direction, phase, gait, args.forces or push_directions.forces(),
                setting == 'on', args.interval) for k in range(args.repeats)])
                for gait in args.gaits for phase in args.phases
                for direction in args.directions for setting in args.adjustment]
            results.extend(cells)
            for gait in args.gaits:
                print(f'\n{model}, {gait}:\n' + push_directions.table(
                    [c for c in cells if c['gait'] == gait]), flush=True)
        elif args.scenario == 'terrain':
            heights = tuple(args.heights)
            label = '' if heights == terrain.HEIGHTS else \
                f'_{1000 * heights[0]:g}-{1000 * heights[1]:g}mm'
            results.extend(terrain.run(trial('terrain', f'{area:g}cm2_seed{seed}{label}'), area,
                                       seed, side=args.side, stand=args.stand, heights=heights)
                           for area in args.tile_areas for seed in args.seeds)
        elif args.scenario == 'goal':
            results.append(start_goal.run(trial('goal', 'paper_map')))
    print(json.dumps(results, indent=2))
    return 0 if all(r['success'] for r in results) else 1


def run_summary(args) -> int:
    wall0 = time.monotonic()
    args.out.mkdir(parents=True, exist_ok=True)
    per_model = summary.run_models(args.out, MODELS, args.domain_id, args.seeds,
                                   not args.no_bag, log, max(1, args.jobs), args.repeats)
    table = summary.table(per_model['lipm'], per_model['three_mass'])
    table['wall_s'] = round(time.monotonic() - wall0, 1)
    table['jobs'] = max(1, args.jobs)
    table['repeats'] = args.repeats
    table['per_model'] = per_model
    (args.out / 'summary.json').write_text(json.dumps(table, indent=2))
    text = summary.markdown(table) + f'\nMade by `scripts/scenarios.py summary --jobs ' \
        f'{table["jobs"]} --repeats {args.repeats}` in {table["wall_s"] / 60:.0f} min.\n'
    (args.out / 'summary.md').write_text(text)
    print(text)
    return 0


def interrupt_on_sigterm() -> None:
    """SIGTERM as Ctrl-C: the running trial's graph is stopped on the way out (its nodes run in
    sessions of their own and would otherwise walk on, on a domain the next run uses)."""
    def interrupt(*_):
        raise KeyboardInterrupt('SIGTERM')
    signal.signal(signal.SIGTERM, interrupt)


def main(argv=None) -> int:
    interrupt_on_sigterm()
    parser = build_parser()
    args = parser.parse_args(argv)
    last = args.domain_id + summary.UNIT_DOMAINS - 1
    if args.scenario != 'summary' and not 0 <= args.domain_id <= last <= summary.MAX_DOMAIN_ID:
        parser.error(f'--domain-id {args.domain_id}: the trials use domains {args.domain_id}..'
                     f'{last}, which must lie in 0..{summary.MAX_DOMAIN_ID} (Fast DDS ports)')
    try:
        parse_overrides(getattr(args, 'param', []))
    except argparse.ArgumentTypeError as error:
        parser.error(str(error))
    heights = getattr(args, 'heights', terrain.HEIGHTS)
    if not 0.0 <= heights[0] <= heights[1] <= terrain.MAX_HEIGHT:
        parser.error(f'--heights {heights[0]} {heights[1]}: need 0 <= MIN <= MAX <= '
                     f'{terrain.MAX_HEIGHT} m')
    if args.scenario == 'summary' and args.param:
        parser.error('summary does not take -p: its table is measured with the nodes\' '
                     'configured parameters (run a scenario with -p instead)')
    if args.scenario == 'summary':
        return run_summary(args)
    if args.scenario == 'video':
        from biped_tools.scenarios.video import run_video
        return run_video(args, trials_for(args, models_of(args)[-1]))
    return run_scenario(args)

