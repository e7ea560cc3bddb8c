"""Smoke tests of the paper's scenarios through the real node graph (short horizon, one
setting each); the full sweeps are `scripts/scenarios.py summary`. Each asserts the physical
outcome, read from the run's topics."""
import math

import numpy as np
import pytest

from biped_tools.scenarios import disk, omni, push, terrain
from biped_tools.scenarios.sweep import grid, largest_completing
from biped_tools.scenarios.trial import sample_at, stated_start_time, Trial
from ros_harness import domain_id_for_worker


def trial(tmp_path, scenario, setting, model='three_mass', record=False):
    # node logs go to pytest's captured output: shown when a test fails
    return Trial(scenario, model, setting, tmp_path, domain_id_for_worker(), record=record,
                 log=lambda line: None, node_log=print)


def test_a_quarter_lap_around_the_disk_keeps_near_the_2_m_circle(tmp_path):
    result = disk.run(trial(tmp_path, 'disk', '0.15', record=True), 0.15, laps=0.25)
    assert not result['fallen']
    assert result['swept_deg'] >= 90.0
    assert 2.0 - 0.35 <= result['radius_min_m'] and result['radius_max_m'] <= 2.0 + 0.35
    assert (tmp_path / 'disk' / 'three_mass' / '0.15' / 'bag' / 'metadata.yaml').exists()
    assert (tmp_path / 'disk' / 'three_mass' / '0.15' / 'disk_top_view.png').exists()
    # every node's log, kept beside the result
    node_log = (tmp_path / 'disk' / 'three_mass' / '0.15' / 'nodes.log').read_text()
    assert '[bringup] all nodes up' in node_log
    assert 'reference generator ready' in node_log and 'MPC ready' in node_log


def test_omnidirectional_setpoints_walk_forward_then_diagonally(tmp_path):
    result = omni.run(trial(tmp_path, 'omni', '1.00'), 1.0, duration=14.0)
    assert result['success'] and not result['fallen']
    x, y = result['final_pelvis']
    # 8 s forward at 0.1 m per 0.6 s step (~1.1 m after the lag), then 4 s diagonally
    assert x > 0.9
    assert y > 0.1


def test_the_paper_first_push_is_withstood_while_walking_in_place(tmp_path):
    result = push.run(trial(tmp_path, 'push', '80'), [80.0])
    assert result['largest_withstood_n'] == 80.0 and not result['fallen']
    assert (tmp_path / 'push' / 'three_mass' / '80' / 'push_com_velocity.png').exists()


def test_on_the_paper_tiles_the_robot_starts_on_them_and_its_outcome_is_reported(tmp_path):
    # The paper's 25-50 mm tiles of 100 cm^2, seed 1: the run starts on the tiles and ends at
    # its outcome (not at the time budget), reporting how far it got. Which outcome is not
    # asked: this trial falls in most runs and crossed once in CI (docs/flaky_graph_tests.md;
    # the graph's tile trial is not reproducible to the period); the fall path alone is pinned
    # by test_reproducible_runs.py's fall while the graph comes up on the tiles.
    result = terrain.run(trial(tmp_path, 'terrain', '100cm2'), 100, seed=1, side=2.0)
    assert 0.54 + 0.02 < result['start_pelvis_z'] < 0.54 + 0.06
    assert result['fallen'] != result['success']
    if result['fallen']:
        assert result['simulated_s'] <= result['fall_time_s'] + 0.5
        assert 0.125 < result['terrain_fraction_crossed'] < 1.0  # walked onward first
    else:
        assert result['terrain_fraction_crossed'] == 1.0
        assert result['stop_stated_s'] is not None
        assert result['stop_stated_s'] < result['simulated_s']
    assert (tmp_path / 'terrain' / 'three_mass' / '100cm2' / 'terrain_com_height.png').exists()


# --- the sweep's search, against an exhaustive scan (no graph) -----------------------------
def test_a_terrain_run_that_crosses_stops_at_a_stated_time_after_the_exit(tmp_path):
    # flat "tiles" (height 0 is not built): the success path of the scenario, its final STOP
    # stated from the first pelvis sample past the exit rather than applied when seen
    result = terrain.run(trial(tmp_path, 'terrain', 'flat'), 100, seed=1, side=1.0,
                         heights=(0.0, 0.0))
    assert result['success'] and not result['fallen']
    assert result['distance_m'] >= 1.0 - terrain.BEHIND + terrain.EXIT_MARGIN
    assert result['stop_stated_s'] is not None and result['stop_stated_s'] < result['simulated_s']


