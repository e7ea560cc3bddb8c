"""What a killed writer left in an MCAP file: every complete schema, channel and message.

MCAP (https://mcap.dev/spec) is a sequence of records `opcode (1 byte) | length (uint64) |
content`, little endian, between two magic strings; the index, summary and footer come last,
at close. A writer that dies leaves the data section only, possibly cut inside its last record.
scan_mcap reads record by record and stops at the first one that is incomplete, keeping what
came before: schemas, channels and messages, at top level or inside chunks. Chunks are
checked (size, CRC when set); a cut chunk that is not compressed still yields the complete
messages in its first part.
"""
from dataclasses import dataclass, field
import mmap
from pathlib import Path
import struct
from typing import Dict, List, Optional
import zlib

from biped_tools.recording.errors import RecordError

MAGIC = b'\x89MCAP0\r\n'
OP_FOOTER, OP_SCHEMA, OP_CHANNEL, OP_MESSAGE, OP_CHUNK, OP_DATA_END = 0x02, 0x03, 0x04, 0x05, \
    0x06, 0x0F


@dataclass(frozen=True)
class Schema:
    id: int
    name: str        # the message type, e.g. 'geometry_msgs/msg/Twist'
    encoding: str    # 'ros2msg' or 'ros2idl'
    data: bytes      # the full (concatenated) message definition


@dataclass(frozen=True)
class Channel:
    id: int
    schema_id: int
    topic: str
    message_encoding: str        # 'cdr'
    metadata: Dict[str, str]     # rosbag2 keeps 'offered_qos_profiles' here


@dataclass(frozen=True)
class Message:
    channel_id: int
    log_time: int    # ns: the time the bag stamps
    data: bytes


@dataclass
class McapScan:
    """The readable content of one MCAP file, in file order.

    :ivar complete: a footer was found (the writer closed the file)
    :ivar stopped_at: file offset where reading stopped (a cut or bad record), None at the end
    :ivar problem: why reading stopped early, or what was dropped
    :ivar dropped_messages: messages found whose channel was never seen
    """

    schemas: Dict[int, Schema] = field(default_factory=dict)
    channels: Dict[int, Channel] = field(default_factory=dict)
    messages: List[Message] = field(default_factory=list)
    complete: bool = False
    stopped_at: Optional[int] = None
    problem: str = ''
    dropped_messages: int = 0


class _Cut(Exception):
    """A record ends beyond the data available; args[0] is its offset."""


class _Fields:
    """Reads the fields of one record's content."""

    def __init__(self, data: bytes) -> None:
        self.data, self.pos = data, 0

    def take(self, size: int) -> bytes:
        if self.pos + size > len(self.data):
            raise RecordError(f'a field of {size} bytes at {self.pos} lies beyond the record')
        chunk = self.data[self.pos:self.pos + size]
        self.pos += size
        return chunk

    def uint(self, fmt: str) -> int:
        return struct.unpack('<' + fmt, self.take(struct.calcsize(fmt)))[0]

    def string(self) -> str:
        return self.take(self.uint('I')).decode('utf-8')

    def string_map(self) -> Dict[str, str]:
        entries = _Fields(self.take(self.uint('I')))
        result = {}
        while entries.pos < len(entries.data):
            key = entries.string()
            result[key] = entries.string()
        return result

    def rest(self) -> bytes:
        return self.take(len(self.data) - self.pos)


def _records(data, start: int = 0):
    """(offset, opcode, content) of each complete record in data from start.

    :raises _Cut: at the first record that does not fit, with its offset
    """
    pos = start
    while pos < len(data):
        if pos + 9 > len(data):
            raise _Cut(pos)
        opcode = data[pos]
        (length,) = struct.unpack_from('<Q', data, pos + 1)
        if pos + 9 + length > len(data):
            raise _Cut(pos)
        yield pos, opcode, data[pos + 9:pos + 9 + length]
        pos += 9 + length


