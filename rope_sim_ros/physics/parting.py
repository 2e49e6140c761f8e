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
A line parting under load, and the peak hold of its end forces: what is checked after a step.

After every step, a line whose segment pulls harder than its break load (spring, by EA or
the line's strain-tension curve, and damper) parts there: that segment, and the bending
springs across it, lose their stiffness and damping, and its rest length becomes
PARTED_REST, which no strain limit ever reaches (on a curve its strain is then -1: no
tension). The particles stay where they are, with their masses: the two pieces are the
particles on either side, still in the one line, each hanging from its end's point, and
they recoil under the energy the rope had stored. A line parts once, at its most loaded
segment; it stays parted until it is rebuilt.

Also after every step, the force of each line on the points at its ends (the springs and
dampers at the end particle and the weight of the half segment there; the fluid's share of
that half segment, a few newtons, is left out) raises PEAK_A and PEAK_B, so that a snap
shorter than the output interval is still reported with its peak.
"""

import numba
import numpy as np

from .forces.springs import add_springs
from .layout import (AXIAL, BEND_DAMPING, BEND_STIFFNESS, BENDING, BREAK_LOAD, DAMPING, FIRST,
                     LAST, MASS, PARTED, PARTED_STEP, PEAK_A, PEAK_B, REST, REST_RATE,
                     STIFFNESS)
from .winch import segment_tension

PARTED_REST = 1e300  # [m]: the rest length of a parted segment, never stretched


@numba.njit(cache=True)
def part(particles, lines, rest, k, i):
    """Part line k's structural spring starting at particle row i (rest: the run's copy)."""
    particles[i, STIFFNESS] = 0.0
    particles[i, DAMPING] = 0.0
    particles[i, REST_RATE] = 0.0
    particles[i, REST] = PARTED_REST
    rest[i] = PARTED_REST
    for j in (i - 1, i):  # the bending springs (j, j + 2) across it
        if j >= lines[k, FIRST] and j + 2 <= lines[k, LAST]:
            particles[j, BEND_STIFFNESS] = 0.0
            particles[j, BEND_DAMPING] = 0.0


@numba.njit(cache=True)
def part_overloaded(x, v, particles, lines, line_real, rest, step):
    """After step `step` of a run: part every whole line with a segment past its break load."""
    for k in range(lines.shape[0]):
        limit = line_real[k, BREAK_LOAD]
        if line_real[k, PARTED] >= 0.0 or not limit < np.inf:
            continue
        first = lines[k, FIRST]
        worst, where = -np.inf, first
        for i in range(first, lines[k, LAST]):
            tension = segment_tension(x, v, particles, line_real[k], i)
            if tension > worst:
                worst, where = tension, i
        if worst > limit:  # the most loaded segment goes
            part(particles, lines, rest, k, where)
            line_real[k, PARTED] = where - first
            line_real[k, PARTED_STEP] = step


@numba.njit(cache=True)
def hold_peaks(x, v, particles, lines, line_real, gravity, scratch):
    """After a step: raise each line's PEAK_A and PEAK_B to its end forces' magnitudes."""
    for k in range(lines.shape[0]):
        first, last = lines[k, FIRST], lines[k, LAST]
        axial = lines[k, AXIAL] == 1
        bending = lines[k, BENDING] == 1 and last - first >= 2
        for e in range(2):
            # only the end row of scratch is read: the other rows the springs write are not
            row = first if e == 0 else last
            for p in range(3):
                scratch[row, p] = particles[row, MASS] * gravity[p]
            start = row if e == 0 else row - 1
            add_springs(x, v, scratch, particles, start, start + 1, False, axial,
                        line_real[k])
            if bending:
                start = row if e == 0 else row - 2
                add_springs(x, v, scratch, particles, start, start + 2, True, axial,
                            line_real[k])
            load = np.sqrt(scratch[row, 0] ** 2 + scratch[row, 1] ** 2 + scratch[row, 2] ** 2)
            column = PEAK_A if e == 0 else PEAK_B
            if load > line_real[k, column]:
                line_real[k, column] = load
