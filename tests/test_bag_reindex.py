"""Bags whose writer died: what reached the file is flushed regularly, and reindex recovers it.

No DDS here: the BagWriter is driven directly and its file copied as a killed writer leaves it
(everything flushed is on disk, the pending part only in the dead process's memory).
"""
from pathlib import Path
import shutil
import subprocess

import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile
from rclpy.serialization import deserialize_message, serialize_message
from std_msgs.msg import String
import yaml

from biped_tools.recording import reindex, RecordError, TypeRegistry
from biped_tools.recording.bag_writer import BagWriter
from biped_tools.recording.mcap_scan import MAGIC, scan_mcap
from ros_harness import PYTHON, REPO

RECORD = str(REPO / 'scripts' / 'record.py')
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


def message(i: int) -> bytes:
    return serialize_message(String(data=f'message {i} ' + 'x' * (i % 7)))


class DyingWriter:
    """A BagWriter on two topics whose file can be copied as a kill would leave it."""

    def __init__(self, path: Path, storage: str = 'mcap') -> None:
        registry = TypeRegistry()
        registry.ensure('std_msgs/msg/String')
        self.writer = BagWriter(path, storage, flush_period=1000.0)
        self.connections = [
            self.writer.add_connection('/chatter', 'std_msgs/msg/String', registry.typestore),
            self.writer.add_connection('/latched', 'std_msgs/msg/String', registry.typestore,
                                       offered=[LATCHED])]
        self.sent = 0

    def write(self, count: int) -> None:
        """count messages, alternating topics, stamped 1 s + i ms."""
        for _ in range(count):
            self.writer.write(self.connections[self.sent % 2], 10**9 + self.sent * 10**6,
                              message(self.sent))
            self.sent += 1


def killed_copy(source: Path, target: Path) -> Path:
    shutil.copytree(source, target)
    return target


