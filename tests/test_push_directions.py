"""The push-directions scenario's schedule: which time a push of each phase starts at."""
import pytest

from biped_tools.scenarios.push_directions import (DURATION, forces, median_run,
                                                   next_push_time, PHASES, table, TIMING)

SINGLE, DOUBLE = TIMING
STEP = SINGLE + DOUBLE


@pytest.mark.parametrize('phase, support, expected', [
    # a single support on the right foot from t = 10 s, the state machine's 0.3 s
    ('early_single', 'right', 10.0 + 0.25 * SINGLE + 2 * STEP),  # the next right one in time
    ('late_single', 'right', 10.0 + SINGLE - DURATION),  # still ahead in this one
    ('double', 'right', 10.0 + SINGLE),
    ('early_single_left', 'right', 10.0 + STEP + 0.25 * SINGLE),
    # from a single support on the left foot, the right one comes a step later
    ('early_single', 'left', 10.0 + STEP + 0.25 * SINGLE),
    ('early_single_left', 'left', 10.0 + 2 * STEP + 0.25 * SINGLE),
])
def test_the_push_meets_its_phase(phase, support, expected):
    assert next_push_time(10.0, SINGLE, support, phase, earliest=10.1) == pytest.approx(expected)


def test_a_push_the_current_phase_still_allows_is_taken_there():
    assert next_push_time(10.0, SINGLE, 'right', 'early_single', earliest=10.0) == \
        pytest.approx(10.0 + 0.25 * SINGLE)


def test_a_stretched_single_support_moves_the_phases_after_it():
    """The step adjuster gave the current step 0.36 s: the state machine's duration counts."""
    assert next_push_time(10.0, 0.36, 'right', 'double', earliest=10.1) == pytest.approx(10.36)
    assert next_push_time(10.0, 0.36, 'right', 'early_single_left', earliest=10.1) == \
        pytest.approx(10.36 + DOUBLE + 0.25 * SINGLE)


@pytest.mark.parametrize('phase, support', [('sideways', 'right'), ('double', 'both')])
def test_unknown_phases_and_supports_are_refused(phase, support):
    with pytest.raises(ValueError):
        next_push_time(10.0, SINGLE, support, phase, earliest=10.1)


def test_schedule_and_table():
    assert forces(80.0, 140.0, 20.0) == [80.0, 100.0, 120.0, 140.0]
    results = [{'direction_deg': d, 'phase': p, 'adjustment': a,
                'largest_withstood_n': 100.0 + d + (50.0 if a else 0.0)}
               for d in (0, 90) for p in PHASES for a in (False, True)]
    text = table(results)
    assert '| 90 deg | 190 / 240 |' in text
    assert '| minimum | 100 / 150 N' in text
    assert 'no walk' not in text


def test_a_trial_without_a_push_is_no_figure_but_a_fall_before_one_is_zero():
    results = [{'direction_deg': d, 'phase': 'early_single', 'adjustment': True,
                'largest_withstood_n': 0.0 if d else 140.0, 'pushes': [] if d else [{}],
                'fallen': d == 90} for d in (0, 45, 90)]
    text = table(results)
    assert '| 45 deg | no walk |' in text and '| 90 deg | 0 |' in text
    assert '| minimum | 0 N' in text and '1 trial(s) made no push' in text
    results[2]['fallen'] = False
    assert '| minimum | 140 N' in table(results)


def test_a_push_is_walked_through_when_the_robot_stands_at_the_next_one():
    from biped_tools.scenarios.push_directions import outcome
    pushes = [{'force_n': f, 'at_s': at} for f, at in ((80, 3.0), (110, 6.0), (140, 9.0))]
    assert outcome(pushes, None) == ([80, 110, 140], None)
    assert outcome(pushes, 10.0) == ([80, 110], 140)
    assert outcome(pushes, 7.0) == ([80], 110)
    # fell after 110 N's window closed but before 140 N started: 110 N felled it
    assert outcome(pushes, 8.9) == ([80], 110)
    assert outcome(pushes, 2.0) == ([], None)  # down before any push


