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
Lines that part as they restart or as they are pulled apart, as the mooring_line node shows it.

Over real DDS from the colcon install, in sim time driven by the test: what the node
publishes (tensions, peaks, the parted flag) and what it logs.
"""

from node_harness import Client, NodeProcess
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import Bool, Float64

START = 7000 * 1_000_000_000  # [ns] sim time of the first pose
FAIRLEAD = np.array([36.0, 0.0, 8.0])
MBL = 1261568.0  # [N] the default line's (64 mm polyester)


@pytest.fixture
def line_node(colcon_install, colcon_env, tmp_path):
    """Start a mooring_line in sim time; yield (node, client, peaks, parted); stop both."""
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'restarts.log', '/restarts',
                       '-p', 'use_sim_time:=true')
    client = Client('/restarts')
    peaks, parted = [], []
    subscriptions = [client.node.create_subscription(
        Float64, f'{end}/peak_tension', lambda msg: peaks.append(msg.data), 2000)
        for end in ('fairlead', 'bollard')]
    subscriptions.append(client.node.create_subscription(
        Bool, 'rope/parted', lambda msg: parted.append(msg.data),
        QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)))
    try:
        client.wait_for_node(node)
        client.wait_for(lambda: all(s.get_publisher_count() for s in subscriptions), 30.0,
                        'the peak topics')
        client.drive(START - 500_000_000, 0.5, fairlead=None)
        yield node, client, peaks, parted
    finally:
        client.close()
        if node.process.poll() is None:
            node.interrupt()


def test_a_bollard_teleport_past_the_reach_parts_the_line_without_a_peak(line_node):
    # The bollard jumps 20 m off, 56.6 m from the fairlead: past the 50 m the 40 m line can
    # stretch to (issue: 4.4 MN on bollard/peak_tension, EA x max_strain, on a line that
    # never parted). It parts as it restarts; no number of the jump reaches an output.
    node, client, peaks, parted = line_node
    client.drive(START, 2.0, lambda t: FAIRLEAD,
                 bollard=lambda t: (None if t < 0.5 else [0.0, 0.0, 0.0] if t < 1.0
                                    else [-20.0, 0.0, 0.0]))
    client.wait_for(lambda: len(client.outputs()) >= 99, 30.0, 'the outputs')
    assert node.interrupt() == 0
    outputs = client.outputs()
    jump = next(k for k, (ns, _, _) in enumerate(outputs) if ns >= START + 960_000_000)
    before = max(max(f, b) for _, f, b in outputs[:jump])
    after = max(max(f, b) for _, f, b in outputs[jump + 1:])
    print(f'largest tension before the jump {before:.0f} N, after it {after:.0f} N; largest '
          f'peak {max(peaks):.0f} N')
    assert max(peaks) < 1.05 * before and after < before  # below the line at rest: ~1 kN
    assert parted == [False, True], parted
    text = node.text()
    assert 'bollard jumped 20.00 m' in text and 'parted at t = 0.960 s as it (re)started' in text
    assert 'inf m' not in text and 'back within reach' not in text, text


def test_a_line_pulled_apart_parts_without_reach_logs_after(line_node):
    # The fairlead runs off 26 m in 3 s: held at its reach the line pulls its break load and
    # parts. Then no "beyond its reach of inf m" nor "back within reach ... restarted" (the
    # issue's logs for a parted line).
    node, client, peaks, parted = line_node

    def fairlead(t):
        return FAIRLEAD + [26.0 * min(max(t - 0.5, 0.0) / 3.0, 1.0), 0.0, 0.0]

    client.drive(START, 5.0, fairlead)
    client.wait_for(lambda: len(client.outputs()) >= 249, 30.0, 'the outputs')
    assert node.interrupt() == 0
    text = node.text()
    assert parted == [False, True], parted
    assert len([line for line in text.splitlines() if 'the line parted at t' in line]) == 1
    assert 'inf m' not in text and 'back within reach' not in text, text
    assert max(peaks) < 1.5 * MBL  # what a segment pulls as it parts: its break load
