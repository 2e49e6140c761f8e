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
The forces of a System at one state, summed in one place: compiled (numba), no stepping.

A System (objects.py) packs its lines and points into the tables of layout.py. Each line is
a chain of particles; its two end particles sit on points, MoorDyn's way: a fixed or driven
point sets its line ends' positions and velocities, and a free point (a lumped body: a
payload, a shackle joining lines) moves under its own weight plus the force of every line
end on it, each end's springs and dampers with the weight and drag of the half segment
lumped there, over its own mass plus those half-segment masses.

The force terms live in this folder (one module each, force and Jacobian); this module is
the one place that sums them, for the integrators (stepping/kernels.py), the end forces a
line reports, and the state check. Tests run these same functions interpreted
(``.py_func``).
"""

import numba
import numpy as np

from .body import add_point_load, add_point_matrix, body_loads, lever_of, mass_matrix, rotation_of
from .contact import add_contact, add_contact_block
from .drag import add_drag
from .fluid import (accelerate, add_line_drag, add_line_drag_block, add_mass_block, add_point_drag,
                    add_point_drag_block, line_pass, point_fraction)
from .gravity import add_weight
from .springs import add_springs
from ..layout import (ADDED_MASS, AXIAL, BENDING, BODY_CLOCK, BODY_OMEGA, CARRIED, DIAMETER, DRAG,
                      DRAG_AREA, END_A, ENV_AIR_DENSITY, ENV_CURRENT, ENV_GRAVITY, ENV_QUAY_NORMAL,
                      ENV_SEABED_LEVEL, ENV_WATER_DENSITY, ENV_WATER_LEVEL, FIRST, FLUID, FREE,
                      KIND, LAST, LENGTH, MASS, NORMAL_ADDED_MASS, NORMAL_DRAG, OWN_MASS, PEAK_A,
                      POINT_BODY, POINT_SINK, REST, SINK, SIZE, TANGENTIAL_ADDED_MASS,
                      TANGENTIAL_DRAG, TANGENTS, TOTAL_MASS, VOLUME, VOLUME_AREA, VOLUME_DIAMETER)
from ..linalg import dense_cholesky_solve, inverse3
from ..tension_curve import axial_tension


@numba.njit(cache=True, inline='always')
def line_forces(x, v, out, particles, lines, line_real):
    """Spring and damper forces of every line on its particles into `out` (P, 3)."""
    out[:] = 0.0
    for k in range(lines.shape[0]):
        first, last, axial = lines[k, FIRST], lines[k, LAST], lines[k, AXIAL] == 1
        add_springs(x, v, out, particles, first, last, False, axial, line_real[k])
        if lines[k, BENDING] == 1:
            add_springs(x, v, out, particles, first, last, True, axial, line_real[k])


@numba.njit(cache=True, inline='always')
def has_water(env):
    """Tell whether there is water: a water level above -inf."""
    return env[ENV_WATER_LEVEL] > -np.inf


@numba.njit(cache=True, inline='always')
def has_contact(env):
    """Tell whether anything can be touched: a seabed above -inf or a quay."""
    return (env[ENV_SEABED_LEVEL] > -np.inf or env[ENV_QUAY_NORMAL] != 0.0
            or env[ENV_QUAY_NORMAL + 1] != 0.0)


@numba.njit(cache=True)
def line_passes(x, particles, lines, line_real, env, sub, tangent):
    """
    Fill every line's submerged lengths sub (P,) and tangents tangent (P, 3) where needed.

    A line without fluid terms, or without water, keeps sub as it is (zero from the start);
    tangents only for the lines whose terms read them.
    """
    wet = has_water(env)
    level = env[ENV_WATER_LEVEL]
    for k in range(lines.shape[0]):
        if lines[k, FLUID] != 1:
            continue
        tangents = lines[k, TANGENTS] == 1
        if wet or tangents:
            line_pass(x, particles, lines[k, FIRST], lines[k, LAST], level,
                      line_real[k, VOLUME_DIAMETER], wet, tangents, sub, tangent)


@numba.njit(cache=True, inline='always')
def particle_environment(x, v, i, particles, line_real, k, tangents, contact, env, sub,
                         tangent, out, out_row):
    """
    Add particle i's fluid drag and contact force (of line k) to out[out_row].

    Return (a, b, weight): its mass matrix a I + b q q^T (mass plus added mass) and the mass
    whose weight it carries, m - D (D: the displaced water and air).
    """
    mass = particles[i, MASS]
    length = particles[i, LENGTH]
    wet = sub[i]
    dry = length - wet
    rho_w = env[ENV_WATER_DENSITY]
    rho_a = env[ENV_AIR_DENSITY]
    displaced = line_real[k, VOLUME_AREA] * (rho_w * wet + rho_a * dry)
    ca = line_real[k, NORMAL_ADDED_MASS]
    if tangents:
        c_n = line_real[k, NORMAL_DRAG]
        c_t = line_real[k, TANGENTIAL_DRAG]
        if wet > 0.0:
            add_line_drag(v, i, tangent, i, rho_w * wet * c_n, rho_w * wet * c_t,
                          env[ENV_CURRENT], env[ENV_CURRENT + 1], env[ENV_CURRENT + 2], out,
                          out_row)
        if dry > 0.0 and rho_a > 0.0:
            add_line_drag(v, i, tangent, i, rho_a * dry * c_n, rho_a * dry * c_t, 0.0, 0.0,
                          0.0, out, out_row)
    if contact:
        add_contact(x, v, i, line_real[k, DIAMETER], length, particles[i, SINK], env, out,
                    out_row)
    return (mass + ca * displaced, (line_real[k, TANGENTIAL_ADDED_MASS] - ca) * displaced,
            mass - displaced)


@numba.njit(cache=True, inline='always')
def particle_environment_block(x, v, i, particles, line_real, k, tangents, contact, env,
                               sub, tangent, b, h, half_h2, block):
    """
    Add particle i's b q q^T and h C + h^2/2 S of its fluid drag and contact to block.

    b: the anisotropic part of its mass matrix (from _environment); C, S: minus the
    Jacobians in v and x.
    """
    if b != 0.0:
        add_mass_block(0.0, b, tangent, i, block)
    if tangents:
        wet = sub[i]
        dry = particles[i, LENGTH] - wet
        c_n = line_real[k, NORMAL_DRAG]
        c_t = line_real[k, TANGENTIAL_DRAG]
        rho_w = env[ENV_WATER_DENSITY]
        rho_a = env[ENV_AIR_DENSITY]
        if wet > 0.0:
            add_line_drag_block(v, i, tangent, i, rho_w * wet * c_n, rho_w * wet * c_t,
                                env[ENV_CURRENT], env[ENV_CURRENT + 1], env[ENV_CURRENT + 2],
                                h, block)
        if dry > 0.0 and rho_a > 0.0:
            add_line_drag_block(v, i, tangent, i, rho_a * dry * c_n, rho_a * dry * c_t, 0.0,
                                0.0, 0.0, h, block)
    if contact:
        add_contact_block(x, v, i, line_real[k, DIAMETER], particles[i, LENGTH],
                          particles[i, SINK], env, h, half_h2, block)


@numba.njit(cache=True)
def point_environment(point_x, point_v, q, points, contact, env, out, out_row):
    """
    Add free point q's own fluid drag and contact force to out[out_row].

    Return (added, weight): its added mass Ca_p D and the mass whose weight it carries,
    m - D (D: the water and air its volume displaces).
    """
    own = points[q, OWN_MASS]
    volume = points[q, VOLUME]
    area = points[q, DRAG_AREA]
    if volume == 0.0 and area == 0.0:
        return 0.0, own
    wet = 0.0
    if has_water(env):
        wet = point_fraction(point_x[q, 2], env[ENV_WATER_LEVEL], max(points[q, SIZE], 1e-6))
    rho_w = env[ENV_WATER_DENSITY]
    rho_a = env[ENV_AIR_DENSITY]
    displaced = volume * (rho_w * wet + rho_a * (1.0 - wet))
    if area > 0.0:
        if wet > 0.0:
            add_point_drag(point_v, q, 0.5 * rho_w * area * wet, env[ENV_CURRENT],
                           env[ENV_CURRENT + 1], env[ENV_CURRENT + 2], out, out_row)
        if wet < 1.0:
            add_point_drag(point_v, q, 0.5 * rho_a * area * (1.0 - wet), 0.0, 0.0, 0.0, out,
                           out_row)
    if contact:
        size = points[q, SIZE]
        add_contact(point_x, point_v, q, size, size, points[q, POINT_SINK], env, out, out_row)
    return points[q, ADDED_MASS] * displaced, own - displaced


@numba.njit(cache=True)
def point_environment_block(point_x, point_v, q, points, contact, env, h, half_h2, block):
    """Add h C + h^2/2 S of free point q's own drag and contact to block (3, 3)."""
    area = points[q, DRAG_AREA]
    if area > 0.0:
        wet = 0.0
        if has_water(env):
            wet = point_fraction(point_x[q, 2], env[ENV_WATER_LEVEL],
                                 max(points[q, SIZE], 1e-6))
        if wet > 0.0:
            add_point_drag_block(point_v, q, 0.5 * env[ENV_WATER_DENSITY] * area * wet,
                                 env[ENV_CURRENT], env[ENV_CURRENT + 1], env[ENV_CURRENT + 2],
                                 h, block)
        if wet < 1.0:
            add_point_drag_block(point_v, q, 0.5 * env[ENV_AIR_DENSITY] * area * (1.0 - wet),
                                 0.0, 0.0, 0.0, h, block)
    if contact:
        size = points[q, SIZE]
        add_contact_block(point_x, point_v, q, size, size, points[q, POINT_SINK], env, h,
                          half_h2, block)


