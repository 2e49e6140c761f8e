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
Ground contact: a flat seabed and an optional quay block, with MoorDyn's law, made smooth.

What MoorDyn (v2.7, source/Line.cpp, Line::getStateDeriv) does, per line node i with
lumped length len_i (half of each adjacent segment) and line diameter d, when the node is
below the seabed (z < seabed z, penetration delta = seabed z - z):

    B_z = (kBot delta - cBot v_z) d len_i                  (may be negative: it can pull)
    B_h = -F v_h / |v_h|,  F = mu FricDamp |v_h|,  but F = mu |B_z| once
          mu FricDamp |v_h| > StatDynFricScale mu |B_z|       (0 when v_h = 0)

v_h is the node's horizontal velocity. Defaults (source/MoorDyn2.cpp, the MoorDyn
constructor; options kBot, cBot, FrictionCoefficient, FricDamp, StatDynFricScale of the
input file): kBot = 3.0e6 Pa/m, cBot = 3.0e5 Pa s/m, FrictionCoefficient mu = 0 (no
friction), FricDamp = 200 N s/m, StatDynFricScale = 1. FricDamp is per node, not per metre:
below saturation the friction is a plain viscous damper mu FricDamp on the node. MoorDyn's
free points (source/Point.cpp) have no ground contact at all, and it has no quay.

What this module does, and where it differs:

- Normal force, per contact area d len_i (`width` times `length`), for a penetration
  delta > 0 and the velocity v_n along the outward normal:
      F_n = max(0, k_b delta - c_b v_n min(1, delta / delta_d)) d len_i.
  The damping fades in over the ramp depth delta_d (`sink`: the line's static sink depth,
  computed by the caller): MoorDyn's full damping acts the instant a node touches, so a
  node arriving at speed gets a force step of c_b v_z d len_i (for a chain, far above its
  weight), which rings an explicit step and kicks the implicit one. Here the force is
  continuous in delta. At rest on the ground a node sinks by its weight / (k_b d len_i),
  which is about delta_d, where the damping is full, so the resting behaviour is MoorDyn's.
  And the ground never pulls (the max): a node lifting off fast is let go, not held down.
- Friction: MoorDyn's regularised Coulomb law, with StatDynFricScale fixed at 1 (so the law
  is continuous: F = mu min(FricDamp |v_t|, F_n)) and FricDamp at 200 N s/m, against the
  velocity v_t in the contact surface's plane. Because F_n is never negative, |F_n| is F_n.
- Quay: a block with a vertical face, which MoorDyn does not have. Edge point E (E.z: deck
  level), outward horizontal unit normal n, depth D below the deck. A particle is inside
  when (x - E).n < 0 and E.z - D < z < E.z; it is pushed out through the nearer surface
  (the top: delta = E.z - z along +z; the face: delta = -(x - E).n along +n) with the same
  law, friction in that surface's plane. An all-zero normal means no quay.

