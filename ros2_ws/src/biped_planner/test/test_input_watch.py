import pytest

from biped_planner.errors import ConfigError
from biped_planner.input_watch import InputWatch


def watch(**kwargs):
    return InputWatch(('odom', 'reference_trajectory'), ('footstep_plan',), 0.5, **kwargs)


def test_an_input_never_seen_is_not_stale_and_a_live_one_neither():
    w = watch()
    assert w.check(100.0, 10.0) == ()
    w.arrived('odom', 100.0, 10.0)
    assert w.check(100.4, 10.4) == ()


def test_a_stream_silent_on_both_clocks_is_stale_until_it_arrives_again():
    w = watch()
    w.arrived('odom', 100.0, 10.0)
    w.arrived('reference_trajectory', 100.0, 10.0)
    w.arrived('reference_trajectory', 100.6, 10.6)
    assert w.check(100.6, 10.6) == ('odom',)
    w.arrived('odom', 100.7, 10.7)
    assert w.check(100.7, 10.7) == ()


def test_silence_on_one_clock_only_is_no_loss():
    w = watch()
    w.arrived('odom', 100.0, 10.0)
    # simulation 4x faster than real time: 2 s simulated, 0.5 s of wall time
    assert w.check(102.0, 10.4) == ()
    # a loaded machine: 2 s of wall time, the simulated clock advanced 0.1 s
    assert w.check(100.1, 12.0) == ()
    assert w.check(102.0, 12.0) == ('odom',)


def test_a_due_input_is_stale_when_it_does_not_come_in_time_and_stays_so():
    w = watch()
    assert w.check(200.0, 20.0) == ()
    w.due('footstep_plan', 100.0, 10.0)
    w.due('footstep_plan', 100.3, 10.3)  # the first due time counts
    assert w.check(100.45, 10.45) == ()
    assert w.check(100.6, 10.6) == ('footstep_plan',)
    w.withdraw('footstep_plan')  # the walk ended: a loss already seen stays reported
    assert w.check(101.0, 11.0) == ('footstep_plan',)
    w.arrived('footstep_plan', 101.1, 11.1)
    assert w.check(105.0, 15.0) == ()
    w.due('footstep_plan', 105.0, 15.0)
    w.withdraw('footstep_plan')  # withdrawn in time: nothing to report
    assert not w.is_due('footstep_plan') and w.check(110.0, 20.0) == ()


def test_a_stopped_clock_is_reported_with_the_streams_of_its_producer():
    w = watch(clock_name='/clock', clock_sources=('odom',))
    w.clock(0.0, 1.0)
    assert w.check(0.0, 5.0) == ()  # a clock that never ran is not watched
    for k in range(10):
        t, wall = 100.0 + 0.02 * k, 5.0 + 0.02 * k
        w.clock(t, wall)
        w.arrived('odom', t, wall)
        w.arrived('reference_trajectory', t, wall)
    w.clock(100.18, 5.5)
    assert w.check(100.18, 5.5) == ()
    w.clock(100.18, 5.9)
    # the simulator is gone: clock and odometry (judged by wall time); the references are
    # not due while nothing moves
    assert w.check(100.18, 5.9) == ('odom', '/clock')
    w.clock(100.2, 6.0)
    w.arrived('odom', 100.2, 6.0)
    assert w.check(100.2, 6.0) == ()


def test_bad_settings_are_refused():
    with pytest.raises(ConfigError, match='timeout'):
        InputWatch(('odom',), timeout=-1.0)
    with pytest.raises(ConfigError, match='clock sources'):
        InputWatch(('odom',), clock_name='/clock', clock_sources=('imu',))
