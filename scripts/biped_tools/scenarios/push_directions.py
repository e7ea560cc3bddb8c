"""Pushes from every direction at every phase of the gait, with and without step adjustment.

What users meet, beyond the paper's one sagittal push: a 100 ms push on the pelvis from one of 8
directions (every 45 deg, from +x towards +y), at one of 4 phases of a step, walking in place or
forward at 0.1 m steps (the paper's 0.3 + 0.1 s step). The phases, as in the library trials
(biped_sim.push_trial): early_single (a quarter into a single support on the right foot),
late_single (its last 0.1 s, ending at touchdown), double (the double support), and
early_single_left (a quarter into a single support on the left foot).

Both settings run the same controller, the stabilizer with the swing foot on the reference
(CONTROLLER): the step adjuster moves the reference's landing, which the paper's swing target
(2 leg mass - hip) follows too late. One trial is one graph: the forces of a schedule, one
push every `interval` s of sim time, until a fall. Each push is scheduled from the
walking_state of a single support shortly before it, so it meets its phase even after the step
adjuster moved earlier touchdowns. Reported: the largest push walked through and the first
that fell.
"""
import math
import time
from typing import Dict, List, Optional, Sequence

import numpy as np

from biped_sim import push_trial
from biped_sim.push_trial import MAX_FLIGHT, RECOVERY_SWING_LAG
from biped_sim.run_log import longest_run
from biped_tools.graph_session import stamp_seconds
from biped_tools.scenarios import sweep
from biped_tools.scenarios.trial import (base_result, drive, graph_for, Progress,
                                         request_push, stated_start, Trial, write_result)

TIMING = (0.3, 0.1)       # s: the paper's push scenario
DURATION = 0.1            # s
FIRST_PUSH = 3.0          # s after the walk start: past the initial shift, into steady stepping
INTERVAL = 4.0            # s of sim time between pushes (10 steps)
LEAD = 0.3                # s: a push is scheduled at least this far ahead of the clock
DIRECTIONS_DEG = tuple(range(0, 360, 45))
GAITS = {'in_place': 0.0, 'forward': 0.1}   # m per step
# phase: (support foot of its single support or None for the double support, s into the phase)
PHASES = {
    'early_single': ('right', 0.25 * TIMING[0]),
    'late_single': ('right', TIMING[0] - DURATION),
    'double': (None, 0.0),
    'early_single_left': ('left', 0.25 * TIMING[0]),
}
SUPPORT_NAMES = {0: 'left', 1: 'right'}  # WalkingState.SUPPORT_LEFT / SUPPORT_RIGHT
CONTACT_FORCE = 15.0  # N: an ankle's normal force above this is a foot on the ground (as the
#                       controller's contact_force; a foot in the air reads its own weight, -8 N)
# the stabilizer with recovery steps that land on time (biped_sim.push_trial.RECOVERY_SWING_LAG)
CONTROLLER = ['balance:=stabilizer', 'swing_target:=planned',
              f'swing_smoothing_time_constant:={RECOVERY_SWING_LAG}']


def forces(first: float = 80.0, maximum: float = 320.0, step: float = 20.0) -> List[float]:
    """first, first + step, ... up to maximum (N)."""
    count = int(math.floor((maximum - first) / step + 1e-9)) + 1
    return [first + k * step for k in range(max(count, 0))]


def next_push_time(single_start: float, single_duration: float, support: str, phase: str,
                   earliest: float, timing: Sequence[float] = TIMING) -> float:
    """The start time of the first push of `phase` at or after `earliest`.

    From a single support under way (its start, its duration as the state machine has it, its
    support foot), the later phases follow at the nominal timing, the feet alternating.

    :param single_start: start of the current single support (s)
    :param single_duration: its duration (s)
    :param support: its support foot, 'left' or 'right'
    :param phase: a key of PHASES
    :param earliest: the push starts at or after this time (s)
    :return: the push's start time (s)
    :raises ValueError: for an unknown phase or support
    """
    if phase not in PHASES or support not in ('left', 'right'):
        raise ValueError(f'phase must be one of {tuple(PHASES)} and support left or right, '
                         f'got {phase!r}, {support!r}')
    wanted, delay = PHASES[phase]
    single, double = timing
    t, duration = single_start, single_duration
    for _ in range(100000):
        if wanted == support and t + delay >= earliest:
            return t + delay
        double_start = t + duration
        if wanted is None and double_start >= earliest:
            return double_start
        t, duration = double_start + double, single
        support = 'left' if support == 'right' else 'right'
    raise ValueError(f'no {phase} phase found after {earliest} s')


