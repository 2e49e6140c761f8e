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
Waves: a long-crested sea state, its elevation, and its first- and second-order loads on a hull.

Sea state
---------
A sum of linear wave components travelling along one direction beta (where the waves go
TO; ``direction`` is where they come FROM, counter-clockwise from +x in frame_id, as the
wind's: beta = direction + pi), each at the depth h of the water (finite-depth dispersion
omega^2 = g k tanh(k h), deep water where h is inf)::

    eta(x, y, t) = sum_i a_i cos(k_i (x cos beta + y sin beta) - omega_i t + phi_i).

The time goes as exp(-i omega t), as in the hydrodynamic database (hydro.py): the complex
amplitude of component i at a point p is a_i exp(i theta_i), theta_i = k_i p.e_beta -
omega_i t + phi_i.

``'regular'``: one component, a = H / 2, omega = 2 pi / T, phi = 0 (a crest at the origin
of frame_id at t = 0).

``'jonswap'``: the JONSWAP spectrum of DNV-RP-C205 "Environmental conditions and
environmental loads" (section 3.5.5), significant wave height Hs, peak period Tp, peak
enhancement gamma::

    S(omega) = C (5/16) Hs^2 omega_p^4 omega^-5 exp(-5/4 (omega/omega_p)^-4)
               gamma^exp(-(omega - omega_p)^2 / (2 sigma^2 omega_p^2)),
    omega_p = 2 pi / Tp,  sigma = 0.07 (omega <= omega_p), 0.09 (omega > omega_p).

DNV's normalising factor is C = A_gamma = 1 - 0.287 ln gamma, an approximation; here C is
the exact one, so that the spectrum's m0 = int S d omega is Hs^2 / 16 (``jonswap_scale``:
for gamma = 3.3 it is 0.6558 against DNV's 0.6573, 0.24 % apart; 1.8 % at gamma = 7).

The components: equal bins of width d omega = 2 pi / 3600 s over the band 0.5 omega_p to
4 omega_p, one component per bin at a frequency drawn uniformly within it, amplitude
a_i = sqrt(2 S(omega_i) d omega), phase uniform in [0, 2 pi), both from
numpy.random.default_rng(seed): the same seed gives the same sea. Why so many (1575 for
Tp = 8 s, 3150 for Tp = 4 s): a one-hour record analysed by Fourier resolves frequencies
2 pi / 3600 s apart, so with one component per such bin the sea cannot be told from a
continuous spectrum over an hour, and with its frequencies drawn within the bins (not on
their centres) the sum has no period at all (equal spacing would repeat it after exactly
3600 s). The slow drift lives at the differences omega_i - omega_j, which then fill the
band from 2 pi / 3600 s up without gaps: a moored ship's surge or sway resonance at periods
of 60 to 300 s and bandwidths of a few 1e-3 rad/s is resolved by several of them. The band
holds 99.7 % of m0 for gamma = 3.3 (99.5 % for gamma = 1; the tail above 4 omega_p goes as
1.25 (omega / omega_p)^-4 of m0, the part below 0.5 omega_p is exp(-20) small): the sea's
Hs is 0.998 of the one asked for (0.9986 drawn with seed 1, Tp 8 s).

Loads on a hull
---------------
From a HydroDatabase (hydro.py): its excitation X(beta_b, omega) (per metre of amplitude,
phase at the body origin) and mean drift coefficients D(beta_b, omega) (per square metre,
surge, sway, yaw, about the centre of gravity), at the heading in body axes beta_b = beta -
yaw (the ship turns, the sea does not), linear in omega and on the ring of headings (the
last heading joined to the first plus 2 pi; a database of headings within [0, pi] only is
completed by the hull's port-starboard symmetry: X(-beta) = S X(beta), S = diag(1, -1, 1,
-1, 1, -1), and the drift's sway and yaw change sign likewise). A component whose
frequency lies outside the database's has no load (the sea's share there is checked by
the caller: ``outside_share``).

First order, at the ship's body origin p (horizontal, frame_id)::

    F1(t) = Re(sum_i X_i(beta_b) a_i exp(i theta_i(p, t)))      (6,), body axes, about the CG.

