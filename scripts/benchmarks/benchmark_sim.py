#!/usr/bin/env python3
"""Benchmark of the simulator backend and the leg IK on this machine.

Prints markdown tables: the real-time factor of the physics alone (PyBullet stepping with the
joint controller, no planner or MPC) while the COMAN-like robot stands, per control mode, as the
median of several runs; then per-call timings (median and p99) of the sensor readout, a camera
frame, the analytic IK and the Pinocchio IK (warm and cold started).

Usage: .venv/bin/python scripts/benchmarks/benchmark_sim.py [--runs 5] [--seconds 10]
"""

import argparse
import time

from biped_mpc.leg_ik import AnalyticLegIk
from biped_planner.rotations import rotation_z as yaw_rotation
from biped_mpc.pinocchio_ik import PinocchioLegIk
from biped_sim.camera_view import CameraView
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like
import numpy as np

MODES = (
    ('torque (PD + gravity compensation every step)', {'control_mode': 'torque'}),
    ('torque, gravity compensation every 4 steps',
     {'control_mode': 'torque', 'gravity_compensation_period': 4}),
    ('position (PyBullet motors)', {'control_mode': 'position'}),
)


def _percentiles(samples_us: list) -> tuple:
    samples = np.asarray(samples_us)
    return float(np.median(samples)), float(np.percentile(samples, 99))


def benchmark_physics(description, runs: int, seconds: float) -> list:
    """Return rows (mode, median RTF, min RTF, max RTF, median us per physics step)."""
    rows = []
    for label, kwargs in MODES:
        sim = PyBulletBackend(description, PyBulletConfig(**kwargs))
        q = description.nominal_leg_positions()
        control_steps = int(round(seconds / (sim.time_step * sim.config.control_substeps)))
        factors = []
        for _ in range(runs):
            sim.reset()
            start = time.perf_counter()
            for _ in range(control_steps):
                readings = sim.step(q)
            elapsed = time.perf_counter() - start
            if readings.base.position[2] < 0.45:
                raise RuntimeError('the robot fell during the %s benchmark' % label)
            factors.append(readings.time / elapsed)
        sim.close()
        median = float(np.median(factors))
        physics_steps = control_steps * sim.config.control_substeps
        rows.append((label, median, min(factors), max(factors),
                     seconds / median / physics_steps * 1e6))
    return rows


def benchmark_calls(description, calls: int) -> list:
    """Return rows (what, median us, p99 us)."""
    rows = []
    sim = PyBulletBackend(description)
    sim.reset()
    samples = []
    for _ in range(calls):
        start = time.perf_counter()
        sim.sensors()
        samples.append((time.perf_counter() - start) * 1e6)
    rows.append(('sensors() readout', *_percentiles(samples)))
    samples = []
    for _ in range(max(5, calls // 100)):
        start = time.perf_counter()
        sim.render(CameraView(width=320, height=240))
        samples.append((time.perf_counter() - start) * 1e6)
    rows.append(('camera frame 320x240 (ER_TINY_RENDERER)', *_percentiles(samples)))
    sim.close()

    analytic = AnalyticLegIk(description.leg_geometry)
    numeric = PinocchioLegIk(description.urdf_path, description.leg_joint_names,
                             description.sole_frames)
    # A walking-like sweep: the pelvis sways, the feet swing and the right foot lifts.
    targets = []
    for k in range(calls):
        phase = 2 * np.pi * k / 200
        pelvis = np.array([0.02 * np.cos(phase), 0.03 * np.sin(phase), 0.53])
        left = (np.array([pelvis[0] + 0.05 * np.sin(phase), 0.07, 0.0]), yaw_rotation(0.0))
        right = (np.array([pelvis[0] - 0.05 * np.sin(phase), -0.07,
                           0.03 * max(0.0, np.sin(phase))]),
                 yaw_rotation(0.05 * np.sin(phase)))
        targets.append((pelvis, np.eye(3), left[0], left[1], right[0], right[1]))
    for label, solve, reset in (
            ('analytic IK, both legs', analytic.solve, None),
            ('Pinocchio IK, both legs, warm start', numeric.solve, None),
            ('Pinocchio IK, both legs, cold (bent-knee seed)', numeric.solve,
             numeric.reset_warm_start)):
        samples = []
        for target in targets:
            if reset is not None:
                reset()
            start = time.perf_counter()
            solve(*target)
            samples.append((time.perf_counter() - start) * 1e6)
        rows.append((label, *_percentiles(samples)))
    return rows


def main() -> None:
    """Run the benchmarks and print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--runs', type=int, default=5, help='runs per control mode')
    parser.add_argument('--seconds', type=float, default=10.0, help='simulated seconds a run')
    parser.add_argument('--calls', type=int, default=2000, help='calls per timing')
    args = parser.parse_args()
    description = coman_like()

    print('## Physics alone: COMAN-like robot (23 DOF) standing %.0f s, 1 kHz, %d runs\n'
          % (args.seconds, args.runs))
    print('| control mode | RTF median | RTF min | RTF max | us per physics step |')
    print('|---|---|---|---|---|')
    for label, median, low, high, per_step in benchmark_physics(description, args.runs,
                                                                 args.seconds):
        print('| %s | %.2f | %.2f | %.2f | %.0f |' % (label, median, low, high, per_step))

    print('\n## Per call, %d calls\n' % args.calls)
    print('| what | median (us) | p99 (us) |')
    print('|---|---|---|')
    for label, median, p99 in benchmark_calls(description, args.calls):
        print('| %s | %.1f | %.1f |' % (label, median, p99))


if __name__ == '__main__':
    main()
