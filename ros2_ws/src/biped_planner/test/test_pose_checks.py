import math

import pytest

from biped_planner.errors import ConfigError, InputError
from biped_planner.pose_checks import check_pose, PoseBounds, PoseStream

BOUNDS = PoseBounds(workspace=100.0, quaternion_tolerance=0.01)


def test_a_plausible_pose_passes():
    check_pose('odom', (1.0, -2.0, 0.55), (0.0, 0.0, math.sin(0.3), math.cos(0.3)), BOUNDS)


@pytest.mark.parametrize('position, quaternion, match', [
    ((math.nan, 0.0, 0.5), (0, 0, 0, 1), r'odom position.x nan'),
    ((0.0, 1e30, 0.5), (0, 0, 0, 1), r'position.y 1e\+30 outside \[-100.0, 100.0\]'),
    ((0.0, 0.0, -math.inf), (0, 0, 0, 1), 'position.z'),
    ((0.0, 0.0, 0.5), (0, 0, 0, 0), r'not a unit quaternion: \|q\| = 0'),
    ((0.0, 0.0, 0.5), (0, 0, 0, 1.1), 'not a unit quaternion'),
    ((0.0, 0.0, 0.5), (0, math.nan, 0, 1), 'not finite'),
])
def test_impossible_poses_are_rejected_naming_the_field(position, quaternion, match):
    with pytest.raises(InputError, match=match):
        check_pose('odom', position, quaternion, BOUNDS)


def test_bounds_are_checked():
    with pytest.raises(ConfigError, match='workspace'):
        PoseBounds(workspace=0.0)


UPRIGHT = (0.0, 0.0, 0.0, 1.0)


def test_a_pose_stream_keeps_its_stamps_in_order_and_behind_the_clock():
    stream = PoseStream('odom', 'map')
    stream.check('map', 10.0, (0.0, 0.0, 0.5), UPRIGHT, 10.0, BOUNDS, 0.2)
    stream.check('map', 10.0, (0.0, 0.0, 0.5), UPRIGHT, 10.0, BOUNDS, 0.2)  # same stamp
    with pytest.raises(InputError, match='before the previous'):
        stream.check('map', 9.0, (0.0, 0.0, 0.5), UPRIGHT, 10.0, BOUNDS, 0.2)
    with pytest.raises(InputError, match='ahead of the clock'):
        stream.check('map', 110.0, (0.0, 0.0, 0.5), UPRIGHT, 10.0, BOUNDS, 0.2)
    assert stream.last_stamp == 10.0  # refused poses leave it
    stream.check('map', 110.0, (0.0, 0.0, 0.5), UPRIGHT, 0.0, BOUNDS, 0.2)  # no clock yet


@pytest.mark.parametrize('frame, position, match', [
    ('odom', (0.0, 0.0, 0.5), "frame 'odom', expected 'map'"),
    ('', (0.0, 0.0, 0.5), "frame ''"),
    ('map', (math.nan, 0.0, 0.5), 'position.x nan'),
])
def test_a_pose_stream_refuses_other_frames_and_impossible_poses(frame, position, match):
    with pytest.raises(InputError, match=match):
        PoseStream('odom', 'map').check(frame, 1.0, position, UPRIGHT, 1.0, BOUNDS, 0.2)


def test_after_a_reset_older_poses_are_refused_and_the_order_restarts():
    stream = PoseStream('odom', 'map')
    stream.check('map', 20.0, (0.0, 0.0, 0.1), UPRIGHT, 20.0, BOUNDS, 0.2)
    assert stream.since_reset(20.0) == math.inf
    stream.reset(20.0)
    with pytest.raises(InputError, match='before the reset'):
        stream.check('map', 20.0, (0.0, 0.0, 0.1), UPRIGHT, 20.0, BOUNDS, 0.2)
    stream.check('map', 20.02, (0.0, 0.0, 0.5), UPRIGHT, 20.0, BOUNDS, 0.2)
    assert stream.since_reset(20.3) == pytest.approx(0.3)
