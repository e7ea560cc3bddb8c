#!/usr/bin/env python3
"""Benchmark of the online step adjuster's cost per control cycle.

Records what the adjuster is given at every cycle of a PyBullet push trial (walking in place,
0.3 / 0.1 s steps, a 190 N lateral push early in a single support, adjustment on: the trial of
biped_sim.push_trial), then replays those inputs to a fresh adjuster `--repeats` times and times
each cycle: the measured DCM (biped_mpc.balance.measured_dcm) and the adjuster's update (QP,
and the replan of the reference when it triggers). Prints the median, p99 and max per cycle,
over all cycles and split into cycles with and without a replan, as a Markdown table.

Usage: .venv/bin/python scripts/benchmarks/benchmark_step_adjuster.py [--repeats 20]
           [--force 190] [--direction 90] [--phase early_single]
"""
import argparse
from dataclasses import replace
import math
import time

from biped_mpc.balance.measured_dcm import MeasuredDcm
from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.step_adjuster import OnlineStepAdjuster
from biped_sim import push_trial
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.reference_sources import AdjustedWalk
from biped_sim.robot_description import coman_like
import numpy as np


def record(force: float, direction: float, phase: str) -> list:
    """(t, leg joints, pelvis position, pelvis orientation) of every cycle of a push trial."""
    robot = coman_like()
    backend = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
    inputs = []
    original = MeasuredDcm.update

    def recording(self, t, q, position, orientation):
        inputs.append((t, np.array(q), np.array(position), np.array(orientation)))
        return original(self, t, q, position, orientation)

    MeasuredDcm.update = recording
    try:
        result = push_trial.run_push_trial(
            backend, WalkingController(WalkingControllerParams(robot=robot.controller_model)),
            robot.controller_model, force, math.radians(direction), phase,
            push_trial.HUMANOID_ADJUSTER)
    finally:
        MeasuredDcm.update = original
        backend.close()
    print(f'recorded {len(inputs)} cycles: {force:g} N at {direction:g} deg, {phase}, '
          f'{"fell" if result.fallen else "stood"}, {result.revisions} replans')
    return inputs


def replay(inputs: list, repeats: int):
    """Per-cycle times (s) of measured DCM + update, and which cycles replanned."""
    robot = coman_like().controller_model
    qp = replace(push_trial.HUMANOID_STEP_LIMITS, com_height=push_trial.REFERENCE.com_height)
    times, replanned = [], []
    for _ in range(repeats):
        measured = MeasuredDcm(robot)
        source = AdjustedWalk(push_trial.walk_in_place_reference(),
                              OnlineStepAdjuster(push_trial.HUMANOID_ADJUSTER, qp))
        for t, q, position, orientation in inputs:
            begin = time.perf_counter()
            com, dcm = measured.update(t, q, position, orientation)
            output = source.adjust(t, com, dcm)
            times.append(time.perf_counter() - begin)
            replanned.append(output.applied)
    return np.array(times), np.array(replanned)


def row(name: str, values: np.ndarray) -> str:
    if values.size == 0:
        return f'| {name} | 0 | - | - | - |'
    median, p99, top = np.percentile(values * 1e3, [50, 99, 100])
    return f'| {name} | {values.size} | {median:.3f} | {p99:.3f} | {top:.3f} |'


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--repeats', type=int, default=20)
    parser.add_argument('--force', type=float, default=190.0)
    parser.add_argument('--direction', type=float, default=90.0, help='deg from +x')
    parser.add_argument('--phase', default='early_single', choices=tuple(push_trial.PHASES))
    args = parser.parse_args()
    inputs = record(args.force, args.direction, args.phase)
    times, replanned = replay(inputs, args.repeats)
    print()
    print('| cycles | n | median (ms) | p99 (ms) | max (ms) |')
    print('|---|---|---|---|---|')
    print(row('all', times))
    print(row('without replan', times[~replanned]))
    print(row('with replan', times[replanned]))


if __name__ == '__main__':
    main()
