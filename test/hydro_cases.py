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
A hydrodynamic database whose retardation function is known in closed form, for the tests.

K(t) = sum_m P_m k_m(t), each k_m(t) = exp(-zeta w0 t) (cos(wd t) - zeta w0 / wd sin(wd t))
(wd = w0 sqrt(1 - zeta^2)), whose transform int_0^inf k_m exp(-i w t) dt = i w / (w0^2 - w^2
+ 2 i zeta w0 w) gives B(w) (its real part) and A(w) - A_inf (its imaginary part over w),
a causal pair as a hull's is: B(0) = 0, B ~ w^-2 far out. The P_m are symmetric positive
semi-definite, so that B is at every frequency (the hull takes energy from no motion), with
the couplings a ship's A and B have: sway-roll-yaw and surge-pitch; heave stands alone.
Scaled to a 60 m barge of 3.69e6 kg, its centre of gravity at its body origin.
"""

import math

import numpy as np

from rope_sim_ros.model.ship.hydro import HydroDatabase

MASS = 1025.0 * 60.0 * 15.0 * 4.0  # [kg] a 60 m x 15 m barge at 4 m draft
RADII = (5.0, 17.0, 17.0)  # [m] roll, pitch, yaw
INERTIA = tuple(MASS * k * k for k in RADII)
SCALE = np.array([MASS, MASS, MASS] + list(INERTIA))
WATERPLANE = 900.0  # [m^2]
METACENTRIC = (2.0, 80.0)  # [m] GM_T, GM_L
WATER, G = 1025.0, 9.81
# (w0 [rad/s], zeta, share of each degree of freedom's scale, correlations)
MODES = ((0.8, 0.5, (0.04, 0.3, 0.15, 0.02, 0.4, 0.1)),
         (1.5, 0.35, (0.02, 0.2, 0.1, 0.01, 0.3, 0.08)))
# correlations of the degrees of freedom within each mode (surge-pitch, sway-roll, sway-yaw,
# roll-yaw)
COUPLING = {(0, 4): -0.5, (1, 3): 0.4, (1, 5): 0.3, (3, 5): 0.1}
ADDED_INFINITE = np.diag([0.03, 0.5, 0.7, 0.05, 0.5, 0.2]) * SCALE
for (_i, _j), _share in {(1, 3): -0.1, (1, 5): 0.2, (0, 4): -0.1}.items():
    ADDED_INFINITE[_i, _j] = ADDED_INFINITE[_j, _i] = _share * math.sqrt(
        ADDED_INFINITE[_i, _i] * ADDED_INFINITE[_j, _j])


def residues():
    """Return each mode's P (6, 6): symmetric, positive definite."""
    correlation = np.eye(6)
    for (i, j), value in COUPLING.items():
        correlation[i, j] = correlation[j, i] = value
    assert np.linalg.eigvalsh(correlation).min() > 0.0
    out = []
    for w0, zeta, shares in MODES:
        # P = S R S: the mode's B_ii peaks at share_i scale_i w0 (at w0)
        peak = 1.0 / (2.0 * zeta * w0)  # the largest b_m(w) / (its P) at w = w0
        size = np.sqrt(np.array(shares) * SCALE * w0 / peak)
        out.append(size[:, None] * correlation * size[None, :])
    return out


def transfer(omega: np.ndarray) -> np.ndarray:
    """Return int_0^inf K(t) exp(-i w t) dt (n, 6, 6): B + i w (A - A_inf)."""
    s = 1j * np.asarray(omega, dtype=float)
    out = np.zeros((s.size, 6, 6), dtype=complex)
    for (w0, zeta, _), p in zip(MODES, residues()):
        out += (s / (s * s + 2.0 * zeta * w0 * s + w0 * w0))[:, None, None] * p
    return out


def kernel(t: np.ndarray) -> np.ndarray:
    """Return K(t) (m, 6, 6) in closed form."""
    t = np.asarray(t, dtype=float)
    out = np.zeros((t.size, 6, 6))
    for (w0, zeta, _), p in zip(MODES, residues()):
        rate, wd = zeta * w0, w0 * math.sqrt(1.0 - zeta * zeta)
        k = np.exp(-rate * t) * (np.cos(wd * t) - rate / wd * np.sin(wd * t))
        out += k[:, None, None] * p
    return out


def database(omega: np.ndarray = None) -> HydroDatabase:
    """Return the barge's database at these frequencies (default 0.02 to 4 rad/s, 200)."""
    if omega is None:
        omega = np.linspace(0.02, 4.0, 200)
    h = transfer(omega)
    return HydroDatabase(
        omega=omega, added_mass=ADDED_INFINITE + h.imag / omega[:, None, None],
        radiation_damping=h.real, added_mass_infinite=ADDED_INFINITE,
        headings=np.array([0.0]), excitation=np.zeros((1, omega.size, 6), dtype=complex),
        drift=np.zeros((1, omega.size, 3)), reference_point=np.zeros(3),
        water_depth=math.inf, water_density=WATER, g=G)


def stiffness() -> np.ndarray:
    """Return the barge's hydrostatic stiffness about its centre of gravity (6, 6)."""
    return np.diag([0.0, 0.0, WATER * G * WATERPLANE, MASS * G * METACENTRIC[0],
                    MASS * G * METACENTRIC[1], 0.0])


def rigid_mass() -> np.ndarray:
    """Return the barge's mass and inertia about its centre of gravity (6, 6)."""
    return np.diag([MASS] * 3 + list(INERTIA))


def heave_poles() -> np.ndarray:
    """
    Return the poles s of free heave: (m + A_inf) s^2 + s Khat(s) + k = 0, exactly.

    Khat(s) = sum_m P_m s / (s^2 + 2 zeta w0 s + w0^2) is rational: the roots of a
    polynomial, the slowest-decaying pair first... sorted by decay rate.
    """
    inertia = MASS + ADDED_INFINITE[2, 2]
    k = WATER * G * WATERPLANE
    factors = [np.array([1.0, 2.0 * zeta * w0, w0 * w0]) for w0, zeta, _ in MODES]
    shares = [p[2, 2] for p in residues()]
    poly = np.polyadd(np.polymul(np.polymul([inertia, 0.0, k], factors[0]), factors[1]),
                      np.polymul([1.0, 0.0, 0.0],
                                 shares[0] * factors[1] + shares[1] * factors[0]))
    roots = np.roots(poly)
    return roots[np.argsort(-roots.real)]
