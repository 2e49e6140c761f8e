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
Timestamped positions of one rope end, interpolated between samples.

'linear' interpolation moves the end on the secant of each interval (the velocity jumps at
every sample); 'cubic' uses a Catmull-Rom Hermite spline, whose velocity is continuous.
Holding a pose until the next one (zero-order hold) would jerk a stiff line at every
message, and so does a velocity step, more gently: a velocity jump dv launches an axial wave
of dv sqrt(EA m) newtons. Past the newest sample the end coasts to a stop: its velocity
falls linearly from the last one to zero over `coast_time` seconds, then it holds. A ship
does not stop at once when its pose messages do, and a gentle stop and a gentle return (an
EndBlend) when the messages resume jerk the line least. Offline, in a 1 m surge (10 s
period) whose 100 Hz samples stop for 0.4 s and then come late, the worst tension error
was 105 N with 1 s for both and 2.1 kN with 0.1 s of coasting and a 0.25 s return. Through
the node, on the replay test's motion with the same gap, the old way (0.1 s at full speed,
a stop, then a jump back onto the track) cost 11 kN.

An EndBlend takes an end that is off its trajectory (the samples that arrived changed the
trajectory under the rope) back onto it, with position and velocity continuous.
"""

import math
from typing import NamedTuple, Optional

import numba
import numpy as np


class TrajectoryError(ValueError):
    """A sample cannot be accepted (non-finite, or not newer than the last one)."""


class EndTrajectory:
    """
    A bounded buffer of (t, position) samples of one end, or of several points moving as one.

    With `width` K each sample holds K points, (K, 3): a ship's fairleads, all sampled in one
    call, each point the very numbers an EndTrajectory of that point alone gives.
    """

    def __init__(self, coast_time: float = 1.0, keep: float = 5.0,
                 method: str = 'linear', width: Optional[int] = None):
        """
        Create an empty trajectory.

        :param coast_time: how long [s] the end takes to coast to a stop past the newest
            sample.
        :param keep: how much history [s] to keep behind the newest sample.
        :param method: 'linear' or 'cubic'.
        :param width: None: a sample is one point (3,); K: it is K points (K, 3).
        """
        self.coast_time = coast_time
        self.method = method
        self.keep = keep
        self.width = width
        self._shape = (3,) if width is None else (width, 3)  # a sample's
        # samples live in [_first, _count) of arrays that grow by doubling: a push at 1 kHz
        # must not copy the whole history
        self._times = np.empty(64)
        self._points = np.empty((64,) + self._shape)
        self._first = 0
        self._count = 0
        self.version = 0  # counts the changes (pushes and clears): a copy can tell it holds

    @property
    def _t(self) -> np.ndarray:
        return self._times[self._first:self._count]

    @property
    def _p(self) -> np.ndarray:
        return self._points[self._first:self._count]

    def __len__(self) -> int:
        """Count the buffered samples."""
        return self._count - self._first

    @property
    def last_time(self) -> float:
        """Stamp of the newest sample [s] (-inf when empty)."""
        return float(self._times[self._count - 1]) if len(self) else -math.inf

    @property
    def settled_until(self) -> float:
        """
        Time up to which a new sample cannot change the track (-inf when empty).

        The second-newest sample's: a spline's tangent at the newest sample waits for the
        next one. With a single sample, that sample's time.
        """
        if not len(self):
            return -math.inf
        return float(self._times[max(self._count - 2, self._first)])

    @property
    def last_position(self):
        """Newest sample position as a list (K of them with width K), or None."""
        return self._points[self._count - 1].tolist() if len(self) else None

    def clear(self) -> None:
        """Forget every sample."""
        self._first = self._count = 0
        self.version += 1

    def push(self, t: float, position) -> None:
        """
        Append a sample.

        :raises TrajectoryError: non-finite time or position, or t not after the newest sample.
        """
        if self.width is None:
            x, y, z = position  # plain floats: this runs at 1 kHz
            point = x, y, z = float(x), float(y), float(z)
            finite = math.isfinite(x) and math.isfinite(y) and math.isfinite(z)
        else:
            point = np.asarray(position, dtype=float)
            if point.shape != self._shape:
                raise TrajectoryError(f'a sample of {self.width} points has shape '
                                      f'{self._shape}, not {point.shape}')
            finite = _all_finite(point.reshape(-1))  # (numpy's isfinite().all(): 3 us)
        if not (finite and math.isfinite(t)):
            raise TrajectoryError(f'non-finite sample at t={t}: {np.asarray(point).tolist()}')
        if self._count > self._first and t <= self._times[self._count - 1]:
            raise TrajectoryError(
                f'sample at t={t:.6f} s is not after the newest one ({self.last_time:.6f} s)')
        # forget what is older than `keep`, always keeping one sample to interpolate from
        while self._count - self._first > 1 and self._times[self._first + 1] < t - self.keep:
            self._first += 1
        if self._count == len(self._times):
            self._make_room()
        self._times[self._count] = t
        self._points[self._count] = point
        self._count += 1
        self.version += 1

    def _make_room(self) -> None:
        """Move the live samples to the front, doubling the arrays if they are half full."""
        live = self._count - self._first
        size = len(self._times) * (2 if 2 * live >= len(self._times) else 1)
        times, points = np.empty(size), np.empty((size,) + self._shape)
        times[:live] = self._times[self._first:self._count]
        points[:live] = self._points[self._first:self._count]
        self._times, self._points = times, points
        self._first, self._count = 0, live

    def sample(self, times: np.ndarray) -> tuple:
        """
        Positions and velocities at `times`, shapes (n, 3) each ((n, K, 3) of K points).

        Before the first sample the end rests there; between samples it follows the chosen
        interpolation; after the last one it coasts to a stop, then holds.
        """
        times = np.ascontiguousarray(times, dtype=float)
        return _sample(self._t, self._p, times, self.coast_time, self.method == 'cubic')


@numba.njit(cache=True)
def _all_finite(values):
    for value in values:
        if not np.isfinite(value):
            return False
    return True


@numba.njit(cache=True)
def _tangent(t, p, k):
    """Catmull-Rom tangent at sample k: central difference, one-sided at the two ends."""
    lo, hi = max(k - 1, 0), min(k + 1, len(t) - 1)
    return (p[hi] - p[lo]) / (t[hi] - t[lo])


@numba.njit(cache=True)
def _sample(t, p, times, coast_time, cubic):
    positions = np.empty((len(times),) + p.shape[1:])
    velocities = np.zeros((len(times),) + p.shape[1:])
    last = len(t) - 1
    for n in range(len(times)):
        tau = min(max(times[n], t[0]), t[last] + coast_time)
        moving = t[0] <= times[n] < t[last] + coast_time and last > 0
        if last == 0:
            positions[n] = p[0]
            continue
        if tau >= t[last]:  # past the newest sample: slow down evenly from its velocity
            if cubic:
                m = _tangent(t, p, last)
            else:
                m = (p[last] - p[last - 1]) / (t[last] - t[last - 1])
            if coast_time <= 0.0:
                positions[n] = p[last]
                continue
            coast = tau - t[last]
            positions[n] = p[last] + m * (coast - coast * coast / (2.0 * coast_time))
            if moving:
                velocities[n] = m * (1.0 - coast / coast_time)
            continue
        i = min(max(np.searchsorted(t, tau, side='right') - 1, 0), last - 1)
        h = t[i + 1] - t[i]
        s = (tau - t[i]) / h
        if not cubic:
            secant = (p[i + 1] - p[i]) / h
            positions[n] = p[i] + secant * (tau - t[i])
            if moving:
                velocities[n] = secant
            continue
        m0, m1 = _tangent(t, p, i) * h, _tangent(t, p, i + 1) * h
        s2, s3 = s * s, s * s * s
        positions[n] = ((2 * s3 - 3 * s2 + 1) * p[i] + (s3 - 2 * s2 + s) * m0
                        + (3 * s2 - 2 * s3) * p[i + 1] + (s3 - s2) * m1)
        if moving:
            velocities[n] = ((6 * s2 - 6 * s) * p[i] + (3 * s2 - 4 * s + 1) * m0
                             + (6 * s - 6 * s2) * p[i + 1] + (3 * s2 - 2 * s) * m1) / h
    return positions, velocities


class EndBlend(NamedTuple):
    """
    An offset from an end's trajectory that fades from (offset, rate) at `start` to zero.

    The fade is a cubic Hermite curve over `duration` seconds, so the end keeps the position
    and velocity the rope has at `start` and meets its trajectory with the trajectory's own
    velocity: no jump and no velocity step, whose axial wave a stiff line would feel.
    """

    start: float
    duration: float
    offset: np.ndarray  # rope end minus trajectory at start [m]
    rate: np.ndarray  # rope end velocity minus trajectory velocity at start [m/s]

    def at(self, times) -> tuple:
        """Offsets and their rates at `times`, shapes (n, 3) each; zero from start + duration."""
        s = np.clip((np.asarray(times, dtype=float) - self.start) / self.duration, 0.0, 1.0)
        s = s[:, np.newaxis]
        slope = self.duration * self.rate
        offsets = ((2 * s - 3) * s * s + 1) * self.offset + (s - 1) * (s - 1) * s * slope
        rates = (6 * (s - 1) * s * self.offset + (3 * s - 1) * (s - 1) * slope) / self.duration
        return offsets, rates
