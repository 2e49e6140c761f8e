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

    python benchmarks/line_node_cpu.py [--seconds 15] [--every-output] [--late-stamps]
        [--repeat 3]
"""

import argparse
import math

import installed_node

RATE = 100.0
# every output of a line without payload, with its message type
OUTPUTS = {'rope/particles': 'PoseArray', 'fairlead/tension': 'Wrench',
           'bollard/tension': 'Wrench', 'fairlead/peak_tension': 'Float64',
           'bollard/peak_tension': 'Float64', 'winch/length': 'Float64'}


def run(seconds: float, every_output: bool, late_stamps: bool = False) -> dict:
    """Return the node's share of a core and the tensions received a second (feed's)."""
    from geometry_msgs.msg import PoseArray, Wrench
    from std_msgs.msg import Float64
    classes = {'PoseArray': PoseArray, 'Wrench': Wrench, 'Float64': Float64}
    node = installed_node.start('mooring_line', [
        '--ros-args', '--params-file',
        str(installed_node.INSTALL / 'share' / 'rope_sim_ros' / 'config' / 'mooring_line.yaml'),
        '-p', f'publish_rate:={RATE}', '-p', 'segments:=50'])
    also = [(topic, classes[type_name]) for topic, type_name in OUTPUTS.items()
            if every_output and topic != 'fairlead/tension']
    return installed_node.feed(node, 'fairlead/tension', Wrench, 'fairlead/pose', seconds,
                               RATE, _place_fairlead, late_stamps, also)


def _place_fairlead(pose, t: float) -> None:
    """Set a geometry_msgs/Pose to the fairlead at t [s]: a 0.5 m, 0.16 Hz surge."""
    pose.position.x = 32.0 + 0.5 * math.sin(2.0 * math.pi * 0.16 * t)
    pose.position.y, pose.position.z = 12.0, 6.0
    pose.orientation.w = 1.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--seconds', type=float, default=15.0)
    parser.add_argument('--every-output', action='store_true')
    parser.add_argument('--repeat', type=int, default=3)
    parser.add_argument('--late-stamps', action='store_true',
                        help='stamp each pose when sent, a millisecond or two after the time '
                        'it is the pose of (see benchmarks/installed_node.py feed)')
    args = parser.parse_args()
    taken = 'every output' if args.every_output else 'fairlead/tension only'
    stamps = ', stamped late' if args.late_stamps else ''
    for _ in range(args.repeat):
        result = run(args.seconds, args.every_output, args.late_stamps)
        print(f'mooring_line, 50 segments, 100 Hz poses{stamps} and outputs, {taken} subscribed: '
              f'{100 * result["cpu"]:.1f} % of one core, {result["outputs"]:.1f} tensions a '
              'second received', flush=True)


if __name__ == '__main__':
    main()
