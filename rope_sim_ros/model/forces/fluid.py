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
Buoyancy, drag and added mass of the water and the air around a line, MoorDyn's way.

Every per-length load is lumped on the particles: particle i carries half of each adjacent
segment's unstretched length, len_i, of which sub_i is in the water. A segment's wetted
fraction is the mean over the segment of the ramp r(z) = clip((level - z) / dv + 1/2, 0, 1)
(dv: the volume-equivalent diameter), z linear between its two particles: continuous and
piecewise smooth in both particles' heights, so a segment crossing the surface feels no jump.
(MoorDyn's Line::calcSubSeg takes the fraction of the segment's length below the surface,
with a small correction of d/2 at the surface: the same almost everywhere, with a kink.)
A parted segment joins nothing: each half of it is wetted at its own particle's height, r(z_i).

With A_v = pi dv^2 / 4 and the displaced mass D_i = A_v (rho_w sub_i + rho_a (len_i - sub_i)):

- weight and buoyancy: (m_i - D_i) g;
- drag, for the water part (rho_w, sub_i, relative to the current U) and the air part
  (rho_a, len_i - sub_i, relative to still air) alike, with u = U - v split along the tangent
  q into u_t = (u . q) q and u_n = u - u_t:
  F = 1/2 rho Cd d L |u_n| u_n + 1/2 rho CdAx pi d L |u_t| u_t (MoorDyn's CdAx is on the
  circumference pi d);
- added mass: M_i = m_i I + D_i (Ca (I - q q^T) + CaAx q q^T) = a I + b q q^T, whose inverse
  is (1/a)(I - b / (a + b) q q^T).

For the implicit step the drag's minus-Jacobian in v is
C = c_n (|u_n| P + u_n u_n^T / |u_n|) + 2 c_t |u . q| q q^T (P = I - q q^T, q frozen within a
step); buoyancy's dependence on z is left out of the stiffness (rho g A_v per metre, about a
millionth of a segment's).

