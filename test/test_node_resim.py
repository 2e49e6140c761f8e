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
`rope_sim resim` of a node's bag gives the node's own outputs: forces and torques.

The installed node records in sim time (the test publishes /clock and the poses); its bag
is re-simulated with the parameters it stored. The node and the re-simulation share the
input and output rules (line_driver), and the node records its clock-driven decisions
(rope/events), so they agree to round-off under a fairlead offset and a rolling ship, and
across a gap in the poses followed by a jump, a skip ahead and a reset; a line ending in a
free payload publishes and records payload/pose.
"""

import json
import math

from geometry_msgs.msg import PoseStamped
from node_harness import Client, NodeProcess
import numpy as np
from rope_sim_ros.bag import read_messages
from rope_sim_ros.bag.cdr import (decode_pose_array, decode_pose_stamped, decode_string,
                                  decode_wrench)
from rope_sim_ros.offline import cli
from std_srvs.srv import Trigger

START = 3000 * 1_000_000_000  # [ns] sim time of the first pose
FAIRLEAD = np.array([34.0, 4.0, 7.0])
OFFSET = [2.0, 1.0, 3.0]  # fairlead point in the ship frame [m]


def ship(t: float) -> tuple:
    """Return the pose origin and orientation of a surging ship rolling 0.2 rad."""
    roll = 0.2 * math.sin(2.0 * math.pi * t / 3.0)
    position = FAIRLEAD - OFFSET + [0.4 * math.sin(2.0 * math.pi * t / 5.0), 0.0, 0.0]
    return position, (math.sin(roll / 2.0), 0.0, 0.0, math.cos(roll / 2.0))


def outputs(bag, namespace: str) -> list:
    """Return [(stamp, fairlead force + torque, bollard force + torque)] in recorded order."""
    topics = [f'{namespace}/{name}' for name in (
        'rope/particles', 'fairlead/tension', 'bollard/tension')]
    rows, row = [], None
    for m in read_messages(bag, topics):
        if m.topic == topics[0]:
            sec, nanosec = decode_pose_array(m.data)[:2]
            row = [sec * 1_000_000_000 + nanosec]
            rows.append(row)
        else:
            row.append(np.concatenate(decode_wrench(m.data)))
    assert rows and all(len(r) == 3 for r in rows)
    return rows


def events(bag, namespace: str) -> list:
    return [json.loads(decode_string(m.data))['event']
            for m in read_messages(bag, [f'{namespace}/rope/events'])]


def record(colcon_install, colcon_env, tmp_path, namespace, drive, *ros_args):
    """Run a recording node in sim time, drive(client) it, stop it; return its bag."""
    bag = tmp_path / 'node_bag'
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'node.log', namespace,
                       '-p', 'use_sim_time:=true', '-p', f'record_path:={bag}',
                       '-p', f'fairlead_offset:={OFFSET}', *ros_args)
    client = Client(namespace)
    try:
        client.wait_for_node(node)
        # the clock; discovery settles meanwhile
        client.drive(START - 500_000_000, 0.5, fairlead=None)
        drive(client, node)
        assert node.interrupt() == 0, node.text()
    finally:
        client.close()
        node.interrupt()
    assert 'Traceback' not in node.text(), node.text()
    return bag, node


def compare(node_bag, tmp_path, namespace: str) -> tuple:
    """Re-simulate the node's bag; return (node rows, resim rows, largest relative differences)."""
    again = tmp_path / 'resim'
    assert cli.main(['resim', str(node_bag), '--out', str(again), '--quiet']) == 0
    live, offline = outputs(node_bag, namespace), outputs(again, namespace)
    assert [r[0] for r in live] == [r[0] for r in offline]
    live_numbers = np.array([np.concatenate(r[1:]) for r in live])
    offline_numbers = np.array([np.concatenate(r[1:]) for r in offline])
    difference = np.abs(live_numbers - offline_numbers)
    force_scale = np.abs(live_numbers[:, [0, 1, 2, 6, 7, 8]]).max()
    torque_scale = np.abs(live_numbers[:, [3, 4, 5, 9, 10, 11]]).max()
    force = difference[:, [0, 1, 2, 6, 7, 8]].max() / force_scale
    torque = difference[:, [3, 4, 5, 9, 10, 11]].max() / torque_scale
    print(f'{len(live)} outputs; node vs resim: force {force:.2e} of {force_scale:.0f} N, '
          f'torque {torque:.2e} of {torque_scale:.0f} N m')
    return live, offline, force, torque


def test_resim_of_a_rolling_ship_gives_the_node_forces_and_torques(
        colcon_install, colcon_env, tmp_path):
    def drive(client, node):
        client.drive(START, 4.0, ship)
        client.wait_for(lambda: len(client.outputs()) >= 199, 30.0, '199 outputs')

    bag, node = record(colcon_install, colcon_env, tmp_path, '/resim_roll', drive)
    live, _, force, torque = compare(bag, tmp_path, '/resim_roll')
    assert len(live) >= 199
    torques = np.array([r[1][3:] for r in live])
    assert np.abs(torques).max() > 500.0  # the offset and the roll make a real torque
    assert force < 1e-9 and torque < 1e-9, (force, torque)
    # the old rule (the lever of the newest pose, one ahead) is not what either publishes
    plain = tmp_path / 'plain'
    assert cli.main(['resim', str(bag), '--out', str(plain), '--quiet', '--rate', '50']) == 0
    plain_rows = {r[0]: r for r in outputs(plain, '/resim_roll')}
    same = [r for r in live if r[0] in plain_rows]
    assert len(same) > 0.9 * len(live)
    worst = max(np.abs(r[1] - plain_rows[r[0]][1]).max() for r in same)
    print(f'resim in stamp order (no events): largest fairlead difference {worst:.2e}')
    assert worst < 1e-6 * np.abs(torques).max()


