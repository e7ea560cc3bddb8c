#!/usr/bin/env python3
"""Benchmark of the dynamic planner: A*, footsteps and references per control cycle.

Prints a table of medians and 99th percentiles (wall time, this machine). Targets: A* on the
20 x 20 m map at 0.05 m (160,000 cells) <= 50 ms; references for one control cycle (80 samples)
<= 0.2 ms. Usage: scripts/benchmarks/benchmark_planner.py [--repeats 50] [--cycles 5000]
"""
import argparse
import math
import time
from typing import Callable, List

from biped_planner.astar import AStarPlanner
from biped_planner.example_maps import benchmark_map, paper_start_goal_example
from biped_planner.footstep_planner import FootstepPlanner
from biped_planner.footsteps import Footstep, straight_footsteps
from biped_planner.omnidirectional_stepper import (OmnidirectionalStepper,
                                                   StepCommand)
from biped_planner.pose2d import Pose2D
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import WalkingReference
import numpy as np


def _times(function: Callable[[], object], repeats: int) -> List[float]:
    samples = []
    for _ in range(repeats):
        begin = time.perf_counter()
        function()
        samples.append(time.perf_counter() - begin)
    return samples


def _row(name: str, samples: List[float], unit: str, target: str = '') -> str:
    scale = {'ms': 1e3, 'us': 1e6}[unit]
    values = np.array(samples) * scale
    return (f'| {name:<52} | {len(values):>6} | {np.median(values):>9.3f} | '
            f'{np.percentile(values, 99):>9.3f} | {unit:<4} | {target:<8} |')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=50, help='repetitions of each plan')
    parser.add_argument('--cycles', type=int, default=5000, help='control cycles sampled')
    args = parser.parse_args()
    rows = []

    small, start, goal = paper_start_goal_example()
    rows.append(_row('A* precompute, 4 x 4 m at 0.1 m (1,600 cells)',
                     _times(lambda: AStarPlanner(small), args.repeats), 'ms'))
    astar_small = AStarPlanner(small)
    rows.append(_row('A* query, 4 x 4 m at 0.1 m',
                     _times(lambda: astar_small.plan((start.x, start.y), (goal.x, goal.y)),
                            args.repeats), 'ms'))
    plain_small = AStarPlanner(small, method='plain')
    rows.append(_row('A* query, 4 x 4 m at 0.1 m, plain (cell by cell)',
                     _times(lambda: plain_small.plan((start.x, start.y), (goal.x, goal.y)),
                            args.repeats), 'ms'))

    large, large_start, large_goal = benchmark_map()
    rows.append(_row('A* precompute, 20 x 20 m at 0.05 m (160,000 cells)',
                     _times(lambda: AStarPlanner(large), max(3, args.repeats // 10)), 'ms'))
    astar_large = AStarPlanner(large)
    ends = ((large_start.x, large_start.y), (large_goal.x, large_goal.y))
    rows.append(_row('A* query, 20 x 20 m at 0.05 m', _times(lambda: astar_large.plan(*ends),
                                                               args.repeats), 'ms', '<= 50'))
    plain_large = AStarPlanner(large, method='plain')
    rows.append(_row('A* query, 20 x 20 m at 0.05 m, plain (cell by cell)',
                     _times(lambda: plain_large.plan(*ends), 3), 'ms'))

    planner = FootstepPlanner()
    rows.append(_row('A* + footsteps, paper START-GOAL map',
                     _times(lambda: planner.plan_on_map(astar_small, start, goal),
                            args.repeats), 'ms'))
    plan = planner.plan_on_map(astar_small, start, goal)
    timing = StepTiming(0.4, 0.1)
    rows.append(_row(f'WalkingReference build, {len(plan.footsteps) - 2} steps',
                     _times(lambda: WalkingReference(plan.footsteps, timing), args.repeats),
                     'ms'))
    reference = WalkingReference(plan.footsteps, timing)
    times = np.linspace(0.0, reference.duration, args.cycles)
    cycle = iter(times.tolist() * 2)
    rows.append(_row('references for one control cycle (80 samples, Ts 0.02)',
                     _times(lambda: reference.sample(next(cycle), 80, 0.02), args.cycles),
                     'us', '<= 200'))

    stepper = OmnidirectionalStepper(Pose2D(0.0, 0.0, 0.0))
    command = StepCommand(0.1, 0.05, math.radians(7.5))
    rows.append(_row('omnidirectional next_footstep (teleop, per step)',
                     _times(lambda: stepper.next_footstep(command, 0.5), args.repeats * 20),
                     'us'))
    walk = WalkingReference(straight_footsteps(20, 0.1, 0.2), timing)
    last, before = walk.footsteps[-1], walk.footsteps[-2]
    more = [Footstep(before.side, last.x + 0.1, before.y), Footstep(last.side, last.x + 0.1,
                                                                    last.y)]
    rows.append(_row('WalkingReference.extend by one step (teleop), 20-step plan',
                     _times(lambda: walk.extend(more, 3.0), args.repeats), 'ms'))

    print('| benchmark' + ' ' * 44 + '|   runs |    median |       p99 | unit | target   |')
    print('|' + '-' * 54 + '|--------|-----------|-----------|------|----------|')
    for row in rows:
        print(row)


if __name__ == '__main__':
    main()
