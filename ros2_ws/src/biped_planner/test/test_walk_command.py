import math

import pytest

from biped_planner.errors import CommandError, ConfigError, FrameError
from biped_planner.walk_command import (check_command_frame, CommandKind, CommandLimits,
                                        goal_command, velocity_command, WalkCommand)

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


IDENTITY = (0.0, 0.0, 0.0, 1.0)


def test_a_goal_pose_in_the_map_frame_becomes_a_goto_with_its_heading():
    half = math.sqrt(0.5)
    command = goal_command('map', 'map', (3.4, 3.4, 0.0), (0.0, 0.0, half, half), LIMITS)
    assert command.kind == CommandKind.GOTO
    assert command.goal == pytest.approx((3.4, 3.4, math.pi / 2))
    # within the tolerance, the quaternion is normalised before its yaw is read
    slightly_long = (0.0, 0.0, 0.0, 1.005)
    assert goal_command('map', 'map', (1.0, 0.0, 0.0), slightly_long, LIMITS).goal[2] == 0.0


@pytest.mark.parametrize('frame, position, orientation, error, match', [
    ('', (1.0, 1.0, 0.0), IDENTITY, FrameError, "frame_id '' is not the map frame 'map'"),
    ('odom', (1.0, 1.0, 0.0), IDENTITY, FrameError, "'odom'"),
    ('map', (1.0, 1.0, 0.0), (0.0, 0.0, 0.0, 0.0), CommandError, r'\|q\| = 0'),
    ('map', (1.0, 1.0, 0.0), (0.0, 0.0, 0.0, 2.0), CommandError, 'not a unit quaternion'),
    ('map', (math.nan, 1.0, 0.0), IDENTITY, CommandError, 'position.x must be finite'),
    ('map', (1.0, 1.0, math.inf), IDENTITY, CommandError, 'position.z must be finite'),
    ('map', (1.0, 1.0, 0.0), (0.0, 0.0, math.nan, 1.0), CommandError, 'orientation.z'),
    ('map', (1e30, 1.0, 0.0), IDENTITY, CommandError, 'goal_x'),
])
def test_bad_goal_poses_are_rejected_naming_what_is_wrong(frame, position, orientation, error,
                                                          match):
    with pytest.raises(error, match=match):
        goal_command(frame, 'map', position, orientation, LIMITS)


def test_a_velocity_command_gives_vx_vy_wz_within_the_limits():
    assert velocity_command((0.2, -0.1, 0.0), (0.0, 0.0, 0.3), LIMITS) == (0.2, -0.1, 0.3)


@pytest.mark.parametrize('linear, angular, match', [
    ((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0), 'linear.x must be finite'),
    ((0.0, 0.0, math.inf), (0.0, 0.0, 0.0), 'linear.z must be finite'),
    ((0.0, 0.0, 0.0), (0.0, -math.inf, 0.0), 'angular.y must be finite'),
    ((1e30, 0.0, 0.0), (0.0, 0.0, 0.0), r'linear.x 1e\+30 outside \[-1.0, 1.0\]'),
    ((0.0, -1.5, 0.0), (0.0, 0.0, 0.0), 'linear.y'),
    ((0.0, 0.0, 0.0), (0.0, 0.0, 3.0), r'angular.z 3.0 outside \[-2.0, 2.0\]'),
])
def test_bad_velocity_commands_are_rejected(linear, angular, match):
    with pytest.raises(CommandError, match=match):
        velocity_command(linear, angular, LIMITS)


def test_a_goto_command_may_leave_its_frame_empty_but_not_name_another():
    goto = make(CommandKind.GOTO, goal=(1.0, 1.0, 0.0))
    check_command_frame(goto, '', 'map')
    check_command_frame(goto, 'map', 'map')
    with pytest.raises(FrameError, match="'odom'"):
        check_command_frame(goto, 'odom', 'map')
    check_command_frame(make(CommandKind.START), 'odom', 'map')  # no goal, no frame


def test_a_walk_starts_at_its_start_time_or_at_once_when_that_is_past():
    from biped_planner.walk_command import MAX_START_LEAD, start_time_of
    assert start_time_of(12.5, 10.0) == 12.5
    assert start_time_of(0.0, 10.0) == 10.0   # 0: at once
    assert start_time_of(9.0, 10.0) == 10.0   # already past: at once
    assert start_time_of(10.0 + MAX_START_LEAD, 10.0) == 10.0 + MAX_START_LEAD


@pytest.mark.parametrize('start_time', [math.nan, math.inf, -1.0, 1e30, True, '1'])
def test_a_start_time_that_is_not_a_time_or_too_far_ahead_is_refused(start_time):
    from biped_planner.walk_command import start_time_of
    with pytest.raises(CommandError, match='start_time'):
        start_time_of(start_time, 10.0)
