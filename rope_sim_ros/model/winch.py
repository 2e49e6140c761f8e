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
The winch: a line end that pays out or heaves in, changing the line's unstretched length.

The change is spread over the segments in proportion to their rest lengths, as MoorDyn
spreads it (Line::setUnstretchedLength): the segment count stays, so a line hauled in from
40 to 10 m keeps its 20 segments, each finer, and what the node publishes keeps its size;
the mass follows the length (the rope taken in leaves with its mass). Paid out far past its
start, a line's segments grow as long: the winch's maximum length (4 times the start by
default) bounds that.

The length changes before every step, at that step's speed: never in jumps between outputs
(one jump of 0.5 mm per 1 ms on a 40 m polyester line, EA 50 MN, is 625 N of tension, as
much as the line holds: MoorDyn driven that way computed a third to a half of the tension).
A segment's damper acts on its stretch rate, the rate of its length less that of its rest
length (layout.REST_RATE), so hauling a line in at a steady speed adds no damping force.

Modes (layout.WINCH_MODE):

- SPEED: pays out (+) or heaves in at the commanded speed, within the maximum speed and
  acceleration, the acceleration itself eased in and out over JERK_TIME;
- BRAKE: holds; while the segment at the winch pulls harder than the brake's holding load
  (elastic tension), it pays out (renders) just enough to bring it back to that load, at
  whatever speed that takes (a slipping brake);
- CONSTANT_TENSION: pays out or heaves in to bring the tension at the winch to the set one
  within WINCH_RESPONSE seconds, as the line's quasi-static stiffness says it would
  (quasi_static_stiffness), within the maximum speed and acceleration.

The winch stops where the line reaches its minimum or maximum length.

