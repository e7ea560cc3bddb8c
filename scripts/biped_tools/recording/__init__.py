"""Recording topics into rosbag2 directories: the in-process recorder and `scripts/record.py`.

- message_types: definitions and RIHS01 hashes of every installed interface (TypeRegistry);
- topic_subscription: resolved topic names and the QoS that matches the publishers;
- bag_writer: the bag being written (connections, raw messages, regular flushes, index and
  metadata);
- bag_recorder: discovery of publishers and their subscriptions into a BagWriter (BagRecorder);
- mcap_scan: the complete records of an MCAP file whose writer died;
- bag_reindex: a bag whose writer died made readable again (reindex, like `ros2 bag reindex`);
- command: the command line.
"""
from biped_tools.recording.bag_recorder import BagRecorder, RecordSummary, TopicRecord
from biped_tools.recording.bag_reindex import reindex, ReindexResult
from biped_tools.recording.errors import RecordError
from biped_tools.recording.message_types import import_message_class, TypeRegistry

__all__ = ['BagRecorder', 'import_message_class', 'RecordError', 'RecordSummary', 'reindex',
           'ReindexResult', 'TopicRecord', 'TypeRegistry']
