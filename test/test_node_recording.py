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
Recording in the mooring_line node (record_path), against the installed node over real DDS.

One node per scenario: Ctrl-C (the full comparison with what crossed DDS, read back with
rosbags and mcap_ros2), SIGTERM (lighter), SIGKILL (readable up to the last chunk, then
`rope_sim recover`), and two that must refuse to start. A disk error mid-run is tested in
process: on the Recorder alone and on a node whose bag file breaks under it.
"""

import errno
import json
import math
import os
from pathlib import Path
import signal
import time
import warnings

from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
from mcap.reader import make_reader
from node_harness import Client, NodeProcess, Sent
import numpy as np
import pytest
import rclpy
from rclpy.parameter import Parameter
from rclpy.serialization import deserialize_message
from rclpy.signals import SignalHandlerOptions
from rope_sim_ros.bag import bag_info, read_messages
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.resim import stored_setup
from rope_sim_ros.ros import recorder as rec
from rope_sim_ros.ros.conversions import pose_array, wrench
from rope_sim_ros.ros2bag import deserialize
from rosbags.rosbag2 import Reader
from rosbags.typesys import get_typestore, Stores
from std_msgs.msg import Bool, Float64, String
import yaml

with warnings.catch_warnings():
    warnings.simplefilter('ignore', DeprecationWarning)
    from mcap_ros2.reader import read_ros2_messages

START_TIMEOUT = 60.0  # the first node of a fresh install compiles the rope kernels
FAIRLEAD = np.array([36.0, 0.0, 8.0])
TYPES = {
    'fairlead/pose': 'geometry_msgs/msg/PoseStamped',
    'bollard/pose': 'geometry_msgs/msg/PoseStamped',
    'rope/particles': 'geometry_msgs/msg/PoseArray',
    'fairlead/tension': 'geometry_msgs/msg/Wrench',
    'bollard/tension': 'geometry_msgs/msg/Wrench',
    'rope/events': 'std_msgs/msg/String',
    'fairlead/peak_tension': 'std_msgs/msg/Float64',
    'bollard/peak_tension': 'std_msgs/msg/Float64',
    'winch/length': 'std_msgs/msg/Float64',
    'rope/parted': 'std_msgs/msg/Bool',
}


# ------------------------------------------------------------------------------ helpers


def fairlead_motion(t: float) -> np.ndarray:
    """Return a slow surge and heave of the fairlead around its rest point."""
    return FAIRLEAD + [0.4 * math.sin(2.0 * t), 0.0, 0.2 * math.sin(1.3 * t)]


def recorded(sent: Sent) -> tuple:
    """Return a pose the client sent as the bag's is compared with it (pose_values)."""
    return sent.stamp_ns, sent.position, sent.orientation


def warm_up(client: Client, node: NodeProcess, rate: float = 50.0, after: int = 10) -> dict:
    """
    Publish the rest poses at `rate` until tensions come back, then `after` more.

    A node's readers match our writers a little after our writers match its readers
    (wait_for_node sees only the latter); a pose sent in between may be lost, so these
    are the only poses a test may miss. What was received so far is then forgotten.

    :returns: the poses sent, as drive() returns them.
    """
    sent = {'fairlead/pose': [], 'bollard/pose': []}
    end = time.monotonic() + START_TIMEOUT
    remaining = after
    while remaining > 0:
        if time.monotonic() > end or node.process.poll() is not None:
            raise AssertionError(f'no tension came back:\n{node.text()}')
        stamp_ns = time.time_ns()
        sent['fairlead/pose'].append(recorded(client.pose(fairlead_motion(0.0), stamp_ns)))
        sent['bollard/pose'].append(recorded(client.pose((0.0, 0.0, 0.0), stamp_ns, 'bollard')))
        client.spin(1.0 / rate)
        remaining -= 1 if client.fairlead and client.bollard else 0
    client.clear()
    return sent