A free point (a payload) has a volume V, a drag area CdA and an added-mass coefficient Ca_p:
its wetted fraction is r(z) with the ramp width V^(1/3), its drag 1/2 rho CdA |u| u and its
added mass Ca_p rho V, isotropic, with rho blended between water and air as for a particle.
"""

import numba
import numpy as np

from ..layout import LENGTH, REST, STIFFNESS


@numba.njit(cache=True, inline='always')
def _ramp_integral(r):
    """Return the integral from 0 to r of clip(s, 0, 1) ds."""
    if r <= 0.0:
        return 0.0
    if r < 1.0:
        return 0.5 * r * r
    return r - 0.5


@numba.njit(cache=True, inline='always')
def point_fraction(z, level, width):
    """Return the wetted fraction clip((level - z) / width + 1/2, 0, 1) of a point at z."""
    r = (level - z) / width + 0.5
    if r <= 0.0:
        return 0.0
    if r >= 1.0:
        return 1.0
    return r


@numba.njit(cache=True, inline='always')
def wetted_fraction(z_a, z_b, level, width):
    """
    Return a segment's wetted fraction: the mean of the surface ramp between its ends.

    z_a, z_b: its two particles' heights [m]; level: the water level [m]; width: the ramp's
    width dv [m]. The closed form of the integral of the clipped ramp, the ramp at the middle
    where the segment is level (|z_b - z_a| < 1e-9 m).
    """
    r_a = (level - z_a) / width + 0.5
    r_b = (level - z_b) / width + 0.5
    if r_a >= 1.0 and r_b >= 1.0:
        return 1.0
    if r_a <= 0.0 and r_b <= 0.0:
        return 0.0
    if abs(z_b - z_a) < 1e-9:
        return min(max(0.5 * (r_a + r_b), 0.0), 1.0)
    return (_ramp_integral(r_b) - _ramp_integral(r_a)) / (r_b - r_a)


@numba.njit(cache=True, inline='always')
def _unit(x, i, j, tangent, row):
    """Put unit(x[j] - x[i]) into tangent[row] (zero where the two coincide)."""
    d0 = x[j, 0] - x[i, 0]
    d1 = x[j, 1] - x[i, 1]
    d2 = x[j, 2] - x[i, 2]
    n = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    inv = 1.0 / n if n > 0.0 else 0.0
    tangent[row, 0] = d0 * inv
    tangent[row, 1] = d1 * inv
    tangent[row, 2] = d2 * inv


@numba.njit(cache=True)
def line_pass(x, particles, first, last, level, width, wet, tangents, sub, tangent):
    """
    Fill one line's submerged lengths sub[i] and tangents tangent[i] in one pass.

    :param first, last: the line's particle rows (inclusive).
    :param level, width: the water level and the ramp's width dv [m].
    :param wet: compute sub (else it is left as it is: zero when there is no water); a
        parted segment's halves each at their own particle's height (point_fraction).
    :param tangents: compute the tangents: interior unit(x[i+1] - x[i-1]), an end its
        segment's direction.
    """
    if wet:
        before = 0.0  # wetted length of the segment before particle i
        for i in range(first, last):
            if particles[i, STIFFNESS] > 0.0:  # whole
                s = wetted_fraction(x[i, 2], x[i + 1, 2], level, width) * particles[i, REST]
                sub[i] = 0.5 * (before + s)
                before = s
            else:
                # parted (parting.py): its REST, PARTED_REST = 1e300 m, is no length of
                # rope (times a wetted fraction of 6.5e-6 it displaced D = 8e294 kg, and
                # accelerate's mass along the line, a + b = m + Ca D + (CaAx - Ca) D,
                # rounded to 0: a division by zero). Half of its rope hangs at each piece's
                # end, wetted at that particle's own height: the particle's lumped length
                # less the half segment on its other side.
                half = particles[i, LENGTH] - (0.5 * particles[i - 1, REST] if i > first
                                               else 0.0)
                sub[i] = 0.5 * before + point_fraction(x[i, 2], level, width) * half
                before = 2.0 * point_fraction(x[i + 1, 2], level, width) * half
        sub[last] = 0.5 * before
    if tangents:
        _unit(x, first, first + 1, tangent, first)
        for i in range(first + 1, last):
            _unit(x, i - 1, i + 1, tangent, i)
        _unit(x, last - 1, last, tangent, last)


@numba.njit(cache=True, inline='always')
def add_line_drag(v, row, tangent, trow, c_n, c_t, u0, u1, u2, out, out_row):
    """
    Add the normal and tangential drag on particle `row` to out[out_row].

    c_n = 1/2 rho Cd d L, c_t = 1/2 rho CdAx pi d L; (u0, u1, u2): the fluid's velocity;
    tangent[trow]: the particle's unit tangent q.
    """
    w0 = u0 - v[row, 0]
    w1 = u1 - v[row, 1]
    w2 = u2 - v[row, 2]
    q0, q1, q2 = tangent[trow, 0], tangent[trow, 1], tangent[trow, 2]
    s = w0 * q0 + w1 * q1 + w2 * q2
    n0, n1, n2 = w0 - s * q0, w1 - s * q1, w2 - s * q2
    normal = c_n * np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    along = c_t * abs(s) * s
    out[out_row, 0] += normal * n0 + along * q0
    out[out_row, 1] += normal * n1 + along * q1
    out[out_row, 2] += normal * n2 + along * q2


@numba.njit(cache=True, inline='always')
def add_line_drag_block(v, row, tangent, trow, c_n, c_t, u0, u1, u2, h, block):
    """
    Add h C of add_line_drag to block (3, 3): C its minus-Jacobian in the velocity.

    C = c_n (|u_n| P + u_n u_n^T / |u_n|) + 2 c_t |u . q| q q^T, P = I - q q^T.
    """
    w0 = u0 - v[row, 0]
    w1 = u1 - v[row, 1]
    w2 = u2 - v[row, 2]
    q0, q1, q2 = tangent[trow, 0], tangent[trow, 1], tangent[trow, 2]
    s = w0 * q0 + w1 * q1 + w2 * q2
    n0, n1, n2 = w0 - s * q0, w1 - s * q1, w2 - s * q2
    size = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    a = h * c_n * size  # on P
    b = h * c_n / max(size, 1e-12)  # on u_n u_n^T
    t = 2.0 * h * c_t * abs(s) - a  # on q q^T, P's -q q^T folded in
    block[0, 0] += a + b * n0 * n0 + t * q0 * q0
    block[1, 1] += a + b * n1 * n1 + t * q1 * q1
    block[2, 2] += a + b * n2 * n2 + t * q2 * q2
    e01 = b * n0 * n1 + t * q0 * q1
    e02 = b * n0 * n2 + t * q0 * q2
    e12 = b * n1 * n2 + t * q1 * q2
    block[0, 1] += e01
    block[1, 0] += e01
    block[0, 2] += e02
    block[2, 0] += e02
    block[1, 2] += e12
    block[2, 1] += e12


@numba.njit(cache=True, inline='always')
def add_point_drag(v, row, c, u0, u1, u2, out, out_row):
    """Add the isotropic drag c |u| u (c = 1/2 rho CdA, u = U - v[row]) to out[out_row]."""
    w0 = u0 - v[row, 0]
    w1 = u1 - v[row, 1]
    w2 = u2 - v[row, 2]
    f = c * np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    out[out_row, 0] += f * w0
    out[out_row, 1] += f * w1
    out[out_row, 2] += f * w2


@numba.njit(cache=True)
def add_point_drag_block(v, row, c, u0, u1, u2, h, block):
    """Add h c (|u| I + u u^T / |u|) (add_point_drag's minus-Jacobian in v, times h)."""
    w0 = u0 - v[row, 0]
    w1 = u1 - v[row, 1]
    w2 = u2 - v[row, 2]
    size = np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    b = h * c / max(size, 1e-12)
    block[0, 0] += h * c * size + b * w0 * w0
    block[1, 1] += h * c * size + b * w1 * w1
    block[2, 2] += h * c * size + b * w2 * w2
    block[0, 1] += b * w0 * w1
    block[1, 0] += b * w0 * w1
    block[0, 2] += b * w0 * w2
    block[2, 0] += b * w0 * w2
    block[1, 2] += b * w1 * w2
    block[2, 1] += b * w1 * w2


@numba.njit(cache=True, inline='always')
def add_mass_block(a, b, tangent, trow, block):
    """Add the mass matrix a I + b q q^T (q = tangent[trow]) to block (3, 3)."""
    q0, q1, q2 = tangent[trow, 0], tangent[trow, 1], tangent[trow, 2]
    block[0, 0] += a + b * q0 * q0
    block[1, 1] += a + b * q1 * q1
    block[2, 2] += a + b * q2 * q2
    block[0, 1] += b * q0 * q1
    block[1, 0] += b * q0 * q1
    block[0, 2] += b * q0 * q2
    block[2, 0] += b * q0 * q2
    block[1, 2] += b * q1 * q2
    block[2, 1] += b * q1 * q2


@numba.njit(cache=True, inline='always')
def accelerate(a, b, tangent, trow, weight, gravity, out, row):
    """
    Replace the force out[row] by the acceleration (a I + b q q^T)^-1 (out[row] + weight g).

    The inverse in closed form, (1/a)(I - b / (a + b) q q^T) (q = tangent[trow], read only
    where b != 0); the weight (m - D) g passes through it apart, so that with no fluid
    (b = 0, weight = a = m) the result is f / m + g to the last bit.
    """
    f0, f1, f2 = out[row, 0], out[row, 1], out[row, 2]
    g0, g1, g2 = gravity[0], gravity[1], gravity[2]
    if b != 0.0:
        q0, q1, q2 = tangent[trow, 0], tangent[trow, 1], tangent[trow, 2]
        c = b / (a + b)
        s = c * (q0 * f0 + q1 * f1 + q2 * f2)
        f0 -= s * q0
        f1 -= s * q1
        f2 -= s * q2
        s = c * (q0 * g0 + q1 * g1 + q2 * g2)
        g0 -= s * q0
        g1 -= s * q1
        g2 -= s * q2
    ratio = weight / a
    out[row, 0] = f0 / a + ratio * g0
    out[row, 1] = f1 / a + ratio * g1
    out[row, 2] = f2 / a + ratio * g2
