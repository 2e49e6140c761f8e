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
Write the driven-ship motions of the study demo: the berth demo's passing ship, stronger or weaker.

The moored ship's scripted response to a passing ship (rope_sim_ros/mooring/scenario.py: a
surge ahead then astern, a sway off the quay and a yaw, fading in and out over 60 s from
8 s) with its surge, sway and yaw scaled by each INTENSITIES value, as passing_NNN.csv
(NNN: the scale in per cent) at RATE rows per second over DURATION s, in SHIP.csv form (t,
x, y, z, qx, qy, qz, qw). A stand-in for a passing ship's speed and separation until the
study varies those parameters themselves::

    python examples/study/passing_motions.py
"""

import csv
import math
import os

from rope_sim_ros.mooring import scenario

INTENSITIES = (0.50, 0.75, 1.00, 1.25, 1.50)
DURATION = 70.0  # [s]: the passing ship's 60 s from 8 s, and 2 s after
RATE = 5.0  # [rows/s]: the motion is smooth; the runs interpolate it (cubic)
HERE = os.path.dirname(os.path.abspath(__file__))


def scaled_pose(t: float, scale: float):
    """Return the ship's pose at t [s] with its excursion from rest scaled."""
    position, orientation = scenario.ship_pose(t)
    yaw = scale * 2.0 * math.atan2(orientation[2], orientation[3])
    moved = [rest + scale * (p - rest) for p, rest in zip(position, scenario.REST)]
    return moved, [0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)]


def main() -> None:
    """Write every passing_NNN.csv next to this script."""
    for scale in INTENSITIES:
        path = os.path.join(HERE, f'passing_{round(100 * scale):03d}.csv')
        with open(path, 'w', newline='') as stream:
            writer = csv.writer(stream, lineterminator='\n')
            writer.writerow(['t', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw'])
            for i in range(int(round(DURATION * RATE)) + 1):
                t = i / RATE
                position, orientation = scaled_pose(t, scale)
                writer.writerow([f'{t:g}'] + [f'{v:.9g}' for v in position + orientation])
        print(path)


if __name__ == '__main__':
    main()
