"""Tests of the rate-limited log of refused inputs."""
from biped_planner.node_support.rejection_log import RejectionLog


def make(period=2.0):
    lines, now = [], [0.0]
    return RejectionLog(lines.append, period, lambda: now[0]), lines, now


def test_each_kind_is_logged_at_once_and_the_same_kind_once_per_period():
    log, lines, now = make()
    log('odom', 'position 1e+30 is outside the workspace')
    log('odom', 'position 3e+31 is outside the workspace')  # same kind, other number
    log('odom', "frame_id is 'odom', expected 'map'")       # another kind
    log('zmp', 'position 1e+30 is outside the workspace')   # another topic
    assert len(lines) == 3 and lines[0].startswith('odom rejected: position')
    now[0] = 2.5
    log('odom', 'position nan is outside the workspace')
    assert len(lines) == 4 and '(1 more like it since the last line)' in lines[-1]


def test_arbitrary_kinds_do_not_grow_without_bound():
    log, lines, now = make()
    for i in range(1000):
        now[0] = 3.0 * i
        log('odom', f"frame_id is 'frame_{chr(65 + i % 26)}{i}'")
    assert len(lines) == 1000 and len(log._last) <= 256
