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
When the nodes decide and publish, as a user sees it over DDS from the colcon install.

A steady pose stream is never taken for silent while ordinary `ros2 param` and `ros2 topic`
calls come and go and the node itself stalls; a real gap is. With use_sim_time and no
/clock the poses set the pace without a skip. Outputs that slower poses let through
together go out evenly. A bag logs on the clock the node runs on from its first message.
"""

import os
from pathlib import Path
import signal
import subprocess
import sys
import time

from geometry_msgs.msg import Wrench, WrenchStamped
from node_harness import bag_events, berth_file, Client, Executable, Keep, NodeProcess
import numpy as np
from rope_sim_ros.bag import read_messages
from rope_sim_ros.mooring.pacing import Pacer

REPO = Path(__file__).resolve().parent.parent
SECOND = 1_000_000_000
START = 3000 * SECOND  # [ns] sim time of the first pose
FAIRLEAD = np.array([36.0, 0.0, 8.0])  # the default line's fairlead, at rest

# What `ros2 param list`, `ros2 param get` and `ros2 topic echo --once` do: a new process
# with its own node (a new DDS participant), a few calls, gone.
POKE = """
import rclpy
from rcl_interfaces.srv import DescribeParameters, GetParameters, ListParameters
from geometry_msgs.msg import WrenchStamped
rclpy.init()
node = rclpy.create_node('_ros2cli_probe')
for srv, name, request in (
        (ListParameters, 'list_parameters', ListParameters.Request()),
        (GetParameters, 'get_parameters', GetParameters.Request(names=['publish_rate'])),
        (DescribeParameters, 'describe_parameters',
         DescribeParameters.Request(names=['head_1.length']))):
    client = node.create_client(srv, '/mooring/' + name)
    if client.wait_for_service(timeout_sec=5.0):
        future = client.call_async(request)
        rclpy.spin_until_future_complete(node, future, timeout_sec=5.0)
node.get_topic_names_and_types()
got = []
node.create_subscription(WrenchStamped, '/ship/mooring_wrench', got.append, 10)
end = node.get_clock().now().nanoseconds + 2_000_000_000
while not got and node.get_clock().now().nanoseconds < end:
    rclpy.spin_once(node, timeout_sec=0.1)
