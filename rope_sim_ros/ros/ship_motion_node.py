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
A scripted ship for demos and test rigs: publishes fairlead/pose.

The ship oscillates around a mean position in surge, sway and heave (along its own axes,
turned by `heading` about z) and rolls about its x axis; every motion is a sine with its
own amplitude and period, faded in over `ramp_duration` so that the line is not jerked at
the start. The ship rests at the mean position until fairlead/pose has a subscriber, so the
line sees the whole ramp. Each pose is computed at its own stamp (the node clock): the
mooring_line node interpolates between stamps, so a pose computed at another time than its
stamp would shake the line.
"""

import math
import sys

from geometry_msgs.msg import PoseStamped
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.exceptions import ParameterException
from rclpy.node import Node

from .spinning import run_node

NODE_NAME = 'ship_motion'

# name: (default, unit, description, low, high)
PARAMETERS = {
    'mean_position': ([36.0, 0.0, 8.0], 'm', 'mean pose position in frame_id', None, None),
    'heading': (0.0, 'rad', 'yaw of the ship x axis (surge) from the frame x axis',
                -math.pi, math.pi),
    'surge_amplitude': (0.8, 'm', 'surge amplitude (along the ship x axis)', 0.0, 100.0),
    'surge_period': (10.0, 's', 'surge period', 0.1, 3600.0),
    'sway_amplitude': (0.4, 'm', 'sway amplitude (along the ship y axis)', 0.0, 100.0),
    'sway_period': (14.0, 's', 'sway period', 0.1, 3600.0),
    'heave_amplitude': (0.5, 'm', 'heave amplitude (along z)', 0.0, 100.0),
    'heave_period': (8.0, 's', 'heave period', 0.1, 3600.0),
    'roll_amplitude': (0.05, 'rad', 'roll amplitude (about the ship x axis)', 0.0, 1.0),
    'roll_period': (9.0, 's', 'roll period', 0.1, 3600.0),
    'ramp_duration': (10.0, 's', 'the motion fades in over this time (0 = at once)',
                      0.0, 3600.0),
    'publish_rate': (50.0, 'Hz', 'rate of fairlead/pose', 1.0, 1000.0),
    'frame_id': ('world', '', 'header.frame_id of the poses', None, None),
}


def ship_pose(t: float, p: dict) -> tuple:
    """
    Return (position [x, y, z], quaternion (x, y, z, w)) of the ship at time t [s].

    :param t: seconds since the start of the motion.
    :param p: parameter values by name (PARAMETERS).
    """
    ramp = p['ramp_duration']
    fade = 1.0 if t >= ramp else 0.5 * (1.0 - math.cos(math.pi * max(t, 0.0) / ramp))

    def wave(name):
        return fade * p[name + '_amplitude'] * math.sin(2.0 * math.pi * t / p[name + '_period'])

    surge, sway, heave, roll = wave('surge'), wave('sway'), wave('heave'), wave('roll')
    c, s = math.cos(p['heading']), math.sin(p['heading'])
    x0, y0, z0 = p['mean_position']
    position = [x0 + c * surge - s * sway, y0 + s * surge + c * sway, z0 + heave]
    # yaw (heading) then roll about the ship x axis: q = q_z(heading) * q_x(roll)
    cy, sy = math.cos(p['heading'] / 2.0), math.sin(p['heading'] / 2.0)
    cr, sr = math.cos(roll / 2.0), math.sin(roll / 2.0)
    return position, (cy * sr, sy * sr, sy * cr, cy * cr)


class ShipMotionNode(Node):
    """Publishes fairlead/pose for a ship oscillating around its mean position."""

    def __init__(self):
        """Declare the parameters (all read-only) and start publishing."""
        super().__init__(NODE_NAME)
        self.p = {}
        for name, (default, unit, description, low, high) in PARAMETERS.items():
            descriptor = ParameterDescriptor(
                description=description + (f' [{unit}]' if unit else ''), read_only=True)
            if low is not None:
                descriptor.floating_point_range = [
                    FloatingPointRange(from_value=low, to_value=high)]
            self.p[name] = self.declare_parameter(name, default, descriptor).value
        self.p['mean_position'] = [float(v) for v in self.p['mean_position']]
        if len(self.p['mean_position']) != 3:
            raise ParameterException('mean_position must be [x, y, z]', 'mean_position')
        self.publisher = self.create_publisher(PoseStamped, 'fairlead/pose', 10)
        self.start_ns = None
        self.timer = self.create_timer(1.0 / self.p['publish_rate'], self._on_tick)
        self.get_logger().info(
            f'ship around {self.p["mean_position"]}: surge {self.p["surge_amplitude"]:g} m, '
            f'sway {self.p["sway_amplitude"]:g} m, heave {self.p["heave_amplitude"]:g} m, '
            f'roll {self.p["roll_amplitude"]:g} rad; publishing on {self.publisher.topic_name}')

    def _on_tick(self) -> None:
        now = self.get_clock().now()
        if self.start_ns is None and self.publisher.get_subscription_count() > 0:
            self.start_ns = now.nanoseconds  # the motion starts when someone listens
        t = 0.0 if self.start_ns is None else (now.nanoseconds - self.start_ns) * 1e-9
        position, q = ship_pose(t, self.p)
        msg = PoseStamped()
        msg.header.stamp = now.to_msg()
        msg.header.frame_id = self.p['frame_id']
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = position
        (msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z,
         msg.pose.orientation.w) = q
        self.publisher.publish(msg)


USAGE = (
    'usage: ros2 run rope_sim_ros ship_motion [--ros-args -p NAME:=VALUE ...]\n\n'
    'A scripted ship: publishes fairlead/pose (PoseStamped) at publish_rate, oscillating '
    'around mean_position\nin surge, sway, heave and roll. Parameters (all read-only):\n'
    + ''.join(f'  {name}: {description} [{unit or "-"}], default {default}\n'
              for name, (default, unit, description, _, _) in PARAMETERS.items())
    + 'For the mooring node of config/berth.yaml, with the motions its lines hold (its own '
    'defaults part the\nspring lines within 30 s):\n'
    '  ros2 run rope_sim_ros ship_motion --ros-args -r fairlead/pose:=ship/pose --params-file '
    'config/berth_motion.yaml\n'
    'or ros2 launch rope_sim_ros mooring.launch.py ship_motion:=true\n')


def main(args=None) -> int:
    """Run the ship until Ctrl-C; exit code 2 when a parameter is not allowed."""
    argv = list(sys.argv if args is None else args)
    if any(arg in ('-h', '--help') for arg in
           (argv[:argv.index('--ros-args')] if '--ros-args' in argv else argv)[1:]):
        print(USAGE, end='')
        return 0
    return run_node(ShipMotionNode, NODE_NAME, (ParameterException,), args)


if __name__ == '__main__':
    raise SystemExit(main())