Second order, the slow drift by Newman's approximation (J. N. Newman, "Second-order,
slowly-varying forces on vessels in irregular waves", Proc. Int. Symp. on Dynamics of
Marine Vehicles and Structures in Waves, London, 1974, 182-186; O. M. Faltinsen, "Sea
loads on ships and offshore structures", Cambridge University Press, 1990, section 5.5):
the difference-frequency quadratic transfer function T_ij is taken as sqrt(D_i D_j) for
components whose mean drift coefficients have the same sign, and 0 between signs, so that
the double sum sum_ij a_i a_j T_ij cos(theta_i - theta_j) factors into envelopes::

    F2(t) = |Z+(t)|^2 - |Z-(t)|^2,  Z+- = sum_{i: +-D_i > 0} a_i sqrt(|D_i|) exp(i theta_i),

per degree of freedom (surge, sway, yaw). Its time mean is sum_i a_i^2 D_i, the mean drift
of the components; in a regular wave it is a^2 D at every instant. It keeps only the
difference frequencies (the form 2 [sum_i a_i sqrt(D_i) cos theta_i]^2 adds sum-frequency
terms of mean zero that a moored ship does not follow).
"""

from dataclasses import dataclass, field
import math
from typing import Optional, Tuple

import numba
import numpy as np

from .hydro import HydroDatabase
from ..frames import cross

SPECTRA = ('regular', 'jonswap')  # 'none' (no waves) is the caller's business
DEFAULT_PEAK_ENHANCEMENT = 3.3
RECORD = 3600.0  # [s] the record length whose Fourier resolution sets the bins
BAND = (0.5, 4.0)  # the components' band, in omega_p
# the port-starboard mirror of the six degrees of freedom and of the drift's three
MIRROR = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])
DRIFT_MIRROR = np.array([1.0, -1.0, -1.0])


def wavenumber(omega, depth: float, g: float) -> np.ndarray:
    """
    Return k [rad/m] with omega^2 = g k tanh(k depth) (depth inf: omega^2 / g).

    Newton's iterations from the deep-water and shallow-water guesses' larger, to 1e-14.
    """
    omega = np.asarray(omega, dtype=float)
    deep = omega * omega / g
    if math.isinf(depth):
        return deep
    k = np.maximum(deep, omega / math.sqrt(g * depth))
    for _ in range(100):
        t = np.tanh(k * depth)
        f = g * k * t - omega * omega
        step = f / (g * t + g * k * depth * (1.0 - t * t))
        k = k - step
        if np.all(np.abs(step) <= 1e-14 * k):
            break
    return k


def jonswap_shape(omega, peak_period: float, gamma: float) -> np.ndarray:
    """Return the JONSWAP spectrum for Hs = 1 m before its scale C (module docstring)."""
    omega = np.asarray(omega, dtype=float)
    wp = 2.0 * math.pi / peak_period
    out = np.zeros_like(omega)
    on = omega > 0.0
    w = omega[on]
    sigma = np.where(w <= wp, 0.07, 0.09)
    pm = 5.0 / 16.0 * wp ** 4 * w ** -5.0 * np.exp(-1.25 * (w / wp) ** -4.0)
    out[on] = pm * gamma ** np.exp(-(w - wp) ** 2 / (2.0 * sigma ** 2 * wp ** 2))
    return out


def jonswap_scale(gamma: float) -> float:
    """Return C making m0 = Hs^2 / 16 (independent of Tp: the shape scales with omega_p)."""
    x = np.linspace(0.05, 40.0, 400001)  # omega / omega_p; outside, < 1e-9 of m0
    shape = jonswap_shape(x, 2.0 * math.pi, gamma)
    return float(1.0 / 16.0 / np.trapezoid(shape, x))


def jonswap_spectrum(omega, significant_height: float, peak_period: float,
                     gamma: float = DEFAULT_PEAK_ENHANCEMENT) -> np.ndarray:
    """Return the JONSWAP spectrum S(omega) [m^2 s/rad] (module docstring)."""
    return (jonswap_scale(gamma) * significant_height ** 2
            * jonswap_shape(omega, peak_period, gamma))


@dataclass(frozen=True)
class Sea:
    """
    A sea state's components (module docstring): built once, evaluated at any point and time.

    :ivar omega, amplitude, phase, k: per component [rad/s], [m], [rad], [rad/m].
    :ivar travel: the direction the waves travel TOWARD in frame_id [rad].
    """

    omega: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    k: np.ndarray
    travel: float

    @classmethod
    def make(cls, spectrum: str, height: float, period: float, direction: float,
             depth: float, g: float, peak_enhancement: float = DEFAULT_PEAK_ENHANCEMENT,
             seed: int = 0) -> 'Sea':
        """
        Draw a sea state's components.

        :param spectrum: 'regular' (height H, period T) or 'jonswap' (Hs, Tp, gamma, seed).
        :param direction: where the waves come FROM, frame_id, counter-clockwise from +x.
        :param depth: the water's depth [m] (inf: deep); g: [m/s^2].
        :raises ValueError: an unknown spectrum, or a number out of range.
        """
        if spectrum not in SPECTRA:
            raise ValueError(f'wave spectrum {spectrum!r} is unknown; allowed: '
                             f'{", ".join(SPECTRA)}')
        for name, value in (('height', height), ('period', period), ('g', g)):
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'wave {name} {value!r} must be a finite number > 0')
        if not (depth > 0.0):
            raise ValueError(f'water depth {depth!r} must be > 0 (inf: deep)')
        travel = float(direction) + math.pi
        if spectrum == 'regular':
            omega = np.array([2.0 * math.pi / period])
            amplitude, phase = np.array([0.5 * height]), np.zeros(1)
        else:
            if not (math.isfinite(peak_enhancement) and peak_enhancement >= 1.0):
                raise ValueError(f'peak enhancement {peak_enhancement!r} must be >= 1')
            wp = 2.0 * math.pi / period
            step = 2.0 * math.pi / RECORD
            low = BAND[0] * wp
            count = int(math.ceil((BAND[1] - BAND[0]) * wp / step))
            rng = np.random.default_rng(int(seed))
            omega = low + (np.arange(count) + rng.uniform(0.0, 1.0, count)) * step
            phase = rng.uniform(0.0, 2.0 * math.pi, count)
            spectral = jonswap_spectrum(omega, height, period, peak_enhancement)
            amplitude = np.sqrt(2.0 * spectral * step)
        k = wavenumber(omega, depth, g)
        for array in (omega, amplitude, phase, k):
            array.setflags(write=False)
        return cls(omega, amplitude, phase, k, travel)

    @property
    def variance(self) -> float:
        """Return the elevation's variance sum a_i^2 / 2 [m^2] (over a long record)."""
        return float(0.5 * np.dot(self.amplitude, self.amplitude))

    def complex_amplitudes(self, t: float, x: float, y: float) -> np.ndarray:
        """Return each component's a_i exp(i theta_i) at the point (x, y) and time t."""
        along = x * math.cos(self.travel) + y * math.sin(self.travel)
        return self.amplitude * np.exp(1j * (self.k * along - self.omega * t + self.phase))

    def elevation(self, t, x: float = 0.0, y: float = 0.0):
        """Return the elevation [m] at (x, y) in frame_id at time(s) t [s]."""
        times = np.asarray(t, dtype=float)
        along = x * math.cos(self.travel) + y * math.sin(self.travel)
        base = self.k * along + self.phase
        if times.ndim == 0:
            return float(self.amplitude @ np.cos(base - self.omega * float(times)))
        flat = times.ravel()
        out = np.empty(flat.size)
        for start in range(0, flat.size, 1024):
            block = flat[start:start + 1024]
            out[start:start + 1024] = np.cos(base - np.outer(block, self.omega)) @ self.amplitude
        return out.reshape(times.shape)

    def outside_share(self, low: float, high: float) -> float:
        """Return the share of the sea's variance at frequencies outside [low, high]."""
        total = np.dot(self.amplitude, self.amplitude)
        out = (self.omega < low * (1.0 - 1e-12)) | (self.omega > high * (1.0 + 1e-12))
        part = np.dot(self.amplitude[out], self.amplitude[out])
        return float(part / total) if total > 0.0 else 0.0


