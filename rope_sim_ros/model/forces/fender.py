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
A fender on the quay and the hull side that pushes on it: compression, reaction, friction.

The hull a fender touches is the ship's side: a box of length L x beam B centred on the body
origin in plan, its vertical sides reaching from the keel (the draft T below the origin) up
without end. A fender is the centre P of its face, uncompressed, and the unit normal n out
of the quay toward the ship. The side it meets is the one whose outward normal s faces it
most (s . n most negative, among the box's four sides); along the fender's axis P + d n the
side's plane lies at d = (h - s . p) / (s . n) (h: half the length or beam, p: P in the box's
frame). d > 0 is a gap; d < 0 has pushed the face in: the compression is -d, the contact point
is P + d n, and it counts only if it lies on the side (within the box's other half width and
above the keel).

The reaction R(compression) follows the fender's curve as a manufacturer rates it (a table
from (0, 0), linear between its points, the last slope past them) and pushes the hull along
n at the contact point. The face's friction opposes the hull's sliding across it: mu R along
the sliding direction, regularised below FRICTION_SPEED (linear in the sliding speed there,
so that a ship at rest against a fender is held by a smooth force, as the seabed's friction
is). A fender has no damping and no hysteresis here.
"""

import numba
import numpy as np

from ..layout import (BODY_HULL, BODY_ORIGIN, BODY_POSITION, FENDER_CURVE_COMPRESSION,
                      FENDER_CURVE_REACTION, FENDER_FRICTION, FENDER_NORMAL, FENDER_POINTS,
                      FENDER_POSITION)

FRICTION_SPEED = 0.01  # [m/s]: the friction grows linearly with the sliding speed up to it


@numba.njit(cache=True)
def reaction(fender, compression):
    """Return the fender's reaction [N] at a compression [m] and its slope [N/m] (0 if none)."""
    if compression <= 0.0:
        return 0.0, 0.0
    n = int(fender[FENDER_POINTS])
    c0 = FENDER_CURVE_COMPRESSION
    r0 = FENDER_CURVE_REACTION
    for i in range(1, n):
        if compression <= fender[c0 + i] or i == n - 1:
            slope = (fender[r0 + i] - fender[r0 + i - 1]) / (fender[c0 + i] - fender[c0 + i - 1])
            return fender[r0 + i - 1] + slope * (compression - fender[c0 + i - 1]), slope
    return 0.0, 0.0


@numba.njit(cache=True)
def contact(fender, body, rotation, point):
    """
    Return how far the body's hull side compresses the fender [m] (<= 0: no contact).

    :param body: the body's row of the BODY table; rotation: its body-to-world matrix (3, 3).
    :param point: out (3,): the contact point in world coordinates (when there is contact).
    """
    # the fender's centre and normal in the hull box's frame (origin: the body origin)
    p = np.empty(3)
    for i in range(3):
        origin = body[BODY_POSITION + i]
        for j in range(3):
            origin += rotation[i, j] * body[BODY_ORIGIN + j]
        p[i] = fender[FENDER_POSITION + i] - origin
    pb = np.empty(3)
    nb = np.empty(3)
    for j in range(3):
        pb[j] = rotation[0, j] * p[0] + rotation[1, j] * p[1] + rotation[2, j] * p[2]
        nb[j] = (rotation[0, j] * fender[FENDER_NORMAL]
                 + rotation[1, j] * fender[FENDER_NORMAL + 1]
                 + rotation[2, j] * fender[FENDER_NORMAL + 2])
    # the side facing it: +-x (bow, stern) or +-y (port, starboard)
    axis = 0 if abs(nb[0]) > abs(nb[1]) else 1
    sign = -1.0 if nb[axis] > 0.0 else 1.0
    facing = sign * nb[axis]
    if facing > -1e-9:
        return 0.0
    half = 0.5 * body[BODY_HULL + axis]
    d = (half - sign * pb[axis]) / facing
    if d >= 0.0:
        return -d  # a gap
    other = 1 - axis
    across = pb[other] + d * nb[other]
    if abs(across) > 0.5 * body[BODY_HULL + other] or pb[2] + d * nb[2] < -body[BODY_HULL + 2]:
        return 0.0
    for i in range(3):
        point[i] = fender[FENDER_POSITION + i] + d * fender[FENDER_NORMAL + i]
    return -d


@numba.njit(cache=True)
def fender_force(fender, body, rotation, velocity, omega, force, point):
    """
    Put the fender's force on the hull into force (3,) and its point into point (3,).

    :param velocity, omega: the body's centre of gravity velocity and angular velocity.
    :returns: (compression [m], reaction [N], its slope [N/m], friction's sliding factor:
        mu R / FRICTION_SPEED while the hull slides slower than it, else 0) — the last two
        for the implicit step's Jacobian.
    """
    force[:] = 0.0
    compression = contact(fender, body, rotation, point)
    if compression <= 0.0:
        return compression, 0.0, 0.0, 0.0
    push, slope = reaction(fender, compression)
    normal = fender[FENDER_NORMAL:FENDER_NORMAL + 3]
    # the hull's velocity at the contact point, and its part across the face
    r0 = point[0] - body[BODY_POSITION]
    r1 = point[1] - body[BODY_POSITION + 1]
    r2 = point[2] - body[BODY_POSITION + 2]
    v0 = velocity[0] + omega[1] * r2 - omega[2] * r1
    v1 = velocity[1] + omega[2] * r0 - omega[0] * r2
    v2 = velocity[2] + omega[0] * r1 - omega[1] * r0
    along = v0 * normal[0] + v1 * normal[1] + v2 * normal[2]
    s0, s1, s2 = v0 - along * normal[0], v1 - along * normal[1], v2 - along * normal[2]
    sliding = np.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
    limit = fender[FENDER_FRICTION] * push
    factor = limit / max(sliding, FRICTION_SPEED)
    force[0] = push * normal[0] - factor * s0
    force[1] = push * normal[1] - factor * s1
    force[2] = push * normal[2] - factor * s2
    return compression, push, slope, factor if sliding < FRICTION_SPEED else 0.0
