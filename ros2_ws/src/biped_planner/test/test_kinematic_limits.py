"""Tests of biped_planner.kinematic_limits."""
import math

import pytest

from biped_planner.errors import ConfigError
from biped_planner.footsteps import Footstep, LEFT, RIGHT
from biped_planner.kinematic_limits import (clamp_step, feet_overlap, KinematicLimits,
                                            relative_step, step_violations)

LIMITS = KinematicLimits()


def test_relative_step_in_the_stance_frame():
    stance = Footstep(RIGHT, 1.0, 1.0, math.pi / 2)
    landing = Footstep(LEFT, 0.8, 1.1, math.pi / 2 + 0.2)
    forward, lateral, turn = relative_step(stance, landing)
    assert forward == pytest.approx(0.1) and lateral == pytest.approx(0.2)
    assert turn == pytest.approx(0.2)
    crossed = Footstep(LEFT, 1.1, 1.0, math.pi / 2)
    assert relative_step(stance, crossed)[1] == pytest.approx(-0.1)


def test_feet_overlap_separating_axis():
    a = Footstep(LEFT, 0.0, 0.0, 0.0)
    assert feet_overlap(a, Footstep(RIGHT, 0.0, -0.079, 0.0), 0.16, 0.08)
    assert not feet_overlap(a, Footstep(RIGHT, 0.0, -0.081, 0.0), 0.16, 0.08)
    assert feet_overlap(a, Footstep(RIGHT, 0.0, -0.085, 0.0), 0.16, 0.08, clearance=0.01)
    # rotated by 90 deg the foot is 0.16 wide across y: corner contact decided exactly
    assert feet_overlap(a, Footstep(RIGHT, 0.0, -0.119, math.pi / 2), 0.16, 0.08)
    assert not feet_overlap(a, Footstep(RIGHT, 0.0, -0.121, math.pi / 2), 0.16, 0.08)
    # diagonal placement where only the rotated axes separate
    assert not feet_overlap(a, Footstep(RIGHT, 0.13, -0.1, math.pi / 4), 0.16, 0.08)


@pytest.mark.parametrize('landing, problem', [
    (Footstep(LEFT, 0.3, 0.2), 'forward'), (Footstep(LEFT, -0.2, 0.2), 'forward'),
    (Footstep(LEFT, 0.0, 0.5), 'lateral'), (Footstep(LEFT, 0.0, -0.2), 'crossed'),
    (Footstep(LEFT, 0.0, 0.2, 0.7), 'turn'), (Footstep(RIGHT, 0.0, -0.2), 'stance foot'),
    (Footstep(LEFT, 0.0, 0.121, math.pi / 2 - 0.6), 'collide')])
def test_violations_are_named(landing, problem):
    stance = Footstep(RIGHT, 0.0, 0.0, 0.0)
    assert any(problem in message for message in step_violations(stance, landing, LIMITS))


def test_feasible_step_has_no_violation():
    assert step_violations(Footstep(RIGHT, 0, 0), Footstep(LEFT, 0.1, 0.2, 0.1), LIMITS) == []


@pytest.mark.parametrize('landing', [
    Footstep(LEFT, 0.6, 0.2), Footstep(LEFT, -0.5, 0.1), Footstep(LEFT, 0.0, -0.3),
    Footstep(LEFT, 0.1, 0.9, 1.2), Footstep(LEFT, 0.05, 0.13, -1.4),
    Footstep(LEFT, 0.0, 0.12, 0.5)])
def test_clamped_steps_are_feasible(landing):
    stance = Footstep(RIGHT, 0.3, -0.2, 0.4)
    cos_yaw, sin_yaw = math.cos(0.4), math.sin(0.4)
    moved = Footstep(LEFT, 0.3 + cos_yaw * landing.x - sin_yaw * landing.y,
                     -0.2 + sin_yaw * landing.x + cos_yaw * landing.y, 0.4 + landing.yaw)
    clamped = clamp_step(stance, moved, LIMITS)
    assert step_violations(stance, clamped, LIMITS) == []


def test_clamp_keeps_a_feasible_step():
    stance = Footstep(LEFT, 0.0, 0.1, 0.0)
    landing = Footstep(RIGHT, 0.1, -0.1, -0.1)
    clamped = clamp_step(stance, landing, LIMITS)
    assert (clamped.x, clamped.y, clamped.yaw) == pytest.approx((0.1, -0.1, -0.1))


@pytest.mark.parametrize('kwargs', [dict(max_forward=-0.1), dict(min_width=0.05),
                                    dict(min_width=0.5), dict(max_turn=2.0),
                                    dict(foot_length=0.0), dict(clearance=math.nan),
                                    dict(max_width=True)])
def test_limits_reject_bad_values(kwargs):
    with pytest.raises(ConfigError):
        KinematicLimits(**kwargs)
