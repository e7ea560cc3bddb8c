"""The main job: the humanoid walks from START to GOAL around obstacles, through the node graph.

Brings up the whole graph headless in lockstep (simulator, map server, state machine, A*/footstep
planner, reference generator, MPC controller) with the paper's START -> GOAL map served from its
nav2 map file (biped_planner's maps/paper_start_goal.yaml), sends the goal as a user would
(goal_pose), records a rosbag2 of the run, and writes plots (map, A* path, footsteps, COM; ZMP
against the support polygon) and summary.json to output/demo/.
"""
import argparse
import json
from pathlib import Path
import sys

from biped_tools.paths import OUTPUT
from biped_tools.scenarios.start_goal import arrived, walk_start_to_goal


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--out', type=Path, default=OUTPUT / 'demo')
    parser.add_argument('--domain-id', type=int, default=42)
    parser.add_argument('--model', choices=['three_mass', 'lipm'], default='three_mass')
    parser.add_argument('--timeout', type=float, default=300.0,
                        help='wall seconds to wait for the walk to end')
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    try:
        summary = walk_start_to_goal(args.out, args.domain_id, args.model, args.timeout)
    except (RuntimeError, TimeoutError) as error:
        print(f'[demo] error: {error}', file=sys.stderr)
        return 1
    print(json.dumps(summary, indent=2))
    print(f'[demo] plots and summary in {args.out}')
    return 0 if arrived(summary) else 1

