"""Ctrl-C and SIGTERM as a flag that the user commands poll.

A handler that only sets a flag lets a command finish properly (close the bag, send a zero
Twist, stop the nodes) instead of being cut off mid-write by rclpy's own SIGINT handling.
"""
import signal
import threading


def stop_on_signals() -> threading.Event:
    """:return: an event set by the next SIGINT or SIGTERM (installed in the main thread)"""
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    return stop
