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
``rope_sim run --bag``: the node's bag layout, read back by rosbags and mcap_ros2.

Every message is compared with what the run computed: the input poses with the motion
rows, the tension wrenches, peaks and the winch's length with the OUT.csv rows of the same
run, the latched parted flag with its one message, the particles with the end points and
the rope tangent.
"""

import csv
import math
from typing import NamedTuple
import warnings

import numpy as np
import pytest
from rope_sim_ros.bag import bag_info
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.motion import read_motion
from rope_sim_ros.offline.resim import stored_setup
from rope_sim_ros.offline.sinks import STATE_COLUMN
from rosbags.rosbag2 import Reader
from rosbags.typesys import get_typestore, Stores
import yaml

with warnings.catch_warnings():
    warnings.simplefilter('ignore', DeprecationWarning)
    from mcap_ros2.reader import read_ros2_messages

SEGMENTS = 12
FAIRLEAD_OFFSET = np.array([1.0, 0.5, -0.25])
TYPES = {
    '/fairlead/pose': 'geometry_msgs/msg/PoseStamped',
    '/bollard/pose': 'geometry_msgs/msg/PoseStamped',
    '/rope/particles': 'geometry_msgs/msg/PoseArray',
    '/fairlead/tension': 'geometry_msgs/msg/Wrench',
    '/bollard/tension': 'geometry_msgs/msg/Wrench',
    '/fairlead/peak_tension': 'std_msgs/msg/Float64',
    '/bollard/peak_tension': 'std_msgs/msg/Float64',
    '/winch/length': 'std_msgs/msg/Float64',
    '/rope/parted': 'std_msgs/msg/Bool',
}


class Motion(NamedTuple):
    """The rows of a MOTION.csv: times [s] (n,), fairlead and bollard points (n, 3)."""

    t: np.ndarray
    fairlead: np.ndarray
    bollard: np.ndarray


def read_points(path) -> Motion:
    """Read a MOTION.csv with both ends' points."""
    streams = read_motion(path)  # no fairlead_offset: the ship's poses are the points
    _, bollard, _ = streams.bollards['']
    return Motion(np.array([ns / 10**9 for ns in streams.t_ns.tolist()]), streams.position,
                  bollard)


def write_motion(path):
    """Three seconds: the fairlead surges smoothly, the bollard creeps along y."""
    lines = ['t,fairlead_x,fairlead_y,fairlead_z,bollard_x,bollard_y,bollard_z']
    for k in range(61):
        t = k * 0.05
        surge = 0.5 * (1.0 - math.cos(math.pi * t / 3.0))
        lines.append(f'{t:.2f},{36.0 + surge!r},0.0,8.0,0.0,{0.01 * t!r},0.0')
    path.write_text('\n'.join(lines) + '\n')
    return path


@pytest.fixture(scope='module')
def run(tmp_path_factory):
    base = tmp_path_factory.mktemp('runbag')
    motion = write_motion(base / 'motion.csv')
    out, bag = base / 'out.csv', base / 'run1'
    code = cli.main([
        'run', '--motion', str(motion), '--out', str(out), '--bag', str(bag), '--rate', '50',
        '--quiet', '--set', f'segments={SEGMENTS}', '--set', 'frame_id=quay',
        '--set', f'fairlead_offset={FAIRLEAD_OFFSET.tolist()}'])
    assert code == 0
    with open(out, newline='') as f:
        rows = [{k: float(v) for k, v in row.items() if k != STATE_COLUMN}
                for row in csv.DictReader(f)]
    return {'motion': read_points(motion), 'rows': rows, 'bag': bag}


def stamp_ns(t):
    return int(round(t * 1e9))


def xyz(v):
    return np.array([v.x, v.y, v.z])


def x_axis(q):
    """Return the body x axis of quaternion q (x, y, z, w) in the parent frame."""
    x, y, z, w = q.x, q.y, q.z, q.w
    return np.array([1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)])


