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
The radiation memory of a floating hull: the Cummins equation's retardation function.

A hull moving in calm water makes waves that go on pushing it after it moved. Cummins (1962):

    (M + A_inf) x'' + int_0^t K(t - tau) x'(tau) dtau + C x = loads,

x the six motions about the centre of gravity in body axes (hydro.py), A_inf the added mass
at infinite frequency and K(t) (6x6) the retardation function, from the radiation damping:

    K(t) = (2 / pi) int_0^inf B(omega) cos(omega t) domega.

Ogilvie (1964) gives the frequency-domain record back from K:

    B(omega) = int_0^inf K(t) cos(omega t) dt,
    A(omega) - A_inf = -(1 / omega) int_0^inf K(t) sin(omega t) dt,

which checks a database (retardation_function, ogilvie): its A and B hold together only if
the pair is causal, and its frequencies reach far enough.

**B between and past the database's frequencies.** B is linear between its frequencies;
below the first it rises from 0 at omega = 0 as omega^2 (a floating hull radiates no energy
at zero frequency, and a B linear there would make A(omega) - A_inf diverge as log omega at
low frequency: Kramers-Kronig's integral of B / omega^2); past the last,
omega_N, it falls as (omega_N / omega)^2 up to TAIL_SPAN omega_N and is 0 beyond (a tail of
the order of a slender body's; what it leaves out past 20 omega_N is 1/20 of the last
value's tail). The cosine transform of a line is closed-form, so K is exact for that B: no
quadrature error, at any t.

**The memory's length** (`memory`): K is taken as 0 from the time past which every entry
stays below MEMORY_FRACTION (1e-4) of its scale, sqrt(K_ii(0) K_jj(0)) (a coupling's scale
is its two degrees of freedom's), up to MAX_MEMORY (120 s). So short a fraction because
A(omega) - A_inf weighs K by t at low frequency (-(1 / omega) sin(omega t) -> -t): on an
analytic hull like the tests', cut at 1e-3 (19 s) A at 0.02 rad/s came 2.5 % off, at 1e-4
0.1 %. The modes (below) fit K up to FIT_FRACTION (1e-3) only: past it their own decay
stands for it.

**Stepped as modes** (radiation_modes): the simulator does not sum the convolution over the
past at each step; it carries K as a sum of damped modes, K(t) = sum_i w_i Re(c_i b_i^T
exp(lambda_i t)), each a state z_i' = lambda_i z_i + b_i . u (u the body's six velocities in
body axes), the memory load w_i Re(c_i z_i) summed (forces/body.py steps them exactly for
velocities linear over a step). The modes are a realisation of K's samples (Kung's
eigensystem realisation: a Hankel matrix of the samples, its singular values truncated),
of the least order that fits K within MODE_TOLERANCE of each entry's scale.
benchmarks/radiation_memory.py measured the choice against the convolution summed over the
history at every step, on the tests' barge (12 modes, a 21 s memory): its heave decay's
period within 0.01 % of the exact pole's either way, its damping within 0.5 % (the modes'
fit) and 0.06 %; the memory cost 3 us a step as modes, 82 us as the convolution at a step
of 0.01 s and 519 us at 0.002 s (it grows as the step shrinks; the modes' does not). A
history kept every 10th step cost a sixth and erred 1 to 6 % in damping; and the adaptive
integrator's steps vary, which a sampled history would have to follow.
"""

from dataclasses import dataclass
import math

import numpy as np

from .hydro import DOF, HydroDatabase

TAIL_SPAN = 20.0  # B falls as omega^-2 from the last frequency up to this many times it
TAIL_NODES = 60  # frequencies of the tail (geometric)
LOW_NODES = 10  # frequencies below the first (even), where B rises as omega^2
MEMORY_FRACTION = 1e-4  # K past the memory stays below this fraction of its scale
FIT_FRACTION = 1e-3  # the modes fit K up to where it stays below this fraction
MAX_MEMORY = 120.0  # [s] the longest memory kept
MODE_TOLERANCE = 0.01  # the modes fit K within this fraction of each entry's scale
MAX_MODES = 48  # modes kept (a complex pair counts once): layout.MODE_CAPACITY
OGILVIE_SAMPLES = 40  # K's samples per period of the highest frequency in ogilvie


def damping_nodes(omega: np.ndarray, damping: np.ndarray):
    """
    Return B as a piecewise-linear function: its frequencies (m,) and values (m, ...).

    0 at omega = 0, the database's values, then its tail (module docstring).
    """
    omega = np.asarray(omega, dtype=float)
    damping = np.asarray(damping, dtype=float)
    tail = omega[-1] * np.geomspace(1.0, TAIL_SPAN, TAIL_NODES + 1)[1:]
    low = omega[0] * np.linspace(0.0, 1.0, LOW_NODES + 1)[:-1]
    shape = (-1,) + (1,) * (damping.ndim - 1)
    tail_values = damping[-1] * ((omega[-1] / tail) ** 2).reshape(shape)
    tail_values[-1] = 0.0  # down to 0 at its end: no step, whose K would ring as 1 / t
    low_values = damping[0] * ((low / omega[0]) ** 2).reshape(shape)
    nodes = np.concatenate((low, omega, tail))
    values = np.concatenate((low_values, damping, tail_values))
    return nodes, values


def cosine_weights(nodes: np.ndarray, t: np.ndarray) -> np.ndarray:
    """
    Return W (len(t), len(nodes)): int_0^inf f(omega) cos(omega t) domega = W @ f(nodes).

    f piecewise linear between the nodes (rising from the first) and 0 past the last.
    """
    t = np.asarray(t, dtype=float)[:, None]
    a, b = nodes[:-1][None, :], nodes[1:][None, :]
    span = b - a
    weights = np.zeros((t.shape[0], nodes.size))
    small = np.abs(t * span) < 1e-3
    safe = np.where(t == 0.0, 1.0, t)
    # int_a^b (b - w) / L cos(w t) and int_a^b (w - a) / L cos(w t), closed form; their
    # series in (L t) where the closed form would cancel
    difference = 2.0 * np.sin(0.5 * (a + b) * safe) * np.sin(0.5 * span * safe)  # cos at - cos bt
    left = -np.sin(a * safe) / safe + difference / (span * safe ** 2)
    right = np.sin(b * safe) / safe - difference / (span * safe ** 2)
    c, s, x = np.cos(a * t), np.sin(a * t), span * t  # the series about a, to (L t)^3
    left_series = span * (c * (0.5 - x * x / 24.0) - s * (x / 6.0 - x ** 3 / 120.0))
    right_series = span * (c * (0.5 - x * x / 8.0) - s * (x / 3.0 - x ** 3 / 30.0))
    left = np.where(small, left_series, left)
    right = np.where(small, right_series, right)
    weights[:, :-1] += left
    weights[:, 1:] += right
    return weights


def retardation(omega: np.ndarray, damping: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Return K(t) (len(t), 6, 6) of a radiation damping B(omega) (n, 6, 6) (see above)."""
    nodes, values = damping_nodes(omega, damping)
    weights = cosine_weights(nodes, t)
    return (2.0 / math.pi) * np.einsum('tn,nij->tij', weights, values)


def _scales(kernel: np.ndarray) -> np.ndarray:
    """Return each entry's scale sqrt(|K_ii(0)| |K_jj(0)|) (6, 6), never 0."""
    diagonal = np.abs(np.diagonal(kernel[0]))
    diagonal = np.where(diagonal > 0.0, diagonal, max(diagonal.max(), 1e-300))
    return np.sqrt(np.outer(diagonal, diagonal))


@dataclass(frozen=True)
class RetardationFunction:
    """
    K sampled from t = 0 to its memory.

    :ivar t: times [s] (m,), evenly spaced from 0; kernel: K(t) (m, 6, 6).
    :ivar memory: [s] the time past which K is taken as 0 (module docstring).
    :ivar scales: each entry's scale sqrt(K_ii(0) K_jj(0)) (6, 6).
    """

    t: np.ndarray
    kernel: np.ndarray
    memory: float
    scales: np.ndarray


def retardation_function(omega: np.ndarray, damping: np.ndarray,
                         samples_per_period: int = OGILVIE_SAMPLES,
                         fraction: float = MEMORY_FRACTION) -> RetardationFunction:
    """
    Return K of a radiation damping B(omega) (n, 6, 6), sampled up to its memory.

    The sampling resolves the database's highest frequency by samples_per_period; the
    memory ends where K stays below `fraction` of its scale.
    """
    omega = np.asarray(omega, dtype=float)
    step = 2.0 * math.pi / (samples_per_period * omega[-1])
    t = np.arange(0.0, MAX_MEMORY + 0.5 * step, step)
    kernel = retardation(omega, damping, t)
    scales = _scales(kernel)
    above = np.flatnonzero((np.abs(kernel) / scales).max(axis=(1, 2)) >= fraction)
    last = int(above[-1]) + 1 if above.size else 1
    last = min(last, t.size - 1)
    return RetardationFunction(t[:last + 1], kernel[:last + 1], float(t[last]), scales)


def ogilvie(function: RetardationFunction, omega: np.ndarray):
    """
    Return B(omega) and A(omega) - A_inf (n, 6, 6) from K by Ogilvie's relations.

    int_0^memory of K cos(omega t) and -(1 / omega) K sin(omega t), by the trapezoid rule.
    """
    omega = np.asarray(omega, dtype=float)
    t, kernel = function.t, function.kernel
    weights = np.full(t.size, t[1] - t[0])
    weights[[0, -1]] *= 0.5
    phase = np.outer(omega, t)
    damping = np.einsum('nt,tij->nij', np.cos(phase) * weights, kernel)
    added = -np.einsum('nt,tij->nij', np.sin(phase) * weights, kernel) / omega[:, None, None]
    return damping, added


@dataclass(frozen=True)
class RadiationModes:
    """
    K as damped modes: K(t) = sum_i weights_i Re(outputs_i inputs_i^T exp(poles_i t)).

    :ivar poles: lambda_i [1/s], complex, Re < 0 (r,).
    :ivar weights: 2 where a complex pole stands for its conjugate pair too, else 1 (r,).
    :ivar inputs, outputs: b_i, c_i, complex (r, 6).
    :ivar error: the largest misfit of K over its memory, as a fraction of each entry's scale.
    """

    poles: np.ndarray
    weights: np.ndarray
    inputs: np.ndarray
    outputs: np.ndarray
    error: float

    def kernel(self, t: np.ndarray) -> np.ndarray:
        """Return the modes' K(t) (len(t), 6, 6)."""
        growth = np.exp(np.outer(np.asarray(t, dtype=float), self.poles))  # (m, r)
        residues = self.weights[:, None, None] * np.einsum('ri,rj->rij', self.outputs,
                                                           self.inputs)
        return np.einsum('tr,rij->tij', growth, residues).real

    def transfer(self, omega: np.ndarray) -> np.ndarray:
        """
        Return int_0^inf K(t) exp(-i omega t) dt (n, 6, 6) of the modes.

        Its real part is their B(omega), its imaginary part over omega A(omega) - A_inf.
        """
        s = 1j * np.asarray(omega, dtype=float)[:, None]
        residues = 0.5 * self.weights[:, None, None] * np.einsum('ri,rj->rij', self.outputs,
                                                                 self.inputs)
        direct = 1.0 / (s - self.poles[None, :])
        mirror = 1.0 / (s - np.conj(self.poles)[None, :])
        return (np.einsum('nr,rij->nij', direct, residues)
                + np.einsum('nr,rij->nij', mirror, np.conj(residues)))


def _realise(samples: np.ndarray):
    """
    Return the SVD (u, s, vt) of the samples' block Hankel matrix and the one a sample on.

    Kung's eigensystem realisation of samples (m, 6, 6) = C A^k B, k = 0...: _modes_of
    truncates it.
    """
    m = samples.shape[0]
    rows = (m - 1) // 2
    hankel = np.empty((rows * DOF, rows * DOF))
    shifted = np.empty_like(hankel)
    for i in range(rows):
        for j in range(rows):
            hankel[i * DOF:(i + 1) * DOF, j * DOF:(j + 1) * DOF] = samples[i + j]
            shifted[i * DOF:(i + 1) * DOF, j * DOF:(j + 1) * DOF] = samples[i + j + 1]
    u, s, vt = np.linalg.svd(hankel)
    return u, s, vt, shifted


def _modes_of(u, s, vt, shifted, order: int, step: float):
    """Return (poles, weights, inputs, outputs) of the realisation truncated at `order`."""
    root = np.sqrt(s[:order])
    left = u[:, :order] / root
    right = vt[:order].T / root
    system = left.T @ shifted @ right
    inputs = (root[:, None] * vt[:order])[:, :DOF]
    outputs = (u[:DOF, :order] * root)
    values, vectors = np.linalg.eig(system)
    modal_inputs = np.linalg.solve(vectors, inputs.astype(complex))
    modal_outputs = outputs @ vectors
    keep = values.imag >= 0.0  # one of each conjugate pair
    values, modal_inputs, modal_outputs = (values[keep], modal_inputs[keep],
                                           modal_outputs[:, keep])
    weights = np.where(values.imag > 0.0, 2.0, 1.0)
    # a discrete pole mu is exp(lambda step); a negative real one is an oscillation at the
    # sampling's Nyquist frequency, its log's imaginary part pi / step
    poles = np.log(values.astype(complex)) / step
    # a pole that would grow (a misfit's, never K's) decays at the same rate instead
    poles = np.where(poles.real >= 0.0, -np.abs(poles.real) - 1e-9 + 1j * poles.imag, poles)
    return poles, weights, modal_inputs, modal_outputs.T


def radiation_modes(omega: np.ndarray, damping: np.ndarray,
                    tolerance: float = MODE_TOLERANCE) -> RadiationModes:
    """
    Return the modes of the least order that fit K within tolerance of each entry's scale.

    K is sampled up to where it stays below FIT_FRACTION of its scale (past it the modes'
    own decay stands for it) at a quarter of the Nyquist step of the database's highest
    frequency; the inputs and outputs are scaled by sqrt(K_ii(0)) so that the realisation
    weighs every degree of freedom alike.

    :raises ValueError: no order up to MAX_MODES modes fits K within tolerance.
    """
    omega = np.asarray(omega, dtype=float)
    if not np.any(damping):  # a hull that radiates no waves remembers nothing
        empty = np.zeros((0, DOF), dtype=complex)
        return RadiationModes(np.zeros(0, dtype=complex), np.zeros(0), empty, empty, 0.0)
    function = retardation_function(omega, damping, OGILVIE_SAMPLES // 4, FIT_FRACTION)
    step = 0.25 * math.pi / omega[-1]
    t = np.arange(0.0, function.memory + 0.5 * step, step)
    kernel = retardation(omega, damping, t)
    scale = np.sqrt(np.diagonal(function.scales))
    balanced = kernel / np.outer(scale, scale)
    check = retardation(omega, damping, function.t) / function.scales
    u, s, vt, shifted = _realise(balanced)
    best = None
    for order in range(2, min(2 * MAX_MODES, s.size) + 1, 2):
        poles, weights, inputs, outputs = _modes_of(u, s, vt, shifted, order, step)
        if poles.size > MAX_MODES:
            break
        fitted = RadiationModes(poles, weights, inputs, outputs, 0.0).kernel(function.t)
        error = float(np.abs(fitted - check).max())
        if best is None or error < best[0]:
            best = (error, poles, weights, inputs, outputs)
        if error <= tolerance:
            break
    error, poles, weights, inputs, outputs = best
    if error > tolerance:
        raise ValueError(f'hydrodynamic database: its radiation memory takes more than '
                         f'{MAX_MODES} modes to fit within {tolerance:.0%} '
                         f'({error:.1%} with the best)')
    return RadiationModes(poles, weights, inputs * scale[None, :], outputs * scale[None, :],
                          error)


def consistent_added_mass(database: HydroDatabase, modes: RadiationModes) -> np.ndarray:
    """
    Return the added mass at infinite frequency that the modes make A(omega) of (6, 6).

    By Ogilvie, A(omega) = A_inf - Im(Khat(omega)) / omega at every frequency: each
    frequency of the database gives its own A_inf, A(omega) less what the modes' memory adds
    there, and the median of them is taken (the solver's A_inf, solved apart, is a few per
    cent off theirs: the default ship's heave 3.93e8 kg against 4.07e8 to 4.21e8 from 0.2
    to 1.3 rad/s, which put its heave response near resonance 6 % off the frequency
    domain's). Symmetric.
    """
    omega = database.omega
    memory = modes.transfer(omega).imag / omega[:, None, None]
    added = np.median(database.added_mass - memory, axis=0)
    return 0.5 * (added + added.T)


def database_modes(database: HydroDatabase) -> RadiationModes:
    """Return the radiation memory's modes of a hydrodynamic database."""
    return radiation_modes(database.omega, database.radiation_damping)