def adjustment_records(series, sim0: float) -> dict:
    """What the step adjuster did, from step_adjustment and footstep_plan records: each
    adjustment's time (from sim0), step, landing and the landing the plan had before it, and
    whether the planner's last plan of the walk holds the last adjusted landing (the planner
    republished it).

    The plan before an adjustment is the newest of its plans received before it (a plan's stamp
    is the step it was made for, which can be earlier than an adjustment it already holds) or,
    when the plan that made the step came in after the adjustment (under load in a CI run), the
    newest stamped by then; never one that holds the adjusted landing: that is the planner's
    republish, which can also come in before the adjustment."""
    steps = []
    for msg, count in zip(series.adjustments, series.plans_before_adjustment):
        index = msg.step_index + 2
        landing = msg.footsteps[index]

        def without_the_adjustment(plan) -> bool:
            return plan.plan_id == msg.plan_id and len(plan.footsteps) > index and \
                plan.footsteps[index] != landing
        stamp = stamp_seconds(msg.header.stamp)
        before = [p for p in series.plans[:count] if without_the_adjustment(p)] or \
            [p for p in series.plans if without_the_adjustment(p) and
             stamp_seconds(p.header.stamp) <= stamp + 1e-9]
        planned = before[-1].footsteps[index] if before else landing
        steps.append({'at_s': round(stamp - sim0, 3),
                      'step': msg.step_index, 'revision': msg.revision,
                      'landing': (round(landing.x, 4), round(landing.y, 4)),
                      'planned_landing': (round(planned.x, 4), round(planned.y, 4)),
                      'touchdown_s': round(msg.touchdown_time - sim0, 3),
                      'planned_touchdown_s': round(msg.planned_touchdown_time - sim0, 3)})
    in_plan = True
    if series.adjustments:
        last = series.adjustments[-1]
        plans = [p for p in series.plans if p.plan_id == last.plan_id]
        index = last.step_index + 2
        landing = last.footsteps[index]
        in_plan = bool(plans) and len(plans[-1].footsteps) > index and \
            abs(plans[-1].footsteps[index].x - landing.x) < 1e-9 and \
            abs(plans[-1].footsteps[index].y - landing.y) < 1e-9
    return {'steps': steps, 'in_plan': in_plan}


def outcome(pushes: List[Dict], t_fall: Optional[float]):
    """The forces walked through and the first that felled the robot.

    A push is walked through when the robot still stands when the next one starts (the last
    one: at the end of the run); a push that met a robot already down counts for neither.

    :param pushes: {'force_n', 'at_s', 'met'} in order, times from the run's start
    :param t_fall: fall time (s) or None (a run ends early only by a fall)
    :return: (forces walked through, first felling force or None)
    """
    walked, first_fall = [], None
    for index, push in enumerate(pushes):
        if t_fall is not None and t_fall <= push['at_s']:
            break  # met a fallen robot
        last = index + 1 == len(pushes)
        if t_fall is None or not last and pushes[index + 1]['at_s'] <= t_fall:
            walked.append(push['force_n'])
        else:
            first_fall = push['force_n']
            break
    return walked, first_fall


