#!/usr/bin/env python3
"""Benchmark of the closed loop on this machine: references + MPC + IK + physics, headless.

Prints Markdown tables:

1. the real-time factor (simulated time / wall time) of the PyBullet simulator alone (the
   robot standing on its nominal setpoints, torque control, physics and joint servo only)
   and of the full closed loop (ClosedLoopRunner: reference window, walking controller,
   physics) walking 20 steps of 0.1 m, on PyBullet and on the model plant, as the median,
   min and max over several runs;
2. the per-cycle wall time split of the PyBullet closed loop (reference window, controller,
   physics with sensing), median and p99 in microseconds, with the QP solve time inside the
   controller.

Usage: .venv/bin/python scripts/benchmarks/benchmark_closed_loop.py [--runs 3]
"""

import argparse
import time

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.walking_reference import WalkingReference
from biped_sim.closed_loop import ClosedLoopParams, ClosedLoopRunner
from biped_sim.model_plant_backend import ModelPlantBackend
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like
import numpy as np

from biped_tools.closed_loop_walk import LEG_KP, REFERENCE, STEP_WIDTH, T_START, TIMING


def simulator_alone(sim, description, seconds: float) -> float:
    """Real-time factor of standing: physics and joint servo, no controller."""
    sim.reset()
    q = description.nominal_leg_positions()
    cycles = int(round(seconds / 0.02))
    start = time.perf_counter()
    for _ in range(cycles):
        sim.step(q)
    return cycles * 0.02 / (time.perf_counter() - start)


def closed_loop(sim, controller, reference, seconds: float, params=ClosedLoopParams()) -> tuple:
    """Real-time factor of the closed loop and its log."""
    runner = ClosedLoopRunner(sim, controller, reference, params=params)
    runner.reset()
    start = time.perf_counter()
    log = runner.run(seconds)
    wall = time.perf_counter() - start
    return log.t.size * 0.02 / wall, log


def _row(label: str, values: list) -> str:
    values = np.asarray(values)
    return (f'| {label} | {np.median(values):.2f} | {values.min():.2f} | {values.max():.2f} |')


def _split_row(label: str, seconds: np.ndarray) -> str:
    micro = 1e6 * np.asarray(seconds)
    return f'| {label} | {np.median(micro):.0f} | {np.percentile(micro, 99):.0f} |'


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--runs', type=int, default=3, help='runs per measurement')
    parser.add_argument('--stand-seconds', type=float, default=5.0,
                        help='simulated time of the simulator-alone run')
    args = parser.parse_args()
    description = coman_like()
    footsteps = straight_footsteps(20, 0.1, STEP_WIDTH)
    reference = WalkingReference(footsteps, TIMING, REFERENCE, t_start=T_START)
    duration = reference.t_end + 0.5
    sim = PyBulletBackend(description, PyBulletConfig(leg_kp=LEG_KP))
    controller = WalkingController(WalkingControllerParams(robot=description.controller_model))
    plant = ModelPlantBackend(description)
    plant_controller = WalkingController(WalkingControllerParams(
        robot=description.controller_model, pelvis_velocity_gain=0.0, tilt_gain=0.0))
    alone, loop, model_loop, logs = [], [], [], []
    for _ in range(args.runs):
        alone.append(simulator_alone(sim, description, args.stand_seconds))
        factor, log = closed_loop(sim, controller, reference, duration)
        loop.append(factor)
        logs.append(log)
        model_loop.append(closed_loop(plant, plant_controller, reference, duration,
                                      ClosedLoopParams(setpoint_interpolation=1))[0])
    sim.close()
    fallen = sum(log.fallen for log in logs)
    print(f'Real-time factor, {args.runs} runs (walk: 20 steps of 0.1 m, '
          f'{duration:.1f} s simulated; {fallen} falls)\n')
    print('| run | median | min | max |')
    print('|---|---|---|---|')
    print(_row('PyBullet alone, standing (torque mode, 1 kHz)', alone))
    print(_row('closed loop on PyBullet (references + MPC + IK + physics)', loop))
    print(_row('closed loop on the model plant', model_loop))
    log = logs[int(np.argsort(loop)[len(loop) // 2])]
    total = log.time_references + log.time_controller + log.time_physics
    print(f'\nPer-cycle wall time of the PyBullet closed loop (median run, {log.t.size} '
          f'cycles of 20 ms), microseconds\n')
    print('| part | median | p99 |')
    print('|---|---|---|')
    print(_split_row('reference window (WalkingReference.sample, 81 samples)',
                     log.time_references))
    print(_split_row('walking controller (estimator + MPC + IK)', log.time_controller))
    print(_split_row('  of which QP solves, both planes', log.solve_time))
    print(_split_row('physics (20 steps of 1 ms) and sensors', log.time_physics))
    print(_split_row('whole cycle', total))


if __name__ == '__main__':
    main()
