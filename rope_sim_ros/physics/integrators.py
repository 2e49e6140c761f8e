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
Time integration of the rope and the choice of its time step.

The seed's improved Euler (eq. 7) is Heun's method: an Euler predictor, then the mean of the
two accelerations for the velocity and the trapezoid of the two velocities for the position.
On an undamped oscillator its amplification is |G|^2 = 1 + (w dt)^4 / 4 > 1 for every step,
so it lives on the line's damping: the automatic step is the largest one for which every
axial mode of the chain, with its damping, is stable, times a safety factor.
"""

import numpy as np

from .rope import Rope, RopeProperties

SAFETY_FACTOR = 0.8


def improved_euler_step(rope: Rope, dt: float, ends_next: np.ndarray,
                        end_velocities_next: np.ndarray) -> None:
    """
    Advance the rope by dt in place (seed eq. 7).

    :param rope: the rope at time t.
    :param dt: step [s].
    :param ends_next: positions of particles 0 and N at t + dt, shape (2, 3).
    :param end_velocities_next: their velocities at t + dt, shape (2, 3).
    """
    x, v = rope.x, rope.v
    a1 = rope.accelerations(x, v)
    x_pred = x + dt * v
    v_pred = v + dt * a1
    x_pred[[0, -1]] = ends_next
    v_pred[[0, -1]] = end_velocities_next
    a2 = rope.accelerations(x_pred, v_pred)
    x += (0.5 * dt) * (v + v_pred)
    v += (0.5 * dt) * (a1 + a2)
    x[[0, -1]] = ends_next
    v[[0, -1]] = end_velocities_next


def _heun_growth(z: np.ndarray) -> np.ndarray:
    """|R(z)| of Heun's method, R(z) = 1 + z + z^2 / 2."""
    return np.abs(1.0 + z + 0.5 * z * z)


def _mode_eigenvalues(props: RopeProperties, count: int = 400) -> np.ndarray:
    """
    Eigenvalues of the chain's axial modes, from the slowest to the fastest.

    The chain's frequencies lie in (0, w_max] with w_max^2 <= 4 (k_s + k_b) / m
    (Gershgorin). Each mode is damped in proportion to its stiffness (w^2 beta).
    """
    m = props.particle_mass
    k = props.structural_stiffness + props.bending_stiffness
    c = props.structural_damping + props.bending_damping
    w2 = 4.0 * k / m * np.geomspace(1e-8, 1.0, count)
    # roots of s^2 + (c/k) w^2 s + w^2 = 0, both branches (overdamped modes have two)
    half = 0.5 * (c / k) * w2
    root = np.sqrt((half * half - w2).astype(complex))
    return np.concatenate([-half + root, -half - root])


def stability_limit(props: RopeProperties) -> float:
    """
    Largest stable improved-Euler step [s] for the line's axial modes.

    Returns 0 when no step is stable (an undamped line).
    """
    if props.structural_damping + props.bending_damping <= 0.0:
        return 0.0  # |G| > 1 for every mode: rounding would hide it at tiny steps
    modes = _mode_eigenvalues(props)
    lo, hi = 0.0, 4.0 / np.abs(modes).max()
    if _heun_growth(1e-9 * hi * modes).max() > 1.0:
        return 0.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _heun_growth(mid * modes).max() <= 1.0 + 1e-12:
            lo = mid
        else:
            hi = mid
    return lo


def wave_time_step(props: RopeProperties) -> float:
    """Time an axial wave takes to cross one segment: (L/N) sqrt(m / EA) [s]."""
    return props.segment_length * np.sqrt(props.mass_per_length / props.axial_stiffness)


IMPLICIT_STEPS_PER_AXIAL_PERIOD = 4.0
IMPLICIT_MAX_STEP = 0.005
# Bending springs go into the implicit matrix once an explicit treatment would need a step
# below this fraction of their own stability limit (h^2 k_b / m > this).
IMPLICIT_BENDING_THRESHOLD = 0.1


def first_axial_period(props: RopeProperties) -> float:
    """Period of the line's first axial mode with both ends held, 2 L sqrt(m / EA) [s]."""
    return 2.0 * props.length * np.sqrt(props.mass_per_length / props.axial_stiffness)


def automatic_time_step(props: RopeProperties, integrator: str = 'improved_euler') -> float:
    """
    Choose the step used when the user sets time_step 0 [s].

    improved_euler: the stability limit times a safety factor. implicit_euler (stable for any
    step): a step that still sees the first axial mode, at most IMPLICIT_MAX_STEP.

    :raises ValueError: the line has no damping, so the improved Euler step is never stable.
    """
    if integrator == 'implicit_euler':
        return min(IMPLICIT_MAX_STEP, first_axial_period(props) / IMPLICIT_STEPS_PER_AXIAL_PERIOD)
    limit = min(stability_limit(props), wave_time_step(props))
    if limit <= 0.0:
        raise ValueError(
            'improved_euler is unstable on an undamped line: set axial_damping > 0')
    return SAFETY_FACTOR * limit


def implicit_bending(props: RopeProperties, dt: float) -> bool:
    """Whether the implicit step must include the bending springs in its matrix."""
    return dt * dt * props.bending_stiffness / props.particle_mass > IMPLICIT_BENDING_THRESHOLD
