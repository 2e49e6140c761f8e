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

"""Timestamped positions of one rope end, interpolated between samples.

Positions are interpolated linearly between samples, with the secant of the interval as the
velocity: holding a pose until the next one (zero-order hold) jerks a stiff line at every
message. Past the newest sample the end moves on with the last secant velocity for at most
`extrapolation` seconds, then holds: a live node would otherwise see a stair-case.
"""

import math

import numpy as np


class TrajectoryError(ValueError):
    """A sample cannot be accepted (non-finite, or not newer than the last one)."""


class EndTrajectory:
    """A bounded buffer of (t, position) samples of one end."""

    def __init__(self, extrapolation: float = 0.1, keep: float = 5.0):
        """Create an empty trajectory.

        Args:
            extrapolation: how long [s] to move on with the last velocity past the newest
                sample before holding.
            keep: how much history [s] to keep behind the newest sample.
        """
        self.extrapolation = extrapolation
        self.keep = keep
        self._t = np.empty(0)
        self._p = np.empty((0, 3))

    def __len__(self) -> int:
        """Number of buffered samples."""
        return len(self._t)

    @property
    def last_time(self) -> float:
        """Stamp of the newest sample [s] (-inf when empty)."""
        return float(self._t[-1]) if len(self._t) else -math.inf

    @property
    def last_position(self):
        """Newest sample position, or None."""
        return self._p[-1].copy() if len(self._t) else None

    def clear(self) -> None:
        """Forget every sample."""
        self._t = np.empty(0)
        self._p = np.empty((0, 3))

    def push(self, t: float, position) -> None:
        """Append a sample.

        Raises:
            TrajectoryError: non-finite time or position, or t not after the newest sample.
        """
        p = np.asarray(position, dtype=float).reshape(3)
        if not (math.isfinite(t) and np.isfinite(p).all()):
            raise TrajectoryError(f'non-finite sample at t={t}: {p.tolist()}')
        if len(self._t) and t <= self._t[-1]:
            raise TrajectoryError(
                f'sample at t={t:.6f} s is not after the newest one ({self._t[-1]:.6f} s)')
        old = self._t < t - self.keep
        old[-1:] = False  # always keep one sample to interpolate from
        self._t = np.append(self._t[~old], t)
        self._p = np.vstack([self._p[~old], p])

    def sample(self, times: np.ndarray) -> tuple:
        """Positions and velocities at `times`, shapes (n, 3) each.

        Before the first sample the end rests there; between samples it moves on the secant;
        after the last one it extrapolates, then holds.
        """
        times = np.asarray(times, dtype=float)
        t, p = self._t, self._p
        if len(t) == 1:
            return np.repeat(p[:1], len(times), axis=0), np.zeros((len(times), 3))
        # interval index: i such that t[i] <= time < t[i+1], clipped to the ends
        i = np.clip(np.searchsorted(t, times, side='right') - 1, 0, len(t) - 2)
        secant = (p[i + 1] - p[i]) / (t[i + 1] - t[i])[:, None]
        start = np.maximum(times, t[0])
        past = np.minimum(start, t[-1] + self.extrapolation)
        positions = p[i] + secant * (past - t[i])[:, None]
        moving = (times >= t[0]) & (times < t[-1] + self.extrapolation)
        return positions, np.where(moving[:, None], secant, 0.0)
