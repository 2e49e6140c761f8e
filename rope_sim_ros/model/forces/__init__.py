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
Force terms of the mass-spring lines: one module per term, each with what the integrators need.

Every module gives the term's force (for both integrators) and, for the implicit step, its
contribution to the step matrix M + h C + h^2/2 S (C, S: minus the force's Jacobians in v and
x). Adding a term is one module here and one line in kernels.py's assembly. All are numba
functions (njit, cache=True); the tests may run them interpreted through ``.py_func``.

The particle table (see layout.py) holds, per particle, what the terms read: its lumped mass
and length, its drag factor and the rest length, stiffness and damping of the springs starting
at it; the line table the fluid's coefficients; the ENV array what the lines live in.

- gravity: weight (less the displaced fluid's, from fluid);
- springs: structural and bending springs with their dampers;
- drag: the seed's isotropic air drag;
- fluid: buoyancy, MoorDyn's normal and tangential drag in water and air, added mass;
- contact: seabed and quay.
"""
