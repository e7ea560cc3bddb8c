"""Tests of the controller's sensor intake: which messages it keeps (no DDS needed)."""
from builtin_interfaces.msg import Time
from geometry_msgs.msg import WrenchStamped
from nav_msgs.msg import Odometry
import pytest

from biped_mpc.input_bounds import InputBounds
from biped_mpc.nodes.sensor_intake import MAX_JUMP, NEW_TIMELINE, SensorFrames, SensorIntake


def intake(clock=None, wall=None):
    """An intake whose node clock reads clock: a number, a one-element list to move it, or None
    (no /clock); its wall clock reads wall[0] (a list), by default 0.01 s more at each read (a
    steady stream)."""
    if wall is None:
        ticks = iter(range(1_000_000))
        wall_now = lambda: 0.01 * next(ticks)  # noqa: E731
    else:
        wall_now = lambda: wall[0]  # noqa: E731
    return SensorIntake(InputBounds(), SensorFrames(), ['j'] * 12, [-1.0] * 12, [1.0] * 12,
                        lambda: clock[0] if isinstance(clock, list) else clock, wall=wall_now)


def odom(t: float, x: float = 0.0, frame: str = 'map') -> Odometry:
    msg = Odometry()
    msg.header.stamp = Time(sec=int(t), nanosec=int(round((t - int(t)) * 1e9)))
    msg.header.frame_id, msg.child_frame_id = frame, 'pelvis'
    msg.pose.pose.position.x, msg.pose.pose.position.z = x, 0.54
    msg.pose.pose.orientation.w = 1.0
    return msg


def test_a_valid_message_is_kept_and_a_refused_one_keeps_the_previous():
    sensors = intake()
    assert sensors.accept('odom', odom(1.0)) == (True, None)
    kept, why = sensors.accept('odom', odom(1.02, x=1e30))
    assert not kept and 'workspace' in why
    assert sensors.valid['odom'].pose.pose.position.x == 0.0
    assert sensors.has_period('odom', (1, 20000000))  # refused, but that period's came
    assert 'odom 0.30 s old' in sensors.stale(['odom'], 1.3, 0.1)


@pytest.mark.parametrize('t, words', [(0.5, 'goes back'), (1.0 + MAX_JUMP + 0.1, 'jumps ahead')])
def test_stamps_off_the_stream_are_refused(t, words):
    sensors = intake()
    sensors.accept('odom', odom(1.0))
    kept, why = sensors.accept('odom', odom(t))
    assert not kept and words in why
    assert sensors.accept('odom', odom(1.02)) == (True, None)


def test_a_refused_message_stamped_ahead_does_not_make_the_next_valid_ones_old():
    sensors = intake()
    sensors.accept('odom', odom(1.0))
    sensors.accept('odom', odom(1.2, x=float('nan')))
    assert sensors.accept('odom', odom(1.02)) == (True, None)


def test_with_a_clock_a_stamp_ahead_of_it_is_refused():
    sensors = intake(clock=10.0)
    kept, why = sensors.accept('odom', odom(12.0))
    assert not kept and 'ahead of the clock' in why


def test_with_a_clock_a_gap_in_the_stream_is_taken_once_the_clock_has_run_through_it():
    """A controller held up while the simulator, giving it up, ran on in real time: its next
    joint_states is 0.34 s newer than the last it took (CI, 2026-12-07). Refused as a jump until
    the clock has come there; then taken at once, not after NEW_TIMELINE messages."""
    clock = [3.38]
    sensors = intake(clock=clock)
    assert sensors.accept('odom', odom(3.38)) == (True, None)
    kept, why = sensors.accept('odom', odom(3.72))
    assert not kept and 'jumps ahead' in why  # the clock is not there yet
    clock[0] = 3.70
    assert sensors.accept('odom', odom(3.74)) == (True, None)
    assert sensors.accept('odom', odom(3.76)) == (True, None)
    kept, why = sensors.accept('odom', odom(3.76 + MAX_JUMP + 0.1))
    assert not kept and 'jumps ahead' in why  # still refused beyond the clock


def test_a_stream_silent_in_wall_time_takes_its_jump_ahead():
    """This node held up while the simulator ran on, its /clock handled after the sensors
    (the graph test of a SIGSTOPped controller): the stream was silent for 0.8 s of wall time
    and its stamp moved on by 0.8 s: taken. The same stamp within a steady stream is not."""
    wall = [100.0]
    sensors = intake(clock=[0.06], wall=wall)
    assert sensors.accept('odom', odom(0.06)) == (True, None)
    wall[0] += 0.01
    kept, why = sensors.accept('odom', odom(0.86))
    assert not kept and 'jumps ahead' in why
    wall[0] += 0.8
    assert sensors.accept('odom', odom(0.86)) == (True, None)
    assert sensors.accept('odom', odom(0.88)) == (True, None)


def test_repeats_of_the_newest_stamp_are_not_a_stream_that_runs():
    """A simulator holding its clock sends its held sensors again; queued during a held-up
    node's silence, the repeat comes first (the graph test, 1 run of 5 under load): the silence
    still counts from when the stamps last moved on."""
    wall = [100.0]
    sensors = intake(clock=[0.30], wall=wall)
    assert sensors.accept('odom', odom(0.30)) == (True, None)
    wall[0] += 1.5
    assert sensors.accept('odom', odom(0.30)) == (True, None)  # the held period again
    wall[0] += 0.001
    assert sensors.accept('odom', odom(0.92)) == (True, None)


def test_a_restarted_simulator_becomes_the_time_once_it_runs_on():
    sensors = intake()
    sensors.accept('odom', odom(50.0))
    results = [sensors.accept('odom', odom(0.02 * k))[0] for k in range(1, NEW_TIMELINE + 2)]
    assert not any(results[:NEW_TIMELINE - 1]) and all(results[NEW_TIMELINE - 1:])


def test_wrong_frames_are_refused():
    sensors = intake()
    kept, why = sensors.accept('odom', odom(1.0, frame='odom'))
    assert not kept and "'odom'" in why
    wrench = WrenchStamped()
    wrench.header.frame_id = ''
    kept, why = sensors.accept('right_foot_wrench', wrench)
    assert not kept and 'r_ankle_ft' in why
