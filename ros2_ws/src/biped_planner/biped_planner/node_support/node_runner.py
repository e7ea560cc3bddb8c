"""The main loop shared by every node of the biped stack."""
import faulthandler
import os
import signal
import threading
from typing import Callable, Sequence

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions


DUMP_STACKS_SIGNAL = signal.SIGUSR1


def make_executor(context=None):
    """rclpy's EventsExecutor (its loop in C++) unless BIPED_EXECUTOR=single.

    The Python SingleThreadedExecutor rebuilds its wait set on every wake-up: at the graph's
    message rates that cost a node 10-20 % of a core for callbacks that do almost nothing.
    """
    if os.environ.get('BIPED_EXECUTOR', 'events') == 'single':
        return SingleThreadedExecutor(context=context)
    from rclpy.experimental import EventsExecutor
    return EventsExecutor(context=context)


def run_node(make_node: Callable[[], Node], args=None) -> None:
    """Init rclpy, build the node, spin until SIGINT or SIGTERM, then clean up.

    The node's own handlers turn both signals into a flag that the loop checks every 0.2 s, so
    shutdown always runs the cleanup below (rclpy's handler shuts the context down under a
    running spin, and rclpy.spin() was seen to hang on SIGTERM right after start).
    """
    run_nodes([make_node], args)


def run_nodes(node_factories: Sequence[Callable[[], Node]], args=None) -> None:
    """run_node for several nodes in one process on one executor (composition).

    Like rclcpp's component container: the nodes share the process, the DDS participant and
    the executor's thread, so a message between them costs no context switch between
    processes. The nodes are built in the order given and destroyed in the reverse order.

    :param node_factories: callables that each build one node
    :param args: rclpy's command-line arguments (global to the process)
    """
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    # A node that hangs gets SIGUSR1 from the bring-up before SIGKILL: every thread's Python
    # stack goes to stderr, the only trace of where it hung (faulthandler's C-level handler
    # runs even when the interpreter never returns from a call into the executor).
    faulthandler.register(DUMP_STACKS_SIGNAL, all_threads=True)
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    nodes = []
    executor = make_executor()
    try:
        for make_node in node_factories:
            nodes.append(make_node())
            executor.add_node(nodes[-1])
        while not stop.is_set() and rclpy.ok():
            executor.spin_once(timeout_sec=0.2)
    finally:
        for node in reversed(nodes):
            executor.remove_node(node)
            node.destroy_node()
        executor.shutdown()
        rclpy.try_shutdown()
