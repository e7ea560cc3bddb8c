"""Keyboard teleop: drive the biped with geometry_msgs/Twist on `cmd_vel`, like
teleop_twist_keyboard.

  .venv/bin/python scripts/teleop.py                              # in a terminal
  .venv/bin/python scripts/teleop.py --max-vx 0.2 --rate 20
  .venv/bin/python scripts/teleop.py --ros-args -r cmd_vel:=/robot/cmd_vel
  printf 'w\\nw\\nj\\nq\\n' | .venv/bin/python scripts/teleop.py   # keys from a pipe

Keys (each press changes the setpoint by one step; values are clamped to the limits):

  w / x    forward velocity  + / -    (linear.x, m/s)
  a / d    sideways velocity + / -    (linear.y, m/s, left positive)
  j / l    turn rate         + / -    (angular.z, rad/s, counter-clockwise positive)
  space, k stop (zero setpoint)
  q        quit (publishes a zero Twist first); Ctrl-C, SIGTERM and end of input do the same

The current setpoint is published at --rate Hz and at once when a key changes it. From a
terminal, keys are read one by one (cbreak mode, restored on exit); from a pipe or file, input
is read as lines and every character of a line is one key (a line with one space is a stop).
"""
import argparse
from dataclasses import dataclass
import os
import select
import sys
import time
from typing import List, Tuple

from biped_tools.stop_signal import stop_on_signals

# key -> (setpoint field, direction of one step)
STEP_KEYS = {'w': ('vx', 1), 'x': ('vx', -1), 'a': ('vy', 1), 'd': ('vy', -1),
             'j': ('wz', 1), 'l': ('wz', -1)}
STOP_KEYS = {' ', 'k'}
# q, and the EOT / ETX bytes a terminal sends for Ctrl-D / Ctrl-C when signals are off.
QUIT_KEYS = {'q', '\x04', '\x03'}
KEY_HELP = 'keys: w/x forward +/-, a/d sideways +/-, j/l turn +/-, space or k stop, q quit'


@dataclass(frozen=True)
class TeleopLimits:
    """Bounds and increments of the velocity setpoint.

    :param max_vx: largest |forward velocity| (m/s)
    :param max_vy: largest |sideways velocity| (m/s)
    :param max_wz: largest |turn rate| (rad/s)
    :param step_linear: change of vx or vy per key press (m/s)
    :param step_angular: change of wz per key press (rad/s)
    """

    max_vx: float = 0.3
    max_vy: float = 0.15
    max_wz: float = 0.5
    step_linear: float = 0.05
    step_angular: float = 0.1

    def __post_init__(self) -> None:
        for name in ('max_vx', 'max_vy', 'max_wz'):
            value = getattr(self, name)
            if not 0.0 <= value < float('inf'):
                raise ValueError(f'{name} = {value}: expected a finite value >= 0')
        for name in ('step_linear', 'step_angular'):
            value = getattr(self, name)
            if not 0.0 < value < float('inf'):
                raise ValueError(f'{name} = {value}: expected a finite value > 0')


class VelocitySetpoint:
    """The commanded (vx, vy, wz), changed key by key within the limits."""

    def __init__(self, limits: TeleopLimits) -> None:
        self.limits = limits
        self.vx = self.vy = self.wz = 0.0

    def apply(self, key: str) -> bool:
        """Change the setpoint for one key press.

        :param key: one character; keys without a meaning are ignored
        :return: whether the setpoint changed
        """
        before = self.values()
        if key in STOP_KEYS:
            self.vx = self.vy = self.wz = 0.0
        elif key in STEP_KEYS:
            name, direction = STEP_KEYS[key]
            step = self.limits.step_angular if name == 'wz' else self.limits.step_linear
            bound = getattr(self.limits, f'max_{name}')
            value = min(bound, max(-bound, getattr(self, name) + direction * step))
            # Rounding keeps repeated steps on the grid (three steps of 0.05 give 0.15, not
            # 0.15000000000000002); adding 0.0 turns -0.0 into 0.0 for a clean display.
            setattr(self, name, round(value, 9) + 0.0)
        return self.values() != before

    def values(self) -> Tuple[float, float, float]:
        """:return: (vx m/s, vy m/s, wz rad/s)"""
        return self.vx, self.vy, self.wz

    def describe(self) -> str:
        return f'vx {self.vx:+.2f} m/s  vy {self.vy:+.2f} m/s  wz {self.wz:+.2f} rad/s'


