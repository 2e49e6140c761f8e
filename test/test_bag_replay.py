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
bag_replay + the installed mooring_line node (use_sim_time) re-run a recording.

The recording is made offline with ``rope_sim run --bag`` on a smooth 5 s surge after 1 s
at rest; the replayed fairlead tension, taken at the stamps of the node's rope/particles
published with it, must match the recorded one within 2 % NRMSE (RMS difference / RMS of
the recorded series minus its mean). Both sides use the same fixed time step.

The node starts on the first pose it receives. A loaded machine (CI) has lost the first
0.32 s of poses to discovery even after bag_replay saw the node's subscriptions: started
on a moving fairlead, the rope rings (1.6 NRMSE). The second of rest at the start and
bag_replay's --delay keep discovery out of the comparison.
"""

import csv
import math
import signal
import subprocess
import time

from geometry_msgs.msg import PoseArray, Wrench
import numpy as np
import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions

NAMESPACE = '/replay_test'
SECONDS = 6.0
REST = 1.0  # seconds at rest before the surge
TIME_STEP = 1.0 / 3200.0  # divides 10 ms: the runner's and the node's steps coincide
TIMEOUT = 60.0


def write_inputs(base):
    """Write a rest, then a smooth surge along the chord, and the parameters."""
    chord = np.array([36.0, 0.0, 8.0]) / math.hypot(36.0, 8.0)
    lines = ['t,fairlead_x,fairlead_y,fairlead_z']
    for k in range(int(SECONDS * 100) + 1):
        t = k * 0.01
        phase = max(0.0, t - REST) / (SECONDS - REST)
        point = np.array([36.0, 0.0, 8.0]) + chord * (1.0 - math.cos(2.0 * math.pi * phase)) / 2.0
        lines.append(f'{t:.2f},' + ','.join(repr(float(v)) for v in point))
    (base / 'motion.csv').write_text('\n'.join(lines) + '\n')
    # '/**': a plain 'mooring_line:' would not match the node in its test namespace.
    (base / 'params.yaml').write_text(
        f'/**:\n  ros__parameters:\n    time_step: {TIME_STEP!r}\n')


def run(command, env, log, **kwargs):
    with open(log, 'w') as f:
        return subprocess.Popen(command, env=env, stdin=subprocess.DEVNULL, stdout=f,
                                stderr=subprocess.STDOUT, **kwargs)


def stop(process, log):
    """SIGINT (Ctrl-C) a child and return its exit code."""
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        return process.wait(15)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
        raise AssertionError(f'{process.args[0]} ignored SIGINT:\n{log.read_text()}')


@pytest.fixture(scope='module')
def recording(colcon_install, colcon_env, tmp_path_factory):
    """Record the inputs once with `rope_sim run`: a folder with params.yaml, out.csv, the bag."""
    base = tmp_path_factory.mktemp('recording')
    write_inputs(base)
    result = subprocess.run(
        [str(colcon_install / 'lib' / 'rope_sim_ros' / 'rope_sim'), 'run', '--params',
         str(base / 'params.yaml'), '--motion', str(base / 'motion.csv'), '--out',
         str(base / 'out.csv'), '--bag', str(base / 'recorded')],
        env=colcon_env, capture_output=True, text=True, timeout=TIMEOUT)
    assert result.returncode == 0, result.stderr
    return base


def test_replay_through_the_node_reproduces_the_recorded_tension(
        colcon_install, colcon_env, recording, tmp_path):
    bin_dir = colcon_install / 'lib' / 'rope_sim_ros'
    params, bag = recording / 'params.yaml', recording / 'recorded'
    with open(recording / 'out.csv', newline='') as f:
        rows = list(csv.DictReader(f))
    t_ref = np.array([float(r['t']) for r in rows])
    tension_ref = np.array([float(r['fairlead_tension']) for r in rows])

    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    probe = rclpy.create_node('replay_probe', namespace=NAMESPACE, context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(probe)
    stamps, tensions = [], []
    subscriptions = [
        probe.create_subscription(
            PoseArray, 'rope/particles',
            lambda m: stamps.append(m.header.stamp.sec + m.header.stamp.nanosec * 1e-9), 1000),
        probe.create_subscription(
            Wrench, 'fairlead/tension',
            lambda m: tensions.append(math.sqrt(m.force.x ** 2 + m.force.y ** 2
                                                + m.force.z ** 2)), 1000),
    ]
    node_log, replay_log = tmp_path / 'node.log', tmp_path / 'replay.log'
    node = run([str(bin_dir / 'mooring_line'), '--ros-args', '--params-file', str(params),
                '-p', 'use_sim_time:=true', '-r', f'__ns:={NAMESPACE}'], colcon_env, node_log)
    replay = None
    try:
        end = time.monotonic() + TIMEOUT
        while not all(s.get_publisher_count() for s in subscriptions):
            assert node.poll() is None, node_log.read_text()
            assert time.monotonic() < end, 'the node did not come up:\n' + node_log.read_text()
            executor.spin_once(timeout_sec=0.05)
        replay = run([str(bin_dir / 'bag_replay'), str(bag), '--wait', '30', '--delay', '1',
                      '--ros-args',
                      '-r', f'/fairlead/pose:={NAMESPACE}/fairlead/pose'], colcon_env,
                     replay_log)
        end = time.monotonic() + SECONDS + TIMEOUT
        while replay.poll() is None:
            assert time.monotonic() < end, 'bag_replay did not finish:\n' + replay_log.read_text()
            executor.spin_once(timeout_sec=0.05)
        settle = time.monotonic() + 1.0
        while time.monotonic() < settle:
            executor.spin_once(timeout_sec=0.05)
        assert replay.returncode == 0, replay_log.read_text()
    finally:
        node_code = stop(node, node_log)
        if replay is not None and replay.poll() is None:
            stop(replay, replay_log)
        executor.shutdown()
        probe.destroy_node()
        rclpy.try_shutdown(context=context)
    assert node_code == 0, node_log.read_text()
    assert 'end of bag' in replay_log.read_text()
    # a clean replay: no silent stream, no clock trouble, no zero-stamp guess
    assert '[WARN]' not in node_log.read_text(), node_log.read_text()

    # One particles and one tension message per publish, in the same order.
    assert len(stamps) == len(tensions) >= 0.8 * SECONDS * 50, (len(stamps), len(tensions))
    t_node, tension_node = np.array(stamps), np.array(tensions)
    assert np.all(np.diff(t_node) > 0)
    assert t_node[0] < REST - 0.2, (f'the node started at {t_node[0]} s, not at rest:\n'
                                    f'{node_log.read_text()}')
    assert t_node[-1] > SECONDS - 0.5
    assert np.isfinite(tension_node).all()
    inside = (t_node >= t_ref[0]) & (t_node <= t_ref[-1])
    recorded = np.interp(t_node[inside], t_ref, tension_ref)
    rms_difference = np.sqrt(np.mean((tension_node[inside] - recorded) ** 2))
    nrmse = rms_difference / np.sqrt(np.mean((recorded - recorded.mean()) ** 2))
    print(f'replayed fairlead tension: NRMSE {nrmse:.2e} over {inside.sum()} samples')
    assert nrmse < 0.02, (f'NRMSE {nrmse:.4f}\n--- node ---\n{node_log.read_text()}'
                          f'--- bag_replay ---\n{replay_log.read_text()}')


@pytest.mark.parametrize('arguments, complaint', [
    (['--delay', '-1'], '--delay -1.0 must be >= 0 seconds'),
    (['--rate', '0'], '--rate 0.0 and --clock-rate 100.0 must be > 0'),
    # a recording holds the node's outputs: the peaks, the winch's length, parted too
    (['--topics', '/nowhere'], 'has no topic /nowhere; it has /bollard/peak_tension, '
     '/bollard/tension, /fairlead/peak_tension, /fairlead/pose'),
])
def test_bad_arguments_are_named_with_exit_code_2(
        colcon_install, colcon_env, recording, arguments, complaint):
    bin_dir = colcon_install / 'lib' / 'rope_sim_ros'
    result = subprocess.run([str(bin_dir / 'bag_replay'), str(recording / 'recorded'), *arguments],
                            env=colcon_env, capture_output=True, text=True, timeout=TIMEOUT)
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith('bag_replay: error: ') and complaint in result.stderr
    assert 'Traceback' not in result.stderr
