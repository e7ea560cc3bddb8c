"""A scripted trial gives the same trajectory on a quiet and on a loaded machine.

Lockstep holds the clock until the controller answers (simulator wait_for_controller), waits
for live producers instead of timing out, and the walk starts at the command's start_time, not
when the message happens to arrive: the physics sees the same inputs at the same sim times.
"""
import subprocess
import sys

import numpy as np

from biped_tools.graph_session import GraphSession
from ros_harness import domain_id_for_worker

START = 20.0  # s of sim time: the walk's start_time, well after the graph is ready (the
#               planner answers in wall time while lockstep runs the clock at 2-3x)
HORIZON = 1.8  # s of the reference window: a plan that arrives later than START - HORIZON
#               changes the controller's preview at another time in each run
WALK = 6.0   # s of walking compared: the start and eight steps, through the planner's
#              extensions of the walk in place (they apply at a time stated from the step that
#              asked for them; spliced on arrival, the runs were 5e-6 m apart 1.64 s into the
#              walk)


def walk_in_place(busy_processes: int, domain_id: int) -> tuple:
    hogs = [subprocess.Popen([sys.executable, '-c', 'while True: pass'])
            for _ in range(busy_processes)]
    try:
        with GraphSession(domain_id, log=print) as session:
            session.wait_until_ready()
            assert session.sim_time() < START - HORIZON - 5.0
            session.send_command(command=1, start_time=START)
            assert session.spin_until(lambda: session.series.plans, 60)
            arrived = session.sim_time()
            assert arrived < START - HORIZON, f'the plan came at t={arrived:.2f} s'
            assert session.spin_until(lambda: session.sim_time() >= START + WALK, 240)
            walk_start = session.walk_start_time
            pelvis = np.array(session.series.pelvis)
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
    return walk_start, {round(row[0], 3): row[1:4] for row in pelvis}


def test_the_start_of_a_walk_in_place_is_the_same_quiet_and_under_two_busy_loops():
    # a fresh domain for the second graph: no discovery data of the first one in it
    quiet_start, quiet = walk_in_place(0, domain_id_for_worker())
    loaded_start, loaded = walk_in_place(2, domain_id_for_worker() + 2)
    assert quiet_start == loaded_start == START
    times = sorted(t for t in set(quiet) & set(loaded) if t <= START + WALK)
    assert times[0] < START and times[-1] >= START + WALK - 0.02
    differences = [np.abs(quiet[t] - loaded[t]).max() for t in times]
    first = next((t for t, d in zip(times, differences) if d >= 1e-9), None)
    print(f'pelvis paths of {len(times)} samples differ by at most {max(differences):.3e} m')
    # Identical (< 1e-9 m) in most runs; a run differed by 4.5e-7 m from the standing before
    # the command on, and a CI run by 1 cm from 1 s before the walk (the planner had planned
    # from odom's pelvis, not the feet: fixed). Before start_time and the held clock the two
    # walks started 0.76 s apart and differed by 0.1 m.
    assert max(differences) < 1e-5, \
        f'pelvis paths differ by up to {max(differences):.3e} m, from t={first} s'
