"""Push recovery while walking in place (paper, "Push Recovery").

Walking in place with a 0.4 s step (0.3 s single + 0.1 s double support), a 100 ms push on the
middle of the hip every 8 s: 80 N first, +20 N while below 120 N, then +10 N, until the robot
falls. Each push starts at the same phase of a step (8 s is a whole number of steps, and the
simulator's push service takes the sim time it starts at). Reported: the largest force
withstood (paper: 100 N baseline, 150 N proposed on COMAN), and the COM velocity with the
push bands (paper Fig. push).
"""
import time
from typing import List

import numpy as np

from biped_tools.scenarios.sweep import check_repeats, median_run, run_name
from biped_tools.scenarios.trial import (base_result, drive, graph_for, Progress,
                                         request_push, stated_start, STOP_LEAD, stop_walking,
                                         Trial, write_result)

TIMING = (0.3, 0.1)      # s: the paper's 0.4 s step
FIRST_PUSH = 4.0         # s after the walk start: past the initial shift, into steady stepping
PUSH_FRACTION = 0.25     # of a single support phase, before the push starts
PUSH_PHASE = PUSH_FRACTION * TIMING[0]  # s into the single support (0.075 s)
INTERVAL = 8.0           # s between pushes (20 steps)
DURATION = 0.1           # s
RECOVERY = INTERVAL      # s of walking after the last push to call it withstood (like the others)


def forces(first: float = 80.0, maximum: float = 400.0) -> List[float]:
    """80, 100, 120, then +10 N: the paper's schedule, up to maximum."""
    values, force = [], first
    while force <= maximum + 1e-9:
        values.append(force)
        force += 20.0 if force < 120.0 else 10.0
    return values


def schedule_pushes(session, schedule: List[float], first_single: float,
                    direction: float) -> tuple:
    """Ask the simulator for every push of schedule, each PUSH_PHASE into a single support.

    :param session: the trial's GraphSession (its push service).
    :param schedule: forces (N), one push per INTERVAL from FIRST_PUSH on.
    :param first_single: sim time (s) the walk's first single support begins.
    :param direction: 1 along +x, -1 along -x.
    :return: (push times (s), None or the error of the last push, which got no answer: it may
        have been scheduled, so it is watched as if it was and none is asked for after it)
    :raises RuntimeError: a push refused by the simulator.
    """
    step = sum(TIMING)
    times = []
    for k, force in enumerate(schedule):
        at = first_single + step * round((FIRST_PUSH + k * INTERVAL) / step) + PUSH_PHASE
        times.append(at)
        unanswered = request_push(session, force, direction * force, 0.0, at, DURATION)
        if unanswered is not None:
            return times, unanswered
    return times, None


def run(trial: Trial, schedule: List[float], direction: float = 1.0) -> dict:
    """Walk in place and push with the forces of schedule (N) along +x (direction 1) or -x."""
    from biped_msgs.msg import WalkCommand
    wall0 = time.monotonic()
    with graph_for(trial, timing=TIMING) as session:
        progress = Progress(trial)
        sim0 = session.sim_time()
        # in place, from a stated sim time: the trial does not depend on when the command got
        # through (the pushes are timed from the walk's start)
        session.send_command(command=WalkCommand.START, start_time=stated_start(session, trial))
        session.spin_until(lambda: session.walk_start_time > 0.0, 60.0)
        walk0 = session.walk_start_time
        # the first single support begins after Initialize (1 s) and the first double support
        first_single = walk0 + 1.0 + TIMING[1]
        times, unanswered = schedule_pushes(session, schedule, first_single, direction)
        schedule = schedule[:len(times)]
        end = times[-1] + DURATION + RECOVERY
        drive(session, lambda t: t >= end - STOP_LEAD, end - session.sim_time() + 1.0, progress)
        stood = stop_walking(session, at=end) if not session.fallen() else False
        result = base_result(trial, session, wall0, sim0)
        series = session.series
    t_fall = None if result['fall_time_s'] is None else result['fall_time_s'] + sim0
    # withstood: no fall before the next push (or, for the last one, before the run's end)
    ends = times[1:] + [end]
    withstood = [f for f, until in zip(schedule, ends) if t_fall is None or until <= t_fall]
    result.update({
        'forces_n': schedule, 'push_times_s': [round(at - sim0, 3) for at in times],
        'largest_withstood_n': max(withstood) if withstood else 0.0,
        'first_fall_force_n': None if t_fall is None else next(
            (f for f, at, until in zip(schedule, times, ends) if at <= t_fall < until), None),
    })
    result['success'] = bool(stood and not result['fallen'])
    if unanswered is not None:
        result['error'] = (f'{unanswered}; watched as if made, and no push was scheduled after '
                           f'it')
    result['plots'] = [str(plot(trial, series, result, times, schedule))]
    return write_result(trial, result)


def repeated(make_trial, schedule: List[float], repeats: int = 1) -> dict:
    """The push schedule walked `repeats` times (odd), each run a fresh graph: the median run's
    largest push withstood and first falling force (a limit confirmed by repeats, not one
    run's), and every run's.

    :param make_trial: make_trial(scenario, setting) gives each trial
    """
    runs = [run(make_trial('push', run_name('schedule', k)), schedule)
            for k in range(check_repeats(repeats))]
    median = median_run(runs, 'largest_withstood_n')
    return {'largest_withstood_n': median['largest_withstood_n'],
            'first_fall_force_n': median['first_fall_force_n'],
            'runs': [{k: r[k] for k in ('largest_withstood_n', 'first_fall_force_n', 'success')}
                     for r in runs]}


def plot(trial: Trial, series, result: dict, times, schedule):
    """COM velocity in x with the push bands (paper Fig. push b)."""
    from biped_tools.run_plots import pyplot, save_time_figure
    plt = pyplot()
    com = np.array(series.com)
    t = com[:, 0]
    velocity = np.gradient(com[:, 1], t) if len(t) > 2 else np.zeros_like(t)
    fig, ax = plt.subplots(figsize=(10, 4))
    ax.plot(t, velocity, 'b-', lw=1, label='COM velocity x')
    for at, force in zip(times, schedule):
        if at > t[-1]:
            break
        ax.axvspan(at, at + DURATION, color='m', alpha=0.3)
        ax.text(at, ax.get_ylim()[1] * 0.9, f'{force:.0f} N', fontsize=7, rotation=90)
    return save_time_figure(fig, ax, trial.directory / 'push_com_velocity.png',
                            'COM velocity x (m/s)', f'Push recovery ({trial.model}): largest '
                            f'withstood {result["largest_withstood_n"]:.0f} N')
