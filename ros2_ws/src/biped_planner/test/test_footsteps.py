"""Tests of biped_planner.footsteps."""
import math

import pytest

from biped_planner.errors import ConfigError
from biped_planner.footsteps import (body_beside, check_footstep_sequence, feet_beside,
                                     foot_beside, Footstep, LEFT, other_side, RIGHT,
                                     straight_footsteps)
from biped_planner.pose2d import Pose2D


def test_footstep_is_frozen_and_validated():
    step = Footstep(LEFT, 1.0, 2.0, 0.5)
    with pytest.raises(AttributeError):
        step.x = 3.0
    assert Footstep(RIGHT, 0, 0).yaw == 0.0


@pytest.mark.parametrize('kwargs', [
    dict(side=2, x=0.0, y=0.0), dict(side=True, x=0.0, y=0.0), dict(side=-1, x=0.0, y=0.0),
    dict(side=LEFT, x=math.nan, y=0.0), dict(side=LEFT, x=0.0, y=math.inf),
    dict(side=LEFT, x=0.0, y=0.0, yaw=-math.inf), dict(side=LEFT, x='1', y=0.0)])
def test_footstep_rejects_bad_fields(kwargs):
    with pytest.raises(ConfigError):
        Footstep(**kwargs)


def test_other_side():
    assert other_side(LEFT) == RIGHT and other_side(RIGHT) == LEFT
    with pytest.raises(ConfigError):
        other_side(3)


@pytest.mark.parametrize('first_swing', [LEFT, RIGHT])
@pytest.mark.parametrize('n_steps', [0, 1, 2, 5])
def test_straight_footsteps_layout(first_swing, n_steps):
    length, width, x0, y0 = 0.12, 0.2, 1.0, -0.5
    steps = straight_footsteps(n_steps, length, width, first_swing, x0, y0)
    assert len(steps) == n_steps + 3
    check_footstep_sequence(steps)
    assert steps[1].side == first_swing and steps[0].side == other_side(first_swing)
    for step in steps:
        expected_y = y0 + width / 2 if step.side == LEFT else y0 - width / 2
        assert step.y == pytest.approx(expected_y)
        assert step.yaw == 0.0
    assert steps[0].x == steps[1].x == x0
    for k in range(1, n_steps + 1):
        assert steps[k + 1].x == pytest.approx(x0 + k * length)
    # the final step brings the feet side by side
    last_other = next(step for step in reversed(steps) if step.side != steps[-1].side)
    assert steps[-1].x == pytest.approx(last_other.x)
    assert steps[-1].x == pytest.approx(x0 + n_steps * length)


@pytest.mark.parametrize('args', [
    (-1, 0.1, 0.2), (1.5, 0.1, 0.2), (True, 0.1, 0.2), (2, math.nan, 0.2), (2, 0.1, 0.0),
    (2, 0.1, -0.2), (2, 2.0, 0.2), (2, 0.1, 1.5), (2, 0.1, math.inf)])
def test_straight_footsteps_rejects_bad_arguments(args):
    with pytest.raises(ConfigError):
        straight_footsteps(*args)


def test_straight_footsteps_rejects_bad_side_and_origin():
    with pytest.raises(ConfigError):
        straight_footsteps(2, 0.1, 0.2, first_swing=5)
    with pytest.raises(ConfigError):
        straight_footsteps(2, 0.1, 0.2, x0=math.nan)


def test_check_footstep_sequence_errors():
    good = straight_footsteps(3, 0.1, 0.2)
    check_footstep_sequence(good)
    with pytest.raises(ConfigError, match='at least 3'):
        check_footstep_sequence(good[:2])
    with pytest.raises(ConfigError, match='must be a Footstep'):
        check_footstep_sequence(good[:2] + [(0, 0.1, 0.1)])
    with pytest.raises(ConfigError, match='initial feet'):
        check_footstep_sequence([good[0], good[0], good[2]])
    with pytest.raises(ConfigError, match='first swing foot'):
        check_footstep_sequence([good[0], good[1], good[0]])
    with pytest.raises(ConfigError, match='alternate'):
        check_footstep_sequence(good[:4] + [good[3]])


@pytest.mark.parametrize('yaw', [0.0, 0.7, -2.5])
def test_feet_beside_and_body_beside_are_inverse(yaw):
    body = Pose2D(0.3, -0.2, yaw)
    left, right = feet_beside(body, 0.2)
    assert (left.side, right.side) == (LEFT, RIGHT)
    assert math.hypot(left.x - right.x, left.y - right.y) == pytest.approx(0.2)
    # the left foot is to the left of the heading
    assert -math.sin(yaw) * (left.x - body.x) + math.cos(yaw) * (left.y - body.y) == \
        pytest.approx(0.1)
    for foot in (left, right):
        back = body_beside(foot, 0.1)
        assert (back.x, back.y, back.yaw) == pytest.approx((body.x, body.y, body.yaw))
    assert foot_beside(body.x, body.y, yaw, RIGHT, 0.1) == right
