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
Wind and current loads on a moored ship in the OCIMF form, from a table of coefficients.

Contract
--------
Everything is in the ship's body axes (REP-103): x forward, y to port, z up, origin at
midship. The caller passes u, the velocity of the air (or water) RELATIVE to the ship, in
body axes (where the fluid goes: u = fluid velocity - ship velocity, both in body axes).
With V = |u| and rho the fluid density::

    F_x = 1/2 rho V^2 A_T C_x(theta)
    F_y = 1/2 rho V^2 A_L C_y(theta)
    M_z = 1/2 rho V^2 A_L L C_mz(theta)

A_T is the front (transverse) projected area, A_L the side (lateral) projected area and L the
length between perpendiculars; the table says which areas its coefficients go with (the
wind tables in config/ship/ use the windage areas above water, the current tables the
areas below it: beam x draft in front and length x draft at the side).

theta is the direction the fluid comes FROM, in degrees, measured in the body frame from the
bow (+x) toward port (+y): theta = 0 is a head wind (fluid moving toward -x), theta = 90
comes from port (fluid moving toward -y), theta = 180 from astern, theta = 270 from
starboard. For a relative velocity u: theta = atan2(-u_y, -u_x) in degrees.

C_x, C_y, C_mz give the force along +x, +y and the moment about +z at midship with their own
signs: a head wind has C_x < 0 (it pushes the ship astern); a wind from port (theta = 90)
pushes the ship to starboard, so C_y(90) < 0. Zero relative velocity gives exactly zero
loads.

The table is interpolated linearly in theta and periodically over 360 degrees: its angles are
strictly increasing and span at most one turn; the segment from the last angle to the first
angle + 360 closes the circle. A table that lists both 0 and 360 must give the same
coefficients at both (they are the same direction).

