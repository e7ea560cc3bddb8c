#!/usr/bin/env python3
"""Benchmark the whole node graph in lockstep: real-time factor and control-loop latency.

Brings up the five nodes, lets the humanoid walk in place, and measures on the wall clock:
- real-time factor: simulated seconds per wall second while walking (lockstep: physics waits
  for each controller command, so this is how fast the whole graph runs);
- control-loop latency: from the arrival of a joint_states message (the last sensor message of
  a period) to the arrival of the joint command answering it, both seen by this client.
Prints a Markdown table of medians and p99 over several runs.
"""
import argparse
from pathlib import Path
import statistics
import sys
import time

sys.path.insert(0, str(Path(__file__).resolve().parent))

from graph_session import GraphSession  # noqa: E402


def measure(domain_id: int, seconds: float) -> dict:
    from sensor_msgs.msg import JointState
    with GraphSession(domain_id, log=lambda line: None) as session:
        session.wait_until_ready()
        sensor_arrival, command_arrival = {}, {}

        def key(msg):
            return msg.header.stamp.sec, msg.header.stamp.nanosec

        session.node.create_subscription(JointState, 'joint_states', lambda m: sensor_arrival.
                                         setdefault(key(m), time.perf_counter()), 100)
        session.node.create_subscription(JointState, 'joint_commands', lambda m: command_arrival.
                                         setdefault(key(m), time.perf_counter()), 100)
        session.send_command(command=1)
        session.wait_sim_time(1.5, 60)  # into the walk
        sim0, wall0 = session.sim_time(), time.perf_counter()
        session.wait_sim_time(seconds, 10 * seconds + 60)
        rtf = (session.sim_time() - sim0) / (time.perf_counter() - wall0)
        fallen = session.fallen()
    latencies = [command_arrival[k] - sensor_arrival[k] for k in command_arrival
                 if k in sensor_arrival and command_arrival[k] >= sensor_arrival[k]]
    latencies.sort()
    return {'rtf': rtf, 'latency_median_ms': 1e3 * statistics.median(latencies),
            'latency_p99_ms': 1e3 * latencies[int(0.99 * (len(latencies) - 1))],
            'cycles': len(latencies), 'fallen': fallen}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--runs', type=int, default=3)
    parser.add_argument('--seconds', type=float, default=10.0, help='simulated s per run')
    parser.add_argument('--domain-id', type=int, default=47)
    args = parser.parse_args(argv)
    results = [measure(args.domain_id, args.seconds) for _ in range(args.runs)]
    for name in ('rtf', 'latency_median_ms', 'latency_p99_ms'):
        values = [r[name] for r in results]
        print(f'{name}: runs {", ".join(f"{v:.2f}" for v in values)}')
    rtf = statistics.median(r['rtf'] for r in results)
    median = statistics.median(r['latency_median_ms'] for r in results)
    p99 = statistics.median(r['latency_p99_ms'] for r in results)
    print()
    print(f'Whole graph in lockstep, walking in place, {args.runs} runs of {args.seconds:.0f} '
          f'simulated s (medians over runs):')
    print()
    print('| metric | value | target |')
    print('|---|---|---|')
    print(f'| real-time factor | {rtf:.2f}x | >= 2x |')
    print(f'| sensor -> joint command latency, median | {median:.2f} ms | |')
    print(f'| sensor -> joint command latency, p99 | {p99:.2f} ms | <= 2 ms |')
    print(f'| fell | {sum(r["fallen"] for r in results)} of {args.runs} runs | 0 |')
    return 0


if __name__ == '__main__':
    sys.exit(main())
