#!/usr/bin/env python3
"""Benchmark of the MPC's QP backends over a realistic closed-loop walk on the model plant.

Records the MPC inputs of every cycle of the paper's five-step walk (0.8 m steps of 1 s, with
the paper's measurement noise, the Kalman filter and a 200 N push at 1.6 s) run with the
default backend, then replays them to every backend (each warm-starting from its own previous
solve, u_prev taken from the recording). Per backend: the build time (matrices and solver
set-up), the per-cycle time of the solver calls of both planes and of the whole MPC cycle
(validation, linear term, bounds, both solves), as median / p99 / max over all replayed
cycles, and the largest difference of the applied jerks and the largest relative cost
difference to the exact reference (quadprog). Prints a Markdown table.

Usage: .venv/bin/python scripts/benchmarks/benchmark_mpc.py [--repeats 3]
           [--backends daqp,quadprog]
"""

import argparse
import dataclasses
import sys
import time

from biped_mpc.linear_mpc import LinearMpc, MpcParams
from biped_mpc.lipm_model import LipmParams
from biped_mpc.qp_backends import BACKENDS
from biped_mpc.reference_adapter import outputs_from_window
from biped_mpc.state_estimator import EstimatorParams
from biped_mpc.three_mass_model import three_mass_model, ThreeMassParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference
from biped_sim.external_push import ExternalPush
from biped_sim.model_plant import PlantParams
from biped_sim.model_walk import run_walk, WalkSetup
import numpy as np

REFERENCE_BACKEND = 'quadprog'


def record_cycles(params: MpcParams) -> list:
    """MPC inputs (estimate, references, bounds, previous jerks) of a closed-loop walk."""
    reference = WalkingReference(
        straight_footsteps(5, 0.8, 0.2), StepTiming(0.8, 0.2),
        ReferenceParams(com_height=LipmParams.from_three_mass(ThreeMassParams()).com_height,
                        foot_length=0.1, foot_width=0.08))
    model = three_mass_model()
    setup = WalkSetup(controller_model=model, plant_model=model, mpc=params,
                      plant=PlantParams.paper_noise(0), estimator=EstimatorParams(),
                      push=ExternalPush((200.0, 0.0, 0.0), duration=0.1, start_time=1.6),
                      polygon_margin=(0.005, 0.004))
    log = run_walk(reference, setup)
    cycles = []
    previous = np.zeros((2, 3))
    for k, t in enumerate(log.t):
        window = reference.sample(float(t) + params.dt, params.n_predict, params.dt)
        y_ref, y_min, y_max = outputs_from_window(window)
        cycles.append((log.estimate[k], y_ref, y_min, y_max, previous))
        previous = log.jerk[k]
    return cycles


def replay(backend: str, params: MpcParams, cycles: list, repeats: int) -> dict:
    start = time.perf_counter()
    mpc = LinearMpc(three_mass_model(), dataclasses.replace(params, backend=backend))
    build = time.perf_counter() - start
    solver, total, jerks, costs, failures = [], [], [], [], 0
    for repeat in range(repeats):
        mpc.reset()
        for cycle in cycles:
            start = time.perf_counter()
            result = mpc.solve(*cycle)
            total.append(time.perf_counter() - start)
            solver.append(result.solve_time)
            if repeat == 0:
                jerks.append(result.jerk)
                costs.append(result.cost)
                failures += sum(1 for s in result.status if s != 0)
    return {'build': build, 'solver': np.array(solver) * 1e6, 'total': np.array(total) * 1e6,
            'jerks': np.array(jerks), 'costs': np.array(costs), 'failures': failures}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--repeats', type=int, default=3, help='replays of the walk per backend')
    parser.add_argument('--backends', default=','.join(BACKENDS),
                        help='comma-separated backends (quadprog is always run)')
    parser.add_argument('--constraint-horizon', type=int, default=MpcParams().constraint_horizon)
    parser.add_argument('--blocking', default=MpcParams().move_blocking,
                        choices=('spread', 'hold'))
    args = parser.parse_args()
    params = MpcParams(constraint_horizon=args.constraint_horizon,
                       move_blocking=args.blocking)
    cycles = record_cycles(params)
    backends = [REFERENCE_BACKEND] + [b for b in args.backends.split(',')
                                      if b and b != REFERENCE_BACKEND]
    results = {}
    for backend in backends:
        results[backend] = replay(backend, params, cycles, args.repeats)
        print(f'{backend}: done', file=sys.stderr, flush=True)
    reference = results[REFERENCE_BACKEND]
    rows = LinearMpc(three_mass_model(), params).n_rows
    print(f'\nMPC per control cycle, both planes (x and y), {len(cycles)} cycles x '
          f'{args.repeats} replays of the paper walk with noise and a 200 N push; '
          f'Np={params.n_predict}, Nc={params.n_control} ({params.move_blocking} blocking), '
          f'{rows} constraint rows per plane (constraint horizon {params.constraint_horizon}).'
          f'\nTimes in microseconds (median / p99 / max); differences to {REFERENCE_BACKEND} '
          f'on the first replay.\n')
    print('| backend | build (ms) | solver calls | whole MPC cycle | failed plane-solves | '
          'max jerk difference (m/s^3) | max relative cost difference |')
    print('|---|---|---|---|---|---|---|')
    for backend, result in results.items():
        def stats(samples):
            return (f'{np.median(samples):.0f} / {np.percentile(samples, 99):.0f} / '
                    f'{samples.max():.0f}')
        both = np.isfinite(result['costs']) & np.isfinite(reference['costs'])
        jerk_difference = np.abs(result['jerks'] - reference['jerks']).max()
        cost_difference = (np.abs(result['costs'] - reference['costs'])[both]
                           / np.maximum(np.abs(reference['costs'][both]), 1e-12)).max()
        print(f'| {backend} | {result["build"] * 1e3:.1f} | {stats(result["solver"])} | '
              f'{stats(result["total"])} | {result["failures"]} | {jerk_difference:.2e} | '
              f'{cost_difference:.2e} |')
    print('\n"unconstrained" ignores every constraint: a lower bound of the time, not a '
          'solver of this QP.')


if __name__ == '__main__':
    main()
