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
A recording mooring node: its bag holds what its subscribers receive.

Its own module: the shared node of test_node_mooring, on the same topics, is gone by then.
"""

from geometry_msgs.msg import WrenchStamped
from rosbags.rosbag2 import Reader
from rosbags.typesys import get_typestore, Stores
from test_node_mooring import drive, line_values, mooring_client, MooringProcess
import yaml


def test_the_bag_holds_the_wrenches_a_subscriber_received(colcon_install, colcon_env, tmp_path):
    # Both wrenches go out as CDR bytes built from the numbers, to subscribers and to the bag
    # alike: read back by an independent reader, the bag's are the received ones, stamps and
    # frames included, in order.
    values = dict(line_values(), record_path=str(tmp_path / 'bag'))
    params_file = tmp_path / 'recording.yaml'
    params_file.write_text(yaml.safe_dump({'mooring': {'ros__parameters': values}}))
    node = MooringProcess(colcon_install, colcon_env, tmp_path / 'recording.log', params_file,
                          '-p', 'use_sim_time:=true')
    client = mooring_client()
    world = client.subscribe('ship/mooring_wrench_world', WrenchStamped, 2000, lambda m: m)
    try:
        client.wait_for_node(node)
        drive(client, 0.0, 3.0)
    finally:
        client.close()
        assert node.interrupt() == 0, node.text()

    def numbers(msg):
        return (msg.header.stamp.sec, msg.header.stamp.nanosec, msg.header.frame_id,
                msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z,
                msg.wrench.torque.x, msg.wrench.torque.y, msg.wrench.torque.z)

    store = get_typestore(Stores.ROS2_JAZZY)
    recorded = {'/ship/mooring_wrench': [], '/ship/mooring_wrench_world': []}
    with Reader(tmp_path / 'bag') as reader:
        for connection, _, data in reader.messages():
            if connection.topic in recorded:
                recorded[connection.topic].append(
                    numbers(store.deserialize_cdr(data, connection.msgtype)))
    received = [numbers(msg) for _, msg in sorted(client.wrenches.by_sequence().items())]
    received_world = [numbers(msg) for msg in world]
    assert len(received) >= 100 and len(received_world) >= 100  # 3 s at 50 Hz, less the start
    # every output is in the bag; a subscriber gets them from its match on (a first one may
    # go out while the node's side of the match is still on its way)
    assert len(recorded['/ship/mooring_wrench_world']) == len(recorded['/ship/mooring_wrench'])
    assert recorded['/ship/mooring_wrench'][-len(received):] == received
    assert recorded['/ship/mooring_wrench_world'][-len(received_world):] == received_world
    assert {r[2] for r in received} == {'base_link'}
    assert {r[2] for r in recorded['/ship/mooring_wrench_world']} == {'world'}
    assert all(r[3] < -1.0e5 for r in received[-10:])  # the lines hold the ship back
