"""The definition of a withstood push and the bisection for the largest one."""
import pytest

from biped_mpc.three_mass_model import three_mass_model
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.model_walk import run_walk, WalkSetup
from biped_sim.push_recovery import (
    evaluate_push, largest_withstood_force, PushOutcome, WithstandCriteria)

MODEL = three_mass_model()


def pushed_walk(reference, force):
    push = ExternalPush((force, 0.0, 0.0), duration=0.1, start_time=1.6)
    setup = WalkSetup(controller_model=MODEL, plant_model=MODEL, push=push,
                      polygon_margin=(0.005, 0.004))
    return run_walk(reference, setup), push


def test_small_push_is_withstood(paper_reference):
    log, push = pushed_walk(paper_reference, 100.0)
    outcome = evaluate_push(log, push)
    assert outcome.withstood, outcome.failures
    assert outcome.metrics['max_leg_error'] < 0.15
    assert outcome.metrics['final_com_error'] < 0.05


def test_huge_push_is_not_withstood_and_says_why(paper_reference):
    log, push = pushed_walk(paper_reference, -1500.0)
    outcome = evaluate_push(log, push)
    assert not outcome.withstood
    assert any('leg mass' in failure for failure in outcome.failures)


def threshold_judge(threshold_positive, threshold_negative, calls):
    def outcome_of(force):
        calls.append(force)
        limit = threshold_positive if force >= 0 else threshold_negative
        return PushOutcome((force, 0.0), abs(force) <= limit, ())
    return outcome_of


@pytest.mark.parametrize('sign, expected', [(1.0, 437.0), (-1.0, 391.0)])
def test_bisection_brackets_the_threshold(sign, expected):
    calls = []
    best, outcomes = largest_withstood_force(threshold_judge(437.0, 391.0, calls), sign,
                                             initial=100.0, limit=3000.0, resolution=5.0)
    assert expected - 5.0 <= best <= expected
    assert len(outcomes) == len(calls) < 20
    assert all(f * sign >= 0 for f in calls)


def test_bisection_stops_at_zero_and_at_the_limit():
    best, outcomes = largest_withstood_force(threshold_judge(-1.0, -1.0, []), 1.0)
    assert best == 0.0 and len(outcomes) == 1
    best, _ = largest_withstood_force(threshold_judge(1e9, 1e9, []), 1.0, limit=800.0)
    assert best == 800.0


@pytest.mark.parametrize('kwargs', [dict(sign=0.5), dict(sign=1.0, initial=0.0),
                                    dict(sign=1.0, resolution=0.0),
                                    dict(sign=1.0, initial=500.0, limit=100.0)])
def test_bad_search_arguments_raise(kwargs):
    with pytest.raises(ConfigError):
        largest_withstood_force(lambda f: None, **kwargs)


@pytest.mark.parametrize('field, value', [('recovery_time', -1.0), ('zmp_tolerance', 0.5),
                                          ('leg_error', 0.0), ('final_com_speed', float('nan'))])
def test_bad_criteria_raise(field, value):
    with pytest.raises(ConfigError, match=field):
        WithstandCriteria(**{field: value})
