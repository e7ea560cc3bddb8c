import math

import pytest

from biped_planner.errors import CommandError, ConfigError
from biped_planner.walk_command import CommandKind, CommandLimits, WalkCommand

LIMITS = CommandLimits()


def make(command=CommandKind.OMNI, goal=(0.0, 0.0, 0.0), step=(0.1, 0.0, 0.0), step_time=0.0):
    return WalkCommand.from_fields(command, goal, step, step_time, LIMITS)


def test_valid_commands_keep_their_values():
    cmd = make(step=(0.1, -0.05, 0.2), step_time=0.5)
    assert cmd.kind == CommandKind.OMNI and cmd.step == (0.1, -0.05, 0.2)
    assert make(CommandKind.GOTO, goal=(2.0, 1.0, 0.5)).goal == (2.0, 1.0, 0.5)


@pytest.mark.parametrize('kwargs, match', [
    (dict(command=9), 'unknown command 9'),
    (dict(step=(math.nan, 0.0, 0.0)), 'step_length must be finite'),
    (dict(step=(0.5, 0.0, 0.0)), r'step_length 0.5 outside \[-0.3, 0.3\]'),
    (dict(step=(0.0, 0.3, 0.0)), 'step_width'),
    (dict(step=(0.0, 0.0, -1.0)), 'step_angle'),
    (dict(step_time=-0.4), 'step_time -0.4'),
    (dict(step_time=math.inf), 'step_time must be finite'),
    (dict(command=CommandKind.GOTO, goal=(1e7, 0.0, 0.0)), 'goal_x'),
    (dict(command=CommandKind.GOTO, goal=(0.0, math.nan, 0.0)), 'goal_y must be finite'),
])
def test_bad_commands_name_the_field_and_range(kwargs, match):
    with pytest.raises(CommandError, match=match):
        make(**kwargs)


def test_step_limits_only_apply_to_omni():
    assert make(CommandKind.START, step=(5.0, 5.0, 5.0)).kind == CommandKind.START


def test_inconsistent_limits_are_rejected():
    with pytest.raises(ConfigError, match='min_step_time'):
        CommandLimits(min_step_time=2.0, max_step_time=1.0)
