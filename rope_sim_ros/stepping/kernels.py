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
The integrators: improved Euler and implicit Euler over a whole System, compiled (numba).

The forces at a state are model/forces/assembly.py's; here they are stepped through time.
Each kernel takes a run of steps of one System in place (its arrays as one record:
model/record.py's SystemArrays), its driven points at the samples it is given, its free
points moving with the lines. Tests run these same functions interpreted (``.py_func``).
"""

from typing import NamedTuple

import numba
import numpy as np

from ..model.forces.assembly import (accelerations, has_contact, line_forces, line_passes,
                                     particle_accelerations, particle_environment,
                                     particle_environment_block, point_environment,
                                     point_environment_block, set_ends)
from ..model.forces.body import (body_loads, finish_modes, lever_of, mass_matrix, place_points,
                                 rotation_of, start_modes, turn)
from ..model.forces.drag import add_drag, add_drag_block
from ..model.forces.gravity import add_weight
from ..model.forces.springs import spring_block_at
from ..model.layout import (ADJUST, AXIAL, BODY_ACCEL, BODY_CLOCK, BODY_MODE, BODY_MODES,
                            BODY_OMEGA, BODY_POSITION, BODY_VELOCITY, CARRIED, DRAG, DRIVEN, END_A,
                            ENV_GRAVITY, FIRST, FLUID, FREE, HISTORY, INV_MASS, KIND, LAST, MASS,
                            MAX_STRAIN, MODE_COLUMNS, OWN_MASS, POINT_BODY, REST, TANGENTS)
from ..model.linalg import dense_cholesky_solve, inverse3
from ..model.parting import check_segments, hold_peaks
from ..model.superelastic import adjust, over_limit
from ..model.winch import pay_out, render


@numba.njit(cache=True, inline='always')
def _set_ends_at(x, v, lines, points, point_x, point_v, drive_x, drive_v, k):
    """Put every line end on its fixed point, or on its driven point's k-th sample."""
    for line in range(lines.shape[0]):
        for e in range(2):
            q = lines[line, END_A + e]
            row = lines[line, FIRST] if e == 0 else lines[line, LAST]
            if points[q, KIND] == DRIVEN:
                for p in range(3):
                    x[row, p] = drive_x[k, q, p]
                    v[row, p] = drive_v[k, q, p]
            else:
                for p in range(3):
                    x[row, p] = point_x[q, p]
                    v[row, p] = point_v[q, p]


@numba.njit(cache=True, inline='always')
def _limit_kinematic_strains(x, v, inv_mass, rest, lines, line_real, max_iterations):
    """
    Apply the strain limit to every line that asks for it, when no point is free.

    The ends (inverse mass 0) do not move; the projection itself returns at once when no
    spring is over its limit.
    """
    for k in range(lines.shape[0]):
        first, last = lines[k, FIRST], lines[k, LAST]
        if lines[k, ADJUST] == 1 and over_limit(x, rest, first, last, line_real[k, MAX_STRAIN]):
            adjust(x[first:last + 1], v[first:last + 1], inv_mass[first:last + 1],
                   rest[first:last], line_real[k, MAX_STRAIN], max_iterations)


@numba.njit(cache=True, inline='always')
def _drive(points, point_x, point_v, drive_x, drive_v, k):
    """Move the driven points to their k-th sample."""
    for q in range(points.shape[0]):
        if points[q, KIND] == DRIVEN:
            for p in range(3):
                point_x[q, p] = drive_x[k, q, p]
                point_v[q, p] = drive_v[k, q, p]


@numba.njit(cache=True)
def _limit_strains(x, v, inv_mass, rest, lines, line_real, points, point_x, point_v,
                   max_iterations):
    """
    Apply the strain-limit projection (superelastic.adjust) to every line that asks for it.

    Line by line: a free point shared by several lines is moved by each line's projection in
    turn (its end particle carries the point's whole lumped mass), and the next line starts
    from where the previous one left it. Exact for one line per free point; with several, a
    later line may pull a shared point back over an earlier line's limit by a little, which
    the next step's projection takes up.
    """
    for k in range(lines.shape[0]):
        if lines[k, ADJUST] != 1:
            continue
        first, last = lines[k, FIRST], lines[k, LAST]
        for e in range(2):  # from the point, as an earlier line may have moved it
            q = lines[k, END_A + e]
            row = first if e == 0 else last
            for p in range(3):
                x[row, p] = point_x[q, p]
                v[row, p] = point_v[q, p]
        adjust(x[first:last + 1], v[first:last + 1], inv_mass[first:last + 1],
               rest[first:last], line_real[k, MAX_STRAIN], max_iterations)
        for e in range(2):
            q = lines[k, END_A + e]
            if points[q, KIND] == FREE:
                row = first if e == 0 else last
                for p in range(3):
                    point_x[q, p] = x[row, p]
                    point_v[q, p] = v[row, p]
    set_ends(x, v, lines, point_x, point_v)


@numba.njit(cache=True)
def _after_step(x, v, particles, lines, line_real, points, rest, inv_mass, dt, step, gravity,
                scratch):
    """After step `step` of a run: brakes render, lines part or are watched, peaks are held."""
    render(x, particles, lines, line_real, points, rest, inv_mass, dt)
    check_segments(x, v, particles, lines, line_real, rest, step)
    hold_peaks(x, v, particles, lines, line_real, gravity, scratch)


# -- improved Euler (the seed's eq. 7: Heun's method) ----------------------------------------

@numba.njit(cache=True)
def improved_euler_run(arrays, drive_x, drive_v, dt, max_iterations):
    """
    Take len(drive_x) improved Euler steps of the whole system in place.

    :param arrays: the System's arrays (model/record.py's SystemArrays): the particles' x,
        v (P, 3), every line's rows stacked; the points' point_x, point_v (Q, 3); the
        tables of layout.py (particles, lines, line_real, points; env: gravity, water, air,
        current, seabed, quay; bodies, fenders: the bodies' state is stepped in place, their
        carried points follow them).
    :param drive_x, drive_v: driven points' positions and velocities at the end of each step
        (n, Q, 3) (rows of other points ignored).
    """
    x, v, point_x, point_v = arrays.x, arrays.v, arrays.point_x, arrays.point_v
    particles, lines, line_real, points = (arrays.particles, arrays.lines, arrays.line_real,
                                           arrays.points)
    env, bodies, fenders = arrays.env, arrays.bodies, arrays.fenders
    n_points = points.shape[0]
    gravity = env[ENV_GRAVITY:ENV_GRAVITY + 3]
    contact = has_contact(env)
    sub = np.zeros(x.shape[0])  # submerged length of each particle
    tangent = np.zeros_like(x)  # unit tangent of each particle
    iso = np.zeros(n_points)  # a free point's mass matrix: iso I + aniso
    aniso = np.zeros((n_points, 3, 3))
    work = np.empty((3, 3))
    inv_mass = np.ascontiguousarray(particles[:, INV_MASS])  # for the strain limit
    rest = np.ascontiguousarray(particles[:, REST])
    a1 = np.empty_like(x)
    a2 = np.empty_like(x)
    xp = np.empty_like(x)
    vp = np.empty_like(x)
    pa1 = np.zeros((n_points, 3))
    pa2 = np.zeros((n_points, 3))
    pxp = np.empty((n_points, 3))
    pvp = np.empty((n_points, 3))
    scratch = np.empty_like(x)
    if not _moving_points(points) and bodies.shape[0] == 0:  # every end fixed or driven
        for k in range(drive_x.shape[0]):
            line_forces(x, v, a1, particles, lines, line_real)
            line_passes(x, particles, lines, line_real, env, sub, tangent)
            particle_accelerations(x, v, a1, particles, lines, line_real, env, gravity,
                                   contact, sub, tangent)
            # the winch's rest lengths of the step's end, for its second stage
            pay_out(x, v, particles, lines, line_real, points, rest, inv_mass, dt, gravity)
            for i in range(x.shape[0]):
                for d in range(3):
                    xp[i, d] = x[i, d] + dt * v[i, d]
                    vp[i, d] = v[i, d] + dt * a1[i, d]
            _set_ends_at(xp, vp, lines, points, point_x, point_v, drive_x, drive_v, k)
            line_forces(xp, vp, a2, particles, lines, line_real)
            line_passes(xp, particles, lines, line_real, env, sub, tangent)
            particle_accelerations(xp, vp, a2, particles, lines, line_real, env, gravity,
                                   contact, sub, tangent)
            for i in range(x.shape[0]):
                for d in range(3):
                    x[i, d] += 0.5 * dt * (v[i, d] + vp[i, d])
                    v[i, d] += 0.5 * dt * (a1[i, d] + a2[i, d])
            _drive(points, point_x, point_v, drive_x, drive_v, k)
            set_ends(x, v, lines, point_x, point_v)
            _limit_kinematic_strains(x, v, inv_mass, rest, lines, line_real, max_iterations)
            _after_step(x, v, particles, lines, line_real, points, rest, inv_mass, dt, k,
                        gravity, scratch)
        return
    body_a1 = np.zeros((bodies.shape[0], 6))
    body_a2 = np.zeros((bodies.shape[0], 6))
    predicted = bodies.copy()  # the bodies at the end of the first stage
    for k in range(drive_x.shape[0]):
        accelerations(x, v, a1, particles, lines, line_real, points, point_x, point_v, env,
                      gravity, contact, sub, tangent, pa1, iso, aniso, work, bodies, fenders,
                      body_a1)
        pay_out(x, v, particles, lines, line_real, points, rest, inv_mass, dt, gravity)
        for i in range(x.shape[0]):
            for d in range(3):
                xp[i, d] = x[i, d] + dt * v[i, d]
                vp[i, d] = v[i, d] + dt * a1[i, d]
        for q in range(n_points):
            kind = points[q, KIND]
            for d in range(3):
                if kind == DRIVEN:
                    pxp[q, d], pvp[q, d] = drive_x[k, q, d], drive_v[k, q, d]
                elif kind == FREE:
                    pxp[q, d] = point_x[q, d] + dt * point_v[q, d]
                    pvp[q, d] = point_v[q, d] + dt * pa1[q, d]
                else:
                    pxp[q, d], pvp[q, d] = point_x[q, d], point_v[q, d]
        if bodies.shape[0] > 0:
            _euler_bodies(bodies, body_a1, dt, predicted)
            place_points(predicted, points, pxp, pvp)
        set_ends(xp, vp, lines, pxp, pvp)
        accelerations(xp, vp, a2, particles, lines, line_real, points, pxp, pvp, env,
                      gravity, contact, sub, tangent, pa2, iso, aniso, work, predicted,
                      fenders, body_a2)
        for i in range(x.shape[0]):
            for d in range(3):
                x[i, d] += 0.5 * dt * (v[i, d] + vp[i, d])
                v[i, d] += 0.5 * dt * (a1[i, d] + a2[i, d])
        for q in range(n_points):
            if points[q, KIND] == FREE:
                for d in range(3):
                    point_x[q, d] += 0.5 * dt * (point_v[q, d] + pvp[q, d])
                    point_v[q, d] += 0.5 * dt * (pa1[q, d] + pa2[q, d])
        if bodies.shape[0] > 0:
            _heun_bodies(bodies, predicted, body_a1, body_a2, dt)
            place_points(bodies, points, point_x, point_v)
        _drive(points, point_x, point_v, drive_x, drive_v, k)
        set_ends(x, v, lines, point_x, point_v)
        _limit_strains(x, v, inv_mass, rest, lines, line_real, points, point_x, point_v,
                       max_iterations)
        _after_step(x, v, particles, lines, line_real, points, rest, inv_mass, dt, k, gravity,
                    scratch)


@numba.njit(cache=True, inline='always')
def _moving_points(points):
    """Tell whether a point moves with the lines: a free point, or one a body carries."""
    for q in range(points.shape[0]):
        if points[q, KIND] == FREE or points[q, KIND] == CARRIED:
            return True
    return False


@numba.njit(cache=True)
def _euler_bodies(bodies, accel, dt, out):
    """
    Put the bodies one Euler step of dt ahead into out (improved Euler's first stage).

    Their radiation memory's modes are stepped exactly over dt for velocities linear from
    the body's to out's (forces/body.py).
    """
    for b in range(bodies.shape[0]):
        for c in range(BODY_MODE + int(bodies[b, BODY_MODES]) * MODE_COLUMNS):  # the rest unused
            out[b, c] = bodies[b, c]
        start_modes(out[b], dt)
        for p in range(3):
            out[b, BODY_POSITION + p] += dt * bodies[b, BODY_VELOCITY + p]
            out[b, BODY_VELOCITY + p] += dt * accel[b, p]
            out[b, BODY_OMEGA + p] += dt * accel[b, 3 + p]
        turn(out[b], dt * bodies[b, BODY_OMEGA], dt * bodies[b, BODY_OMEGA + 1],
             dt * bodies[b, BODY_OMEGA + 2])
        out[b, BODY_CLOCK] += dt
        finish_modes(out[b], dt)


@numba.njit(cache=True)
def _heun_bodies(bodies, predicted, accel, accel_predicted, dt):
    """
    Finish the bodies' improved Euler step: the mean of both stages' rates (in place).

    Their radiation memory's modes as in _euler_bodies, to the step's end.
    """
    for b in range(bodies.shape[0]):
        body = bodies[b]
        start_modes(body, dt)
        rx = 0.5 * dt * (body[BODY_OMEGA] + predicted[b, BODY_OMEGA])
        ry = 0.5 * dt * (body[BODY_OMEGA + 1] + predicted[b, BODY_OMEGA + 1])
        rz = 0.5 * dt * (body[BODY_OMEGA + 2] + predicted[b, BODY_OMEGA + 2])
        for p in range(3):
            body[BODY_POSITION + p] += 0.5 * dt * (body[BODY_VELOCITY + p]
                                                   + predicted[b, BODY_VELOCITY + p])
            body[BODY_VELOCITY + p] += 0.5 * dt * (accel[b, p] + accel_predicted[b, p])
            body[BODY_OMEGA + p] += 0.5 * dt * (accel[b, 3 + p] + accel_predicted[b, 3 + p])
        turn(body, rx, ry, rz)
        body[BODY_CLOCK] += dt
        finish_modes(body, dt)


# -- implicit Euler: the seed's scheme made implicit -----------------------------------------
#
# Backward Euler on the velocity, trapezoid on the position (Newmark gamma = 1, beta = 1/2):
#     v1 = v0 + h a1,   x1 = x0 + h (v0 + v1) / 2,   M a1 = f(x1, v1),
# linearised once per step about the predictor x^ = x0 + h v0, v0 (driven points already at
# their new places), as Baraff & Witkin (1998) do:
#     (M + h C + h^2/2 S) a1 = f(x^, v0),
# with S and C the stiffness and damping matrices of the forces (minus their Jacobians).
# Unconditionally stable, first order, and it damps the fastest axial waves; predictors that
# extrapolate the acceleration (Newmark gamma < 1) blew up on slack-taut snaps. The adaptive
# integrator (adaptive.py) takes them all the same, Newmark's general step
#     x1 = x0 + h v0 + h^2 ((1/2 - beta) a0 + beta a1),   v1 = v0 + h ((1 - gamma) a0 + gamma a1),
#     (M + gamma h C + beta h^2 S) a1 = f(x^, v^)   about that predictor,
# because it takes every step in which a snap starts again with improved Euler; a0 is the
# acceleration the step before solved for (accel, point_accel).
#
# The unknowns are the accelerations of every line's interior particles and of every free
# point. A line couples particle i to i+1 and i+2 only: its interior block A_k is
# block-tridiagonal (structural springs: block Thomas) or banded (with the bending springs:
# half bandwidth 8 scalars, banded Cholesky), solved in O(N). Free points couple lines: B_k
# (interior rows x the free ends' point columns) is nonzero only next to the ends, and the
# points' own block D holds their masses and the end springs. The points are solved through
# the Schur complement S = D - sum_k B_k^T A_k^-1 B_k (small, dense, SPD: Cholesky), then
# every line's interior by back-substitution: a_k = A_k^-1 (r_k - B_k a_points).

@numba.njit(cache=True)
def _block_thomas_factor(diagonal, lower, inverse, multiplier, m):
    """
    Factor the symmetric block-tridiagonal matrix of m blocks (block Thomas).

    diagonal[i] -= L D^-1 L^T down the chain; inverse[i] gets the inverse of the reduced
    diagonal block, multiplier[i] = lower[i - 1] inverse[i - 1].
    """
    inverse3(diagonal[0], inverse[0])
    for i in range(1, m):
        low = lower[i - 1]
        prev = inverse[i - 1]
        work = multiplier[i]
        for p in range(3):
            for q in range(3):
                work[p, q] = (low[p, 0] * prev[0, q] + low[p, 1] * prev[1, q]
                              + low[p, 2] * prev[2, q])
        for p in range(3):
            for q in range(3):
                diagonal[i, p, q] -= (work[p, 0] * low[q, 0] + work[p, 1] * low[q, 1]
                                      + work[p, 2] * low[q, 2])
        inverse3(diagonal[i], inverse[i])


@numba.njit(cache=True)
def _block_thomas_solve(lower, inverse, multiplier, rhs, m):
    """Solve with the factors of _block_thomas_factor in place; rhs (>= m, 3) -> solution."""
    for i in range(1, m):
        work = multiplier[i]
        for p in range(3):
            rhs[i, p] -= (work[p, 0] * rhs[i - 1, 0] + work[p, 1] * rhs[i - 1, 1]
                          + work[p, 2] * rhs[i - 1, 2])
    _back_substitute(lower, inverse, rhs, m)


@numba.njit(cache=True, inline='always')
def _back_substitute(lower, inverse, rhs, m):
    """Finish a block Thomas solve: back-substitution up the chain; rhs (>= m, 3)."""
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
def _block_thomas(diagonal, lower, inverse, work, rhs, m):
    """
    Solve the symmetric block-tridiagonal system of m blocks in place; rhs (>= m, 3).

    _block_thomas_factor and _block_thomas_solve in one pass down the chain, for a single
    right-hand side: the multipliers are not kept (work (3, 3) holds the current one).
    """
    inverse3(diagonal[0], inverse[0])
    for i in range(1, m):
        low = lower[i - 1]
        prev = inverse[i - 1]
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
        inverse3(diagonal[i], inverse[i])
    _back_substitute(lower, inverse, rhs, m)


@numba.njit(cache=True)
def _cholesky_factor(band, n):
    """Factor the banded SPD matrix of size n in place (band[i, i - j] = A[i, j])."""
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


@numba.njit(cache=True)
def _cholesky_band_solve(band, rhs, n):
    """Solve with the factor of _cholesky_factor in place; rhs (>= n,) -> solution."""
    width = band.shape[1] - 1
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


@numba.njit(cache=True, inline='always')
def _add_band(band, a, b, block, sign):
    """Add sign * block into the band at unknown rows a, columns b (lower triangle only)."""
    width = band.shape[1] - 1
    for p in range(3):
        for q in range(3):
            i, j = 3 * a + p, 3 * b + q
            if j <= i and i - j <= width:
                band[i, i - j] += sign * block[p, q]


@numba.njit(cache=True, inline='always')
def _scatter(block, i, j, first, last, end_col, end_free, free_index, banded, band, diagonal,
             lower, coupling, schur):
    """
    Add a spring's block K between particles i < j of one line into the step's matrices.

    The full matrix gets K at (i, i) and (j, j), -K at (i, j) and (j, i). An interior particle
    is an unknown of the line's A (band or block tridiagonal); a line end on a free point is
    that point's unknown (the Schur system `schur`, the coupling B `coupling`); an end on a
    fixed or driven point is no unknown.
    """
    ii = i - first - 1 if first < i < last else -1
    jj = j - first - 1 if first < j < last else -1
    pi = -1
    pj = -1
    ci = 0
    cj = 0
    if ii < 0:
        e = 0 if i == first else 1
        if end_free[e]:
            pi, ci = free_index[e], end_col[e]
    if jj < 0:
        e = 0 if j == first else 1
        if end_free[e]:
            pj, cj = free_index[e], end_col[e]
    if banded:
        if ii >= 0:
            _add_band(band, ii, ii, block, 1.0)
        if jj >= 0:
            _add_band(band, jj, jj, block, 1.0)
        if ii >= 0 and jj >= 0:
            _add_band(band, jj, ii, block, -1.0)
    else:
        for p in range(3):
            for q in range(3):
                if ii >= 0:
                    diagonal[ii, p, q] += block[p, q]
                if jj >= 0:
                    diagonal[jj, p, q] += block[p, q]
                if ii >= 0 and jj >= 0:
                    lower[ii, p, q] -= block[p, q]  # A[j, i] with j = i + 1
    if pi < 0 and pj < 0:
        return
    for p in range(3):
        for q in range(3):
            if pi >= 0:
                schur[3 * pi + p, 3 * pi + q] += block[p, q]
            if pj >= 0:
                schur[3 * pj + p, 3 * pj + q] += block[p, q]
            if pi >= 0 and pj >= 0:
                schur[3 * pi + p, 3 * pj + q] -= block[p, q]
                schur[3 * pj + p, 3 * pi + q] -= block[p, q]
            if ii >= 0 and pj >= 0:
                coupling[ii, p, cj + q] -= block[p, q]
            if jj >= 0 and pi >= 0:
                coupling[jj, p, ci + q] -= block[p, q]


@numba.njit(cache=True, inline='always')
def _add_band_spring(band, a, b, m, block):
    """Add a spring's block between unknowns a < b (-1 or m: an end, no unknown) to the band."""
    if a >= 0:
        _add_band(band, a, a, block, 1.0)
    if b < m:
        _add_band(band, b, b, block, 1.0)
        if a >= 0:
            _add_band(band, b, a, block, -1.0)


@numba.njit(cache=True, inline='always')
def _add_chain_block(diagonal, lower, u, m, block):
    """Add the block of structural spring u (unknowns u - 1 and u) to a line's A."""
    for p in range(3):
        for q in range(3):
            if u > 0:
                diagonal[u - 1, p, q] += block[p, q]
            if u < m:
                diagonal[u, p, q] += block[p, q]
            if 0 < u < m:
                lower[u - 1, p, q] -= block[p, q]


@numba.njit(cache=True, inline='always')
def _particle_system(x, v, f, i, particles, line_real, k, environment, tangents, contact, env,
                     gravity, sub, tangent, dt, half_h2, rhs, local, block):
    """
    Set particle i's (line k's) right-hand side rhs[local] and its diagonal block.

    rhs: its spring force f[i] plus drag, contact, weight and buoyancy; block: its mass
    matrix (added mass in) + h C + h^2/2 S of the drag and the contact. environment: the
    line has fluid terms or something to touch (else only the seed's terms).
    """
    for p in range(3):
        rhs[local, p] = f[i, p]
    mass = particles[i, MASS]
    a, b, weight = mass, 0.0, mass
    if environment:
        a, b, weight = particle_environment(x, v, i, particles, line_real, k, tangents,
                                            contact, env, sub, tangent, rhs, local)
    add_drag(v, i, particles[i, DRAG], rhs, local)
    add_weight(rhs, local, weight, gravity)
    block[:] = 0.0
    add_drag_block(v, i, dt * particles[i, DRAG], a, block)
    if environment:
        particle_environment_block(x, v, i, particles, line_real, k, tangents, contact, env, sub,
                                   tangent, b, dt, half_h2, block)


class _LineWork(NamedTuple):
    """An implicit run's scratch: the forces at the predictor, one line's system at a time."""

    inv_mass: np.ndarray  # (P,) the strain limit's inverse masses (layout.INV_MASS)
    rest: np.ndarray  # (P,) the springs' rest lengths (layout.REST; the winch changes them)
    f: np.ndarray  # (P, 3) the springs' forces
    sub: np.ndarray  # (P,) submerged length of each particle
    tangent: np.ndarray  # (P, 3) unit tangent of each particle
    block: np.ndarray  # (3, 3) one spring's or one particle's block
    rhs_flat: np.ndarray  # (3 W,) a line's right-hand side, then its solution (W: the most
    rhs: np.ndarray  # (W, 3) interior particles of any line); the same by particle
    band: np.ndarray  # (3 W, 9) A banded (with the bending springs), else (0, 0)
    diagonal: np.ndarray  # (W, 3, 3) A block tridiagonal: its diagonal blocks,
    lower: np.ndarray  # (W, 3, 3) those below it,
    inverse: np.ndarray  # (W, 3, 3) and block Thomas's factors
    multiplier: np.ndarray  # (W, 3, 3)


class _PointWork(NamedTuple):
    """An implicit run's scratch where points are free or carried: the point system."""

    free_of: np.ndarray  # (Q,) each point's row among the point unknowns, -1 for none
    schur: np.ndarray  # (3 F, 3 F) the point system S (F: free and carried points)
    point_rhs: np.ndarray  # (3 F,) its right-hand side g, then the points' accelerations
    point_force: np.ndarray  # (1, 3) a free point's own load
    end_force: np.ndarray  # (1, 3) a line end's load on its point
    coupling: np.ndarray  # (W, 3, 6) a line's B: end A's point's columns, then end B's
    solved_coupling: np.ndarray  # (P, 3, 6) every line's A^-1 B, by particle row
    column: np.ndarray  # (3 W,) one column of B, then of A^-1 B
    column_blocks: np.ndarray  # (W, 3) the same by particle
    end_free: np.ndarray  # (2,) a line's ends: on a free or carried point
    free_index: np.ndarray  # (2,) their points' rows among the unknowns
    solution: np.ndarray  # (P, 3) the interior particles' accelerations
    transform: np.ndarray  # the bodies' condensed system (_body_arrays; empty without)
    reduced: np.ndarray
    reduced_rhs: np.ndarray
    body_accel: np.ndarray  # (B, 6) the bodies' accelerations


@numba.njit(cache=True, inline='always')
def _line_work(arrays, implicit_bending):
    """Return an implicit run's _LineWork for these arrays' lines."""
    x, particles, lines = arrays.x, arrays.particles, arrays.lines
    widest = 1
    for k in range(lines.shape[0]):
        widest = max(widest, lines[k, LAST] - lines[k, FIRST] - 1)
    rhs_flat = np.empty(3 * widest)
    # structural springs only: 3x3 block-tridiagonal (block Thomas); with the bending
    # springs the band is wider (banded Cholesky)
    return _LineWork(np.ascontiguousarray(particles[:, INV_MASS]),
                     np.ascontiguousarray(particles[:, REST]), np.empty_like(x),
                     np.zeros(x.shape[0]), np.zeros_like(x), np.empty((3, 3)), rhs_flat,
                     rhs_flat.reshape(widest, 3),
                     np.empty((3 * widest, 9) if implicit_bending else (0, 0)),
                     np.empty((widest, 3, 3)), np.empty((widest, 3, 3)),
                     np.empty((widest, 3, 3)), np.empty((widest, 3, 3)))


@numba.njit(cache=True, inline='always')
def _point_work(arrays, widest):
    """Return an implicit run's _PointWork: free and carried points are its unknowns."""
    points, n_bodies = arrays.points, arrays.bodies.shape[0]
    free_of = np.full(points.shape[0], -1, dtype=np.int64)
    n_free = 0
    for q in range(points.shape[0]):
        if points[q, KIND] == FREE or points[q, KIND] == CARRIED:
            free_of[q] = n_free
            n_free += 1
    column = np.empty(3 * widest)
    if n_bodies > 0:
        transform, reduced, reduced_rhs, body_accel = _body_arrays(points, free_of, n_free,
                                                                   n_bodies)
    else:
        transform, reduced, reduced_rhs, body_accel = (np.zeros((0, 0)), np.empty((0, 0)),
                                                       np.empty(0), np.zeros((0, 6)))
    return _PointWork(free_of, np.empty((3 * n_free, 3 * n_free)), np.empty(3 * n_free),
                      np.empty((1, 3)), np.empty((1, 3)), np.empty((widest, 3, 6)),
                      np.zeros((arrays.x.shape[0], 3, 6)), column, column.reshape(widest, 3),
                      np.zeros(2, dtype=np.bool_),
                      np.zeros(2, dtype=np.int64), np.zeros_like(arrays.x), transform, reduced,
                      reduced_rhs, body_accel)


@numba.njit(cache=True, inline='always')
def _implicit_kinematic_line(k, x, v, accel, f, sub, tangent, particles, lines, line_real,
                             env, contact, gravity, implicit_bending, dt, half_h2, block, rhs,
                             rhs_flat, band, diagonal, lower, inverse):
    """
    Take the implicit step of line k, whose two ends are on fixed or driven points.

    The general assembly without the free points' bookkeeping: the line's interior is the
    whole system, solved and applied at once. dt, half_h2: the step's h gamma, h^2 beta.
    """
    first, last = lines[k, FIRST], lines[k, LAST]
    axial = lines[k, AXIAL] == 1
    environment = lines[k, FLUID] == 1 or contact
    tangents = lines[k, TANGENTS] == 1
    m = last - first - 1
    if m <= 0:
        return
    if implicit_bending:
        band[:3 * m] = 0.0
        for i in range(first, last):
            spring_block_at(x, particles, i, False, half_h2, dt, axial, block, line_real[k])
            _add_band_spring(band, i - first - 1, i - first, m, block)
        for i in range(first, last - 1):
            spring_block_at(x, particles, i, True, half_h2, dt, axial, block, line_real[k])
            _add_band_spring(band, i - first - 1, i - first + 1, m, block)
    else:
        diagonal[:m] = 0.0
        lower[:m] = 0.0
        for i in range(first, last):
            spring_block_at(x, particles, i, False, half_h2, dt, axial, block, line_real[k])
            _add_chain_block(diagonal, lower, i - first, m, block)
    for i in range(first + 1, last):
        local = i - first - 1
        _particle_system(x, v, f, i, particles, line_real, k, environment, tangents, contact,
                         env, gravity, sub, tangent, dt, half_h2, rhs, local, block)
        if implicit_bending:
            _add_band(band, local, local, block, 1.0)
        else:
            for p in range(3):
                for q in range(3):
                    diagonal[local, p, q] += block[p, q]
    if implicit_bending:
        _cholesky_factor(band, 3 * m)
        _cholesky_band_solve(band, rhs_flat, 3 * m)
    else:
        _block_thomas(diagonal, lower, inverse, block, rhs, m)
    for i in range(m):
        for p in range(3):
            x[first + 1 + i, p] += half_h2 * rhs[i, p]
            v[first + 1 + i, p] += dt * rhs[i, p]
            accel[first + 1 + i, p] = rhs[i, p]


@numba.njit(cache=True, inline='always')
def _newmark(k, newmark, ready, dt):
    """
    Return step k's (h gamma, h^2 beta, (1/2 - beta) h^2, (1 - gamma) h) of a run.

    newmark: (gamma, beta). The first step of a run on lines not ready (their accelerations
    are not their last step's: HISTORY 0) takes gamma 1, beta 1/2, which need none.
    """
    gamma, beta = newmark
    if k == 0 and not ready:
        gamma, beta = 1.0, 0.5
    return gamma * dt, beta * dt * dt, (0.5 - beta) * dt * dt, (1.0 - gamma) * dt


@numba.njit(cache=True, inline='always')
def _predict_rows(x, v, accel, dt, ahead_x, ahead_v, first, stop):
    """
    Rows first..stop-1's predictor: x += h v + ahead_x a0, v += ahead_v a0 (a0: accel).

    Without a0 terms (implicit Euler), accel is not read: it may hold what a state restarted
    since left there, even NaN.
    """
    if ahead_x == 0.0 and ahead_v == 0.0:
        for i in range(first, stop):
            for p in range(3):
                x[i, p] += dt * v[i, p]
        return
    for i in range(first, stop):
        for p in range(3):
            x[i, p] += dt * v[i, p] + ahead_x * accel[i, p]
            v[i, p] += ahead_v * accel[i, p]


@numba.njit(cache=True)
def _implicit_kinematic_steps(arrays, work, drive_x, drive_v, dt, max_iterations,
                              implicit_bending, newmark):
    """
    Take implicit_euler_run's steps when no point is free (work: its _LineWork).

    Each line alone, from its own history: the predictor, the forces there, then line by
    line its system assembled, solved and applied (_implicit_kinematic_line). Compiled on
    its own, not inlined into implicit_euler_run: inlined (once for each matrix kind) it
    took a third of the two minutes numba spent compiling that kernel, for no speed.
    """
    x, v, accel = arrays.x, arrays.v, arrays.accel
    point_x, point_v = arrays.point_x, arrays.point_v
    particles, lines, line_real, points = (arrays.particles, arrays.lines, arrays.line_real,
                                           arrays.points)
    env = arrays.env
    (inv_mass, rest, f, sub, tangent, block, rhs_flat, rhs, band, diagonal, lower, inverse,
     _) = work
    gravity = env[ENV_GRAVITY:ENV_GRAVITY + 3]
    contact = has_contact(env)
    for k in range(drive_x.shape[0]):
        pay_out(x, v, particles, lines, line_real, points, rest, inv_mass, dt, gravity)
        for line in range(lines.shape[0]):  # each line from its own history
            _, _, ahead_x, ahead_v = _newmark(k, newmark, line_real[line, HISTORY] > 0.0, dt)
            _predict_rows(x, v, accel, dt, ahead_x, ahead_v, lines[line, FIRST],
                          lines[line, LAST] + 1)
        _drive(points, point_x, point_v, drive_x, drive_v, k)
        set_ends(x, v, lines, point_x, point_v)
        line_forces(x, v, f, particles, lines, line_real)
        line_passes(x, particles, lines, line_real, env, sub, tangent)
        for line in range(lines.shape[0]):
            h_gamma, h2_beta, _, _ = _newmark(k, newmark, line_real[line, HISTORY] > 0.0, dt)
            _implicit_kinematic_line(line, x, v, accel, f, sub, tangent, particles, lines,
                                     line_real, env, contact, gravity, implicit_bending,
                                     h_gamma, h2_beta, block, rhs, rhs_flat, band, diagonal,
                                     lower, inverse)
        _limit_kinematic_strains(x, v, inv_mass, rest, lines, line_real, max_iterations)
        _after_step(x, v, particles, lines, line_real, points, rest, inv_mass, dt, k, gravity,
                    f)  # f: scratch here, the next step computes it afresh


@numba.njit(cache=True)
def implicit_euler_run(arrays, drive_x, drive_v, dt, max_iterations, implicit_bending, gamma,
                       beta):
    """
    Take len(drive_x) implicit steps of the whole system in place.

    Arguments as improved_euler_run; implicit_bending: put the bending springs in the matrix
    too (needed only when they are stiff enough to limit an explicit step; it widens a
    line's band from 5 to 8). gamma, beta: Newmark's (1, 1/2: implicit Euler, as above; the
    adaptive integrator's are less damping), from the arrays' accel and point_accel, the
    accelerations of each line's step before where its HISTORY says they are (the run
    leaves its last ones there). A body's accelerations of the step before are in its
    BODY_ACCEL.

    A body (the arrays' bodies and fenders: the BODY and FENDER tables) joins the step
    through its carried points: they are unknowns of the point system as free points are,
    and the body's own six accelerations y replace them, a_q = J_q y with
    J_q = [I, -[r_q]x] (_solve_with_bodies). Its predictor is the rigid body's (its points
    follow it there, centripetal terms and all), its own loads and their Jacobians
    (forces/body.py) join the condensed system, and its points are placed on it again after
    the step: a stiff line on a light body steps as stably as on a payload.

    Each step is composed of the small steps of the comment above: the winches' rest lengths
    of the step's end and _predict; the forces at the predictor and _assemble_points (the
    free points' own rows); _condense_lines (each line's system assembled, its interior
    solved and condensed onto its free ends); _solve (the points, then every line's
    interior); _update, the strain limit and _after_step.

    The records (the System's arrays, the run's scratch) are read once, here, and the
    steps, compiled into this function (inline), take their arrays: with steps that read the
    records themselves a 20-segment line with a free end took 14-19 % longer a step, eight of 50
    segments 6 % (numba takes and drops a reference count at each read of a record's
    field that it cannot prove needless).
    """
    work = _line_work(arrays, implicit_bending)
    if not _moving_points(arrays.points) and arrays.bodies.shape[0] == 0:
        # every end fixed or driven: each line alone
        _implicit_kinematic_steps(arrays, work, drive_x, drive_v, dt, max_iterations,
                                  implicit_bending, (gamma, beta))
        return
    x, v, accel = arrays.x, arrays.v, arrays.accel
    point_x, point_v, point_accel = arrays.point_x, arrays.point_v, arrays.point_accel
    particles, lines, line_real, points = (arrays.particles, arrays.lines, arrays.line_real,
                                           arrays.points)
    env, bodies, fenders = arrays.env, arrays.bodies, arrays.fenders
    (inv_mass, rest, f, sub, tangent, block, rhs_flat, rhs, band, diagonal, lower, inverse,
     multiplier) = work
    (free_of, schur, point_rhs, point_force, end_force, coupling, solved_coupling, column,
     column_blocks, end_free, free_index, solution, transform, reduced, reduced_rhs,
     body_accel) = _point_work(arrays, rhs.shape[0])
    gravity = env[ENV_GRAVITY:ENV_GRAVITY + 3]
    contact = has_contact(env)
    ready = True  # lines joined by free points step as one: all from their history, or none
    for line in range(lines.shape[0]):
        ready &= line_real[line, HISTORY] > 0.0
    for k in range(drive_x.shape[0]):
        dt_c, half_h2, ahead_x, ahead_v = _newmark(k, (gamma, beta), ready, dt)
        pay_out(x, v, particles, lines, line_real, points, rest, inv_mass, dt, gravity)
        _predict(x, v, accel, point_x, point_v, point_accel, points, lines, bodies, drive_x,
                 drive_v, k, dt, ahead_x, ahead_v)
        line_forces(x, v, f, particles, lines, line_real)
        line_passes(x, particles, lines, line_real, env, sub, tangent)
        _assemble_points(point_x, point_v, points, env, contact, gravity, free_of, schur,
                         point_rhs, point_force, block, dt_c, half_h2)
        _condense_lines(x, v, f, sub, tangent, particles, lines, line_real, env, dt_c,
                        half_h2, block, rhs, rhs_flat, band, diagonal, lower, inverse,
                        multiplier, free_of, end_free, free_index, coupling, solved_coupling,
                        column, column_blocks, end_force, schur, point_rhs, solution)
        _solve(lines, points, point_x, bodies, fenders, free_of, schur, point_rhs, solution,
               solved_coupling, transform, reduced, reduced_rhs, body_accel, dt, dt_c,
               half_h2)
        _update(x, v, accel, point_x, point_v, point_accel, points, lines, bodies, free_of,
                point_rhs, solution, body_accel, dt, dt_c, half_h2)
        _limit_strains(x, v, inv_mass, rest, lines, line_real, points, point_x, point_v,
                       max_iterations)
        _after_step(x, v, particles, lines, line_real, points, rest, inv_mass, dt, k, gravity,
                    f)  # f: scratch here, the next step computes it afresh


@numba.njit(cache=True, inline='always')
def _predict(x, v, accel, point_x, point_v, point_accel, points, lines, bodies, drive_x,
             drive_v, k, dt, ahead_x, ahead_v):
    """
    Put everything at step k's predictor, the driven points at their k-th sample.

    x^ = x0 + h v0 (with Newmark's a0 terms ahead_x, ahead_v) of every particle, free point
    and body (rigidly turned; its carried points follow it), every line end on its point.
    """
    _predict_rows(x, v, accel, dt, ahead_x, ahead_v, 0, x.shape[0])
    for q in range(points.shape[0]):
        if points[q, KIND] == FREE:
            for p in range(3):
                point_x[q, p] += dt * point_v[q, p]
                if ahead_x != 0.0 or ahead_v != 0.0:
                    point_x[q, p] += ahead_x * point_accel[q, p]
                    point_v[q, p] += ahead_v * point_accel[q, p]
    if bodies.shape[0] > 0:
        _predict_bodies(bodies, dt, ahead_x, ahead_v)
        place_points(bodies, points, point_x, point_v)
    _drive(points, point_x, point_v, drive_x, drive_v, k)
    set_ends(x, v, lines, point_x, point_v)


@numba.njit(cache=True, inline='always')
def _assemble_points(point_x, point_v, points, env, contact, gravity, free_of, schur,
                     point_rhs, point_force, block, dt_c, half_h2):
    """
    Start the point system S, g at the predictor: the free points' own rows.

    S and g cleared, then each free point's mass matrix (its own mass and added mass,
    h C + h^2 K of its drag and contact) and load (weight, buoyancy, drag, contact). A
    carried point's rows are its line ends' only.
    """
    schur[:] = 0.0
    point_rhs[:] = 0.0
    for q in range(points.shape[0]):
        j = free_of[q]
        if points[q, KIND] == FREE:
            point_force[0] = 0.0
            added, weight = point_environment(point_x, point_v, q, points, contact, env,
                                              point_force, 0)
            block[:] = 0.0
            point_environment_block(point_x, point_v, q, points, contact, env, dt_c, half_h2,
                                    block)
            mass = points[q, OWN_MASS] + added
            for p in range(3):
                point_rhs[3 * j + p] = point_force[0, p] + weight * gravity[p]
                schur[3 * j + p, 3 * j + p] += mass
                for r in range(3):
                    schur[3 * j + p, 3 * j + r] += block[p, r]


@numba.njit(cache=True, inline='always')
def _condense_lines(x, v, f, sub, tangent, particles, lines, line_real, env, dt_c, half_h2,
                    block, rhs, rhs_flat, band, diagonal, lower, inverse, multiplier, free_of,
                    end_free, free_index, coupling, solved_coupling, column, column_blocks,
                    end_force, schur, point_rhs, solution):
    """
    Assemble each line's system at the predictor and condense it onto its free ends.

    Line by line (its matrices are the next line's scratch). Assembled: its interior's
    matrix A (band, or diagonal and lower) and right-hand side r (rhs): springs, masses,
    weight, buoyancy, drag and contact; its coupling B (coupling) to its ends on free or
    carried points, which end_free and free_index name; and those ends' rows of the point
    system (schur, point_rhs). Condensed: its interior solved alone, A^-1 r (into solution),
    and where an end is on a free or carried point, A^-1 B (solved_coupling) and the line's
    share of the Schur complement, S -= B^T A^-1 B, g -= B^T A^-1 r.

    One function for every line, its arrays handed over once a step: an array a compiled
    function is handed costs numba a reference count taken and dropped (when it cannot
    prove it needless), and an assembly and a condensation each a function of its own,
    called line by line, took a 20-segment line with a free end 6 % longer a step, eight of
    50 segments 2 %. Compiled on its own, called once a step, it took the 20-segment line
    7 % longer a step, eight of 50 segments 3 % (benchmarks/kernel_cost.py): inlined, it
    costs numba 19 s more CPU to compile implicit_euler_run (43 s against 8 s and 16 s for
    this function). No more than 30 arguments: Python hands more over as *args, which numba
    cannot inline. implicit_bending: band is (0, 0) without the bending springs.
    """
    gravity = env[ENV_GRAVITY:ENV_GRAVITY + 3]
    contact = has_contact(env)
    end_col = (0, 3)  # each end's first column in B
    implicit_bending = band.shape[0] > 0
    for line in range(lines.shape[0]):
        first, last = lines[line, FIRST], lines[line, LAST]
        axial = lines[line, AXIAL] == 1
        environment = lines[line, FLUID] == 1 or contact
        tangents = lines[line, TANGENTS] == 1
        m = last - first - 1
        coupled = False
        for e in range(2):
            q = lines[line, END_A + e]
            end_free[e] = free_of[q] >= 0
            free_index[e] = free_of[q]
            coupled |= end_free[e]
        diagonal[:m] = 0.0
        lower[:m] = 0.0
        if implicit_bending:
            band[:3 * m] = 0.0
        if coupled:
            coupling[:m] = 0.0
        for i in range(first, last):
            spring_block_at(x, particles, i, False, half_h2, dt_c, axial, block, line_real[line])
            if coupled:
                _scatter(block, i, i + 1, first, last, end_col, end_free, free_index,
                         implicit_bending, band, diagonal, lower, coupling, schur)
            elif implicit_bending:  # the common cases, kept lean: A only
                _add_band_spring(band, i - first - 1, i - first, m, block)
            else:
                _add_chain_block(diagonal, lower, i - first, m, block)
        if implicit_bending:
            for i in range(first, last - 1):
                spring_block_at(x, particles, i, True, half_h2, dt_c, axial, block,
                                line_real[line])
                if coupled:
                    _scatter(block, i, i + 2, first, last, end_col, end_free, free_index, True,
                             band, diagonal, lower, coupling, schur)
                else:
                    _add_band_spring(band, i - first - 1, i - first + 1, m, block)
        # mass, weight, buoyancy, drag and contact of the interior particles
        for i in range(first + 1, last):
            local = i - first - 1
            _particle_system(x, v, f, i, particles, line_real, line, environment, tangents,
                             contact, env, gravity, sub, tangent, dt_c, half_h2, rhs, local, block)
            if implicit_bending:
                _add_band(band, local, local, block, 1.0)
            else:
                for p in range(3):
                    for q in range(3):
                        diagonal[local, p, q] += block[p, q]
        # the line ends on free points: their rows of the point system
        for e in range(2):
            if not end_free[e]:
                continue
            row = first if e == 0 else last
            j = free_index[e]
            _particle_system(x, v, f, row, particles, line_real, line, environment, tangents,
                             contact, env, gravity, sub, tangent, dt_c, half_h2, end_force, 0,
                             block)
            for p in range(3):
                point_rhs[3 * j + p] += end_force[0, p]
                for q in range(3):
                    schur[3 * j + p, 3 * j + q] += block[p, q]
        # condense: A^-1 r, A^-1 B and the Schur complement
        if m <= 0:
            continue
        if implicit_bending:
            _cholesky_factor(band, 3 * m)
            _cholesky_band_solve(band, rhs_flat, 3 * m)
        else:
            _block_thomas_factor(diagonal, lower, inverse, multiplier, m)
            _block_thomas_solve(lower, inverse, multiplier, rhs, m)
        for i in range(m):
            for p in range(3):
                solution[first + 1 + i, p] = rhs[i, p]
        if not coupled:
            continue
        # A^-1 B, column by column, and the Schur complement's share of this line
        for c in range(6):
            e = c // 3
            if not end_free[e]:
                continue
            for i in range(m):
                for p in range(3):
                    column[3 * i + p] = coupling[i, p, c]
            if implicit_bending:
                _cholesky_band_solve(band, column, 3 * m)
            else:
                _block_thomas_solve(lower, inverse, multiplier, column_blocks, m)
            for i in range(m):
                for p in range(3):
                    solved_coupling[first + 1 + i, p, c] = column[3 * i + p]
        for c in range(6):
            e = c // 3
            if not end_free[e]:
                continue
            ro = 3 * free_index[e] + c % 3
            s = 0.0
            for i in range(m):
                for p in range(3):
                    s += coupling[i, p, c] * rhs[i, p]
            point_rhs[ro] -= s
            for d in range(6):
                g = d // 3
                if not end_free[g]:
                    continue
                co = 3 * free_index[g] + d % 3
                s = 0.0
                for i in range(m):
                    for p in range(3):
                        s += coupling[i, p, c] * solved_coupling[first + 1 + i, p, d]
                schur[ro, co] -= s


@numba.njit(cache=True, inline='always')
def _solve(lines, points, point_x, bodies, fenders, free_of, schur, point_rhs, solution,
           solved_coupling, transform, reduced, reduced_rhs, body_accel, dt, dt_c, half_h2):
    """
    Solve the condensed system: the points' accelerations, then every line's interior.

    The point system S a = g (point_rhs becomes a; with bodies, through their own six
    accelerations, body_accel: _solve_with_bodies), then each line's interior
    a_k = A^-1 r - A^-1 B a (solution).
    """
    if bodies.shape[0] > 0:
        _solve_with_bodies(schur, point_rhs, points, point_x, free_of, bodies, fenders, dt,
                           dt_c, half_h2, transform, reduced, reduced_rhs, body_accel)
    else:
        dense_cholesky_solve(schur, point_rhs)
    for line in range(lines.shape[0]):
        first, last = lines[line, FIRST], lines[line, LAST]
        for c in range(6):
            q = lines[line, END_A + c // 3]
            if free_of[q] < 0:
                continue
            a = point_rhs[3 * free_of[q] + c % 3]
            for i in range(first + 1, last):
                for p in range(3):
                    solution[i, p] -= solved_coupling[i, p, c] * a


@numba.njit(cache=True, inline='always')
def _update(x, v, accel, point_x, point_v, point_accel, points, lines, bodies, free_of,
            point_rhs, solution, body_accel, dt, dt_c, half_h2):
    """
    Finish the step from the solved accelerations a: x += h^2 beta a, v += h gamma a.

    The free points and the interior particles, the bodies (their carried points placed on
    them again); a kept for the next step (accel, point_accel, BODY_ACCEL); every line end
    on its point.
    """
    for q in range(points.shape[0]):
        j = free_of[q]
        if j >= 0:
            for p in range(3):
                point_accel[q, p] = point_rhs[3 * j + p]
                if points[q, KIND] == FREE:
                    point_x[q, p] += half_h2 * point_rhs[3 * j + p]
                    point_v[q, p] += dt_c * point_rhs[3 * j + p]
    if bodies.shape[0] > 0:
        _correct_bodies(bodies, body_accel, dt, dt_c, half_h2)
        place_points(bodies, points, point_x, point_v)
    for line in range(lines.shape[0]):
        for i in range(lines[line, FIRST] + 1, lines[line, LAST]):
            for p in range(3):
                x[i, p] += half_h2 * solution[i, p]
                v[i, p] += dt_c * solution[i, p]
                accel[i, p] = solution[i, p]
    set_ends(x, v, lines, point_x, point_v)


@numba.njit(cache=True)
def _body_arrays(points, free_of, n_free, n_bodies):
    """
    Return the condensed system's arrays, each to be filled by _solve_with_bodies.

    transform T (3 F, Y), reduced (Y, Y), its right-hand side (Y,) and the bodies'
    accelerations (B, 6); Y holds 3 unknowns per free point and 6 per body, in that order.
    """
    n_y = 6 * n_bodies
    for q in range(points.shape[0]):
        if points[q, KIND] == FREE:
            n_y += 3
    return (np.zeros((3 * n_free, n_y)), np.empty((n_y, n_y)), np.empty(n_y),
            np.zeros((n_bodies, 6)))


@numba.njit(cache=True)
def _solve_with_bodies(schur, point_rhs, points, point_x, free_of, bodies, fenders, dt, dt_c,
                       half_h2, transform, reduced, reduced_rhs, body_accel):
    """
    Solve the point system S a = g with the carried points' accelerations a_q = J_q y.

    (T^T S T + blocks of each body: M + h_c C + h2 K) y = T^T g + each body's own loads;
    point_rhs gets the points' accelerations T y, body_accel each body's y (6,).
    """
    n_bodies = bodies.shape[0]
    first_body = transform.shape[1] - 6 * n_bodies
    transform[:] = 0.0
    column = 0
    for q in range(points.shape[0]):
        j = free_of[q]
        if j < 0:
            continue
        if points[q, KIND] == FREE:
            for p in range(3):
                transform[3 * j + p, column + p] = 1.0
            column += 3
            continue
        b = int(points[q, POINT_BODY])
        c = first_body + 6 * b
        r = lever_of(bodies, points, point_x, q)
        for p in range(3):
            transform[3 * j + p, c + p] = 1.0
        # -[r]x
        transform[3 * j, c + 4] = r[2]
        transform[3 * j, c + 5] = -r[1]
        transform[3 * j + 1, c + 3] = -r[2]
        transform[3 * j + 1, c + 5] = r[0]
        transform[3 * j + 2, c + 3] = r[1]
        transform[3 * j + 2, c + 4] = -r[0]
    _reduce(schur, point_rhs, transform, reduced, reduced_rhs)
    rotation = np.empty((3, 3))
    mass = np.empty((6, 6))
    load = np.empty(6)
    stiffness = np.empty((6, 6))
    damping = np.empty((6, 6))
    for b in range(n_bodies):
        body = bodies[b]
        rotation_of(body, rotation)
        mass_matrix(body, rotation, mass)
        body_loads(body, b, fenders, rotation, body[BODY_CLOCK], dt, load, True, stiffness,
                   damping)
        c = first_body + 6 * b
        for p in range(6):
            reduced_rhs[c + p] += load[p]
            for r in range(6):
                reduced[c + p, c + r] += (mass[p, r] + dt_c * damping[p, r]
                                          + half_h2 * stiffness[p, r])
    dense_cholesky_solve(reduced, reduced_rhs)
    for i in range(transform.shape[0]):
        s = 0.0
        for c in range(transform.shape[1]):
            s += transform[i, c] * reduced_rhs[c]
        point_rhs[i] = s
    for b in range(n_bodies):
        for p in range(6):
            body_accel[b, p] = reduced_rhs[first_body + 6 * b + p]


@numba.njit(cache=True)
def _reduce(schur, rhs, transform, reduced, reduced_rhs):
    """Put T^T S T into reduced and T^T g into reduced_rhs (plain loops: small, often empty)."""
    n, m = transform.shape
    product = np.zeros((n, m))
    for i in range(n):
        for j in range(n):
            s = schur[i, j]
            if s != 0.0:
                for c in range(m):
                    product[i, c] += s * transform[j, c]
    for c in range(m):
        reduced_rhs[c] = 0.0
        for d in range(m):
            reduced[c, d] = 0.0
        for i in range(n):
            t = transform[i, c]
            if t != 0.0:
                reduced_rhs[c] += t * rhs[i]
                for d in range(m):
                    reduced[c, d] += t * product[i, d]


@numba.njit(cache=True)
def _predict_bodies(bodies, dt, ahead_x, ahead_v):
    """
    Put every body at its predictor (as _predict_rows does the particles; rigidly turned).

    Its radiation memory's modes start a step of dt at its state before (forces/body.py).
    """
    history = ahead_x != 0.0 or ahead_v != 0.0
    for b in range(bodies.shape[0]):
        body = bodies[b]
        start_modes(body, dt)
        rotate = np.empty(3)
        for p in range(3):
            body[BODY_POSITION + p] += dt * body[BODY_VELOCITY + p]
            rotate[p] = dt * body[BODY_OMEGA + p]
            if history:
                body[BODY_POSITION + p] += ahead_x * body[BODY_ACCEL + p]
                body[BODY_VELOCITY + p] += ahead_v * body[BODY_ACCEL + p]
                rotate[p] += ahead_x * body[BODY_ACCEL + 3 + p]
                body[BODY_OMEGA + p] += ahead_v * body[BODY_ACCEL + 3 + p]
        turn(body, rotate[0], rotate[1], rotate[2])
        body[BODY_CLOCK] += dt


@numba.njit(cache=True)
def _correct_bodies(bodies, accel, dt, dt_c, half_h2):
    """
    Finish every body's implicit step from its solved accelerations (kept for the next).

    And its radiation memory's step of dt at its new velocities (forces/body.py).
    """
    for b in range(bodies.shape[0]):
        body = bodies[b]
        for p in range(3):
            body[BODY_POSITION + p] += half_h2 * accel[b, p]
            body[BODY_VELOCITY + p] += dt_c * accel[b, p]
            body[BODY_OMEGA + p] += dt_c * accel[b, 3 + p]
        for p in range(6):
            body[BODY_ACCEL + p] = accel[b, p]
        turn(body, half_h2 * accel[b, 3], half_h2 * accel[b, 4], half_h2 * accel[b, 5])
        finish_modes(body, dt)


def run_kernel(system, integrator: str, dt: float, drive_x: np.ndarray, drive_v: np.ndarray,
               max_iterations: int, implicit_bending: bool, compiled: bool,
               newmark: tuple = (1.0, 0.5)) -> None:
    """
    Take len(drive_x) steps of one integrator's kernel on a System (or a LineView of one).

    The Lines are not told (step.step tells them).

    :param newmark: implicit_euler's (gamma, beta): (1, 1/2) is implicit Euler; others
        start each line from its accelerations of the step before where its HISTORY
        column says they are.
    :param compiled: False runs the same kernels' Python code (``.py_func``), for tests.
    """
    if integrator == 'implicit_euler':
        run = implicit_euler_run if compiled else implicit_euler_run.py_func
        run(system.arrays, drive_x, drive_v, dt, max_iterations, implicit_bending, newmark[0],
            newmark[1])
    else:
        run = improved_euler_run if compiled else improved_euler_run.py_func
        run(system.arrays, drive_x, drive_v, dt, max_iterations)
