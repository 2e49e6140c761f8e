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
Structural springs (i, i+1) and bending springs (i, i+2) with their dampers (seed eqs. 2, 3).

A structural spring is a rope segment: Hooke in tension (EA / l), or the line's
strain-tension curve where it has one (tension_curve.py), and nothing in compression. A
bending spring pushes back when the rope folds (the seed's purpose) and pulls when
stretched; it stays linear (r_s EA / l_b, EA the line's nominal stiffness) on a line with a
curve too, being a numerical device and no part of the rope's load-extension. Each spring's
damper is either axial, BA / l times the stretch rate along the spring (as MoorDyn), or the
seed's K_SD (V_A - V_B), which also damps a segment's rigid rotation.

The implicit step's matrix block of a spring (spring_block) is its stiffness
S = k u u^T + (T / l)(I - u u^T) and damping C = c u u^T (axial) or c I (seed), already scaled
by the step (k by h^2 / 2, c by h). On a curve, k is the tangent dT/dstrain / l at the
segment's strain now.
"""

import numba
import numpy as np

from ..layout import (BEND_DAMPING, BEND_REST, BEND_STIFFNESS, CURVE_POINTS, DAMPING, REST,
                      REST_RATE, STIFFNESS)
from ..tension_curve import tension_at


@numba.njit(cache=True, inline='always')
def add_springs(x, v, out, particles, first, last, bending, axial, real):
    """
    Add the forces of one line's springs (i, i + stride) to `out`.

    :param first, last: the line's particle rows (inclusive).
    :param bending: the bending springs (i, i + 2) (else the structural ones (i, i + 1)).
    :param axial: axial damping (else the seed's).
    :param real: the line's LINE_REAL row: its strain-tension curve, if it has one.
    """
    stride = 2 if bending else 1
    col_rest = BEND_REST if bending else REST
    col_k = BEND_STIFFNESS if bending else STIFFNESS
    col_c = BEND_DAMPING if bending else DAMPING
    curved = not bending and real[CURVE_POINTS] > 0.0
    for i in range(first, last + 1 - stride):
        j = i + stride
        rest = particles[i, col_rest]
        stiffness = particles[i, col_k]
        damping = particles[i, col_c]
        dx = x[j, 0] - x[i, 0]
        dy = x[j, 1] - x[i, 1]
        dz = x[j, 2] - x[i, 2]
        length = np.sqrt(dx * dx + dy * dy + dz * dz)
        inv = 1.0 / max(length, 1e-12)
        ux, uy, uz = dx * inv, dy * inv, dz * inv
        stretch = length - rest
        # a winch changing the rest length: the damper sees the stretch rate only
        rest_rate = 0.0
        if curved:  # no tension at a strain <= 0
            rest_rate = particles[i, REST_RATE]
            elastic = tension_at(real, stretch / rest)[0]
        else:
            if not bending:
                rest_rate = particles[i, REST_RATE]
                if stretch < 0.0:  # a segment carries no compression
                    stretch = 0.0
            elastic = stiffness * stretch
        dvx = v[j, 0] - v[i, 0]
        dvy = v[j, 1] - v[i, 1]
        dvz = v[j, 2] - v[i, 2]
        if axial:
            tension = elastic + damping * (dvx * ux + dvy * uy + dvz * uz - rest_rate)
            fx, fy, fz = tension * ux, tension * uy, tension * uz
        else:
            tension = elastic - damping * rest_rate
            fx = tension * ux + damping * dvx
            fy = tension * uy + damping * dvy
            fz = tension * uz + damping * dvz
        out[i, 0] += fx
        out[i, 1] += fy
        out[i, 2] += fz
        out[j, 0] -= fx
        out[j, 1] -= fy
        out[j, 2] -= fz


@numba.njit(cache=True, inline='always')
def spring_block(x, i, j, rest, k, c, axial, block):
    """
    Fill block with S + C of the linear spring (i, j) (k, c already scaled by the step).

    S = k u u^T + (T / l)(I - u u^T), C = c u u^T (axial) or c I (seed form).
    """
    dx = x[j, 0] - x[i, 0]
    dy = x[j, 1] - x[i, 1]
    dz = x[j, 2] - x[i, 2]
    length = max(np.sqrt(dx * dx + dy * dy + dz * dz), 1e-12)
    # The full axial stiffness even where a segment is slack: a single linearised step that
    # expects no resistance overshoots when the segment snaps taut within the step (and then
    # blows up); overestimating it only damps that step a little. The geometric term only
    # where the spring pulls: that keeps the matrix positive definite.
    _fill_block(dx / length, dy / length, dz / length, max(k * (length - rest), 0.0) / length,
                k, c, axial, block)


@numba.njit(cache=True, inline='always')
def curve_spring_block(x, i, j, rest, real, half_h2, c, axial, block):
    """
    Fill block with S + C of the structural spring (i, j) of a line with a curve.

    k = (dT/dstrain) / l at the segment's strain now, T the curve's tension there (both
    scaled by half_h2; c already scaled by the step). Slack, the tangent is the first
    segment's, as the linear spring keeps its full EA (see spring_block).
    """
    dx = x[j, 0] - x[i, 0]
    dy = x[j, 1] - x[i, 1]
    dz = x[j, 2] - x[i, 2]
    length = max(np.sqrt(dx * dx + dy * dy + dz * dz), 1e-12)
    tension, tangent = tension_at(real, length / rest - 1.0)
    _fill_block(dx / length, dy / length, dz / length, half_h2 * tension / length,
                half_h2 * tangent / rest, c, axial, block)


@numba.njit(cache=True, inline='always')
def _fill_block(u0, u1, u2, g, k, c, axial, block):
    """Fill block with k u u^T + g (I - u u^T) and c u u^T (axial) or c I (seed)."""
    diag = g + (0.0 if axial else c)
    along = k - g + (c if axial else 0.0)
    block[0, 0] = along * u0 * u0 + diag
    block[1, 1] = along * u1 * u1 + diag
    block[2, 2] = along * u2 * u2 + diag
    block[0, 1] = block[1, 0] = along * u0 * u1
    block[0, 2] = block[2, 0] = along * u0 * u2
    block[1, 2] = block[2, 1] = along * u1 * u2


@numba.njit(cache=True, inline='always')
def spring_block_at(x, particles, i, bending, half_h2, h, axial, block, real):
    """
    Fill block with the step-scaled S + C of the spring starting at particle row i.

    :param real: the line's LINE_REAL row: its strain-tension curve, if it has one.
    """
    if bending:
        spring_block(x, i, i + 2, particles[i, BEND_REST], particles[i, BEND_STIFFNESS] * half_h2,
                     particles[i, BEND_DAMPING] * h, axial, block)
    elif real[CURVE_POINTS] > 0.0:
        curve_spring_block(x, i, i + 1, particles[i, REST], real, half_h2,
                           particles[i, DAMPING] * h, axial, block)
    else:
        spring_block(x, i, i + 1, particles[i, REST], particles[i, STIFFNESS] * half_h2,
                     particles[i, DAMPING] * h, axial, block)
