#!/usr/bin/env python3
"""Benchmark of the stabilizer's cost per control cycle, on this machine.

Walks 20 steps of 0.1 m on flat ground in the PyBullet closed loop (biped_sim.terrain_trial's
references) with each model and balance mode, and times every cycle:

- sense: the balance loop's F/T filtering, touchdown detection and measured ZMP;
- update: the Stabilizer (DCM feedback, wrench distribution QP, foot damping, force difference,
  vertical drift) and the contact-aware landing on the IK targets;
- controller: the whole WalkingController.step (estimator, MPC, stabilizer, IK).

Prints a Markdown table, median and p99 in microseconds, with the control period (20 ms) as
the budget; then where the three-mass stabilizer's update goes: its modules' time per cycle.

Usage: .venv/bin/python scripts/benchmarks/benchmark_stabilizer.py [--steps 20]
"""
import argparse
import time

import numpy as np

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.walking_reference import WalkingReference
from biped_sim.closed_loop import ClosedLoopRunner
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like
from biped_sim.terrain_trial import REFERENCE, STEP_WIDTH, T_START, TIMING


class _Timed:
    """Wraps a bound method and records the wall time of each call (s)."""

    def __init__(self, method) -> None:
        self._method = method
        self.times = []

    def __call__(self, *args, **kwargs):
        start = time.perf_counter()
        result = self._method(*args, **kwargs)
        self.times.append(time.perf_counter() - start)
        return result


def _cells(seconds: list) -> str:
    if not seconds:
        return '- | -'
    micro = 1e6 * np.asarray(seconds)
    return f'{np.median(micro):.0f} | {np.percentile(micro, 99):.0f}'


def _timed_modules(loop) -> dict:
    """Wrap the stabilizer's modules of a balance loop: {name: [_Timed, ...]}."""
    stabilizer = loop.stabilizer
    owners = {'wrench distribution (QP)': [stabilizer.distributor],
              'DCM feedback and its clamp to the support': [stabilizer.dcm_feedback],
              'foot damping, both feet': list(stabilizer.damping),
              'foot force difference': [stabilizer.force_difference],
              'ground conformance': [loop.conformance]}
    modules = {}
    for name, objects in owners.items():
        modules[name] = []
        for owner in objects:
            timed = _Timed(owner.update)
            owner.update = timed
            modules[name].append(timed)
    return modules


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--steps', type=int, default=20, help='steps of 0.1 m')
    args = parser.parse_args()
    robot = coman_like()
    backend = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
    print('| model | balance | sense median (us) | sense p99 (us) | update median (us) | '
          'update p99 (us) | controller median (us) | controller p99 (us) | fell |')
    print('|---|---|---|---|---|---|---|---|---|')
    modules, cycles = {}, 0
    for model in ('three_mass', 'lipm'):
        for balance in ('stabilizer', 'open_loop'):
            controller = WalkingController(WalkingControllerParams(
                robot=robot.controller_model, model=model, balance=balance))
            loop = controller.balance_loop
            sense = update = None
            if loop is not None:
                sense, update = _Timed(loop.sense), _Timed(loop.update)
                loop.sense, loop.update = sense, update
                if model == 'three_mass':
                    modules = _timed_modules(loop)
            step = _Timed(controller.step)
            controller.step = step
            reference = WalkingReference(straight_footsteps(args.steps, 0.1, STEP_WIDTH),
                                         TIMING, REFERENCE, t_start=T_START)
            backend.clear_scenery()
            runner = ClosedLoopRunner(backend, controller, reference)
            runner.reset()
            log = runner.run(reference.t_end + 0.5)
            print(f'| {model} | {balance} | {_cells(sense.times if sense else [])} | '
                  f'{_cells(update.times if update else [])} | {_cells(step.times)} | '
                  f'{"yes" if log.fallen else "no"} |', flush=True)
            if model == 'three_mass' and balance == 'stabilizer':
                cycles = len(step.times)
    backend.close()
    print('\nthree_mass, stabilizer: time per control cycle (us, mean over the walk)\n')
    print('| part | per cycle |')
    print('|---|---|')
    for name, timers in modules.items():
        total = sum(sum(timer.times) for timer in timers)
        print(f'| {name} | {1e6 * total / max(cycles, 1):.0f} |')


if __name__ == '__main__':
    main()
