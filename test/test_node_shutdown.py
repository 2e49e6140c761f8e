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
The installed nodes end quietly, their bags complete, on two stopping signals in a row.

What `ros2 launch rope_sim_ros mooring.launch.py ship_motion:=true` and a Ctrl-C in its
terminal do: the terminal's SIGINT reaches the process group (launch and both nodes), then
launch sends its own to each node, milliseconds later (issue: a node aborted with
'terminate called after throwing an instance of pybind11::error_already_set ...
KeyboardInterrupt' in 2 of 7 tries). The window the second signal must not break is
test_spinning.py's; here the same through what colcon installs, the mooring node recording.
"""

import signal
import time

from node_harness import berth_file, Executable
import pytest
from rosbags.rosbag2 import Reader

GAP = 0.005  # [s] between the terminal's signal and launch's


@pytest.mark.parametrize('first, second', [(signal.SIGINT, signal.SIGINT),
                                           (signal.SIGTERM, signal.SIGTERM),
                                           (signal.SIGINT, signal.SIGTERM)],
                         ids=['ctrl-c twice', 'sigterm twice', 'ctrl-c then sigterm'])
def test_two_stopping_signals_end_the_launched_nodes_quietly_with_the_bag_complete(
        colcon_install, colcon_env, tmp_path, first, second):
    bag = tmp_path / 'bag'
    mooring = Executable(colcon_install, colcon_env, tmp_path / 'mooring.log', 'mooring',
                         '--ros-args', '--params-file', str(berth_file(tmp_path / 'berth.yaml')),
                         '-p', f'record_path:={bag}')
    motion = colcon_install / 'share' / 'rope_sim_ros' / 'config' / 'berth_motion.yaml'
    ship = Executable(colcon_install, colcon_env, tmp_path / 'ship_motion.log', 'ship_motion',
                      '--ros-args', '-r', 'fairlead/pose:=ship/pose', '--params-file',
                      str(motion))
    nodes = (mooring, ship)
    try:
        end = time.monotonic() + 90.0
        while 'first ship pose: lines started' not in mooring.text():
            assert time.monotonic() < end and all(n.process.poll() is None for n in nodes), \
                mooring.text() + ship.text()
            time.sleep(0.1)
        time.sleep(1.0)  # outputs flowing, recorded
        for node in nodes:
            node.process.send_signal(first)
        time.sleep(GAP)
        for node in nodes:
            node.process.send_signal(second)
        codes = [node.process.wait(30) for node in nodes]
    finally:
        for node in nodes:
            if node.process.poll() is None:
                node.process.kill()
    for node, code in zip(nodes, codes):
        text = node.text()
        assert code == 0, text
        assert 'Traceback' not in text and 'terminate called' not in text, text
    assert 'closed:' in mooring.text() and '0 dropped' in mooring.text(), mooring.text()
    with Reader(bag) as reader:  # complete: metadata.yaml and the summary, readable
        counts = {c.topic: c.msgcount for c in reader.connections}
    assert counts['/ship/pose'] > 10 and counts['/ship/mooring_wrench'] > 10, counts