def longest_flights(foot_forces, starts: Sequence[float], t_end: float,
                    contact_force: float = CONTACT_FORCE) -> List[float]:
    """Per push, the longest time with neither foot loaded (above contact_force) from its start
    until the next push starts (the last: until t_end), from the ankle F/T series.

    :param foot_forces: (left, right) lists of (sim time, normal force (N)), one per period
    :param starts: the pushes' start times, in order (s, the series' time base)
    :return: seconds, 0 where a foot touched at every period
    """
    left, right = dict(foot_forces[0]), dict(foot_forces[1])
    times = np.array(sorted(set(left) & set(right)))
    if times.size < 2:
        return [0.0] * len(starts)
    period = float(np.median(np.diff(times)))
    unloaded = np.array([left[t] <= contact_force and right[t] <= contact_force for t in times])
    ends = list(starts[1:]) + [t_end]
    return [longest_run(unloaded & (times >= start - 1e-9) & (times < end - 1e-9)) * period
            for start, end in zip(starts, ends)]


def largest_grounded(pushes: List[Dict], walked: List[float],
                     max_flight: float = MAX_FLIGHT) -> float:
    """The largest force walked through with a foot loaded: the pushes walked through, up to
    the first that left both feet unloaded for longer than max_flight (s)."""
    return push_trial.largest_grounded(
        walked, [push.get('longest_flight_s', 0.0) for push in pushes], max_flight)


def phase_at(states, t: float) -> str:
    """The walking phase and support foot 10 ms into a push at t (a push at a phase's first
    instant meets that phase), from walking_state records (t, phase, step, fallen, reason,
    support, time_in_phase), e.g. 'single right, step 7'.

    A phase begins at its record's stamp minus its time_in_phase: the state machine notices a
    transition up to a timer period after it happened, and stamps the record then."""
    from biped_msgs.msg import WalkingState
    before = [s for s in states if s[0] - s[6] <= t + 0.01]
    if not before:
        return 'before the walk'
    _, phase, step, _, _, support, _ = before[-1]
    if phase == WalkingState.SINGLE_SUPPORT:
        return f'single {SUPPORT_NAMES.get(support, support)}, step {step}'
    if phase == WalkingState.DOUBLE_SUPPORT:
        return f'double, step {step}'
    return f'phase {phase}'


def gait_command(session, trial: Trial, gait: str) -> None:
    """Start walking in place (START) or forward at GAITS[gait] m per step (OMNI), at a stated
    sim time (trial.stated_start): the trial does not depend on when the command got through."""
    from biped_msgs.msg import WalkCommand
    length = GAITS[gait]
    start = stated_start(session, trial)
    if length == 0.0:
        session.send_command(command=WalkCommand.START, start_time=start)
    else:
        session.send_command(command=WalkCommand.OMNI, step_length=length,
                             step_time=sum(TIMING), start_time=start)