@pytest.mark.parametrize('threshold', [None, 0.08, 0.12, 0.2, 0.25])
def test_bisection_finds_the_largest_completing_value(threshold):
    values = grid(0.08, 0.25, 0.01)
    calls = []

    def completes(value, run=0):
        calls.append(value)
        return threshold is not None and value <= threshold + 1e-9
    best, tried = largest_completing(values, completes, first=0.15)
    exhaustive = max((v for v in values if completes(v)), default=None)
    assert best == exhaustive
    assert len(tried) <= math.ceil(math.log2(len(values) + 1)) + 1
    assert tried[0.15] == [threshold is not None and threshold >= 0.15]
    assert all(len(outcomes) == 1 for outcomes in tried.values())


@pytest.mark.parametrize('threshold', [None, 0.08, 0.12, 0.2, 0.25])
def test_repeats_confirm_a_steady_limit_and_the_value_above_it(threshold):
    values = grid(0.08, 0.25, 0.01)
    best, tried = largest_completing(
        values, lambda value, run: threshold is not None and value <= threshold + 1e-9,
        first=0.15, repeats=3)
    assert best == threshold
    limit = values.index(threshold) if threshold is not None else -1
    for index in (limit, limit + 1):
        if 0 <= index < len(values):
            assert len(tried[values[index]]) == 3
    assert sum(len(o) > 1 for o in tried.values()) == sum(0 <= i < len(values)
                                                          for i in (limit, limit + 1))


def scripted(outcomes):
    """completes(value, run) from {value: [outcome of run 0, 1, ...]}; others: value <= 0.12."""
    return lambda value, run: outcomes[value][run] if value in outcomes else value <= 0.12


def test_a_limit_that_passed_once_but_fails_its_repeats_moves_down():
    values = grid(0.08, 0.25, 0.01)  # bisection from 0.15 tries 0.15, 0.11, 0.13, 0.12
    flaky = {0.12: [True, False, False], 0.13: [False, False, False]}
    best, tried = largest_completing(values, scripted(flaky), first=0.15, repeats=3)
    assert best == 0.11
    assert tried[0.12] == [True, False, False] and len(tried[0.11]) == 3
    # one run, as before: the lucky pass is the figure
    assert largest_completing(values, scripted(flaky), first=0.15)[0] == 0.12


def test_a_setting_above_the_limit_whose_repeats_mostly_complete_moves_it_up():
    values = grid(0.08, 0.25, 0.01)
    flaky = {0.13: [False, True, True], 0.14: [False, False, True]}
    best, tried = largest_completing(values, scripted(flaky), first=0.15, repeats=3)
    assert best == 0.13
    assert tried[0.13] == [False, True, True] and tried[0.14] == [False, False, True]


@pytest.mark.parametrize('repeats', [0, 2, -1])
def test_repeats_must_make_a_median(repeats):
    with pytest.raises(ValueError):
        largest_completing([0.1, 0.2], lambda value, run: True, repeats=repeats)


def test_the_push_figure_is_the_median_of_its_runs(monkeypatch):
    figures = iter([(130.0, 140.0), (110.0, 120.0), (130.0, 140.0)])
    names = []

    def fake_run(trial, schedule):
        names.append(trial)
        withstood, fall = next(figures)
        return {'largest_withstood_n': withstood, 'first_fall_force_n': fall, 'success': False}
    monkeypatch.setattr(push, 'run', fake_run)
    result = push.repeated(lambda scenario, setting: f'{scenario}/{setting}', push.forces(), 3)
    assert names == ['push/schedule', 'push/schedule_run2', 'push/schedule_run3']
    assert result['largest_withstood_n'] == 130.0 and result['first_fall_force_n'] == 140.0
    assert [r['largest_withstood_n'] for r in result['runs']] == [130.0, 110.0, 130.0]


def test_grid_is_inclusive_and_rounded():
    assert grid(0.08, 0.25, 0.01) == [round(0.08 + 0.01 * k, 2) for k in range(18)]
    assert grid(0.5, 1.5, 0.05)[-1] == 1.5 and np.all(np.diff(grid(0.5, 1.5, 0.05)) > 0)