def drive(client: Client, seconds: float, rate: float = 50.0, bollard_every: int = 5) -> dict:
    """
    Publish the fairlead motion at `rate` (and a fixed bollard) on the wall clock.

    :returns: {'fairlead/pose': [...], 'bollard/pose': [...]} of recorded() poses.
    """
    def bollard(t):
        return (0.0, 0.0, 0.0) if round(t * rate) % bollard_every == 0 else None

    sent = {'fairlead/pose': [], 'bollard/pose': []}
    for pose in client.drive_wall(seconds, fairlead_motion, bollard, rate=rate):
        sent[f'{pose.stream}/pose'].append(recorded(pose))
    return sent


def force_values(msg) -> tuple:
    """Return a Wrench (rclpy or rosbags) as six floats."""
    return (msg.force.x, msg.force.y, msg.force.z, msg.torque.x, msg.torque.y, msg.torque.z)


def stamp_ns(msg) -> int:
    """Return the header stamp of a message (rclpy or rosbags) in ns."""
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


def pose_values(msg) -> tuple:
    """Return a PoseStamped (rclpy or rosbags) as it is compared with what was sent."""
    p, q = msg.pose.position, msg.pose.orientation
    return stamp_ns(msg), (p.x, p.y, p.z), (q.x, q.y, q.z, q.w)


def record_run(colcon_install, colcon_env, tmp_path, namespace: str, signum: int,
               seconds: float) -> dict:
    """Record `seconds` of motion with a fresh node, stop it with signum; return the run."""
    bag = tmp_path / 'bag'
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'node.log', namespace,
                       '-p', f'record_path:={bag}')
    client = Client(namespace, sim_time=False)
    try:
        client.wait_for_node(node)
        warmup = warm_up(client, node)
        sent = drive(client, seconds)
        if signum != signal.SIGKILL:
            client.spin(0.5)  # the last inputs arrive, their outputs come back
        code = node.stop(signum)
        return {'bag': bag, 'code': code, 'log': node.text(), 'warmup': warmup, 'sent': sent,
                'fairlead': [force_values(m) for _, m in client.fairlead],
                'bollard': [force_values(m) for _, m in client.bollard]}
    finally:
        if node.process.poll() is None:
            node.process.kill()
            node.process.wait()
        client.close()


def resolved(namespace: str) -> dict:
    return {relative: f'{namespace}/{relative}' for relative in TYPES}


def read_rosbags(bag: Path) -> dict:
    """Return {topic: [(log_time, message)]} as rosbags reads the bag (jazzy typestore)."""
    store = get_typestore(Stores.ROS2_JAZZY)
    messages = {}
    with Reader(bag) as reader:
        for connection in reader.connections:
            messages.setdefault(connection.topic, [])
        for connection, timestamp, data in reader.messages():
            messages[connection.topic].append(
                (timestamp, store.deserialize_cdr(data, connection.msgtype)))
    return messages


def assert_received_in_bag(received: list, recorded: list, what: str) -> None:
    """Every message received over DDS after the warm-up is in the bag, in order, no gaps."""
    assert received, f'no {what} received over DDS'
    n = len(received)
    assert any(recorded[start:start + n] == received
               for start in range(len(recorded) - n + 1)), what


def assert_inputs_in_bag(run: dict, topic: str, recorded: list) -> None:
    """
    Check that the bag holds every pose sent to `topic`, in order (as pose_values).

    Only the first poses of the warm-up may be missing: those the node's reader lost
    before it had matched our writer.
    """
    warmup, sent = run['warmup'][topic], run['sent'][topic]
    lost = len(warmup) + len(sent) - len(recorded)
    assert 0 <= lost < len(warmup), (
        f'{topic}: {len(recorded)} poses in the bag, {len(warmup)} + {len(sent)} sent')
    assert recorded == (warmup + sent)[lost:], topic


# ---------------------------------------------------------------------- Ctrl-C: the full run


