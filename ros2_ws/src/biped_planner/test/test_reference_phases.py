"""Tests of biped_planner.reference_phases: the timeline and ZMP knots of a plan."""
import numpy as np
import pytest

from biped_planner.footsteps import straight_footsteps
from biped_planner.reference_params import ReferenceParams
from biped_planner.reference_phases import (NO_SWING, PHASE_DOUBLE_SUPPORT, PHASE_FINAL_SETTLE,
                                            PHASE_INITIAL_SHIFT, PHASE_SINGLE_SUPPORT,
                                            PHASE_STAND, PhaseTable, plan_phases)
from biped_planner.sides import SUPPORT_DOUBLE
from biped_planner.step_timing import StepTiming

PARAMS = ReferenceParams()
TIMING = StepTiming(0.4, 0.1)


def plan(n_steps=3, **kwargs):
    footsteps = straight_footsteps(n_steps, 0.1, 0.2)
    arguments = dict(first_step=0, t_begin=2.0, start_zmp=np.zeros(2), stand_until=None,
                     yaws=None)
    arguments.update(kwargs)
    return footsteps, plan_phases(footsteps, [TIMING] * (len(footsteps) - 2), PARAMS,
                                  **arguments)


def test_a_walk_from_standing_is_shift_steps_and_settle_without_gaps():
    footsteps, rows = plan()
    kinds = [phase.kind for phase in rows.phases]
    n_steps = len(footsteps) - 2
    assert kinds == [PHASE_INITIAL_SHIFT] + [PHASE_SINGLE_SUPPORT, PHASE_DOUBLE_SUPPORT] * (
        n_steps - 1) + [PHASE_SINGLE_SUPPORT, PHASE_FINAL_SETTLE]
    assert rows.phases[0].t_begin == 2.0
    for before, after in zip(rows.phases[:-1], rows.phases[1:]):
        assert after.t_begin == pytest.approx(before.t_end)
    durations = {PHASE_INITIAL_SHIFT: PARAMS.initial_shift_time,
                 PHASE_SINGLE_SUPPORT: TIMING.single_support,
                 PHASE_DOUBLE_SUPPORT: TIMING.double_support,
                 PHASE_FINAL_SETTLE: PARAMS.final_settle_time}
    for phase in rows.phases:
        assert phase.t_end - phase.t_begin == pytest.approx(durations[phase.kind])
        assert (phase.swing_side == NO_SWING) == (phase.support == SUPPORT_DOUBLE)


def test_knots_increase_and_the_free_knots_sit_in_the_shift_and_the_settle():
    _, rows = plan()
    assert np.all(np.diff(rows.knot_times) > 0.0)
    assert len(rows.free_knots) == 2
    first, last = (rows.knot_times[i] for i in rows.free_knots)
    shift, settle = rows.phases[0], rows.phases[-1]
    assert shift.t_begin < first < shift.t_end and settle.t_begin < last < settle.t_end
    assert rows.knot_times[-1] == pytest.approx(settle.t_end)


def test_a_stand_comes_first_when_asked():
    _, rows = plan(stand_until=2.5)
    assert rows.phases[0].kind == PHASE_STAND and rows.phases[0].t_end == 2.5
    assert rows.phases[1].kind == PHASE_INITIAL_SHIFT


def test_phase_table_keeps_the_first_phases_of_the_previous_one():
    _, rows = plan()
    table = PhaseTable.from_rows(rows)
    assert table.t0.shape == (len(rows.phases),) and table.feet_start.shape == (
        len(rows.phases), 6)
    np.testing.assert_allclose(table.rate, [1.0 / (p.t_end - p.t_begin) for p in rows.phases])
    joined = PhaseTable.from_rows(rows, keep=2, previous=table)
    assert joined.phases[:2] == table.phases[:2] and len(joined.phases) == 2 + len(rows.phases)
    assert joined.yaws_at(0) == (0.0, 0.0) and table.final_yaws() == (0.0, 0.0)