def run(trial: Trial, direction_deg: float, phase: str, gait: str, schedule: List[float],
        adjustment: bool, interval: float = INTERVAL, plot: bool = False) -> dict:
    """Walk, push with the forces of schedule from direction_deg at phase, until a fall.

    :param plot: also write the COM velocity and footsteps figure (plot_run)
    """
    from biped_msgs.msg import WalkingState
    wall0 = time.monotonic()
    extra = {'reference_generator': [f'step_adjustment.enabled:={str(adjustment).lower()}'],
             'mpc_controller': list(CONTROLLER)}
    angle = math.radians(direction_deg)
    pushes: List[Dict] = []
    unanswered = None
    with graph_for(trial, timing=TIMING, extra=extra) as session:
        session.watch_foot_forces()  # a push walked through in the air is reported as such
        progress = Progress(trial)
        sim0 = session.sim_time()
        gait_command(session, trial, gait)
        session.spin_until(lambda: session.walk_start_time > 0.0, 60.0)
        earliest = session.walk_start_time + FIRST_PUSH

        def single_state_near() -> Optional[object]:
            """A single support shortly before the next push: the phases after it are
            nominal."""
            state = session.walking_state
            if state is None or state.phase != WalkingState.SINGLE_SUPPORT:
                return None
            t = stamp_seconds(state.header.stamp)
            return state if t >= earliest - 1.0 - LEAD else None
        for force in schedule:
            if not drive(session, lambda t: single_state_near() is not None,
                         earliest - session.sim_time() + 2.0, progress):
                break
            state = single_state_near()
            now = stamp_seconds(state.header.stamp)
            at = next_push_time(now - state.time_in_phase, state.phase_duration,
                                SUPPORT_NAMES[state.support_foot], phase,
                                max(earliest, session.sim_time() + LEAD))
            # a lost answer: watched as if applied, and the last push of the trial
            unanswered = request_push(session, force, force * math.cos(angle),
                                      force * math.sin(angle), at, DURATION)
            pushes.append({'force_n': force, 'at_s': round(at - sim0, 3)}
                          | ({} if unanswered is None else {'answered': False}))
            end = at + DURATION + interval - 1.0
            drive(session, lambda t: t >= end, end - session.sim_time() + 1.0, progress)
            if session.fallen() or unanswered is not None:
                break
            earliest = at + interval
        result = base_result(trial, session, wall0, sim0)
        series = session.series
        adjustments = adjustment_records(series, sim0)
        flights = longest_flights(series.foot_forces, [p['at_s'] + sim0 for p in pushes],
                                  session.sim_time())
        for push, flight in zip(pushes, flights):
            push['met'] = phase_at(session.series.states, push['at_s'] + sim0)
            push['longest_flight_s'] = round(flight, 3)
    walked, first_fall = outcome(pushes, result['fall_time_s'])
    result.update({
        'direction_deg': direction_deg, 'phase': phase, 'gait': gait, 'adjustment': adjustment,
        'pushes': pushes, 'step_adjustments': len(adjustments['steps']),
        'adjustments': adjustments['steps'],
        'plan_has_adjusted_landings': adjustments['in_plan'],
        'largest_withstood_n': max(walked) if walked else 0.0,
        'largest_grounded_n': largest_grounded(pushes, walked),
        'first_fall_force_n': first_fall,
    })
    result['success'] = bool(walked)
    if not pushes and not result['fallen']:
        result['error'] = ('the walk reached no single support before its first push: no push '
                           'was made, the cell has no figure')
    if unanswered is not None:
        result['error'] = (f'{unanswered}; watched as if made, and the trial stopped after it')
    if plot:
        result['plots'] = [str(plot_run(trial, series, result, sim0))]
    return write_result(trial, result)


def plot_run(trial: Trial, series, result: dict, sim0: float):
    """COM velocity with the push bands (left) and the footsteps seen from above (right): the
    plan as first published, the plan after the adjustments (adjusted landings in red) and the
    COM path."""
    from biped_tools.run_plots import foot_outline, pyplot, save_figure
    plt = pyplot()
    com = np.array(series.com) if series.com else np.zeros((0, 4))
    fig, (speed, top) = plt.subplots(1, 2, figsize=(12, 4.5))
    if len(com) > 2:
        t = com[:, 0] - sim0
        for axis, name, colour in ((1, 'x', 'b'), (2, 'y', 'g')):
            speed.plot(t, np.gradient(com[:, axis], com[:, 0]), colour + '-', lw=1,
                       label=f'COM velocity {name}')
        top.plot(com[:, 1], com[:, 2], 'k-', lw=0.8, label='COM')
    for push in result['pushes']:
        speed.axvspan(push['at_s'], push['at_s'] + DURATION, color='m', alpha=0.3)
        speed.text(push['at_s'], 0.9 * max(speed.get_ylim()[1], 0.1),
                   f'{push["force_n"]:.0f} N', fontsize=7, rotation=90)
    for record in result['adjustments']:
        speed.axvline(record['at_s'], color='r', lw=0.6, alpha=0.6)
    speed.set_xlabel('simulated time (s)')
    speed.set_ylabel('m/s')
    speed.legend(loc='lower left', fontsize=8)
    speed.set_title(f'{result["direction_deg"]:g} deg, {result["phase"]}, {result["gait"]}; '
                    f'red: step adjustments')
    plans = [p for p in series.plans if p.status == 0 and p.footsteps]
    if plans:
        walked = [p for p in plans if p.plan_id == plans[-1].plan_id]
        for step in walked[0].footsteps:
            top.add_patch(foot_outline(step, 0.2, 0.1, edgecolor='0.6', fill=False, lw=0.8))
        moved = {(round(r['landing'][0], 4), round(r['landing'][1], 4))
                 for r in result['adjustments']}
        for step in walked[-1].footsteps:
            red = (round(step.x, 4), round(step.y, 4)) in moved
            top.add_patch(foot_outline(step, 0.2, 0.1, edgecolor='r' if red else 'b',
                                       fill=False, lw=1.2 if red else 0.8))
    top.set_aspect('equal')
    top.autoscale_view()
    top.set_xlabel('x (m)')
    top.set_ylabel('y (m)')
    top.set_title('footsteps: first plan (grey), walked plan (blue), adjusted (red)')
    top.legend(loc='lower left', fontsize=8)
    adjustment = 'on' if result['adjustment'] else 'off'
    fig.suptitle(f'Push recovery, step adjustment {adjustment} ({trial.model}): largest '
                 f'withstood {result["largest_withstood_n"]:.0f} N')
    return save_figure(fig, trial.directory / 'push_com_velocity_footsteps.png')


