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
Reading bags cut short, as a killed recorder leaves them, and recovering them.

A complete bag is cut at byte offsets inside and between its chunks (and its
metadata.yaml removed): the reader must return exactly the messages of the chunks that
lie whole before the cut, with their values, and recover() must turn that into a bag
rosbags opens.
"""

import os
import shutil
import time

from geometry_msgs.msg import PoseStamped
from mcap.reader import make_reader
import pytest
from rclpy.serialization import deserialize_message
from rope_sim_ros.bag import bag_info, BagError, BagWriter, cdr, read_messages, recover
from rosbags.rosbag2 import Reader
from rosbags.typesys import get_typestore, Stores
import yaml

T0 = 1_767_225_600_000_000_000
STEP = 1_000_000  # 1 ms between messages: the k-th message is logged at T0 + k * STEP
COUNT = 3000
CUSTOM = {'rope_sim_ros.parameters': 'length: 40.0\n'}
TOPIC = '/mooring_line/fairlead/pose'


def pose(k):
    """Return the CDR bytes of a PoseStamped at x = k, z = -k / 2."""
    return cdr.pose_stamped(0, 0, 'ship', (float(k), 0.0, -0.5 * k, 0.0, 0.0, 0.0, 1.0))


def check_values(records):
    """Assert the records are messages 0..n-1 with their values; return n."""
    for k, record in enumerate(records):
        assert record.log_time_ns == T0 + k * STEP
        assert record.publish_time_ns == T0 + k * STEP - 7
        message = deserialize_message(record.data, PoseStamped)
        assert (message.pose.position.x, message.pose.position.z) == (float(k), -0.5 * k)
    return len(records)


@pytest.fixture(scope='module')
def complete(tmp_path_factory):
    """Return a closed bag of COUNT poses in 16 KiB chunks, and its chunk index."""
    path = tmp_path_factory.mktemp('complete') / 'run'
    with BagWriter(path, chunk_size=16 * 1024, custom_data=CUSTOM) as bag:
        bag.add_topic(TOPIC, 'geometry_msgs/msg/PoseStamped')
        for k in range(COUNT):
            assert bag.write(TOPIC, pose(k), T0 + k * STEP, T0 + k * STEP - 7)
    with open(path / 'run_0.mcap', 'rb') as stream:
        chunks = sorted(make_reader(stream).get_summary().chunk_indexes,
                        key=lambda index: index.chunk_start_offset)
    assert len(chunks) > 10
    return path, chunks


def cut_copy(complete, tmp_path, offset):
    """Copy the bag, truncate its .mcap at offset and drop metadata.yaml, as a kill does."""
    source, _ = complete
    path = tmp_path / 'killed'
    path.mkdir()
    with open(source / 'run_0.mcap', 'rb') as stream:
        (path / 'killed_0.mcap').write_bytes(stream.read(offset))
    return path


def whole_before(chunks, offset):
    """Return the number of messages in the chunks that end at or before offset."""
    ends = [c.message_end_time for c in chunks
            if c.chunk_start_offset + c.chunk_length <= offset]
    return 0 if not ends else (max(ends) - T0) // STEP + 1


@pytest.mark.parametrize('where', ['middle of last chunk', 'middle of chunk 3',
                                   'right after chunk 3', 'inside chunk 3 header'])
def test_cut_bag_yields_exactly_the_whole_chunks(complete, tmp_path, where):
    _, chunks = complete
    last, third = chunks[-1], chunks[3]
    offset = {
        'middle of last chunk': last.chunk_start_offset + last.chunk_length // 2,
        'middle of chunk 3': third.chunk_start_offset + third.chunk_length // 2,
        'right after chunk 3': third.chunk_start_offset + third.chunk_length,
        'inside chunk 3 header': third.chunk_start_offset + 5,
    }[where]
    path = cut_copy(complete, tmp_path, offset)
    expected = whole_before(chunks, offset)
    assert expected > 0

    records = list(read_messages(path))
    assert check_values(records) == expected
    info = bag_info(path)
    assert info.complete is False
    assert info.message_count == expected
    assert info.topics[TOPIC].message_count == expected
    assert info.topics[TOPIC].type_name == 'geometry_msgs/msg/PoseStamped'
    assert (info.start_ns, info.end_ns) == (T0, T0 + (expected - 1) * STEP)


def test_recover_in_place_makes_a_bag_rosbags_opens(complete, tmp_path):
    source, chunks = complete
    offset = chunks[-1].chunk_start_offset + chunks[-1].chunk_length // 2
    path = cut_copy(complete, tmp_path, offset)
    expected = whole_before(chunks, offset)

    assert recover(path) == expected
    assert sorted(os.listdir(path)) == ['killed_0.mcap', 'metadata.yaml']
    # custom_data (the parameters of a run) survives the kill: it opens the file
    with open(path / 'metadata.yaml', encoding='utf-8') as stream:
        info = yaml.safe_load(stream)['rosbag2_bagfile_information']
    assert info['custom_data'] == CUSTOM
    assert bag_info(path).complete is True
    store = get_typestore(Stores.ROS2_JAZZY)
    with Reader(path) as reader, Reader(source) as original:
        assert reader.message_count == expected
        [connection] = reader.connections
        [original_connection] = original.connections
        # The channel's QoS and type hash are carried over, not re-derived.
        assert connection.digest == original_connection.digest
        assert connection.ext.offered_qos_profiles == \
            original_connection.ext.offered_qos_profiles
        positions = [store.deserialize_cdr(data, c.msgtype).pose.position.x
                     for c, _, data in reader.messages()]
    assert positions == [float(k) for k in range(expected)]
    assert check_values(list(read_messages(path))) == expected


def test_recover_to_a_new_bag_keeps_the_cut_one(complete, tmp_path):
    _, chunks = complete
    offset = chunks[5].chunk_start_offset + 100
    path = cut_copy(complete, tmp_path, offset)
    size = os.path.getsize(path / 'killed_0.mcap')
    out = tmp_path / 'recovered'

    assert recover(path, out) == whole_before(chunks, offset)
    assert os.path.getsize(path / 'killed_0.mcap') == size
    assert sorted(os.listdir(out)) == ['metadata.yaml', 'recovered_0.mcap']
    with Reader(out) as reader:
        assert reader.message_count == whole_before(chunks, offset)
    with pytest.raises(BagError, match='not empty'):
        recover(path, out)


def test_snapshot_of_an_open_bag_is_readable(tmp_path):
    """Copy the .mcap while its writer is still recording, as a kill would leave it."""
    path = tmp_path / 'live'
    interval = 0.1
    bag = BagWriter(path, flush_interval=interval)
    try:
        bag.add_topic(TOPIC, 'geometry_msgs/msg/PoseStamped')
        for k in range(200):
            bag.write(TOPIC, pose(k), T0 + k * STEP, T0 + k * STEP - 7)
        time.sleep(interval + 0.4)  # the thread writes the chunk out within the interval
        for k in range(200, 250):
            bag.write(TOPIC, pose(k), T0 + k * STEP, T0 + k * STEP - 7)
        snapshot = tmp_path / 'snapshot'
        snapshot.mkdir()
        shutil.copyfile(bag.storage_path, snapshot / 'snapshot_0.mcap')
    finally:
        bag.close()
    readable = check_values(list(read_messages(snapshot)))
    assert 200 <= readable <= 250
    assert recover(snapshot) == readable
    assert check_values(list(read_messages(path))) == 250


def test_header_only_file_reads_as_empty(complete, tmp_path):
    _, chunks = complete
    path = cut_copy(complete, tmp_path, chunks[0].chunk_start_offset)
    assert list(read_messages(path)) == []
    info = bag_info(path)
    assert (info.message_count, info.complete, info.topics) == (0, False, {})


def test_not_a_bag(tmp_path):
    with pytest.raises(BagError, match='does not exist'):
        list(read_messages(tmp_path / 'nothing'))
    (tmp_path / 'empty').mkdir()
    with pytest.raises(BagError, match='not a bag'):
        bag_info(tmp_path / 'empty')
    (tmp_path / 'sqlite').mkdir()
    (tmp_path / 'sqlite' / 'metadata.yaml').write_text(
        'rosbag2_bagfile_information:\n  version: 9\n  storage_identifier: sqlite3\n')
    with pytest.raises(BagError, match="'sqlite3'; only mcap"):
        bag_info(tmp_path / 'sqlite')