@numba.njit(cache=True)
def end_forces(x, v, particles, lines, line_real, env, out):
    """
    Force of each line on the points its ends sit on into out (L, 2, 3): end A, end B.

    The springs and dampers at the end particle plus the weight, buoyancy, fluid drag (with
    the end's velocity) and contact of the half segment lumped there: MoorDyn's force on a
    coupled point (not the end particle's inertia). It converges to the catenary's end
    tension at second order in N. (The seed's isotropic air drag of the half segment acts on
    a free point's motion too, but is not part of this reported force.)
    """
    f = np.empty_like(x)
    line_forces(x, v, f, particles, lines, line_real)
    sub = np.zeros(x.shape[0])
    tangent = np.zeros_like(x)
    line_passes(x, particles, lines, line_real, env, sub, tangent)
    gravity = env[ENV_GRAVITY:ENV_GRAVITY + 3]
    contact = has_contact(env)
    for k in range(lines.shape[0]):
        fluid = lines[k, FLUID] == 1
        tangents = lines[k, TANGENTS] == 1
        for e in range(2):
            row = lines[k, FIRST] if e == 0 else lines[k, LAST]
            for p in range(3):
                out[k, e, p] = f[row, p]
            weight = particles[row, MASS]
            if fluid or contact:
                _, _, weight = particle_environment(x, v, row, particles, line_real, k, tangents,
                                                    contact, env, sub, tangent, out[k], e)
            add_weight(out[k], e, weight, gravity)


