"""Tests of biped_planner.step_timing."""
import math

import pytest

from biped_planner.errors import ConfigError
from biped_planner.step_timing import StepTiming, StepTimingLimits, timing_for_speed


def test_step_time_is_the_sum():
    timing = StepTiming(0.35, 0.15)
    assert timing.step_time == pytest.approx(0.5)


@pytest.mark.parametrize('kwargs', [
    dict(single_support=0.0), dict(single_support=-0.4), dict(single_support=math.nan),
    dict(double_support=0.0), dict(double_support=math.inf), dict(double_support=6.0),
    dict(single_support=True), dict(double_support='0.1')])
def test_step_timing_rejects_bad_values(kwargs):
    with pytest.raises(ConfigError):
        StepTiming(**kwargs)


@pytest.mark.parametrize('kwargs', [
    dict(min_step_time=0.05), dict(max_step_time=0.2), dict(nominal_step_time=2.0),
    dict(double_support_ratio=0.9), dict(min_double_support=0.2),
    dict(double_support_ratio=math.nan)])
def test_limits_reject_bad_values(kwargs):
    with pytest.raises(ConfigError):
        StepTimingLimits(**kwargs)


@pytest.mark.parametrize('step_length, speed, expected_step_time', [
    (0.1, 0.2, 0.5),      # inside the limits: exactly step_length / speed
    (0.1, 1.0, 0.3),      # too fast: clipped to min_step_time
    (0.2, 0.05, 1.5),     # too slow: clipped to max_step_time
    (-0.1, 0.25, 0.4),    # walking backwards uses |step_length|
    (0.0, 0.3, 0.5),      # in place: nominal
    (0.1, 0.0, 0.5),      # zero speed: nominal
])
def test_timing_for_speed(step_length, speed, expected_step_time):
    limits = StepTimingLimits()
    timing = timing_for_speed(step_length, speed, limits)
    assert timing.step_time == pytest.approx(expected_step_time)
    assert timing.double_support == pytest.approx(
        max(limits.double_support_ratio * expected_step_time, limits.min_double_support))


def test_timing_for_speed_respects_min_double_support():
    limits = StepTimingLimits(double_support_ratio=0.1, min_double_support=0.08)
    timing = timing_for_speed(0.1, 0.25, limits)
    assert timing.double_support == pytest.approx(0.08)
    assert timing.single_support == pytest.approx(0.32)


@pytest.mark.parametrize('step_length, speed', [(math.nan, 0.1), (0.1, math.inf), (0.1, -0.1),
                                                (0.1, True)])
def test_timing_for_speed_rejects_bad_input(step_length, speed):
    with pytest.raises(ConfigError):
        timing_for_speed(step_length, speed)