def pushed(result: dict) -> bool:
    """The trial met its pushes; False when the walk never reached the first one (a fall
    before it still counts: 0 N)."""
    return bool(result.get('pushes', True)) or bool(result.get('fallen'))


def median_run(runs: List[dict]) -> dict:
    """One cell from its repeated runs (an odd number): the run with the median largest push
    withstood (the lower one of an even count: a limit is not rounded up), with every run's
    figure in 'repeats_withstood_n'; a run that made no push counts only when no run did."""
    median = dict(sweep.median_run([r for r in runs if pushed(r)] or runs,
                                   'largest_withstood_n'))
    median['repeats_withstood_n'] = [r['largest_withstood_n'] if pushed(r) else None
                                     for r in runs]
    return median


def table(results: List[dict]) -> str:
    """Markdown: largest push withstood per direction (rows) and phase (columns), each cell
    'off / on' when both adjustment settings were run, and the minimum; a trial that made no
    push shows 'no walk' and is left out of the minimum."""
    phases = [p for p in PHASES if any(r['phase'] == p for r in results)]
    directions = sorted({r['direction_deg'] for r in results})
    settings = sorted({r['adjustment'] for r in results})

    def cell(direction, phase):
        values = []
        for setting in settings:
            match = [r for r in results if r['direction_deg'] == direction
                     and r['phase'] == phase and r['adjustment'] == setting]
            if not match:
                values.append('-')
            elif pushed(match[0]):
                values.append(f"{match[0]['largest_withstood_n']:.0f}")
            else:
                values.append('no walk')
        return ' / '.join(values)
    heading = ' / '.join('on' if s else 'off' for s in settings)
    lines = [f'| direction ({heading}, N) | ' + ' | '.join(phases) + ' |',
             '|---' * (len(phases) + 1) + '|']
    lines += [f'| {d:.0f} deg | ' + ' | '.join(cell(d, p) for p in phases) + ' |'
              for d in directions]

    def minima(key: str) -> str:
        """'off / on' minimum of a result's figure over the trials that pushed."""
        values = [[r[key] for r in results if r['adjustment'] == setting and pushed(r)]
                  for setting in settings]
        return ' / '.join(f'{min(v):.0f}' if v else '-' for v in values)
    lines.append(f'| minimum | {minima("largest_withstood_n")} N over directions and phases |'
                 + ' |' * (len(phases) - 1))
    if all('largest_grounded_n' in r for r in results):
        lines.append(f'| minimum on the ground | {minima("largest_grounded_n")} N (no push '
                     f'followed by more than {MAX_FLIGHT} s with neither foot loaded) |'
                     + ' |' * (len(phases) - 1))
    unpushed = sum(not pushed(r) for r in results)
    if unpushed:
        lines.append(f'\n{unpushed} trial(s) made no push (no walk): run them again.')
    return '\n'.join(lines)
