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
An installed node fed poses at a steady rate, and its CPU: what the node benchmarks share.

The node runs from the colcon install (<repo>/install: `make build` first) in its own
process; its CPU is read from /proc, so the feeding process's own work is not counted.
"""

import os
from pathlib import Path
import subprocess
import sys
import time
from typing import Any, Callable, List, Sequence, Tuple

REPO = Path(__file__).resolve().parent.parent
INSTALL = REPO / 'install' / 'rope_sim_ros'


def start(executable: str, arguments: List[str]) -> subprocess.Popen:
    """
    Start an installed executable of the package, quiet, in this process's ROS domain.

    A domain of its own (ROS_DOMAIN_ID, unless one is set) and localhost discovery are put
    into this process's environment too, so that its client finds the node.
    """
    path = INSTALL / 'lib' / 'rope_sim_ros' / executable
    if not path.is_file():
        raise SystemExit(f'{path} not found: run `make build` first')
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    env = dict(os.environ)
    env['AMENT_PREFIX_PATH'] = os.pathsep.join([str(INSTALL), sys.prefix])
    env['PYTHONPATH'] = str(INSTALL / 'lib' / f'python{sys.version_info[0]}.'
                            f'{sys.version_info[1]}' / 'site-packages')
    return subprocess.Popen([str(path), *arguments], env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def cpu_seconds(pid: int) -> float:
    """Return a process's user + system CPU seconds (/proc/<pid>/stat)."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def feed(node: subprocess.Popen, output: str, output_type, pose_topic: str, seconds: float,
         rate: float, place: Callable, late_stamps: bool = False,
         also: Sequence[Tuple[str, Any]] = ()) -> dict:
    """
    Feed a started node PoseStamped at `rate` for `seconds` + 1 s of wall time; then stop it.

    A client node here subscribes to `output` (and, raw, to each (topic, type) of `also`),
    waits for the node, then publishes the poses on `pose_topic`. Each pose is where the
    motion is at its stamp, as a simulator sends the sample of its own time. With
    late_stamps it is where the motion was at its due time, stamped when sent, up to a
    millisecond or two later (this loop's own jitter): a sender that stamps at publish.
    That jitter is motion the lines feel: their ends jerk along the cubic through the
    samples, and the adaptive step follows each jerk with improved Euler. At the end the
    node gets SIGINT and is waited for.

    :param output: the node's output topic counted (its publisher shows the node is up).
    :param place: place(pose, t) sets a geometry_msgs/Pose for time t [s] from the first.
    :returns: over the last `seconds` (the first second is the node's start): 'cpu', the
        node's share of one core; 'outputs', `output` messages received a second; and
        'sent', poses.
    """
    import rclpy
    from geometry_msgs.msg import PoseStamped
    rclpy.init()
    client = rclpy.create_node('benchmark_feed')
    received = []
    client.create_subscription(output_type, output, lambda msg: received.append(1), 1000)
    for topic, cls in also:
        client.create_subscription(cls, topic, lambda msg: None, 100, raw=True)
    publisher = client.create_publisher(PoseStamped, pose_topic, 1000)
    try:
        deadline = time.monotonic() + 120.0
        while publisher.get_subscription_count() == 0 or not client.count_publishers(output):
            if time.monotonic() > deadline or node.poll() is not None:
                raise SystemExit(f'the node did not come up (no {output})')
            rclpy.spin_once(client, timeout_sec=0.1)
        sent, start, start_ns = 0, time.monotonic(), client.get_clock().now().nanoseconds
        while time.monotonic() - start < seconds + 1.0:
            t = sent / rate
            if time.monotonic() - start >= t:
                if sent == rate:  # one second in: the start is behind us
                    cpu, wall, first = cpu_seconds(node.pid), time.monotonic(), len(received)
                msg = PoseStamped()
                msg.header.frame_id = 'world'
                stamp = client.get_clock().now()
                msg.header.stamp = stamp.to_msg()
                place(msg.pose, t if late_stamps else (stamp.nanoseconds - start_ns) * 1e-9)
                publisher.publish(msg)
                sent += 1
            rclpy.spin_once(client, timeout_sec=0.001)
        cpu, wall = cpu_seconds(node.pid) - cpu, time.monotonic() - wall
        return {'cpu': cpu / wall, 'outputs': (len(received) - first) / wall, 'sent': sent}
    finally:
        client.destroy_node()
        rclpy.try_shutdown()
        node.send_signal(2)
        node.wait(30)
