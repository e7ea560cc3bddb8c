"""Walking around a disk (paper, "Walking Around A Disk").

A disk of radius 1.35 m whose centre is 1.8 m to the robot's left; the robot walks around it
counter-clockwise keeping 2 m from the centre and returns to its start. The step length is
fixed; the turn of each step comes from the position it is taken from: the heading aims along
the tangent of the 2 m circle, leaning outward or inward by the radial error (CircleSteering).
A lap is the angle the COM sweeps around the centre (LapCounter); `succeeded` is the success
test: a whole lap, no fall, standing at the end, near the circle all along (after the start)
and back near the start.

This module is the one definition of the scenario: `run` walks it through the node graph (the
position is the end of the plan, a few steps ahead of the robot; commands go to the planner as
OMNI walk commands, per-step X, Y, alpha through its lag filter, one per step), and
scripts/experiments/scenario_probe.py walks it in the library closed loop.
"""
import math

import numpy as np

from biped_tools.graph_session import IDLE, stamp_seconds, STEPPING
from biped_tools.scenarios.sweep import grid, largest_completing, run_name
from biped_tools.scenarios.trial import (base_result, drive, graph_for, HOLD_AT, Progress,
                                         sample_at, stated_start, stop_walking, SWEEP_LIMITS, Trial,
                                         write_result)

DISK_CENTRE = (0.0, 1.8)
DISK_RADIUS = 1.35
CIRCLE_RADIUS = 2.0
RADIAL_GAIN = 1.0        # rad of heading lean per m of radial error (through atan)
HEADING_GAIN = 0.5       # share of the heading error corrected per step
MAX_TURN = math.radians(20.0)  # per step, the planner's teleop limit
RADIUS_TOLERANCE = 0.35  # m: the walk must stay within 2 m +- this
RETURN_TOLERANCE = 0.5   # m: distance to the start after the lap
SETTLING = 3.0           # s at the start (weight shift, first steps) not held to the circle
SAMPLE_PERIOD = 0.02     # s between LapCounter updates (one per control period)
COMMAND_DELAY = 0.25  # s after a step starts: its command's stated time (steps of 0.4 + 0.2 s)
# s: the STOP replaces the command of the first step that starts at most this long before the
# lap's end, as the COM up to that start foretells it (the walk goes on for about a step after
# a STOP, so the lap still ends)
STOP_LEAD_OF_LAP = 0.55
PACE_MARGIN = 0.02  # s: a paced clock stops this far short of a step command's stated time
END_AFTER_IDLE = 0.5  # s of sim time: the return is measured this long after the walk ended
PLAN_WAIT = 10.0  # s of wall time a step's command waits for the plan extended at its start
# s of sim time before the walk's start by which its plan must be in (the reference window is
# 1.8 s): sent 1 s before the start, the plan entered the controller's preview at a
# load-dependent time
PLAN_BEFORE_START = 2.5
RATE_WINDOW = 1.0  # s of COM samples before a step's start that give the sweep rate
STEP_LENGTHS = grid(0.08, 0.25, 0.01)  # m, the paper's sweep


def disk_map():
    """Occupancy grid (0.1 m) with the disk, for the simulator's obstacles and the plots."""
    from biped_planner.occupancy_grid import OccupancyGrid
    resolution, origin = 0.1, (-3.0, -1.5)
    width, height = 60, 66
    xs = origin[0] + resolution * (np.arange(width) + 0.5)
    ys = origin[1] + resolution * (np.arange(height) + 0.5)
    gx, gy = np.meshgrid(xs, ys)
    inside = np.hypot(gx - DISK_CENTRE[0], gy - DISK_CENTRE[1]) <= DISK_RADIUS
    return OccupancyGrid(np.where(inside, 100, 0).astype(np.int8), resolution, origin)


class CircleSteering:
    """The per-step command: fixed length, turn toward the 2 m circle's tangent.

    :param step_length: X of every step (m)
    :param max_turn: largest turn per step (rad): the planner's teleop limit by default
    """

    def __init__(self, step_length: float, max_turn: float = MAX_TURN) -> None:
        self.step_length = step_length
        self.max_turn = max_turn

    def command(self, position, planned_yaw: float) -> tuple:
        rel = np.asarray(position) - DISK_CENTRE
        radius = float(np.hypot(*rel))
        tangent = math.atan2(rel[1], rel[0]) + 0.5 * math.pi   # counter-clockwise
        desired = tangent - math.atan(RADIAL_GAIN * (CIRCLE_RADIUS - radius))
        error = math.remainder(desired - planned_yaw, 2.0 * math.pi)
        turn = self.step_length / CIRCLE_RADIUS + HEADING_GAIN * error
        return self.step_length, 0.0, float(np.clip(turn, -self.max_turn, self.max_turn))


