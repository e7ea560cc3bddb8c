"""Omnidirectional walking (paper, "Omnidirectional Walking").

Walking in place, then per-step setpoints (X, Y, alpha) that change at t = 2, 10, 20 and 32 s
of the walk: forward, diagonal, diagonal while turning at 15 deg/s, and back to walking in
place; each goes to the planner as an OMNI walk command and through its first-order lag filter.
A scale factor multiplies every setpoint (the paper's sweep: 1.03 baseline, 1.16 proposed).
Success: the whole schedule walked without a fall, standing at the end.

The schedule is defined here once (`setpoint`): `run` walks it through the node graph and
scripts/experiments/scenario_probe.py in the library closed loop.
"""
import math
import time

import numpy as np

from biped_tools.graph_session import STEPPING
from biped_tools.scenarios.sweep import grid, largest_completing, run_name
from biped_tools.scenarios.trial import (base_result, drive, graph_for, Progress, sample_at,
                                         stated_start, STOP_LEAD, stop_walking, SWEEP_LIMITS,
                                         Trial, write_result)

STEP_TIME = 0.6     # s, the configured gait (0.4 single + 0.2 double support)
DURATION = 36.0     # s of walk: 4 s of walking in place after the last change
# (t from the walk start in s, X m per step, Y m per step, alpha deg/s)
SCHEDULE = ((0.0, 0.0, 0.0, 0.0), (2.0, 0.1, 0.0, 0.0), (10.0, 0.1, 0.05, 0.0),
            (20.0, 0.2, 0.05, 15.0), (32.0, 0.0, 0.0, 0.0))
SCALES = grid(0.5, 1.5, 0.05)  # 1.5: X = 0.3 m, the command bound
LEAD = 1.5  # s: each change is sent this long before its stated time (the planner holds it)


def setpoint(t_walk: float, scale: float, step_time: float = STEP_TIME) -> tuple:
    """The scaled (X m, Y m, alpha rad per step) commanded at t_walk s after the walk start,
    for steps of step_time s (the turn rate is per second)."""
    current = SCHEDULE[0]
    for entry in SCHEDULE:
        if t_walk >= entry[0]:
            current = entry
    _, x, y, rate = current
    return scale * x, scale * y, scale * math.radians(rate) * step_time


def succeeded(completed: bool, stood: bool, fallen: bool) -> bool:
    """The success test: the schedule walked to its end, standing after it, no fall."""
    return bool(completed and stood and not fallen)


def run(trial: Trial, scale: float, duration: float = DURATION) -> dict:
    from biped_msgs.msg import WalkCommand
    wall0 = time.monotonic()
    with graph_for(trial, extra=SWEEP_LIMITS) as session:
        progress = Progress(trial)
        sim0 = session.sim_time()
        # walk in place (all setpoints zero) from a stated time
        session.send_command(command=WalkCommand.OMNI, start_time=stated_start(session, trial))
        session.spin_until(lambda: session.walk_start_time > 0.0, 60.0)
        walk0 = session.walk_start_time
        changes = [entry[0] for entry in SCHEDULE[1:]]
        sent = {'count': 0, 'value': setpoint(0.0, scale)}

        def on_time(t: float) -> bool:
            # each change stated for its time and sent LEAD s before it, once walking (the
            # planner holds it and steers from the first step starting at or after it)
            walking = session.phase() in STEPPING
            while walking and sent['count'] < len(changes) and \
                    t >= walk0 + changes[sent['count']] - LEAD:
                at = changes[sent['count']]
                value = setpoint(at, scale)
                session.command_pub.publish(WalkCommand(
                    command=WalkCommand.OMNI, step_length=value[0], step_width=value[1],
                    step_angle=value[2], start_time=walk0 + at))
                sent['count'] += 1
            sent['value'] = setpoint(t - walk0, scale)
            return t - walk0 >= duration - STOP_LEAD

        completed = drive(session, on_time, walk0 + duration + 5.0 - session.sim_time(), progress,
                          lambda: f'setpoint {sent["value"]}')
        stood = stop_walking(session, at=walk0 + duration) if completed else False
        result = base_result(trial, session, wall0, sim0)
        series = session.series
    at_end = sample_at(series.pelvis, walk0 + duration)
    pelvis = np.array(series.pelvis)
    result.update({'scale': scale, 'walk_start_s': round(walk0 - sim0, 2),
                   'pelvis_at_schedule_end': None if at_end is None else
                   [round(float(v), 6) for v in at_end[1:3]],
                   'final_pelvis': [round(float(v), 3) for v in pelvis[-1, 1:3]],
                   'turned_deg': round(math.degrees(float(np.unwrap(pelvis[:, 5])[-1] -
                                                          pelvis[0, 5])), 1)})
    result['success'] = succeeded(completed, stood, result['fallen'])
    result['plots'] = [str(plot(trial, series, result))]
    return write_result(trial, result)


def largest_scale(make_trial, duration: float = DURATION, repeats: int = 1) -> tuple:
    """Bisection of SCALES from 1, the limit confirmed by `repeats` runs
    (biped_tools.scenarios.sweep): (largest completing or None, {scale: [completed, ...]});
    make_trial(scenario, setting) gives each trial."""
    return largest_completing(SCALES, lambda scale, k: run(
        make_trial('omni', run_name(f'{scale:.2f}', k)), scale, duration)['success'],
        first=1.0, repeats=repeats)


def plot(trial: Trial, series, result: dict):
    """Feet and COM in the XY plane (paper Fig. omniwalk)."""
    from biped_tools.run_plots import top_view
    return top_view(series, trial.directory / 'omni_top_view.png',
                    f'Omnidirectional walking ({trial.model}, scale {result["scale"]}): '
                    f'{"completed" if result["success"] else "failed"}')
