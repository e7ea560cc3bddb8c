import math

import pytest

from biped_planner.errors import CommandError, ConfigError
from biped_planner.walking_state_machine import (EARLY_REASON, MOVED_REASON, Phase,
                                                 StateMachineParams, Support,
                                                 WalkingStateMachine)

PARAMS = StateMachineParams(initialize_duration=1.0, single_support=0.4, double_support=0.1,
                            first_support=Support.RIGHT)


def run(machine, t_end, dt=0.001, t0=0.0):
    """Advance in small ticks and collect every transition."""
    transitions = []
    steps = int(round((t_end - t0) / dt))
    for k in range(1, steps + 1):
        transitions += machine.update(t0 + k * dt)
    return transitions


def test_start_runs_initialize_then_alternating_supports_with_configured_timing():
    machine = WalkingStateMachine(PARAMS)
    assert machine.status.phase == Phase.IDLE
    first = machine.request_start(0.0)
    assert [s.phase for s in first] == [Phase.INITIALIZE]
    transitions = run(machine, 2.5)
    phases = [s.phase for s in transitions]
    assert phases[:6] == [Phase.SINGLE_SUPPORT, Phase.DOUBLE_SUPPORT] * 3
    starts = [s.phase_start for s in transitions]
    # exact boundaries: Initialize 1.0 s, then 0.4 s single + 0.1 s double support per step
    assert starts[:5] == pytest.approx([1.0, 1.4, 1.5, 1.9, 2.0], abs=1e-12)
    supports = [s.support for s in transitions if s.phase == Phase.SINGLE_SUPPORT]
    assert supports[:3] == [Support.RIGHT, Support.LEFT, Support.RIGHT]
    assert all(s.support == Support.DOUBLE for s in transitions if s.phase ==
               Phase.DOUBLE_SUPPORT)
    assert [s.step_index for s in transitions if s.phase == Phase.SINGLE_SUPPORT][:3] == [0, 1, 2]


def test_a_large_time_jump_yields_every_transition_in_order():
    machine = WalkingStateMachine(PARAMS)
    machine.request_start(0.0)
    transitions = machine.update(2.05)
    assert [s.phase_start for s in transitions] == pytest.approx([1.0, 1.4, 1.5, 1.9, 2.0])


def test_stop_in_single_support_finishes_the_step_into_double_support_then_idle():
    machine = WalkingStateMachine(PARAMS)
    machine.request_start(0.0)
    run(machine, 1.2)
    assert machine.status.phase == Phase.SINGLE_SUPPORT
    assert machine.request_stop(1.2) == []
    assert machine.status.stop_requested
    transitions = run(machine, 2.0, t0=1.2)
    assert [s.phase for s in transitions] == [Phase.DOUBLE_SUPPORT, Phase.IDLE]
    assert transitions[-1].phase_start == pytest.approx(1.5)
    assert transitions[-1].step_index == 1
    assert not machine.status.stop_requested


def test_stop_during_initialize_returns_to_idle_at_once_and_start_cancels_a_pending_stop():
    machine = WalkingStateMachine(PARAMS)
    machine.request_start(0.0)
    assert [s.phase for s in machine.request_stop(0.5)] == [Phase.IDLE]
    machine.request_start(1.0)
    run(machine, 2.2, t0=1.0)
    machine.request_stop(2.2)
    machine.request_start(2.25)
    assert not machine.status.stop_requested
    transitions = run(machine, 4.0, t0=2.25)
    assert Phase.IDLE not in [s.phase for s in transitions]


def test_plan_with_n_steps_ends_in_idle_after_the_last_double_support():
    machine = WalkingStateMachine(PARAMS)
    machine.set_plan(3, first_support=Support.LEFT)
    machine.request_start(0.0)
    transitions = run(machine, 5.0)
    singles = [s for s in transitions if s.phase == Phase.SINGLE_SUPPORT]
    assert [s.support for s in singles] == [Support.LEFT, Support.RIGHT, Support.LEFT]
    assert transitions[-1].phase == Phase.IDLE
    assert transitions[-1].reason == 'plan finished'
    assert transitions[-1].phase_start == pytest.approx(1.0 + 3 * 0.5)


def test_fall_from_any_phase_blocks_start_until_reset():
    machine = WalkingStateMachine(PARAMS)
    machine.request_start(0.0)
    run(machine, 1.45)
    fall = machine.report_fall(1.45, 'test')
    assert [s.phase for s in fall] == [Phase.FALLEN] and machine.status.fallen
    assert machine.report_fall(1.5) == []
    assert machine.update(10.0) == []
    with pytest.raises(CommandError, match='fallen'):
        machine.request_start(10.0)
    assert [s.phase for s in machine.reset(11.0)] == [Phase.IDLE]
    assert [s.phase for s in machine.request_start(12.0)] == [Phase.INITIALIZE]


def test_timing_change_applies_from_the_next_phase():
    machine = WalkingStateMachine(PARAMS)
    machine.request_start(0.0)
    run(machine, 1.1)
    machine.set_step_time(1.0)  # keeps the 4:1 ratio: 0.8 s + 0.2 s
    transitions = run(machine, 3.0, t0=1.1)
    starts = [s.phase_start for s in transitions]
    assert starts[:3] == pytest.approx([1.4, 1.6, 2.4])


@pytest.mark.parametrize('field, value', [
    ('initialize_duration', -1.0), ('single_support', math.nan), ('double_support', 0.0),
    ('single_support', 99.0), ('first_support', 2)])
def test_bad_parameters_raise_config_error_naming_the_field(field, value):
    with pytest.raises(ConfigError, match=field):
        StateMachineParams(**{field: value})