class LapCounter:
    """Angle swept around the disk centre by the COM (rad), and the radii seen."""

    def __init__(self, start) -> None:
        rel = np.asarray(start) - DISK_CENTRE
        self.last = math.atan2(rel[1], rel[0])
        self.swept = 0.0
        self.radii = []
        self.history = []  # (t, swept) of every update

    def update(self, position, t: float = math.nan) -> None:
        rel = np.asarray(position) - DISK_CENTRE
        angle = math.atan2(rel[1], rel[0])
        self.swept += math.remainder(angle - self.last, 2.0 * math.pi)
        self.last = angle
        self.radii.append(float(np.hypot(*rel)))
        self.history.append((float(t), self.swept))

    def time_left(self, t: float, laps: float) -> float:
        """How long after t (s) the lap ends, from the updates up to t at the rate of the last
        RATE_WINDOW s before it: 0 when it has ended, inf when the COM does not go round."""
        before = [h for h in self.history if h[0] <= t + 1e-9]
        if not before:
            return math.inf
        t_now, swept = before[-1]
        left = 2.0 * math.pi * laps - swept
        if left <= 0.0:
            return 0.0
        earlier = [h for h in before if h[0] <= t_now - RATE_WINDOW + 1e-9]
        if not earlier:
            return math.inf
        rate = (swept - earlier[-1][1]) / (t_now - earlier[-1][0])
        return left / rate if rate > 0.0 else math.inf

    def settled_radii(self) -> np.ndarray:
        """The radii after the first SETTLING s (all of them in a run shorter than 6 s)."""
        skip = int(SETTLING / SAMPLE_PERIOD)
        return np.array(self.radii[skip:] if len(self.radii) > 2 * skip else self.radii)


def succeeded(completed: bool, stood: bool, fallen: bool, radius_min: float,
              radius_max: float, return_error: float, laps: float) -> bool:
    """The success test of a walk around the disk.

    :param completed: the COM swept `laps` turns around the centre
    :param stood: the robot stood (or walked on) without a fall after the lap
    :param fallen: it fell at any time
    :param radius_min: smallest settled distance of the COM to the centre (m)
    :param radius_max: largest settled distance (m)
    :param return_error: distance of the COM's end to its start (m), checked for a whole lap
    :param laps: turns asked for
    """
    return bool(completed and stood and not fallen and
                abs(radius_min - CIRCLE_RADIUS) <= RADIUS_TOLERANCE and
                abs(radius_max - CIRCLE_RADIUS) <= RADIUS_TOLERANCE and
                (laps < 1.0 or return_error <= RETURN_TOLERANCE))


