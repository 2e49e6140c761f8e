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
Gusty wind: a repeatable wind speed time series from a named gust spectrum.

Spectra
-------
One-sided spectra S(f) of the along-wind speed [m^2/s^2/Hz], f in Hz, at height z [m] above
the sea, for ``mean_speed`` U, the 1-hour mean wind speed AT THAT HEIGHT [m/s] (the mean of
the generated series). 'none' (steady wind) is the caller's business.

``'npd'``: the NPD (Frøya) spectrum of Andersen and Løvseth, as given in DNV-RP-C205
"Environmental conditions and environmental loads" (October 2010), section 2.3.4 (wind
spectra, the Frøya spectrum), and in ISO 19901-1 / API RP 2MET::

    S(f) = 320 (U0/10)^2 (z/10)^0.45 / (1 + f~^n)^(5/(3n)),  n = 0.468,
    f~ = 172 f (z/10)^(2/3) (U0/10)^(-3/4),

with U0 the 1-hour mean speed at 10 m. U0 follows from U at height z through the Frøya wind
profile of the same document (section 2.3.2, the Frøya wind profile for T = 1 hour)::

    U = U0 (1 + C ln(z/10)),  C = 5.73e-2 (1 + 0.148 U0)^(1/2),

solved here for U0 (at z = 10 m, U0 = U). The spectrum's integral over 0 < f < inf is, in
closed form, 320 (U0/10)^2 (z/10)^0.45 / (172 (z/10)^(2/3) (U0/10)^(-3/4)) times
Gamma(1 + 1/n) Gamma(2/(3n)) / Gamma(5/(3n)) (``npd_variance``); for U0 = 20 m/s at 10 m it is
7.099 m^2/s^2 (sigma 2.664 m/s). That is not the standard deviation 0.06 (1 + 0.043 U0) U0
= 2.232 m/s of the Frøya turbulence intensity (which enters the profile's gust factor), so
no published sigma is reproduced for this spectrum.

``'api'``: the API spectrum of API RP 2A-WSD (20th edition, 1993, section 2.3.2)::

    S(f) = sigma^2 / f_p / (1 + 1.5 f/f_p)^(5/3),  f_p = a U / z,  a = 0.025,
    sigma = I(z) U,  I(z) = 0.15 (z/z_s)^(-0.125) for z <= z_s,
                      I(z) = 0.15 (z/z_s)^(-0.275) for z > z_s,  z_s = 20 m.

Its integral over 0 < f < inf is exactly sigma^2 (0.01 <= a <= 0.1 is the range given for
f_p z / U, 0.025 the recommended value).

Provenance and its limits: the text of neither document could be read for this work, so
their section and equation numbers are not checked. The Frøya forms are the ones TurbSim
(OpenFAST, VelocitySpectra.f90, routine Spec_API, which cites DNV-RP-C205 2010-10 page 20
and ISO 19901-1:2005 A.7.4) implements, and agree with the 'npd' spectrum of other open
implementations; TurbSim calls it 'API' because the later editions of API RP 2A-WSD (21st,
2000) and API RP 2MET use the NPD model. The 'api' form here is the older API spectrum with
a peak frequency, written from the secondary literature: check it against the edition of
API RP 2A-WSD in force before relying on it.

Time series
-----------
u(t) = U + sum_k a_k cos(2 pi f_k t + phi_k), f_k = k / T for k = 1..N (T = ``duration``,
N = f_max T), a_k = sqrt(2 S(f_k) df) with df = 1/T, phi_k uniform in [0, 2 pi) from
numpy.random.default_rng(seed). The series is periodic with period T exactly: it does not
repeat within T, and over one period its mean is U and its variance sum(a_k^2)/2 =
sum S(f_k) df exactly (orthogonality of the harmonics), the midpoint-rule integral of S over
the represented band (df/2, f_max + df/2). Below f = df/2 the spectrum's variance is left
out (it belongs to the mean over T); above f_max too (gusts shorter than 1/f_max hardly move a
moored ship). Amplitudes are deterministic, so the same seed gives the same series.

The speed is clamped at 0 where U + gust < 0 (a speed cannot be negative; the wind would
then blow the other way, which a 1-D gust model does not describe). With these spectra that
needs a gust of about -6 sigma (sigma / U is at most 0.16 for API at z >= 10 m, less for
NPD), so in practice it does not happen; where it did, it would raise the mean slightly.

One evaluation at a time is one cosine per precomputed component and a dot product: 20 to
40 us for the default 1800 components (T = 3600 s, f_max = 0.5 Hz) on the 2-core
development machine (numpy 2, Python 3.11; test/test_wind_spectrum.py prints it), so a node
calling it at 1 kHz spends 2 to 4 % of a core on it. The band (0, 0.5 Hz] holds 84 % of
the spectrum's variance at U = 20 m/s, z = 10 m, for both spectra; a higher f_max costs
proportionally more per call.
"""

from dataclasses import dataclass
import math
from typing import Optional, Sequence, Union

import numpy as np

SPECTRA = ('api', 'npd')
ArrayLike = Union[float, Sequence[float], np.ndarray]

NPD_EXPONENT = 0.468  # n in the Frøya spectrum
API_PEAK_FACTOR = 0.025  # a in f_p = a U / z, API RP 2A's recommended value
API_SURFACE_LAYER = 20.0  # z_s [m]
API_INTENSITY = 0.15  # turbulence intensity at z_s
DEFAULT_DURATION = 3600.0  # s: one hour, the averaging period of both spectra's mean speed
DEFAULT_MAX_FREQUENCY = 0.5  # Hz
CHUNK = 1024  # time samples per block when evaluating an array of times


def _check_name(name: str) -> str:
    """Return name if it is a known spectrum, else raise ValueError listing them."""
    if name not in SPECTRA:
        raise ValueError(f'spectrum name {name!r} is unknown; allowed: {", ".join(SPECTRA)} '
                         "('none' means a steady wind and is handled by the caller)")
    return name


def _check_speed(mean_speed: float) -> float:
    """Return mean_speed as a float, or raise ValueError unless finite and >= 0."""
    speed = float(mean_speed)
    if not (math.isfinite(speed) and speed >= 0.0):
        raise ValueError(f'mean_speed {mean_speed!r} must be a finite number >= 0 [m/s]')
    return speed


def _check_height(height: float) -> float:
    """Return height as a float, or raise ValueError unless finite and > 0."""
    value = float(height)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f'height {height!r} must be a finite number > 0 [m]')
    return value


def npd_reference_speed(mean_speed: float, height: float) -> float:
    """
    Return U0 [m/s], the 1-hour mean at 10 m whose Frøya profile gives mean_speed at height.

    Solves U = U0 (1 + 5.73e-2 (1 + 0.148 U0)^(1/2) ln(z/10)) by bisection (the right side
    increases with U0 for the heights of a ship's windage, z >= 1 m).
    """
    speed, z = _check_speed(mean_speed), _check_height(height)
    if speed == 0.0 or z == 10.0:
        return speed
    log_ratio = math.log(z / 10.0)

    def profile(u0: float) -> float:
        return u0 * (1.0 + 5.73e-2 * math.sqrt(1.0 + 0.148 * u0) * log_ratio)

    low, high = 0.0, 2.0 * speed + 10.0
    if profile(high) < speed:
        raise ValueError(f'height {height!r} m is outside the Frøya profile (no U0 gives '
                         f'{speed!r} m/s there)')
    for _ in range(200):
        middle = 0.5 * (low + high)
        if profile(middle) < speed:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


def api_sigma(mean_speed: float, height: float) -> float:
    """Return the API spectrum's standard deviation I(z) U [m/s] (its total variance)."""
    speed, z = _check_speed(mean_speed), _check_height(height)
    exponent = -0.125 if z <= API_SURFACE_LAYER else -0.275
    return API_INTENSITY * (z / API_SURFACE_LAYER) ** exponent * speed


def npd_variance(mean_speed: float, height: float) -> float:
    """Return the integral of the NPD spectrum over 0 < f < inf [m^2/s^2], closed form."""
    u0 = npd_reference_speed(mean_speed, height)
    if u0 == 0.0:
        return 0.0
    z = _check_height(height)
    n = NPD_EXPONENT
    scale = 172.0 * (z / 10.0) ** (2.0 / 3.0) * (u0 / 10.0) ** -0.75
    shape = math.gamma(1.0 + 1.0 / n) * math.gamma(2.0 / (3.0 * n)) / math.gamma(5.0 / (3.0 * n))
    return 320.0 * (u0 / 10.0) ** 2 * (z / 10.0) ** 0.45 / scale * shape


def gust_spectrum(name: str, mean_speed: float, frequencies_hz: ArrayLike,
                  height: float = 10.0) -> np.ndarray:
    """
    Return the one-sided gust spectrum S(f) [m^2/s^2/Hz] at frequencies f [Hz].

    :param name: 'api' or 'npd' (module docstring for the formulas and their sources).
    :param mean_speed: the 1-hour mean wind speed U at ``height``, >= 0 [m/s]; 0 gives 0.
    :param frequencies_hz: frequencies >= 0 [Hz], any shape.
    :param height: height above the sea z, > 0 [m].
    :raises ValueError: unknown name, negative or non-finite speed, height or frequency.
    """
    _check_name(name)
    speed, z = _check_speed(mean_speed), _check_height(height)
    frequencies = np.asarray(frequencies_hz, dtype=float)
    if not np.all(np.isfinite(frequencies)) or np.any(frequencies < 0.0):
        raise ValueError('frequencies_hz must be finite and >= 0 [Hz]')
    if speed == 0.0:
        return np.zeros_like(frequencies)
    if name == 'api':
        sigma = api_sigma(speed, z)
        peak = API_PEAK_FACTOR * speed / z
        return sigma ** 2 / peak / (1.0 + 1.5 * frequencies / peak) ** (5.0 / 3.0)
    u0 = npd_reference_speed(speed, z)
    n = NPD_EXPONENT
    reduced = 172.0 * frequencies * (z / 10.0) ** (2.0 / 3.0) * (u0 / 10.0) ** -0.75
    return (320.0 * (u0 / 10.0) ** 2 * (z / 10.0) ** 0.45
            / (1.0 + reduced ** n) ** (5.0 / (3.0 * n)))


class GustyWind:
    """
    Wind speed at one point: the mean plus a sum of harmonics drawn from a gust spectrum.

    The components are made once here; ``speed`` only evaluates them (module docstring for
    the method, its exact mean and variance, and the cost of a call).
    """

    def __init__(self, name: str, mean_speed: float, seed: int, height: float = 10.0,
                 duration: float = DEFAULT_DURATION,
                 max_frequency: float = DEFAULT_MAX_FREQUENCY) -> None:
        """
        Draw the components.

        :param name: 'api' or 'npd'.
        :param mean_speed: 1-hour mean wind speed U at ``height``, >= 0 [m/s].
        :param seed: seed of numpy.random.default_rng for the phases (an int >= 0).
        :param height: height above the sea z, > 0 [m].
        :param duration: T, the period of the series [s] (> 0): it does not repeat within T,
            so make it at least as long as the simulation.
        :param max_frequency: f_max, the highest component frequency [Hz]; at least 1/T.
        :raises ValueError: an argument out of range.
        """
        self.name = _check_name(name)
        self.mean_speed = _check_speed(mean_speed)
        self.height = _check_height(height)
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise ValueError(f'seed {seed!r} must be an int >= 0')
        self.seed = int(seed)
        self.duration = float(duration)
        if not (math.isfinite(self.duration) and self.duration > 0.0):
            raise ValueError(f'duration {duration!r} must be a finite number > 0 [s]')
        self.max_frequency = float(max_frequency)
        finite = math.isfinite(self.max_frequency)
        count = int(math.floor(self.max_frequency * self.duration + 1e-9)) if finite else 0
        if count < 1:
            raise ValueError(f'max_frequency {max_frequency!r} must be finite and at least '
                             f'1/duration = {1.0 / self.duration!r} [Hz]')
        step = 1.0 / self.duration
        self.frequencies = step * np.arange(1, count + 1)
        spectrum = gust_spectrum(self.name, self.mean_speed, self.frequencies, self.height)
        self.amplitudes = np.sqrt(2.0 * spectrum * step)
        self.phases = np.random.default_rng(self.seed).uniform(0.0, 2.0 * math.pi, count)
        self._omega = 2.0 * math.pi * self.frequencies
        for array in (self.frequencies, self.amplitudes, self.phases, self._omega):
            array.setflags(write=False)

    @property
    def variance(self) -> float:
        """Variance of the gust over one period, sum(a_k^2)/2 [m^2/s^2] (before clamping)."""
        return float(0.5 * np.dot(self.amplitudes, self.amplitudes))

    def gust(self, t: ArrayLike) -> Union[float, np.ndarray]:
        """Return the gust sum_k a_k cos(2 pi f_k t + phi_k) [m/s] at time(s) t [s]."""
        if isinstance(t, (float, int)) and not isinstance(t, bool):
            # The node's path: one time, no array bookkeeping (see the module docstring).
            if not math.isfinite(t):
                raise ValueError(f't {t!r} must be finite [s]')
            return float(self.amplitudes @ np.cos(self._omega * t + self.phases))
        times = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(times)):
            raise ValueError('t must be finite [s]')
        if times.ndim == 0:
            return self.gust(float(times))
        flat = times.ravel()
        out = np.empty(flat.size)
        for start in range(0, flat.size, CHUNK):
            block = flat[start:start + CHUNK]
            out[start:start + CHUNK] = np.cos(np.outer(block, self._omega)
                                              + self.phases) @ self.amplitudes
        return out.reshape(times.shape)

    def speed(self, t: ArrayLike) -> Union[float, np.ndarray]:
        """Return the wind speed max(U + gust(t), 0) [m/s] at time(s) t [s]."""
        gust = self.gust(t)
        if isinstance(gust, float):
            return max(self.mean_speed + gust, 0.0)
        return np.maximum(self.mean_speed + gust, 0.0)


@dataclass(frozen=True)
class Wind:
    """
    The wind at 10 m above the water, steady or gusty.

    :ivar speed: its mean speed [m/s].
    :ivar direction: where it comes FROM in frame_id, counter-clockwise from +x [rad].
    :ivar gusts: a GustyWind about the mean, or None (steady).
    """

    speed: float = 0.0
    direction: float = 0.0
    gusts: Optional[GustyWind] = None

    def velocity(self, t: float) -> np.ndarray:
        """Give the air's velocity at time t, where it goes TO, in frame_id axes (3,)."""
        speed = self.gusts.speed(t) if self.gusts is not None else self.speed
        return -speed * np.array([math.cos(self.direction), math.sin(self.direction), 0.0])
