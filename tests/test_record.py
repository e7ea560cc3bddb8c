"""The bag recorder: real rosbag2 bags read back by independent readers, with real DDS."""
import json
import re
from pathlib import Path
import shutil
import signal
import subprocess
import sys

from biped_msgs.msg import Footstep, FootstepPlan, ReferenceTrajectory, WalkingState
from geometry_msgs.msg import Twist
import pytest
import rclpy
from rclpy.qos import DurabilityPolicy, QoSProfile
from rclpy.serialization import deserialize_message
import yaml

from biped_tools import recording
from ros_harness import PYTHON, REPO, ros_environment, spin_until, wait_for_subscribers

RECORD = str(REPO / 'scripts' / 'record.py')
BIPED_SHARE = REPO / 'ros2_ws' / 'install' / 'biped_msgs' / 'share' / 'biped_msgs' / 'msg'
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
# Deep enough that a burst of test messages never overwrites unacknowledged ones.
BURST = QoSProfile(depth=200)


def rosidl_hash(type_name: str, share: Path) -> str:
    """The RIHS01 hash rosidl generated for type_name (its type description .json)."""
    description = json.loads((share / f'{type_name.split("/")[-1]}.json').read_text())
    return next(h['hash_string'] for h in description['type_hashes']
                if h['type_name'] == type_name)


def walking_state(i: int) -> WalkingState:
    msg = WalkingState(phase=i % 5, support_foot=i % 3, step_index=i, time_in_phase=0.01 * i,
                       phase_duration=0.4, plan_id=7, fallen=i % 2 == 1, reason=f'step {i}')
    msg.header.stamp.sec, msg.header.frame_id = 100 + i, 'odom'
    return msg


def twist(i: int) -> Twist:
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.angular.z = 0.01 * i, -0.02 * i, 0.5 - 0.01 * i
    return msg


def reference(i: int) -> ReferenceTrajectory:
    return ReferenceTrajectory(plan_id=i, dt=0.01, zmp_x=[0.1 * i, 0.2, 0.3],
                               zmp_y=[-0.05, 0.05], support=[0, 1, 2], step_index=[i, i + 1])


def read_bag(path: Path):
    """The bag as {topic: (type, [raw CDR bytes])} and {topic: digest}, via rosbags' AnyReader.

    AnyReader rebuilds every type from the definitions stored in the bag and checks them
    against the stored RIHS01 hashes, so a bag that opens carries complete definitions.
    """
    from rosbags.highlevel import AnyReader
    topics, digests, decoded = {}, {}, {}
    with AnyReader([path]) as reader:
        for connection in reader.connections:
            topics[connection.topic] = (connection.msgtype, [])
            digests[connection.topic] = connection.digest
            decoded[connection.topic] = []
        for connection, _, raw in reader.messages():
            topics[connection.topic][1].append(bytes(raw))
            decoded[connection.topic].append(reader.deserialize(raw, connection.msgtype))
    return topics, digests, decoded


def read_mcap(path: Path):
    """{topic: (schema name, schema encoding, message encoding, [raw bytes])} via `mcap`."""
    from mcap.reader import make_reader
    found = {}
    (mcap_file,) = path.glob('*.mcap')
    with open(mcap_file, 'rb') as stream:
        for schema, channel, message in make_reader(stream).iter_messages():
            entry = found.setdefault(channel.topic, (schema.name, schema.encoding,
                                                     channel.message_encoding, []))
            entry[3].append(message.data)
    return found


