"""Keyboard teleop: setpoint logic, key input from a pipe, and the real process on cmd_vel."""
import os
import signal
import subprocess

from geometry_msgs.msg import Twist
import pytest
import rclpy

from biped_tools import teleop
from ros_harness import Collector, PYTHON, REPO

TELEOP = str(REPO / 'scripts' / 'teleop.py')
LIMITS = ['--max-vx', '0.2', '--max-vy', '0.1', '--max-wz', '0.3', '--step-linear', '0.15',
          '--step-angular', '0.2', '--rate', '20']


def values(msg: Twist):
    return msg.linear.x, msg.linear.y, msg.angular.z


@pytest.mark.parametrize('keys, expected', [
    ('www', (0.15, 0.0, 0.0)),
    ('wwwwwwwwww', (0.3, 0.0, 0.0)),
    ('xxxxxxxxxx', (-0.3, 0.0, 0.0)),
    ('aaaaa', (0.0, 0.15, 0.0)),
    ('dd', (0.0, -0.1, 0.0)),
    ('jjjjjjj', (0.0, 0.0, 0.5)),
    ('ll', (0.0, 0.0, -0.2)),
    ('wwaj k', (0.0, 0.0, 0.0)),
    ('wwaj ', (0.0, 0.0, 0.0)),
    ('w?Z\x1b', (0.05, 0.0, 0.0)),
])
def test_setpoint_steps_and_clamps_to_the_limits(keys, expected):
    setpoint = teleop.VelocitySetpoint(teleop.TeleopLimits())
    for key in keys:
        setpoint.apply(key)
    assert setpoint.values() == expected


def test_apply_reports_whether_the_setpoint_changed():
    setpoint = teleop.VelocitySetpoint(teleop.TeleopLimits(max_vx=0.05))
    assert setpoint.apply('w') and not setpoint.apply('w') and not setpoint.apply('?')


@pytest.mark.parametrize('field, value', [('max_vx', -0.1), ('max_wz', float('nan')),
                                          ('step_linear', 0.0), ('step_angular', float('inf'))])
def test_bad_limits_are_refused_naming_the_field(field, value):
    with pytest.raises(ValueError, match=field):
        teleop.TeleopLimits(**{field: value})


def test_key_reader_takes_lines_from_a_pipe_and_reports_the_end():
    read_end, write_end = os.pipe()
    with os.fdopen(read_end) as stream:
        reader = teleop.KeyReader(stream)
        assert not reader.is_tty
        os.write(write_end, b'wa\n \nj')
        assert reader.read(1.0) == (['w', 'a', ' '], False)
        assert reader.read(0.01) == ([], False)
        os.close(write_end)
        # The unfinished last line still counts once the input ends.
        assert reader.read(1.0) == (['j'], True)


def start_teleop(processes, *args):
    return processes.start([PYTHON, TELEOP, *LIMITS, *args], stdin=subprocess.PIPE,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def send(process, keys: str) -> None:
    process.stdin.write(keys)
    process.stdin.flush()


def test_keys_on_stdin_drive_cmd_vel_within_the_limits_and_q_sends_a_zero_twist(
        ros_context, executor, processes):
    node = executor.track(rclpy.create_node('teleop_test_sink', context=ros_context))
    received = Collector(node, Twist, 'cmd_vel', 100)
    process = start_teleop(processes)
    # The setpoint (zero) is published at the rate from the start: its arrival shows the match.
    assert received.wait_for(executor, timeout=15)
    assert values(received.messages[-1]) == (0.0, 0.0, 0.0)

    send(process, 'w\nw\nw\na\na\nj\nj\n')
    assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (0.2, 0.1, 0.3),
                             timeout=5), values(received.messages[-1])
    send(process, 'xxxxx\nd\n')
    assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (-0.2, -0.05, 0.3),
                             timeout=5), values(received.messages[-1])
    count = len(received.messages)
    # Held setpoints keep coming at the publish rate (20 Hz).
    assert received.wait_for(executor, lambda msgs: len(msgs) >= count + 5, timeout=5)
    assert all(values(m) == (-0.2, -0.05, 0.3) for m in received.messages[count:])
    send(process, 'k\n')
    assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (0.0, 0.0, 0.0),
                             timeout=5)
    send(process, 'j\n')
    assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (0.0, 0.0, 0.2),
                             timeout=5)
    send(process, 'q\n')
    output, _ = process.communicate(timeout=10)
    assert process.returncode == 0, output
    assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (0.0, 0.0, 0.0),
                             timeout=5)
    assert all(abs(m.linear.x) <= 0.2 and abs(m.linear.y) <= 0.1 and abs(m.angular.z) <= 0.3
               for m in received.messages)
    assert 'vx -0.20 m/s  vy -0.05 m/s  wz +0.30 rad/s' in output


@pytest.mark.parametrize('stop', ['eof', 'SIGINT', 'SIGTERM'])
def test_end_of_input_and_signals_also_stop_with_a_zero_twist(ros_context, executor, processes,
                                                             stop):
    node = executor.track(rclpy.create_node('teleop_test_stop', context=ros_context))
    received = Collector(node, Twist, 'cmd_vel', 100)
    process = start_teleop(processes)
    assert received.wait_for(executor, timeout=15)
    send(process, 'w\n')
    assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (0.15, 0.0, 0.0),
                             timeout=5)
    if stop == 'eof':
        process.stdin.close()
    else:
        process.send_signal(getattr(signal, stop))
    assert process.wait(timeout=10) == 0
    assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (0.0, 0.0, 0.0),
                             timeout=5)


def test_a_terminal_gives_single_key_presses_and_is_restored_on_exit(ros_context, executor,
                                                                     processes):
    import pty
    import termios
    node = executor.track(rclpy.create_node('teleop_test_tty', context=ros_context))
    received = Collector(node, Twist, 'cmd_vel', 100)
    controller, terminal = pty.openpty()
    try:
        before = termios.tcgetattr(terminal)
        process = processes.start([PYTHON, TELEOP, *LIMITS], stdin=terminal,
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        assert received.wait_for(executor, timeout=15)
        # No newline: in cbreak mode every key counts as soon as it is pressed.
        os.write(controller, b'j')
        assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (0.0, 0.0, 0.2),
                                 timeout=5)
        assert termios.tcgetattr(terminal)[3] & termios.ICANON == 0
        os.write(controller, b'q')
        assert process.wait(timeout=10) == 0
        assert termios.tcgetattr(terminal) == before
        assert received.wait_for(executor, lambda msgs: values(msgs[-1]) == (0.0, 0.0, 0.0),
                                 timeout=5)
    finally:
        os.close(controller)
        os.close(terminal)


def test_bad_options_are_refused_with_a_clear_error():
    result = subprocess.run([PYTHON, TELEOP, '--max-vx', '-1'], stdin=subprocess.DEVNULL,
                            capture_output=True, text=True, timeout=30)
    assert result.returncode == 2
    assert 'max_vx = -1.0: expected a finite value >= 0' in result.stderr
