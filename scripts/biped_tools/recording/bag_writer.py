"""A rosbag2 directory being written: connections, raw CDR messages, then index and metadata.

Messages are written unchanged as the bytes DDS delivered; each connection keeps its type's
definition and hash (from a TypeRegistry's typestore) and the publishers' QoS, so that
`ros2 bag info` / `ros2 bag play`, rosbags' AnyReader and MCAP tools read the bag. A bag that is
not closed is not readable.
"""
from pathlib import Path
import threading
from typing import Optional, Sequence

from biped_tools.recording.errors import RecordError
from biped_tools.recording.topic_subscription import rosbags_qos

STORAGES = ('mcap', 'sqlite3')


class BagWriter:
    """One bag, written from any thread (subscription callbacks) and closed once.

    :param path: the bag directory to create (must not exist)
    :param storage: 'mcap' or 'sqlite3'
    :raises RecordError: for an unknown storage or a bag that cannot be created
    """

    def __init__(self, path, storage: str = 'mcap') -> None:
        from rosbags.rosbag2 import StoragePlugin, Writer, WriterError
        if storage not in STORAGES:
            raise RecordError(f'storage {storage!r}: expected one of {", ".join(STORAGES)}')
        self.path = Path(path)
        self.storage = storage
        self.closed = False
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
            except OSError as error:
                self.error = f'writing {connection.topic} failed: {error}'
                raise RecordError(self.error) from None
            return True

    def close(self) -> None:
        """Write the index and metadata.yaml (idempotent)."""
        with self._lock:
            if not self.closed:
                self.closed = True
                self._writer.close()
