#!/usr/bin/env python3
"""Benchmark the whole node graph in lockstep: real-time factor and control-loop latency.

Brings up the five nodes (biped_tools.node_graph, sim time, lockstep), lets the humanoid walk in
place, and measures on the wall clock:
- real-time factor: simulated seconds per wall second while walking (lockstep: physics waits
  for each controller command, so this is how fast the whole graph runs);
- control-loop latency: from the arrival of a joint_states message (the last sensor message the
  controller waits for in a period) to the arrival of the joint command answering it (same
  stamp), both seen by one observer process subscribed to both topics; and inside the
  controller, from its joint_states arriving to its command going out (the cycle_latency of
  controller_diagnostics: the loop's own latency, without the DDS hops and the observer).

The observer is part of the measurement, not of the graph: by default it subscribes only to what
it measures (joint_states, joint_commands, walking_state for falls), so that it takes as little
of the two cores from the graph as possible. `--observer session` measures with the demo's and
tests' GraphSession instead, which also keeps odom, com, zmp, references and diagnostics (its
own load slows the graph). Prints a Markdown table of medians and p99 over several runs, one
row per way of putting the nodes into processes (`--compositions separate control all`).
`--real-time` runs the simulator in real time instead (lockstep off), as on a robot: then the
late commands per 10,000 periods are the figure (`--runs 1 --seconds 200`: 10,000 periods).
"""
import argparse
import statistics
import sys
import time

from biped_tools.graph_session import (ALL_NODES, close_client, COMMAND_LISTENERS,
                                       GraphSession, stamp_seconds)
from biped_tools.node_graph import CONTROL_PATH, GraphOptions, NodeGraph

WARM_UP = 1.5  # simulated s of walking before measuring
# How the nodes are put into processes (bringup --compose).
COMPOSITIONS = {
    'separate': [],
    'control': [list(CONTROL_PATH)],
    'all': [list(ALL_NODES)],
}


def clock_overrides(real_time: bool) -> dict:
    """Node parameters of the benchmark's clock: lockstep (the default) or real time."""
    return {'simulator': ['lockstep:=false']} if real_time else {}


def stamp_key(msg) -> tuple:
    return msg.header.stamp.sec, msg.header.stamp.nanosec


class LatencyProbe:
    """Wall arrival times of joint_states and joint_commands, by stamp, in one client node."""

    def __init__(self, node) -> None:
        from biped_msgs.msg import ControllerDiagnostics
        from sensor_msgs.msg import JointState
        self.sensor_arrival, self.command_arrival = {}, {}
        self.controller_latency = []
        self.deadlines = None  # (periods, late periods) of the controller's newest diagnostics
        self.sim_time = 0.0
        node.create_subscription(ControllerDiagnostics, 'controller_diagnostics',
                                 self._on_diagnostics, 100)
        node.create_subscription(JointState, 'joint_states', self._on_sensors, 100)
        node.create_subscription(JointState, 'joint_commands', lambda m: self.command_arrival.
                                 setdefault(stamp_key(m), time.perf_counter()), 100)

    def _on_sensors(self, msg) -> None:
        self.sensor_arrival.setdefault(stamp_key(msg), time.perf_counter())
        self.sim_time = stamp_seconds(msg.header.stamp)

    def _on_diagnostics(self, msg) -> None:
        if msg.cycle_latency > 0.0:
            self.controller_latency.append(msg.cycle_latency)
        if msg.periods:
            self.deadlines = (msg.periods, msg.late_periods)

    def latencies(self) -> list:
        sensors, commands = self.sensor_arrival, self.command_arrival
        return sorted(commands[k] - sensors[k] for k in commands
                      if k in sensors and commands[k] >= sensors[k])