@pytest.fixture(scope='module')
def sigint_run(colcon_install, colcon_env, tmp_path_factory):
    return record_run(colcon_install, colcon_env, tmp_path_factory.mktemp('sigint'),
                      '/rec_int', signal.SIGINT, 3.0)


def test_sigint_exits_cleanly_and_closes_the_bag(sigint_run):
    assert sigint_run['code'] == 0, sigint_run['log']
    assert 'Traceback' not in sigint_run['log']
    assert 'closed:' in sigint_run['log'] and ', 0 dropped' in sigint_run['log']
    bag = sigint_run['bag']
    assert sorted(os.listdir(bag)) == ['bag_0.mcap', 'metadata.yaml']
    assert bag_info(bag).complete


def test_sigint_bag_holds_what_crossed_dds(sigint_run):
    names = resolved('/rec_int')
    messages = read_rosbags(sigint_run['bag'])
    assert sorted(messages) == sorted(names.values())
    with Reader(sigint_run['bag']) as reader:
        assert {c.topic: c.msgtype for c in reader.connections} == {
            names[relative]: type_name for relative, type_name in TYPES.items()}

    for end in ('fairlead', 'bollard'):
        recorded = [force_values(m) for _, m in messages[names[f'{end}/tension']]]
        assert_received_in_bag(sigint_run[end], recorded, f'{end}/tension')
        assert_inputs_in_bag(sigint_run, f'{end}/pose',
                             [pose_values(m) for _, m in messages[names[f'{end}/pose']]])
    particles = [m for _, m in messages[names['rope/particles']]]
    assert len(particles) >= len(sigint_run['fairlead'])
    assert all(len(m.poses) == 21 for m in particles)


def test_sigint_bag_reads_with_mcap_ros2_and_times(sigint_run):
    names = resolved('/rec_int')
    decoded = {}
    for m in read_ros2_messages(str(sigint_run['bag'] / 'bag_0.mcap')):
        decoded.setdefault(m.channel.topic, []).append(m)
    recorded = [force_values(m.ros_msg) for m in decoded[names['fairlead/tension']]]
    assert_received_in_bag(sigint_run['fairlead'], recorded, 'fairlead/tension (mcap_ros2)')
    assert_inputs_in_bag(sigint_run, 'fairlead/pose',
                         [pose_values(m.ros_msg) for m in decoded[names['fairlead/pose']]])
    for topic in (names['fairlead/pose'], names['bollard/pose'], names['rope/particles']):
        for m in decoded[topic]:  # publish time = header stamp, log time = on receipt
            assert m.publish_time_ns == stamp_ns(m.ros_msg)
    for m in decoded[names['fairlead/pose']]:
        assert m.log_time_ns >= m.publish_time_ns
    for m in decoded[names['fairlead/tension']]:
        assert m.publish_time_ns == m.log_time_ns
    for topic, items in decoded.items():
        times = [m.log_time_ns for m in items]
        assert times == sorted(times), topic


def test_sigint_metadata_counts_agree(sigint_run):
    bag = sigint_run['bag']
    with open(bag / 'metadata.yaml', encoding='utf-8') as stream:
        on_disk = yaml.safe_load(stream)['rosbag2_bagfile_information']
    with open(bag / 'bag_0.mcap', 'rb') as stream:
        records = list(make_reader(stream).iter_metadata())
    # custom_data first (so a killed recording keeps it), the rosbag2 record at close
    assert [r.name for r in records] == ['rope_sim_ros.custom_data', 'rosbag2']
    embedded = yaml.safe_load(records[1].metadata['serialized_metadata'])
    assert records[0].metadata == embedded['custom_data']
    assert embedded == on_disk
    real = {topic: len(items) for topic, items in read_rosbags(bag).items()}
    counts = {t['topic_metadata']['name']: t['message_count']
              for t in on_disk['topics_with_message_count']}
    assert counts == real
    assert on_disk['message_count'] == sum(real.values())
    assert all(real.values())

    qos = {t['topic_metadata']['name']: t['topic_metadata']['offered_qos_profiles']
           for t in on_disk['topics_with_message_count']}
    names = resolved('/rec_int')
    tension = qos[names['fairlead/tension']]
    assert len(tension) == 1 and tension[0]['depth'] == 10
    assert tension[0]['reliability'] == 'reliable'
    assert qos[names['fairlead/pose']][0]['reliability'] == 'reliable'  # the client's


