"""Record topics of a node's graph into a rosbag2 directory, as `ros2 bag record` does.

The recorder discovers the awaited topics' publishers (every DISCOVERY_PERIOD s until all are
seen; with record_all, any new topic), subscribes with the QoS that matches them (so latched
data such as `map` and `footstep_plan` is recorded too), and hands the raw CDR bytes to a
BagWriter, which flushes them to the file regularly (a killed recorder leaves a bag that
`record.py reindex` recovers). Messages are stamped with the node clock's receive time; on sim
time that clock reads 0 until the first /clock tick, so messages arriving before it are held
(at most MAX_EARLY) and written, stamped with the first tick's time, once the clock runs.
In-process use (demo, scenarios, tests):

  recorder = BagRecorder(node, 'output/bags/run1', topics=['walking_state', 'cmd_vel'])
  ... spin node's executor ...
  recorder.close(executor)   # drains what has arrived, then writes the index and metadata
"""
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path
import re
import time
from typing import Callable, Dict, Iterable, List, Optional, Sequence

from biped_tools.recording.bag_writer import BagWriter, FLUSH_PERIOD
from biped_tools.recording.errors import RecordError
from biped_tools.recording.message_types import import_message_class, TypeRegistry
from biped_tools.recording.topic_subscription import adapted_qos, resolve_topic

# Discovery poll period while topics are still awaited (s); discovery itself takes 0-2.6 s.
DISCOVERY_PERIOD = 0.2
# Messages held before the clock runs (sim time before the first /clock tick); more are dropped
# and counted.
MAX_EARLY = 10000


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
    dropped_before_clock: int = 0  # messages never written: the clock did not run (in time)

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
        if self.dropped_before_clock:
            out.append(f'  {self.dropped_before_clock} messages not written: they arrived '
                       f'before the first clock tick and the clock never ran (or > {MAX_EARLY})')
        return out


class BagRecorder:
    """Records topics of a node's graph into a rosbag2 directory.

    The caller spins the node (any executor); messages arrive as raw CDR bytes and are written
    unchanged with the node clock's receive time (sim time when the node uses it; messages
    that arrive while that clock reads 0, before the first /clock tick, are held and stamped
    with the first tick's time). Call `close()` (or use the recorder as a context manager) to
    write the index and metadata.yaml; a bag whose recorder was killed needs
    `biped_tools.recording.bag_reindex.reindex` first.

    :param node: the rclpy node whose subscriptions record
    :param output: the bag directory to create (must not exist)
    :param topics: topic names to record once a publisher appears (relative names resolve
        against the node's namespace)
    :param record_all: also record every other topic with a publisher, now and later
    :param exclude: regular expression of full topic names never recorded (with record_all)
    :param storage: 'mcap' or 'sqlite3'
    :param max_messages: stop writing after this many messages in total (0: no limit)
    :param flush_period: seconds between flushes to the file: a kill loses at most that much
    :param registry: type definitions (default: everything installed here)
    :param log: called with one line of text per event (default: the node's logger)
    :raises RecordError: for an invalid topic name, an unknown storage or an existing output
    """

    def __init__(self, node, output, topics: Iterable[str] = (), record_all: bool = False,
                 exclude: Optional[str] = None, storage: str = 'mcap', max_messages: int = 0,
                 flush_period: float = FLUSH_PERIOD, registry: Optional[TypeRegistry] = None,
                 log: Optional[Callable[[str], None]] = None) -> None:
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
        self.records: Dict[str, TopicRecord] = {}
        self.errors: Dict[str, str] = {}
        self._log = log or (lambda text: node.get_logger().info(text))
        self._written = 0
        self._closed = False
        self._early = deque()  # (record, data) received before the clock ran
        self._dropped_early = 0
        self.writer = BagWriter(output, storage, flush_period)
        from rclpy.clock import Clock, ClockType
        # Steady clocks: with use_sim_time, a ROS-time timer would wait for /clock.
        self._timer = node.create_timer(DISCOVERY_PERIOD, self.discover,
                                        clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._flush_timer = node.create_timer(min(0.25, flush_period / 2.0), self._on_flush_timer,
                                              clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.discover()

    @property
    def path(self) -> Path:
        """The bag directory."""
        return self.writer.path

    @property
    def storage(self) -> str:
        return self.writer.storage

    @property
    def message_count(self) -> int:
        """Messages written so far, over all topics."""
        return self._written

    @property
    def done(self) -> bool:
        """True once max_messages are written or writing failed: the caller should stop."""
        return self.writer.error is not None or (
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
        topic = resolve_topic(self.node, topic)
        if topic in self.records:
            raise RecordError(f'{topic} is already recorded')
        if self._closed:
            raise RecordError('the recorder is closed')
        msg_class = import_message_class(type_name)
        self.registry.ensure(type_name)
        self.registry.check_hash(type_name, announced_hash)
        subscription_qos = qos if qos is not None else adapted_qos(offered)
        connection = self.writer.add_connection(topic, type_name, self.registry.typestore,
                                                offered)
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
        if stamp <= 0:
            # Sim time before the first /clock tick: a stamp of 0 would misplace the message.
            if len(self._early) < MAX_EARLY:
                self._early.append((record, data))
            else:
                self._dropped_early += 1
            return
        self._write_early(stamp)
        self._write(record, stamp, data)

    def _write_early(self, stamp: int) -> None:
        """Write the messages held until the clock ran, stamped with its first reading."""
        if self._early:
            self._log(f'clock running: writing {len(self._early)} messages received before '
                      f'its first tick, stamped {stamp * 1e-9:.3f} s')
        while self._early and not self.done:
            record, data = self._early.popleft()
            self._write(record, stamp, data)

    def _write(self, record: TopicRecord, stamp: int, data: bytes) -> None:
        try:
            written = self.writer.write(record.connection, stamp, data)
        except RecordError as error:
            # A full disk must stop the recording cleanly, not kill the executor.
            self._log(f'error: {error}')
            return
        if written:
            record.count += 1
            self._written += 1

    def _on_flush_timer(self) -> None:
        if self._closed:
            return
        stamp = self.node.get_clock().now().nanoseconds
        if stamp > 0:
            self._write_early(stamp)
        try:
            self.writer.flush_if_due()
        except RecordError as error:
            self._log(f'error: {error}')

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
            stamp = self.node.get_clock().now().nanoseconds
            if stamp > 0:
                self._write_early(stamp)
            self._dropped_early += len(self._early)
            self._early.clear()
            self._closed = True
            if self._timer is not None:
                self.node.destroy_timer(self._timer)
                self._timer = None
            self.node.destroy_timer(self._flush_timer)
            for record in self.records.values():
                self.node.destroy_subscription(record.subscription)
            self.writer.close()
        return self.summary()

    def summary(self) -> RecordSummary:
        """:return: the topics, counts, awaited topics and errors so far"""
        errors = dict(self.errors)
        if self.writer.error:
            errors['(bag)'] = self.writer.error
        return RecordSummary(self.path, self.storage, list(self.records.values()),
                             self.waiting, errors, self._dropped_early)

    def __enter__(self) -> 'BagRecorder':
        return self

    def __exit__(self, *exc) -> bool:
        self.close()
        return False
