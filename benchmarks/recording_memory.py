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
The memory of a recording mooring node over a simulated hour: whether it grows.

Starts the colcon-installed mooring node with config/berth.yaml (eight lines, 50 Hz),
use_sim_time and record_path in a new temporary directory, and drives it in sim time: /clock
and the ship's pose (a slow surge and sway about its berth) at 50 Hz of simulated time, as
fast as the node keeps up (never more than --ahead simulated seconds ahead of the last
ship/mooring_wrench it published). Every simulated minute it prints the node's resident
memory (VmRSS of its process), and at the end its growth per simulated hour, fitted from the
second minute on (the first holds the start-up's allocations). Not a test: it takes about
as long as the node needs to simulate and record the hour (--minutes shortens it).

    python benchmarks/recording_memory.py [--minutes 60] [--no-record] [--install install]

Before the MCAP chunk indices were packed and the node's chunks cut by time (bag/storage.py,
ros/recorder.py), the node grew by about 1 MB a simulated minute while recording; see the
numbers this prints.
"""

import argparse
import math
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import tempfile
import time

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

RATE = 50.0  # [Hz] poses and /clock per simulated second
START = 1000 * 1_000_000_000  # [ns] sim time of the first pose
REST = (0.0, -17.6, 0.0)  # the berth's ship at rest


def rss_mb(pid: int) -> float:
    """Return a process's resident memory [MB] (Linux /proc)."""
    with open(f'/proc/{pid}/status') as f:
        for line in f:
            if line.startswith('VmRSS:'):
                return int(line.split()[1]) / 1024.0
    raise RuntimeError(f'no VmRSS for {pid}')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--minutes', type=float, default=60.0, help='simulated minutes')
    parser.add_argument('--no-record', action='store_true', help='the same run unrecorded')
    parser.add_argument('--install', default=str(REPO / 'install'),
                        help='the colcon install base (make build)')
    parser.add_argument('--ahead', type=float, default=1.0,
                        help='simulated seconds the poses may lead the outputs')
    args = parser.parse_args()

    from rope_sim_ros.offline.demo import overlay_environment
    prefix = Path(args.install) / 'rope_sim_ros'
    executable = prefix / 'lib' / 'rope_sim_ros' / 'mooring'
    if not executable.exists():
        print(f'{executable} is missing: run make build first', file=sys.stderr)
        return 2
    env = overlay_environment(prefix)
    os.environ.update({k: env[k] for k in ('ROS_DOMAIN_ID', 'ROS_AUTOMATIC_DISCOVERY_RANGE')})

    import rclpy
    from geometry_msgs.msg import PoseStamped, WrenchStamped
    from rosgraph_msgs.msg import Clock

    folder = Path(tempfile.mkdtemp(prefix='recording_memory_'))
    command = [str(executable), '--ros-args', '--params-file',
               str(REPO / 'config' / 'berth.yaml'), '-p', 'use_sim_time:=true']
    if not args.no_record:
        command += ['-p', f'record_path:={folder / "bag"}']
    log = open(folder / 'mooring.log', 'w')
    node_process = subprocess.Popen(command, env=env, stdin=subprocess.DEVNULL, stdout=log,
                                    stderr=subprocess.STDOUT)
    rclpy.init()
    node = rclpy.create_node('recording_memory')
    pose_pub = node.create_publisher(PoseStamped, 'ship/pose', 1000)
    clock_pub = node.create_publisher(Clock, '/clock', 10)
    last = [0]

    def took(msg):
        last[0] = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec

    wrench = node.create_subscription(WrenchStamped, 'ship/mooring_wrench', took, 100)
    rows = []
    try:
        deadline = time.monotonic() + 120.0
        while not (pose_pub.get_subscription_count() and clock_pub.get_subscription_count()
                   and wrench.get_publisher_count()):
            if time.monotonic() > deadline or node_process.poll() is not None:
                raise RuntimeError(f'the node did not come up; see {folder / "mooring.log"}')
            rclpy.spin_once(node, timeout_sec=0.1)
        time.sleep(1.0)  # DDS matches the subscriber's side last
        print(f'{"sim min":>7} {"wall s":>8} {"RSS MB":>8}   '
              f'({"recording to " + str(folder / "bag") if not args.no_record else "no bag"})')
        wall = time.monotonic()
        steps = round(args.minutes * 60.0 * RATE)
        for k in range(steps + 1):
            ns = START + round(k * 1e9 / RATE)
            while ns - last[0] > args.ahead * 1e9 and k > RATE:  # wait for the node
                rclpy.spin_once(node, timeout_sec=0.01)
                if node_process.poll() is not None:
                    raise RuntimeError(f'the node exited; see {folder / "mooring.log"}')
            t = k / RATE
            clock = Clock()
            clock.clock.sec, clock.clock.nanosec = divmod(ns, 1_000_000_000)
            clock_pub.publish(clock)
            msg = PoseStamped()
            msg.header.frame_id = 'world'
            msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(ns, 1_000_000_000)
            msg.pose.position.x = REST[0] + 0.3 * math.sin(2 * math.pi * t / 60.0)
            msg.pose.position.y = REST[1] - 0.2 * (1 - math.cos(2 * math.pi * t / 90.0))
            msg.pose.orientation.w = 1.0
            pose_pub.publish(msg)
            rclpy.spin_once(node, timeout_sec=0.0)
            if k % round(60 * RATE) == 0:
                rows.append((t / 60.0, time.monotonic() - wall, rss_mb(node_process.pid)))
                print(f'{rows[-1][0]:7.0f} {rows[-1][1]:8.1f} {rows[-1][2]:8.1f}', flush=True)
    finally:
        if node_process.poll() is None:
            node_process.send_signal(signal.SIGINT)
            node_process.wait(60)
        node.destroy_node()
        rclpy.try_shutdown()
        log.close()
    fitted = [(m, r) for m, _, r in rows if m >= 2.0]
    if len(fitted) >= 2:
        import numpy as np
        slope = np.polyfit([m for m, _ in fitted], [r for _, r in fitted], 1)[0]
        print(f'growth from minute 2 on: {slope * 1024:.0f} kB per simulated minute, '
              f'{slope * 60:.1f} MB per simulated hour')
    shutil.rmtree(folder, ignore_errors=True)
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
