"""Helpers for node-level and graph tests with real rclpy and real DDS (no mocks)."""
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Callable, List, Optional

from builtin_interfaces.msg import Time
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rosgraph_msgs.msg import Clock

REPO = Path(__file__).resolve().parent.parent
PYTHON = sys.executable


def domain_id_for_worker() -> int:
    """A ROS_DOMAIN_ID per pytest-xdist worker (80, 81, ...), so parallel runs never cross-talk.

    BIPED_TEST_DOMAIN_BASE moves the range, for two test runs on one machine at once.
    """
    worker = os.environ.get('PYTEST_XDIST_WORKER', 'gw0')
    index = int(worker[2:]) if worker.startswith('gw') and worker[2:].isdigit() else 0
    return int(os.environ.get('BIPED_TEST_DOMAIN_BASE', '80')) + index % 20


def ros_environment() -> dict:
    """The environment every process of a test runs with: localhost discovery, own domain."""
    env = dict(os.environ)
    env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    env['ROS_DOMAIN_ID'] = str(domain_id_for_worker())
    env['PYTHONUNBUFFERED'] = '1'
    return env


def spin_until(executor: SingleThreadedExecutor, predicate: Callable[[], bool],
               timeout: float) -> bool:
    """Spin until predicate() is true or the deadline passes.

    :return: whether the predicate became true
    """
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        executor.spin_once(timeout_sec=0.02)
    return predicate()


def wait_for_subscribers(executor, publisher, count: int = 1, timeout: float = 10.0) -> bool:
    """Wait until the publisher has matched its subscribers (discovery takes up to ~3 s)."""
    return spin_until(executor, lambda: publisher.get_subscription_count() >= count, timeout)


class Collector:
    """Subscribes to a topic and keeps every message with its arrival time."""

    def __init__(self, node, msg_type, topic: str, qos=10):
        self.messages: List = []
        self.subscription = node.create_subscription(msg_type, topic, self._on_msg, qos)

    def _on_msg(self, msg) -> None:
        self.messages.append(msg)

    def wait_for(self, executor, predicate=lambda msgs: bool(msgs), timeout: float = 10.0):
        ok = spin_until(executor, lambda: predicate(self.messages), timeout)
        return ok


class ProcessGroup:
    """Real processes started for a test, always stopped at the end (SIGINT, then SIGKILL)."""

    def __init__(self) -> None:
        self.processes: List[subprocess.Popen] = []

    def start(self, args: List[str], env: Optional[dict] = None, **kwargs) -> subprocess.Popen:
        process = subprocess.Popen(args, env=env or ros_environment(), start_new_session=True,
                                   **kwargs)
        self.processes.append(process)
        return process

    def stop_all(self, grace: float = 8.0) -> None:
        for process in self.processes:
            if process.poll() is None:
                process.send_signal(signal.SIGINT)
        deadline = time.monotonic() + grace
        for process in self.processes:
            try:
                process.wait(timeout=max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()


def pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # a zombie (exited, not yet reaped) is not alive
    try:
        with open(f'/proc/{pid}/stat') as stat:
            return stat.read().split(')')[-1].split()[0] != 'Z'
    except FileNotFoundError:
        return False


def new_context():
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=domain_id_for_worker())
    return context


class SimClock:
    """Publishes /clock in fixed increments and spins between them."""

    def __init__(self, node, executor):
        self.publisher = node.create_publisher(Clock, '/clock', 10)
        self.executor = executor
        self.t = 100.0

    def advance(self, seconds: float, dt: float = 0.005, pace: Optional[float] = None) -> None:
        """:param pace: at most this many simulated seconds per wall second (None: as fast as
            possible), for nodes that also time on the wall clock"""
        t0, wall0 = self.t, time.monotonic()
        for _ in range(int(round(seconds / dt))):
            while pace is not None and self.t - t0 > pace * (time.monotonic() - wall0):
                self.executor.spin_once(timeout_sec=0.002)
            self.t += dt
            sec = int(self.t)
            self.publisher.publish(Clock(clock=Time(sec=sec, nanosec=int((self.t - sec) * 1e9))))
            for _ in range(3):
                self.executor.spin_once(timeout_sec=0.0)


class RosoutLines:
    """The log lines of every node (rcl_interfaces/Log on /rosout)."""

    def __init__(self, node):
        from rcl_interfaces.msg import Log
        self.lines = []
        node.create_subscription(Log, '/rosout', lambda m: self.lines.append(
            f'[{m.name}] {m.msg}'), 100)

    def has(self, *words) -> bool:
        return any(all(word in line for word in words) for line in self.lines)


def goal_pose_msg(x: float, y: float, frame: str = 'map', q=(0.0, 0.0, 0.0, 1.0)):
    """A geometry_msgs/PoseStamped goal at (x, y) with orientation q (x, y, z, w)."""
    from geometry_msgs.msg import PoseStamped
    msg = PoseStamped()
    msg.header.frame_id = frame
    msg.pose.position.x, msg.pose.position.y = x, y
    o = msg.pose.orientation
    o.x, o.y, o.z, o.w = q
    return msg


class OutputLines:
    """A child process's output (text mode, stdout piped), collected line by line."""

    def __init__(self, process) -> None:
        self.lines: List[str] = []
        threading.Thread(target=self._read, args=(process,), daemon=True).start()

    def _read(self, process) -> None:
        for line in process.stdout:
            self.lines.append(line.rstrip())

    def wait_for_line(self, pattern: str, timeout: float):
        """The first match of pattern in a line within timeout s; :raises AssertionError:"""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for line in list(self.lines):
                match = re.search(pattern, line)
                if match:
                    return match
            time.sleep(0.05)
        raise AssertionError(f'no line matching {pattern!r} in {timeout} s:\n' +
                             '\n'.join(self.lines[-60:]))
