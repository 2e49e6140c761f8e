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
from .layout import (AXIAL, AXIAL_STIFFNESS, BEND_DAMPING, BEND_STIFFNESS, BENDING, BREAK_LOAD,
                     CALM_CHANGE, DAMPING, FIRST, LAST, LENGTH, MASS, PARTED, PARTED_STEP, PEAK_A,
                     PEAK_B, REST, REST_RATE, SLACK_IMPACT, SNAP_FLOOR, STIFFNESS, TENSION,
                     TENSION_BEFORE, TENSION_CHANGE)
from .winch import elastic_tension, stretch

# The snap watch's tension scale (check_segments) is never below SNAP_FLOOR_WEIGHT times the
# line's weight nor SNAP_FLOOR_MBL of its MBL (stepping/adaptive.py says why).
SNAP_FLOOR_WEIGHT = 1.0
SNAP_FLOOR_MBL = 0.005
# The calm watch's scale (CALM_CHANGE) is never below this many times the snap watch's floor:
# a slack line's tension rings about nothing, and is calm (stepping/adaptive.py says why).
CALM_FLOOR_FACTOR = 10.0
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
def check_segments(x, v, particles, lines, line_real, rest, step):
    """
    After step `step` of a run: part every whole line with a segment past its break load.

    On the way, for the adaptive integrator (adaptive.py), each segment's spring tension goes
    to its TENSION column (the one before to TENSION_BEFORE), and each line's TENSION_CHANGE
    and SLACK_IMPACT are raised to, as fractions of the step's tension scale (the largest
    segment tension, spring and damper, at least SNAP_FLOOR; CALM_CHANGE the same change
    against a scale of at least CALM_FLOOR_FACTOR x SNAP_FLOOR): the largest change of a
    segment's spring tension per step over this step and the one before (from NaN, a tension
    not yet measured, none), and the largest impact of a slack segment, the tension
    sqrt(EA m) |u| it would take if it came taut at its stretch rate u now.
    """
    for k in range(lines.shape[0]):
        real = line_real[k]
        first = lines[k, FIRST]
        worst, where = -np.inf, first
        change = 0.0
        impact = 0.0
        for i in range(first, lines[k, LAST]):
            length, rate = stretch(x, v, i)
            elastic = elastic_tension(particles, real, i, length)
            tension = elastic + particles[i, DAMPING] * (rate - particles[i, REST_RATE])
            if tension > worst:
                worst, where = tension, i
            # the watch reads the spring alone, and its change over two steps: a stiff end
            # segment rings at the step's own period under both implicit schemes (they damp
            # it little), hundreds of newtons up and down every step, and that is no snap
            difference = 0.5 * abs(elastic - particles[i, TENSION_BEFORE])
            if difference > change:
                change = difference
            particles[i, TENSION_BEFORE] = particles[i, TENSION]
            particles[i, TENSION] = elastic
            if length < particles[i, REST]:
                # the impedance of the line there: EA over the wave speed sqrt(EA / m)
                mass_per_length = particles[i + 1, MASS] / particles[i + 1, LENGTH]
                impact = max(impact, np.sqrt(real[AXIAL_STIFFNESS] * mass_per_length)
                             * abs(rate - particles[i, REST_RATE]))
        scale = max(worst, real[SNAP_FLOOR])
        real[TENSION_CHANGE] = max(real[TENSION_CHANGE], change / scale)
        real[CALM_CHANGE] = max(real[CALM_CHANGE],
                                change / max(worst, CALM_FLOOR_FACTOR * real[SNAP_FLOOR]))
        real[SLACK_IMPACT] = max(real[SLACK_IMPACT], impact / scale)
        if real[PARTED] < 0.0 and worst > real[BREAK_LOAD]:  # the most loaded one goes
            part(particles, lines, rest, k, where)
            real[PARTED] = where - first
            real[PARTED_STEP] = step


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