def test_push_schedule_is_the_papers():
    assert push.forces(80.0, 160.0) == [80.0, 100.0, 120.0, 130.0, 140.0, 150.0, 160.0]


def test_omni_setpoints_change_at_the_papers_times():
    assert omni.setpoint(1.9, 1.0) == (0.0, 0.0, 0.0)
    assert omni.setpoint(2.0, 1.0) == (0.1, 0.0, 0.0)
    assert omni.setpoint(10.5, 2.0) == (0.2, 0.1, 0.0)
    x, y, alpha = omni.setpoint(25.0, 1.0)
    assert (x, y) == (0.2, 0.05) and alpha == pytest.approx(math.radians(15.0) * 0.6)
    assert omni.setpoint(33.0, 1.0) == (0.0, 0.0, 0.0)


def test_disk_steering_follows_the_tangent_and_corrects_the_radius():
    steering = disk.CircleSteering(0.15)
    # on the circle, straight below the centre, heading along +x (the tangent): a gentle left
    # turn of L / R per step
    x, y, turn = steering.command((0.0, 1.8 - 2.0), 0.0)
    assert (x, y) == (0.15, 0.0) and turn == pytest.approx(0.15 / 2.0)
    # inside the circle: turn less (lean outward); outside: turn more
    assert steering.command((0.0, 1.8 - 1.7), 0.0)[2] < turn
    assert steering.command((0.0, 1.8 - 2.3), 0.0)[2] > turn


def test_the_lap_counter_foretells_the_end_of_the_lap_from_the_sweep_so_far():
    centre, radius = np.array(disk.DISK_CENTRE), disk.CIRCLE_RADIUS
    start = centre + [0.0, -radius]
    lap = disk.LapCounter(start)
    rate = 2.0 * math.pi / 40.0  # rad/s: a lap in 40 s
    for k in range(1, 1001):  # 20 s, half a lap, at 50 Hz
        t = 0.02 * k
        angle = -0.5 * math.pi + rate * t
        lap.update(centre + radius * np.array([math.cos(angle), math.sin(angle)]), t)
    assert lap.time_left(20.0, 1.0) == pytest.approx(20.0, rel=1e-6)
    assert lap.time_left(10.0, 1.0) == pytest.approx(30.0, rel=1e-6)  # only the updates to t
    assert lap.time_left(20.0, 0.5) == pytest.approx(0.0, abs=1e-6)
    assert lap.time_left(0.5, 1.0) == math.inf  # less than the rate window seen
    still = disk.LapCounter(start)
    for k in range(100):
        still.update(start, 0.02 * k)
    assert still.time_left(1.98, 1.0) == math.inf


def test_sample_at_takes_the_last_sample_stamped_at_or_before_a_time():
    samples = [(1.0, 'a'), (1.02, 'b'), (1.04, 'c')]
    assert sample_at(samples, 1.02) == (1.02, 'b')
    assert sample_at(samples, 1.039) == (1.02, 'b')
    assert sample_at(samples, 5.0) == (1.04, 'c')
    assert sample_at(samples, 0.99) is None and sample_at([], 1.0) is None


def test_the_stated_start_is_ten_seconds_or_the_next_multiple_with_the_margin():
    assert stated_start_time(0.0) == stated_start_time(7.99) == 10.0
    assert stated_start_time(8.01) == 20.0


def test_a_fall_is_timed_from_the_state_machine_not_from_when_the_runner_looked():
    """The first walking_state the runner receives may come after the fall (a robot that fell
    while the graph came up): its time is the FALLEN phase's start, stamp - time_in_phase."""
    from types import SimpleNamespace

    from biped_msgs.msg import WalkingState
    from biped_tools.scenarios.trial import fall_time
    fell_at_1_5 = [(4.52, WalkingState.FALLEN, 0, True, 'fell', 2, 3.02),
                   (4.54, WalkingState.FALLEN, 0, True, 'fell', 2, 3.04)]
    standing = (4.50, WalkingState.IDLE, 0, False, '', 2, 4.5)
    assert fall_time(SimpleNamespace(series=SimpleNamespace(states=fell_at_1_5))) == \
        pytest.approx(1.5)
    assert fall_time(SimpleNamespace(series=SimpleNamespace(states=[standing]))) is None