def check_message(run, topic, log_time, msg):
    """Assert one decoded message equals what the run computed; return its kind."""
    motion, rows = run['motion'], run['rows']
    if topic.endswith('/pose'):
        k = int(np.flatnonzero(np.isclose(motion.t, log_time / 1e9, rtol=0, atol=1e-9))[0])
        assert msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec == log_time
        assert log_time == stamp_ns(motion.t[k])
        assert msg.header.frame_id == 'quay'
        if topic == '/fairlead/pose':
            # The recorded pose ⊕ fairlead_offset is the motion's fairlead point.
            expected = motion.fairlead[k] - FAIRLEAD_OFFSET
        else:
            expected = motion.bollard[k]
        assert xyz(msg.pose.position).tolist() == expected.tolist()
        q = msg.pose.orientation
        assert (q.x, q.y, q.z, q.w) == (0.0, 0.0, 0.0, 1.0)
        return topic
    if topic == '/rope/parted':  # latched: said once, at the first output
        assert log_time == stamp_ns(rows[0]['t'])
        assert not msg.data and not any(r['parted'] for r in rows)
        return topic
    row = next(r for r in rows if stamp_ns(r['t']) == log_time)
    if topic.endswith('/peak_tension'):
        end = topic.split('/')[1]
        assert msg.data == row[f'{end}_peak_tension']
        return topic
    if topic == '/winch/length':
        assert msg.data == row['line_length']
        return topic
    if topic.endswith('/tension'):
        end = topic.split('/')[1]
        force = xyz(msg.force)
        assert force.tolist() == [row[f'{end}_fx'], row[f'{end}_fy'], row[f'{end}_fz']]
        assert float(np.linalg.norm(force)) == pytest.approx(row[f'{end}_tension'], rel=1e-15)
        lever = FAIRLEAD_OFFSET if end == 'fairlead' else np.zeros(3)
        np.testing.assert_allclose(xyz(msg.torque), np.cross(lever, force), rtol=1e-12,
                                   atol=1e-9)
        return topic
    assert topic == '/rope/particles'
    assert msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec == log_time
    assert msg.header.frame_id == 'quay'
    points = np.array([xyz(p.position) for p in msg.poses])
    assert points.shape == (SEGMENTS + 1, 3)
    t = row['t']
    at_row = np.isclose(motion.t, t, rtol=0, atol=1e-9)
    if at_row.any():  # the ends are on the motion rows exactly
        np.testing.assert_allclose(points[-1], motion.fairlead[at_row][0], atol=1e-9)
        np.testing.assert_allclose(points[0], motion.bollard[at_row][0], atol=1e-9)
    else:  # and in between close to the chord (end_interpolation may be a spline)
        fairlead = [np.interp(t, motion.t, motion.fairlead[:, i]) for i in range(3)]
        bollard = [np.interp(t, motion.t, motion.bollard[:, i]) for i in range(3)]
        np.testing.assert_allclose(points[-1], fairlead, atol=1e-3)
        np.testing.assert_allclose(points[0], bollard, atol=1e-3)
    tangent = np.gradient(points, axis=0)  # central differences, one-sided at the ends
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    axes = np.array([x_axis(p.orientation) for p in msg.poses])
    np.testing.assert_allclose(axes, tangent, atol=1e-9)
    return topic


def expected_counts(run):
    n_in, n_out = len(run['motion'].t), len(run['rows'])
    return {'/fairlead/pose': n_in, '/bollard/pose': n_in, '/rope/particles': n_out,
            '/fairlead/tension': n_out, '/bollard/tension': n_out,
            '/fairlead/peak_tension': n_out, '/bollard/peak_tension': n_out,
            '/winch/length': n_out, '/rope/parted': 1}


def test_rows_cover_the_motion_at_the_rate(run):
    times = [r['t'] for r in run['rows']]
    assert len(times) == 151 and times[0] == 0.0 and times[-1] == pytest.approx(3.0)


def test_rosbags_reads_every_message_as_computed(run):
    typestore = get_typestore(Stores.ROS2_JAZZY)
    seen = {topic: 0 for topic in TYPES}
    with Reader(run['bag']) as reader:
        assert {c.topic: c.msgtype for c in reader.connections} == TYPES
        assert {c.topic: c.msgcount for c in reader.connections} == expected_counts(run)
        for connection, log_time, raw in reader.messages():
            msg = typestore.deserialize_cdr(raw, connection.msgtype)
            seen[check_message(run, connection.topic, log_time, msg)] += 1
    assert seen == expected_counts(run)


def test_mcap_ros2_decodes_every_message_as_computed(run):
    seen = {topic: 0 for topic in TYPES}
    for message in read_ros2_messages(str(run['bag'] / 'run1_0.mcap')):
        assert message.log_time_ns == message.publish_time_ns
        assert message.schema.name == TYPES[message.channel.topic]
        seen[check_message(run, message.channel.topic, message.log_time_ns,
                           message.ros_msg)] += 1
    assert seen == expected_counts(run)


