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
A driven ship's scripted track: config/berth.yaml's ship moved as a ship passing it might.

A pose track for a driven ship (ship_mode: driven) that loads the berth's lines, for the
driven runs of the study example (examples/study/passing_motions.py) and of the tests: a
ship passing close by first pushes the moored ship ahead, then, once abeam, sucks it off the
quay, then pulls it astern as it leaves. Scripted as the moored ship's motion (no ship
dynamics here): over DURATION s from START, a surge of one period ahead then astern of up to
SURGE, a sway off the quay of up to SWAY and a yaw of up to YAW, all fading in and out with
the passer's approach and departure. At rest the ship lies at REST heading along the quay
(config/berth.yaml). With the berth's lines this loads the springs to about 47 % of their
MBL, near their working load limit (50 %). A free ship moved by a passing ship's loads
(passing_ship.*) is the berth demo's (config/berth_demo.yaml).
"""

import math
from typing import List, Tuple

REST = (0.0, -17.6, 0.0)  # [m] the ship's origin at rest (config/berth.yaml)
START = 8.0  # [s] the passing ship's effect begins
DURATION = 60.0  # [s] and lasts this long
END = START + DURATION
SURGE = 0.4  # [m] ahead, then astern
SWAY = 0.6  # [m] off the quay (world -y)
YAW = 0.0005  # [rad] bow off, then in


def ship_pose(t: float) -> Tuple[List[float], List[float]]:
    """Return the moored ship's (position [m], quaternion (x, y, z, w)) at t [s]."""
    s = min(max((t - START) / DURATION, 0.0), 1.0)
    fade = math.sin(math.pi * s)
    surge = SURGE * math.sin(2.0 * math.pi * s) * fade
    sway = SWAY * fade * fade
    yaw = YAW * math.sin(2.0 * math.pi * s) * fade
    x, y, z = REST
    return ([x + surge, y - sway, z],
            [0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)])


def motion_rows(duration: float, rate: float) -> List[List[float]]:
    """Return rows t, x, y, z, qx, qy, qz, qw of the ship pose every 1 / rate s."""
    rows = []
    for i in range(int(round(duration * rate)) + 1):
        t = i / rate
        position, orientation = ship_pose(t)
        rows.append([t, *position, *orientation])
    return rows
