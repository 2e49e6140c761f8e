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
Gravity (seed eq. 4): the weight m g of a lumped mass; it does not depend on the state.

Its Jacobians are zero: it adds nothing to the implicit step's matrix.
"""

import numba


@numba.njit(cache=True, inline='always')
def add_weight(out, row, mass, gravity):
    """Add the weight mass * gravity to out[row] (gravity (3,) [m/s^2])."""
    for p in range(3):
        out[row, p] += mass * gravity[p]
