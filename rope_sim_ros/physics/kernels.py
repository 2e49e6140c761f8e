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
Compiled (numba) loops for the rope's hot path, with the same physics as rope.py.

Pure numpy pays about 40 us of call overhead per force evaluation whatever N is, which caps
a stiff line near real time. These kernels run many steps per call. The numpy forces and
improved Euler step of rope.py / integrators.py stay the reference the tests compare with;
the strain limit (superelastic.py) is one compiled implementation shared by both paths.
"""

import numba
import numpy as np

from .rope import RopeProperties
from .superelastic import adjust


def coefficients(props: RopeProperties) -> np.ndarray:
    """Pack the line's numbers in the flat layout the kernels take (see line_forces)."""
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
    """
    Spring and damper forces of the line on every particle into `out`.

    coef = (l0, k_s, c_s, k_b, c_b, axial, drag_per_particle, particle_mass, gx, gy, gz).
    """
    out[:] = 0.0
    l0, ks, cs, kb, cb, axial = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5] > 0.5
    _add_springs(x, v, out, 1, l0, ks, cs, axial, True)
    if kb > 0.0 or cb > 0.0:
        _add_springs(x, v, out, 2, 2.0 * l0, kb, cb, axial, False)


@numba.njit(cache=True)
def end_forces(x, v, coef, out):
    """Force of the line on particle 0 and on particle N into out (2, 3) (see Rope)."""
    f = np.empty_like(x)
    line_forces(x, v, f, coef)
    half = 0.5 * coef[7]
    for p in range(3):
        out[0, p] = f[0, p] + half * coef[8 + p]
        out[1, p] = f[-1, p] + half * coef[8 + p]


@numba.njit(cache=True)
def all_finite(x, v):
    """Tell whether every position and velocity is a finite number."""
    for i in range(x.shape[0]):
        for p in range(3):
            if not (np.isfinite(x[i, p]) and np.isfinite(v[i, p])):
                return False
    return True


@numba.njit(cache=True)
def max_strain(x, segment_length):
    """Largest strain of the structural springs."""
    worst = -1.0
    for i in range(x.shape[0] - 1):
        d = np.sqrt((x[i + 1, 0] - x[i, 0]) ** 2 + (x[i + 1, 1] - x[i, 1]) ** 2
                    + (x[i + 1, 2] - x[i, 2]) ** 2)
        worst = max(worst, d / segment_length - 1.0)
    return worst