def run(trial: Trial, step_length: float, laps: float = 1.0) -> dict:
    """One walk around the disk with the given step length (m)."""
    import time
    wall0 = time.monotonic()
    steering = CircleSteering(step_length)
    with graph_for(trial, extra=SWEEP_LIMITS) as session:
        session.publish_map(disk_map())
        progress = Progress(trial)
        sim0 = session.sim_time()
        session.wait_for_command_listeners()
        walk0 = stated_start(session, trial)
        # where the robot stands, read at a stated time once its COM sample is in (the clock
        # can be ahead of the samples: the one before, read instead, turned the first steps
        # 1e-7 rad apart between runs, and the disk at 0.24 m walked in some and fell in others)
        com = session.series.com
        session.spin_until(lambda: com and com[-1][0] >= HOLD_AT - 1e-6, 120.0)
        start = np.array((sample_at(com, HOLD_AT) or com[0])[1:3], dtype=float)
        lap = LapCounter(start)
        state = {'step': 0, 'since': 0.0, 'sent': True, 'read': 0}

        def planned_pose(plans):
            """Where the plan ends (midpoint of its last two footsteps, last yaw): the new
            step is taken from there, a few steps ahead of the robot (teleop lookahead)."""
            plans = [p for p in plans if p.status == 0 and len(p.footsteps) >= 2]
            if not plans:
                return start, 0.0
            a, b = plans[-1].footsteps[-2:]
            return (0.5 * (a.x + b.x), 0.5 * (a.y + b.y)), b.yaw

        def send_command(plans, start_time: float):
            x, y, turn = steering.command(*planned_pose(plans))
            session.command_pub.publish(_omni(x, y, turn, start_time))

        def read_lap() -> None:
            # every COM sample, in order, up to the one that completes the lap
            com = session.series.com
            while state['read'] < len(com) and lap.swept < 2.0 * math.pi * laps:
                sample = com[state['read']]
                state['read'] += 1
                if sample[0] >= walk0:
                    lap.update(sample[1:3], sample[0])

        # the first command starts the walk at walk0; the clock waits for its plan
        plans_before = len(session.series.plans)
        session.pace_limit = walk0 - PLAN_BEFORE_START
        send_command([], walk0)
        if not session.spin_until(lambda: len(session.series.plans) > plans_before, PLAN_WAIT):
            trial.log(f'[{trial.label}] no plan for the walk after {PLAN_WAIT:.0f} s of wall '
                      'time (this run may differ)')
        session.pace_limit = None

        def on_time(t: float) -> bool:
            read_lap()
            states = session.series.states
            if states and states[-1][2] != state['step'] and states[-1][1] in STEPPING:
                state.update(step=states[-1][2], since=states[-1][0] - states[-1][6],
                             sent=False, waiting_from=time.monotonic())
                # the clock waits short of the command's stated time until it is decided
                session.pace_limit = state['since'] + COMMAND_DELAY - PACE_MARGIN - \
                    (session.pace_lead or 0.0)
            # One command per step, from the plan the robot extended at the step's start
            # (stamped with that start), stated for COMMAND_DELAY after it: the planner applies
            # it at the next phase (the double support) and extends with it at the next step,
            # whenever it arrived before then. Without the plan in time, the newest one.
            if not state['sent']:
                since = state['since']
                com = session.series.com
                waited_out = time.monotonic() - state['waiting_from'] > PLAN_WAIT
                if lap.swept < 2.0 * math.pi * laps and (not com or com[-1][0] < since) and \
                        not waited_out:
                    return False  # the COM up to the step's start decides, not the load
                if lap.time_left(since, laps) <= STOP_LEAD_OF_LAP:
                    state['stop_at'] = since + COMMAND_DELAY
                    session.pace_limit = None
                    return True
                plans = [p for p in session.series.plans
                         if stamp_seconds(p.header.stamp) < since + 1e-6]
                extended = plans and stamp_seconds(plans[-1].header.stamp) > since - 1e-6
                late = t >= since + COMMAND_DELAY or waited_out
                if extended or late:
                    if not extended:
                        trial.log(f'[{trial.label}] no plan extended at t={since:.2f} s: the '
                                  'step is steered from the newest (this run may differ)')
                    state['sent'] = True
                    session.pace_limit = None
                    send_command(plans, since + COMMAND_DELAY)
            return False

        step_time = 0.6
        expected = 2.0 * math.pi * CIRCLE_RADIUS * laps / step_length * step_time
        completed = drive(session, on_time, 1.5 * expected + 10.0 + walk0 - session.sim_time(),
                          progress,
                          lambda: f'swept {math.degrees(lap.swept):.0f} deg')
        # the STOP takes the place of a step's command, stated as that command would have been
        # (a STOP stated STOP_AFTER_ARRIVAL after the lap was seen walked the robot 0.39-0.52 m
        # past its start, where the return error is measured)
        stood = stop_walking(session, at=state['stop_at']) if completed else False
        read_lap()
        completed = completed and lap.swept >= 2.0 * math.pi * laps
        result = base_result(trial, session, wall0, sim0)
        series = session.series
    # where it stands END_AFTER_IDLE after the walk ended, not the last sample the runner saw
    idle = next((row[0] for row in series.states
                 if row[1] == IDLE and row[0] >= state.get('stop_at', math.inf)), None)
    at_end = None if idle is None else sample_at(series.com, idle + END_AFTER_IDLE)
    end = np.array((at_end or series.com[-1])[1:3])
    radii = lap.settled_radii()
    result.update({
        'step_length_m': step_length, 'swept_deg': round(math.degrees(lap.swept), 1),
        'radius_min_m': round(float(radii.min()), 3), 'radius_max_m': round(float(radii.max()), 3),
        'radius_rms_error_m': round(float(np.sqrt(np.mean((radii - CIRCLE_RADIUS) ** 2))), 3),
        'return_error_m': round(float(np.hypot(*(end - start))), 3),
    })
    result['success'] = succeeded(completed, stood, result['fallen'], result['radius_min_m'],
                                  result['radius_max_m'], result['return_error_m'], laps)
    result['plots'] = [str(plot(trial, series, result))]
    return write_result(trial, result)


def largest_step_length(make_trial, repeats: int = 1) -> tuple:
    """Bisection of STEP_LENGTHS from the paper's 0.15 m, the limit confirmed by `repeats` runs
    (biped_tools.scenarios.sweep): (largest completing or None, {length: [completed, ...]});
    make_trial(scenario, setting) gives each trial."""
    return largest_completing(STEP_LENGTHS, lambda length, k: run(
        make_trial('disk', run_name(f'{length:.2f}', k)), length)['success'], first=0.15,
        repeats=repeats)


def _omni(x: float, y: float, turn: float, start_time: float):
    from biped_msgs.msg import WalkCommand
    return WalkCommand(command=WalkCommand.OMNI, step_length=x, step_width=y, step_angle=turn,
                       start_time=float(start_time))


def plot(trial: Trial, series, result: dict):
    """Feet and COM in the XY plane with the disk and the 2 m circle (paper Fig. walkingaround)."""
    from biped_tools.run_plots import top_view

    def circles(ax):
        from matplotlib.patches import Circle
        ax.add_patch(Circle(DISK_CENTRE, DISK_RADIUS, color='0.6', alpha=0.5, label='disk'))
        ax.add_patch(Circle(DISK_CENTRE, CIRCLE_RADIUS, fill=False, ls=':', color='k',
                            label='2 m circle'))
    return top_view(series, trial.directory / 'disk_top_view.png',
                    f'Walking around a disk ({trial.model}, step {result["step_length_m"]} m): '
                    f'{"completed" if result["success"] else "failed"}', extra=circles)
