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
A line's tabulated strain-tension curve (its load-extension), in MoorDyn's table form.

Pairs (strain, tension [N]), linear in between, and no tension at a strain <= 0 (a rope
carries no compression). A table that starts above strain 0 starts from (0, 0). Past its
last point the curve goes on with its last segment's slope. MoorDyn clamps the tension at
the table's last value there instead; a line stretched past its table then stops pulling
harder and its tangent stiffness drops to 0, which a line past its table should not do and
which would leave the implicit step's matrix without the line's stiffness.

The one rule of the curve is tension_at: compiled, on a line's LINE_REAL row (layout.py),
it gives the kernels the tension and the tangent dT/dstrain at a strain (curve_strain, its
inverse, gives a winch's brake the strain of its holding load). TensionCurve gives
everything else the same curve: the tension and tangent (through tension_at), the strain at
a tension (the inverse), the energy stored per metre of rest length (its integral), the
stiffest tangent up to a strain, and the pieces strain = a + b T of the inverse that the
catenary integrates.
"""

from dataclasses import dataclass
import math

import numba
import numpy as np

from .layout import (AXIAL_STIFFNESS, CURVE_CAPACITY, CURVE_POINTS, CURVE_SLOPE, CURVE_STRAIN,
                     CURVE_TENSION, LINE_REAL_COLUMNS)


@numba.njit(cache=True, inline='always')
def tension_at(real, strain):
    """
    Return the curve's (tension [N], tangent dT/dstrain [N]) at a strain.

    :param real: the line's LINE_REAL row, with a curve (CURVE_POINTS >= 2).
    :param strain: length / rest length - 1.

    At a strain <= 0 the tension is 0 and the tangent the first segment's: the stiffness the
    line meets as soon as it pulls again (the implicit step's matrix wants it, see springs).
    """
    if strain <= 0.0:
        return 0.0, real[CURVE_SLOPE]
    last = int(real[CURVE_POINTS]) - 1
    k = 0
    while k < last and strain > real[CURVE_STRAIN + k + 1]:
        k += 1
    slope = real[CURVE_SLOPE + k]
    return real[CURVE_TENSION + k] + slope * (strain - real[CURVE_STRAIN + k]), slope


@numba.njit(cache=True, inline='always')
def curve_strain(real, tension):
    """
    Return the strain at which the curve pulls `tension` [N] (tension_at's inverse).

    :param real: the line's LINE_REAL row, with a curve (CURVE_POINTS >= 2).

    0 at a tension <= 0; past the table, along its last slope, as tension_at goes on.
    """
    if tension <= 0.0:
        return 0.0
    last = int(real[CURVE_POINTS]) - 1
    k = 0
    while k < last and tension > real[CURVE_TENSION + k + 1]:
        k += 1
    return real[CURVE_STRAIN + k] + (tension - real[CURVE_TENSION + k]) / real[CURVE_SLOPE + k]


@numba.njit(cache=True, inline='always')
def axial_tension(real, strain):
    """Return a line's elastic tension at a strain [N]: its curve's, or EA times the strain."""
    if real[CURVE_POINTS] > 0.0:
        return tension_at(real, strain)[0]
    return real[AXIAL_STIFFNESS] * strain


@numba.njit(cache=True)
def _tensions_at(real, strains, tensions, tangents):
    """Fill tensions and tangents (M,) at strains (M,) (tension_at, elementwise)."""
    for i in range(strains.shape[0]):
        tensions[i], tangents[i] = tension_at(real, strains[i])


def check_curve(pairs) -> tuple:
    """
    Return a strain-tension table as a tuple of (strain, tension) floats that starts at (0, 0).

    () (or None) is no curve: a linear line. A table whose first strain is above 0 gets (0, 0)
    in front of it.

    :raises ValueError: one line naming what is wrong and what is allowed.
    """
    if pairs is None or (hasattr(pairs, '__len__') and len(pairs) == 0):
        return ()
    try:
        points = [tuple(float(c) for c in pair) for pair in pairs]
    except (TypeError, ValueError):
        points = None
    if points is None or any(len(p) != 2 for p in points):
        raise ValueError(f'tension_curve {pairs!r} must be a list of [strain, tension] pairs')
    for i, (strain, tension) in enumerate(points):
        if not (math.isfinite(strain) and math.isfinite(tension)):
            raise ValueError(f'tension_curve point {i} ({strain!r}, {tension!r}) must be two '
                             'finite numbers')
    if points[0][0] > 0.0:
        points.insert(0, (0.0, 0.0))
    if points[0] != (0.0, 0.0):
        raise ValueError(f'tension_curve starts at {points[0]}: allowed: strains >= 0, and a '
                         'tension of 0 at strain 0')
    for (e0, t0), (e1, t1) in zip(points, points[1:]):
        if not (e1 > e0 and t1 > t0):
            raise ValueError(f'tension_curve goes from {(e0, t0)} to {(e1, t1)}: strains and '
                             'tensions must both increase from point to point')
    if len(points) < 2:
        raise ValueError('tension_curve needs a point at a strain above 0')
    if len(points) > CURVE_CAPACITY:
        raise ValueError(f'tension_curve has {len(points)} points with (0, 0): allowed at most '
                         f'{CURVE_CAPACITY}')
    return tuple(points)


@dataclass(frozen=True, eq=False)
class TensionCurve:
    """
    A checked strain-tension curve (check_curve's rules) and what the model needs from it.

    :ivar strains: the points' strains, from 0, shape (n,).
    :ivar tensions: their tensions [N], from 0, shape (n,).
    :ivar slopes: the slope of the segment starting at each point [N per unit strain], the
        last one the last segment's (it goes on past the table), shape (n,).
    """

    strains: np.ndarray
    tensions: np.ndarray
    slopes: np.ndarray

    @classmethod
    def from_pairs(cls, pairs) -> 'TensionCurve':
        """Make the curve of a table of (strain, tension) pairs (raises as check_curve)."""
        points = check_curve(pairs)
        if not points:
            raise ValueError('tension_curve is empty: a linear line has no curve')
        strains = np.array([p[0] for p in points])
        tensions = np.array([p[1] for p in points])
        slopes = np.diff(tensions) / np.diff(strains)
        return cls(strains, tensions, np.append(slopes, slopes[-1]))

    def fill(self, real: np.ndarray) -> None:
        """Write the curve into a line's LINE_REAL row (the columns tension_at reads)."""
        n = len(self.strains)
        real[CURVE_POINTS] = n
        real[CURVE_STRAIN:CURVE_STRAIN + n] = self.strains
        real[CURVE_TENSION:CURVE_TENSION + n] = self.tensions
        real[CURVE_SLOPE:CURVE_SLOPE + n] = self.slopes

    def _evaluate(self, strain) -> tuple:
        real = np.zeros(LINE_REAL_COLUMNS)
        self.fill(real)
        strain = np.asarray(strain, dtype=float)
        flat = np.ascontiguousarray(strain.reshape(-1))
        tensions, tangents = np.empty_like(flat), np.empty_like(flat)
        _tensions_at(real, flat, tensions, tangents)
        return tensions.reshape(strain.shape), tangents.reshape(strain.shape)

    def tension(self, strain):
        """Return the tension [N] at strain(s) (tension_at), shaped like strain."""
        return self._evaluate(strain)[0]

    def tangent(self, strain):
        """Return the tangent dT/dstrain [N] at strain(s) (tension_at), shaped like strain."""
        return self._evaluate(strain)[1]

    def _piece(self, tension) -> np.ndarray:
        """Return the index of the segment each tension (> 0) lies on."""
        return np.clip(np.searchsorted(self.tensions, tension, side='left') - 1, 0,
                       len(self.tensions) - 1)

    def strain_at(self, tension):
        """Return the strain at tension(s) [N] (the inverse; 0 for a tension <= 0)."""
        tension = np.asarray(tension, dtype=float)
        k = self._piece(tension)
        strain = self.strains[k] + (tension - self.tensions[k]) / self.slopes[k]
        return np.where(tension > 0.0, strain, 0.0)

    def compliance(self, tension):
        """Return dstrain/dT at tension(s) [1/N] (at a tension <= 0: the first segment's)."""
        return 1.0 / self.slopes[self._piece(np.asarray(tension, dtype=float))]

    def energy(self, strain):
        """Return the energy stored per metre of rest length at strain(s), int_0^e T [J/m]."""
        strain = np.asarray(strain, dtype=float)
        stored = np.concatenate([[0.0], np.cumsum(
            0.5 * (self.tensions[1:] + self.tensions[:-1]) * np.diff(self.strains))])
        k = np.clip(np.searchsorted(self.strains, strain, side='left') - 1, 0,
                    len(self.strains) - 1)
        d = strain - self.strains[k]
        energy = stored[k] + self.tensions[k] * d + 0.5 * self.slopes[k] * d * d
        return np.where(strain > 0.0, energy, 0.0)

    def stiffest(self, strain: float) -> float:
        """Return the largest tangent [N] of the curve between strain 0 and `strain`."""
        k = int(np.searchsorted(self.strains, strain, side='left'))
        return float(self.slopes[:max(k, 1)].max())

    def inverse_pieces(self) -> tuple:
        """
        Return the inverse as pieces: strain = a_k + b_k T from tension T_k on.

        :returns: (T_k (n,) [N], a_k (n,), b_k (n,) [1/N]); the last piece has no end.
        """
        b = 1.0 / self.slopes
        return self.tensions, self.strains - self.tensions * b, b
