# Copyright 2026 rope_sim_ros contributors
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
BagWriter and RosBagWriter against rosbag2 Jazzy's layout, read back by rosbags and mcap_ros2.

Every number written (times, poses, forces, counts, QoS, hashes) is read back through
two readers that share no code with ours, and metadata.yaml is compared with the copy
rosbag2 embeds in the MCAP file.
"""

import errno
import os
import threading
import time
import warnings

from geometry_msgs.msg import Pose, PoseArray, PoseStamped, Wrench
from mcap.reader import make_reader
import pytest
from rclpy.duration import Duration
from rclpy.qos import QoSDurabilityPolicy, QoSProfile, QoSReliabilityPolicy
from rclpy.serialization import deserialize_message, serialize_message
from rope_sim_ros.bag import BagError, BagWriter, cdr, read_messages
from rope_sim_ros.bag import schema
from rope_sim_ros.bag import storage
from rope_sim_ros.bag.metadata import DEFAULT_QOS
from rope_sim_ros.ros2bag import deserialize, qos_to_dict, RosBagWriter
from rosbags.interfaces import QosDurability, QosReliability
from rosbags.rosbag2 import Reader
from rosbags.typesys import get_typestore, Stores
import yaml

with warnings.catch_warnings():
    warnings.simplefilter('ignore', DeprecationWarning)
    from mcap_ros2.reader import read_ros2_messages

T0 = 1_767_225_600_000_000_000  # 2026-01-01T00:00:00Z [ns]
STEP = 10_000_000  # 100 Hz
LATENCY = 1_234_567  # publish -> record [ns]
N_STEPS = 40
N_POSES = 21
TOPICS = {
    '/mooring_line/fairlead/pose': 'geometry_msgs/msg/PoseStamped',
    '/mooring_line/rope/particles': 'geometry_msgs/msg/PoseArray',
    '/mooring_line/fairlead/tension': 'geometry_msgs/msg/Wrench',
}
TENSION_QOS = QoSProfile(
    depth=5, reliability=QoSReliabilityPolicy.BEST_EFFORT,
    durability=QoSDurabilityPolicy.TRANSIENT_LOCAL, deadline=Duration(seconds=1, nanoseconds=5e8))


def pose_stamped(k):
    message = PoseStamped()
    message.header.stamp.sec, message.header.stamp.nanosec = divmod(T0 + k * STEP, 10**9)
    message.header.frame_id = 'ship'
    message.pose.position.x, message.pose.position.y = 10.0 + 0.01 * k, -2.5
    message.pose.position.z = 0.25 * k
    message.pose.orientation.z, message.pose.orientation.w = 0.6, 0.8
    return message


def pose_array(k):
    message = PoseArray()
    message.header.stamp.sec, message.header.stamp.nanosec = divmod(T0 + k * STEP, 10**9)
    message.header.frame_id = 'quay'
    for i in range(N_POSES):
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = 1.5 * i, 0.001 * k, -0.1 * i * i
        pose.orientation.x, pose.orientation.w = 0.0, 1.0
        message.poses.append(pose)
    return message


def wrench(k):
    message = Wrench()
    message.force.x, message.force.y, message.force.z = 1.0e5 + k, -2.0e3, -9.81 * k
    message.torque.x, message.torque.y, message.torque.z = 0.5, -0.25, 1.0e-3 * k
    return message


def expected_fields(topic, k):
    """Return the values written at step k on a topic, as a comparable tuple."""
    if topic.endswith('pose'):
        return ('ship', T0 + k * STEP, 10.0 + 0.01 * k, -2.5, 0.25 * k, 0.6, 0.8)
    if topic.endswith('particles'):
        return ('quay', T0 + k * STEP,
                [(1.5 * i, 0.001 * k, -0.1 * i * i, 1.0) for i in range(N_POSES)])
    return (1.0e5 + k, -2.0e3, -9.81 * k, 0.5, -0.25, 1.0e-3 * k)


def fields(topic, message):
    """Return the same tuple from a message decoded by any of the readers."""
    if topic.endswith('pose'):
        stamp = message.header.stamp.sec * 10**9 + message.header.stamp.nanosec
        p, q = message.pose.position, message.pose.orientation
        return (message.header.frame_id, stamp, p.x, p.y, p.z, q.z, q.w)
    if topic.endswith('particles'):
        stamp = message.header.stamp.sec * 10**9 + message.header.stamp.nanosec
        return (message.header.frame_id, stamp,
                [(p.position.x, p.position.y, p.position.z, p.orientation.w)
                 for p in message.poses])
    f, t = message.force, message.torque
    return (f.x, f.y, f.z, t.x, t.y, t.z)


BUILDERS = {'pose': pose_stamped, 'particles': pose_array, 'tension': wrench}


def build(topic, k):
    return BUILDERS[topic.rsplit('/', 1)[1]](k)


@pytest.fixture(scope='module')
def recorded(tmp_path_factory):
    """Record N_STEPS of each topic; the tension topic is written as raw CDR bytes."""
    path = tmp_path_factory.mktemp('bags') / 'mooring_run'
    with RosBagWriter(path, chunk_size=4096, custom_data={'material': 'nylon'}) as bag:
        for topic, type_name in TOPICS.items():
            bag.add_topic(topic, type_name, TENSION_QOS if 'tension' in topic else None)
        for k in range(N_STEPS):
            log_time = T0 + k * STEP
            for topic in TOPICS:
                message = build(topic, k)
                if 'tension' in topic:
                    message = serialize_message(message)
                assert bag.write(topic, message, log_time, log_time - LATENCY)
        assert bag.dropped == 0
    assert bag.error is None
    return path


def test_layout(recorded):
    assert sorted(os.listdir(recorded)) == ['metadata.yaml', 'mooring_run_0.mcap']


def test_rosbags_reads_every_field(recorded):
    store = get_typestore(Stores.ROS2_JAZZY)
    seen = {topic: [] for topic in TOPICS}
    with Reader(recorded) as reader:
        assert reader.message_count == N_STEPS * len(TOPICS)
        assert reader.start_time == T0
        assert reader.end_time == T0 + (N_STEPS - 1) * STEP + 1  # rosbags: exclusive end
        assert reader.ros_distro == 'jazzy'
        connections = {c.topic: c for c in reader.connections}
        assert {t: c.msgtype for t, c in connections.items()} == TOPICS
        for topic, connection in connections.items():
            assert connection.msgcount == N_STEPS
            assert connection.digest == schema.type_hash(TOPICS[topic])
        tension_qos = connections['/mooring_line/fairlead/tension'].ext.offered_qos_profiles
        assert tension_qos[0].reliability == QosReliability.BEST_EFFORT
        assert tension_qos[0].durability == QosDurability.TRANSIENT_LOCAL
        assert (tension_qos[0].deadline.sec, tension_qos[0].deadline.nsec) == (1, 500_000_000)
        assert tension_qos[0].depth == 5
        for connection, log_time, data in reader.messages():
            message = store.deserialize_cdr(data, connection.msgtype)
            seen[connection.topic].append((log_time, fields(connection.topic, message)))
    for topic, records in seen.items():
        assert records == [(T0 + k * STEP, expected_fields(topic, k)) for k in range(N_STEPS)]


def test_mcap_ros2_decodes_from_the_embedded_schema(recorded):
    seen = {topic: [] for topic in TOPICS}
    for message in read_ros2_messages(str(recorded / 'mooring_run_0.mcap')):
        assert message.schema.encoding == 'ros2msg'
        assert message.schema.data.decode() == schema.message_definition(message.schema.name)
        assert message.channel.message_encoding == 'cdr'
        seen[message.channel.topic].append(
            (message.log_time_ns, message.publish_time_ns,
             fields(message.channel.topic, message.ros_msg)))
    for topic, records in seen.items():
        assert records == [(T0 + k * STEP, T0 + k * STEP - LATENCY, expected_fields(topic, k))
                           for k in range(N_STEPS)]


def test_our_reader_gives_times_and_types(recorded):
    records = list(read_messages(recorded))
    assert len(records) == N_STEPS * len(TOPICS)
    times = [r.log_time_ns for r in records]
    assert times == sorted(times)
    for record in records:
        k = (record.log_time_ns - T0) // STEP
        assert record.publish_time_ns == record.log_time_ns - LATENCY
        assert record.type_name == TOPICS[record.topic]
        assert fields(record.topic, deserialize(record)) == expected_fields(record.topic, k)
    only = list(read_messages(recorded, topics=['/mooring_line/fairlead/tension']))
    assert [r.log_time_ns for r in only] == [T0 + k * STEP for k in range(N_STEPS)]


def test_mcap_header_channels_and_metadata_record(recorded):
    with open(recorded / 'mooring_run_0.mcap', 'rb') as stream:
        reader = make_reader(stream)
        header = reader.get_header()
        summary = reader.get_summary()
        records = list(reader.iter_metadata())
    assert header.profile == 'ros2'
    assert header.library.startswith('rope_sim_ros ')
    assert len(summary.chunk_indexes) > 1  # 4 KiB chunks
    assert all(index.compression == '' for index in summary.chunk_indexes)
    channels = {c.topic: c for c in summary.channels.values()}
    for topic, type_name in TOPICS.items():
        channel = channels[topic]
        assert summary.schemas[channel.schema_id].name == type_name
        assert channel.metadata['topic_type_hash'] == schema.type_hash(type_name)
        profiles = yaml.safe_load(channel.metadata['offered_qos_profiles'])
        assert len(profiles) == 1
    tension = yaml.safe_load(
        channels['/mooring_line/fairlead/tension'].metadata['offered_qos_profiles'])[0]
    assert tension == {
        'history': 'keep_last', 'depth': 5, 'reliability': 'best_effort',
        'durability': 'transient_local', 'deadline': {'sec': 1, 'nsec': 500_000_000},
        'lifespan': {'sec': 9223372036, 'nsec': 854775807}, 'liveliness': 'automatic',
        'liveliness_lease_duration': {'sec': 9223372036, 'nsec': 854775807},
        'avoid_ros_namespace_conventions': False}
    # custom_data first (so a killed recording keeps it), the rosbag2 record at close
    assert [r.name for r in records] == ['rope_sim_ros.custom_data', 'rosbag2']
    embedded = yaml.safe_load(records[1].metadata['serialized_metadata'])
    assert records[0].metadata == embedded['custom_data']
    with open(recorded / 'metadata.yaml', encoding='utf-8') as stream:
        on_disk = yaml.safe_load(stream)
    assert embedded == on_disk['rosbag2_bagfile_information']


def test_metadata_yaml(recorded):
    with open(recorded / 'metadata.yaml', encoding='utf-8') as stream:
        info = yaml.safe_load(stream)['rosbag2_bagfile_information']
    duration = (N_STEPS - 1) * STEP
    assert info['version'] == 9
    assert info['storage_identifier'] == 'mcap'
    assert info['ros_distro'] == 'jazzy'
    assert info['message_count'] == N_STEPS * len(TOPICS)
    assert info['starting_time'] == {'nanoseconds_since_epoch': T0}
    assert info['duration'] == {'nanoseconds': duration}
    assert info['compression_format'] == info['compression_mode'] == ''
    assert info['relative_file_paths'] == ['mooring_run_0.mcap']
    assert info['files'] == [{
        'path': 'mooring_run_0.mcap', 'starting_time': {'nanoseconds_since_epoch': T0},
        'duration': {'nanoseconds': duration}, 'message_count': N_STEPS * len(TOPICS)}]
    assert info['custom_data'] == {'material': 'nylon'}
    topics = {t['topic_metadata']['name']: t for t in info['topics_with_message_count']}
    assert sorted(topics) == sorted(TOPICS)
    for name, entry in topics.items():
        metadata = entry['topic_metadata']
        assert entry['message_count'] == N_STEPS
        assert metadata['type'] == TOPICS[name]
        assert metadata['serialization_format'] == 'cdr'
        assert metadata['type_description_hash'] == schema.type_hash(TOPICS[name])
        # Version 9: a YAML list with policies as strings.
        assert isinstance(metadata['offered_qos_profiles'], list)
    default = topics['/mooring_line/fairlead/pose']['topic_metadata']['offered_qos_profiles']
    assert default[0]['history'] == 'keep_last' and default[0]['depth'] == 10
    assert default[0]['reliability'] == 'reliable' and default[0]['durability'] == 'volatile'


def test_empty_directory_is_used(tmp_path):
    (tmp_path / 'empty').mkdir()
    with BagWriter(tmp_path / 'empty') as bag:
        bag.add_topic('/w', 'geometry_msgs/msg/Wrench')
    with Reader(tmp_path / 'empty') as reader:
        assert reader.message_count == 0
        assert [c.topic for c in reader.connections] == ['/w']


def test_non_empty_directory_is_refused(tmp_path):
    path = tmp_path / 'old_run'
    path.mkdir()
    (path / 'keep.txt').write_text('precious')
    with pytest.raises(BagError) as info:
        BagWriter(path)
    assert str(path) in str(info.value)
    assert 'exists already and is not empty, not overwriting; choose a new path' in str(
        info.value)
    assert os.listdir(path) == ['keep.txt']
    assert (path / 'keep.txt').read_text() == 'precious'


def test_existing_file_is_refused(tmp_path):
    path = tmp_path / 'run.mcap'
    path.write_bytes(b'x')
    with pytest.raises(BagError, match='not a directory'):
        BagWriter(path)
    assert path.read_bytes() == b'x'


def test_file_as_parent_is_reported_at_construction(tmp_path):
    parent = tmp_path / 'plain_file'
    parent.write_text('')
    with pytest.raises(BagError) as info:
        BagWriter(parent / 'run')
    assert str(parent / 'run') in str(info.value)
    assert 'cannot create bag directory' in str(info.value)


def test_read_only_location_is_reported_at_construction(tmp_path):
    parent = tmp_path / 'read_only'
    parent.mkdir()
    parent.chmod(0o555)
    if os.access(parent, os.W_OK):
        # root writes anywhere on a normal file system; sysfs refuses it new directories.
        if not os.path.ismount('/sys'):
            pytest.skip('running as root and no sysfs to be refused by')
        parent = '/sys'
    with pytest.raises(BagError) as info:
        BagWriter(os.path.join(parent, 'rope_sim_ros_bag'))
    assert os.path.join(parent, 'rope_sim_ros_bag') in str(info.value)
    assert not os.path.exists(os.path.join(parent, 'rope_sim_ros_bag'))


def test_topic_and_type_checks(tmp_path):
    with RosBagWriter(tmp_path / 'run') as bag:
        with pytest.raises(BagError, match='fully qualified'):
            bag.add_topic('fairlead/pose', 'geometry_msgs/msg/PoseStamped')
        bag.add_topic('/p', 'geometry_msgs/msg/PoseStamped')
        bag.add_topic('/p', 'geometry_msgs/PoseStamped')  # the same again: no effect
        with pytest.raises(BagError, match='recorded as geometry_msgs/msg/PoseStamped'):
            bag.add_topic('/p', 'geometry_msgs/msg/Wrench')
        with pytest.raises(BagError, match='add_topic'):
            bag.write('/unknown', Wrench(), T0)
        with pytest.raises(BagError, match='Wrench'):
            bag.write('/p', Wrench(), T0)
    assert bag.write('/p', PoseStamped(), T0) is False  # closed: dropped, not raised
    assert bag.dropped == 1


def test_bytes_writer_takes_bytes_and_the_types_it_carries(tmp_path):
    with BagWriter(tmp_path / 'run') as bag:
        bag.add_topic('/w', 'geometry_msgs/msg/Wrench')
        with pytest.raises(BagError, match='CDR bytes.*RosBagWriter'):
            bag.write('/w', Wrench(), T0)
        with pytest.raises(BagError, match="'sensor_msgs/msg/Imu'.*RosBagWriter"):
            bag.add_topic('/imu', 'sensor_msgs/msg/Imu')
        with pytest.raises(BagError, match='QoSProfile'):
            bag.add_topic('/q', 'geometry_msgs/msg/Wrench', TENSION_QOS)
        assert bag.write('/w', bytearray(cdr.wrench((1.0, 2.0, 3.0), (0.0, 0.0, 0.0))), T0)
    assert [cdr.decode_wrench(r.data)[0].tolist() for r in read_messages(tmp_path / 'run')] \
        == [[1.0, 2.0, 3.0]]
    # the ROS side records any installed type
    with RosBagWriter(tmp_path / 'imu') as bag:
        bag.add_topic('/imu', 'sensor_msgs/msg/Imu')
    assert bag_topics(tmp_path / 'imu') == {'/imu': 'sensor_msgs/msg/Imu'}


def bag_topics(path):
    with Reader(path) as reader:
        return {c.topic: c.msgtype for c in reader.connections}


def channel_records(path):
    """Return (topic, schema name, schema text, channel metadata) of each channel."""
    name = os.path.basename(path)
    with open(os.path.join(path, name + '_0.mcap'), 'rb') as stream:
        summary = make_reader(stream).get_summary()
    return sorted((c.topic, summary.schemas[c.schema_id].name,
                   summary.schemas[c.schema_id].data, dict(c.metadata))
                  for c in summary.channels.values())


def test_bytes_writer_stores_what_the_ros_writer_stores(tmp_path):
    """Schemas, hashes and QoS from stored data equal those read from the installed ROS."""
    qos = {name: (TENSION_QOS if 'tension' in name else None) for name in TOPICS}
    with RosBagWriter(tmp_path / 'ros') as bag:
        for name, type_name in TOPICS.items():
            bag.add_topic(name, type_name, qos[name])
    with BagWriter(tmp_path / 'plain') as bag:
        for name, type_name in TOPICS.items():
            bag.add_topic(name, type_name, qos[name] and qos_to_dict(qos[name]))
    assert channel_records(tmp_path / 'plain') == channel_records(tmp_path / 'ros')
    assert qos_to_dict(QoSProfile(depth=10)) == DEFAULT_QOS


def stall_writes(monkeypatch):
    """Make the writer thread block in its first write until released."""
    entered, release = threading.Event(), threading.Event()
    original = storage.McapFile.write

    def stalled(self, *args, **kwargs):
        entered.set()
        assert release.wait(10)
        original(self, *args, **kwargs)

    monkeypatch.setattr(storage.McapFile, 'write', stalled)
    return entered, release


def test_full_queue_drops_and_counts_without_blocking(tmp_path, monkeypatch):
    entered, release = stall_writes(monkeypatch)
    bag = RosBagWriter(tmp_path / 'stalled', queue_size=4)
    bag.add_topic('/t', 'geometry_msgs/msg/Wrench')
    assert bag.write('/t', wrench(0), T0)
    assert entered.wait(5)  # the thread holds message 0 and waits on the "disk"
    results, seconds = [], []
    for k in range(1, 25):
        start = time.perf_counter()
        results.append(bag.write('/t', wrench(k), T0 + k * STEP))
        seconds.append(time.perf_counter() - start)
    assert results == [True] * 4 + [False] * 20
    assert bag.dropped == 20
    assert max(seconds) < 0.05
    release.set()
    bag.close()
    records = list(read_messages(tmp_path / 'stalled'))
    assert [fields('/t', deserialize_message(r.data, Wrench)) for r in records] == [
        expected_fields('/t', k) for k in range(5)]
    with Reader(tmp_path / 'stalled') as reader:
        assert reader.message_count == 5


def test_disk_error_stops_recording_and_is_raised_at_close(tmp_path, monkeypatch):
    def full_disk(self):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(storage.McapFile, 'flush_stream', full_disk)
    monkeypatch.setattr(storage.McapFile, 'flush_chunk', full_disk)
    bag = RosBagWriter(tmp_path / 'full')
    bag.add_topic('/t', 'geometry_msgs/msg/Wrench')
    assert bag.write('/t', wrench(0), T0)  # queued; the thread fails on it
    deadline = time.monotonic() + 5
    while bag.error is None and time.monotonic() < deadline:
        time.sleep(0.005)
    assert isinstance(bag.error, BagError)
    assert 'No space left on device' in str(bag.error)
    assert str(tmp_path / 'full' / 'full_0.mcap') in str(bag.error)
    assert bag.write('/t', wrench(1), T0 + STEP) is False
    assert bag.dropped == 2  # the one in the failed batch and the one refused
    with pytest.raises(BagError, match='No space left on device'):
        bag.close()
    bag.close()  # a second close is quiet