def test_metadata_counts_and_stored_parameters(run):
    metadata = yaml.safe_load((run['bag'] / 'metadata.yaml').read_text())
    info = metadata['rosbag2_bagfile_information']
    counts = {t['topic_metadata']['name']: t['message_count']
              for t in info['topics_with_message_count']}
    assert counts == expected_counts(run)
    assert info['message_count'] == sum(counts.values())
    assert info['starting_time']['nanoseconds_since_epoch'] == 0
    assert info['duration']['nanoseconds'] == 3 * 10**9
    ours = bag_info(run['bag'])
    assert ours.complete and {n: t.message_count for n, t in ours.topics.items()} == counts
    stored = stored_setup(run['bag']).lines[0].params.as_dict()
    assert stored['segments'] == SEGMENTS and stored['frame_id'] == 'quay'
    assert stored['fairlead_offset'] == FAIRLEAD_OFFSET.tolist()


def test_existing_bag_directory_is_refused(run, tmp_path, capsys):
    before = sorted(p.name for p in run['bag'].iterdir())
    motion = write_motion(tmp_path / 'motion.csv')
    code = cli.main(['run', '--motion', str(motion), '--bag', str(run['bag']), '--quiet'])
    err = capsys.readouterr().err
    assert code == 2 and 'not overwriting' in err and err.count('\n') == 1, err
    assert sorted(p.name for p in run['bag'].iterdir()) == before


def encoded(ns, frame_id, points, force, lever) -> dict:
    """Return {topic: CDR bytes} the offline run's encoder builds for one line's output."""
    from rope_sim_ros.messages import topics
    from rope_sim_ros.messages.encode import OutputEncoder
    from rope_sim_ros.mooring.records import Published
    from rope_sim_ros.mooring.records import MooringOutput
    zeros = np.zeros((1, 3))
    output = MooringOutput(
        t=0.0, positions=(points,), fairlead_forces=np.array([force]), bollard_forces=zeros,
        max_strains=np.zeros(1), payload_positions=(None,), parted=np.zeros(1, dtype=bool),
        fairlead_peaks=np.zeros(1), fairlead_tensions=np.zeros(1),
        bollard_tensions=np.zeros(1), bollard_peaks=np.zeros(1), line_lengths=np.zeros(1),
        winch_speeds=np.zeros(1))
    # the ship at the origin, unturned: the fairlead's offset is its lever
    published = Published(ns, output, np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]),
                          np.array([lever]), zeros, None)
    encoder = OutputEncoder(topics.LINE_NODE, [''], [False], frame_id)
    return dict(encoder.messages(published, [topics.PARTICLES, topics.FAIRLEAD_TENSION]))


@pytest.mark.parametrize('frame_id', ['', 'a', 'abc', 'abcd', 'world', 'ship/base_link'])
def test_numpy_cdr_equals_rclpy_serialization(frame_id):
    """The run's encoders: the node's messages as rclpy serialises them, zero padding."""
    from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
    from rclpy.serialization import deserialize_message, serialize_message
    from rope_sim_ros.messages.encode import pose_stamped
    from rope_sim_ros.ros.conversions import ns_to_stamp, pose_array, wrench
    points = np.random.default_rng(7).normal(size=(SEGMENTS + 1, 3)) * 20.0
    ns = 1_767_225_600_123_456_789
    pose = PoseStamped()
    pose.header.stamp, pose.header.frame_id = ns_to_stamp(ns), frame_id
    pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = points[3].tolist()
    pose.pose.orientation.w = 1.0
    line = encoded(ns, frame_id, points, points[0], points[1])
    for ours, message, cls in (
            (line['rope/particles'], pose_array(points, frame_id, ns), PoseArray),
            (pose_stamped(ns, frame_id, points[3]), pose, PoseStamped),
            (line['fairlead/tension'], wrench(points[0], points[1]), Wrench)):
        theirs = serialize_message(message)
        assert len(ours) == len(theirs)
        assert deserialize_message(ours, cls) == message
        differ = [i for i in range(len(ours)) if ours[i] != theirs[i]]
        assert all(ours[i] == 0 for i in differ)  # only rclpy's uninitialised padding
        assert len(differ) < 8


def test_two_runs_give_identical_payloads(run, tmp_path):
    motion = write_motion(tmp_path / 'motion.csv')
    again = tmp_path / 'again'
    assert cli.main([
        'run', '--motion', str(motion), '--bag', str(again), '--rate', '50', '--quiet',
        '--set', f'segments={SEGMENTS}', '--set', 'frame_id=quay',
        '--set', f'fairlead_offset={FAIRLEAD_OFFSET.tolist()}']) == 0
    with Reader(run['bag']) as a, Reader(again) as b:
        assert [(c.topic, t, raw) for c, t, raw in a.messages()] == [
            (c.topic, t, raw) for c, t, raw in b.messages()]