@dataclass(frozen=True)
class Waves:
    """
    The waves on the water: their parameters, and their components (None: calm).

    :ivar spectrum: 'none', 'regular' or 'jonswap'; height [m] (H, or Hs); period [s] (T,
        or Tp); direction: where they come FROM in frame_id, counter-clockwise from +x
        [rad]; peak_enhancement: JONSWAP's gamma; seed: of the components' draw.
    :ivar sea: the components, or None (spectrum 'none' or height 0).
    """

    spectrum: str = 'none'
    height: float = 0.0
    period: float = 8.0
    direction: float = 0.0
    peak_enhancement: float = DEFAULT_PEAK_ENHANCEMENT
    seed: int = 0
    sea: Optional[Sea] = None

    @classmethod
    def make(cls, spectrum: str, height: float, period: float, direction: float,
             peak_enhancement: float, seed: int, depth: float, g: float) -> 'Waves':
        """Return the waves of these parameters at this depth [m] (inf: deep) and g."""
        sea = None
        if spectrum != 'none' and height > 0.0:
            sea = Sea.make(spectrum, height, period, direction, depth, g, peak_enhancement,
                           seed)
        return cls(spectrum, float(height), float(period), float(direction),
                   float(peak_enhancement), int(seed), sea)

    @property
    def configured(self) -> bool:
        """Tell whether waves are asked for (a spectrum), whatever their height now."""
        return self.spectrum != 'none'


