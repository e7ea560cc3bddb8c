"""Recover a bag whose writer died, like `ros2 bag reindex`: a readable file and metadata.yaml.

A recorder killed by SIGKILL (or a power cut) leaves its storage file without index, summary
and footer (MCAP) or without its last transaction (sqlite3), and no metadata.yaml; no reader
opens it. reindex reads every complete message that reached the file (mcap_scan for MCAP; for
sqlite3 the committed rows), writes them again with rosbags' Writer, whose file then has an
index and footer, and replaces the storage file and metadata.yaml atomically. Each connection
keeps its topic, type, message definition, serialization format and offered QoS; its RIHS01
hash is taken from the file (sqlite3) or computed from the stored definition (MCAP), as rosbags'
readers check it.
"""
from dataclasses import dataclass, field
import os
from pathlib import Path
import shutil
import sqlite3
from typing import Callable, Dict, Iterator, List, Optional, Tuple

from biped_tools.recording.errors import RecordError
from biped_tools.recording.mcap_scan import McapScan, scan_mcap


@dataclass
class ConnectionInfo:
    """One topic of the bag being recovered, in the form rosbags' Writer takes."""

    topic: str
    type_name: str
    definition: str
    rihs01: str
    serialization_format: str
    qos_yaml: str   # offered_qos_profiles as the storage keeps it


@dataclass
class ReindexResult:
    """What reindex did.

    :ivar path: the bag directory
    :ivar storage_file: the file rewritten
    :ivar counts: messages kept per topic
    :ivar rewritten: False when the bag was complete already and left alone
    :ivar problem: why reading stopped before the end of the file (what was lost), or ''
    """

    path: Path
    storage_file: Path
    counts: Dict[str, int] = field(default_factory=dict)
    rewritten: bool = True
    problem: str = ''

    @property
    def message_count(self) -> int:
        return sum(self.counts.values())

    def lines(self) -> List[str]:
        if not self.rewritten:
            return [f'{self.path}: complete already ({self.storage_file.name} was closed by '
                    'its writer and metadata.yaml exists); nothing to do (--force rewrites it)']
        out = [f'{self.path}: rebuilt {self.storage_file.name} and metadata.yaml, '
               f'{self.message_count} messages on {len(self.counts)} topics']
        out += [f'  {topic}  {count}' for topic, count in sorted(self.counts.items())]
        if self.problem:
            out.append(f'  lost after that: {self.problem}')
        return out


def storage_file(bag: Path) -> Path:
    """The one storage file of a bag directory (.mcap or .db3).

    :raises RecordError: if the directory is missing or holds none or several
    """
    if not bag.is_dir():
        raise RecordError(f'{bag}: no such bag directory')
    files = sorted(p for p in bag.iterdir() if p.suffix in ('.mcap', '.db3') and p.is_file())
    if len(files) != 1:
        found = ', '.join(p.name for p in files) or 'none'
        raise RecordError(f'{bag}: expected one .mcap or .db3 file, found {found}')
    return files[0]


def rihs01_of_definition(type_name: str, definition: str) -> str:
    """The RIHS01 hash of a type from its stored (concatenated) .msg definition.

    :raises RecordError: if the definition cannot be parsed
    """
    from rosbags.typesys import get_typestore, get_types_from_msg, Stores, TypesysError
    store = get_typestore(Stores.EMPTY)
    try:
        store.register(get_types_from_msg(definition, type_name))
        return store.hash_rihs01(type_name)
    except (TypesysError, KeyError) as error:
        raise RecordError(f'{type_name}: cannot parse its stored definition: {error}') from None


def _mcap_content(path: Path) -> Tuple[List[Tuple[int, ConnectionInfo]], Iterator, McapScan]:
    scan = scan_mcap(path)
    connections = []
    for channel in scan.channels.values():
        schema = scan.schemas.get(channel.schema_id)
        if schema is None or schema.encoding != 'ros2msg':
            raise RecordError(f'{path}: channel {channel.topic} has no ros2msg schema')
        definition = schema.data.decode('utf-8')
        # rosbag2 keeps the hash in the channel; rosbags does not.
        digest = channel.metadata.get('topic_type_hash') or rihs01_of_definition(schema.name,
                                                                                  definition)
        connections.append((channel.id, ConnectionInfo(
            channel.topic, schema.name, definition, digest, channel.message_encoding,
            channel.metadata.get('offered_qos_profiles', ''))))
    messages = ((m.channel_id, m.log_time, m.data) for m in scan.messages)
    return connections, messages, scan