class MinimalObserver:
    """The graph and a client node that only sends the walk command and takes the probe's
    timings."""

    def __init__(self, domain_id: int, compose, real_time: bool = False) -> None:
        self.domain_id = domain_id
        self.graph = NodeGraph(GraphOptions(
            nodes=list(ALL_NODES), domain_id=domain_id, use_sim_time=True, compose=compose,
            overrides=clock_overrides(real_time)), log=lambda line: None)
        self._context = None
        self.node = None
        self._fallen = False

    def __enter__(self) -> 'MinimalObserver':
        import rclpy
        from biped_msgs.msg import WalkCommand, WalkingState
        from biped_planner.node_support.node_runner import make_executor
        self.graph.start()
        try:
            self.graph.wait_until_up(60.0)
            self._context = rclpy.Context()
            rclpy.init(context=self._context, domain_id=self.domain_id)
            self.executor = make_executor(context=self._context)
            self.node = rclpy.create_node('graph_benchmark', context=self._context)
            self.executor.add_node(self.node)
            self.probe = LatencyProbe(self.node)
            self.node.create_subscription(WalkingState, 'walking_state', self._on_state, 50)
            self._command_pub = self.node.create_publisher(WalkCommand, 'walk_command', 10)
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *exc) -> bool:
        if self._context is not None:
            close_client(self.executor, self.node, self._context)
            self._context = None
        self.graph.stop()
        return False

    def _on_state(self, msg) -> None:
        self._fallen = self._fallen or msg.fallen

    def spin_until(self, predicate, timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if predicate():
                return True
            self.graph.check_alive()
            self.executor.spin_once(timeout_sec=0.05)
        return predicate()

    def wait_until_ready(self) -> None:
        if not self.spin_until(lambda: len(self.probe.command_arrival) > 5, 60.0):
            raise TimeoutError('the controller does not answer')

    def start_walking(self) -> None:
        from biped_msgs.msg import WalkCommand
        subscribed = lambda: set(COMMAND_LISTENERS) <= {  # noqa: E731
            info.node_name for info in self.node.get_subscriptions_info_by_topic('/walk_command')}
        if not self.spin_until(subscribed, 15.0):
            raise TimeoutError('nobody subscribes to walk_command')
        self._command_pub.publish(WalkCommand(command=WalkCommand.START))

    def sim_time(self) -> float:
        return self.probe.sim_time

    def wait_sim_time(self, seconds: float, timeout: float) -> None:
        end = self.sim_time() + seconds
        self.spin_until(lambda: self.sim_time() >= end, timeout)

    def fallen(self) -> bool:
        return self._fallen


class SessionObserver(MinimalObserver):
    """The graph as GraphSession (demo, tests) runs and watches it."""

    def __init__(self, domain_id: int, compose, real_time: bool = False) -> None:
        self.session = GraphSession(domain_id, compose=compose, log=lambda line: None,
                                    overrides=clock_overrides(real_time))

    def __enter__(self) -> 'SessionObserver':
        self.session.start()
        self.probe = LatencyProbe(self.session.node)
        return self

    def __exit__(self, *exc) -> bool:
        self.session.stop()
        return False

    def wait_until_ready(self) -> None:
        self.session.wait_until_ready()

    def start_walking(self) -> None:
        self.session.send_command(command=1)

    def wait_sim_time(self, seconds: float, timeout: float) -> None:
        self.session.wait_sim_time(seconds, timeout)

    def sim_time(self) -> float:
        return self.session.sim_time()

    def fallen(self) -> bool:
        return self.session.fallen()


def measure(domain_id: int, seconds: float, observer: str, compose,
            real_time: bool = False) -> dict:
    kind = MinimalObserver if observer == 'minimal' else SessionObserver
    with kind(domain_id, compose, real_time) as run:
        run.wait_until_ready()
        run.start_walking()
        run.wait_sim_time(WARM_UP, 60)
        deadlines0 = run.probe.deadlines or (0, 0)
        sim0, wall0 = run.sim_time(), time.perf_counter()
        run.wait_sim_time(seconds, 10 * seconds + 60)
        rtf = (run.sim_time() - sim0) / (time.perf_counter() - wall0)
        fallen = run.fallen()
        latencies = run.probe.latencies()
        inside = sorted(run.probe.controller_latency)
        periods, late = (a - b for a, b in zip(run.probe.deadlines or (0, 0), deadlines0))
    return {'late_per_10000': 1e4 * late / periods if periods else float('nan'),
            'periods': periods, 'rtf': rtf, 'latency_median_ms': 1e3 * statistics.median(latencies),
            'latency_p99_ms': 1e3 * latencies[int(0.99 * (len(latencies) - 1))],
            'controller_median_ms': 1e3 * statistics.median(inside),
            'controller_p99_ms': 1e3 * inside[int(0.99 * (len(inside) - 1))],
            'cycles': len(latencies), 'fallen': fallen}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--runs', type=int, default=5)
    parser.add_argument('--seconds', type=float, default=10.0, help='simulated s per run')
    parser.add_argument('--domain-id', type=int, default=61)
    parser.add_argument('--observer', choices=['minimal', 'session'], default='minimal',
                        help='client that watches the graph (see above)')
    parser.add_argument('--real-time', action='store_true',
                        help='the simulator runs in real time (lockstep off), as a robot does: '
                             'the late commands are the figure that matters')
    parser.add_argument('--compositions', nargs='+', choices=list(COMPOSITIONS),
                        default=list(COMPOSITIONS),
                        help='separate: one process per node; control: the control path '
                             '(simulator, reference generator, controller) in one process; '
                             'all: every node in one process')
    args = parser.parse_args(argv)
    # Interleaved (run 1 of each, run 2 of each, ...) so that a change of the machine's load
    # during the benchmark falls on every composition alike.
    results = {name: [] for name in args.compositions}
    for _ in range(args.runs):
        for name in args.compositions:
            results[name].append(measure(args.domain_id, args.seconds, args.observer,
                                         COMPOSITIONS[name], args.real_time))
            print(f'{name}: ' + ', '.join(f'{k} {v:.2f}' for k, v in results[name][-1].items()),
                  flush=True)
    print()
    mode = 'in real time' if args.real_time else 'in lockstep'
    print(f'Whole graph {mode}, walking in place, {args.runs} runs of {args.seconds:.0f} '
          f'simulated s each, {args.observer} observer; medians over runs unless said:')
    print()
    print('| processes | real-time factor, median / worst | joint_states -> joint_commands '
          'latency, median / p99 (ms) | inside the controller, median / p99 (ms) | '
          'late commands per 10,000 periods | falls |')
    print('|---|---|---|---|---|---|')
    for name, runs in results.items():
        def median(key):
            return statistics.median(r[key] for r in runs)
        late = sum(r['late_per_10000'] * r['periods'] for r in runs) / max(
            1, sum(r['periods'] for r in runs))
        print(f'| {name} | {median("rtf"):.2f}x / {min(r["rtf"] for r in runs):.2f}x | '
              f'{median("latency_median_ms"):.2f} / {median("latency_p99_ms"):.2f} | '
              f'{median("controller_median_ms"):.2f} / {median("controller_p99_ms"):.2f} | '
              f'{late:.1f} | {sum(r["fallen"] for r in runs)} of {len(runs)} |')
    print()
    print('Targets (issue 14): control path composed >= 3x real time in every run and latency '
          'p99 <= 2 ms; separate processes >= 2x in every run.')
    return 0


if __name__ == '__main__':
    sys.exit(main())
