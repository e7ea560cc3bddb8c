"""Probe of the paper's COMAN scenarios in the library closed loop (no ROS), both controllers.

Investigation for issue 7 (the paper's table tb:summary): push recovery while walking in place,
walking around a disk, omnidirectional walking with a command scale factor. The scenarios'
geometry, commands and success tests are those of biped_tools.scenarios (the node-graph runs);
here they drive ClosedLoopRunner directly. Each trial is a fresh reset of one PyBullet backend;
one simulation at a time.

Usage: .venv/bin/python scripts/experiments/scenario_probe.py [push] [omni] [disk]
           [--models three_mass,lipm]
(no part: all three, in the order push, omni, disk)
"""
import argparse
from dataclasses import replace
import math
import sys
import time

from biped_mpc.mpc_params import LEG_OUTPUTS
from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.omnidirectional_stepper import (OmnidirectionalStepper, StepCommand,
                                                   StepperParams)
from biped_planner.pose2d import Pose2D
from biped_planner.rotations import quaternion_to_matrix, roll_pitch_of_matrix
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import WalkingReference
from biped_sim.closed_loop import ClosedLoopRunner
from biped_sim.reference_sources import CommandedWalk
from biped_sim.external_push import ExternalPush
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like
import numpy as np

from biped_tools import closed_loop_walk
from biped_tools.closed_loop_walk import STEP_WIDTH, T_START
from biped_tools.scenarios import disk, omni, push
from biped_tools.scenarios.summary import PAPER as PAPER_TABLE

REFERENCE = closed_loop_walk.REFERENCE
PAPER_TIMING = StepTiming(*push.TIMING)    # 0.4 s step, as in the paper
WORKING_TIMING = closed_loop_walk.TIMING   # the timing the tests walk with
UNITS = {'push': ' N', 'omni': '', 'disk': ' m'}
# the paper's (proposed / LIPM) of each part
PAPER = {part: f'{PAPER_TABLE[part][1]:g} / {PAPER_TABLE[part][0]:g}{unit}'
         for part, unit in UNITS.items()}

ROBOT = coman_like()
LEG_KP = closed_loop_walk.LEG_KP
FRESH = False
BACKEND = None
LEG_OUTPUTS_CHOICE = None   # None: the walking controller's default


def backend():
    """The shared backend, or a new one per trial with --fresh-backend (PyBullet keeps some
    state across resets: a trial's first run in a process differs slightly from later ones)."""
    global BACKEND
    if FRESH and BACKEND is not None:
        BACKEND.close()
        BACKEND = None
    if BACKEND is None:
        BACKEND = PyBulletBackend(ROBOT, PyBulletConfig(leg_kp=LEG_KP))
    return BACKEND


def controller(model):
    params = WalkingControllerParams(robot=ROBOT.controller_model, model=model)
    if LEG_OUTPUTS_CHOICE is not None:
        params = replace(params, mpc=replace(params.mpc, leg_outputs=LEG_OUTPUTS_CHOICE))
    return WalkingController(params)


def stepper_params():
    return StepperParams(step_width=STEP_WIDTH, max_step_length=0.3, max_step_width=0.1,
                         max_step_angle=math.radians(30.0))


def commanded_runner(model, timing, command):
    source = CommandedWalk(OmnidirectionalStepper(Pose2D(0.0, 0.0, 0.0), stepper_params()),
                           timing, REFERENCE, command, WalkingReference, steps_ahead=2,
                           t_start=T_START)
    runner = ClosedLoopRunner(backend(), controller(model), source)
    runner.reset()
    return runner, source


def diagnose(log, window=1.5):
    """Why a run fell: tilt axis, ZMP and QP/IK trouble over the last `window` s."""
    if log.t.size == 0:
        return ''
    last = log.t >= log.t[-1] - window
    roll, pitch = map(math.degrees,
                      roll_pitch_of_matrix(quaternion_to_matrix(log.base_orientation[-1])))
    single = last & (log.support != 2)
    inside = log.zmp_inside_support()[single].mean() if single.any() else math.nan
    clipped = np.mean((log.controller_status[last] & 8) != 0)
    fallback = np.mean((log.controller_status[last] & 3) != 0)
    early = log.t < log.t[-1] - window
    inside_before = log.zmp_inside_support()[early & (log.support != 2)].mean() \
        if (early & (log.support != 2)).any() else math.nan
    return (f'[end roll {roll:+.0f} pitch {pitch:+.0f} deg; ZMP in stance foot {inside:.0%} of '
            f'single support in the last {window} s (before: {inside_before:.0%}); IK clipped '
            f'{clipped:.0%}, MPC fallback/error {fallback:.0%}]')


# ----------------------------------------------------------------------------- push recovery
def walk_in_place(model, timing, duration, push=None):
    step_time = timing.single_support + timing.double_support
    n_steps = int(math.ceil((duration - T_START) / step_time)) + 2
    reference = WalkingReference(straight_footsteps(n_steps, 0.0, STEP_WIDTH), timing,
                                 REFERENCE, t_start=T_START)
    runner = ClosedLoopRunner(backend(), controller(model), reference)
    runner.reset()
    if push is not None:
        runner.push(push)
    return runner.run(duration)