def _ring(database: HydroDatabase) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """
    Return the database's headings on a closed ring: headings, X, D (module docstring).

    Headings within [0, pi] only are mirrored to the starboard side first; the ring ends
    with its first heading plus 2 pi.
    """
    headings, x, d = database.headings, database.excitation, database.drift
    if headings[0] >= -1e-9 and headings.size > 1:
        side = headings > 1e-9
        if headings[-1] >= math.pi - 1e-9:
            side &= headings < math.pi - 1e-9
        headings = np.concatenate([-headings[side][::-1], headings])
        x = np.concatenate([x[side][::-1] * MIRROR, x])
        d = np.concatenate([d[side][::-1] * DRIFT_MIRROR, d])
    headings = np.append(headings, headings[0] + 2.0 * math.pi)
    return headings, np.concatenate([x, x[:1]]), np.concatenate([d, d[:1]])


class WaveLoads:
    """
    A hull's wave loads in a sea state (module docstring): first order and slow drift.

    The database's X and D are interpolated to the sea's frequencies once per sea state
    (at every heading of the ring); each call interpolates between two headings.
    """

    def __init__(self, database: HydroDatabase, sea: Sea):
        """Take the hull's database and the sea it is in."""
        self.database = database
        self.sea = sea
        headings, x, d = _ring(database)
        self.headings = headings
        omega = database.omega
        inside = (sea.omega >= omega[0] * (1.0 - 1e-12)) & \
            (sea.omega <= omega[-1] * (1.0 + 1e-12))

        def at_sea(values: np.ndarray) -> np.ndarray:
            # (m, n, c) at the database's omega -> (m, N, c) at the sea's, 0 outside
            out = np.zeros((values.shape[0], sea.omega.size, values.shape[2]),
                           dtype=values.dtype)
            w = np.clip(sea.omega, omega[0], omega[-1])
            j = np.clip(np.searchsorted(omega, w) - 1, 0, omega.size - 2)
            f = ((w - omega[j]) / (omega[j + 1] - omega[j]))[None, :, None]
            out[:] = values[:, j] * (1.0 - f) + values[:, j + 1] * f
            out[:, ~inside] = 0.0
            return out

        excitation = at_sea(x)  # (m, N, 6) complex
        # Re(X w) = Re X . a cos(theta) - Im X . a sin(theta): one real product of
        # [a cos; a sin] (2N,) with [Re X; -Im X] (2N, 6), a tenth of the complex one's time
        self.excitation = np.ascontiguousarray(
            np.concatenate([excitation.real, -excitation.imag], axis=1))
        self.drift = at_sea(d)  # (m, N, 3)

    def heading_weights(self, heading: float) -> Tuple[int, float]:
        """Return (j, f): a body-axes heading is (1 - f) of ring entry j and f of j + 1."""
        h = self.headings
        b = h[0] + (heading - h[0]) % (2.0 * math.pi)
        j = min(int(np.searchsorted(h, b, side='right')) - 1, h.size - 2)
        return j, float((b - h[j]) / (h[j + 1] - h[j]))

    def at(self, t: float, x: float, y: float, yaw: float) -> Tuple[np.ndarray, np.ndarray]:
        """
        Return the first-order load (6,) and the slow drift (3,) at time t, about the CG.

        :param x, y: the ship's body origin in frame_id [m]; yaw: its heading [rad].
        :returns: F1 (surge, sway, heave forces [N], roll, pitch, yaw moments [N m]) and
            F2 (surge, sway [N], yaw [N m]), body axes about the centre of gravity.
        """
        j, f = self.heading_weights(self.sea.travel - yaw)
        sea = self.sea
        along = x * math.cos(sea.travel) + y * math.sin(sea.travel)
        first, drift = np.zeros(6), np.zeros(3)
        _loads(sea.amplitude, sea.k, sea.omega, sea.phase, along, t, self.excitation[j],
               self.excitation[j + 1], self.drift[j], self.drift[j + 1], f, first, drift)
        return first, drift

    def mean_drift(self, yaw: float) -> np.ndarray:
        """
        Return the slow drift's mean, sum a_i^2 D_i (3,): surge, sway [N], yaw [N m].

        Body axes about the centre of gravity, for a ship heading yaw [rad]: what a
        ship held at rest feels of the waves on average (the berth check's).
        """
        j, f = self.heading_weights(self.sea.travel - yaw)
        drift = self.drift[j] * (1.0 - f) + self.drift[j + 1] * f  # (N, 3)
        return (self.sea.amplitude ** 2) @ drift


