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

"""Step a System through time with one of the integrators: the one entry to them."""

import numpy as np

from . import adaptive
from .kernels import run_kernel
from ..model.objects import System
from ..model.superelastic import MAX_ITERATIONS

INTEGRATORS = ('adaptive', 'implicit_euler', 'improved_euler')


def step(system: System, integrator: str, dt: float, drive_x: np.ndarray, drive_v: np.ndarray,
         max_iterations: int = MAX_ITERATIONS, implicit_bending: bool = False,
         compiled: bool = True, fine_step=0.0) -> list:
    """
    Take len(drive_x) steps of dt with the driven points at drive_x, drive_v (n, Q, 3).

    :param integrator: 'improved_euler', 'implicit_euler' or 'adaptive' (adaptive.py).
    :param compiled: False runs the same kernels' Python code (``.py_func``), for tests.
    :param fine_step: adaptive only: the largest stable improved Euler step now [s], one
        for every line or each line's (L,).
    :returns: (line index, step of the run) of every line that parted in these steps
        (a fraction where the adaptive integrator's improved Euler steps parted it).
    """
    if integrator == 'adaptive':
        adaptive.run(system, dt, drive_x, drive_v, fine_step, max_iterations,
                     implicit_bending, compiled)
    else:
        run_kernel(system, integrator, dt, drive_x, drive_v, max_iterations, implicit_bending,
                   compiled)
    # the accelerations the adaptive step leaves are the state's (HISTORY says whose)
    return system.took_steps(history_kept=integrator == 'adaptive')