def _sqlite3_content(path: Path):
    try:
        # Opening rolls back a transaction the dead writer left half done (its journal).
        db = sqlite3.connect(f'file:{path}', uri=True)
        definitions = {row[0]: row[1:] for row in db.execute(
            'SELECT topic_type, encoding, encoded_message_definition, type_description_hash '
            'FROM message_definitions')}
        topics = db.execute('SELECT id, name, type, serialization_format, offered_qos_profiles, '
                            'type_description_hash FROM topics ORDER BY id').fetchall()
    except sqlite3.Error as error:
        raise RecordError(f'{path}: not a readable rosbag2 sqlite3 file: {error}') from None
    connections = []
    for topic_id, name, type_name, serialization, qos, digest in topics:
        definition = definitions.get(type_name, ('', '', ''))[1]
        if not definition:
            raise RecordError(f'{path}: no message definition stored for {type_name}')
        connections.append((topic_id, ConnectionInfo(name, type_name, definition, digest,
                                                     serialization, qos)))

    def messages():
        try:
            yield from db.execute('SELECT topic_id, timestamp, data FROM messages ORDER BY id')
        finally:
            db.close()
    return connections, messages(), None


def _complete(bag: Path, path: Path) -> bool:
    """Whether the bag opens as it is: metadata.yaml exists and the file was closed."""
    if not (bag / 'metadata.yaml').is_file():
        return False
    if path.suffix == '.mcap':
        return scan_mcap(path).complete
    return True


def reindex(bag, force: bool = False, log: Optional[Callable[[str], None]] = None
            ) -> ReindexResult:
    """Rebuild a bag directory's storage file and metadata.yaml from what was written.

    :param bag: the bag directory (as `record.py -o` made it)
    :param force: rewrite even a bag that is complete
    :param log: called with progress lines
    :return: what was kept
    :raises RecordError: for a missing directory, no storage file, or nothing readable
    """
    from rosbags.rosbag2 import StoragePlugin, Writer, WriterError
    from rosbags.rosbag2.metadata import parse_qos
    from rosbags.rosbag2.errors import ReaderError
    log = log or (lambda text: None)
    bag = Path(bag)
    path = storage_file(bag)
    if not force and _complete(bag, path):
        return ReindexResult(bag, path, rewritten=False)
    if path.suffix == '.mcap':
        connections, messages, scan = _mcap_content(path)
        problem = scan.problem
        if scan.dropped_messages:
            problem += f'; {scan.dropped_messages} messages of unknown channels dropped'
        plugin = StoragePlugin.MCAP
    else:
        connections, messages, _ = _sqlite3_content(path)
        problem = ''
        plugin = StoragePlugin.SQLITE3
    work = bag / '.reindex'
    if work.exists():
        shutil.rmtree(work)
    work.mkdir()
    result = ReindexResult(bag, path, problem=problem.lstrip('; '))
    try:
        # rosbags names the file after the directory: the same name as the file replaced.
        new_bag = work / path.stem
        writer = Writer(new_bag, version=Writer.VERSION_LATEST, storage_plugin=plugin)
        writer.open()
        by_id = {}
        for key, info in connections:
            try:
                qos = parse_qos(info.qos_yaml)
            except ReaderError:
                qos = []
                log(f'warning: {info.topic}: offered QoS unreadable, written without')
            by_id[key] = (writer.add_connection(
                info.topic, info.type_name, msgdef=info.definition, rihs01=info.rihs01,
                serialization_format=info.serialization_format, offered_qos_profiles=qos),
                info.topic)
            result.counts[info.topic] = 0
        for key, stamp, data in messages:
            if key not in by_id:
                continue
            connection, topic = by_id[key]
            writer.write(connection, stamp, data)
            result.counts[topic] += 1
        writer.close()
        # A dead sqlite3 writer's journal must not be applied to the new file.
        (bag / (path.name + '-journal')).unlink(missing_ok=True)
        os.replace(new_bag / path.name, path)
        os.replace(new_bag / 'metadata.yaml', bag / 'metadata.yaml')
    except (WriterError, OSError) as error:
        raise RecordError(f'{bag}: cannot write the recovered bag: {error}') from None
    finally:
        shutil.rmtree(work, ignore_errors=True)
    log(f'{bag}: {result.message_count} messages kept')
    return result