class KeyReader:
    """Keys from stdin: single key presses from a terminal, lines from a pipe or file.

    Use as a context manager: a terminal is put in cbreak mode (no echo, no line buffering,
    Ctrl-C still raises SIGINT) and always restored on exit.
    """

    def __init__(self, stream=None) -> None:
        self.stream = stream or sys.stdin
        self.fd = self.stream.fileno()
        self.is_tty = os.isatty(self.fd)
        self._saved = None
        self._pending = ''

    def __enter__(self) -> 'KeyReader':
        if self.is_tty:
            import termios
            import tty
            self._saved = termios.tcgetattr(self.fd)
            tty.setcbreak(self.fd)
        return self

    def __exit__(self, *exc) -> bool:
        if self._saved is not None:
            import termios
            termios.tcsetattr(self.fd, termios.TCSADRAIN, self._saved)
            self._saved = None
        return False

    def read(self, timeout: float) -> Tuple[List[str], bool]:
        """Wait up to timeout seconds for input.

        :return: (keys read, whether the input has ended)
        """
        ready, _, _ = select.select([self.fd], [], [], max(0.0, timeout))
        if not ready:
            return [], False
        data = os.read(self.fd, 1024)
        if not data:
            keys = [c for c in self._pending if c not in '\r\n']
            self._pending = ''
            return keys, True
        text = data.decode(errors='ignore')
        if self.is_tty:
            return list(text), False
        self._pending += text
        lines = self._pending.split('\n')
        self._pending = lines.pop()
        return [c for line in lines for c in line.rstrip('\r')], False


def build_parser() -> argparse.ArgumentParser:
    defaults = TeleopLimits()
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--rate', type=float, default=10.0,
                        help='publish rate of the setpoint (Hz, default 10)')
    parser.add_argument('--max-vx', type=float, default=defaults.max_vx,
                        help=f'largest |forward velocity| (m/s, default {defaults.max_vx})')
    parser.add_argument('--max-vy', type=float, default=defaults.max_vy,
                        help=f'largest |sideways velocity| (m/s, default {defaults.max_vy})')
    parser.add_argument('--max-wz', type=float, default=defaults.max_wz,
                        help=f'largest |turn rate| (rad/s, default {defaults.max_wz})')
    parser.add_argument('--step-linear', type=float, default=defaults.step_linear,
                        help=f'vx / vy change per key (m/s, default {defaults.step_linear})')
    parser.add_argument('--step-angular', type=float, default=defaults.step_angular,
                        help=f'wz change per key (rad/s, default {defaults.step_angular})')
    return parser


def make_twist(values: Tuple[float, float, float]):
    from geometry_msgs.msg import Twist
    twist = Twist()
    twist.linear.x, twist.linear.y, twist.angular.z = values
    return twist


def main(argv=None) -> int:
    from rclpy.utilities import remove_ros_args
    argv = list(sys.argv if argv is None else ['teleop.py', *argv])
    args = build_parser().parse_args(remove_ros_args(argv)[1:])
    try:
        if not 0.0 < args.rate <= 1000.0:
            raise ValueError(f'rate = {args.rate}: expected a value in (0, 1000] Hz')
        limits = TeleopLimits(args.max_vx, args.max_vy, args.max_wz, args.step_linear,
                              args.step_angular)
    except ValueError as error:
        print(f'[teleop] error: {error}', file=sys.stderr)
        return 2
    # Signals only set a flag, so the loop below always ends by sending a zero Twist and
    # restoring the terminal.
    stop = stop_on_signals()
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    from geometry_msgs.msg import Twist
    import rclpy
    from rclpy.duration import Duration
    from rclpy.signals import SignalHandlerOptions
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('teleop_keyboard')
    publisher = node.create_publisher(Twist, 'cmd_vel', 10)
    setpoint = VelocitySetpoint(limits)
    period = 1.0 / args.rate
    reader = KeyReader()
    print(f'[teleop] {KEY_HELP}\n[teleop] publishing on {publisher.topic_name} at '
          f'{args.rate:g} Hz; limits vx {limits.max_vx} vy {limits.max_vy} m/s, '
          f'wz {limits.max_wz} rad/s', flush=True)
    try:
        with reader:
            next_publish = time.monotonic()
            quitting = False
            while not stop.is_set() and not quitting:
                keys, ended = reader.read(next_publish - time.monotonic())
                changed = False
                for key in keys:
                    if key in QUIT_KEYS:
                        quitting = True
                        break
                    changed |= setpoint.apply(key)
                quitting = quitting or ended
                if changed:
                    # On a terminal the setpoint line is rewritten in place.
                    print(('\r' if reader.is_tty else '') + setpoint.describe(),
                          end='\x1b[K' if reader.is_tty else '\n', flush=True)
                now = time.monotonic()
                if changed or now >= next_publish:
                    publisher.publish(make_twist(setpoint.values()))
                    next_publish += period
                    # A late loop (or a key press) restarts the period instead of catching up
                    # with a burst.
                    if changed or next_publish <= now:
                        next_publish = now + period
    finally:
        publisher.publish(make_twist((0.0, 0.0, 0.0)))
        # The stop must reach the robot before this process (and its DDS writer) is gone.
        publisher.wait_for_all_acked(Duration(seconds=1.0))
        print(('\n' if reader.is_tty else '') + '[teleop] stopped: sent a zero Twist', flush=True)
        node.destroy_node()
        rclpy.try_shutdown()
    return 0