@numba.njit(cache=True)
def _accelerations(x, v, out, coef):
    line_forces(x, v, out, coef)
    drag, mass = coef[6], coef[7]
    for i in range(x.shape[0]):
        speed = np.sqrt(v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
        for d in range(3):
            out[i, d] = (out[i, d] - drag * speed * v[i, d]) / mass + coef[8 + d]


@numba.njit(cache=True)
def improved_euler_run(x, v, ends, end_velocities, dt, coef, inv_mass, max_strain,
                       adjusting, max_iterations):
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
            adjust(x, v, inv_mass, coef[0], max_strain, max_iterations)


# -- implicit Euler: the seed's scheme made implicit -----------------------------------------
#
# Backward Euler on the velocity, trapezoid on the position (Newmark gamma = 1, beta = 1/2):
#     v1 = v0 + h a1,   x1 = x0 + h (v0 + v1) / 2,   M a1 = f(x1, v1),
# linearised once per step about the predictor x^ = x0 + h v0, v0 (the ends already at their
# new places), as Baraff & Witkin (1998) do:
#     (M + h C + h^2/2 S) a1 = f(x^, v0),
# with S and C the stiffness and damping matrices of the springs (minus the force Jacobians).
# Unconditionally stable, first order, and it damps the fastest axial waves; predictors that
# extrapolate the acceleration (Newmark gamma < 1) blew up on slack-taut snaps. A rope couples
# particle i to i+1 and i+2 only, so the system is banded (half bandwidth 5 scalars, 8 with
# the bending springs) and symmetric positive definite: a banded Cholesky solves it in O(N).

@numba.njit(cache=True)
def _add_block(band, a, b, block, sign):
    """Add sign * block into the band at particle rows a, columns b (free numbering)."""
    if a < 0 or b < 0:
        return
    width = band.shape[1] - 1
    for p in range(3):
        for q in range(3):
            i, j = 3 * a + p, 3 * b + q
            if j <= i and i - j <= width:
                band[i, i - j] += sign * block[p, q]


@numba.njit(cache=True)
def _spring_block(x, i, j, rest, k, c, axial, block):
    """
    Fill block with S + C of the spring (i, j) (k, c already scaled by the step).

    S = k u u^T + (T / l)(I - u u^T), C = c u u^T (axial) or c I (seed form).
    """
    dx = x[j, 0] - x[i, 0]
    dy = x[j, 1] - x[i, 1]
    dz = x[j, 2] - x[i, 2]
    length = max(np.sqrt(dx * dx + dy * dy + dz * dz), 1e-12)
    u0, u1, u2 = dx / length, dy / length, dz / length
    # The full axial stiffness even where a segment is slack: a single linearised step that
    # expects no resistance overshoots when the segment snaps taut within the step (and then
    # blows up); overestimating it only damps that step a little. The geometric term only
    # where the spring pulls: that keeps the matrix positive definite.
    g = max(k * (length - rest), 0.0) / length
    diag = g + (0.0 if axial else c)
    along = k - g + (c if axial else 0.0)
    block[0, 0] = along * u0 * u0 + diag
    block[1, 1] = along * u1 * u1 + diag
    block[2, 2] = along * u2 * u2 + diag
    block[0, 1] = block[1, 0] = along * u0 * u1
    block[0, 2] = block[2, 0] = along * u0 * u2
    block[1, 2] = block[2, 1] = along * u1 * u2


@numba.njit(cache=True)
def _spring_jacobians(x, band, block, stride, rest, k, c, axial):
    """Add S + C of the springs (i, i + stride) to the band (free-particle numbering)."""
    n = x.shape[0]
    for i in range(n - stride):
        j = i + stride
        _spring_block(x, i, j, rest, k, c, axial, block)
        # particle 1 is unknown 0; the ends are not unknowns
        a = i - 1 if 0 < i < n - 1 else -1
        b = j - 1 if 0 < j < n - 1 else -1
        _add_block(band, a, a, block, 1.0)
        _add_block(band, b, b, block, 1.0)
        _add_block(band, b, a, block, -1.0)


@numba.njit(cache=True)
def _structural_blocks(x, diagonal, lower, block, rest, k, c, axial):
    """Add S + C of the structural springs as 3x3 blocks of a block-tridiagonal matrix."""
    m = diagonal.shape[0]
    for i in range(m + 1):  # spring i joins particles i and i + 1, unknowns i - 1 and i
        _spring_block(x, i, i + 1, rest, k, c, axial, block)
        for p in range(3):
            for q in range(3):
                if i > 0:
                    diagonal[i - 1, p, q] += block[p, q]
                if i < m:
                    diagonal[i, p, q] += block[p, q]
                if 0 < i < m:
                    lower[i - 1, p, q] -= block[p, q]  # A[i, i - 1]


@numba.njit(cache=True)
def _inverse3(a, out):
    """Invert a 3x3 matrix into out (adjugate over determinant)."""
    c00 = a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1]
    c01 = a[1, 2] * a[2, 0] - a[1, 0] * a[2, 2]
    c02 = a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]
    inv_det = 1.0 / (a[0, 0] * c00 + a[0, 1] * c01 + a[0, 2] * c02)
    out[0, 0] = c00 * inv_det
    out[1, 0] = c01 * inv_det
    out[2, 0] = c02 * inv_det
    out[0, 1] = (a[0, 2] * a[2, 1] - a[0, 1] * a[2, 2]) * inv_det
    out[1, 1] = (a[0, 0] * a[2, 2] - a[0, 2] * a[2, 0]) * inv_det
    out[2, 1] = (a[0, 1] * a[2, 0] - a[0, 0] * a[2, 1]) * inv_det
    out[0, 2] = (a[0, 1] * a[1, 2] - a[0, 2] * a[1, 1]) * inv_det
    out[1, 2] = (a[0, 2] * a[1, 0] - a[0, 0] * a[1, 2]) * inv_det
    out[2, 2] = (a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]) * inv_det


@numba.njit(cache=True)
def _block_thomas(diagonal, lower, rhs, inverse, work):
    """
    Solve the symmetric block-tridiagonal system in place; rhs (m, 3) -> solution.

    Block Thomas: diagonal[i] -= L D^-1 L^T down the chain, then back-substitution.
    inverse (m, 3, 3) and work (3, 3) are scratch.
    """
    m = diagonal.shape[0]
    _inverse3(diagonal[0], inverse[0])
    for i in range(1, m):
        low = lower[i - 1]
        prev = inverse[i - 1]
        # work = low @ prev (the multiplier), then diagonal[i] -= work @ low^T
        for p in range(3):
            for q in range(3):
                work[p, q] = (low[p, 0] * prev[0, q] + low[p, 1] * prev[1, q]
                              + low[p, 2] * prev[2, q])
        for p in range(3):
            rhs[i, p] -= (work[p, 0] * rhs[i - 1, 0] + work[p, 1] * rhs[i - 1, 1]
                          + work[p, 2] * rhs[i - 1, 2])
            for q in range(3):
                diagonal[i, p, q] -= (work[p, 0] * low[q, 0] + work[p, 1] * low[q, 1]
                                      + work[p, 2] * low[q, 2])
        _inverse3(diagonal[i], inverse[i])
    for i in range(m - 1, -1, -1):
        if i < m - 1:  # subtract A[i, i + 1] x[i + 1] = lower[i]^T x[i + 1]
            low = lower[i]
            for p in range(3):
                rhs[i, p] -= (low[0, p] * rhs[i + 1, 0] + low[1, p] * rhs[i + 1, 1]
                              + low[2, p] * rhs[i + 1, 2])
        inv = inverse[i]
        r0, r1, r2 = rhs[i, 0], rhs[i, 1], rhs[i, 2]
        for p in range(3):
            rhs[i, p] = inv[p, 0] * r0 + inv[p, 1] * r1 + inv[p, 2] * r2


