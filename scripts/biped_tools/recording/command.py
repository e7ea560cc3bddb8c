"""Record topics into a real rosbag2 directory (metadata.yaml + MCAP or sqlite3), like
`ros2 bag record` (rosbag2 is not installable here).

Messages are taken as raw CDR bytes and written unchanged; every connection carries its full
message definition and RIHS01 type hash, so `ros2 bag info` / `ros2 bag play` on a full ROS
install, rosbags' AnyReader and MCAP tools read the bag. Subscriptions take the publishers' QoS
(transient_local topics such as `map` and `footstep_plan` are recorded, latched data included).

  .venv/bin/python scripts/record.py walking_state cmd_vel footstep_plan     # until Ctrl-C
  .venv/bin/python scripts/record.py --all -x '/rosout|/parameter_events' --duration 10
  .venv/bin/python scripts/record.py -o output/bags/walk1 --storage sqlite3 walking_state

Named topics are recorded as soon as a publisher appears; topics appearing later are added
when discovered. Ctrl-C, SIGTERM, --duration and --max-messages all close the bag properly.
In-process use: biped_tools.recording.BagRecorder.
"""
import argparse
from datetime import datetime
import os
from pathlib import Path
import sys
import threading
import time

from biped_tools.paths import OUTPUT
from biped_tools.recording.bag_recorder import BagRecorder
from biped_tools.recording.bag_writer import STORAGES
from biped_tools.recording.errors import RecordError
from biped_tools.stop_signal import stop_on_signals

DEFAULT_BAG_DIR = OUTPUT / 'bags'


def default_output() -> Path:
    """output/bags/<YYYY_MM_DD-HH_MM_SS> in the repository (rosbag2's naming)."""
    return DEFAULT_BAG_DIR / datetime.now().strftime('%Y_%m_%d-%H_%M_%S')


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('topics', nargs='*', help='topics to record, e.g. walking_state cmd_vel')
    parser.add_argument('-a', '--all', action='store_true',
                        help='record every topic with a publisher, including later ones')
    parser.add_argument('-x', '--exclude-regex', default=None, metavar='REGEX',
                        help='with --all: skip topics whose full name matches')
    parser.add_argument('-o', '--output', type=Path, default=None,
                        help='bag directory to create (default: output/bags/<timestamp>)')
    parser.add_argument('-s', '--storage', choices=STORAGES, default='mcap')
    parser.add_argument('-d', '--duration', type=float, default=0.0,
                        help='stop after this many seconds (0: until Ctrl-C / SIGTERM)')
    parser.add_argument('--max-messages', type=int, default=0,
                        help='stop after this many messages in total (0: no limit)')
    parser.add_argument('--use-sim-time', action='store_true',
                        help='stamp messages with /clock time (as the simulated graph does)')
    return parser


def run(args, node, executor, stop: threading.Event) -> int:
    """Record as the command line asks until stopped, then close the bag and report.

    :return: exit status: 0 done, 1 a named topic could not be recorded or writing failed,
        2 bad arguments
    """
    import rclpy

    def log(text: str) -> None:
        print(f'[record] {text}', flush=True)

    try:
        recorder = BagRecorder(node, args.output or default_output(), topics=args.topics,
                               record_all=args.all, exclude=args.exclude_regex,
                               storage=args.storage, max_messages=args.max_messages, log=log)
    except RecordError as error:
        print(f'[record] error: {error}', file=sys.stderr)
        return 2
    log(f'writing {recorder.path} ({args.storage}); Ctrl-C stops')
    if recorder.waiting:
        log(f'waiting for publishers on {", ".join(recorder.waiting)}')
    end = time.monotonic() + args.duration if args.duration > 0 else None
    try:
        while not stop.is_set() and not recorder.done and rclpy.ok():
            if end is not None and time.monotonic() >= end:
                break
            executor.spin_once(timeout_sec=0.1)
    finally:
        summary = recorder.close(executor)
    for line in summary.lines():
        log(line)
    failed = [topic for topic in recorder.wanted if topic in summary.errors]
    return 1 if failed or '(bag)' in summary.errors else 0


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    if not args.topics and not args.all:
        print('[record] error: name topics to record or give --all', file=sys.stderr)
        return 2
    if args.duration < 0 or args.max_messages < 0:
        print('[record] error: --duration and --max-messages must be >= 0', file=sys.stderr)
        return 2
    # The bag is then closed by run(), never left half-written by rclpy's SIGINT handling.
    stop = stop_on_signals()
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.parameter import Parameter
    from rclpy.signals import SignalHandlerOptions
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('bag_recorder', parameter_overrides=[
        Parameter('use_sim_time', value=args.use_sim_time)])
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    try:
        return run(args, node, executor, stop)
    finally:
        executor.remove_node(node)
        node.destroy_node()
        executor.shutdown()
        rclpy.try_shutdown()

