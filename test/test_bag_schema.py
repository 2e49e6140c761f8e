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
The schema text and type hash rope_sim_ros.bag embeds, against the files and two decoders.

rope_sim_ros.bag carries its own copy of the .msg texts and hashes (bag/definitions.py) so
that it needs no ROS; rope_sim_ros.ros2bag.schema reads the installed ones. The copy is
checked here against the installed files, so it cannot go stale unnoticed.

The expected PoseStamped text is spelled out by hand from rosbag2_storage_mcap's rule (root
file, then each nested type once, depth-first, in sorted order) so that a change of order
or delimiter shows here, not in somebody's replay tool.
"""

import json
import os
import warnings

from ament_index_python.packages import get_package_share_directory
from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
import pytest
from rclpy.serialization import serialize_message
from rope_sim_ros.bag import BagError
from rope_sim_ros.bag import schema
from rope_sim_ros.ros2bag import schema as installed
from rosbags.typesys import get_types_from_msg, get_typestore, Stores

with warnings.catch_warnings():
    warnings.simplefilter('ignore', DeprecationWarning)
    from mcap_ros2._dynamic import generate_dynamic

DELIMITER = '\n' + '=' * 80 + '\n'


def msg_file(package, name):
    path = os.path.join(get_package_share_directory(package), 'msg', name + '.msg')
    with open(path, encoding='utf-8', newline='') as stream:
        return stream.read()


def test_pose_stamped_text_is_rosbag2_layout():
    expected = msg_file('geometry_msgs', 'PoseStamped')
    for package, name in [('geometry_msgs', 'Pose'), ('geometry_msgs', 'Point'),
                          ('geometry_msgs', 'Quaternion'), ('std_msgs', 'Header'),
                          ('builtin_interfaces', 'Time')]:
        expected += DELIMITER + f'MSG: {package}/{name}\n' + msg_file(package, name)
    assert schema.message_definition('geometry_msgs/msg/PoseStamped') == expected
    # The short form names the same type.
    assert schema.message_definition('geometry_msgs/PoseStamped') == expected


@pytest.mark.parametrize('type_name, sections', [
    ('geometry_msgs/msg/PoseStamped', 6),
    ('geometry_msgs/msg/PoseArray', 6),
    ('geometry_msgs/msg/Wrench', 2),
])
def test_each_nested_type_once(type_name, sections):
    text = schema.message_definition(type_name)
    names = [line[5:] for line in text.split('\n') if line.startswith('MSG: ')]
    assert len(names) == len(set(names)) == sections - 1


def pose_array():
    message = PoseArray()
    message.header.frame_id = 'quay'
    for i in range(3):
        pose = PoseStamped().pose
        pose.position.x, pose.orientation.w = 1.25 * i, 0.5
        message.poses.append(pose)
    return message


def wrench():
    message = Wrench()
    message.force.x, message.torque.z = 1.5e5, -2.0
    return message


def pose_stamped():
    message = PoseStamped()
    message.header.stamp.sec, message.header.frame_id = 17, 'ship'
    message.pose.position.z = -3.5
    return message


def fields(message):
    """Return the values the three builders above set, from any decoder's object."""
    if hasattr(message, 'poses'):
        return (message.header.frame_id, [p.position.x for p in message.poses],
                [p.orientation.w for p in message.poses])
    if hasattr(message, 'force'):
        return (message.force.x, message.torque.z)
    return (message.header.stamp.sec, message.header.frame_id, message.pose.position.z,
            message.pose.orientation.w)


@pytest.mark.parametrize('type_name, build, expected', [
    ('geometry_msgs/msg/PoseStamped', pose_stamped, (17, 'ship', -3.5, 1.0)),
    ('geometry_msgs/msg/PoseArray', pose_array, ('quay', [0.0, 1.25, 2.5], [0.5] * 3)),
    ('geometry_msgs/msg/Wrench', wrench, (1.5e5, -2.0)),
])
def test_text_decodes_with_mcap_ros2_and_rosbags(type_name, build, expected):
    text = schema.message_definition(type_name)
    data = serialize_message(build())

    decoded = generate_dynamic(type_name, text)[type_name](data)
    store = get_typestore(Stores.EMPTY)
    store.register(get_types_from_msg(text, type_name))
    from_rosbags = store.deserialize_cdr(data, type_name)

    assert fields(decoded) == expected
    assert fields(from_rosbags) == expected