@numba.njit(cache=True)
def point_forces(x, v, f, particles, lines, line_real, points, point_x, point_v, env,
                 gravity, contact, sub, tangent, out, iso, aniso):
    """
    Net force on each free or carried point into out (Q, 3), from the line forces f.

    A free point's own weight, buoyancy, drag and contact plus, for every line end on a free
    or carried point, that end's springs, dampers and the environment terms of the half
    segment lumped there. The point's mass matrix: iso[q] I + aniso[q] (Q, 3, 3): a free
    point's own mass and added mass and every end particle's mass matrix (a carried point
    has no mass of its own: its body's comes in body_accelerations). Rows of fixed and
    driven points are left as they are.
    """
    for q in range(points.shape[0]):
        kind = points[q, KIND]
        if kind == FREE:
            for p in range(3):
                out[q, p] = 0.0
            added, weight = point_environment(point_x, point_v, q, points, contact, env, out,
                                              q)
            add_weight(out, q, weight, gravity)
            iso[q] = points[q, TOTAL_MASS] + added
            aniso[q] = 0.0
        elif kind == CARRIED:
            for p in range(3):
                out[q, p] = 0.0
            iso[q] = points[q, TOTAL_MASS]
            aniso[q] = 0.0
    for k in range(lines.shape[0]):
        fluid = lines[k, FLUID] == 1
        tangents = lines[k, TANGENTS] == 1
        for e in range(2):
            q = lines[k, END_A + e]
            if points[q, KIND] != FREE and points[q, KIND] != CARRIED:
                continue
            row = lines[k, FIRST] if e == 0 else lines[k, LAST]
            for p in range(3):
                out[q, p] += f[row, p]
            weight = particles[row, MASS]
            if fluid or contact:
                a, b, weight = particle_environment(x, v, row, particles, line_real, k, tangents,
                                                    contact, env, sub, tangent, out, q)
                iso[q] += a - particles[row, MASS]  # its mass is in TOTAL_MASS already
                if b != 0.0:
                    add_mass_block(0.0, b, tangent, row, aniso[q])
            add_weight(out, q, weight, gravity)
            add_drag(v, row, particles[row, DRAG], out, q)


