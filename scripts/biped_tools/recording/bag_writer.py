"""A rosbag2 directory being written: connections, raw CDR messages, then index and metadata.

Messages are written unchanged as the bytes DDS delivered; each connection keeps its type's
definition and hash (from a TypeRegistry's typestore) and the publishers' QoS, so that
`ros2 bag info` / `ros2 bag play`, rosbags' AnyReader and MCAP tools read the bag.

Closing writes the index, summary and metadata.yaml. So that a writer killed before (SIGKILL, a
power cut) leaves a bag that `record.py reindex` recovers (biped_tools.recording.bag_reindex),
what was written reaches the file every `flush_period` s: an MCAP bag closes its pending chunk
(rosbags would otherwise hold up to 1 MiB in memory), an sqlite3 bag commits its transaction.
A kill then loses at most the messages of the last flush period.
"""
from pathlib import Path
import sqlite3
import threading
import time
from typing import Optional, Sequence

from biped_tools.recording.errors import RecordError
from biped_tools.recording.topic_subscription import rosbags_qos

STORAGES = ('mcap', 'sqlite3')
# Seconds between flushes of what was written to the file (see the module docstring).
FLUSH_PERIOD = 0.5


class BagWriter:
    """One bag, written from any thread (subscription callbacks) and closed once.

    :param path: the bag directory to create (must not exist)
    :param storage: 'mcap' or 'sqlite3'
    :param flush_period: seconds between flushes to the file (> 0)
    :raises RecordError: for an unknown storage, a bad flush period or a bag that cannot be
        created
    """

    def __init__(self, path, storage: str = 'mcap', flush_period: float = FLUSH_PERIOD) -> None:
        from rosbags.rosbag2 import StoragePlugin, Writer, WriterError
        if storage not in STORAGES:
            raise RecordError(f'storage {storage!r}: expected one of {", ".join(STORAGES)}')
        if not flush_period > 0.0:
            raise RecordError(f'flush period {flush_period}: expected > 0 s')
        self.path = Path(path)
        self.storage = storage
        self.flush_period = flush_period
        self.closed = False
        self._unflushed = 0
        self._flushed_at = time.monotonic()
        self.error: Optional[str] = None  # why writing stopped (e.g. a full disk)
        self._lock = threading.Lock()
        try:
            self._writer = Writer(self.path, version=Writer.VERSION_LATEST,
                                  storage_plugin=StoragePlugin[storage.upper()])
            self._writer.open()
        except WriterError as error:
            raise RecordError(f'cannot create bag: {error}') from None

    def add_connection(self, topic: str, type_name: str, typestore, offered: Sequence = ()):
        """A new connection for topic.

        :param typestore: rosbags typestore that knows type_name
        :param offered: the publishers' rclpy QoS profiles, kept for `ros2 bag play`
        :raises RecordError: if the bag refuses the connection
        """
        from rosbags.rosbag2 import WriterError
        try:
            with self._lock:
                return self._writer.add_connection(
                    topic, type_name, typestore=typestore,
                    offered_qos_profiles=[rosbags_qos(p) for p in offered])
        except WriterError as error:
            raise RecordError(f'{topic}: {error}') from None

    def write(self, connection, stamp: int, data: bytes) -> bool:
        """Write one message's raw bytes received at stamp (ns).

        :return: whether it was written (not once the bag is closed or writing has failed)
        :raises RecordError: when writing fails (e.g. a full disk); the bag stays closable
        """
        with self._lock:
            if self.closed or self.error is not None:
                return False
            try:
                self._writer.write(connection, stamp, data)
                self._unflushed += 1
                self._flush_if_due()
            except (OSError, sqlite3.Error) as error:
                self.error = f'writing {connection.topic} failed: {error}'
                raise RecordError(self.error) from None
            return True

    def flush_if_due(self) -> None:
        """Flush when flush_period has passed since the last flush (a timer calls this, so
        that the last messages before a quiet spell reach the file too).

        :raises RecordError: when writing fails (e.g. a full disk)
        """
        with self._lock:
            if self.closed or self.error is not None:
                return
            try:
                self._flush_if_due()
            except (OSError, sqlite3.Error) as error:
                self.error = f'flushing failed: {error}'
                raise RecordError(self.error) from None

    def flush(self) -> None:
        """Put every message written so far into the file now.

        :raises RecordError: when writing fails
        """
        with self._lock:
            if self.closed or self.error is not None:
                return
            try:
                self._flush()
            except (OSError, sqlite3.Error) as error:
                self.error = f'flushing failed: {error}'
                raise RecordError(self.error) from None

    def _flush_if_due(self) -> None:
        if self._unflushed and time.monotonic() - self._flushed_at >= self.flush_period:
            self._flush()

    def _flush(self) -> None:
        """rosbags has no flush of its own: close the MCAP writer's pending chunk (it carries
        the chunk's schemas, channels and messages) and flush the file, or commit sqlite3."""
        storage = self._writer.storage
        if self.storage == 'mcap':
            if storage.chunk.msgs:
                storage.close_chunk()
            storage.bio.flush()
        else:
            storage.conn.commit()
        self._unflushed = 0
        self._flushed_at = time.monotonic()

    def close(self) -> None:
        """Write the index and metadata.yaml (idempotent)."""
        with self._lock:
            if not self.closed:
                self.closed = True
                self._writer.close()
