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
A rigid body in six degrees of freedom (a free ship): its mass and the loads on it.

The body's unknowns are its centre of gravity's acceleration and its angular acceleration,
both in world axes; its state the centre of gravity's position and velocity, its orientation
(a unit quaternion, body to world) and its angular velocity in world axes. Line ends sit on
its points (layout.CARRIED points), which it carries rigidly.

Its own loads, all about the centre of gravity in world axes:
- inertia: mass and principal moments of inertia (from the radii of gyration) plus the
  added masses, each along its body axis (surge, sway, heave; roll, pitch, yaw); the
  coupling between added mass and rotation (the Munk moment) is not modelled;
- hydrostatics about where it floats freely: a heave force -rho g A_wp (z - z_rest) acting
  at the body origin (the waterplane's centre, taken on the origin), and the roll and pitch
  moments of the potential 1/2 (m g GM_T phi^2 + m g GM_L theta^2) (Z-Y-X angles): small-
  angle restoring, the ship's weight and buoyancy balancing at rest, conservative at any
  angle and without a moment about the vertical;
- damping on its velocity in body axes, linear and quadratic in each degree of freedom;
- with a hydrodynamic database (model/ship/radiation.py): its full added mass at infinite
  frequency, couplings and all, in place of the diagonal one, and the radiation memory's
  load -int_0^t K(t - tau) u(tau) dtau, u its six velocities in body axes, carried as
  modes whose states the integrators step with the body (start_modes, finish_modes);
- the gyroscopic moment -omega x (I omega), its inertia and added inertia together;
- its fenders (fender.py) and an external force and moment given per run, linear in time.
The lines' forces come to it through its points (the integrators add them).

The implicit step needs the Jacobians of these loads: the stiffness (hydrostatics and the
fenders' slopes) and the damping (linear, the quadratic's 2 c |v|, the fenders' friction
below its sliding speed); each is exact or, where a term's Jacobian would need the rotation's
own derivatives, the part that dominates (the loads themselves are always exact).
"""

import numba
import numpy as np

from .fender import fender_force
from ..layout import (BODY_ADDED, BODY_ADDED_MATRIX, BODY_FULL_ADDED, BODY_INERTIA,
                      BODY_LINEAR_DAMPING, BODY_LOAD, BODY_LOAD_RATE, BODY_MASS, BODY_MODE,
                      BODY_MODES, BODY_OMEGA, BODY_ORIGIN, BODY_POSITION,
                      BODY_QUADRATIC_DAMPING, BODY_QUATERNION, BODY_REST_Z, BODY_RESTORING,
                      BODY_VELOCITY, CARRIED, FENDER_BODY, FENDER_NORMAL, KIND, MODE_COLUMNS,
                      MODE_INPUT, MODE_OUTPUT, MODE_POLE, MODE_STATE, MODE_WEIGHT, POINT_BODY,
                      POINT_OFFSET)


@numba.njit(cache=True, inline='always')
def rotation_of(body, rotation):
    """Fill rotation (3, 3) with the body's orientation matrix, body to world axes."""
    x = body[BODY_QUATERNION]
    y = body[BODY_QUATERNION + 1]
    z = body[BODY_QUATERNION + 2]
    w = body[BODY_QUATERNION + 3]
    rotation[0, 0] = 1.0 - 2.0 * (y * y + z * z)
    rotation[0, 1] = 2.0 * (x * y - z * w)
    rotation[0, 2] = 2.0 * (x * z + y * w)
    rotation[1, 0] = 2.0 * (x * y + z * w)
    rotation[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    rotation[1, 2] = 2.0 * (y * z - x * w)
    rotation[2, 0] = 2.0 * (x * z - y * w)
    rotation[2, 1] = 2.0 * (y * z + x * w)
    rotation[2, 2] = 1.0 - 2.0 * (x * x + y * y)


@numba.njit(cache=True)
def turn(body, rx, ry, rz):
    """Turn the body's orientation by the rotation vector (rx, ry, rz), world axes [rad]."""
    angle = np.sqrt(rx * rx + ry * ry + rz * rz)
    if angle == 0.0:
        return
    s = np.sin(0.5 * angle) / angle
    a0, a1, a2, a3 = s * rx, s * ry, s * rz, np.cos(0.5 * angle)
    q = BODY_QUATERNION
    b0, b1, b2, b3 = body[q], body[q + 1], body[q + 2], body[q + 3]
    # a (x) b, quaternions (x, y, z, w)
    c0 = a3 * b0 + a0 * b3 + a1 * b2 - a2 * b1
    c1 = a3 * b1 - a0 * b2 + a1 * b3 + a2 * b0
    c2 = a3 * b2 + a0 * b1 - a1 * b0 + a2 * b3
    c3 = a3 * b3 - a0 * b0 - a1 * b1 - a2 * b2
    norm = np.sqrt(c0 * c0 + c1 * c1 + c2 * c2 + c3 * c3)
    body[q], body[q + 1], body[q + 2], body[q + 3] = c0 / norm, c1 / norm, c2 / norm, c3 / norm


@numba.njit(cache=True, inline='always')
def roll_pitch(body):
    """Return the body's roll and pitch angles [rad] (Z-Y-X Euler angles of its quaternion)."""
    x = body[BODY_QUATERNION]
    y = body[BODY_QUATERNION + 1]
    z = body[BODY_QUATERNION + 2]
    w = body[BODY_QUATERNION + 3]
    roll = np.arctan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    sine = min(max(2.0 * (w * y - z * x), -1.0), 1.0)
    return roll, np.arcsin(sine)


@numba.njit(cache=True, inline='always')
def _to_world(rotation, diagonal, out, row, col):
    """Add R diag(diagonal) R^T into out[row:row + 3, col:col + 3]."""
    for i in range(3):
        for j in range(3):
            s = 0.0
            for k in range(3):
                s += rotation[i, k] * diagonal[k] * rotation[j, k]
            out[row + i, col + j] += s


@numba.njit(cache=True)
def mass_matrix(body, rotation, mass):
    """Fill mass (6, 6) with the body's mass and inertia, added ones with them, world axes."""
    mass[:] = 0.0
    linear = np.empty(3)
    angular = np.empty(3)
    for k in range(3):
        linear[k] = body[BODY_MASS] + body[BODY_ADDED + k]
        angular[k] = body[BODY_INERTIA + k] + body[BODY_ADDED + 3 + k]
    if body[BODY_FULL_ADDED] != 0.0:  # a database's A_inf, couplings and all
        for k in range(3):
            linear[k] = body[BODY_MASS]
            angular[k] = body[BODY_INERTIA + k]
        _full_to_world(rotation, body, BODY_ADDED_MATRIX, mass)
    _to_world(rotation, linear, mass, 0, 0)
    _to_world(rotation, angular, mass, 3, 3)


@numba.njit(cache=True)
def _full_to_world(rotation, body, column, out):
    """Add T X T^T into out (6, 6): X a 6x6 in body axes, row-major in `body` from `column`."""
    for p in range(2):
        for q in range(2):
            for i in range(3):
                for j in range(3):
                    s = 0.0
                    for k in range(3):
                        for m in range(3):
                            s += (rotation[i, k] * body[column + 6 * (3 * p + k) + 3 * q + m]
                                  * rotation[j, m])
                    out[3 * p + i, 3 * q + j] += s


@numba.njit(cache=True, inline='always')
def add_point_load(load, lever, force):
    """Add a force (3,) acting at lever (3,) from the centre of gravity to load (6,)."""
    for p in range(3):
        load[p] += force[p]
    load[3] += lever[1] * force[2] - lever[2] * force[1]
    load[4] += lever[2] * force[0] - lever[0] * force[2]
    load[5] += lever[0] * force[1] - lever[1] * force[0]


@numba.njit(cache=True)
def add_point_matrix(matrix, lever, block, scale):
    """
    Add scale J^T block J to matrix (6, 6): a point's 3x3 block carried to the body.

    J = [I, -[lever]x] takes the body's accelerations to the point's (a + alpha x r).
    """
    # cross[i, j] = [r]x
    r0, r1, r2 = lever[0], lever[1], lever[2]
    cross = np.array([[0.0, -r2, r1], [r2, 0.0, -r0], [-r1, r0, 0.0]])
    bc = np.zeros((3, 3))  # block [r]x
    cb = np.zeros((3, 3))  # [r]x block
    for i in range(3):
        for j in range(3):
            for k in range(3):
                bc[i, j] += block[i, k] * cross[k, j]
                cb[i, j] += cross[i, k] * block[k, j]
    for i in range(3):
        for j in range(3):
            matrix[i, j] += scale * block[i, j]
            matrix[i, 3 + j] -= scale * bc[i, j]
            matrix[3 + i, j] += scale * cb[i, j]
            s = 0.0
            for k in range(3):
                s += cb[i, k] * cross[k, j]
            matrix[3 + i, 3 + j] -= scale * s


@numba.njit(cache=True, inline='always')
def _hold(pole, h):
    """
    Return exp(lambda h) and the first-order hold's weights g0, g1 of a mode over a step h.

    z' = lambda z + f, f linear over the step from f0 to f1: z1 = exp(lambda h) z0 + g0 f0
    + g1 f1, exactly (their series where the closed form would cancel).
    """
    x = pole * h
    growth = np.exp(x)
    if abs(x) < 1e-3:
        g1 = h * (0.5 + x / 6.0 + x * x / 24.0)
        g0 = h * (0.5 + x / 3.0 + x * x / 8.0)
    else:
        g1 = (growth - 1.0 - x) / (pole * x)
        g0 = (growth - 1.0) / pole - g1
    return growth, g0, g1


@numba.njit(cache=True, inline='always')
def _body_velocities(body, rotation, u):
    """Put the body's velocity and angular velocity in body axes into u (6,)."""
    for k in range(3):
        u[k] = 0.0
        u[3 + k] = 0.0
        for i in range(3):
            u[k] += rotation[i, k] * body[BODY_VELOCITY + i]
            u[3 + k] += rotation[i, k] * body[BODY_OMEGA + i]


@numba.njit(cache=True, inline='always')
def _driven(body, m, u):
    """Return b . u of the mode whose first column is m."""
    bu = 0j
    for k in range(6):
        bu += complex(body[m + MODE_INPUT + k], body[m + MODE_INPUT + 6 + k]) * u[k]
    return bu


@numba.njit(cache=True)
def _step_modes(body, h, start):
    """
    Take the start or the end of a step h of the radiation memory's modes.

    Start: z <- exp(lambda h) z + g0 b . u; end: z <- z + g1 b . u; u the body's velocities
    now (_hold).
    """
    modes = int(body[BODY_MODES])
    if modes == 0:
        return
    rotation = np.empty((3, 3))
    rotation_of(body, rotation)
    u = np.empty(6)
    _body_velocities(body, rotation, u)
    for i in range(modes):
        m = BODY_MODE + i * MODE_COLUMNS
        growth, g0, g1 = _hold(complex(body[m + MODE_POLE], body[m + MODE_POLE + 1]), h)
        z = complex(body[m + MODE_STATE], body[m + MODE_STATE + 1])
        if start:
            z = growth * z + g0 * _driven(body, m, u)
        else:
            z = z + g1 * _driven(body, m, u)
        body[m + MODE_STATE] = z.real
        body[m + MODE_STATE + 1] = z.imag


@numba.njit(cache=True)
def start_modes(body, h):
    """
    Start a step h of the radiation memory's modes at the body's state now (its start).

    z <- exp(lambda h) z + g0 b . u0; finish_modes adds g1 b . u1 at the step's end
    (_hold). Nothing without modes.
    """
    _step_modes(body, h, True)


@numba.njit(cache=True)
def finish_modes(body, h):
    """Finish the step h start_modes started, at the body's state now (its end)."""
    _step_modes(body, h, False)


@numba.njit(cache=True)
def _memory_load(body, rotation, ahead, load, jacobians, damping):
    """
    Add the radiation memory's load -sum_i w_i Re(c_i z_i) (body axes) to load (6,).

    ahead > 0: the modes are started on a step of that length (start_modes) and the body is
    at its end: z_i + g1 b_i . u, and (jacobians) its slope in u into damping, world axes.
    """
    u = np.empty(6)
    _body_velocities(body, rotation, u)
    memory = np.zeros(6)
    slope = np.zeros((6, 6))
    for i in range(int(body[BODY_MODES])):
        m = BODY_MODE + i * MODE_COLUMNS
        weight = body[m + MODE_WEIGHT]
        z = complex(body[m + MODE_STATE], body[m + MODE_STATE + 1])
        g1 = 0j
        if ahead > 0.0:
            _, _, g1 = _hold(complex(body[m + MODE_POLE], body[m + MODE_POLE + 1]), ahead)
            z += g1 * _driven(body, m, u)
        for k in range(6):
            c = complex(body[m + MODE_OUTPUT + k], body[m + MODE_OUTPUT + 6 + k])
            memory[k] += weight * (c * z).real
            if jacobians and ahead > 0.0:
                for j in range(6):
                    b = complex(body[m + MODE_INPUT + j], body[m + MODE_INPUT + 6 + j])
                    slope[k, j] += weight * (g1 * c * b).real
    for part in range(2):
        for i in range(3):
            for k in range(3):
                load[3 * part + i] -= rotation[i, k] * memory[3 * part + k]
    if jacobians and ahead > 0.0:
        _full_to_world(rotation, slope.ravel(), 0, damping)


@numba.njit(cache=True)
def body_loads(body, b, fenders, rotation, t, ahead, load, jacobians, stiffness, damping):
    """
    Put body b's own loads (see the module docstring) into load (6,).

    :param t: the body's clock (BODY_CLOCK) at this state: the external load is
        BODY_LOAD + BODY_LOAD_RATE t.
    :param ahead: 0, or the step [s] the radiation memory's modes were started on
        (start_modes) with the body now at its end (_memory_load).
    :param jacobians: also fill stiffness and damping (6, 6) (minus the loads' Jacobians in
        position and velocity, world axes about the centre of gravity); else they are left.
    """
    velocity = body[BODY_VELOCITY:BODY_VELOCITY + 3]
    omega = body[BODY_OMEGA:BODY_OMEGA + 3]
    for p in range(6):
        load[p] = body[BODY_LOAD + p] + body[BODY_LOAD_RATE + p] * t
    if jacobians:
        stiffness[:] = 0.0
        damping[:] = 0.0
    # hydrostatics: heave at the origin, roll and pitch about the body axes
    lever = np.empty(3)
    for i in range(3):
        lever[i] = (rotation[i, 0] * body[BODY_ORIGIN] + rotation[i, 1] * body[BODY_ORIGIN + 1]
                    + rotation[i, 2] * body[BODY_ORIGIN + 2])
    heave = body[BODY_POSITION + 2] + lever[2] - body[BODY_REST_Z]
    force = np.zeros(3)
    force[2] = -body[BODY_RESTORING] * heave
    add_point_load(load, lever, force)
    # the moment of V = 1/2 (k_roll phi^2 + k_pitch theta^2) in Z-Y-X angles: about the
    # level heading axis and the pitch axis, never about the vertical (no yaw from it)
    roll, pitch = roll_pitch(body)
    heading_x, heading_y = rotation[0, 0], rotation[1, 0]  # body x's level part
    level = np.sqrt(heading_x * heading_x + heading_y * heading_y)  # cos(pitch)
    if level > 1e-9:
        cos_yaw, sin_yaw = heading_x / level, heading_y / level
        tip = -body[BODY_RESTORING + 1] * roll / level
        nod = -body[BODY_RESTORING + 2] * pitch
        load[3] += tip * cos_yaw - nod * sin_yaw  # tip along the heading, nod along
        load[4] += tip * sin_yaw + nod * cos_yaw  # the pitch axis (-sin, cos, 0)
    if jacobians:
        block = np.zeros((3, 3))
        block[2, 2] = body[BODY_RESTORING]
        add_point_matrix(stiffness, lever, block, 1.0)
        tilt = np.array([body[BODY_RESTORING + 1], body[BODY_RESTORING + 2], 0.0])
        _to_world(rotation, tilt, stiffness, 3, 3)
    # damping on the velocities in body axes
    for part in range(2):
        vector = velocity if part == 0 else omega
        slopes = np.empty(3)
        for k in range(3):
            along = (rotation[0, k] * vector[0] + rotation[1, k] * vector[1]
                     + rotation[2, k] * vector[2])
            c1 = body[BODY_LINEAR_DAMPING + 3 * part + k]
            c2 = body[BODY_QUADRATIC_DAMPING + 3 * part + k]
            pull = -(c1 + c2 * abs(along)) * along
            slopes[k] = c1 + 2.0 * c2 * abs(along)
            for i in range(3):
                load[3 * part + i] += rotation[i, k] * pull
        if jacobians:
            _to_world(rotation, slopes, damping, 3 * part, 3 * part)
    if body[BODY_MODES] > 0.0:  # the radiation memory (model/ship/radiation.py)
        _memory_load(body, rotation, ahead, load, jacobians, damping)
    # gyroscopic: -omega x (I omega), inertia and added inertia in world axes
    inertia = np.zeros((6, 6))
    mass_matrix(body, rotation, inertia)
    spin = np.empty(3)
    for i in range(3):
        spin[i] = (inertia[3 + i, 3] * omega[0] + inertia[3 + i, 4] * omega[1]
                   + inertia[3 + i, 5] * omega[2])
    load[3] -= omega[1] * spin[2] - omega[2] * spin[1]
    load[4] -= omega[2] * spin[0] - omega[0] * spin[2]
    load[5] -= omega[0] * spin[1] - omega[1] * spin[0]
    # the fenders it touches
    point = np.empty(3)
    for f in range(fenders.shape[0]):
        if int(fenders[f, FENDER_BODY]) != b:
            continue
        compression, _, slope, sliding = fender_force(fenders[f], body, rotation, velocity,
                                                      omega, force, point)
        if compression <= 0.0:
            continue
        for i in range(3):
            lever[i] = point[i] - body[BODY_POSITION + i]
        add_point_load(load, lever, force)
        if jacobians:
            normal = fenders[f, FENDER_NORMAL:FENDER_NORMAL + 3]
            block = np.empty((3, 3))
            for i in range(3):
                for j in range(3):
                    block[i, j] = slope * normal[i] * normal[j]
            add_point_matrix(stiffness, lever, block, 1.0)
            if sliding > 0.0:
                for i in range(3):
                    for j in range(3):
                        block[i, j] = sliding * ((1.0 if i == j else 0.0) - normal[i] * normal[j])
                add_point_matrix(damping, lever, block, 1.0)


@numba.njit(cache=True)
def place_points(bodies, points, point_x, point_v):
    """Put every body point where its body carries it: position and velocity."""
    rotation = np.empty((3, 3))
    for b in range(bodies.shape[0]):
        body = bodies[b]
        rotation_of(body, rotation)
        for q in range(points.shape[0]):
            if points[q, KIND] != CARRIED or int(points[q, POINT_BODY]) != b:
                continue
            r = np.empty(3)
            for i in range(3):
                r[i] = (rotation[i, 0] * points[q, POINT_OFFSET]
                        + rotation[i, 1] * points[q, POINT_OFFSET + 1]
                        + rotation[i, 2] * points[q, POINT_OFFSET + 2])
            w0, w1, w2 = body[BODY_OMEGA], body[BODY_OMEGA + 1], body[BODY_OMEGA + 2]
            point_x[q, 0] = body[BODY_POSITION] + r[0]
            point_x[q, 1] = body[BODY_POSITION + 1] + r[1]
            point_x[q, 2] = body[BODY_POSITION + 2] + r[2]
            point_v[q, 0] = body[BODY_VELOCITY] + w1 * r[2] - w2 * r[1]
            point_v[q, 1] = body[BODY_VELOCITY + 1] + w2 * r[0] - w0 * r[2]
            point_v[q, 2] = body[BODY_VELOCITY + 2] + w0 * r[1] - w1 * r[0]


@numba.njit(cache=True, inline='always')
def lever_of(bodies, points, point_x, q):
    """Return point q's lever from its body's centre of gravity, world axes (3,)."""
    b = int(points[q, POINT_BODY])
    lever = np.empty(3)
    for i in range(3):
        lever[i] = point_x[q, i] - bodies[b, BODY_POSITION + i]
    return lever
