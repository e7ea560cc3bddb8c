import math

import pytest

from biped_planner.errors import InputError
from biped_planner.scheduled_commands import MAX_WAITING, ScheduledCommands


def test_a_command_is_due_from_the_first_step_starting_at_or_after_its_time():
    queue = ScheduledCommands()
    queue.add(2.0, 'forward')
    assert queue.due(1.99) == [] and len(queue) == 1
    assert queue.due(2.0 - 5e-7) == ['forward']  # a stamp's nanoseconds round down
    assert len(queue) == 0 and queue.due(5.0) == []


def test_commands_come_in_time_order_and_equal_times_in_arrival_order():
    queue = ScheduledCommands()
    for time, name in ((3.0, 'c'), (1.0, 'a'), (3.0, 'd'), (2.0, 'b')):
        queue.add(time, name)
    assert queue.next_time() == 1.0
    assert queue.due(2.5) == ['a', 'b']
    assert queue.next_time() == 3.0
    assert queue.due(10.0) == ['c', 'd']
    assert queue.next_time() == math.inf


def test_clear_drops_everything_and_says_how_much():
    queue = ScheduledCommands()
    queue.add(1.0, 'a')
    queue.add(2.0, 'b')
    assert queue.clear() == 2 and len(queue) == 0 and queue.clear() == 0


@pytest.mark.parametrize('time', [math.nan, math.inf, -math.inf, None, '1.0', True])
def test_a_time_that_is_not_a_finite_number_is_refused(time):
    queue = ScheduledCommands()
    with pytest.raises(InputError):
        queue.add(time, 'x')
    assert len(queue) == 0


def test_a_flood_of_commands_is_refused_beyond_the_limit():
    queue = ScheduledCommands()
    for i in range(MAX_WAITING):
        queue.add(float(i), i)
    with pytest.raises(InputError):
        queue.add(0.5, 'one too many')
    assert len(queue) == MAX_WAITING and queue.due(0.5) == [0]
