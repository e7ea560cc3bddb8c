"""Step adjustment on the PyBullet humanoid: a lateral push that falls without it is survived."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from biped_mpc.walking_controller import WalkingController, WalkingControllerParams
from biped_planner.sides import SUPPORT_RIGHT
from biped_sim import push_trial
from biped_sim.errors import ConfigError
from biped_sim.push_trial import (HUMANOID_ADJUSTER, HUMANOID_STEP_LIMITS, PHASES, push_start,
                                  PushScheduleResult, RECOVERY_SWING_LAG,
                                  run_push_schedule, run_push_trial, SCHEDULE_FIRST_PUSH,
                                  T_START, TIMING, walk_in_place_reference, walk_reference)
from biped_sim.pybullet_backend import PyBulletBackend, PyBulletConfig
from biped_sim.robot_description import coman_like

# N for 100 ms towards the swing side, early in a right single support: with the Bezier swing,
# fresh simulators, off falls and on walks from 160 to 180 N (150 N: off walks, 200 N: both fall)
LATERAL_FORCE = 170.0


@pytest.fixture(scope='module')
def robot():
    return coman_like()


def trial(robot, adjuster):
    """One push in a fresh simulator (a run depends on what the simulator ran before)."""
    sim = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
    try:
        controller = WalkingController(WalkingControllerParams(
            robot=robot.controller_model, balance='stabilizer', swing_target='planned',
            swing_smoothing_time_constant=RECOVERY_SWING_LAG))
        return run_push_trial(sim, controller, robot.controller_model, LATERAL_FORCE,
                              math.radians(90.0), 'early_single', adjuster)
    finally:
        sim.close()


def test_lateral_push_falls_without_and_is_survived_with_step_adjustment(robot):
    fixed = trial(robot, None)
    assert fixed.fallen and fixed.revisions == 0
    adjusted = trial(robot, HUMANOID_ADJUSTER)
    assert not adjusted.fallen
    # answered decisively: the pushed step is replanned at most twice
    assert 1 <= adjusted.revisions
    pushed_step = [a for t, a in adjusted.adjustments
                   if adjusted.push.start_time <= t < adjusted.push.start_time + 0.3]
    assert 1 <= len(pushed_step) <= HUMANOID_ADJUSTER.max_replans_per_step
    # the left (swing) foot landed further out towards the push than planned (0.07 m)
    assert pushed_step[-1].location[1] > 0.07 + 0.03


@pytest.mark.parametrize('phase', tuple(PHASES))
def test_push_starts_in_its_phase(phase):
    reference = walk_in_place_reference()
    start = push_start(reference, phase)
    assert start >= 2.0
    support, delay = PHASES[phase]
    kind = 'double_support' if support is None else 'single_support'
    begins = [p.t_begin for p in reference.phases if p.kind == kind
              and (support is None or p.support == support)]
    assert min(abs(start - delay - b) for b in begins) < 1e-9
    if phase == 'late_single':
        # the push ends at touchdown
        assert any(abs(start + 0.1 - (b + TIMING.single_support)) < 1e-9 for b in begins)
    if phase == 'early_single':
        assert support == SUPPORT_RIGHT and delay == pytest.approx(0.075)


def schedule(robot, forces, interval=3.0, phase_offset=0.0, phase='early_single'):
    sim = PyBulletBackend(robot, PyBulletConfig(leg_kp=2000.0))
    try:
        controller = WalkingController(WalkingControllerParams(
            robot=robot.controller_model, balance='stabilizer', swing_target='planned',
            swing_smoothing_time_constant=RECOVERY_SWING_LAG))
        return run_push_schedule(sim, controller, robot.controller_model, forces, 0.0,
                                 phase, interval=interval, phase_offset=phase_offset)
    finally:
        sim.close()


def test_a_schedule_pushes_at_its_phase_every_interval_until_a_fall(robot):
    calm = schedule(robot, (0.0, 0.0, 0.0), interval=2.0)
    assert math.isnan(calm.fall_time)
    assert calm.largest_withstood == 0.0 and calm.forces == (0.0, 0.0, 0.0)
    times = np.array(calm.push_times)
    assert times[0] >= T_START + SCHEDULE_FIRST_PUSH
    # each push is due `interval` after the one before, and meets the next right single support
    step = TIMING.single_support + TIMING.double_support
    assert np.all(np.diff(times) >= 2.0 - 1e-9) and np.all(np.diff(times) < 2.0 + 2 * step)
    plan = walk_reference(0.0, 40)
    delay = PHASES['early_single'][1]
    assert all(push_start(plan, 'early_single', after=t - delay - 1e-6) == pytest.approx(t)
               for t in times)
    assert calm.flights == (0.0, 0.0, 0.0)  # a walk has a foot on the ground at every cycle
    # a push no robot withstands ends the schedule: the force before it is the figure
    felled = schedule(robot, (40.0, 2000.0, 40.0), interval=2.0)
    assert felled.forces == (40.0, 2000.0) and felled.largest_withstood == 40.0
    assert felled.push_times[1] < felled.fall_time < felled.push_times[1] + 2.0
    assert len(felled.flights) == 2 and felled.largest_grounded() == 40.0


class _FallingRunner:
    """Test double of ClosedLoopRunner: its robot falls at FALL_TIME whatever is pushed."""

    FALL_TIME = math.inf

    def __init__(self, backend, controller, source) -> None:
        self.backend = backend

    def reset(self) -> None:
        self.backend.time = 0.0

    def push(self, push) -> None:
        pass

    def run(self, duration, on_cycle=None):
        end = self.backend.time + duration
        fallen = end >= self.FALL_TIME
        self.backend.time = min(end, self.FALL_TIME)
        return SimpleNamespace(fallen=fallen, fall_time=self.FALL_TIME if fallen else math.nan,
                               longest_flight=lambda start: 0.0)


def test_a_fall_before_a_push_begins_is_the_previous_push_s(monkeypatch):
    monkeypatch.setattr(push_trial, 'ClosedLoopRunner', _FallingRunner)

    def pushed(fall_time):
        monkeypatch.setattr(_FallingRunner, 'FALL_TIME', fall_time)
        return run_push_schedule(SimpleNamespace(time=0.0), None, None, (80.0, 110.0, 140.0),
                                 0.0, 'early_single')
    times = pushed(math.inf).push_times
    # the robot falls 2.5 s after the 80 N push, when its run has ended (1 s before the next
    # push is due) and before the 110 N push starts: 80 N felled it
    early = pushed(times[0] + 2.5)
    assert early.forces == (80.0,) and early.largest_withstood == 0.0
    assert early.largest_grounded() == 0.0
    # a fall after the 110 N push began is that push's
    late = pushed(times[1] + 0.5)
    assert late.forces == (80.0, 110.0) and late.largest_withstood == 80.0


def test_a_push_that_throws_the_robot_off_the_ground_is_no_grounded_recovery():
    def result(flights, fall_time=math.nan):
        forces = (80.0, 110.0, 140.0)[:len(flights)]
        return PushScheduleResult(forces, (3.0, 6.0, 9.0)[:len(flights)], fall_time,
                                  max(forces), 0, (), tuple(flights))
    assert result((0.0, 0.02, 0.0)).largest_grounded() == 140.0  # one cycle: a flicker
    assert result((0.0, 0.04, 0.0)).largest_grounded() == 80.0
    assert result((0.06, 0.0, 0.0)).largest_grounded() == 0.0
    assert result((0.0, 0.04, 0.0)).largest_grounded(max_flight=0.05) == 140.0
    assert result((0.0, 0.0, 0.0), fall_time=9.5).largest_grounded() == 110.0


@pytest.mark.parametrize('offset', [0.03, -0.03])
def test_a_phase_offset_moves_each_scheduled_push_by_itself(robot, offset):
    # double supports begin every 0.4 s: with an interval of five steps a push's due time falls
    # on the start of one, where an offset carried into the schedule would move the next push
    # by a whole step
    calm = schedule(robot, (0.0, 0.0, 0.0), interval=2.0, phase='double')
    moved = schedule(robot, (0.0, 0.0, 0.0), interval=2.0, phase_offset=offset, phase='double')
    assert np.allclose(np.array(moved.push_times) - calm.push_times, offset, atol=1e-9)


def test_bad_trials_are_rejected():
    with pytest.raises(ConfigError):
        push_start(walk_in_place_reference(), 'mid_air')
    with pytest.raises(ConfigError):
        push_start(walk_in_place_reference(4), 'double', after=100.0)
    with pytest.raises(ConfigError):
        run_push_trial(None, None, None, -1.0, 0.0, 'double')
    with pytest.raises(ConfigError):
        run_push_schedule(None, None, None, (80.0, math.nan), 0.0, 'double')
    with pytest.raises(ConfigError):
        run_push_schedule(None, None, None, (80.0,), 0.0, 'double', interval=1.0)
    for offset in (0.06, -0.06, math.nan):
        with pytest.raises(ConfigError):
            run_push_schedule(None, None, None, (80.0,), 0.0, 'double', phase_offset=offset)


def graph_defaults(prefix: str) -> dict:
    """The reference generator node's YAML defaults under prefix (e.g. 'step_adjustment.')."""
    import pathlib
    import yaml
    path = pathlib.Path(__file__).resolve().parents[2] / 'biped_planner' / 'config' / \
        'reference_generator.yaml'
    parameters = yaml.safe_load(path.read_text())['reference_generator']['ros__parameters']
    return {key[len(prefix):]: value for key, value in parameters.items()
            if key.startswith(prefix)}


def test_the_library_trials_adjust_steps_as_the_graph_does():
    # a library table is read as the graph's: the same adjuster settings and step limits
    adjuster = graph_defaults('step_adjustment.')
    adjuster.pop('enabled')
    assert adjuster, 'no step_adjustment.* defaults found'
    for name, value in adjuster.items():
        assert getattr(HUMANOID_ADJUSTER, name) == value, name
    limits = graph_defaults('step_limits.')
    assert limits, 'no step_limits.* defaults found'
    for name, value in limits.items():
        assert getattr(HUMANOID_STEP_LIMITS, name) == value, name


def test_the_forward_walk_lands_every_step_0_1_m_ahead_at_the_in_place_timing():
    forward, in_place = walk_reference(0.1), walk_in_place_reference()
    landings = [step.x for step in forward.footsteps[2:-1]]
    assert np.allclose(np.diff(landings), 0.1)
    assert [(p.kind, p.t_begin) for p in forward.phases] == \
        [(p.kind, p.t_begin) for p in in_place.phases]
    for phase in PHASES:
        assert push_start(forward, phase) == push_start(in_place, phase)