def read_back(bag: Path):
    """[(topic, stamp, index)] via rosbags' AnyReader, and the metadata's topic entries."""
    from rosbags.highlevel import AnyReader
    with AnyReader([bag]) as reader:
        rows = [(c.topic, stamp, deserialize_message(bytes(raw), String).data)
                for c, stamp, raw in reader.messages()]
    info = yaml.safe_load((bag / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    return rows, {t['topic_metadata']['name']: t for t in info['topics_with_message_count']}


@pytest.fixture
def flushed_and_pending(tmp_path):
    """A killed MCAP bag: 3 flushes of 40 messages on disk, 25 more never flushed; and the
    same writer's bag closed properly after those 25."""
    dying = DyingWriter(tmp_path / 'live')
    for _ in range(3):
        dying.write(40)
        dying.writer.flush()
    dying.write(25)
    dead = killed_copy(tmp_path / 'live', tmp_path / 'dead')
    dying.writer.close()
    return dead, tmp_path / 'live'


def test_a_killed_mcap_bag_is_unreadable_and_reindex_recovers_every_flushed_message(
        flushed_and_pending):
    from rosbags.highlevel import AnyReader
    dead, closed = flushed_and_pending
    assert not (dead / 'metadata.yaml').exists()
    with pytest.raises(Exception):
        with AnyReader([dead]):
            pass
    result = reindex(dead)
    assert result.rewritten and result.message_count == 120
    assert result.counts == {'/chatter': 60, '/latched': 60}
    rows, topics = read_back(dead)
    assert [text for _, _, text in rows] == \
        [deserialize_message(message(i), String).data for i in range(120)]
    assert [stamp for _, stamp, _ in rows] == [10**9 + i * 10**6 for i in range(120)]
    # Type hash and offered QoS as the closed bag of the same writer has them.
    _, closed_topics = read_back(closed)
    for topic in ('/chatter', '/latched'):
        for key in ('type', 'type_description_hash', 'offered_qos_profiles'):
            assert topics[topic]['topic_metadata'][key] == \
                closed_topics[topic]['topic_metadata'][key], (topic, key)
    assert topics['/latched']['topic_metadata']['offered_qos_profiles'][0]['durability'] == \
        'transient_local'
    # An independent reader opens the rebuilt file through its summary and index.
    from mcap.reader import make_reader
    with open(result.storage_file, 'rb') as stream:
        reader = make_reader(stream)
        assert reader.get_summary().statistics.message_count == 120
        assert sum(1 for _ in reader.iter_messages()) == 120


def test_reindex_leaves_a_closed_bag_alone_unless_forced(flushed_and_pending):
    _, closed = flushed_and_pending
    before = (closed / 'live.mcap').read_bytes()
    assert not reindex(closed).rewritten
    assert (closed / 'live.mcap').read_bytes() == before
    result = reindex(closed, force=True)
    assert result.rewritten and result.message_count == 145 and not result.problem
    assert len(read_back(closed)[0]) == 145


def test_a_cut_anywhere_keeps_a_prefix_of_the_messages(flushed_and_pending, tmp_path):
    """Files cut at every few bytes (a write interrupted, a full disk): the scan keeps the
    complete messages before the cut, in order, including those of a cut chunk."""
    dead, _ = flushed_and_pending
    data = (dead / 'live.mcap').read_bytes()
    expected = [message(i) for i in range(120)]
    kept_counts = []
    for cut in list(range(len(MAGIC), len(data), 97)) + [len(data)]:
        path = tmp_path / 'cut.mcap'
        path.write_bytes(data[:cut])
        scan = scan_mcap(path)
        kept = [m.data for m in scan.messages]
        assert kept == expected[:len(kept)], cut
        assert not scan.complete
        if cut == len(data):
            assert scan.stopped_at is None and not scan.problem
        kept_counts.append(len(kept))
    assert kept_counts == sorted(kept_counts) and kept_counts[-1] == 120
    # More distinct prefixes than the 3 chunks: the messages of a cut chunk are kept.
    assert len(set(kept_counts)) > 10


def test_a_cut_bag_reindexes_to_what_its_scan_kept(flushed_and_pending):
    dead, _ = flushed_and_pending
    path = dead / 'live.mcap'
    data = path.read_bytes()
    path.write_bytes(data[:len(data) * 2 // 3])
    result = reindex(dead)
    assert 40 < result.message_count < 120
    assert 'ends inside a record' in result.problem
    rows, _ = read_back(dead)
    assert [text for _, _, text in rows] == \
        [deserialize_message(message(i), String).data for i in range(result.message_count)]


def test_a_killed_sqlite3_bag_keeps_its_committed_messages(tmp_path):
    dying = DyingWriter(tmp_path / 'live', storage='sqlite3')
    dying.write(30)
    dying.writer.flush()
    dying.write(10)   # an open transaction: rolled back
    dead = killed_copy(tmp_path / 'live', tmp_path / 'dead')
    dying.writer.close()
    result = reindex(dead)
    assert result.counts == {'/chatter': 15, '/latched': 15}
    rows, topics = read_back(dead)
    assert [text for _, _, text in rows] == \
        [deserialize_message(message(i), String).data for i in range(30)]
    assert topics['/chatter']['message_count'] == 15
    assert not (dead / 'live.db3-journal').exists()


def test_the_writer_flushes_by_itself_once_its_period_has_passed(tmp_path):
    dying = DyingWriter(tmp_path / 'live')
    dying.writer.flush_period = 1e-9
    dying.write(1)   # a write after the period flushes everything written so far
    dying.writer.flush_period = 1000.0
    dying.write(5)
    assert len(scan_mcap(tmp_path / 'live' / 'live.mcap').messages) == 1
    dying.writer.flush_period = 1e-9
    dying.writer.flush_if_due()   # what a timer does in a quiet spell
    assert len(scan_mcap(tmp_path / 'live' / 'live.mcap').messages) == 6
    dying.writer.close()


@pytest.mark.parametrize('make, words', [
    (lambda bag: None, 'no such bag directory'),
    (lambda bag: bag.mkdir(), 'expected one .mcap or .db3 file, found none'),
    (lambda bag: (bag.mkdir(), (bag / 'bag.mcap').write_bytes(b'not mcap at all')),
     'not an MCAP file'),
    (lambda bag: (bag.mkdir(), (bag / 'a.mcap').write_bytes(MAGIC),
                  (bag / 'b.mcap').write_bytes(MAGIC)), 'found a.mcap, b.mcap'),
])
def test_reindex_errors_are_clear(tmp_path, make, words):
    bag = tmp_path / 'bag'
    make(bag)
    with pytest.raises(RecordError, match=words):
        reindex(bag)
    result = subprocess.run([PYTHON, RECORD, 'reindex', str(bag)], capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 1
    assert words in result.stderr and 'Traceback' not in result.stderr
