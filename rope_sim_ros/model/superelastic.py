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
The seed's cure for super-elasticity (section 1.2): position and velocity adjustment.

After a step, wherever a structural spring is stretched beyond l_i (1 + max_strain) (l_i its
rest length), its two particles move toward each other along it until that length is
restored, and their velocities along it are made equal, so that it stops stretching. They
move in inverse proportion to their masses: a particle on a fixed or driven point (inverse
mass 0) not at all, a line end on a free point (a payload) as that point's whole lumped
mass. For one spring between two equal free particles this is exactly the paper's rule:
both move by half the excess.

Made right in three ways. Restoring one spring over-stretches its neighbour, so all springs
over the limit are restored together: a Newton projection onto the constraint set whose
matrix J W J^T is tridiagonal for a chain and solves in O(N), converging in a few
iterations where pairwise sweeps need thousands on a nearly straight line. The velocity
adjustment removes the *relative* velocity along each limited spring and keeps the pair's
momentum, where the paper zeroes both components, which would brake a line simply being
towed. And the bending springs get no threshold of their own: a bending spring (i, i+2)
cannot exceed 2 l0 (1 + max_strain) while both structural springs under it obey theirs, and
projecting both kinds makes them fight on a straight line.

Compiled with numba; the integrators apply it line by line (see kernels.py).

