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
A moored ship's motions over a run, and the limits within which cargo can be worked.

The question a port engineer asks of a berth in swell, wind or a passing ship's wake: can
they work cargo? PIANC's working group on the movements of moored ships (PIANC 1995,
"Criteria for movements of moored ships in harbours: a practical guide", its table of
recommended motion criteria for safe working conditions) gives, per kind of ship and of
cargo handling, the largest motions in surge, sway, heave [m] and yaw, pitch, roll [deg]
at which handling goes on. They are peak-to-peak motions, except sway: zero to peak (off
the fenders). A dash in the table (no limit given) is None here.

The motions of a run, from its poses of the ship's origin (a free ship's output, or the
poses a ship simulator gave a driven ship):

- surge, sway, heave: the origin's displacement from its first pose, in the first pose's
  body axes (x forward, y to port, z up);
- roll, pitch, yaw: the z-y-x angles of the rotation from the first orientation;
- each motion's peak to peak: its largest value less its smallest over the run; sway's
  zero to peak: its largest distance from its mean.
"""

from dataclasses import dataclass
import math
from typing import Dict, Mapping, Optional, Tuple

import numpy as np

MOTIONS = ('surge', 'sway', 'heave', 'roll', 'pitch', 'yaw')
ANGULAR = ('roll', 'pitch', 'yaw')


@dataclass(frozen=True)
class MotionLimits:
    """
    One row of PIANC's table: a kind of ship and its cargo handling, and its limits.

    :ivar ship: the kind of ship; handling: its cargo handling.
    :ivar limits: surge, sway, heave [m], roll, pitch, yaw [rad]: peak to peak (sway: zero
        to peak); None where the table gives none.
    """

    ship: str
    handling: str
    limits: Mapping[str, Optional[float]]


def _row(ship: str, handling: str, surge, sway, heave, yaw, pitch, roll) -> MotionLimits:
    """Return a table row given as PIANC prints it: metres, then degrees (yaw, pitch, roll)."""
    degrees = {'yaw': yaw, 'pitch': pitch, 'roll': roll}
    limits = {'surge': surge, 'sway': sway, 'heave': heave}
    limits.update({name: None if value is None else math.radians(value)
                   for name, value in degrees.items()})
    return MotionLimits(ship, handling, {name: limits[name] for name in MOTIONS})


# PIANC (1995), recommended motion criteria for safe working conditions; the keys are the
# values of ship.motion_criteria
MOTION_CRITERIA: Dict[str, MotionLimits] = {
    'freighter_ships_gear': _row('freighter or coaster (< 10 000 DWT)', "ship's gear",
                                 1.0, 1.2, 0.6, 1.0, 1.0, 2.0),
    'freighter_quay_crane': _row('freighter or coaster (< 10 000 DWT)', 'quay crane',
                                 1.0, 1.2, 0.8, 2.0, 1.0, 3.0),
    'ro_ro_side_ramp': _row('ferry, ro-ro', 'side ramp', 0.6, 0.6, 0.6, 1.0, 1.0, 2.0),
    'ro_ro_linkspan': _row('ferry, ro-ro', 'linkspan', 0.4, 0.6, 0.8, 3.0, 2.0, 4.0),
    'general_cargo': _row('general cargo (5 000-10 000 DWT)', 'any',
                          2.0, 1.5, 1.0, 3.0, 2.0, 5.0),
    'container_full': _row('container ship', '100 % efficiency', 1.0, 0.6, 0.8, 1.0, 1.0, 3.0),
    'container_half': _row('container ship', '50 % efficiency', 2.0, 1.2, 1.2, 1.5, 2.0, 6.0),
    'bulk_cranes': _row('dry bulk carrier (30 000-150 000 DWT)', 'cranes',
                        2.0, 1.0, 1.0, 2.0, 2.0, 6.0),
    'bulk_elevator': _row('dry bulk carrier (30 000-150 000 DWT)', 'elevator, bucket-wheel',
                          1.0, 0.5, 1.0, 2.0, 2.0, 2.0),
    'bulk_conveyor': _row('dry bulk carrier (30 000-150 000 DWT)', 'conveyor belt',
                          5.0, 2.5, None, 3.0, None, None),
    'oil_tanker': _row('oil tanker', 'loading arms', 3.0, 3.0, None, None, None, None),
    'gas_tanker': _row('gas tanker', 'loading arms', 2.0, 2.0, None, 2.0, 2.0, 2.0),
}


def motion_series(positions: np.ndarray, orientations: np.ndarray) -> Dict[str, np.ndarray]:
    """
    Return the six motions of a ship's poses, one pose a row (module docstring).

    :param positions: (N, 3) its origin [m]; orientations: (N, 4) quaternions (x, y, z, w).
    :returns: surge, sway, heave [m], roll, pitch, yaw [rad], each (N,).
    """
    p = np.asarray(positions, dtype=float)
    q = np.asarray(orientations, dtype=float)
    q = q / np.linalg.norm(q, axis=1)[:, None]
    x0, y0, z0, w0 = q[0]
    start = np.array([
        [1.0 - 2.0 * (y0 * y0 + z0 * z0), 2.0 * (x0 * y0 - z0 * w0), 2.0 * (x0 * z0 + y0 * w0)],
        [2.0 * (x0 * y0 + z0 * w0), 1.0 - 2.0 * (x0 * x0 + z0 * z0), 2.0 * (y0 * z0 - x0 * w0)],
        [2.0 * (x0 * z0 - y0 * w0), 2.0 * (y0 * z0 + x0 * w0), 1.0 - 2.0 * (x0 * x0 + y0 * y0)]])
    body = (p - p[0]) @ start  # R0^T (p - p0), row by row
    # the relative rotation conj(q0) q, then its z-y-x angles
    x, y, z, w = q.T
    rw = w0 * w + x0 * x + y0 * y + z0 * z
    rx = w0 * x - x0 * w - y0 * z + z0 * y
    ry = w0 * y + x0 * z - y0 * w - z0 * x
    rz = w0 * z - x0 * y + y0 * x - z0 * w
    roll = np.arctan2(2.0 * (rw * rx + ry * rz), 1.0 - 2.0 * (rx * rx + ry * ry))
    pitch = np.arcsin(np.clip(2.0 * (rw * ry - rz * rx), -1.0, 1.0))
    yaw = np.arctan2(2.0 * (rw * rz + rx * ry), 1.0 - 2.0 * (ry * ry + rz * rz))
    return {'surge': body[:, 0], 'sway': body[:, 1], 'heave': body[:, 2], 'roll': roll,
            'pitch': pitch, 'yaw': yaw}


def motion_ranges(series: Mapping[str, np.ndarray]) -> Dict[str, float]:
    """Return each motion's peak to peak, sway's zero to peak (module docstring)."""
    ranges = {name: float(np.ptp(series[name])) for name in MOTIONS}
    sway = np.asarray(series['sway'])
    ranges['sway'] = float(np.max(np.abs(sway - sway.mean())))
    return ranges


def against_limits(ranges: Mapping[str, float],
                   criteria: MotionLimits) -> Tuple[Dict[str, Optional[float]], float]:
    """
    Return each motion's share of its limit (None: no limit), and the largest share.

    A share of 1 or more: cargo handling stops (a run without any limit gives 0).
    """
    shares = {name: None if criteria.limits[name] is None
              else ranges[name] / criteria.limits[name] for name in MOTIONS}
    return shares, max((s for s in shares.values() if s is not None), default=0.0)