@pytest.mark.parametrize('step_time', [math.nan, -0.5, 0.0, math.inf])
def test_bad_step_time_is_a_command_error(step_time):
    machine = WalkingStateMachine(PARAMS)
    with pytest.raises(CommandError, match='step_time'):
        machine.set_step_time(step_time)
    assert machine.single_support == 0.4


def test_every_reset_starts_a_new_epoch_in_idle_and_none_happens_while_walking():
    machine = WalkingStateMachine(PARAMS)
    assert machine.status.epoch == 0
    standing = machine.reset(0.5)  # a standing robot is re-initialised too
    assert [(s.phase, s.epoch, s.reason) for s in standing] == [(Phase.IDLE, 1, 'reset')]
    machine.request_start(1.0)
    for t in (1.5, 2.2, 2.45):  # Initialize, single support, double support
        run(machine, t, t0=machine.status.phase_start)
        with pytest.raises(CommandError, match='cannot reset while walking'):
            machine.reset(t)
        assert machine.status.epoch == 1
    machine.report_fall(2.5, 'pushed')
    after = machine.reset(3.0)
    assert [(s.phase, s.epoch, s.step_index) for s in after] == [(Phase.IDLE, 2, 0)]
    assert after[0].reason == 'reset after a fall'


def test_an_unplanned_stop_ends_a_planned_walk_after_the_current_step():
    machine = WalkingStateMachine(PARAMS)
    machine.set_plan(None, planned=True)
    machine.request_start(0.0)
    run(machine, 1.2)  # single support of step 0
    machine.request_stop(1.2, 'planner silent', unplanned=True)
    assert machine.status.reason == 'planner silent'
    phases = [(s.phase, s.step_index) for s in run(machine, 3.0, t0=1.2)]
    assert phases == [(Phase.DOUBLE_SUPPORT, 0), (Phase.IDLE, 1)]


def test_a_planned_walk_ignores_a_plain_stop_until_its_plan_ends():
    machine = WalkingStateMachine(PARAMS)
    machine.set_plan(None, planned=True)
    machine.request_start(0.0)
    run(machine, 1.2)
    machine.request_stop(1.2)
    assert all(s.phase != Phase.IDLE for s in run(machine, 3.0, t0=1.2))


def test_an_adjusted_touchdown_moves_the_end_of_that_single_support_only():
    """The step adjuster's new touchdown ends the single support; the later phases keep their
    durations (as in the adjusted reference)."""
    machine = WalkingStateMachine(PARAMS)
    machine.request_start(0.0)
    run(machine, 1.55)  # single support of step 1: 1.5 .. 1.9 s
    assert machine.status.phase == Phase.SINGLE_SUPPORT and machine.status.step_index == 1
    assert not machine.retime_single_support(0, 1.7)  # not the step under way
    assert machine.status.phase_duration == pytest.approx(0.4)
    assert machine.retime_single_support(1, 1.75)
    assert machine.status.reason == MOVED_REASON
    assert machine.retime_single_support(1, 1.75, EARLY_REASON)  # an early landing: the same
    assert machine.status.reason == EARLY_REASON
    transitions = run(machine, 2.5, t0=1.55)
    assert [s.phase_start for s in transitions[:3]] == pytest.approx([1.75, 1.85, 2.25],
                                                                     abs=1e-9)
    assert [s.phase for s in transitions[:3]] == [Phase.DOUBLE_SUPPORT, Phase.SINGLE_SUPPORT,
                                                  Phase.DOUBLE_SUPPORT]
    assert not machine.retime_single_support(machine.status.step_index, 0.5)  # before start


def test_a_late_landing_holds_the_single_support_from_its_double_support():
    """The hold comes after the planned landing, once the timer began the double support:
    the single support starts again and ends at the held touchdown; the touchdown that ends
    the hold early is taken the same way."""
    machine = WalkingStateMachine(PARAMS)
    machine.request_start(0.0)
    run(machine, 1.92)  # step 1: single support 1.5 .. 1.9 s, double support from 1.9 s
    assert machine.status.phase == Phase.DOUBLE_SUPPORT and machine.status.step_index == 1
    assert not machine.hold_single_support(0, 2.1)  # not the step under way
    assert machine.hold_single_support(1, 2.1)
    status = machine.status
    assert (status.phase, status.step_index) == (Phase.SINGLE_SUPPORT, 1)
    assert status.support == machine.support_of_step(1)
    assert status.phase_start == pytest.approx(1.9)
    assert status.phase_start + status.phase_duration == pytest.approx(2.1)
    assert machine.hold_single_support(1, 1.981)  # the foot met the ground
    transitions = run(machine, 2.6, t0=1.92)
    assert [s.phase for s in transitions[:3]] == [Phase.DOUBLE_SUPPORT, Phase.SINGLE_SUPPORT,
                                                  Phase.DOUBLE_SUPPORT]
    assert [s.phase_start for s in transitions[:3]] == pytest.approx([1.981, 2.081, 2.481],
                                                                     abs=1e-9)
    assert transitions[1].step_index == 2
    assert not machine.hold_single_support(machine.status.step_index, 0.5)  # before start


@pytest.mark.parametrize('retime', ['retime_single_support', 'hold_single_support'])
@pytest.mark.parametrize('end', [math.nan, math.inf])
def test_a_non_finite_adjusted_or_held_touchdown_is_a_command_error(retime, end):
    machine = WalkingStateMachine(PARAMS)
    machine.request_start(0.0)
    run(machine, 1.1)
    with pytest.raises(CommandError):
        getattr(machine, retime)(0, end)
    assert machine.status.phase_duration == pytest.approx(0.4)