On a line with a strain-tension curve the threshold is no lower than the strain at which the
curve pulls LIMIT_BREAKING_LOADS times the breaking load (curve_strain_limit): a nylon rope
breaks near 25 % strain, the default threshold, and a limit there would cut its curve off
where the rope still pulls harder with every centimetre.
"""

import math

import numba
import numpy as np

# Sweeps stop at TOLERANCE; the cap matters only for a line held straight at its full reach,
# where every segment sits at the limit and each sweep moves a correction one segment on:
# 50 sweeps left a 64-segment manila line jerked to its reach at 8.5 % strain (limit 1 %).
MAX_ITERATIONS = 200
TOLERANCE = 1e-9
REGULARISATION = 1e-6
# A curve's strain limit: where it pulls this many breaking loads (its last tabulated
# tension where the line has no MBL), well past any tension a line that has not parted holds.
LIMIT_BREAKING_LOADS = 2.0


def curve_strain_limit(max_strain: float, curve, mbl: float) -> float:
    """
    Return the strain limit of a line: max_strain, raised on a curve to its 2 MBL strain.

    :param curve: the line's TensionCurve, or None (a linear line: max_strain).
    :param mbl: its minimum breaking load [N]; inf or 0: unknown.
    """
    if curve is None:
        return max_strain
    load = mbl if math.isfinite(mbl) and mbl > 0.0 else float(curve.tensions[-1])
    return max(max_strain, float(curve.strain_at(LIMIT_BREAKING_LOADS * load)))


@numba.njit(cache=True)
def _directions(x, d, length):
    """Fill unit vectors d (N, 3) and lengths (N,) of the structural springs."""
    for i in range(x.shape[0] - 1):
        for p in range(3):
            d[i, p] = x[i + 1, p] - x[i, p]
        length[i] = np.sqrt(d[i, 0] ** 2 + d[i, 1] ** 2 + d[i, 2] ** 2)
        for p in range(3):
            d[i, p] /= max(length[i], 1e-300)


@numba.njit(cache=True, inline='always')
def over_limit(x, rest, first, last, max_strain):
    """
    Tell whether a structural spring of rows first..last of x is over the limit adjust sets.

    rest[i] is the rest length of the spring (i, i + 1). A cheap test (no scratch arrays, no
    array views) the integrators make before calling adjust on a line.
    """
    scale = 1.0 + max_strain
    for i in range(first, last):
        length = np.sqrt((x[i + 1, 0] - x[i, 0]) ** 2 + (x[i + 1, 1] - x[i, 1]) ** 2
                         + (x[i + 1, 2] - x[i, 2]) ** 2)
        if length > rest[i] * scale * (1.0 + TOLERANCE):
            return True
    return False


@numba.njit(cache=True)
def _solve_chain(u, inv_mass, active, rhs):
    """Solve (J W J^T) lam = rhs over the active springs (tridiagonal Thomas); rhs -> lam."""
    n = len(rhs)
    diag = np.zeros(n)
    upper = np.zeros(n)
    for i in range(n):
        if active[i]:
            # a whisker of compliance keeps a straight chain pulled past its total limit
            # (collinear constraints: a singular matrix) solvable, in the least-squares sense
            diag[i] = (inv_mass[i] + inv_mass[i + 1]) * (1.0 + REGULARISATION)
            if i + 1 < n and active[i + 1]:
                upper[i] = -inv_mass[i + 1] * (u[i, 0] * u[i + 1, 0] + u[i, 1] * u[i + 1, 1]
                                               + u[i, 2] * u[i + 1, 2])
        if diag[i] <= 0.0:  # inactive, or both ends kinematic: no correction
            diag[i], rhs[i] = 1.0, 0.0
            upper[i] = 0.0
            if i > 0:
                upper[i - 1] = 0.0
    for i in range(1, n):
        factor = upper[i - 1] / diag[i - 1]
        diag[i] -= factor * upper[i - 1]
        rhs[i] -= factor * rhs[i - 1]
    rhs[n - 1] /= diag[n - 1]
    for i in range(n - 2, -1, -1):
        rhs[i] = (rhs[i] - upper[i] * rhs[i + 1]) / diag[i]


@numba.njit(cache=True)
def _apply(q, u, inv_mass, lam):
    """Apply q -= W J^T lam: particle i moves along u_i by w_i lam_i, back along u_{i-1}."""
    for i in range(len(lam)):
        for p in range(3):
            q[i, p] += inv_mass[i] * lam[i] * u[i, p]
            q[i + 1, p] -= inv_mass[i + 1] * lam[i] * u[i, p]


@numba.njit(cache=True)
def adjust(x, v, inv_mass, rest, max_strain, max_iterations):
    """
    Apply the position and velocity adjustment in place.

    :param x: positions (N+1, 3), modified in place.
    :param v: velocities (N+1, 3), modified in place.
    :param inv_mass: inverse masses, shape (N+1,): 0 for an end on a fixed or driven point;
        only their ratios matter (1 for equal particles will do).
    :param rest: unstretched structural spring lengths l_i [m], shape (N,).
    :param max_strain: threshold strain.
    :param max_iterations: bound on the Newton iterations.

    :returns: Newton iterations taken (0 when no spring was over the threshold).
    """
    n = x.shape[0] - 1
    scale = 1.0 + max_strain
    if not over_limit(x, rest, 0, n, max_strain):
        return 0  # the common case, without the projection's scratch arrays
    u = np.empty((n, 3))
    length = np.empty(n)
    active = np.zeros(n, dtype=np.bool_)
    lam = np.empty(n)
    iterations = 0
    while iterations < max_iterations:
        _directions(x, u, length)
        over = False
        for i in range(n):
            if length[i] > rest[i] * scale * (1.0 + TOLERANCE):
                active[i] = True
                over = True
        if not over:
            break
        # limited springs stay at their limit while the others are being restored
        for i in range(n):
            lam[i] = length[i] - rest[i] * scale if active[i] else 0.0
        _solve_chain(u, inv_mass, active, lam)
        _apply(x, u, inv_mass, lam)
        iterations += 1
    if iterations:
        _directions(x, u, length)
        for i in range(n):
            lam[i] = ((v[i + 1, 0] - v[i, 0]) * u[i, 0] + (v[i + 1, 1] - v[i, 1]) * u[i, 1]
                      + (v[i + 1, 2] - v[i, 2]) * u[i, 2]) if active[i] else 0.0
        _solve_chain(u, inv_mass, active, lam)
        _apply(v, u, inv_mass, lam)
    return iterations
