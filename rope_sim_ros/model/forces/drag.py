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
The seed's isotropic quadratic air drag (eq. 5): f = -kappa |v| v on each particle.

kappa = K_A times the particle's lumped length (the DRAG column of the particle table). Its
velocity Jacobian is -kappa (|v| I + v v^T / |v|): the implicit step adds h times it (negated)
to the particle's diagonal block. It stays beside MoorDyn's drag (fluid.py) for reproducing
the seed's paper: the two add up when both are set.
"""

import numba
import numpy as np


@numba.njit(cache=True, inline='always')
def speed(v, row):
    """Return |v[row]| [m/s]."""
    return np.sqrt(v[row, 0] ** 2 + v[row, 1] ** 2 + v[row, 2] ** 2)


@numba.njit(cache=True, inline='always')
def add_drag(v, row, kappa, out, out_row):
    """Add the drag -kappa |v| v of particle `row` to out[out_row]."""
    s = speed(v, row)
    for p in range(3):
        out[out_row, p] -= kappa * s * v[row, p]


@numba.njit(cache=True, inline='always')
def add_drag_block(v, row, kappa_h, diagonal, block):
    """
    Add h kappa (|v| I + v v^T / |v|) + diagonal I of particle `row` to block.

    kappa_h = h kappa. `diagonal` (the particle's mass) joins the |v| I term in one sum,
    so that the step's matrix keeps its rounding whatever the drag.
    """
    s = speed(v, row)
    for p in range(3):
        for q in range(3):
            jac = kappa_h * v[row, p] * v[row, q] / max(s, 1e-12)
            if p == q:
                jac += kappa_h * s + diagonal
            block[p, q] += jac
