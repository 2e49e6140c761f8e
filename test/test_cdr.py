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
bag.cdr against rclpy: random messages encoded by one and decoded by the other, both ways.

bag.cdr writes and reads CDR with struct and numpy so that the offline commands need no
ROS; rclpy's serialize_message/deserialize_message are the reference it must agree with.
"""

import math

from geometry_msgs.msg import Pose, PoseArray, PoseStamped, Wrench
import numpy as np
import pytest
from rclpy.serialization import deserialize_message, serialize_message
from rope_sim_ros.bag import BagError, cdr
from std_msgs.msg import Float64, String

RNG = np.random.default_rng(20260101)
FRAMES = ['', 'w', 'ab', 'abc', 'ship', 'quay_7', 'wörld', 'x' * 61]


def random_pose_values():
    position = RNG.normal(scale=100.0, size=3)
    orientation = RNG.normal(size=4)  # not normalised: stored as given
    return position, orientation


def random_stamp():
    return int(RNG.integers(-2**31, 2**31)), int(RNG.integers(0, 10**9))


def pose_message(position, orientation):
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = (float(v) for v in position)
    o = pose.orientation
    o.x, o.y, o.z, o.w = (float(v) for v in orientation)
    return pose


@pytest.mark.parametrize('frame_id', FRAMES)
def test_pose_stamped_both_ways(frame_id):
    for _ in range(20):
        (sec, nanosec), (position, orientation) = random_stamp(), random_pose_values()
        ours = cdr.pose_stamped(sec, nanosec, frame_id, [*position, *orientation])
        message = PoseStamped()
        message.header.stamp.sec, message.header.stamp.nanosec = sec, nanosec
        message.header.frame_id = frame_id
        message.pose = pose_message(position, orientation)
        assert deserialize_message(ours, PoseStamped) == message
        theirs = serialize_message(message)
        assert len(theirs) == len(ours)
        for data in (ours, theirs):
            got = cdr.decode_pose_stamped(data)
            assert got[:3] == (sec, nanosec, frame_id)
            assert got[3].tolist() == position.tolist()
            assert got[4].tolist() == orientation.tolist()


@pytest.mark.parametrize('frame_id', FRAMES)
@pytest.mark.parametrize('count', [0, 1, 2, 17])
def test_pose_array_both_ways(frame_id, count):
    (sec, nanosec) = random_stamp()
    poses = RNG.normal(scale=50.0, size=(count, 7))
    ours = cdr.pose_array(sec, nanosec, frame_id, poses)
    message = PoseArray()
    message.header.stamp.sec, message.header.stamp.nanosec = sec, nanosec
    message.header.frame_id = frame_id
    message.poses = [pose_message(row[:3], row[3:]) for row in poses]
    assert deserialize_message(ours, PoseArray) == message
    for data in (ours, serialize_message(message)):
        got_sec, got_nanosec, got_frame, got_poses = cdr.decode_pose_array(data)
        assert (got_sec, got_nanosec, got_frame) == (sec, nanosec, frame_id)
        assert got_poses.shape == (count, 7)
        assert got_poses.tolist() == poses.tolist()


def test_wrench_both_ways():
    for _ in range(50):
        force, torque = RNG.normal(scale=1e5, size=3), RNG.normal(scale=1e3, size=3)
        ours = cdr.wrench(force, torque)
        message = Wrench()
        message.force.x, message.force.y, message.force.z = (float(v) for v in force)
        message.torque.x, message.torque.y, message.torque.z = (float(v) for v in torque)
        theirs = serialize_message(message)
        assert ours == theirs  # no padding in a Wrench: the very same bytes
        got_force, got_torque = cdr.decode_wrench(theirs)
        assert got_force.tolist() == force.tolist()
        assert got_torque.tolist() == torque.tolist()


@pytest.mark.parametrize('text', ['', 'a', 'ab', 'abc', 'abcd', 'line tension 1.2e5 N',
                                  'ünïcödé ⚓', 'event: {"winch": 3}\nsecond line'])
def test_string_both_ways(text):
    ours = cdr.string(text)
    assert deserialize_message(ours, String).data == text
    assert ours == serialize_message(String(data=text))
    assert cdr.decode_string(ours) == text
    assert cdr.decode_string(serialize_message(String(data=text))) == text


@pytest.mark.parametrize('value', [0.0, -0.0, 1.5, -273.15, 1e-300, 1e300, math.inf, 40.125])
def test_float64_both_ways(value):
    ours = cdr.float64(value)
    assert ours == serialize_message(Float64(data=value))
    assert deserialize_message(ours, Float64).data == value
    assert cdr.decode_float64(ours) == value


def test_big_endian_is_read_too():
    body = b'\x00\x00\x00\x00' + (3).to_bytes(4, 'big') + (2).to_bytes(4, 'big')
    body += (3).to_bytes(4, 'big') + b'ab\x00'
    body += bytes(-(len(body) - 4) % 8) + np.arange(7, dtype='>f8').tobytes()
    sec, nanosec, frame_id, position, orientation = cdr.decode_pose_stamped(body)
    assert (sec, nanosec, frame_id) == (3, 2, 'ab')
    assert position.tolist() == [0.0, 1.0, 2.0]
    assert orientation.tolist() == [3.0, 4.0, 5.0, 6.0]


@pytest.mark.parametrize('decode, data, reason', [
    (cdr.decode_wrench, b'', 'encapsulation header'),
    (cdr.decode_wrench, b'\x07\x07\x00\x00' + bytes(48), 'encapsulation header'),
    (cdr.decode_wrench, cdr.wrench((1, 2, 3), (4, 5, 6))[:-1], 'cut short'),
    (cdr.decode_pose_stamped, cdr.pose_stamped(1, 2, 'ship', [0] * 7)[:30], 'cut short'),
    (cdr.decode_pose_array, cdr.pose_array(1, 2, 'w', np.zeros((3, 7)))[:-8], 'do not fit'),
    (cdr.decode_string, cdr.CDR_LE + b'\x03\x00\x00\x00abc', 'not NUL-terminated'),
    (cdr.decode_string, cdr.CDR_LE + b'\x02\x00\x00\x00\xff\x00', 'not UTF-8'),
    (cdr.decode_float64, cdr.CDR_LE + b'\x00', 'cut short'),
])
def test_bad_bytes_are_one_clear_error(decode, data, reason):
    with pytest.raises(BagError, match=reason):
        decode(data)
