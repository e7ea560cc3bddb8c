"""A node that hangs in a callback ignores SIGINT; the bring-up's stop writes its Python stacks
(faulthandler on SIGUSR1, registered by every node's main loop) before it kills it, so a hang
seen once in a long run says where it was."""
import subprocess
import sys
import textwrap
import threading

from biped_tools.node_graph import GraphOptions, NodeGraph

HUNG_NODE = textwrap.dedent('''
    import time
    from rclpy.node import Node
    from biped_planner.node_support.node_runner import run_nodes

    def hang_in_the_timer_callback():
        print('hanging', flush=True)
        time.sleep(600.0)

    def make_node():
        node = Node('hung_node')
        node.create_timer(0.05, hang_in_the_timer_callback)
        return node

    run_nodes([make_node])
''')


def test_stop_writes_a_hung_nodes_stacks_before_sigkill():
    lines = []
    graph = NodeGraph(GraphOptions(nodes=[]), log=lines.append)
    process = subprocess.Popen([sys.executable, '-c', HUNG_NODE], env=graph.environment(),
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               bufsize=1, start_new_session=True)
    graph.processes['hung_node'] = process
    hanging = threading.Event()

    def forward():
        for line in process.stdout:
            lines.append(line.rstrip())
            if 'hanging' in line:
                hanging.set()
    reader = threading.Thread(target=forward, daemon=True)
    reader.start()
    try:
        assert hanging.wait(30.0), lines
        graph.stop(grace=1.0)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    reader.join(timeout=5.0)
    assert any('ignored SIGINT' in line for line in lines), lines
    assert process.returncode == -9
    stack = [line for line in lines if 'hang_in_the_timer_callback' in line]
    assert stack, lines