@numba.njit(cache=True)
def _loads(amplitude, k, omega, phase, along, t, excitation, excitation_next, drift,
           drift_next, f, first, slow):
    """
    Put the first-order load (6,) and Newman's slow drift (3,) at t into first and slow.

    One pass over the components (WaveLoads.at; the module docstring's formulas): each
    component's a cos(theta), a sin(theta) at the ship's origin (`along` its travel),
    against X = [Re X; -Im X] (2N, 6) and D (N, 3) at the two ring headings either side,
    weighed 1 - f and f. Compiled: numpy's products over the 1,575 components of a 8 s sea
    took 0.2 ms an evaluation, three an output.
    """
    count = amplitude.size
    envelopes = np.zeros((4, 3))  # Re, Im of Z+ and of Z-
    for i in range(count):
        theta = k[i] * along - omega[i] * t + phase[i]
        c = amplitude[i] * math.cos(theta)
        s = amplitude[i] * math.sin(theta)
        for m in range(6):
            first[m] += ((1.0 - f) * (c * excitation[i, m] + s * excitation[count + i, m])
                         + f * (c * excitation_next[i, m] + s * excitation_next[count + i, m]))
        for m in range(3):
            d = (1.0 - f) * drift[i, m] + f * drift_next[i, m]
            root = math.sqrt(abs(d))
            if d > 0.0:
                envelopes[0, m] += c * root
                envelopes[1, m] += s * root
            elif d < 0.0:
                envelopes[2, m] += c * root
                envelopes[3, m] += s * root
    for m in range(3):
        slow[m] = (envelopes[0, m] ** 2 + envelopes[1, m] ** 2
                   - envelopes[2, m] ** 2 - envelopes[3, m] ** 2)


def about_origin(first: np.ndarray, drift: np.ndarray,
                 reference_point: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return loads about the CG (first (6,), drift (3,)) as loads about the body origin.

    :param reference_point: the CG from the body origin, body axes [m] (3,).
    """
    r = np.asarray(reference_point, dtype=float)
    moved = np.array(first, dtype=float)
    moved[3:] += cross(r, moved[:3])
    force = np.array([drift[0], drift[1], 0.0])
    turned = np.array([drift[0], drift[1], drift[2] + cross(r, force)[2]])
    return moved, turned


@dataclass
class ShipWaves:
    """
    The waves' loads on one ship: its database, and the loads of the sea state now.

    :ivar database: the hull's HydroDatabase, or None (no waves allowed then).
    """

    database: Optional[HydroDatabase] = None
    _loads: Optional[WaveLoads] = field(default=None, init=False, repr=False)

    def at(self, t: float, waves: Waves, position, yaw: float) -> Tuple[float, np.ndarray]:
        """
        Return the elevation at the ship's origin [m] and its wave loads (2, 6) at time t.

        Rows: first order; slow drift (F_x, F_y, 0, 0, 0, M_z); body axes, about the
        ship's origin. Zeros (and 0 m) in a calm sea.

        :param waves: the environment's; position: the ship's origin in frame_id (3,);
            yaw: its heading [rad].
        """
        loads = np.zeros((2, 6))
        hull = self._in(waves)
        if hull is None:
            return 0.0, loads
        x, y = float(position[0]), float(position[1])
        first, drift = hull.at(t, x, y, yaw)
        first, drift = about_origin(first, drift, self.database.reference_point)
        loads[0] = first
        loads[1, [0, 1, 5]] = drift
        return waves.sea.elevation(t, x, y), loads

    def mean_drift(self, waves: Waves, yaw: float) -> np.ndarray:
        """
        Return the waves' mean drift on the ship heading yaw [rad] (3,): F_x, F_y, M_z.

        Body axes about the ship's origin (WaveLoads.mean_drift); zeros in a calm sea.
        """
        hull = self._in(waves)
        if hull is None:
            return np.zeros(3)
        _, drift = about_origin(np.zeros(6), hull.mean_drift(yaw), self.database.reference_point)
        return drift

    def _in(self, waves: Waves) -> Optional[WaveLoads]:
        """Return the hull's loads in this sea state (made once per sea), or None: calm."""
        sea = waves.sea
        if sea is None or self.database is None:
            return None
        if self._loads is None or self._loads.sea is not sea:
            self._loads = WaveLoads(self.database, sea)
        return self._loads