def push_time(log, after=2.0):
    """Start of a single support after `after` s, plus a quarter of it."""
    single = (log.support != 2).astype(int)
    starts = np.flatnonzero(np.diff(single) == 1) + 1
    starts = starts[log.t[starts] >= after]
    return float(log.t[starts[0]])


def push_part(model, timing=PAPER_TIMING):
    calm = walk_in_place(model, timing, 6.0)
    note = f'{timing.single_support}/{timing.double_support}'
    if calm.fallen:
        note = f'0.3/0.1 falls in place at {calm.fall_time:.2f} s; used 0.4/0.2'
        timing = WORKING_TIMING
        calm = walk_in_place(model, timing, 6.0)
        if calm.fallen:
            return None, f'falls walking in place at 0.4/0.2 too ({calm.fall_time:.2f} s)'
    # the paper's push: a quarter into a single support, push.DURATION long
    t_push = push_time(calm) + push.PUSH_FRACTION * timing.single_support
    duration = t_push + push.DURATION + 3.0

    def survives(force):
        log = walk_in_place(model, timing, duration,
                            ExternalPush(force=(force, 0.0, 0.0), duration=push.DURATION,
                                         start_time=t_push))
        outcome = f'FELL at {log.fall_time:.2f} s' if log.fallen else 'ok'
        print(f'  push {model} {force:6.1f} N: {outcome}'
              f' (max tilt {math.degrees(log.tilt.max()):.1f} deg)', flush=True)
        return not log.fallen

    low, high = 0.0, 300.0
    if survives(high):
        return high, note + ', withstood the upper bound'
    while high - low > 5.0:
        middle = 0.5 * (low + high)
        if survives(middle):
            low = middle
        else:
            high = middle
    return low, note + f', push at t={t_push:.2f} s'


# ----------------------------------------------------------------------------- omnidirectional
def omni_run(model, timing, scale):
    step_time = timing.single_support + timing.double_support
    runner, _ = commanded_runner(
        model, timing, lambda t: StepCommand(*omni.setpoint(t, scale, step_time)))
    return runner.run(omni.DURATION)


def omni_part(model, timing):
    """Scale 1.0, 1.1, ... up to the first fall; if 1.0 falls, 0.9, 0.8, ... down to a success."""
    def trial(scale):
        log = omni_run(model, timing, scale)
        print(f'  omni {model} scale {scale:.1f}: '
              f'{"FELL at %.2f s" % log.fall_time if log.fallen else "ok"}'
              f' (COM end {log.com[-1, 0]:.2f}, {log.com[-1, 1]:.2f}; max tilt '
              f'{math.degrees(log.tilt.max()):.1f} deg) {diagnose(log) if log.fallen else ""}',
              flush=True)
        return log

    best, detail = None, ''
    up = not trial(1.0).fallen
    scales = [round(1.0 + 0.1 * k, 2) for k in range(1, 11)] if up else \
        [round(1.0 - 0.1 * k, 2) for k in range(1, 8)]
    if up:
        best = 1.0
    else:
        detail = 'fell at 1.0'
    for scale in scales:
        log = trial(scale)
        if up and log.fallen:
            detail = f'fell at scale {scale:.1f}, t={log.fall_time:.1f} s'
            break
        if up:
            best = scale
        elif not log.fallen:
            best = scale
            break
    return best, detail


# ----------------------------------------------------------------------------- disk
def disk_run(model, timing, step_length, turns=1.0):
    """Around the disk, steered from the COM and the stepper's heading (the graph runs steer
    from the end of the plan) with the stepper's turn limit."""
    stepper = OmnidirectionalStepper(Pose2D(0.0, 0.0, 0.0), stepper_params())
    steering = disk.CircleSteering(step_length, max_turn=stepper_params().max_step_angle)
    state = {'runner': None, 'done': False}

    def position():
        runner = state['runner']
        if runner is None or runner.readings is None:
            return np.array([0.0, 0.0])
        return np.asarray(runner.readings.com_position[:2], dtype=float)

    def command(t):
        if state['done'] or t < 1.0:
            return StepCommand(0.0, 0.0, 0.0)
        return StepCommand(*steering.command(position(), stepper.body.yaw))

    source = CommandedWalk(stepper, timing, REFERENCE, command, WalkingReference,
                           steps_ahead=2, t_start=T_START)
    runner = ClosedLoopRunner(backend(), controller(model), source)
    runner.reset()
    state['runner'] = runner
    lap = disk.LapCounter((0.0, 0.0))

    def on_cycle(t, window, output, readings):
        lap.update(readings.com_position[:2])
        if lap.swept >= 2.0 * math.pi * turns:
            state['done'] = True

    step_time = timing.single_support + timing.double_support
    expected = 2.0 * math.pi * disk.CIRCLE_RADIUS * turns / step_length * step_time
    budget = 1.0 + 1.6 * expected + 3.0
    elapsed, chunk = 0.0, 2.0
    fallen, fall_time = False, math.nan
    why = ''
    done_at = None
    while elapsed < budget:
        log = runner.run(chunk, on_cycle=on_cycle)
        elapsed += chunk
        if log.fallen:
            fallen, fall_time = True, log.fall_time
            why = diagnose(log)
            break
        if state['done'] and done_at is None:
            done_at = elapsed
        if done_at is not None and elapsed - done_at >= 3.0:
            break
    end_error = float(np.hypot(*position()))
    radii = lap.settled_radii()
    r_min = float(radii.min()) if radii.size else math.nan
    r_max = float(radii.max()) if radii.size else math.nan
    done = state['done'] and not fallen
    # walking on for 3 s after the lap stands in for the graph runs' stop
    return dict(fallen=fallen, fall_time=fall_time, why=why, done=done,
                success=disk.succeeded(done, True, fallen, r_min, r_max, end_error, turns),
                angle=math.degrees(lap.swept), end_error=end_error, r_min=r_min, r_max=r_max)