def test_node_bag_stores_parameters_and_rope_sim_reads_it(sigint_run, capsys):
    stored = stored_setup(sigint_run['bag'])
    assert stored.single
    line = stored.lines[0].params
    assert line.material == 'polyester' and line.segments == 20
    assert line.record_path == ''  # not stored: a re-run records nowhere by itself
    assert cli.main(['info', str(sigint_run['bag'])]) == 0
    out = capsys.readouterr().out
    for name in resolved('/rec_int').values():
        assert name in out
    assert 'peak fairlead tension' in out


def outputs_by_stamp(bag: Path, names: dict) -> dict:
    """Return {particles stamp [ns]: fairlead force (x, y, z)} of a bag's outputs."""
    messages = read_rosbags(bag)
    particles = messages[names['rope/particles']]
    tensions = messages[names['fairlead/tension']]
    assert len(particles) == len(tensions)  # published together, one of each per output
    return {stamp_ns(p): force_values(w)[:3] for (_, p), (_, w) in
            zip(particles, tensions)}


def test_resim_of_the_node_bag_gives_the_node_outputs(sigint_run, tmp_path):
    # `rope_sim resim` with the parameters stored in the bag: outputs fall on the same
    # stamps (every 1 / publish_rate from the first pose) with the same forces
    names = resolved('/rec_int')
    assert cli.main(['resim', str(sigint_run['bag']), '--out', str(tmp_path / 'resim')]) == 0
    live = outputs_by_stamp(sigint_run['bag'], names)
    offline = outputs_by_stamp(tmp_path / 'resim', names)
    # the node ran on after the last pose (the stream went quiet): compare up to it
    last_pose = sigint_run['sent']['fairlead/pose'][-1][0]
    stamps = sorted(t for t in live if t <= last_pose - 40_000_000)
    assert len(stamps) > 0.9 * 50 * 3.0, f'{len(stamps)} outputs in 3 s at 50 Hz'
    assert set(stamps) <= set(offline), sorted(set(stamps) - set(offline))[:5]
    difference = max(np.max(np.abs(np.subtract(live[t], offline[t]))) for t in stamps)
    scale = max(np.max(np.abs(live[t])) for t in stamps)
    print(f'node vs resim: {len(stamps)} outputs, largest difference {difference:.3g} N')
    # round-off: 1e-13 m of stretch is 1e-6 N on this line (EA / segment length 9e6 N/m)
    assert difference < 1e-6 * scale, f'node and resim differ by {difference:.3g} N'


# ------------------------------------------------------------------ SIGTERM and SIGKILL


def test_sigterm_gives_a_complete_bag(colcon_install, colcon_env, tmp_path):
    run = record_run(colcon_install, colcon_env, tmp_path, '/rec_term', signal.SIGTERM, 2.0)
    assert run['code'] == 0, run['log']
    assert 'Traceback' not in run['log']
    assert bag_info(run['bag']).complete
    names = resolved('/rec_term')
    messages = read_rosbags(run['bag'])
    recorded = [force_values(m) for _, m in messages[names['fairlead/tension']]]
    assert_received_in_bag(run['fairlead'], recorded, 'fairlead/tension')
    assert_inputs_in_bag(run, 'fairlead/pose',
                         [pose_values(m) for _, m in messages[names['fairlead/pose']]])