@numba.njit(cache=True)
def _cholesky_solve(band, rhs):
    """Solve the banded SPD system in place (band[i, i - j] = A[i, j]); return rhs."""
    n = band.shape[0]
    width = band.shape[1] - 1
    for i in range(n):
        for j in range(max(0, i - width), i + 1):
            s = band[i, i - j]
            for p in range(max(0, i - width, j - width), j):
                s -= band[i, i - p] * band[j, j - p]
            if i == j:
                band[i, 0] = np.sqrt(max(s, 1e-300))
            else:
                band[i, i - j] = s / band[j, 0]
    for i in range(n):
        s = rhs[i]
        for p in range(max(0, i - width), i):
            s -= band[i, i - p] * rhs[p]
        rhs[i] = s / band[i, 0]
    for i in range(n - 1, -1, -1):
        s = rhs[i]
        for p in range(i + 1, min(n, i + width + 1)):
            s -= band[p, p - i] * rhs[p]
        rhs[i] = s / band[i, 0]
    return rhs


@numba.njit(cache=True)
def implicit_euler_run(x, v, ends, end_velocities, dt, coef, inv_mass, max_strain,
                       adjusting, max_iterations, implicit_bending):
    """
    Take len(ends) implicit Euler steps in place (arguments as improved_euler_run).

    implicit_bending: put the bending springs in the matrix too (needed only when they are
    stiff enough to limit an explicit step; it widens the band from 5 to 8).
    """
    n = x.shape[0]
    last = n - 1
    m = n - 2  # unknowns: the free particles
    l0, ks, cs, kb, cb, axial = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5] > 0.5
    drag, mass = coef[6], coef[7]
    half_h2 = 0.5 * dt * dt
    f = np.empty_like(x)
    block = np.empty((3, 3))
    rhs = np.empty((m, 3))
    # structural springs only: 3x3 block-tridiagonal (block Thomas); with the bending
    # springs the band is wider (banded Cholesky)
    band = np.empty((3 * m, 9) if implicit_bending else (0, 0))
    diagonal = np.empty((m, 3, 3))
    lower = np.empty((max(m - 1, 0), 3, 3))
    inverse = np.empty((m, 3, 3))
    for k in range(ends.shape[0]):
        for i in range(1, last):
            for p in range(3):
                x[i, p] += dt * v[i, p]
        for p in range(3):
            x[0, p], x[last, p] = ends[k, 0, p], ends[k, 1, p]
            v[0, p], v[last, p] = end_velocities[k, 0, p], end_velocities[k, 1, p]
        line_forces(x, v, f, coef)
        diagonal[:] = 0.0
        lower[:] = 0.0
        if implicit_bending:
            band[:] = 0.0
            _spring_jacobians(x, band, block, 1, l0, ks * half_h2, cs * dt, axial)
            _spring_jacobians(x, band, block, 2, 2.0 * l0, kb * half_h2, cb * dt, axial)
        else:
            _structural_blocks(x, diagonal, lower, block, l0, ks * half_h2, cs * dt, axial)
        for i in range(1, last):
            speed = np.sqrt(v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
            for p in range(3):
                rhs[i - 1, p] = f[i, p] - drag * speed * v[i, p] + mass * coef[8 + p]
                # mass, and the drag Jacobian kappa (|v| I + v v^T / |v|)
                for q in range(3):
                    jac = dt * drag * v[i, p] * v[i, q] / max(speed, 1e-12)
                    if p == q:
                        jac += dt * drag * speed + mass
                    if implicit_bending:
                        if q <= p:
                            band[3 * (i - 1) + p, p - q] += jac
                    else:
                        diagonal[i - 1, p, q] += jac
        if implicit_bending:
            _cholesky_solve(band, rhs.reshape(3 * m))
        else:
            _block_thomas(diagonal, lower, rhs, inverse, block)
        for i in range(1, last):
            for p in range(3):
                x[i, p] += half_h2 * rhs[i - 1, p]
                v[i, p] += dt * rhs[i - 1, p]
        if adjusting:
            adjust(x, v, inv_mass, l0, max_strain, max_iterations)
