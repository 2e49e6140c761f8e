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
The floor under the node benchmarks: a bare rclpy node doing the nodes' I/O and nothing else.

One PoseStamped subscription and one WrenchStamped (or Wrench) publisher, a wrench out per
pose in, spun as the nodes spin (rope_sim_ros/ros/spinning.py: the events executor), fed
100 Hz poses for --seconds by benchmarks/installed_node.py's feed, its CPU from /proc. What
the mooring node (arrangement_speed.py --node) and one mooring_line node (line_node_cpu.py)
cost beyond it is the simulation and the node's own rules; run them in the same session.

    python benchmarks/node_floor.py [--seconds 20] [--repeat 3] [--line]
"""

import argparse
import os
import subprocess
import sys

import installed_node

RATE = 100.0

# The bare node: ship/pose in, ship/mooring_wrench out (--line: fairlead/pose and a Wrench
# on fairlead/tension, as mooring_line).
FLOOR = """
import sys
import rclpy
from geometry_msgs.msg import PoseStamped, Wrench, WrenchStamped
from rope_sim_ros.ros.spinning import spin_until_shutdown
line = sys.argv[1] == 'line'
rclpy.init()
node = rclpy.create_node('floor')
if line:
    out = node.create_publisher(Wrench, 'fairlead/tension', 10)
    def on_pose(msg):
        wrench = Wrench()
        wrench.force.x = msg.pose.position.x
        out.publish(wrench)
else:
    out = node.create_publisher(WrenchStamped, 'ship/mooring_wrench', 10)
    def on_pose(msg):
        wrench = WrenchStamped()
        wrench.header = msg.header
        wrench.wrench.force.x = msg.pose.position.x
        out.publish(wrench)
node.create_subscription(PoseStamped, 'fairlead/pose' if line else 'ship/pose', on_pose, 1000)
spin_until_shutdown(node)
"""


def run(seconds: float, line: bool) -> dict:
    """Return the bare node's share of a core and its outputs received a second (feed's)."""
    from geometry_msgs.msg import Wrench, WrenchStamped
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    env = dict(os.environ, PYTHONPATH=str(installed_node.REPO))
    node = subprocess.Popen([sys.executable, '-c', FLOOR, 'line' if line else 'ship'], env=env,
                            stdin=subprocess.DEVNULL)
    output = 'fairlead/tension' if line else 'ship/mooring_wrench'
    return installed_node.feed(node, output, Wrench if line else WrenchStamped,
                               'fairlead/pose' if line else 'ship/pose', seconds, RATE, _place)


def _place(pose, t: float) -> None:
    """Set a geometry_msgs/Pose: the content does not matter to the floor."""
    pose.position.x = t
    pose.orientation.w = 1.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--seconds', type=float, default=20.0)
    parser.add_argument('--repeat', type=int, default=3)
    parser.add_argument('--line', action='store_true',
                        help="mooring_line's topics (fairlead/pose in, a Wrench out)")
    args = parser.parse_args()
    topics = 'fairlead/pose -> fairlead/tension' if args.line else \
        'ship/pose -> ship/mooring_wrench'
    for _ in range(args.repeat):
        result = run(args.seconds, args.line)
        print(f'floor: bare rclpy node, {topics}, one out per pose at {RATE:g} Hz: '
              f'{100 * result["cpu"]:.1f} % of one core, {result["outputs"]:.1f} outputs a '
              'second received', flush=True)


if __name__ == '__main__':
    main()