def test_sigkill_leaves_a_recoverable_bag(colcon_install, colcon_env, tmp_path):
    run = record_run(colcon_install, colcon_env, tmp_path, '/rec_kill', signal.SIGKILL, 3.0)
    assert run['code'] == -signal.SIGKILL
    bag = run['bag']
    assert not (bag / 'metadata.yaml').exists()
    assert not bag_info(bag).complete
    messages = list(read_messages(bag))
    assert messages
    by_topic = {}
    for message in messages:
        by_topic.setdefault(message.topic, []).append(message)
    names = resolved('/rec_kill')
    assert by_topic.get(names['fairlead/pose']) and by_topic.get(names['fairlead/tension'])
    for topic, items in by_topic.items():
        times = [m.log_time_ns for m in items]
        assert times == sorted(times), topic
        for item in items:
            msg = deserialize(item)
            if isinstance(msg, Wrench):
                assert all(map(math.isfinite, force_values(msg)))
            elif isinstance(msg, PoseStamped):
                assert all(map(math.isfinite, pose_values(msg)[1]))
            elif isinstance(msg, String):
                assert json.loads(msg.data)['event']
            elif isinstance(msg, Float64):  # a peak tension or the winch's length
                assert math.isfinite(msg.data) and msg.data >= 0.0
            elif isinstance(msg, Bool):
                assert msg.data is False  # the line never parts here
            else:
                assert all(math.isfinite(p.position.z) for p in msg.poses)
    # Chunks are flushed every second: after 3 s more than the first one is there.
    span = messages[-1].log_time_ns - messages[0].log_time_ns
    assert span > 0.5e9, f'only {span / 1e9:.2f} s readable'

    assert cli.main(['recover', str(bag)]) == 0
    with Reader(bag) as reader:
        assert reader.message_count == len(messages)
    assert bag_info(bag).complete
    # the node's parameters survive the kill, so resim and plot still know the line
    assert stored_setup(bag).lines[0].params.segments == 20


# ------------------------------------------------------------------- refusing to start


def test_refuses_an_existing_bag_and_an_unwritable_path(colcon_install, colcon_env,
                                                        tmp_path):
    existing = tmp_path / 'existing'
    existing.mkdir()
    (existing / 'metadata.yaml').write_text('rosbag2_bagfile_information: {}\n')
    (existing / 'existing_0.mcap').write_bytes(bytes(range(256)))
    before = {p.name: p.read_bytes() for p in existing.iterdir()}
    (tmp_path / 'a_file').write_text('not a directory\n')
    unwritable = tmp_path / 'a_file' / 'bag'

    nodes = [NodeProcess(colcon_install, colcon_env, tmp_path / f'{name}.log', f'/rec_{name}',
                         '-p', f'record_path:={path}')
             for name, path in (('existing', existing), ('unwritable', unwritable))]
    try:
        codes = [node.process.wait(START_TIMEOUT) for node in nodes]
    finally:
        for node in nodes:
            if node.process.poll() is None:
                node.process.kill()
                node.process.wait()
    logs = [node.text() for node in nodes]
    assert codes == [2, 2], logs
    for log, path, words in zip(logs, (existing, unwritable),
                                ('not overwriting', 'cannot create bag directory')):
        errors = [line for line in log.splitlines() if '[ERROR]' in line]
        assert len(errors) == 1, log
        assert str(path) in errors[0] and words in errors[0]
        assert 'Traceback' not in log
    assert {p.name: p.read_bytes() for p in existing.iterdir()} == before
    assert not unwritable.exists()


# ------------------------------------------------------- in process: encoding, disk errors


