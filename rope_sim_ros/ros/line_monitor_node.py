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
A console view of one mooring line: one line per second on stdout.

Subscribes rope/particles, fairlead/tension and bollard/tension and prints the state time
(from the first particles message), both tensions, the largest strain of a segment (from
the particle spacing and the `length` parameter) and the real-time factor: how much state
time passed per second of wall time since the previous line.
"""

import math
import time

from geometry_msgs.msg import PoseArray, Wrench
import numpy as np
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import ParameterException
from rclpy.node import Node

from .spinning import run_node

NODE_NAME = 'line_monitor'
HEADER = f'{"t [s]":>8}  {"fairlead [N]":>12}  {"bollard [N]":>11}  {"max strain":>10}  {"RTF":>5}'


def norm(wrench: Wrench) -> float:
    """Return |force| of a Wrench [N]."""
    f = wrench.force
    return math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)


def max_strain(particles: PoseArray, length: float) -> float:
    """Return the largest segment strain: spacing / (length / segments) - 1."""
    x = np.array([[p.position.x, p.position.y, p.position.z] for p in particles.poses])
    if len(x) < 2:
        return math.nan
    spacing = np.linalg.norm(np.diff(x, axis=0), axis=1)
    return float(spacing.max() / (length / (len(x) - 1)) - 1.0)


def stamp_seconds(particles: PoseArray) -> float:
    """Return header.stamp in seconds."""
    return particles.header.stamp.sec + particles.header.stamp.nanosec * 1e-9


class LineMonitorNode(Node):
    """Prints a status line per `period` seconds of wall time."""

    def __init__(self):
        """Declare `length` and `period`, subscribe, and start the wall-clock timer."""
        super().__init__(NODE_NAME)
        self.length = self.declare_parameter(
            'length', 40.0, ParameterDescriptor(
                description='unstretched line length, for the strain [m]', read_only=True,
                floating_point_range=[FloatingPointRange(from_value=0.001, to_value=1e4)])
        ).value
        period = self.declare_parameter(
            'period', 1.0, ParameterDescriptor(
                description='seconds of wall time between lines [s]', read_only=True,
                floating_point_range=[FloatingPointRange(from_value=0.05, to_value=3600.0)])
        ).value
        self.particles = None
        self.tension = {'fairlead': None, 'bollard': None}
        self.first_stamp = None
        self.last = None  # (wall time, state time) of the previous line
        self.create_subscription(PoseArray, 'rope/particles', self._on_particles, 10)
        self.create_subscription(Wrench, 'fairlead/tension',
                                 lambda msg: self.tension.update(fairlead=msg), 10)
        self.create_subscription(Wrench, 'bollard/tension',
                                 lambda msg: self.tension.update(bollard=msg), 10)
        # wall time: a line per second even when the line follows a faster /clock
        self.timer = self.create_timer(period, self._on_tick,
                                       clock=Clock(clock_type=ClockType.STEADY_TIME))
        print(f'waiting for {self.resolve_topic_name("rope/particles")} ...', flush=True)

    def _on_particles(self, msg: PoseArray) -> None:
        if self.first_stamp is None:
            self.first_stamp = stamp_seconds(msg)
            print(HEADER, flush=True)
        self.particles = msg

    def _on_tick(self) -> None:
        if self.particles is None or None in self.tension.values():
            return
        wall, state = time.monotonic(), stamp_seconds(self.particles) - self.first_stamp
        rtf = '-' if self.last is None else f'{(state - self.last[1]) / (wall - self.last[0]):.2f}'
        self.last = (wall, state)
        print(f'{state:8.2f}  {norm(self.tension["fairlead"]):12.1f}  '
              f'{norm(self.tension["bollard"]):11.1f}  '
              f'{max_strain(self.particles, self.length) * 100:8.4f} %  {rtf:>5}', flush=True)


def main(args=None) -> int:
    """Run the monitor until Ctrl-C."""
    return run_node(LineMonitorNode, NODE_NAME, (ParameterException,), args)


if __name__ == '__main__':
    raise SystemExit(main())
