"""The user's side of the two-host graph test, run inside the workstation's namespace.

Waits for the graph (walking_state, the controller's diagnostics), sends START once the state
machine listens (again if no walk has begun 20 s later: on a loaded machine the planner may not
be offering plan_walk yet), waits until `steps` steps are walked, sends STOP, and prints one
JSON line: steps walked, fallen, sim and wall time, the controller's cycle latency (median,
p99), the answers on walk_command_status.

    python two_host_client.py STEPS TIMEOUT_S
"""
import json
import statistics
import sys
import time

import rclpy
from biped_msgs.msg import CommandStatus, ControllerDiagnostics, WalkCommand, WalkingState
from rosgraph_msgs.msg import Clock


def main() -> int:
    steps, timeout = int(sys.argv[1]), float(sys.argv[2])
    rclpy.init()
    node = rclpy.create_node('two_host_user')
    states, latencies, clock, answers = [], [], [0.0], []
    node.create_subscription(WalkingState, 'walking_state', states.append, 50)
    node.create_subscription(CommandStatus, 'walk_command_status', lambda m: answers.append(
        f'{m.command}:{m.error_code} {m.error_msg}'), 50)
    node.create_subscription(ControllerDiagnostics, 'controller_diagnostics',
                             lambda m: latencies.append(m.cycle_latency), 50)
    node.create_subscription(Clock, 'clock', lambda m: clock.__setitem__(
        0, m.clock.sec + m.clock.nanosec * 1e-9), 10)
    commands = node.create_publisher(WalkCommand, 'walk_command', 10)
    deadline = time.monotonic() + timeout

    def spin_until(predicate, within: float = None) -> bool:
        end = deadline if within is None else min(deadline, time.monotonic() + within)
        while time.monotonic() < end:
            if predicate():
                return True
            rclpy.spin_once(node, timeout_sec=0.05)
        return predicate()

    ready = spin_until(lambda: states and len(latencies) > 5 and
                       commands.get_subscription_count() > 0)
    walked = fallen = False
    wall = sim = 0.0
    if ready:
        wall0, sim0 = time.monotonic(), clock[0]
        for _ in range(3):
            commands.publish(WalkCommand(command=WalkCommand.START))
            if spin_until(lambda: states[-1].phase != WalkingState.IDLE, within=20.0):
                break
        walked = spin_until(lambda: any(s.step_index >= steps for s in states) or
                            any(s.fallen for s in states))
        wall, sim = time.monotonic() - wall0, clock[0] - sim0
        commands.publish(WalkCommand(command=WalkCommand.STOP))
        spin_until(lambda: states[-1].phase == WalkingState.IDLE)
    fallen = any(s.fallen for s in states)
    cycle = sorted(x for x in latencies if x > 0.0)
    print(json.dumps({
        'ready': bool(ready), 'steps': max((s.step_index for s in states), default=0),
        'walked': bool(walked), 'fallen': bool(fallen), 'sim_s': sim, 'wall_s': wall,
        'cycle_latency_median_ms': 1e3 * statistics.median(cycle) if cycle else None,
        'cycle_latency_p99_ms': 1e3 * cycle[int(0.99 * (len(cycle) - 1))] if cycle else None,
        'answers': answers}),
        flush=True)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
