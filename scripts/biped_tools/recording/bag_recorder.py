#!/usr/bin/env python3
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

In-process use (demo and scenario scripts):

  recorder = BagRecorder(node, 'output/bags/run1', topics=['walking_state', 'cmd_vel'])
  ... spin node's executor ...
  recorder.close(executor)   # drains what has arrived, then writes the index and metadata
"""
import argparse
from dataclasses import dataclass, field
from datetime import datetime
import importlib
import os
from pathlib import Path
import re
import signal
import sys
import threading
import time
from typing import Callable, Dict, Iterable, Iterator, List, Optional, Sequence

REPO = Path(__file__).resolve().parent.parent
DEFAULT_BAG_DIR = REPO / 'output' / 'bags'
STORAGES = ('mcap', 'sqlite3')
# Discovery poll period while topics are still awaited (s); discovery itself takes 0-2.6 s.
DISCOVERY_PERIOD = 0.2
# Subscription history: deep enough for a publisher's transient_local history and for bursts of
# a 1 kHz topic while Python writes (DDS allocates samples as they come, not up front).
RECORD_DEPTH = 1000


class RecordError(Exception):
    """A topic or type cannot be recorded, or the bag cannot be written."""


def interface_prefixes() -> List[Path]:
    """Install prefixes whose share/<pkg>/msg/*.msg define the interfaces rclpy uses.

    :return: AMENT_PREFIX_PATH entries, the workspace's biped_msgs install and the venv (where
        the ROS wheels install their share/ files), without duplicates, in that order
    """
    candidates = [Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    candidates += [REPO / 'ros2_ws' / 'install' / 'biped_msgs', Path(sys.prefix)]
    prefixes: List[Path] = []
    for prefix in candidates:
        if prefix not in prefixes:
            prefixes.append(prefix)
    return prefixes


def _nested_types(desc) -> Iterator[str]:
    """Names of the message types a rosbags field descriptor refers to."""
    from rosbags.interfaces import Nodetype
    kind, rest = desc
    if kind == Nodetype.NAME:
        yield rest
    elif kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        yield from _nested_types(rest[0])


class TypeRegistry:
    """A rosbags typestore that knows every interface type installed here, ours included.

    Definitions come from the installed .msg files (the ones rclpy's type support was generated
    from); rosbags' own Jazzy store only fills in types that have no .msg file (e.g. service
    event types). rosbags then computes the message definition and RIHS01 hash written into
    the bag; `check_hash` compares that hash with the one a publisher announces on the graph.

    :param prefixes: install prefixes to search (default: `interface_prefixes()`)
    """

    def __init__(self, prefixes: Optional[Sequence[Path]] = None) -> None:
        from rosbags.typesys import get_typestore, Stores
        self.prefixes = list(interface_prefixes() if prefixes is None else prefixes)
        self.typestore = get_typestore(Stores.EMPTY)
        self._fallback = get_typestore(Stores.ROS2_JAZZY)

    def find_msg_file(self, type_name: str) -> Optional[Path]:
        """:return: the installed .msg file of 'pkg/msg/Type', or None"""
        package, kind, name = split_type_name(type_name)
        for prefix in self.prefixes:
            path = prefix / 'share' / package / kind / f'{name}.msg'
            if path.is_file():
                return path
        return None

    def ensure(self, type_name: str) -> None:
        """Register type_name and every type it uses.

        :raises RecordError: if a definition is found neither installed nor in rosbags' store
        """
        from rosbags.typesys import get_types_from_msg, TypesysError
        if type_name in self.typestore.fielddefs:
            return
        path = self.find_msg_file(type_name)
        if path is not None:
            try:
                types = get_types_from_msg(path.read_text(), type_name)
            except TypesysError as error:
                raise RecordError(f'cannot parse {path}: {error}') from None
        elif type_name in self._fallback.fielddefs:
            types = {type_name: self._fallback.fielddefs[type_name]}
        else:
            searched = ', '.join(str(p / 'share') for p in self.prefixes)
            raise RecordError(f'no message definition for {type_name}: no .msg file under '
                              f'{searched} and not a standard Jazzy type')
        for _, fields in types.values():
            for _, desc in fields:
                for nested in _nested_types(desc):
                    if nested != type_name:
                        self.ensure(nested)
        self.typestore.register(types)

    def rihs01(self, type_name: str) -> str:
        """:return: the RIHS01 type hash rosbags writes for type_name (registering it first)"""
        self.ensure(type_name)
        return self.typestore.hash_rihs01(type_name)

    def check_hash(self, type_name: str, announced: str) -> None:
        """Compare rosbags' hash of type_name with the one a publisher announced.

        A mismatch means the bag would carry a definition other than the publisher's, so its
        messages could not be decoded correctly.
        :param announced: 'RIHS01_<hex>' from the graph; anything else is not checked
        :raises RecordError: naming both hashes on a mismatch
        """
        if not announced.startswith('RIHS01_') or set(announced[7:]) <= {'0'}:
            return
        ours = self.rihs01(type_name)
        if ours != announced:
            raise RecordError(f'{type_name}: the publisher\'s type hash {announced} differs '
                              f'from the installed definition\'s {ours}; rebuild the workspace')


def split_type_name(type_name: str) -> tuple:
    """'pkg/msg/Type' -> ('pkg', 'msg', 'Type').

    :raises RecordError: for any other form
    """
    parts = type_name.split('/')
    if len(parts) != 3 or not all(parts):
        raise RecordError(f'type {type_name!r}: expected package/msg/Type')
    return tuple(parts)


def import_message_class(type_name: str):
    """Import the Python class of 'pkg/msg/Type' (rclpy needs it for the type support).

    :raises RecordError: if the type is not installed here
    """
    package, kind, name = split_type_name(type_name)
    try:
        return getattr(importlib.import_module(f'{package}.{kind}'), name)
    except (ImportError, AttributeError):
        raise RecordError(f'unknown type {type_name!r}: not installed for this Python '
                          f'(no {package}.{kind}.{name}); run scripts/setup.sh or install '
                          f'the interface package') from None


def _rosbags_qos(profile):
    """An rclpy QoSProfile as rosbags' Qos (for offered_qos_profiles in the bag)."""
    from rosbags.interfaces import (Qos, QosDurability, QosHistory, QosLiveliness,
                                    QosReliability, QosTime)

    def as_time(duration) -> QosTime:
        # rclpy's infinite duration is int64 max ns, which rosbag2 also writes as sec/nsec.
        return QosTime(*divmod(duration.nanoseconds, 10**9))

    return Qos(history=QosHistory(int(profile.history)), depth=int(profile.depth),
               reliability=QosReliability(int(profile.reliability)),
               durability=QosDurability(int(profile.durability)),
               deadline=as_time(profile.deadline), lifespan=as_time(profile.lifespan),
               liveliness=QosLiveliness(int(profile.liveliness)),
               liveliness_lease_duration=as_time(profile.liveliness_lease_duration),
               avoid_ros_namespace_conventions=bool(profile.avoid_ros_namespace_conventions))


def adapted_qos(offered: Sequence):
    """The subscription QoS that matches every offered publisher QoS, as rosbag2 chooses it.

    Reliable only if every publisher is reliable (a reliable reader does not match a
    best-effort writer); transient_local only if every publisher is, so that their stored
    history (maps, plans) is delivered to us too.
    :param offered: the publishers' rclpy QoSProfiles
    """
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    reliable = all(p.reliability == ReliabilityPolicy.RELIABLE for p in offered)
    latched = bool(offered) and all(p.durability == DurabilityPolicy.TRANSIENT_LOCAL
                                    for p in offered)
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST, depth=RECORD_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)


def resolve_topic(node, topic: str) -> str:
    """Expand a (relative) topic name against the node's namespace and remappings.

    :raises RecordError: with rcl's reason for an invalid name
    """
    try:
        return node.resolve_topic_name(topic)
    except RuntimeError as error:
        reason = str(error).replace('failed to resolve name: ', '').split(', at /')[0]
        raise RecordError(f'invalid topic name {topic!r}: {reason}') from None


@dataclass
class TopicRecord:
    """One recorded topic: its bag connection, subscription and message count."""

    topic: str
    type_name: str
    connection: object
    subscription: object = None
    count: int = 0
    qos: Optional[object] = None


@dataclass
class RecordSummary:
    """What a recording wrote, for the end-of-run report."""

    path: Path
    storage: str
    topics: List[TopicRecord] = field(default_factory=list)
    waiting: List[str] = field(default_factory=list)
    errors: Dict[str, str] = field(default_factory=dict)

    @property
    def message_count(self) -> int:
        return sum(t.count for t in self.topics)

    def lines(self) -> List[str]:
        """One line for the bag, then one per topic (count, type), then waits and errors."""
        rows = [(t.topic, t.type_name, str(t.count)) for t in self.topics]
        rows += [(topic, '(no publisher seen)', '0') for topic in self.waiting]
        rows += [(topic, f'(not recorded: {error})', '0') for topic, error in self.errors.items()]
        width = max([len(r[0]) for r in rows] + [5])
        type_width = max([len(r[1]) for r in rows if not r[1].startswith('(')] + [4])
        out = [f'bag {self.path} ({self.storage}): {self.message_count} messages on '
               f'{len(self.topics)} topics']
        out += [f'  {topic.ljust(width)}  {count.rjust(7)}  {kind.ljust(type_width)}'.rstrip()
                for topic, kind, count in rows]
        return out


class BagRecorder:
    """Records topics of a node's graph into a rosbag2 directory.

    The caller spins the node (any executor); messages arrive as raw CDR bytes and are written
    unchanged with the node clock's receive time (sim time when the node uses it). Call
    `close()` (or use the recorder as a context manager) to write the index and metadata.yaml:
    a bag that is not closed is not readable.

    :param node: the rclpy node whose subscriptions record
    :param output: the bag directory to create (must not exist)
    :param topics: topic names to record once a publisher appears (relative names resolve
        against the node's namespace)
    :param record_all: also record every other topic with a publisher, now and later
    :param exclude: regular expression of full topic names never recorded (with record_all)
    :param storage: 'mcap' or 'sqlite3'
    :param max_messages: stop writing after this many messages in total (0: no limit)
    :param registry: type definitions (default: everything installed here)
    :param log: called with one line of text per event (default: the node's logger)
    :raises RecordError: for an invalid topic name, an unknown storage or an existing output
    """

    def __init__(self, node, output, topics: Iterable[str] = (), record_all: bool = False,
                 exclude: Optional[str] = None, storage: str = 'mcap', max_messages: int = 0,
                 registry: Optional[TypeRegistry] = None,
                 log: Optional[Callable[[str], None]] = None) -> None:
        from rosbags.rosbag2 import StoragePlugin, Writer, WriterError
        if storage not in STORAGES:
            raise RecordError(f'storage {storage!r}: expected one of {", ".join(STORAGES)}')
        if max_messages < 0:
            raise RecordError(f'max_messages {max_messages}: expected >= 0')
        try:
            self._exclude = re.compile(exclude) if exclude else None
        except re.error as error:
            raise RecordError(f'exclude pattern {exclude!r}: {error}') from None
        self.node = node
        self.wanted = [resolve_topic(node, t) for t in topics]
        self.record_all = record_all
        self.max_messages = max_messages
        self.registry = registry or TypeRegistry()
        self.path = Path(output)
        self.storage = storage
        self.records: Dict[str, TopicRecord] = {}
        self.errors: Dict[str, str] = {}
        self._log = log or (lambda text: node.get_logger().info(text))
        self._lock = threading.Lock()
        self._written = 0
        self._closed = False
        self._write_error: Optional[str] = None
        try:
            self._writer = Writer(self.path, version=Writer.VERSION_LATEST,
                                  storage_plugin=StoragePlugin[storage.upper()])
            self._writer.open()
        except WriterError as error:
            raise RecordError(f'cannot create bag: {error}') from None
        from rclpy.clock import Clock, ClockType
        # A steady clock: with use_sim_time, a ROS-time timer would wait for /clock.
        self._timer = node.create_timer(DISCOVERY_PERIOD, self.discover,
                                        clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.discover()

    @property
    def message_count(self) -> int:
        """Messages written so far, over all topics."""
        return self._written

    @property
    def done(self) -> bool:
        """True once max_messages are written or writing failed: the caller should stop."""
        return self._write_error is not None or (
            self.max_messages > 0 and self._written >= self.max_messages)

    @property
    def waiting(self) -> List[str]:
        """Named topics not recorded yet (no publisher seen, no error)."""
        return [t for t in self.wanted if t not in self.records and t not in self.errors]

    def discover(self) -> None:
        """Subscribe to awaited (or, with record_all, any new) topics that have publishers.

        Errors (unknown type, hash mismatch) are logged once per topic and kept in `errors`;
        the recording of other topics goes on.
        """
        if self._closed:
            return
        candidates = set(self.waiting)
        if self.record_all:
            candidates |= {name for name, _ in self.node.get_topic_names_and_types()
                           if name not in self.records and name not in self.errors and
                           not (self._exclude and self._exclude.search(name))}
        for topic in sorted(candidates):
            infos = self.node.get_publishers_info_by_topic(topic)
            if not infos:
                continue
            types = sorted({info.topic_type for info in infos})
            if len(types) > 1:
                self._log(f'warning: {topic} is published with several types {types}; '
                          f'recording {types[0]}')
            same_type = [info for info in infos if info.topic_type == types[0]]
            try:
                self.add_topic(topic, types[0], offered=[info.qos_profile for info in same_type],
                               announced_hash=str(same_type[0].topic_type_hash))
            except RecordError as error:
                self.errors[topic] = str(error)
                self._log(f'error: not recording {topic}: {error}')
        if not self.record_all and not self.waiting and self._timer is not None:
            self.node.destroy_timer(self._timer)
            self._timer = None

    def add_topic(self, topic: str, type_name: str, offered: Sequence = (),
                  announced_hash: str = '', qos=None) -> TopicRecord:
        """Start recording one topic now (discovery calls this; in-process users may too).

        :param topic: topic name (relative names resolve against the node's namespace)
        :param type_name: 'pkg/msg/Type'
        :param offered: the publishers' QoS profiles; the subscription matches them and the
            bag keeps them (ros2 bag play republishes with them)
        :param announced_hash: the publishers' RIHS01 type hash, checked against ours
        :param qos: subscription QoS (default: adapted to `offered`)
        :return: the topic's record
        :raises RecordError: for an invalid name, an unknown type, a hash mismatch or a topic
            already recorded
        """
        from rosbags.rosbag2 import WriterError
        topic = resolve_topic(self.node, topic)
        if topic in self.records:
            raise RecordError(f'{topic} is already recorded')
        if self._closed:
            raise RecordError('the recorder is closed')
        msg_class = import_message_class(type_name)
        self.registry.ensure(type_name)
        self.registry.check_hash(type_name, announced_hash)
        subscription_qos = qos if qos is not None else adapted_qos(offered)
        try:
            with self._lock:
                connection = self._writer.add_connection(
                    topic, type_name, typestore=self.registry.typestore,
                    offered_qos_profiles=[_rosbags_qos(p) for p in offered])
        except WriterError as error:
            raise RecordError(f'{topic}: {error}') from None
        record = TopicRecord(topic, type_name, connection, qos=subscription_qos)
        record.subscription = self.node.create_subscription(
            msg_class, topic, lambda data, record=record: self._on_message(record, data),
            subscription_qos, raw=True)
        self.records[topic] = record
        self.errors.pop(topic, None)
        durability = subscription_qos.durability.name.lower()
        self._log(f'recording {topic} ({type_name}, {durability})')
        return record

    def _on_message(self, record: TopicRecord, data: bytes) -> None:
        if self.done or self._closed:
            return
        stamp = self.node.get_clock().now().nanoseconds
        with self._lock:
            if self._closed:
                return
            try:
                self._writer.write(record.connection, stamp, data)
            except OSError as error:
                # A full disk must stop the recording cleanly, not kill the executor.
                self._write_error = f'writing {record.topic} failed: {error}'
                self._log(f'error: {self._write_error}')
                return
            record.count += 1
            self._written += 1

    def drain(self, executor, quiet: float = 0.15, limit: float = 2.0) -> None:
        """Spin until no message has arrived for `quiet` s (at most `limit` s).

        Takes what DDS has already delivered to our readers, so that a stop right after a
        publish loses nothing.
        """
        deadline = time.monotonic() + limit
        last, quiet_since = self._written, time.monotonic()
        while time.monotonic() < deadline and not self.done:
            executor.spin_once(timeout_sec=0.02)
            now = time.monotonic()
            if self._written != last:
                last, quiet_since = self._written, now
            elif now - quiet_since >= quiet:
                break

    def close(self, executor=None) -> RecordSummary:
        """Stop the subscriptions and write the bag's index and metadata.yaml (idempotent).

        :param executor: if given, first drain the messages DDS has already delivered
        :return: what was recorded
        """
        if not self._closed:
            if executor is not None:
                self.drain(executor)
            with self._lock:
                self._closed = True
                if self._timer is not None:
                    self.node.destroy_timer(self._timer)
                    self._timer = None
                for record in self.records.values():
                    self.node.destroy_subscription(record.subscription)
                self._writer.close()
        return self.summary()

    def summary(self) -> RecordSummary:
        """:return: the topics, counts, awaited topics and errors so far"""
        errors = dict(self.errors)
        if self._write_error:
            errors['(bag)'] = self._write_error
        return RecordSummary(self.path, self.storage, list(self.records.values()),
                             self.waiting, errors)

    def __enter__(self) -> 'BagRecorder':
        return self

    def __exit__(self, *exc) -> bool:
        self.close()
        return False


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
    # Our handlers only set a flag: the bag is then closed by run(), never left half-written
    # by rclpy's own SIGINT handling.
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
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


if __name__ == '__main__':
    sys.exit(main())
