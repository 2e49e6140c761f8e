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
The berth demo's ship and its instructor's table, beside a mooring node (`make demo`).

Publishes /clock and ship/pose (passing_ship.ship_pose: a passing ship's surge and sway)
in sim time running at --speed times the wall clock, so the mooring node (use_sim_time)
follows it, and prints one row per simulated second from what the node publishes: the
most loaded line, its tension and utilisation, and the total force of the lines on the ship
(ship/mooring_wrench, body frame). Ends by itself after --duration simulated seconds.

    python -m rope_sim_ros.ros.berth_demo_node --params config/berth.yaml [--speed 2]
"""

import argparse
import math
import sys
import time
from typing import Dict

from geometry_msgs.msg import PoseStamped, Wrench, WrenchStamped
import numpy as np
import rclpy
from rclpy.node import Node
from rosgraph_msgs.msg import Clock

from ..mooring.scenario import END, ship_pose, START
from ..params import arrangement
from ..params.materials import load_materials

START_TIMEOUT = 90.0  # [s] a first start compiles or loads the kernels


class BerthDemo(Node):
    """Drives the ship in sim time and prints the live table."""

    def __init__(self, setup: arrangement.ArrangementParams, rate: float):
        """Create the publishers and a subscription to every line's fairlead tension."""
        super().__init__('berth_demo')
        library = load_materials()
        self.names = setup.names
        self.mbl = {line.name: library.properties(line.params.material,
                                                  line.params.diameter).mbl
                    for line in setup.lines}
        self.rate = rate
        self.clock_pub = self.create_publisher(Clock, '/clock', 10)
        self.pose_pub = self.create_publisher(PoseStamped, 'ship/pose', 1000)
        self.tensions: Dict[str, float] = {}
        self.wrench = None
        self._subs = [self.create_subscription(
            Wrench, f'{name}/fairlead/tension', self._keeper(name), 100)
            for name in self.names]
        self._subs.append(self.create_subscription(
            WrenchStamped, 'ship/mooring_wrench', self._on_wrench, 100))

    def _keeper(self, name: str):
        def keep(msg: Wrench) -> None:
            f = msg.force
            self.tensions[name] = math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)
        return keep

    def _on_wrench(self, msg: WrenchStamped) -> None:
        self.wrench = msg.wrench

    def wait_for_mooring(self) -> bool:
        """Wait until the mooring node listens to ship/pose and publishes its wrench."""
        end = time.monotonic() + START_TIMEOUT
        while time.monotonic() < end:
            if (self.pose_pub.get_subscription_count() and self.clock_pub.get_subscription_count()
                    and self.count_publishers('ship/mooring_wrench')):
                return True
            rclpy.spin_once(self, timeout_sec=0.1)
        return False

    def publish(self, t: float) -> None:
        """Publish /clock and the ship pose at sim time t [s] (stamped t, from 1000 s)."""
        ns = round((1000.0 + t) * 1e9)
        sec, nanosec = divmod(ns, 1_000_000_000)
        clock = Clock()
        clock.clock.sec, clock.clock.nanosec = sec, nanosec
        self.clock_pub.publish(clock)
        position, orientation = ship_pose(t)
        msg = PoseStamped()
        msg.header.frame_id = 'world'
        msg.header.stamp.sec, msg.header.stamp.nanosec = sec, nanosec
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = position
        (msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z,
         msg.pose.orientation.w) = orientation
        self.pose_pub.publish(msg)

    def row(self, t: float) -> str:
        """Return the table row of sim time t from the newest outputs received."""
        if not self.tensions or self.wrench is None:
            return f'{t:7.0f}   (waiting for the first outputs)'
        name = max(self.tensions, key=lambda n: self.tensions[n] / self.mbl[n])
        tension = self.tensions[name]
        f = self.wrench.force
        event = 'passing ship' if START <= t <= END else ''
        share = 100 * tension / self.mbl[name]
        return (f'{t:7.0f}   {name:<12} {tension / 1e3:9.1f} {share:8.1f}   {f.x / 1e3:8.1f} '
                f'{f.y / 1e3:8.1f} {math.hypot(f.x, f.y) / 1e3:8.1f}   {event}')


HEADER = ('  t [s]   most loaded  T [kN]   % of MBL   Fx [kN]  Fy [kN]  |F| [kN]   '
          '(force of the lines on the ship, body frame)')


def main(argv=None) -> int:
    """Run the ship for --duration simulated seconds; 0 when the mooring node answered."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--params', required=True, help="the mooring node's parameter file")
    parser.add_argument('--speed', type=float, default=2.0, help='sim seconds per wall second')
    parser.add_argument('--duration', type=float, default=END + 8.0, help='sim seconds')
    parser.add_argument('--rate', type=float, default=20.0, help='ship poses per sim second')
    args = parser.parse_args(argv)
    setup = arrangement.read_arrangement_file(args.params)
    rclpy.init()
    node = BerthDemo(setup, args.rate)
    try:
        if not node.wait_for_mooring():
            print(f'berth demo: no mooring node within {START_TIMEOUT:g} s', file=sys.stderr)
            return 1
        print(HEADER, flush=True)
        start = time.monotonic()
        sent = 0
        next_row = 1.0
        while sent / args.rate <= args.duration:
            t = sent / args.rate
            if time.monotonic() - start >= t / args.speed:
                node.publish(t)
                sent += 1
                if t >= next_row:
                    print(node.row(t), flush=True)
                    next_row += 1.0
            rclpy.spin_once(node, timeout_sec=0.002)
        end = time.monotonic() + 0.5
        while time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=0.01)
        peaks = np.array([node.tensions.get(n, 0.0) for n in node.names])
        return 0 if peaks.any() else 1
    except KeyboardInterrupt:
        return 130
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    raise SystemExit(main())