def test_a_push_meets_the_phase_that_began_before_it_not_the_one_last_reported():
    """The double support began at 10.3 s; its record came at 10.38 s (the state machine's
    timer): a push at 10.3 s meets the double support."""
    from biped_msgs.msg import WalkingState
    from biped_tools.scenarios.push_directions import phase_at
    states = [(9.95, WalkingState.SINGLE_SUPPORT, 7, False, '', 1, 0.05),
              (10.38, WalkingState.DOUBLE_SUPPORT, 7, False, '', 2, 0.08)]
    assert phase_at(states, 10.3) == 'double, step 7'
    assert phase_at(states, 10.2) == 'single right, step 7'
    assert phase_at(states, 9.8) == 'before the walk'


def test_a_repeated_cell_is_its_median_run_and_a_run_without_a_push_does_not_count():
    runs = [{'largest_withstood_n': f, 'pushes': [{}] if f is not None else [], 'fallen': False,
             'run': k} for k, f in enumerate((140.0, 80.0, None, 110.0, 170.0))]
    runs[2]['largest_withstood_n'] = 0.0
    cell = median_run(runs)
    assert cell['run'] == 3 and cell['largest_withstood_n'] == 110.0  # of 80, 110, 140, 170
    assert cell['repeats_withstood_n'] == [140.0, 80.0, None, 110.0, 170.0]
    assert median_run([runs[0]])['repeats_withstood_n'] == [140.0]


def test_the_planned_landing_comes_from_the_plan_stamped_before_an_adjustment_that_overtook_it():
    """Under load the plan that made the pushed step can reach the runner after the step's
    adjustment (a CI run): its planned landing is then found by stamp, not reported as moved 0."""
    from types import SimpleNamespace
    from builtin_interfaces.msg import Time
    from biped_msgs.msg import Footstep, FootstepPlan, StepAdjustment
    from std_msgs.msg import Header
    from biped_tools.scenarios.push_directions import adjustment_records

    def plan(stamp, last_y):
        steps = [Footstep(y=0.07 * (-1) ** k) for k in range(7)] + [Footstep(y=last_y)]
        return FootstepPlan(header=Header(stamp=Time(sec=stamp)), plan_id=1, footsteps=steps)
    extended, republished = plan(12, -0.07), plan(13, -0.097)
    adjustment = StepAdjustment(header=Header(stamp=Time(sec=13)), plan_id=1, revision=1,
                                step_index=5, footsteps=list(republished.footsteps))
    # the extension received before the adjustment, or after it; or the planner's republish of
    # the adjustment received before the adjustment itself as well
    for plans_before in (1, 0, 2):
        series = SimpleNamespace(adjustments=[adjustment], plans_before_adjustment=[plans_before],
                                 plans=[extended, republished])
        first = adjustment_records(series, 0.0)['steps'][0]
        assert first['planned_landing'] == (0.0, -0.07)
        assert first['landing'] == (0.0, -0.097)


def test_the_longest_flight_after_each_push_comes_from_both_ankles():
    from biped_tools.scenarios.push_directions import longest_flights
    times = [round(0.02 * k, 2) for k in range(20)]
    left = [(t, 100.0) for t in times]
    right = [(t, 100.0) for t in times]
    for k in (5, 6, 7):           # after the first push: 60 ms in the air
        left[k] = (times[k], -8.0)
        right[k] = (times[k], 10.0)  # below the contact force: not on the ground
    left[14] = (times[14], -8.0)  # one foot up, the other down: a step, not a flight
    assert longest_flights((left, right), [0.04, 0.2], 0.4) == pytest.approx([0.06, 0.0])
    assert longest_flights((left, right), [0.14], 0.4) == pytest.approx([0.02])  # cycle 7
    assert longest_flights(([], []), [0.04], 0.4) == [0.0]


def test_a_push_walked_through_in_the_air_ends_the_grounded_figure():
    from biped_tools.scenarios.push_directions import largest_grounded
    pushes = [{'force_n': f, 'longest_flight_s': flight}
              for f, flight in ((80, 0.0), (110, 0.02), (140, 0.3), (170, 0.0))]
    assert largest_grounded(pushes, [80, 110, 140, 170]) == 110  # 20 ms: one cycle, a flicker
    assert largest_grounded(pushes, [80]) == 80  # 110 N felled it
    assert largest_grounded(pushes, []) == 0.0
    results = [{'direction_deg': 0, 'phase': 'double', 'adjustment': a,
                'largest_withstood_n': 170.0, 'largest_grounded_n': 110.0 if a else 80.0}
               for a in (False, True)]
    assert '| minimum on the ground | 80 / 110 N' in table(results)
    del results[0]['largest_grounded_n']  # a table of older results: no such line
    assert 'on the ground' not in table(results)