On a line with a strain-tension curve (tension_curve.py) every tension here is the curve's:
the segment's tension, the brake's holding strain (the curve's inverse at the holding load)
and the elastic compliance in the constant-tension stiffness (each segment's tangent at its
strain now). The winch's resizing needs nothing more: the curve is in strain, and the rest
lengths it scales are what the strain is measured against.
"""

import numba
import numpy as np

from .layout import (AXIAL_STIFFNESS, BEND_DAMPING, BEND_REST, BEND_STIFFNESS, BRAKE,
                     CONSTANT_TENSION, CURVE_POINTS, DAMPING, DRAG, END_A, FIRST, FREE, INV_MASS,
                     KIND, LAST, LENGTH, MASS, NO_WINCH, REST, REST_RATE, SPEED, STIFFNESS,
                     TOTAL_MASS, UNSTRETCHED, WINCH_ACCELERATION, WINCH_BRAKE_LOAD, WINCH_COMMAND,
                     WINCH_END, WINCH_MAX_LENGTH, WINCH_MAX_SPEED, WINCH_MIN_LENGTH, WINCH_MODE,
                     WINCH_RAMP, WINCH_RESPONSE, WINCH_SPEED)
from .tension_curve import curve_strain, tension_at

# The winch's acceleration itself changes from 0 to its maximum in this time [s] (a drive's
# S-curve): a speed step with the acceleration alone limited ends the ramp with a jump of
# the acceleration, which set a 40 m polyester line's sag swinging, +-15 N about 1024 N
# where MoorDyn's smooth ramp of the same length left +-3 N.
JERK_TIME = 1.0


@numba.njit(cache=True, inline='always')
def elastic_tension(particles, real, i, length):
    """Return the elastic tension [N] of the structural spring at row i at `length` [m]."""
    stretch = length - particles[i, REST]
    if real[CURVE_POINTS] > 0.0:  # the curve gives no tension at a strain <= 0
        return tension_at(real, stretch / particles[i, REST])[0]
    return particles[i, STIFFNESS] * max(stretch, 0.0)


@numba.njit(cache=True, inline='always')
def stretch(x, v, i):
    """Return the length [m] of the structural spring (i, i + 1) and its rate [m/s]."""
    dx = x[i + 1, 0] - x[i, 0]
    dy = x[i + 1, 1] - x[i, 1]
    dz = x[i + 1, 2] - x[i, 2]
    length = np.sqrt(dx * dx + dy * dy + dz * dz)
    inv = 1.0 / max(length, 1e-12)
    rate = ((v[i + 1, 0] - v[i, 0]) * dx + (v[i + 1, 1] - v[i, 1]) * dy
            + (v[i + 1, 2] - v[i, 2]) * dz) * inv
    return length, rate


@numba.njit(cache=True, inline='always')
def segment_tension(x, v, particles, real, i):
    """
    Return the axial tension of the structural spring (i, i + 1) [N]: spring and damper.

    The spring (EA, or the line's curve: real is its LINE_REAL row) pulls only when
    stretched; the damper acts on the stretch rate (it can push).
    """
    length, rate = stretch(x, v, i)
    return elastic_tension(particles, real, i, length) + particles[i, DAMPING] * (
        rate - particles[i, REST_RATE])


@numba.njit(cache=True, inline='always')
def winch_load(x, v, particles, lines, line_real, k, gravity):
    """
    Return the force of line k on its winch's point [N]: as the node reports it.

    The winch segment's tension and the weight of the half segment lumped at the end.
    """
    i = winch_segment(lines, line_real, k)
    end = lines[k, FIRST] if line_real[k, WINCH_END] == 0.0 else lines[k, LAST]
    other = i + 1 if end == i else i
    tension = segment_tension(x, v, particles, line_real[k], i)
    dx = x[other, 0] - x[end, 0]
    dy = x[other, 1] - x[end, 1]
    dz = x[other, 2] - x[end, 2]
    inv = tension / max(np.sqrt(dx * dx + dy * dy + dz * dz), 1e-12)
    fx = dx * inv + particles[end, MASS] * gravity[0]
    fy = dy * inv + particles[end, MASS] * gravity[1]
    fz = dz * inv + particles[end, MASS] * gravity[2]
    return np.sqrt(fx * fx + fy * fy + fz * fz)


@numba.njit(cache=True, inline='always')
def winch_segment(lines, line_real, k):
    """Return the particle row starting the segment at line k's winch."""
    return lines[k, FIRST] if line_real[k, WINCH_END] == 0.0 else lines[k, LAST] - 1


@numba.njit(cache=True)
def resize(particles, lines, line_real, points, rest, inv_mass, k, length):
    """
    Make line k's unstretched length `length` [m], every segment scaled alike.

    Masses, lumped lengths and drag scale with the segments, stiffness and damping per
    segment inversely; so does a free point's share of the end's mass (and its inverse mass
    in the strain limit). rest and inv_mass: the run's copies of those columns.
    """
    scale = length / line_real[k, UNSTRETCHED]
    inverse = 1.0 / scale
    first, last = lines[k, FIRST], lines[k, LAST]
    for i in range(first, last + 1):
        particles[i, MASS] *= scale
        particles[i, LENGTH] *= scale
        particles[i, DRAG] *= scale
        if i < last:
            particles[i, REST] *= scale
            particles[i, STIFFNESS] *= inverse
            particles[i, DAMPING] *= inverse
            rest[i] = particles[i, REST]
        if i < last - 1:
            particles[i, BEND_REST] *= scale
            particles[i, BEND_STIFFNESS] *= inverse
            particles[i, BEND_DAMPING] *= inverse
    for e in range(2):
        q = lines[k, END_A + e]
        row = first if e == 0 else last
        if points[q, KIND] == FREE:
            before = points[q, TOTAL_MASS]
            points[q, TOTAL_MASS] += particles[row, MASS] * (1.0 - inverse)
            particles[row, INV_MASS] *= scale * before / points[q, TOTAL_MASS]
            inv_mass[row] = particles[row, INV_MASS]
    line_real[k, UNSTRETCHED] = length


@numba.njit(cache=True, inline='always')
def quasi_static_stiffness(x, particles, lines, line_real, k, tension, g):
    """
    Return how much line k's tension rises per metre hauled in, slowly [N/m].

    The elastic and the geometric compliance of a shallow catenary in series (Irvine):
    L / EA + w^2 c^3 / (12 H^3), with w its weight per metre, c the chord between its ends
    and H the horizontal part of the tension at the winch. On a line with a curve, L / EA
    is the sum of l_i / (dT/dstrain) over its segments, each tangent at the segment's strain
    now: the nylon preset's is 30 % larger at a tenth of its MBL than at half of it, and
    steering by one fixed EA would over- or undershoot the set tension by as much. Hanging
    straight down (H = 0) a line's tension does not follow its length: 0.
    """
    first, last = lines[k, FIRST], lines[k, LAST]
    i = winch_segment(lines, line_real, k)
    length = line_real[k, UNSTRETCHED]
    mass = 0.0
    for j in range(first, last + 1):
        mass += particles[j, MASS]
    w = mass * g / length
    dx = x[last, 0] - x[first, 0]
    dy = x[last, 1] - x[first, 1]
    dz = x[last, 2] - x[first, 2]
    chord = np.sqrt(dx * dx + dy * dy + dz * dz)
    sx = x[i + 1, 0] - x[i, 0]
    sy = x[i + 1, 1] - x[i, 1]
    sz = x[i + 1, 2] - x[i, 2]
    span = np.sqrt(sx * sx + sy * sy)
    horizontal = tension * span / max(np.sqrt(span * span + sz * sz), 1e-12)
    if not horizontal > 0.0:
        return 0.0
    real = line_real[k]
    if real[CURVE_POINTS] > 0.0:
        elastic = 0.0
        for j in range(first, last):
            rest = particles[j, REST]
            span_j = np.sqrt((x[j + 1, 0] - x[j, 0]) ** 2 + (x[j + 1, 1] - x[j, 1]) ** 2
                             + (x[j + 1, 2] - x[j, 2]) ** 2)
            elastic += rest / tension_at(real, span_j / rest - 1.0)[1]
    else:
        # the line's EA, not its winch segment's EA / l_i times l_i: a parted one's are 0
        # and 1e300 m (parting.py), and a constant-tension winch whose own segment parted
        # divided by zero
        elastic = length / real[AXIAL_STIFFNESS]  # L / EA
    compliance = elastic + w * w * chord ** 3 / (12.0 * horizontal ** 3)
    return 1.0 / compliance


@numba.njit(cache=True, inline='always')
def _commanded_speed(x, v, particles, lines, line_real, k, dt, gravity):
    """Return the speed a SPEED or CONSTANT_TENSION winch runs at this step [m/s]."""
    real = line_real[k]
    if real[WINCH_MODE] == SPEED:
        target = real[WINCH_COMMAND]
    else:
        tension = winch_load(x, v, particles, lines, line_real, k, gravity)
        g = np.sqrt(gravity[0] ** 2 + gravity[1] ** 2 + gravity[2] ** 2)
        stiffness = quasi_static_stiffness(x, particles, lines, line_real, k, tension, g)
        target = 0.0
        if stiffness > 0.0:
            target = (tension - real[WINCH_COMMAND]) / (stiffness * real[WINCH_RESPONSE])
    target = min(max(target, -real[WINCH_MAX_SPEED]), real[WINCH_MAX_SPEED])
    # the acceleration that, eased off at the jerk limit, arrives at the target speed
    most = real[WINCH_ACCELERATION]
    jerk = most / JERK_TIME
    gap = target - real[WINCH_SPEED]
    if gap == 0.0:
        real[WINCH_RAMP] = 0.0
        return target
    wanted = np.sqrt(2.0 * jerk * abs(gap))
    wanted = min(wanted, most, abs(gap) / dt)
    if gap < 0.0:
        wanted = -wanted
    ramp = min(max(wanted, real[WINCH_RAMP] - jerk * dt), real[WINCH_RAMP] + jerk * dt)
    speed = real[WINCH_SPEED] + ramp * dt
    if (speed - target) * gap >= 0.0:  # the ramp's last step: arrive, never overshoot
        speed, ramp = target, 0.0
    real[WINCH_RAMP] = ramp
    return speed


@numba.njit(cache=True)
def pay_out(x, v, particles, lines, line_real, points, rest, inv_mass, dt, gravity):
    """Before a step: run every SPEED and CONSTANT_TENSION winch for dt."""
    for k in range(lines.shape[0]):
        mode = line_real[k, WINCH_MODE]
        if mode == NO_WINCH or mode == BRAKE:
            continue
        before = line_real[k, UNSTRETCHED]
        speed = _commanded_speed(x, v, particles, lines, line_real, k, dt, gravity)
        length = min(max(before + speed * dt, line_real[k, WINCH_MIN_LENGTH]),
                     line_real[k, WINCH_MAX_LENGTH])
        speed = (length - before) / dt
        line_real[k, WINCH_SPEED] = speed
        if length != before:
            resize(particles, lines, line_real, points, rest, inv_mass, k, length)
        for i in range(lines[k, FIRST], lines[k, LAST]):
            if particles[i, STIFFNESS] > 0.0:  # not parted (parting.py)
                particles[i, REST_RATE] = particles[i, REST] * speed / length


@numba.njit(cache=True)
def render(x, particles, lines, line_real, points, rest, inv_mass, dt):
    """After a step: let every BRAKE winch pay out while its segment exceeds the holding load."""
    for k in range(lines.shape[0]):
        if line_real[k, WINCH_MODE] != BRAKE:
            continue
        line_real[k, WINCH_SPEED] = 0.0
        i = winch_segment(lines, line_real, k)
        rest_i = particles[i, REST]
        length = np.sqrt((x[i + 1, 0] - x[i, 0]) ** 2 + (x[i + 1, 1] - x[i, 1]) ** 2
                         + (x[i + 1, 2] - x[i, 2]) ** 2)
        holding = line_real[k, WINCH_BRAKE_LOAD]
        real = line_real[k]
        if not elastic_tension(particles, real, i, length) > holding:
            continue
        # the rest length at which this segment pulls with the holding load: at the strain
        # the curve (or EA) gives that load
        if real[CURVE_POINTS] > 0.0:
            strain = curve_strain(real, holding)
        else:
            strain = holding / (particles[i, STIFFNESS] * rest_i)
        wanted = length / (1.0 + strain)
        before = line_real[k, UNSTRETCHED]
        after = min(before * wanted / rest_i, line_real[k, WINCH_MAX_LENGTH])
        if after > before:
            resize(particles, lines, line_real, points, rest, inv_mass, k, after)
            line_real[k, WINCH_SPEED] = (after - before) / dt


def mode_code(mode: str) -> int:
    """Return the WINCH_MODE code of a mode's name ('none', 'speed', 'brake', ...)."""
    return {'none': NO_WINCH, 'speed': SPEED, 'brake': BRAKE,
            'constant_tension': CONSTANT_TENSION}[mode]