For the implicit step, add_contact_block adds h C + h^2/2 S with C, S minus the force's
Jacobians in v and x, kept symmetric and positive semidefinite so that the step matrix
stays so: normal n n^T (h c_b ramp + h^2/2 k_b) d len_i; friction h mu FricDamp P below
saturation, h mu F_n / |v_t| (P - t t^T) once saturated (P = I - n n^T the plane's
projector, t = v_t / |v_t|). Left out: the ramp's own slope (c_b v_n / delta_d), and the
coupling of the saturated friction to the normal force (it would make the block
unsymmetric); both are zero for a particle resting in the ground.
"""

import numba
import numpy as np

from ..layout import (ENV_QUAY_DEPTH, ENV_QUAY_EDGE, ENV_QUAY_NORMAL, ENV_SEABED_DAMPING,
                      ENV_SEABED_FRICTION, ENV_SEABED_LEVEL, ENV_SEABED_STIFFNESS)

FRICTION_DAMPING = 200.0  # MoorDyn's FricDamp [N s/m]: the friction's slope at low speed
STATIC_DYNAMIC_SCALE = 1.0  # MoorDyn's StatDynFricScale; 1 keeps the friction continuous


@numba.njit(cache=True, inline='always')
def _quay(x, row, env):
    """
    Return the particle's penetration into the quay block and the surface's normal.

    (delta, nx, ny, nz): delta > 0 inside (through the nearer of the top and the face),
    else 0.
    """
    nx = env[ENV_QUAY_NORMAL]
    ny = env[ENV_QUAY_NORMAL + 1]
    deck = env[ENV_QUAY_EDGE + 2]
    z = x[row, 2]
    if not (z < deck and z > deck - env[ENV_QUAY_DEPTH]):
        return 0.0, 0.0, 0.0, 0.0
    out = (x[row, 0] - env[ENV_QUAY_EDGE]) * nx + (x[row, 1] - env[ENV_QUAY_EDGE + 1]) * ny
    if not out < 0.0:  # in front of the face, or no quay (n = 0)
        return 0.0, 0.0, 0.0, 0.0
    norm = np.sqrt(nx * nx + ny * ny)
    face = -out / norm
    top = deck - z
    if top <= face:
        return top, 0.0, 0.0, 1.0
    return face, nx / norm, ny / norm, 0.0


@numba.njit(cache=True, inline='always')
def _normal_force(v, row, nx, ny, nz, delta, area, sink, env):
    """Return (F_n, v_n, ramp): the normal force [N] (>= 0), normal speed, damping ramp."""
    vn = v[row, 0] * nx + v[row, 1] * ny + v[row, 2] * nz
    ramp = 1.0
    if delta < sink:
        ramp = delta / sink
    fn = (env[ENV_SEABED_STIFFNESS] * delta - env[ENV_SEABED_DAMPING] * vn * ramp) * area
    return max(fn, 0.0), vn, ramp


@numba.njit(cache=True, inline='always')
def _add_surface(v, row, nx, ny, nz, delta, area, sink, env, out, out_row):
    """Add the force of one surface (outward normal n, penetration delta > 0) to out."""
    fn, vn, ramp = _normal_force(v, row, nx, ny, nz, delta, area, sink, env)
    if fn <= 0.0:
        return
    fx, fy, fz = fn * nx, fn * ny, fn * nz
    mu = env[ENV_SEABED_FRICTION]
    if mu > 0.0:
        tx = v[row, 0] - vn * nx
        ty = v[row, 1] - vn * ny
        tz = v[row, 2] - vn * nz
        slip = np.sqrt(tx * tx + ty * ty + tz * tz)
        if slip > 0.0:
            friction = mu * FRICTION_DAMPING * slip
            if friction > STATIC_DYNAMIC_SCALE * mu * fn:
                friction = mu * fn
            scale = friction / slip
            fx -= scale * tx
            fy -= scale * ty
            fz -= scale * tz
    out[out_row, 0] += fx
    out[out_row, 1] += fy
    out[out_row, 2] += fz


@numba.njit(cache=True, inline='always')
def _add_surface_block(v, row, nx, ny, nz, delta, area, sink, env, h, half_h2, block):
    """Add h C + h^2/2 S of one surface's force to block (see the module docstring)."""
    fn, vn, ramp = _normal_force(v, row, nx, ny, nz, delta, area, sink, env)
    if fn <= 0.0:
        return
    normal = (h * env[ENV_SEABED_DAMPING] * ramp + half_h2 * env[ENV_SEABED_STIFFNESS]) * area
    mu = env[ENV_SEABED_FRICTION]
    slide = 0.0  # h times the friction's damping across the sliding direction (P - t t^T)
    along = 0.0  # ... and along it (t t^T)
    tx = v[row, 0] - vn * nx
    ty = v[row, 1] - vn * ny
    tz = v[row, 2] - vn * nz
    slip = np.sqrt(tx * tx + ty * ty + tz * tz)
    if mu > 0.0:
        if FRICTION_DAMPING * slip <= STATIC_DYNAMIC_SCALE * fn:
            slide = h * mu * FRICTION_DAMPING
            along = slide
        else:  # saturated: constant magnitude, only its direction turns with v_t
            slide = h * mu * fn / slip
    inv = 1.0 / slip if slip > 0.0 else 0.0
    tx *= inv
    ty *= inv
    tz *= inv
    n = (nx, ny, nz)
    t = (tx, ty, tz)
    for p in range(3):
        for q in range(3):
            plane = (1.0 if p == q else 0.0) - n[p] * n[q]
            block[p, q] += (normal * n[p] * n[q] + slide * plane
                            + (along - slide) * t[p] * t[q])


@numba.njit(cache=True)
def add_contact(x, v, row, width, length, sink, env, out, out_row):
    """
    Add the seabed and quay contact force on particle `row` to out[out_row].

    :param width: contact width d [m] (a line's diameter).
    :param length: lumped length len_i [m] (the contact area is width * length).
    :param sink: the damping's ramp depth delta_d [m] (> 0).
    :param env: the ENV array (layout.ENV_*).
    """
    delta = env[ENV_SEABED_LEVEL] - x[row, 2]
    # the common case first: above the ground and no quay
    if not delta > 0.0 and env[ENV_QUAY_NORMAL] == 0.0 and env[ENV_QUAY_NORMAL + 1] == 0.0:
        return
    area = width * length
    if not area > 0.0:
        return
    if delta > 0.0:
        _add_surface(v, row, 0.0, 0.0, 1.0, delta, area, sink, env, out, out_row)
    delta, nx, ny, nz = _quay(x, row, env)
    if delta > 0.0:
        _add_surface(v, row, nx, ny, nz, delta, area, sink, env, out, out_row)


@numba.njit(cache=True)
def add_contact_block(x, v, row, width, length, sink, env, h, half_h2, block):
    """
    Add h C + h^2/2 S of particle `row`'s contact force to block (3, 3).

    C, S: minus the force's Jacobians in v and x, in their symmetric positive semidefinite
    part (the module docstring says what is left out). Arguments as add_contact; h: the
    step, half_h2: h^2 / 2.
    """
    delta = env[ENV_SEABED_LEVEL] - x[row, 2]
    if not delta > 0.0 and env[ENV_QUAY_NORMAL] == 0.0 and env[ENV_QUAY_NORMAL + 1] == 0.0:
        return
    area = width * length
    if not area > 0.0:
        return
    if delta > 0.0:
        _add_surface_block(v, row, 0.0, 0.0, 1.0, delta, area, sink, env, h, half_h2, block)
    delta, nx, ny, nz = _quay(x, row, env)
    if delta > 0.0:
        _add_surface_block(v, row, nx, ny, nz, delta, area, sink, env, h, half_h2, block)