def test_encoders_match_rclpy_deserialisation():
    for frame_id in ('', 'w', 'world', 'ship_frame'):
        positions = np.cumsum(np.full((21, 3), 0.5), axis=0)
        particles = pose_array(positions, frame_id, 1_767_225_600_123_456_789)
        assert deserialize_message(rec.pose_array_cdr(particles), PoseArray) == particles
        pose = PoseStamped()
        pose.header.frame_id = frame_id
        pose.header.stamp.sec, pose.header.stamp.nanosec = 12, 345
        pose.pose.position.x, pose.pose.orientation.w = 1.5, 1.0
        assert deserialize_message(rec.pose_stamped_cdr(pose), PoseStamped) == pose
    force = wrench([1.0, -2.0, 3.0], [0.0, 0.5, 0.0])
    assert deserialize_message(rec.wrench_cdr(force), Wrench) == force
    assert deserialize_message(rec.pose_array_cdr(PoseArray()), PoseArray) == PoseArray()


class ListLogger:
    """Stands in for an rclpy logger."""

    def __init__(self):
        self.lines = []

    def info(self, text):
        self.lines.append(('INFO', text))

    def warning(self, text):
        self.lines.append(('WARN', text))

    def error(self, text):
        self.lines.append(('ERROR', text))

    def errors(self):
        return [text for level, text in self.lines if level == 'ERROR']


def _no_space(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_recorder_disk_error_stops_recording_once(tmp_path):
    logger = ListLogger()
    recorder = rec.Recorder(str(tmp_path / 'bag'), {}, logger, flush_interval=0.05)
    recorder.add_topic('fairlead/tension', '/ns/fairlead/tension', rec.WRENCH)
    for k in range(5):
        recorder.write('fairlead/tension', wrench([k, 0, 0], [0, 0, 0]), 1_000 + k)
    time.sleep(0.5)  # written out as a finished chunk
    recorder.writer._file.write = _no_space
    end = time.monotonic() + 10.0
    k = 5
    while recorder.recording and time.monotonic() < end:
        recorder.write('fairlead/tension', wrench([k, 0, 0], [0, 0, 0]), 1_000 + k)
        k += 1
        time.sleep(0.01)
    assert not recorder.recording
    for _ in range(10):  # later writes are no-ops: no exception, no new log line
        recorder.write('fairlead/tension', wrench([k, 0, 0], [0, 0, 0]), 2_000)
    assert len(logger.errors()) == 1
    assert 'No space left on device' in logger.errors()[0]
    assert 'the simulation goes on' in logger.errors()[0]
    assert recorder.close() is False
    assert 'rope_sim recover' in logger.errors()[-1]
    forces = [deserialize(m).force.x for m in read_messages(tmp_path / 'bag')]
    assert forces == [0.0, 1.0, 2.0, 3.0, 4.0]


def test_node_simulates_on_after_a_disk_error(tmp_path, capfd):
    from rope_sim_ros.messages.topics import LINE_NODE
    from rope_sim_ros.mooring.driver import SHIP
    from rope_sim_ros.ros.node import MooringNode
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = MooringNode(LINE_NODE, context=context, namespace='/rec_disk', parameter_overrides=[
        Parameter('record_path', value=str(tmp_path / 'bag'))])
    try:
        assert node.recorder is not None and node.recorder.recording

        def run(seconds, until_error=False):
            end = time.monotonic() + seconds
            while time.monotonic() < end:
                msg = PoseStamped()
                now_ns = node.get_clock().now().nanoseconds
                msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(now_ns, 10**9)
                msg.header.frame_id = 'world'
                msg.pose.position.x, msg.pose.position.z = FAIRLEAD[0], FAIRLEAD[2]
                msg.pose.orientation.w = 1.0
                node._on_pose(SHIP, msg)
                time.sleep(0.02)
                node._on_tick()
                if until_error and not node.recorder.recording:
                    return

        run(0.5)
        node.recorder.writer._file.write = _no_space
        run(5.0, until_error=True)
        assert not node.recorder.recording
        before = node.driver.time
        run(0.5)
        assert node.driver.time > before  # the rope goes on
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)
    err = capfd.readouterr().err
    assert err.count('the simulation goes on without recording') == 1, err
    assert 'No space left on device' in err