def topic_metadata(path: Path) -> dict:
    info = yaml.safe_load((path / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    return {t['topic_metadata']['name']: t for t in info['topics_with_message_count']}


@pytest.mark.parametrize('type_name', sorted(f'biped_msgs/msg/{p.stem}'
                                             for p in BIPED_SHARE.glob('*.json')))
def test_rosbags_type_hash_equals_the_rosidl_hash_of_every_biped_type(type_name):
    assert recording.TypeRegistry().rihs01(type_name) == rosidl_hash(type_name, BIPED_SHARE)


def test_rosbags_type_hash_equals_the_rosidl_hash_of_a_standard_type():
    share = Path(sys.prefix) / 'share' / 'geometry_msgs' / 'msg'
    assert recording.TypeRegistry().rihs01('geometry_msgs/msg/Twist') == \
        rosidl_hash('geometry_msgs/msg/Twist', share)


@pytest.mark.parametrize('call, words', [
    (lambda: recording.import_message_class('nopkg/msg/Nope'), "unknown type 'nopkg/msg/Nope'"),
    (lambda: recording.import_message_class('biped_msgs/msg/Nope'), 'not installed'),
    (lambda: recording.import_message_class('just_a_name'), 'expected package/msg/Type'),
    (lambda: recording.TypeRegistry(prefixes=[]).ensure('biped_msgs/msg/WalkingState'),
     'no message definition for biped_msgs/msg/WalkingState'),
])
def test_unknown_types_are_clear_errors(call, words):
    with pytest.raises(recording.RecordError, match=words):
        call()


def test_custom_standard_and_transient_local_topics_are_recorded_byte_for_byte(
        ros_context, executor, tmp_path):
    source = executor.track(rclpy.create_node('record_test_source', context=ros_context))
    states = source.create_publisher(WalkingState, 'walking_state', BURST)
    velocities = source.create_publisher(Twist, 'cmd_vel', BURST)
    references = source.create_publisher(ReferenceTrajectory, 'reference_trajectory', BURST)
    plans = source.create_publisher(FootstepPlan, 'footstep_plan', LATCHED)
    # Published before the recorder exists: only a transient_local subscription receives it.
    plan = FootstepPlan(plan_id=12, error_msg='latched',
                        footsteps=[Footstep(side=1, x=0.15, y=-0.1)])
    plans.publish(plan)

    node = executor.track(rclpy.create_node('record_test_recorder', context=ros_context))
    recorder = recording.BagRecorder(
        node, tmp_path / 'bag', topics=['walking_state', 'cmd_vel', 'reference_trajectory',
                                        'footstep_plan'])
    sent = {'/walking_state': [walking_state(i) for i in range(20)],
            '/cmd_vel': [twist(i) for i in range(20)],
            '/reference_trajectory': [reference(i) for i in range(5)],
            '/footstep_plan': [plan]}
    classes = {topic: type(messages[0]) for topic, messages in sent.items()}
    # What DDS delivers, taken raw by a second, independent subscriber: the bag must hold
    # exactly these bytes (CDR padding included, which a fresh serialization may not match).
    wire = {topic: [] for topic in sent}
    for topic, cls in classes.items():
        source.create_subscription(cls, topic, wire[topic].append,
                                   LATCHED if topic == '/footstep_plan' else BURST, raw=True)
    publishers = [states, velocities, references]
    assert spin_until(executor, lambda: len(recorder.records) == 4 and all(
        p.get_subscription_count() >= 2 for p in publishers), timeout=10), recorder.errors
    for i in range(20):
        states.publish(sent['/walking_state'][i])
        velocities.publish(sent['/cmd_vel'][i])
        if i < 5:
            references.publish(sent['/reference_trajectory'][i])
    assert spin_until(executor, lambda: recorder.message_count == 46 and
                      sum(map(len, wire.values())) == 46, timeout=10)
    summary = recorder.close(executor)
    assert {t.topic: t.count for t in summary.topics} == {
        '/walking_state': 20, '/cmd_vel': 20, '/reference_trajectory': 5, '/footstep_plan': 1}

    types = {'/walking_state': 'biped_msgs/msg/WalkingState', '/cmd_vel':
             'geometry_msgs/msg/Twist', '/reference_trajectory':
             'biped_msgs/msg/ReferenceTrajectory', '/footstep_plan': 'biped_msgs/msg/FootstepPlan'}
    topics, digests, decoded = read_bag(tmp_path / 'bag')
    assert {topic: kind for topic, (kind, _) in topics.items()} == types
    for topic, messages in sent.items():
        assert topics[topic][1] == wire[topic], topic
        assert [deserialize_message(raw, classes[topic]) for raw in topics[topic][1]] == \
            messages, topic
    assert digests['/walking_state'] == rosidl_hash('biped_msgs/msg/WalkingState', BIPED_SHARE)
    # rosbags decodes our custom types from the definitions embedded in the bag alone.
    assert [(m.step_index, m.reason, m.fallen) for m in decoded['/walking_state']] == \
        [(i, f'step {i}', i % 2 == 1) for i in range(20)]
    assert decoded['/reference_trajectory'][3].zmp_x.tolist() == pytest.approx([0.3, 0.2, 0.3])
    assert decoded['/cmd_vel'][7].angular.z == pytest.approx(0.43)
    assert decoded['/footstep_plan'][0].footsteps[0].x == 0.15

    # An independent reader (the `mcap` package) sees the ROS 2 profile and the same bytes.
    channels = read_mcap(tmp_path / 'bag')
    assert sorted(channels) == sorted(types)
    for topic, (schema, encoding, message_encoding, data) in channels.items():
        assert (schema, encoding, message_encoding) == (types[topic], 'ros2msg', 'cdr')
        assert data == wire[topic], topic

    metadata = topic_metadata(tmp_path / 'bag')
    assert metadata['/cmd_vel']['message_count'] == 20
    assert metadata['/footstep_plan']['topic_metadata']['offered_qos_profiles'][0][
        'durability'] == 'transient_local'
    assert metadata['/cmd_vel']['topic_metadata']['offered_qos_profiles'][0][
        'durability'] == 'volatile'


def test_all_records_topics_appearing_later_and_max_messages_closes_a_sqlite3_bag(
        ros_context, executor, tmp_path):
    node = executor.track(rclpy.create_node('record_test_all', context=ros_context))
    recorder = recording.BagRecorder(node, tmp_path / 'bag', record_all=True,
                                     exclude='rosout|parameter_events', storage='sqlite3',
                                     max_messages=5)
    source = executor.track(rclpy.create_node('record_test_late', context=ros_context))
    late = source.create_publisher(Twist, 'late_topic', BURST)
    assert spin_until(executor, lambda: '/late_topic' in recorder.records and
                      late.get_subscription_count() >= 1, timeout=10)
    for i in range(8):
        late.publish(twist(i))
    assert spin_until(executor, lambda: recorder.done, timeout=10)
    summary = recorder.close(executor)
    assert [(t.topic, t.count) for t in summary.topics] == [('/late_topic', 5)]
    assert (tmp_path / 'bag' / 'bag.db3').exists()
    topics, _, _ = read_bag(tmp_path / 'bag')
    assert list(topics) == ['/late_topic']
    kind, data = topics['/late_topic']
    assert kind == 'geometry_msgs/msg/Twist'
    assert [deserialize_message(d, Twist) for d in data] == [twist(i) for i in range(5)]


def test_unknown_type_or_hash_mismatch_skips_that_topic_and_records_the_others(
        ros_context, executor, tmp_path):
    # A prefix whose WalkingState.msg differs from the one the publisher was built with.
    share = tmp_path / 'prefix' / 'share' / 'biped_msgs' / 'msg'
    shutil.copytree(BIPED_SHARE, share)
    (share / 'WalkingState.msg').write_text(
        (share / 'WalkingState.msg').read_text() + '\nfloat64 extra\n')
    source = executor.track(rclpy.create_node('record_test_bad_source', context=ros_context))
    states = source.create_publisher(WalkingState, 'walking_state', BURST)
    velocities = source.create_publisher(Twist, 'cmd_vel', BURST)
    node = executor.track(rclpy.create_node('record_test_bad', context=ros_context))
    logged = []
    recorder = recording.BagRecorder(
        node, tmp_path / 'bag', topics=['walking_state', 'cmd_vel'],
        registry=recording.TypeRegistry(prefixes=[tmp_path / 'prefix', Path(sys.prefix)]),
        log=logged.append)
    assert spin_until(executor, lambda: '/walking_state' in recorder.errors and
                      velocities.get_subscription_count() >= 1, timeout=10)
    assert 'differs from the installed definition' in recorder.errors['/walking_state']
    assert any(line.startswith('error: not recording /walking_state') for line in logged)
    with pytest.raises(recording.RecordError, match="unknown type 'nopkg/msg/Nope'"):
        recorder.add_topic('other', 'nopkg/msg/Nope')
    with pytest.raises(recording.RecordError, match='invalid topic name'):
        recorder.add_topic('bad name', 'geometry_msgs/msg/Twist')
    velocities.publish(twist(3))
    states.publish(walking_state(3))
    assert spin_until(executor, lambda: recorder.message_count == 1, timeout=10)
    summary = recorder.close(executor)
    assert [(t.topic, t.count) for t in summary.topics] == [('/cmd_vel', 1)]
    assert list(summary.errors) == ['/walking_state']
    (data,) = read_bag(tmp_path / 'bag')[0]['/cmd_vel'][1]
    assert deserialize_message(data, Twist) == twist(3)


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
def test_recorder_process_stopped_by_a_signal_keeps_every_message_sent_before(
        ros_context, executor, processes, tmp_path, signum):
    source = executor.track(rclpy.create_node('record_test_signal', context=ros_context))
    states = source.create_publisher(WalkingState, 'walking_state', BURST)
    velocities = source.create_publisher(Twist, 'cmd_vel', BURST)
    process = processes.start([PYTHON, RECORD, '-o', str(tmp_path / 'bag'), 'walking_state',
                               'cmd_vel'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True)
    assert wait_for_subscribers(executor, states, timeout=15)
    assert wait_for_subscribers(executor, velocities, timeout=15)
    for i in range(50):
        states.publish(walking_state(i))
        velocities.publish(twist(i))
    # No pause: the signal lands while messages may still be in flight.
    process.send_signal(signum)
    output, _ = process.communicate(timeout=15)
    assert process.returncode == 0, output
    assert 'bag ' in output and '100 messages on 2 topics' in output, output
    topics, _, _ = read_bag(tmp_path / 'bag')
    assert [deserialize_message(d, WalkingState) for d in topics['/walking_state'][1]] == \
        [walking_state(i) for i in range(50)]
    assert [deserialize_message(d, Twist) for d in topics['/cmd_vel'][1]] == \
        [twist(i) for i in range(50)]


def test_recorder_process_duration_ends_with_a_readable_bag_and_a_summary(processes,
                                                                          tmp_path):
    process = processes.start([PYTHON, RECORD, '-o', str(tmp_path / 'bag'), '--duration',
                               '0.5', 'nobody_publishes_this'], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True)
    output, _ = process.communicate(timeout=20)
    assert process.returncode == 0, output
    assert '/nobody_publishes_this' in output and '(no publisher seen)' in output
    assert read_bag(tmp_path / 'bag')[0] == {}


@pytest.mark.parametrize('args, words', [
    (['bad name'], "invalid topic name 'bad name'"),
    (['1abc'], 'must not start with a number'),
    ([], 'name topics to record or give --all'),
    (['--max-messages', '-1', 'cmd_vel'], 'must be >= 0'),
])
def test_recorder_process_rejects_bad_arguments_with_a_clear_error(tmp_path, args, words):
    result = subprocess.run([PYTHON, RECORD, '-o', str(tmp_path / 'bag'), *args],
                            env=ros_environment(), capture_output=True, text=True, timeout=30)
    assert result.returncode == 2
    assert words in result.stderr
    assert 'Traceback' not in result.stderr


def test_recorder_process_refuses_to_overwrite_a_bag(tmp_path):
    (tmp_path / 'bag').mkdir()
    result = subprocess.run([PYTHON, RECORD, '-o', str(tmp_path / 'bag'), 'cmd_vel'],
                            env=ros_environment(), capture_output=True, text=True, timeout=30)
    assert result.returncode == 2
    assert 'exists already' in result.stderr and 'Traceback' not in result.stderr


def test_a_recorder_killed_mid_way_leaves_a_bag_that_reindex_recovers_on_sim_time(
        ros_context, executor, processes, tmp_path):
    """kill -9 of `record.py --use-sim-time`: every message flushed before is recovered, the
    ones received before the first /clock tick are stamped with it (none with 0), and the
    stamps of a topic never go back."""
    from builtin_interfaces.msg import Time
    from rosgraph_msgs.msg import Clock
    from biped_tools.recording.mcap_scan import scan_mcap
    source = executor.track(rclpy.create_node('record_test_kill', context=ros_context))
    states = source.create_publisher(WalkingState, 'walking_state', BURST)
    clock = source.create_publisher(Clock, '/clock', 10)
    bag = tmp_path / 'bag'
    process = processes.start([PYTHON, RECORD, '-o', str(bag), '--use-sim-time',
                               'walking_state'], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True)
    assert wait_for_subscribers(executor, states, timeout=15)
    assert wait_for_subscribers(executor, clock, timeout=15)
    for i in range(10):   # before the clock runs
        states.publish(walking_state(i))
    spin_until(executor, lambda: False, timeout=1.0)
    t = 5.0
    for i in range(10, 60):
        t += 0.01
        clock.publish(Clock(clock=Time(sec=int(t), nanosec=int(round((t % 1) * 1e9)))))
        states.publish(walking_state(i))
        executor.spin_once(timeout_sec=0.005)
    # With no message coming, the recorder's timer flushes everything to the file.
    mcap_file = bag / 'bag.mcap'

    def on_disk() -> int:
        return len(scan_mcap(mcap_file).messages) if mcap_file.exists() else 0
    assert spin_until(executor, lambda: on_disk() == 60, timeout=30), on_disk()
    for i in range(60, 80):   # a burst the recorder may not flush before it dies
        states.publish(walking_state(i))
    process.kill()
    output, _ = process.communicate(timeout=15)
    assert not (bag / 'metadata.yaml').exists()
    early = re.search(r'writing (\d+) messages received before its first tick', output)
    assert early and int(early.group(1)) >= 1, output

    result = subprocess.run([PYTHON, RECORD, 'reindex', str(bag)], env=ros_environment(),
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert 'rebuilt bag.mcap and metadata.yaml' in result.stdout
    from rosbags.highlevel import AnyReader
    with AnyReader([bag]) as reader:
        rows = [(stamp, reader.deserialize(raw, c.msgtype).step_index)
                for c, stamp, raw in reader.messages()]
    indices = [index for _, index in rows]
    assert 60 <= len(indices) <= 80
    assert indices == list(range(len(indices)))
    stamps = [stamp for stamp, _ in rows]
    assert min(stamps) >= 5 * 10**9
    assert stamps == sorted(stamps)
    assert topic_metadata(bag)['/walking_state']['message_count'] == len(indices)
