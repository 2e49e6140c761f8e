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
CPU of one mooring_line node at 100 Hz: what each of a ship's single-line nodes costs.

Starts the colcon-installed node (<repo>/install: run `make build` first) with the
package's parameter file, 50 segments and publish_rate 100 Hz, in its own ROS domain, and
feeds it fairlead poses at 100 Hz (a 0.5 m, 0.16 Hz surge) for --seconds of wall time. Only
fairlead/tension is subscribed (a ship simulator taking the force), or with --every-output
every output. Prints the node process's CPU (user + system, /proc) over that time, one core
= 100 %, and the tensions received per second.

    python benchmarks/line_node_cpu.py [--seconds 15] [--every-output] [--repeat 3]
"""

import argparse
import math
import os
from pathlib import Path
import subprocess
import sys
import time

import rclpy
from rclpy.node import Node

REPO = Path(__file__).resolve().parent.parent
RATE = 100.0
# every output of a line without payload, with its message type
OUTPUTS = {'rope/particles': 'PoseArray', 'fairlead/tension': 'Wrench',
           'bollard/tension': 'Wrench', 'fairlead/peak_tension': 'Float64',
           'bollard/peak_tension': 'Float64', 'winch/length': 'Float64'}


def cpu_seconds(pid: int) -> float:
    """Return a process's user + system CPU seconds (/proc/<pid>/stat)."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def start_node() -> subprocess.Popen:
    """Start the installed mooring_line node at 100 Hz output, 50 segments."""
    install = REPO / 'install' / 'rope_sim_ros'
    executable = install / 'lib' / 'rope_sim_ros' / 'mooring_line'
    if not executable.is_file():
        raise SystemExit(f'{executable} not found: run `make build` first')
    env = dict(os.environ)
    env['AMENT_PREFIX_PATH'] = os.pathsep.join([str(install), sys.prefix])
    env['PYTHONPATH'] = str(install / 'lib' / f'python{sys.version_info[0]}.'
                            f'{sys.version_info[1]}' / 'site-packages')
    return subprocess.Popen(
        [str(executable), '--ros-args', '--params-file',
         str(install / 'share' / 'rope_sim_ros' / 'config' / 'mooring_line.yaml'),
         '-p', f'publish_rate:={RATE}', '-p', 'segments:=50'],
        env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL)


def run(seconds: float, every_output: bool) -> tuple:
    """Return the node's share of a core and the tensions received per second."""
    from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
    from std_msgs.msg import Float64
    classes = {'PoseArray': PoseArray, 'Wrench': Wrench, 'Float64': Float64}
    node = start_node()
    rclpy.init()
    client = Node('line_node_cpu')
    received = []
    client.create_subscription(Wrench, 'fairlead/tension', lambda msg: received.append(1), 1000)
    if every_output:
        for topic, type_name in OUTPUTS.items():
            if topic != 'fairlead/tension':
                client.create_subscription(classes[type_name], topic, lambda msg: None, 100,
                                           raw=True)
    publisher = client.create_publisher(PoseStamped, 'fairlead/pose', 1000)
    try:
        deadline = time.monotonic() + 120.0
        while publisher.get_subscription_count() == 0 or not client.count_publishers(
                'fairlead/tension'):
            if time.monotonic() > deadline or node.poll() is not None:
                raise SystemExit('the mooring_line node did not come up')
            rclpy.spin_once(client, timeout_sec=0.1)
        sent, start = 0, time.monotonic()
        while time.monotonic() - start < seconds + 1.0:
            t = sent / RATE
            if time.monotonic() - start >= t:
                if sent == RATE:  # one second in: the start is behind us
                    cpu, wall, first = cpu_seconds(node.pid), time.monotonic(), len(received)
                msg = PoseStamped()
                msg.header.frame_id = 'world'
                msg.header.stamp = client.get_clock().now().to_msg()
                msg.pose.position.x = 32.0 + 0.5 * math.sin(2.0 * math.pi * 0.16 * t)
                msg.pose.position.y, msg.pose.position.z = 12.0, 6.0
                msg.pose.orientation.w = 1.0
                publisher.publish(msg)
                sent += 1
            rclpy.spin_once(client, timeout_sec=0.001)
        used, wall = cpu_seconds(node.pid) - cpu, time.monotonic() - wall
        return used / wall, (len(received) - first) / wall
    finally:
        client.destroy_node()
        rclpy.try_shutdown()
        node.send_signal(2)
        node.wait(30)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--seconds', type=float, default=15.0)
    parser.add_argument('--every-output', action='store_true')
    parser.add_argument('--repeat', type=int, default=3)
    args = parser.parse_args()
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    taken = 'every output' if args.every_output else 'fairlead/tension only'
    for _ in range(args.repeat):
        share, tensions = run(args.seconds, args.every_output)
        print(f'mooring_line, 50 segments, 100 Hz poses and outputs, {taken} subscribed: '
              f'{100 * share:.1f} % of one core, {tensions:.1f} tensions a second received',
              flush=True)


if __name__ == '__main__':
    main()
