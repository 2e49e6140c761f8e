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
A real recorder process killed with SIGKILL, and one stopped with Ctrl-C (SIGINT).

The child records one Wrench every 5 ms with log time = wall clock, as the node does.
After SIGKILL everything older than the chunk flush interval must be readable; after
SIGINT the child closes its writer in the KeyboardInterrupt handler and the bag must be
complete and agree with what the child says it wrote.
"""

import os
import signal
import subprocess
import sys
import time

from geometry_msgs.msg import Wrench
from rclpy.serialization import deserialize_message
from rope_sim_ros.bag import bag_info, BagWriter, read_messages, recover
from rosbags.rosbag2 import Reader
from rosbags.typesys import get_typestore, Stores
import yaml

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOPIC = '/mooring_line/fairlead/tension'
PERIOD = 0.005
# Scheduling slack on a loaded two-core machine on top of the flush interval.
SLACK = 0.35

CHILD = """
import signal
import sys
import time

from rope_sim_ros.bag import BagWriter, cdr

signal.signal(signal.SIGINT, signal.default_int_handler)
bag = BagWriter(sys.argv[1])
bag.add_topic('{topic}', 'geometry_msgs/msg/Wrench')
print('recording', flush=True)
k = 0
try:
    while True:
        message = cdr.wrench((float(k), 0.0, 0.0), (0.0, 0.0, 0.0))
        # Ctrl-C between the write and the count would make them disagree by one
        signal.pthread_sigmask(signal.SIG_BLOCK, {{signal.SIGINT}})
        bag.write('{topic}', message, time.time_ns())
        k += 1
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {{signal.SIGINT}})
        time.sleep({period})
except KeyboardInterrupt:
    bag.close()
    print('closed', k, bag.dropped, flush=True)
""".format(topic=TOPIC, period=PERIOD)


def start_recorder(path):
    env = dict(os.environ)
    env['PYTHONPATH'] = os.pathsep.join([REPO_ROOT] + [
        p for p in env.get('PYTHONPATH', '').split(os.pathsep) if p])
    env['PYTHONDONTWRITEBYTECODE'] = '1'
    child = subprocess.Popen(
        [sys.executable, '-c', CHILD, str(path)], env=env, stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = child.stdout.readline()
    if line.strip() != 'recording':
        child.kill()
        raise AssertionError(f'recorder did not start: {line!r} {child.stderr.read()}')
    return child, time.time_ns()


def forces(records):
    return [deserialize_message(r.data, Wrench).force.x for r in records]


def test_sigkill_leaves_everything_older_than_the_flush_interval(tmp_path):
    path = tmp_path / 'killed'
    child, started_ns = start_recorder(path)
    try:
        time.sleep(2.0)
        killed_ns = time.time_ns()
        child.send_signal(signal.SIGKILL)
        assert child.wait(10) == -signal.SIGKILL
    finally:
        child.kill()
        child.stdout.close()
        child.stderr.close()
    assert not (path / 'metadata.yaml').exists()

    records = list(read_messages(path))
    print(f'{len(records)} messages readable, the last '
          f'{(killed_ns - records[-1].log_time_ns) / 1e9:.3f} s before the kill')
    # Messages 0..n-1, in order, with their values: no gap, nothing half-written.
    assert forces(records) == [float(k) for k in range(len(records))]
    assert records[0].log_time_ns >= started_ns - 10**9
    flushed_until = killed_ns - int((BagWriter.DEFAULT_FLUSH_INTERVAL + SLACK) * 1e9)
    assert records[-1].log_time_ns >= flushed_until
    # At 200 Hz for 2 s, at least the first (2 - 1 - slack) s are there.
    assert len(records) >= int((2.0 - BagWriter.DEFAULT_FLUSH_INTERVAL - SLACK) / PERIOD / 2)
    info = bag_info(path)
    assert (info.complete, info.message_count) == (False, len(records))

    assert recover(path) == len(records)
    with Reader(path) as reader:
        assert reader.message_count == len(records)


def test_sigint_closes_a_complete_bag(tmp_path):
    path = tmp_path / 'interrupted'
    child, _ = start_recorder(path)
    try:
        time.sleep(1.0)
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=20)
    finally:
        child.kill()
    assert child.returncode == 0, err
    word, written, dropped = out.split()
    assert (word, int(dropped)) == ('closed', 0)
    written = int(written)
    assert written > 50

    with open(path / 'metadata.yaml', encoding='utf-8') as stream:
        info = yaml.safe_load(stream)['rosbag2_bagfile_information']
    assert info['message_count'] == written
    assert info['topics_with_message_count'][0]['message_count'] == written
    store = get_typestore(Stores.ROS2_JAZZY)
    with Reader(path) as reader:
        assert reader.message_count == written
        values = [store.deserialize_cdr(data, c.msgtype).force.x
                  for c, _, data in reader.messages()]
        assert reader.duration == info['duration']['nanoseconds'] + 1
    assert values == [float(k) for k in range(written)]
    assert bag_info(path).complete is True