node.destroy_node()
rclpy.shutdown()
"""


def log_lines(node, word: str) -> list:
    return [line for line in node.text().splitlines() if word in line]


def test_a_steady_stream_is_never_silent_beside_calls_and_a_stall(
        colcon_install, colcon_env, tmp_path):
    # The berth's eight lines, 50 Hz ship poses on the wall clock for 15 s, recorded. From
    # 4 s to 11 s, every 1.5 s a process does what `ros2 param list/get/describe` and `ros2
    # topic echo --once` do (issue: 4-12 false `silent` events a minute, on a 3 s grid; and
    # 1-4 a minute with the ros2 daemon beside the node: 0.30-0.33 s without a pose taken
    # while DDS discovered a new participant); at 7 s the node is stopped for 0.4 s
    # (SIGSTOP: its timer late, its poses queued); at 12 s the poses stop for 0.9 s: the one
    # real silence. (test_pacing.py plays this with poses delivered 0.35 s late, twice.)
    bag = tmp_path / 'bag'
    node = Executable(colcon_install, colcon_env, tmp_path / 'mooring.log', 'mooring',
                      '--ros-args', '--params-file', str(berth_file(tmp_path / 'berth.yaml')),
                      '-p', f'record_path:={bag}')
    client = Client(node='mooring', poses=('ship',), sim_time=False,
                    keep={'wrenches': Keep('ship/mooring_wrench_world', WrenchStamped)})
    pokes = []

    def rest(t):
        return [0.0, -17.6, 0.0]

    try:
        client.wait_for_node(node)
        first = client.drive_wall(1.98, ship=rest)[0].made  # started, settled
        stopped = []

        def scenario(t):
            if t >= 2.0 and len(pokes) < (t - 2.0) / 1.5 and t < 9.0:
                pokes.append(subprocess.Popen([sys.executable, '-c', POKE], env=colcon_env,
                                              stdout=subprocess.DEVNULL,
                                              stderr=subprocess.DEVNULL))
            if 5.0 <= t and not stopped:
                os.kill(node.process.pid, signal.SIGSTOP)
                stopped.append(t)
            if 5.4 <= t and len(stopped) == 1:
                os.kill(node.process.pid, signal.SIGCONT)
                stopped.append(t)
            return not 10.0 <= t < 10.9  # the real gap

        sent = np.array([s.made for s in client.drive_wall(12.98, ship=rest, at=scenario)]) - first
        for poke in pokes:
            poke.wait(30)
        assert node.interrupt() == 0
    finally:
        client.close()
        for poke in pokes:
            if poke.poll() is None:
                poke.kill()
        if node.process.poll() is None:
            os.kill(node.process.pid, signal.SIGCONT)
            node.interrupt()
    # The gaps as made, [start, end] in simulated time (0: the first pose). A busy machine
    # may stall this process too (0.33 s once, in a pytest run beside other work): such a
    # gap is as real as the planned one, and the node may take the stream for silent in it
    # (less 50 ms: delivery may stretch a gap that much).
    gaps, live = np.diff(sent), Pacer.LIVE_INPUT - 0.05
    real = [(round(float(sent[k]), 3), round(float(sent[k + 1]), 3))
            for k in np.flatnonzero(gaps > live)]
    real.append((round(float(sent[-1]), 3), np.inf))  # the stream's end, before the Ctrl-C
    print(f'{len(pokes)} probes; gaps over {live} s as sent: {real}; the longest others: '
          f'{np.sort(gaps[gaps <= live])[-3:]}')
    assert len(pokes) == 5
    assert any(11.9 < start < 12.1 and 12.8 < end < 13.1 for start, end in real[:-1]), real
    silent = [e for e in bag_events(bag) if e['event'] == 'silent']
    warnings = log_lines(node, f'no new pose for {Pacer.LIVE_INPUT:g} s')
    # Silent only in a real gap (t: how far the ropes had gone when the node took it for
    # silent, at most a pose period past the last pose; on a busy machine up to a few pose
    # periods behind it: 0.061 s once, at load 5), and in the planned one.
    assert all(any(start - 0.1 < e['t'] < end + 0.05 for start, end in real)
               for e in silent), (silent, real)
    assert any(11.8 < e['t'] < 12.9 for e in silent), silent
    assert 1 <= len(warnings) <= len(silent) <= len(real), (silent, warnings, node.text())
    # No skip ahead, unless the machine itself stalled for about as long as a skip needs (a CI
    # run once stalled this process 1.0 s twice in a row, and the node 2.6 s: a skip is then
    # the right answer). A stall this process saw is a lower bound of the node's.
    stalled = sum(end - start for start, end in real[:-1] if not 11.9 < start < 12.1)
    assert stalled >= Pacer.MAX_LAG / 2 or 'skipped ahead' not in node.text(), stalled
    assert '[ERROR]' not in node.text()


def test_without_a_clock_the_poses_set_the_pace_without_a_skip(
        colcon_install, colcon_env, tmp_path):
    # use_sim_time and no /clock: no tick runs, each pose must take every output it lets
    # through. 20 Hz poses for 8 s of stamps, 50 Hz outputs (issue: a skip ahead every 4.8
    # s: 2 outputs a pose where 2.5 were due). Sent at 100 poses a wall second.
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'noclock.log', '/noclock',
                       '-p', 'use_sim_time:=true')
    client = Client('/noclock')
    try:
        client.wait_for_node(node)
        count = 161  # stamps 0 .. 8 s
        for k in range(count):
            client.pose(FAIRLEAD + [0.2 * np.sin(0.5 * k / 20.0), 0.0, 0.0],
                        START + k * 50_000_000)
            end = time.monotonic() + 0.01
            while time.monotonic() < end:
                client.spin_once()
        # one sample behind: outputs every 20 ms up to the second-newest pose, 7.95 s
        last = START + 20_000_000 * 397
        client.wait_for(lambda: any(ns == last for ns, _, _ in client.outputs()), 30.0,
                        'the outputs')
        assert node.interrupt() == 0
    finally:
        client.close()
        if node.process.poll() is None:
            node.interrupt()
    stamps = np.array([ns for ns, _, _ in client.outputs()])
    # every output from the first this subscriber got (the node may match it a few outputs
    # after it matched the node: DDS discovery is not symmetric) to the last, none skipped
    assert stamps[0] <= START + 1_000_000_000, stamps[0] - START
    assert np.array_equal(stamps, stamps[0] + 20_000_000 * np.arange(len(stamps))), \
        (len(stamps), np.diff(stamps).max())
    assert stamps[-1] == last
    assert 'skipped ahead' not in node.text(), node.text()
    assert log_lines(node, 'no /clock message has come'), node.text()


def test_outputs_between_slower_poses_go_out_evenly(colcon_install, colcon_env, tmp_path):
    # Wall clock, 20 Hz poses, publish_rate 50: each pose lets 2 or 3 outputs through at
    # once (issue: 41 % of the gaps under 5 ms). They go out near their own times.
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'even.log', '/even')
    client = Client('/even', poses=('fairlead',), sim_time=False,
                    keep={'tensions': Keep('fairlead/tension', Wrench)})
    try:
        client.wait_for_node(node)
        client.drive_wall(9.95, lambda t: FAIRLEAD, rate=20.0)
        stream_end = time.monotonic()
        client.spin(0.5)
        assert node.interrupt() == 0
    finally:
        client.close()
        if node.process.poll() is None:
            node.interrupt()
    arrivals = np.array([t for t, _ in client.tensions])
    # after the first pose and the lag window, while the poses came
    later = arrivals[(arrivals > arrivals[0] + 3.0) & (arrivals < stream_end)]
    gaps = np.diff(later)
    short = float(np.mean(gaps < 0.005))
    print(f'{len(arrivals)} outputs; after 3 s: gaps median {np.median(gaps) * 1e3:.1f} ms, '
          f'{100 * short:.1f} % under 5 ms, longest {gaps.max() * 1e3:.1f} ms')
    assert len(arrivals) > 9.0 * 50, len(arrivals)
    # the issue: 41 % under 5 ms; 0.3-0.6 % on a quiet machine, 17 % once on a busy one (a
    # node that stalls sends its overdue outputs at once)
    assert short < 0.25, short
    assert 0.015 < np.median(gaps) < 0.025, np.median(gaps)
    warnings = log_lines(node, '[WARN]')  # but the stream's end, taken for silence
    assert len(warnings) <= 1 and all('no new pose' in w for w in warnings), node.text()


def test_a_bag_logs_on_the_node_clock_from_its_first_message(
        colcon_install, colcon_env, tmp_path):
    # use_sim_time, recording. A parameter is set and the first pose comes before any
    # /clock (issue: one message logged at time 0, the rest from 1000 s): every message is
    # logged at or after the first pose's stamp, the first output's log time first.
    bag = tmp_path / 'bag'
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'bagtime.log', '/bagtime',
                       '-p', 'use_sim_time:=true', '-p', f'record_path:={bag}')
    client = Client('/bagtime')
    try:
        client.wait_for_node(node)
        assert client.set_parameter('axial_damping', 1000.0).successful
        client.pose(FAIRLEAD, START)  # before any /clock
        client.wait_for(lambda: len(client.outputs()) >= 1, 20.0, 'the first output')
        client.drive(START + 20_000_000, 1.0, lambda t: FAIRLEAD)
        client.wait_for(lambda: len(client.outputs()) >= 50, 20.0, 'the outputs')
        assert node.interrupt() == 0
    finally:
        client.close()
        if node.process.poll() is None:
            node.interrupt()
    messages = list(read_messages(bag))
    first = min(m.log_time_ns for m in messages)
    outputs = [m for m in messages if m.topic == '/bagtime/rope/particles']
    print(f'{len(messages)} messages, the first logged at {first / 1e9:.9f} s, the first '
          f'output at {outputs[0].log_time_ns / 1e9:.9f} s, stamped '
          f'{outputs[0].publish_time_ns / 1e9:.9f} s')
    assert outputs[0].publish_time_ns == START
    assert START <= first <= outputs[0].log_time_ns < START + 1_000_000
    assert [e['event'] for e in bag_events(bag)][:1] == ['set']
    # and on: every message no earlier than the node clock says
    assert max(m.log_time_ns for m in messages) < START + 2 * SECOND
