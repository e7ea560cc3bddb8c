"""Record topics into a real rosbag2 directory (metadata.yaml + MCAP or sqlite3), like
`ros2 bag record` (rosbag2 is not installable here).

Messages are taken as raw CDR bytes and written unchanged; every connection carries its full
message definition and RIHS01 type hash, so `ros2 bag info` / `ros2 bag play` on a full ROS
install, rosbags' AnyReader and MCAP tools read the bag. Subscriptions take the publishers' QoS
(transient_local topics such as `map` and `footstep_plan` are recorded, latched data included).

  .venv/bin/python scripts/record.py walking_state cmd_vel footstep_plan     # until Ctrl-C
  .venv/bin/python scripts/record.py --all -x '/rosout|/parameter_events' --duration 10
  .venv/bin/python scripts/record.py -o output/bags/walk1 --storage sqlite3 walking_state
  .venv/bin/python scripts/record.py reindex output/bags/walk1    # after a kill -9

Named topics are recorded as soon as a publisher appears; topics appearing later are added
when discovered. Ctrl-C, SIGTERM, --duration and --max-messages all close the bag properly.
What is recorded reaches the file every --flush-period s, so a recorder killed otherwise
(SIGKILL, a crash) loses at most that much: `record.py reindex BAG_DIR` (like `ros2 bag
reindex`) then rebuilds a readable file (MCAP index and footer) and metadata.yaml from every
complete message written. With --use-sim-time, messages that arrive before the first /clock
tick are held and written once the clock runs, stamped with its first time (none is stamped 0).
In-process use: biped_tools.recording.BagRecorder and bag_reindex.reindex.
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
from biped_tools.recording.bag_reindex import reindex
from biped_tools.recording.bag_writer import FLUSH_PERIOD, STORAGES
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
    parser.add_argument('--flush-period', type=float, default=FLUSH_PERIOD, metavar='S',
                        help='seconds between flushes to the file: a killed recorder loses at '
                             'most that much (default %(default)s)')
    parser.add_argument('--use-sim-time', action='store_true',
                        help='stamp messages with /clock time (as the simulated graph does); '
                             'messages arriving before the first /clock tick are buffered '
                             'and written with its time, never stamped 0')
    return parser


def build_reindex_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='record.py reindex',
        description='Rebuild a bag whose recorder was killed, like `ros2 bag reindex`: a '
                    'readable storage file (MCAP with index and footer, or sqlite3) and '
                    'metadata.yaml, from every complete message that reached the file.')
    parser.add_argument('bag', type=Path, help='the bag directory')
    parser.add_argument('--force', action='store_true',
                        help='rewrite even a bag that was closed properly')
    return parser


def reindex_main(argv) -> int:
    """:return: 0 rebuilt (or complete already), 1 nothing could be read"""
    args = build_reindex_parser().parse_args(argv)
    try:
        result = reindex(args.bag, force=args.force)
    except RecordError as error:
        print(f'[record] error: {error}', file=sys.stderr)
        return 1
    for line in result.lines():
        print(f'[record] {line}')
    return 0


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
                               storage=args.storage, max_messages=args.max_messages,
                               flush_period=args.flush_period, log=log)
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
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ['reindex']:
        return reindex_main(argv[1:])
    args = build_parser().parse_args(argv)
    if not args.topics and not args.all:
        print('[record] error: name topics to record or give --all', file=sys.stderr)
        return 2
    if args.duration < 0 or args.max_messages < 0:
        print('[record] error: --duration and --max-messages must be >= 0', file=sys.stderr)
        return 2
    if not args.flush_period > 0:
        print('[record] error: --flush-period must be > 0', file=sys.stderr)
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

