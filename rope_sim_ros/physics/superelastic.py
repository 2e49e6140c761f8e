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

"""The seed's cure for super-elasticity (section 1.2): position and velocity adjustment.

After a step, wherever a spring is stretched beyond its threshold, its two particles move
toward each other along the spring until the threshold length is restored (only the free one
moves where the other is a kinematic end), and their velocity components along the spring
are made equal, so the spring stops stretching.

Two departures from the paper's text, both to make it right: the velocity adjustment removes
the *relative* velocity along the spring (keeping the pair's mean), where the paper zeroes
both components, which would brake a line that is simply being towed; and the sweep repeats
(red-black Gauss-Seidel) until no spring is beyond its threshold, since restoring one spring
can over-stretch its neighbour.
"""

import numpy as np

# Springs of one colour share no particle, so each colour is corrected in one vector op.
MAX_SWEEPS = 1000
TOLERANCE = 1e-9


def _colours(count: int, stride: int) -> tuple:
    """Index sets of springs (i, i + stride) in which no two springs share a particle."""
    first = np.arange(count)
    block = (first // stride) % 2
    return first[block == 0], first[block == 1]


def _project(x, v, inv_mass, first, stride, limit):
    """Shorten over-long springs (first, first + stride) of one colour; return the worst."""
    a, b = first, first + stride
    d = x[b] - x[a]
    length = np.sqrt(np.einsum('ij,ij->i', d, d))
    over = length > limit * (1.0 + TOLERANCE)
    if not over.any():
        return 0.0
    a, b, d, length = a[over], b[over], d[over], length[over]
    wa, wb = inv_mass[a], inv_mass[b]
    total = wa + wb
    movable = total > 0.0
    a, b, d, length = a[movable], b[movable], d[movable], length[movable]
    wa, wb, total = wa[movable], wb[movable], total[movable]
    u = d / length[:, None]
    excess = (length - limit)[:, None] * u
    x[a] += (wa / total)[:, None] * excess
    x[b] -= (wb / total)[:, None] * excess
    closing = np.einsum('ij,ij->i', v[b] - v[a], u)[:, None] * u
    v[a] += (wa / total)[:, None] * closing
    v[b] -= (wb / total)[:, None] * closing
    return float(np.max(length / limit - 1.0)) if len(length) else 0.0


def adjust(x: np.ndarray, v: np.ndarray, inv_mass: np.ndarray, segment_length: float,
           max_strain: float) -> int:
    """Apply position and velocity adjustment in place to structural and bending springs.

    Args:
        x: positions (N+1, 3), modified in place.
        v: velocities (N+1, 3), modified in place.
        inv_mass: 1 for free particles, 0 for kinematic ends, shape (N+1,).
        segment_length: unstretched structural spring length l0 [m].
        max_strain: threshold; structural springs are limited to l0 (1 + max_strain), bending
            springs to 2 l0 (1 + max_strain).

    Returns:
        Number of sweeps that moved something (0 when no spring was over its threshold).
    """
    count = len(x) - 1
    sweeps = 0
    for stride in (1, 2):
        if count < stride:
            continue
        limit = stride * segment_length * (1.0 + max_strain)
        colours = _colours(count - stride + 1, stride)
        for _ in range(MAX_SWEEPS):
            worst = max(_project(x, v, inv_mass, c, stride, limit) for c in colours)
            if worst <= 0.0:
                break
            sweeps += 1
    return sweeps