def test_resim_reproduces_the_node_across_a_gap_a_jump_a_skip_and_a_reset(
        colcon_install, colcon_env, tmp_path):
    # Poses for 2 s, none for 1 s (the node takes the stream for silent and coasts), then
    # the ship 3.6 m away; poses to 4.5 s; then the clock jumps 2 s ahead with no pose (the
    # node skips ahead), poses again for 1 s, a ~/reset, 0.5 s more.
    def moved(t):
        position, orientation = ship(t)
        return position + [3.6, 0.0, 0.0], orientation

    def drive(client, node):
        client.drive(START, 2.0, ship)
        client.drive(START + 2_020_000_000, 0.98, fairlead=None)
        client.drive(START + 3_000_000_000, 1.5, lambda t: moved(3.0 + t))
        client.wait_for(lambda: client.outputs()[-1][0] >= START + 4_460_000_000, 30.0,
                        'the outputs up to 4.46 s')
        client.drive(START + 6_500_000_000, 1.0, lambda t: moved(6.5 + t))
        client.wait_for(lambda: client.outputs()[-1][0] >= START + 7_460_000_000, 30.0,
                        'the outputs up to 7.46 s')
        future = client.reset.call_async(Trigger.Request())
        client.wait_for(future.done, 10.0, 'the reset')
        assert future.result().success
        client.drive(START + 7_520_000_000, 0.5, lambda t: moved(7.52 + t))

    bag, node = record(colcon_install, colcon_env, tmp_path, '/resim_gap', drive)
    recorded = events(bag, '/resim_gap')
    assert {'silent', 'skip', 'reset'} <= set(recorded), (recorded, node.text())
    live, _, force, torque = compare(bag, tmp_path, '/resim_gap')
    assert len(live) > 300
    assert force < 1e-9 and torque < 1e-9, (force, torque)
    # Without the events (in stamp order, as a `rope_sim run` bag) resim cannot know when
    # the node went on without poses, nor where it skipped and reset: it differs.
    plain = tmp_path / 'plain'
    assert cli.main(['resim', str(bag), '--out', str(plain), '--quiet', '--rate', '50']) == 0
    plain_rows = {r[0]: r for r in outputs(plain, '/resim_gap')}
    worst = max(np.abs(r[1][:3] - plain_rows[r[0]][1][:3]).max()
                for r in live if r[0] in plain_rows)
    print(f'resim in stamp order (no events): largest fairlead force difference {worst:.0f} N')
    assert worst > 100.0


def test_a_payload_node_publishes_and_records_its_pose(colcon_install, colcon_env, tmp_path):
    # payload_mass 500 kg: the bollard end hangs free. The node ignores bollard/pose (one
    # warning) and publishes payload/pose at every output, which resim reproduces.
    received = []

    def drive(client, node):
        client.node.create_subscription(
            PoseStamped, 'payload/pose', lambda m: received.append(m), 1000)
        client.drive(START, 2.0, ship, bollard=lambda t: [0.0, 0.0, 0.0])
        client.wait_for(lambda: len(client.outputs()) >= 99 and len(received) >= 50, 30.0,
                        '99 outputs')

    bag, node = record(colcon_install, colcon_env, tmp_path, '/resim_payload', drive,
                       '-p', 'payload_mass:=500.0')
    warnings = [line for line in node.text().splitlines() if 'bollard/pose: ignored' in line]
    assert len(warnings) == 1, node.text()
    live, _, force, torque = compare(bag, tmp_path, '/resim_payload')
    assert force < 1e-9 and torque < 1e-9, (force, torque)
    poses = [decode_pose_stamped(m.data)
             for m in read_messages(bag, ['/resim_payload/payload/pose'])]
    assert [sec * 1_000_000_000 + nanosec for sec, nanosec, _, _, _ in poses] == [
        r[0] for r in live]
    particles = [decode_pose_array(m.data)[3]
                 for m in read_messages(bag, ['/resim_payload/rope/particles'])]
    for (_, _, frame, position, orientation), points in zip(poses, particles):
        assert frame == 'world' and np.array_equal(position, points[0, :3])
        assert np.array_equal(orientation, [0.0, 0.0, 0.0, 1.0])
    # it hangs about a line's length under the fairlead point
    assert np.allclose(poses[0][3], FAIRLEAD + [0.0, 0.0, -40.0], atol=0.2), poses[0][3]
    assert len(received) >= 50  # over DDS too (the first may come before discovery)
    again = [m.data for m in read_messages(tmp_path / 'resim', ['/resim_payload/payload/pose'])]
    assert again == [m.data for m in read_messages(bag, ['/resim_payload/payload/pose'])]
