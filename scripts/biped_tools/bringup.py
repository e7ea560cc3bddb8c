"""Bring up the biped node graph: one process per node (or groups composed in one process).

Starts each selected node with its parameter file, waits until every node is on the ROS graph,
forwards their logs with a [node] prefix, and stops the whole graph (SIGINT, wait, SIGKILL) on
Ctrl-C / SIGTERM, or as soon as one node dies, naming it.

The map_server node serves the map the planner and the simulator use, latched on `map`: the
file given with --map (nav2 map_server format: a YAML file naming a PGM/PNG image, with
resolution, origin, occupied_thresh, free_thresh, negate, mode), or else an empty map around
the robot's start (so a goal_pose can be sent at once). A map file that cannot be used stops
map_server at start with an error naming the file and field, and with it the graph.

With the simulator among the nodes every node follows its /clock (use_sim_time): the
simulator makes the time, and a node on the wall clock would stamp its messages decades ahead of
the sensors. Without it (a robot's own driver, or the workstation side of a simulated robot on
another host) the nodes keep the wall clock unless --sim-time is given.

  .venv/bin/python scripts/bringup.py                      # every node, headless
  .venv/bin/python scripts/bringup.py --map FILE.yaml -p simulator:start_x:=0.5
  .venv/bin/python scripts/bringup.py --nodes state_machine --domain-id 7
  .venv/bin/python scripts/bringup.py --gui -p simulator:lockstep:=false
  .venv/bin/python scripts/bringup.py --compose control    # control path in one process
  .venv/bin/python scripts/bringup.py --compose all        # every node in one process
  .venv/bin/python scripts/bringup.py --compose simulator,mpc_controller \
      --compose map_server,state_machine
"""
import argparse
from pathlib import Path
import sys
from typing import Dict, List

from biped_tools.node_graph import (available_nodes, CONTROL_PATH, GraphOptions, KNOWN_NODES,
                                    NodeGraph)
from biped_tools.stop_signal import stop_on_signals


def parse_overrides(values: List[str]) -> Dict[str, List[str]]:
    overrides: Dict[str, List[str]] = {}
    for value in values:
        node, sep, assignment = value.partition(':')
        if not sep or ':=' not in assignment:
            raise argparse.ArgumentTypeError(f'-p {value!r}: expected node:param:=value')
        overrides.setdefault(node, []).append(assignment)
    return overrides


def parse_params_files(values: List[str]) -> Dict[str, Path]:
    files = {}
    for value in values:
        node, sep, path = value.partition('=')
        if not sep:
            raise argparse.ArgumentTypeError(f'--params-file {value!r}: expected node=path')
        files[node] = Path(path).resolve()
    return files


def parse_compose(values: List[str], nodes: List[str]) -> List[List[str]]:
    """--compose values: 'control' (the control path), 'all', or node names joined by commas."""
    groups = []
    for value in values:
        if value == 'control':
            groups.append([n for n in CONTROL_PATH if n in nodes])
        elif value == 'all':
            groups.append(list(nodes))
        else:
            groups.append([n for n in value.split(',') if n])
    return [g for g in groups if g]


def follows_sim_time(args: argparse.Namespace, nodes: List[str]) -> bool:
    """Whether the nodes follow /clock: asked for, or the simulator makes it here (beside it
    the wall clock has no use: the sensors are stamped with the simulator's time)."""
    return args.sim_time or 'simulator' in nodes


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--nodes', nargs='+', default=None,
                        help=f'nodes to start (default: all installed of {list(KNOWN_NODES)})')
    parser.add_argument('--params-file', action='append', default=[], metavar='NODE=PATH',
                        help='replace a node\'s default parameter file')
    parser.add_argument('-p', '--param', action='append', default=[],
                        metavar='NODE:NAME:=VALUE', help='override one parameter of a node')
    parser.add_argument('--domain-id', type=int, default=None, help='ROS_DOMAIN_ID (0-101)')
    parser.add_argument('--backend', choices=['pybullet', 'model'], default='pybullet',
                        help='simulator backend')
    parser.add_argument('--gui', action='store_true', help='open the simulator window')
    parser.add_argument('--sim-time', action='store_true',
                        help='every node follows the simulator\'s /clock (always when the '
                             'simulator is among the nodes)')
    parser.add_argument('--map', type=Path, default=None, metavar='FILE.yaml',
                        help='map for map_server, in the nav2 map_server format (YAML + '
                             'PGM/PNG); default: an empty map around the start pose')
    parser.add_argument('--keep-going', action='store_true',
                        help='when a node dies, keep the others running')
    parser.add_argument('--compose', action='append', default=[], metavar='GROUP',
                        help='run a group of nodes in one process on one executor: '
                             '"control" (simulator, reference_generator, mpc_controller), '
                             '"all", or node names joined by commas; repeatable')
    parser.add_argument('--timeout', type=float, default=30.0,
                        help='seconds to wait for all nodes to come up')
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    if args.domain_id is not None and not 0 <= args.domain_id <= 101:
        print(f'[bringup] error: --domain-id {args.domain_id} outside [0, 101]', file=sys.stderr)
        return 2
    nodes = args.nodes or available_nodes()
    if args.map is not None:
        if not args.map.is_file():
            print(f'[bringup] error: --map {args.map}: no such file', file=sys.stderr)
            return 2
        if 'map_server' not in nodes:
            print('[bringup] error: --map needs the map_server node', file=sys.stderr)
            return 2
    options = GraphOptions(nodes=nodes, params_files=parse_params_files(args.params_file),
                           overrides=parse_overrides(args.param), domain_id=args.domain_id,
                           backend=args.backend, gui=args.gui,
                           use_sim_time=follows_sim_time(args, nodes),
                           keep_going=args.keep_going,
                           map_file=args.map.resolve() if args.map else None,
                           compose=parse_compose(args.compose, nodes))
    print('[bringup] clock: ' + ("the simulator's /clock (use_sim_time)" if options.use_sim_time
                                  else 'the wall clock'), flush=True)
    stop = stop_on_signals()
    try:
        graph = NodeGraph(options)
    except (ValueError, FileNotFoundError) as error:
        print(f'[bringup] error: {error}', file=sys.stderr)
        return 2
    graph.start()
    status = 0
    try:
        graph.wait_until_up(args.timeout, abort=stop)
        while not stop.is_set():
            graph.check_alive()
            stop.wait(0.1)
        print('[bringup] shutting down')
    except (RuntimeError, TimeoutError) as error:
        print(f'[bringup] error: {error}', file=sys.stderr)
        status = 1
    finally:
        graph.stop()
    return status

