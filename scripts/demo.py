#!/usr/bin/env python3
"""The main job: bring up the node graph headless, walk, stop, and plot what happened.

Today's graph is the walking state machine: the demo sends START, lets the robot take steps,
sends STOP, waits for Idle, and writes output/demo/walking_phases.png and summary.json from the
walking_state messages it received over DDS.
"""
import argparse
import json
from pathlib import Path
import sys
import time

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bringup import available_nodes, GraphOptions, NodeGraph  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
PHASE_NAMES = ['Idle', 'Initialize', 'Single support', 'Double support', 'Fallen']


def record_walk(walk_seconds: float, domain_id: int, log=print) -> list:
    """Start the graph, walk for walk_seconds, stop; return (t, phase, support, step) samples."""
    import rclpy
    from biped_msgs.msg import WalkCommand, WalkingState
    graph = NodeGraph(GraphOptions(nodes=[n for n in available_nodes()
                                          if n == 'state_machine'], domain_id=domain_id), log)
    graph.start()
    rclpy.init(domain_id=domain_id)
    node = rclpy.create_node('demo_client')
    samples = []
    node.create_subscription(WalkingState, 'walking_state', lambda m: samples.append((
        m.header.stamp.sec + m.header.stamp.nanosec * 1e-9, m.phase, m.support_foot,
        m.step_index)), 50)
    commands = node.create_publisher(WalkCommand, 'walk_command', 10)

    def spin_for(seconds, until=lambda: False):
        end = time.monotonic() + seconds
        while time.monotonic() < end and not until():
            graph.check_alive()
            rclpy.spin_once(node, timeout_sec=0.02)
        return until()

    try:
        graph.wait_until_up()
        if not spin_for(15.0, lambda: commands.get_subscription_count() > 0 and samples):
            raise RuntimeError('the state machine did not answer within 15 s')
        log('[demo] START: walking in place')
        commands.publish(WalkCommand(command=WalkCommand.START))
        spin_for(walk_seconds)
        log('[demo] STOP: finish the step, then stand')
        commands.publish(WalkCommand(command=WalkCommand.STOP))
        if not spin_for(5.0, lambda: samples and samples[-1][1] == WalkingState.IDLE):
            raise RuntimeError('the state machine did not return to Idle after STOP')
        spin_for(0.3)
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
        graph.stop()
    return samples


def plot(samples: list, out: Path) -> Path:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    t0 = samples[0][0]
    t = [s[0] - t0 for s in samples]
    fig, (ax_phase, ax_step) = plt.subplots(2, 1, sharex=True, figsize=(9, 5))
    ax_phase.step(t, [s[1] for s in samples], where='post')
    ax_phase.set_yticks(range(len(PHASE_NAMES)), PHASE_NAMES)
    ax_phase.set_title('Walking state machine over DDS: START, steps, STOP')
    ax_step.step(t, [s[3] for s in samples], where='post', label='steps completed')
    ax_step.step(t, [s[2] for s in samples], where='post', label='support (0 L, 1 R, 2 both)')
    ax_step.set_xlabel('time (s)')
    ax_step.legend(loc='upper left')
    fig.tight_layout()
    path = out / 'walking_phases.png'
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--walk-seconds', type=float, default=4.0)
    parser.add_argument('--domain-id', type=int, default=42)
    parser.add_argument('--out', type=Path, default=REPO / 'output' / 'demo')
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    started = time.monotonic()
    try:
        samples = record_walk(args.walk_seconds, args.domain_id)
    except (RuntimeError, TimeoutError) as error:
        print(f'[demo] error: {error}', file=sys.stderr)
        return 1
    phases = [s[1] for s in samples]
    summary = {
        'walking_state_messages': len(samples),
        'steps_completed': max(s[3] for s in samples),
        'phases_seen': sorted({PHASE_NAMES[p] for p in phases}),
        'ended_idle': phases[-1] == 0,
        'wall_time_s': round(time.monotonic() - started, 2),
    }
    (args.out / 'summary.json').write_text(json.dumps(summary, indent=2))
    figure = plot(samples, args.out)
    print(f'[demo] {summary["steps_completed"]} steps, ended Idle: {summary["ended_idle"]}')
    print(f'[demo] wrote {figure} and {args.out / "summary.json"}')
    return 0 if summary['ended_idle'] and summary['steps_completed'] > 0 else 1


if __name__ == '__main__':
    sys.exit(main())
