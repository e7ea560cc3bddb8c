"""START -> GOAL with obstacles (paper, "Walking with Path Planning"): the main job and demo.

Brings up the whole graph headless in lockstep (simulator, map server, state machine, A*/footstep
planner, reference generator, MPC controller), the map server serving the paper's START -> GOAL
map from its nav2 map file (biped_planner's maps/paper_start_goal.yaml + .pgm), sends the goal
as a user would (goal_pose), records a rosbag2 of the run, and writes plots (map, A* path,
footsteps, COM; ZMP against the support polygon) and summary.json. Success: the walk finished
without a fall, the pelvis within GOAL_TOLERANCE of the goal, SETTLE s after the walk ended.
As a summary trial the goal goes as a GOTO walk command with a stated start
(trial.stated_start_time) instead, so that the trial does not depend on when the message arrived.
"""
import json
from pathlib import Path
import statistics
import time

from biped_msgs.msg import WalkCommand

from biped_tools.graph_session import GraphSession, IDLE
from biped_tools.paths import PAPER_MAP
from biped_tools.run_plots import top_view, zmp_figure, zmp_inside_fraction
from biped_tools.scenarios.trial import (fresh_bag_dir, graph_overrides, HOLD_AT, PACE_LEAD,
                                         sample_at, stated_start_time, Trial, write_result)

GOAL_TOLERANCE = 0.15  # m between the final pelvis and the goal
NO_MAP_RETRIES = 5     # goals sent while the planner answers that it has no map yet
SETTLE = 1.0           # s after the walk ended (Idle) at which the final pelvis is read


def arrived(summary: dict) -> bool:
    """The success test: finished, standing, and within GOAL_TOLERANCE of the goal."""
    return bool(summary['finished'] and not summary['fallen'] and
                summary['final_error_m'] <= GOAL_TOLERANCE)


def walk_start_to_goal(out: Path, domain_id: int, model: str, timeout: float,
                        log=print, stated: bool = False) -> dict:
    """One walk from the paper's START to its GOAL; the summary, also in out/summary.json.

    :param stated: send the goal as a GOTO walk command that starts at a stated sim time
        (scripted trials), not as goal_pose (as a user in RViz does)
    """
    from biped_planner.example_maps import paper_start_goal_example
    _, start, goal = paper_start_goal_example()
    bag = fresh_bag_dir(out)
    overrides = graph_overrides(model, (start.x, start.y, start.yaw))
    wall_start = time.monotonic()
    # a scripted trial's clock holds until the session is ready, as in every scripted trial
    with GraphSession(domain_id, bag_dir=bag, overrides=overrides, map_file=PAPER_MAP,
                      hold_at=HOLD_AT if stated else None,
                      pace_lead=PACE_LEAD if stated else None, log=log) as session:
        session.wait_until_ready()
        if stated:
            session.resume_clock()
        grid = session.map
        t0 = session.sim_time()
        log(f'[demo] goal ({goal.x}, {goal.y}) from ({start.x}, {start.y})')
        start_time = stated_start_time(t0)
        if stated:
            plan = session.plan_answering(lambda: session.send_command(
                command=WalkCommand.GOTO, goal_x=goal.x, goal_y=goal.y, goal_yaw=goal.yaw,
                start_time=start_time), NO_MAP_RETRIES)
        else:
            plan = session.plan_answering(lambda: session.send_goal(goal.x, goal.y, goal.yaw),
                                          NO_MAP_RETRIES)
        if plan is None or plan.status != 0:
            raise RuntimeError(f'planning failed: {plan.error_msg if plan else "no plan"}')
        walked = session.spin_until(lambda: session.phase() not in (None, IDLE), 20.0)
        finished = walked and session.spin_until(
            lambda: session.phase() == IDLE or session.fallen(), timeout)
        session.wait_sim_time(SETTLE + 0.1, 20.0)  # the final settle of the hip
        series = session.series
        wall = time.monotonic() - wall_start
    bag_summary = session.summary  # written when the session closed the bag
    pelvis = pelvis_after_walk(series, SETTLE)
    error = ((pelvis[1] - goal.x) ** 2 + (pelvis[2] - goal.y) ** 2) ** 0.5
    sim_duration = pelvis[0] - t0
    solve = sorted(series.solve_times)
    summary = {
        'goal': [goal.x, goal.y], 'final_pelvis': [round(pelvis[1], 4), round(pelvis[2], 4)],
        'final_error_m': round(error, 4), 'fallen': session.fallen(), 'finished': finished,
        'steps_planned': len(plan.footsteps) - 2,
        'steps_walked': max(s[2] for s in series.states),
        'simulated_s': round(sim_duration, 2), 'wall_s': round(wall, 1),
        'goal_sent_at_sim_s': round(t0, 3), 'ended_at_sim_s': round(pelvis[0], 3),
        'zmp_inside_support_fraction': round(zmp_inside_fraction(series, margin=0.01), 3),
        'max_tilt_deg': round(max(p[4] for p in series.pelvis) * 57.2958, 2),
        'mpc_solve_time_median_us': round(statistics.median(solve) * 1e6, 1) if solve else None,
        'mpc_solve_time_p99_us': round(solve[int(0.99 * (len(solve) - 1))] * 1e6, 1)
        if solve else None,
        'model': model,
        'bag': str(bag), 'bag_messages': bag_summary.message_count if bag_summary else 0,
    }
    (out / 'summary.json').write_text(json.dumps(summary, indent=2))
    top_view(series, out / 'walk_top_view.png',
             f'START -> GOAL through the node graph ({model}): error {error:.3f} m',
             grid=grid, goal=(goal.x, goal.y))
    zmp_figure(series, out / 'walk_zmp.png', 'ZMP (F/T) against the support polygon')
    return summary


def pelvis_after_walk(series, settle: float):
    """The pelvis sample `settle` s after the walk ended (its Idle phase's start), not when the
    runner noticed; the newest sample when the walk did not end."""
    states = series.states
    walked = next((i for i, s in enumerate(states) if s[1] != IDLE), None)
    idle = None if walked is None else next(
        (s for s in states[walked:] if s[1] == IDLE), None)
    if idle is None:
        return series.pelvis[-1]
    return sample_at(series.pelvis, idle[0] - idle[6] + settle) or series.pelvis[-1]


def run(trial: Trial) -> dict:
    """The walk as a scenario trial: its result.json beside the demo's summary and plots."""
    trial.directory.mkdir(parents=True, exist_ok=True)
    summary = walk_start_to_goal(trial.directory, trial.domain_id, trial.model, timeout=600.0,
                                 log=lambda line: None, stated=True)
    result = {'scenario': trial.scenario, 'model': trial.model, 'setting': trial.setting,
              **summary}
    result['success'] = arrived(summary)
    result['plots'] = [str(trial.directory / 'walk_top_view.png'),
                       str(trial.directory / 'walk_zmp.png')]
    return write_result(trial, result)