@numba.njit(cache=True)
def accelerations(x, v, a, particles, lines, line_real, points, point_x, point_v, env,
                  gravity, contact, sub, tangent, point_a, iso, aniso, work, bodies, fenders,
                  body_a):
    """
    Accelerations of every particle into a (P, 3), of every free point into point_a (Q, 3).

    And of every body into body_a (B, 6) (its carried points' rows of point_a: theirs).
    Rows of line ends are meaningless (their points set them).
    """
    line_forces(x, v, a, particles, lines, line_real)
    line_passes(x, particles, lines, line_real, env, sub, tangent)
    point_forces(x, v, a, particles, lines, line_real, points, point_x, point_v, env,
                 gravity, contact, sub, tangent, point_a, iso, aniso)
    if bodies.shape[0] > 0:
        body_accelerations(bodies, fenders, points, point_x, point_a, iso, aniso, body_a)
    for q in range(points.shape[0]):
        if points[q, KIND] == FREE:
            plain = True
            for p in range(3):
                for r in range(3):
                    plain &= aniso[q, p, r] == 0.0
            if plain:
                for p in range(3):
                    point_a[q, p] /= iso[q]
            else:  # added mass along the end segments: the full 3x3 mass matrix
                for p in range(3):
                    aniso[q, p, p] += iso[q]
                inverse3(aniso[q], work)
                f0, f1, f2 = point_a[q, 0], point_a[q, 1], point_a[q, 2]
                for p in range(3):
                    point_a[q, p] = work[p, 0] * f0 + work[p, 1] * f1 + work[p, 2] * f2
    particle_accelerations(x, v, a, particles, lines, line_real, env, gravity, contact, sub,
                           tangent)


@numba.njit(cache=True)
def body_accelerations(bodies, fenders, points, point_x, point_a, iso, aniso, body_a):
    """
    Turn the forces on carried points (point_a's rows) into their bodies' accelerations.

    Each body: its mass matrix plus J^T m J of every carried point's lumped mass m (the half
    segments there move with the body), its own loads (forces/body.py) plus J^T of every
    carried point's force less the point mass's share of its centripetal acceleration; then
    the points' accelerations a + alpha x r + omega x (omega x r) into point_a.
    """
    rotation = np.empty((3, 3))
    mass = np.empty((6, 6))
    load = np.empty(6)
    unused = np.empty((6, 6))
    block = np.empty((3, 3))
    force = np.empty(3)
    for b in range(bodies.shape[0]):
        body = bodies[b]
        rotation_of(body, rotation)
        mass_matrix(body, rotation, mass)
        body_loads(body, b, fenders, rotation, body[BODY_CLOCK], 0.0, load, False, unused,
                   unused)
        omega = body[BODY_OMEGA:BODY_OMEGA + 3]
        for q in range(points.shape[0]):
            if points[q, KIND] != CARRIED or int(points[q, POINT_BODY]) != b:
                continue
            lever = lever_of(bodies, points, point_x, q)
            for p in range(3):
                for r in range(3):
                    block[p, r] = aniso[q, p, r] + (iso[q] if p == r else 0.0)
            add_point_matrix(mass, lever, block, 1.0)
            spin = _centripetal(omega, lever)
            for p in range(3):
                force[p] = point_a[q, p] - (block[p, 0] * spin[0] + block[p, 1] * spin[1]
                                            + block[p, 2] * spin[2])
            add_point_load(load, lever, force)
        dense_cholesky_solve(mass, load)
        for p in range(6):
            body_a[b, p] = load[p]
        for q in range(points.shape[0]):
            if points[q, KIND] != CARRIED or int(points[q, POINT_BODY]) != b:
                continue
            lever = lever_of(bodies, points, point_x, q)
            spin = _centripetal(omega, lever)
            point_a[q, 0] = load[0] + load[4] * lever[2] - load[5] * lever[1] + spin[0]
            point_a[q, 1] = load[1] + load[5] * lever[0] - load[3] * lever[2] + spin[1]
            point_a[q, 2] = load[2] + load[3] * lever[1] - load[4] * lever[0] + spin[2]


@numba.njit(cache=True, inline='always')
def _centripetal(omega, lever):
    """Return omega x (omega x lever) (3,)."""
    c0 = omega[1] * lever[2] - omega[2] * lever[1]
    c1 = omega[2] * lever[0] - omega[0] * lever[2]
    c2 = omega[0] * lever[1] - omega[1] * lever[0]
    return np.array([omega[1] * c2 - omega[2] * c1, omega[2] * c0 - omega[0] * c2,
                     omega[0] * c1 - omega[1] * c0])