The published loads are quasi-steady: they assume the ship's own yaw rate does not change the
flow, which is the standard use of OCIMF-type tables (OCIMF, "Prediction of Wind and Current
Loads on VLCCs", 2nd ed., 1994) with the relative velocity in place of the absolute one.

Water depth
-----------
OCIMF gives current coefficients for several ratios of the water depth to the draft: the
nearer the keel to the bottom, the harder the same current pushes the ship across.
``table_at_ratio`` takes such a set, one table per ratio, and returns the table at the ratio
of a berth: each coefficient at each angle linear in the ratio between the two tables
around it (the union of their angles), the first table's below the first ratio and the last
table's beyond the last (deep water, an infinite ratio, takes the last). One table alone is
the table at every depth.

Files
-----
``parse_coefficient_csv`` reads the text of a table (the caller reads the file: this layer
does no I/O): ``#`` comment lines and blank lines anywhere, then a header naming at least the
columns angle_deg, cx, cy, cmz (in any order, separated by commas), then one row per angle.
A bad file raises ``CoefficientFileError`` (a ValueError) with a one-line message naming the
source, the line and the column.
"""

from dataclasses import dataclass, field
import math
from typing import Sequence, Tuple, Union

import numpy as np

ArrayLike = Union[float, Sequence[float], np.ndarray]
Loads = Tuple[Union[float, np.ndarray], Union[float, np.ndarray], Union[float, np.ndarray]]

COLUMNS = ('angle_deg', 'cx', 'cy', 'cmz')
FULL_TURN = 360.0  # deg


class CoefficientFileError(ValueError):
    """A coefficient table's text is malformed; the message names source, line and column."""


def _as_vector(name: str, values: ArrayLike) -> np.ndarray:
    """Return values as a finite 1-D float array, or raise ValueError naming the argument."""
    array = np.array(values, dtype=float, copy=True)
    if array.ndim != 1:
        raise ValueError(f'{name} must be a 1-D sequence of numbers, got shape {array.shape}')
    if not np.all(np.isfinite(array)):
        raise ValueError(f'{name} must hold finite numbers only')
    array.setflags(write=False)
    return array


def _positive(name: str, value: float, unit: str) -> float:
    """Return value as a float, or raise ValueError unless it is finite and > 0."""
    number = float(value)
    if not (math.isfinite(number) and number > 0.0):
        raise ValueError(f'{name} {value!r} must be a finite number > 0 [{unit}]')
    return number


@dataclass(frozen=True)
class CoefficientTable:
    """
    OCIMF-form load coefficients against the flow direction, interpolated periodically.

    :ivar angles_deg: flow directions theta [deg] (module docstring for the convention),
        strictly increasing, spanning at most 360 degrees; at least two rows.
    :ivar cx: C_x at each angle, with the front area A_T [-].
    :ivar cy: C_y at each angle, with the side area A_L [-].
    :ivar cmz: C_mz at each angle, with A_L and the length L [-].
    """

    angles_deg: np.ndarray
    cx: np.ndarray
    cy: np.ndarray
    cmz: np.ndarray
    # The closed circle used by at(): angles from the first to the first + 360, values with
    # the first row repeated at the end.
    _knots: np.ndarray = field(init=False, repr=False, compare=False)
    _values: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        """Check the rows (ValueError naming the column at fault) and close the circle."""
        angles = _as_vector('angles_deg', self.angles_deg)
        columns = {name: _as_vector(name, getattr(self, name)) for name in ('cx', 'cy', 'cmz')}
        if angles.size < 2:
            raise ValueError(f'angles_deg must have at least 2 rows, got {angles.size}')
        for name, column in columns.items():
            if column.size != angles.size:
                raise ValueError(f'{name} has {column.size} rows but angles_deg has '
                                 f'{angles.size}; they must match')
        steps = np.diff(angles)
        if np.any(steps <= 0.0):
            row = int(np.argmax(steps <= 0.0)) + 1
            raise ValueError(f'angles_deg must be strictly increasing; row {row} '
                             f'({angles[row]!r}) follows {angles[row - 1]!r}')
        span = float(angles[-1] - angles[0])
        if span > FULL_TURN:
            raise ValueError(f'angles_deg must span at most 360 deg to be periodic, it spans '
                             f'{span!r} ({angles[0]!r} to {angles[-1]!r})')
        stacked = np.vstack([columns['cx'], columns['cy'], columns['cmz']])
        if span == FULL_TURN:
            # The first and the last row are the same direction: they must agree, and the
            # last one is dropped so that the circle is closed once.
            if not np.array_equal(stacked[:, 0], stacked[:, -1]):
                raise ValueError(f'angles_deg {angles[0]!r} and {angles[-1]!r} are the same '
                                 'direction but their coefficients differ')
            knots = angles
            values = stacked
        else:
            knots = np.append(angles, angles[0] + FULL_TURN)
            values = np.hstack([stacked, stacked[:, :1]])
        object.__setattr__(self, 'angles_deg', angles)
        for name, column in columns.items():
            object.__setattr__(self, name, column)
        object.__setattr__(self, '_knots', knots)
        object.__setattr__(self, '_values', values)

    def at(self, theta_deg: ArrayLike) -> Loads:
        """
        Return (C_x, C_y, C_mz) at flow direction(s) theta [deg], any real angle.

        Linear in theta between rows and across the 360/0 seam. Floats for a number, arrays
        of theta's shape for an array.
        """
        theta = np.asarray(theta_deg, dtype=float)
        if not np.all(np.isfinite(theta)):
            raise ValueError('theta_deg must be finite [deg]')
        start = self._knots[0]
        wrapped = start + np.mod(theta - start, FULL_TURN)
        results = tuple(np.interp(wrapped, self._knots, row) for row in self._values)
        if theta.ndim == 0:
            return tuple(float(value) for value in results)
        return results


def flow_angle_deg(relative_velocity_body_xy: ArrayLike) -> Union[float, np.ndarray]:
    """
    Return theta [deg] in [-180, 180], the direction the relative flow comes from.

    theta = atan2(-u_y, -u_x): 0 for a flow toward -x (head wind), 90 for a flow toward -y
    (from port). The last axis of the argument holds (u_x, u_y) [m/s]. A zero velocity gives
    theta = 0 (atan2 of two zeros); ocimf_loads makes its loads zero there regardless.
    """
    velocity = np.asarray(relative_velocity_body_xy, dtype=float)
    if velocity.shape[-1:] != (2,):
        raise ValueError('relative_velocity_body_xy must have (u_x, u_y) on its last axis, '
                         f'got shape {velocity.shape}')
    # -0.0 + 0.0 is +0.0, so that a zero velocity gives atan2(+0, +0) = 0, not +-180.
    theta = np.degrees(np.arctan2(-velocity[..., 1] + 0.0, -velocity[..., 0] + 0.0))
    return float(theta) if theta.ndim == 0 else theta


def ocimf_loads(table: CoefficientTable, density: float, relative_velocity_body_xy: ArrayLike,
                area_front: float, area_side: float, length: float) -> Loads:
    """
    Return (F_x [N], F_y [N], M_z [N m]) on the ship from the flow past it.

    The module docstring has the formulas and the conventions: body axes (x forward, y to
    port), the moment about midship, the relative velocity of the fluid past the ship.

    :param table: the coefficients (wind or current).
    :param density: fluid density rho, > 0 [kg/m^3].
    :param relative_velocity_body_xy: (u_x, u_y), fluid velocity minus ship velocity in body
        axes [m/s]; an array with (u_x, u_y) on its last axis gives arrays of loads.
    :param area_front: A_T, the front projected area the table goes with, > 0 [m^2].
    :param area_side: A_L, the side projected area the table goes with, > 0 [m^2].
    :param length: L, the length between perpendiculars, > 0 [m].
    :raises ValueError: an argument out of range or a non-finite velocity.
    """
    if not isinstance(table, CoefficientTable):
        raise ValueError(f'table must be a CoefficientTable, got {type(table).__name__}')
    density = _positive('density', density, 'kg/m^3')
    area_front = _positive('area_front', area_front, 'm^2')
    area_side = _positive('area_side', area_side, 'm^2')
    length = _positive('length', length, 'm')
    velocity = np.asarray(relative_velocity_body_xy, dtype=float)
    if velocity.shape[-1:] != (2,) or not np.all(np.isfinite(velocity)):
        raise ValueError('relative_velocity_body_xy must be finite with (u_x, u_y) on its last '
                         f'axis [m/s], got {relative_velocity_body_xy!r}')
    speed_squared = velocity[..., 0] ** 2 + velocity[..., 1] ** 2
    cx, cy, cmz = table.at(flow_angle_deg(velocity))
    pressure = 0.5 * density * speed_squared
    still = speed_squared == 0.0
    fx = np.where(still, 0.0, pressure * area_front * np.asarray(cx))
    fy = np.where(still, 0.0, pressure * area_side * np.asarray(cy))
    mz = np.where(still, 0.0, pressure * area_side * length * np.asarray(cmz))
    if fx.ndim == 0:
        return float(fx), float(fy), float(mz)
    return fx, fy, mz


def table_at_ratio(tables: Sequence[Tuple[float, CoefficientTable]],
                   ratio: float) -> CoefficientTable:
    """
    Return the coefficients at a water depth / draft ratio from tables at several ratios.

    The module docstring (Water depth) says how: linear in the ratio between neighbours,
    the end tables beyond the ends.

    :param tables: (ratio, table) pairs, the ratios finite, >= 1 and strictly increasing.
    :param ratio: the water depth over the draft, > 0; math.inf for deep water.
    :raises ValueError: no table, a ratio out of order or range, a table that is not one.
    """
    if not tables:
        raise ValueError('tables must hold at least one (ratio, table) pair')
    ratios = [float(r) for r, _ in tables]
    for (r, table) in tables:
        if not isinstance(table, CoefficientTable):
            raise ValueError(f'the table for ratio {r!r} must be a CoefficientTable, got '
                             f'{type(table).__name__}')
        if not (math.isfinite(float(r)) and float(r) >= 1.0):
            raise ValueError(f'ratio {r!r} of a table must be a finite number >= 1 (water '
                             'depth over draft)')
    if any(b <= a for a, b in zip(ratios, ratios[1:])):
        raise ValueError(f'the ratios of the tables must rise strictly, got {ratios}')
    ratio = float(ratio)
    if not ratio > 0.0:  # (NaN too)
        raise ValueError(f'ratio {ratio!r} must be > 0 (water depth over draft), or inf')
    if ratio <= ratios[0]:
        return tables[0][1]
    if ratio >= ratios[-1]:
        return tables[-1][1]
    above = next(k for k, r in enumerate(ratios) if r > ratio)
    weight = (ratio - ratios[above - 1]) / (ratios[above] - ratios[above - 1])
    low, high = tables[above - 1][1], tables[above][1]
    start = low.angles_deg[0]
    angles = np.unique(np.concatenate([
        start + np.mod(table.angles_deg - start, FULL_TURN) for table in (low, high)]))
    mixed = [(1.0 - weight) * np.asarray(a) + weight * np.asarray(b)
             for a, b in zip(low.at(angles), high.at(angles))]
    return CoefficientTable(angles_deg=angles, cx=mixed[0], cy=mixed[1], cmz=mixed[2])


def _fail(source: str, line: int, column: str, message: str) -> CoefficientFileError:
    """Return the one-line error for a bad coefficient file."""
    return CoefficientFileError(f'{source}: line {line}, column {column}: {message}')


def parse_coefficient_csv(text: str, source: str) -> CoefficientTable:
    """
    Return the CoefficientTable written in text (the contents of a CSV file).

    Pure: the caller reads the file and passes its text; source is the name used in error
    messages (usually the file's path). Format: the module docstring. Columns other than
    angle_deg, cx, cy, cmz are ignored.

    :raises CoefficientFileError: no header, a missing column, a row with the wrong number of
        fields, a value that is not a finite number, angles not strictly increasing or not
        within one turn; the message names source, line (1-based) and column.
    """
    header = None
    header_line = 0
    rows = {name: [] for name in COLUMNS}
    row_lines = []
    for number, raw in enumerate(text.splitlines(), start=1):
        stripped = raw.strip()
        if not stripped or stripped.startswith('#'):
            continue
        fields = [item.strip() for item in stripped.split(',')]
        if header is None:
            header, header_line = fields, number
            for name in COLUMNS:
                if name not in header:
                    raise _fail(source, number, name,
                                f'missing column (header has {", ".join(header)})')
            continue
        if len(fields) != len(header):
            raise _fail(source, number, header[min(len(fields), len(header)) - 1],
                        f'{len(fields)} fields but the header (line {header_line}) has '
                        f'{len(header)}')
        for name in COLUMNS:
            text_value = fields[header.index(name)]
            try:
                value = float(text_value)
            except ValueError:
                raise _fail(source, number, name, f'{text_value!r} is not a number') from None
            if not math.isfinite(value):
                raise _fail(source, number, name, f'{text_value!r} is not finite')
            rows[name].append(value)
        if len(rows['angle_deg']) > 1 and rows['angle_deg'][-1] <= rows['angle_deg'][-2]:
            raise _fail(source, number, 'angle_deg',
                        f'{rows["angle_deg"][-1]!r} does not increase on line '
                        f'{row_lines[-1]} ({rows["angle_deg"][-2]!r})')
        row_lines.append(number)
    if header is None:
        raise _fail(source, 1, 'angle_deg', 'no header line (angle_deg,cx,cy,cmz) found')
    if len(row_lines) < 2:
        raise _fail(source, header_line, 'angle_deg',
                    f'needs at least 2 data rows, found {len(row_lines)}')
    try:
        return CoefficientTable(angles_deg=rows['angle_deg'], cx=rows['cx'], cy=rows['cy'],
                                cmz=rows['cmz'])
    except ValueError as error:
        # Only the span (more than a turn, or 0 and 360 disagreeing) is left to fail here.
        raise _fail(source, row_lines[-1], 'angle_deg', str(error)) from None