@pytest.mark.parametrize('type_name', [
    'geometry_msgs/msg/PoseStamped', 'geometry_msgs/msg/PoseArray', 'geometry_msgs/msg/Wrench'])
def test_type_hash_is_the_json_entry(type_name):
    package, _, name = type_name.split('/')
    path = os.path.join(get_package_share_directory(package), 'msg', name + '.json')
    with open(path, encoding='utf-8') as stream:
        hashes = {e['type_name']: e['hash_string'] for e in json.load(stream)['type_hashes']}
    assert schema.type_hash(type_name) == hashes[type_name]
    assert schema.type_hash(type_name).startswith('RIHS01_')
    assert len(schema.type_hash(type_name)) == len('RIHS01_') + 64


def test_rosbags_typestore_agrees_on_the_hash():
    # rosbags computes RIHS01 itself from its own Jazzy type definitions.
    store = get_typestore(Stores.ROS2_JAZZY)
    for type_name in ('geometry_msgs/msg/PoseStamped', 'geometry_msgs/msg/Wrench'):
        assert store.hash_rihs01(type_name) == schema.type_hash(type_name)


@pytest.mark.parametrize('bad', ['PoseStamped', 'geometry_msgs/srv/X/Y', '', 'a//b'])
def test_bad_type_names_are_refused(bad):
    with pytest.raises(BagError, match='pkg/msg/Type'):
        schema.message_definition(bad)


def test_unknown_package_is_named():
    with pytest.raises(BagError, match='no_such_msgs'):
        schema.type_hash('no_such_msgs/msg/Thing')
    with pytest.raises(BagError, match='no_such_msgs.*not in the ament index'):
        installed.type_hash('no_such_msgs/msg/Thing')


def test_a_type_not_carried_is_left_to_the_ros_side():
    with pytest.raises(BagError, match="'sensor_msgs/msg/Imu' is not one.*RosBagWriter"):
        schema.message_definition('sensor_msgs/msg/Imu')
    text = installed.message_definition('sensor_msgs/msg/Imu')
    assert text.startswith(msg_file('sensor_msgs', 'Imu'))
    assert DELIMITER + 'MSG: geometry_msgs/Quaternion\n' in text


def test_definitions_py_is_what_is_installed():
    """bag/definitions.py is exactly what `python -m rope_sim_ros.ros2bag` prints now."""
    path = os.path.join(os.path.dirname(schema.__file__), 'definitions.py')
    with open(path, encoding='utf-8') as stream:
        current = stream.read()
    assert current == installed.definitions_source(), (
        'rope_sim_ros/bag/definitions.py differs from the installed message definitions; '
        'regenerate it: python -m rope_sim_ros.ros2bag > rope_sim_ros/bag/definitions.py')


@pytest.mark.parametrize('type_name', installed.RECORDED_TYPES)
def test_carried_types_equal_the_installed_ones(type_name):
    assert set(installed.closure([type_name])) <= set(schema.known_types())
    assert schema.message_definition(type_name) == installed.message_definition(type_name)
    assert schema.type_hash(type_name) == installed.type_hash(type_name)
    # every field of the Python class is in the text (the class and the files agree)
    package, _, name = type_name.split('/')
    text = msg_file(package, name)
    for field in installed.message_class(type_name).get_fields_and_field_types():
        assert f' {field}' in text, (type_name, field)


def test_every_carried_type_is_installed_verbatim():
    for type_name in schema.known_types():
        package, _, name = type_name.split('/')
        assert schema.msg_text(type_name) == msg_file(package, name), type_name
