"""Graph tests: scripts/bringup.py starts real node processes; the test talks to them over DDS."""
import re
import signal
import subprocess

from biped_msgs.msg import WalkCommand, WalkingState
import rclpy

from ros_harness import Collector, OutputLines, PYTHON, REPO, pid_alive, ros_environment, \
    wait_for_subscribers

BRINGUP = str(REPO / 'scripts' / 'bringup.py')


class BringupProcess:
    """scripts/bringup.py as a child process whose output is collected line by line."""

    def __init__(self, processes, *args: str) -> None:
        self.process = processes.start([PYTHON, BRINGUP, *args], stdout=subprocess.PIPE,
                                       stderr=subprocess.STDOUT, text=True, bufsize=1)
        self.output = OutputLines(self.process)
        self.lines = self.output.lines
        self.wait_for_line = self.output.wait_for_line

    def node_pids(self) -> dict:
        return {m.group(1): int(m.group(2)) for m in
                (re.search(r'started (\w+) \(pid (\d+)\)', line) for line in self.lines) if m}


def test_bringup_walk_command_and_sigint_leaves_no_process(processes, ros_context, executor):
    bringup = BringupProcess(processes, '--nodes', 'state_machine')
    bringup.wait_for_line(r'all nodes up', timeout=30)
    pids = bringup.node_pids()
    assert set(pids) == {'state_machine'}

    client = executor.track(rclpy.create_node('graph_test_client', context=ros_context))
    states = Collector(client, WalkingState, 'walking_state', 50)
    commands = client.create_publisher(WalkCommand, 'walk_command', 10)
    assert wait_for_subscribers(executor, commands, timeout=15)
    assert states.wait_for(executor, timeout=15)
    assert states.messages[-1].phase == WalkingState.IDLE
    commands.publish(WalkCommand(command=WalkCommand.OMNI, step_length=0.1, step_time=0.5))
    assert states.wait_for(executor, lambda m: any(
        s.phase == WalkingState.DOUBLE_SUPPORT for s in m), timeout=10)
    phases = [s.phase for s in states.messages]
    assert phases.index(WalkingState.INITIALIZE) < phases.index(WalkingState.SINGLE_SUPPORT)

    bringup.process.send_signal(signal.SIGINT)
    assert bringup.process.wait(timeout=15) == 0
    assert not any(pid_alive(pid) for pid in pids.values())
    assert any('all nodes stopped' in line for line in bringup.lines)


def test_a_dead_node_stops_the_graph_with_a_message_naming_it(processes):
    bringup = BringupProcess(processes, '--nodes', 'state_machine')
    bringup.wait_for_line(r'all nodes up', timeout=30)
    pid = bringup.node_pids()['state_machine']
    subprocess.run(['kill', '-9', str(pid)], check=True)
    assert bringup.process.wait(timeout=15) == 1
    bringup.wait_for_line(r'node state_machine died \(signal 9\); stopping the graph', 5)


def test_unknown_node_is_a_clear_error(processes):
    result = subprocess.run([PYTHON, BRINGUP, '--nodes', 'nonexistent'], env=ros_environment(),
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    assert "unknown nodes ['nonexistent']" in result.stderr
