"""Step adjustment through the node graph: a push that the robot falls from with the plan as it
is is walked through when the reference generator's step adjuster moves the next step, and the
adjusted steps reach the plan the planner publishes.

Two graphs, one push each (scripts/biped_tools/scenarios/push_directions.py: walking in place
with the paper's 0.3 + 0.1 s step, a 100 ms push sideways on the pelvis a quarter into a single
support on the left foot, the stabilizer with the swing foot on the reference in both).
"""
import math

from biped_tools.scenarios import push_directions
from biped_tools.scenarios.trial import Trial
from ros_harness import domain_id_for_worker

# (direction deg, phase, N): falls without adjustment and is walked through with it. Graph
# runs, 2026-12-03 with the foot damping split by support: this cell's push ladder gives 110 N
# without and 200 N with adjustment (README, push tables); a single 140 N push fell without and
# was walked through with 7 adjustments. (The forward 160 N push of before fell both ways.)
DIRECTION, PHASE, FORCE = 270.0, 'early_single_left', 140.0


def push_trial(tmp_path, adjustment: bool) -> dict:
    trial = Trial('push_directions', 'three_mass', 'on' if adjustment else 'off', tmp_path,
                  domain_id_for_worker(), record=False, log=print, node_log=print)
    return push_directions.run(trial, DIRECTION, PHASE, 'in_place', [FORCE],
                               adjustment, interval=3.0)


def test_a_push_the_fixed_plan_falls_from_is_walked_through_with_step_adjustment(tmp_path):
    fixed = push_trial(tmp_path, False)
    assert fixed['pushes'][0]['met'].startswith('single left')
    assert fixed['fallen'] and fixed['step_adjustments'] == 0
    adjusted = push_trial(tmp_path, True)
    assert adjusted['pushes'][0]['met'].startswith('single left')
    assert not adjusted['fallen'] and adjusted['largest_withstood_n'] == FORCE
    assert adjusted['step_adjustments'] >= 1
    # the push was answered in its own step, by a step along the push
    first = adjusted['adjustments'][0]
    planned = first['planned_landing']
    moved = first['landing']
    along = (moved[0] - planned[0]) * math.cos(math.radians(DIRECTION)) + \
        (moved[1] - planned[1]) * math.sin(math.radians(DIRECTION))
    assert along > 0.02
    assert first['at_s'] - adjusted['pushes'][0]['at_s'] < 0.3
    # the planner republished every adjusted plan: its last plan has the last adjusted landing
    assert adjusted['plan_has_adjusted_landings']