class _Scanner:
    def __init__(self) -> None:
        self.scan = McapScan()

    def record(self, opcode: int, content: bytes) -> None:
        fields = _Fields(content)
        if opcode == OP_SCHEMA:
            schema = Schema(fields.uint('H'), fields.string(), fields.string(),
                            fields.take(fields.uint('I')))
            self.scan.schemas[schema.id] = schema
        elif opcode == OP_CHANNEL:
            channel = Channel(fields.uint('H'), fields.uint('H'), fields.string(),
                              fields.string(), fields.string_map())
            self.scan.channels[channel.id] = channel
        elif opcode == OP_MESSAGE:
            channel_id = fields.uint('H')
            fields.uint('I')  # sequence
            log_time = fields.uint('Q')
            fields.uint('Q')  # publish time
            if channel_id in self.scan.channels:
                self.scan.messages.append(Message(channel_id, log_time, fields.rest()))
            else:
                self.scan.dropped_messages += 1

    def chunk(self, content: bytes, cut: bool) -> None:
        """The records of a chunk; of a cut one only if it is uncompressed."""
        fields = _Fields(content)
        fields.uint('Q'), fields.uint('Q')  # message start and end time
        size, crc = fields.uint('Q'), fields.uint('I')
        compression = fields.string()
        records_size = fields.uint('Q')
        records = fields.data[fields.pos:fields.pos + records_size]
        if compression:
            if cut or len(records) < records_size:
                raise RecordError('a cut compressed chunk')
            from rosbags.rosbag2.errors import ReaderError
            from rosbags.rosbag2.storage_mcap import decompress
            try:
                records = decompress(records, compression, size, crc)
            except ReaderError as error:
                raise RecordError(f'chunk: {error}') from None
        elif not cut and crc and zlib.crc32(records) != crc:
            raise RecordError('chunk: CRC mismatch')
        try:
            for _, opcode, inner in _records(records):
                self.record(opcode, inner)
        except _Cut:
            if not cut:
                raise RecordError('chunk: a record crosses its end') from None


def scan_mcap(path) -> McapScan:
    """Read every complete record of an MCAP file, tolerating a cut end.

    :param path: the .mcap file
    :return: what was found; `complete` tells whether the file was closed by its writer
    :raises RecordError: if the file cannot be read or is not MCAP (no magic at its start)
    """
    path = Path(path)
    try:
        with open(path, 'rb') as stream:
            if path.stat().st_size < len(MAGIC):
                raise RecordError(f'{path}: not an MCAP file ({path.stat().st_size} bytes)')
            with mmap.mmap(stream.fileno(), 0, access=mmap.ACCESS_READ) as data:
                if data[:len(MAGIC)] != MAGIC:
                    raise RecordError(f'{path}: not an MCAP file (no magic bytes at its start)')
                return _scan(data)
    except OSError as error:
        raise RecordError(f'cannot read {path}: {error}') from None


def _scan(data) -> McapScan:
    scanner = _Scanner()
    scan = scanner.scan
    pos = len(MAGIC)
    try:
        for pos, opcode, content in _records(data, pos):
            if opcode == OP_CHUNK:
                scanner.chunk(content, cut=False)
            elif opcode in (OP_DATA_END, OP_FOOTER):
                # The data section is over; a footer and the magic close the file.
                scan.complete = data[len(data) - len(MAGIC):] == MAGIC
                return scan
            else:
                scanner.record(opcode, content)
    except _Cut as cut:
        offset = cut.args[0]
        scan.stopped_at = offset
        scan.problem = f'the file ends inside a record at byte {offset} of {len(data)}'
        if offset + 9 <= len(data) and data[offset] == OP_CHUNK:
            try:
                scanner.chunk(data[offset + 9:], cut=True)
                scan.problem += ' (a chunk: its complete messages kept)'
            except RecordError:
                scan.problem += ' (a chunk whose messages cannot be read)'
    except (RecordError, UnicodeDecodeError) as error:
        scan.stopped_at = pos
        scan.problem = f'bad record at byte {pos}: {error}'
    return scan
