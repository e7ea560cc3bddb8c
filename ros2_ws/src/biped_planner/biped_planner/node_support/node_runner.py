"""The main loop shared by every node of the biped stack."""
import os
import signal
import threading
from typing import Callable

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions


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
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    executor = make_executor()
    try:
        node = make_node()
        executor.add_node(node)
        while not stop.is_set() and rclpy.ok():
            executor.spin_once(timeout_sec=0.2)
    finally:
        if node is not None:
            executor.remove_node(node)
            node.destroy_node()
        executor.shutdown()
        rclpy.try_shutdown()