@numba.njit(cache=True, inline='always')
def particle_accelerations(x, v, a, particles, lines, line_real, env, gravity, contact, sub,
                           tangent):
    """
    Turn the line forces in a (P, 3) into accelerations of the lines' interior particles.

    Drag, contact, weight and buoyancy, then the inverse of the mass matrix (mass and added
    mass); the line ends' rows are left as they are (their points set them).
    """
    for k in range(lines.shape[0]):
        fluid = lines[k, FLUID] == 1
        tangents = lines[k, TANGENTS] == 1
        for i in range(lines[k, FIRST] + 1, lines[k, LAST]):
            add_drag(v, i, particles[i, DRAG], a, i)
            mass = particles[i, MASS]
            if fluid or contact:
                m, b, weight = particle_environment(x, v, i, particles, line_real, k, tangents,
                                                    contact, env, sub, tangent, a, i)
                accelerate(m, b, tangent, i, weight, gravity, a, i)
            else:
                accelerate(mass, 0.0, tangent, i, mass, gravity, a, i)


@numba.njit(cache=True, inline='always')
def set_ends(x, v, lines, point_x, point_v):
    """Put every line end particle on its point: the point's position and velocity."""
    for k in range(lines.shape[0]):
        for e in range(2):
            q = lines[k, END_A + e]
            row = lines[k, FIRST] if e == 0 else lines[k, LAST]
            for p in range(3):
                x[row, p] = point_x[q, p]
                v[row, p] = point_v[q, p]


@numba.njit(cache=True)
def all_finite(x, v):
    """Tell whether every position and velocity is a finite number."""
    for i in range(x.shape[0]):
        for p in range(3):
            if not (np.isfinite(x[i, p]) and np.isfinite(v[i, p])):
                return False
    return True


@numba.njit(cache=True)
def max_strain(x, rest):
    """Largest strain of a line's structural springs (x (N+1, 3), rest (N,))."""
    worst = -1.0
    for i in range(x.shape[0] - 1):
        d = np.sqrt((x[i + 1, 0] - x[i, 0]) ** 2 + (x[i + 1, 1] - x[i, 1]) ** 2
                    + (x[i + 1, 2] - x[i, 2]) ** 2)
        worst = max(worst, d / rest[i] - 1.0)
    return worst


@numba.njit(cache=True)
def take_tensions(forces, line_real, x, tensions, peaks):
    """
    Write each line's end tensions (L, 2) and their peaks since the last call (L, 2) [N].

    forces (L, 2, 3) are end_forces of this state; a peak is the largest of the steps'
    (held in line_real, cleared here) and this state's tension. One pass instead of five
    numpy calls on small arrays: it runs at every output.

    :returns: the sum of x, the forces and the peaks (finite only if every one is).
    """
    total = 0.0
    for k in range(forces.shape[0]):
        for e in range(2):
            tension = np.sqrt(forces[k, e, 0] ** 2 + forces[k, e, 1] ** 2 + forces[k, e, 2] ** 2)
            held = line_real[k, PEAK_A + e]
            peak = tension if tension >= held else held  # (a NaN held stays: total tells)
            tensions[k, e] = tension
            peaks[k, e] = peak
            line_real[k, PEAK_A + e] = 0.0
            total += forces[k, e, 0] + forces[k, e, 1] + forces[k, e, 2] + peak
    for i in range(x.shape[0]):
        total += x[i, 0] + x[i, 1] + x[i, 2]
    return total


@numba.njit(cache=True)
def largest_load(x, v, point_x, point_v, particles, lines, line_real, env, forces, strains):
    """
    Return whether the state (particles and points) is finite, and its largest load [N].

    The load is the largest end force or elastic tension at the largest strain (EA times it,
    or the line's curve at it); NaN or inf where finite numbers
    overflow. Also fills forces (L, 2, 3) with end_forces and strains (L,) with each line's
    largest strain (left as they are when the state is not finite).
    """
    if not (all_finite(x, v) and all_finite(point_x, point_v)):
        return False, np.inf
    end_forces(x, v, particles, lines, line_real, env, forces)
    largest = 0.0
    for k in range(lines.shape[0]):
        first, last = lines[k, FIRST], lines[k, LAST]
        strains[k] = max_strain(x[first:last + 1], particles[first:last, REST])
        load = axial_tension(line_real[k], strains[k])
        if np.isnan(load):
            return True, np.nan
        largest = max(largest, load)
        for e in range(2):
            load = np.sqrt(forces[k, e, 0] ** 2 + forces[k, e, 1] ** 2 + forces[k, e, 2] ** 2)
            if np.isnan(load):
                return True, np.nan
            largest = max(largest, load)
    return True, largest
