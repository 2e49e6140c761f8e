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

"""Compiled (numba) loops for the rope's hot path, with the same physics as rope.py.

Pure numpy pays about 40 us of call overhead per force evaluation whatever N is, which caps
a stiff line near real time. These kernels run many steps per call. The numpy path in
rope.py / integrators.py / superelastic.py stays the reference that the tests compare with.
"""

import numba
import numpy as np

from .rope import RopeProperties
from .superelastic import TOLERANCE as _TOLERANCE


def coefficients(props: RopeProperties) -> np.ndarray:
    """The line's numbers in the flat layout the kernels take (see line_forces)."""
    return np.array([
        props.segment_length, props.structural_stiffness, props.structural_damping,
        props.bending_stiffness, props.bending_damping,
        1.0 if props.damping_model == 'axial' else 0.0,
        props.air_drag_coefficient * props.segment_length, props.particle_mass,
        *props.gravity], dtype=float)


@numba.njit(cache=True, fastmath=False)
def _add_springs(x, v, out, stride, rest, stiffness, damping, axial, tension_only):
    for i in range(x.shape[0] - stride):
        j = i + stride
        dx = x[j, 0] - x[i, 0]
        dy = x[j, 1] - x[i, 1]
        dz = x[j, 2] - x[i, 2]
        length = np.sqrt(dx * dx + dy * dy + dz * dz)
        inv = 1.0 / max(length, 1e-12)
        ux, uy, uz = dx * inv, dy * inv, dz * inv
        stretch = length - rest
        if tension_only and stretch < 0.0:
            stretch = 0.0
        dvx = v[j, 0] - v[i, 0]
        dvy = v[j, 1] - v[i, 1]
        dvz = v[j, 2] - v[i, 2]
        if axial:
            tension = stiffness * stretch + damping * (dvx * ux + dvy * uy + dvz * uz)
            fx, fy, fz = tension * ux, tension * uy, tension * uz
        else:
            tension = stiffness * stretch
            fx = tension * ux + damping * dvx
            fy = tension * uy + damping * dvy
            fz = tension * uz + damping * dvz
        out[i, 0] += fx
        out[i, 1] += fy
        out[i, 2] += fz
        out[j, 0] -= fx
        out[j, 1] -= fy
        out[j, 2] -= fz


@numba.njit(cache=True)
def line_forces(x, v, out, coef):
    """Spring and damper forces of the line on every particle into `out`.

    coef = (l0, k_s, c_s, k_b, c_b, axial, drag_per_particle, particle_mass, gx, gy, gz).
    """
    out[:] = 0.0
    l0, ks, cs, kb, cb, axial = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5] > 0.5
    _add_springs(x, v, out, 1, l0, ks, cs, axial, True)
    if kb > 0.0 or cb > 0.0:
        _add_springs(x, v, out, 2, 2.0 * l0, kb, cb, axial, False)


@numba.njit(cache=True)
def _accelerations(x, v, out, coef):
    line_forces(x, v, out, coef)
    drag, mass = coef[6], coef[7]
    for i in range(x.shape[0]):
        speed = np.sqrt(v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
        for d in range(3):
            out[i, d] = (out[i, d] - drag * speed * v[i, d]) / mass + coef[8 + d]


@numba.njit(cache=True)
def _project(x, v, inv_mass, stride, limit, colour):
    worst = 0.0
    for i in range(x.shape[0] - stride):
        if (i // stride) % 2 != colour:
            continue
        j = i + stride
        total = inv_mass[i] + inv_mass[j]
        if total <= 0.0:
            continue
        dx = x[j, 0] - x[i, 0]
        dy = x[j, 1] - x[i, 1]
        dz = x[j, 2] - x[i, 2]
        length = np.sqrt(dx * dx + dy * dy + dz * dz)
        if length <= limit * (1.0 + _TOLERANCE):
            continue
        worst = max(worst, length / limit - 1.0)
        ux, uy, uz = dx / length, dy / length, dz / length
        wa, wb = inv_mass[i] / total, inv_mass[j] / total
        excess = length - limit
        closing = ((v[j, 0] - v[i, 0]) * ux + (v[j, 1] - v[i, 1]) * uy
                   + (v[j, 2] - v[i, 2]) * uz)
        for d, u in ((0, ux), (1, uy), (2, uz)):
            x[i, d] += wa * excess * u
            x[j, d] -= wb * excess * u
            v[i, d] += wa * closing * u
            v[j, d] -= wb * closing * u
    return worst


@numba.njit(cache=True)
def adjust(x, v, inv_mass, segment_length, max_strain, max_sweeps):
    """Position and velocity adjustment, as superelastic.adjust (same colour order)."""
    sweeps = 0
    n = x.shape[0] - 1
    for stride in (1, 2):
        if n < stride:
            continue
        limit = stride * segment_length * (1.0 + max_strain)
        for _ in range(max_sweeps):
            worst = max(_project(x, v, inv_mass, stride, limit, 0),
                        _project(x, v, inv_mass, stride, limit, 1))
            if worst <= 0.0:
                break
            sweeps += 1
    return sweeps


@numba.njit(cache=True)
def improved_euler_run(x, v, ends, end_velocities, dt, coef, inv_mass, max_strain,
                       adjusting, max_sweeps):
    """Take len(ends) improved Euler steps in place; ends[k] holds particles 0 and N."""
    a1 = np.empty_like(x)
    a2 = np.empty_like(x)
    xp = np.empty_like(x)
    vp = np.empty_like(x)
    last = x.shape[0] - 1
    for k in range(ends.shape[0]):
        _accelerations(x, v, a1, coef)
        for i in range(x.shape[0]):
            for d in range(3):
                xp[i, d] = x[i, d] + dt * v[i, d]
                vp[i, d] = v[i, d] + dt * a1[i, d]
        for d in range(3):
            xp[0, d], xp[last, d] = ends[k, 0, d], ends[k, 1, d]
            vp[0, d], vp[last, d] = end_velocities[k, 0, d], end_velocities[k, 1, d]
        _accelerations(xp, vp, a2, coef)
        for i in range(x.shape[0]):
            for d in range(3):
                x[i, d] += 0.5 * dt * (v[i, d] + vp[i, d])
                v[i, d] += 0.5 * dt * (a1[i, d] + a2[i, d])
        for d in range(3):
            x[0, d], x[last, d] = ends[k, 0, d], ends[k, 1, d]
            v[0, d], v[last, d] = end_velocities[k, 0, d], end_velocities[k, 1, d]
        if adjusting:
            adjust(x, v, inv_mass, coef[0], max_strain, max_sweeps)