def verdict(res) -> str:
    if res['success']:
        return 'done'
    return 'lap done, off the circle or the start' if res['done'] else 'NOT DONE'


def disk_part(model, timing, lengths, turns):
    results = {}
    for length in lengths:
        start = time.perf_counter()
        res = disk_run(model, timing, length, turns)
        results[length] = res
        print(f'  disk {model} L={length:.2f}: '
              f'{"FELL at %.1f s" % res["fall_time"] if res["fallen"] else verdict(res)}'
              f', swept {res["angle"]:.0f} deg, radius {res["r_min"]:.2f}-{res["r_max"]:.2f} m, '
              f'end {res["end_error"]:.2f} m from start '
              f'({time.perf_counter() - start:.0f} s wall) '
              f'{res["why"]}',
              flush=True)
    return results


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('parts', nargs='*', default=['push', 'omni', 'disk'])
    parser.add_argument('--models', default='three_mass,lipm')
    parser.add_argument('--push-timing', default='0.3,0.1')
    parser.add_argument('--omni-timing', default='0.3,0.1')
    parser.add_argument('--disk-timing', default='0.3,0.1')
    parser.add_argument('--disk-lengths', default='0.08,0.12,0.16,0.20,0.25')
    parser.add_argument('--turns', type=float, default=1.0, help='1: full circle, 0.5: half')
    parser.add_argument('--leg-kp', type=float, default=closed_loop_walk.LEG_KP)
    parser.add_argument('--fresh-backend', action='store_true',
                        help='a new PyBullet backend for every trial (independent trials)')
    parser.add_argument('--com-height', type=float, default=closed_loop_walk.COM_HEIGHT,
                        help='reference COM height (m); lower gives the legs more reach')
    parser.add_argument('--leg-outputs', default=None, choices=LEG_OUTPUTS,
                        help="what the MPC tracks of the legs (MpcParams.leg_outputs; default: "
                             "the walking controller's, torso_relative)")
    args = parser.parse_args(argv)
    global LEG_KP, FRESH, LEG_OUTPUTS_CHOICE
    LEG_OUTPUTS_CHOICE = args.leg_outputs
    LEG_KP = args.leg_kp
    FRESH = args.fresh_backend
    global REFERENCE
    REFERENCE = replace(closed_loop_walk.REFERENCE, com_height=args.com_height)
    models = args.models.split(',')
    rows, walls = {}, {}
    for part in args.parts:
        start = time.perf_counter()
        row = {}
        for model in models:
            if part == 'push':
                force, note = push_part(model, StepTiming(*map(float,
                                                               args.push_timing.split(','))))
                row[model] = ('n/a' if force is None else f'{force:.0f} N') + f' ({note})'
            elif part == 'omni':
                timing = StepTiming(*map(float, args.omni_timing.split(',')))
                best, detail = omni_part(model, timing)
                row[model] = (f'{best:.1f}' if best is not None else '< 1.0') + \
                    f' ({detail}; {timing.single_support}/{timing.double_support})'
            elif part == 'disk':
                timing = StepTiming(*map(float, args.disk_timing.split(',')))
                lengths = [float(v) for v in args.disk_lengths.split(',')]
                res = disk_part(model, timing, lengths, args.turns)
                ok = [f'{L:.2f}' for L, r in res.items() if r['success']]
                row[model] = f'ok: {",".join(ok) or "none"} ({timing.single_support}/' \
                             f'{timing.double_support}, turns {args.turns})'
        rows[part] = row
        walls[part] = time.perf_counter() - start
    print('\n| scenario | ' + ' | '.join(models) + ' | paper (proposed / LIPM) | wall |')
    print('|---|' + '---|' * len(models) + '---|---|')
    for part, row in rows.items():
        print(f'| {part} | ' + ' | '.join(row[m] for m in models) +
              f' | {PAPER[part]} | {walls[part]:.0f} s |')
    if BACKEND is not None:
        BACKEND.close()
    return 0


if __name__ == '__main__':
    sys.exit(main())
