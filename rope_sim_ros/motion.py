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
The offline runner's files: MOTION.csv in, OUT.csv out.

MOTION.csv has a header naming its columns: ``t`` [s] and the world-frame fairlead point
``fairlead_x, fairlead_y, fairlead_z`` [m], optionally the bollard point ``bollard_x,
bollard_y, bollard_z`` (all three or none). Other columns are ignored. Every cell of those
columns must be a finite number and ``t`` must increase strictly. An optional ``winch_speed``
column [m/s] (+ pays out) commands the fairlead's winch (winch_mode speed) from its row's
time to the next row's. Errors name the file, the
data row (1-based, header excluded), the file line and the column.

OUT.csv has one row per output time with the forces of the line on both ends, the largest
tension at each since the previous row, the unstretched length and whether the line has
parted (OUT_COLUMNS),
and the payload's position (PAYLOAD_COLUMNS) when the line ends in a free payload.
"""

import csv
from dataclasses import dataclass
import decimal
import math
import os
from typing import Optional, TextIO

import numpy as np

TIME = 't'
FAIRLEAD_COLUMNS = ('fairlead_x', 'fairlead_y', 'fairlead_z')
BOLLARD_COLUMNS = ('bollard_x', 'bollard_y', 'bollard_z')
WINCH_SPEED = 'winch_speed'
OUT_COLUMNS = (
    't', 'fairlead_fx', 'fairlead_fy', 'fairlead_fz', 'fairlead_tension',
    'bollard_fx', 'bollard_fy', 'bollard_fz', 'bollard_tension', 'max_strain',
    'fairlead_peak_tension', 'bollard_peak_tension', 'line_length', 'parted')
# Added after OUT_COLUMNS when the line ends in a free payload (payload_mass > 0).
PAYLOAD_COLUMNS = ('payload_x', 'payload_y', 'payload_z')


class MotionError(ValueError):
    """A motion file cannot be used; the message names the file, row and column."""


@dataclass(frozen=True)
class Motion:
    """
    End-point trajectories read from a motion file.

    :param path: the file they were read from.
    :param t: sample times [s], strictly increasing, shape (n,).
    :param fairlead: fairlead points [m], shape (n, 3).
    :param bollard: bollard points [m], shape (n, 3), or None when the file has none.
    :param t_ns: the sample times as written, rounded to integer nanoseconds (exact even
        where a float is not, e.g. for epoch times), shape (n,); None = from t.
    :param winch_speed: the winch speed commanded from each row on [m/s], shape (n,), or
        None when the file has no winch_speed column.
    """

    path: str
    t: np.ndarray
    fairlead: np.ndarray
    bollard: Optional[np.ndarray] = None
    t_ns: Optional[np.ndarray] = None
    winch_speed: Optional[np.ndarray] = None

    def __post_init__(self) -> None:
        """Fill t_ns from t when not given."""
        if self.t_ns is None:
            object.__setattr__(self, 't_ns', np.round(np.asarray(self.t) * 1e9).astype(np.int64))

    def __len__(self) -> int:
        """Return the number of samples."""
        return len(self.t)


def _where(path: str, row: int, line: int, column: Optional[str] = None) -> str:
    place = f'{path}: data row {row} (file line {line})'
    return place + (f', column {column!r}' if column else '')


def _header(path: str, names: list) -> tuple:
    """Return (column indices of t + fairlead, bollard indices or None)."""
    names = [name.strip() for name in names]
    seen = set()
    for name in names:
        if name and name in seen:
            raise MotionError(f'{path}: file line 1 (header): column {name!r} appears twice')
        seen.add(name)
    wanted = (TIME,) + FAIRLEAD_COLUMNS
    missing = [name for name in wanted if name not in seen]
    if missing:
        raise MotionError(
            f'{path}: file line 1 (header): missing column(s) {", ".join(missing)}; the header '
            f'must name {", ".join(wanted)} and optionally {", ".join(BOLLARD_COLUMNS)} '
            f'(found: {", ".join(names) or "nothing"})')
    present = [name for name in BOLLARD_COLUMNS if name in seen]
    if present and len(present) < 3:
        missing = [name for name in BOLLARD_COLUMNS if name not in seen]
        raise MotionError(
            f'{path}: file line 1 (header): has {", ".join(present)} but not '
            f'{", ".join(missing)}; give all three bollard columns or none')
    required = [names.index(name) for name in wanted]
    bollard = [names.index(name) for name in BOLLARD_COLUMNS] if present else None
    if WINCH_SPEED in seen:
        bollard = (bollard or []) + [names.index(WINCH_SPEED)]
    return names, required, bollard


def _number(path: str, row: int, line: int, column: str, cell: str) -> float:
    text = cell.strip()
    try:
        value = float(text)
    except ValueError:
        shown = repr(text) if text else 'an empty cell'
        raise MotionError(
            f'{_where(path, row, line, column)}: {shown} is not a number') from None
    if not math.isfinite(value):
        raise MotionError(
            f'{_where(path, row, line, column)}: {text!r} is not a finite number')
    return value


def _nanoseconds(cell: str) -> int:
    """Return a (valid, finite) time cell in integer nanoseconds, rounded half to even."""
    value = decimal.Decimal(cell.strip()) * 1_000_000_000
    return int(value.to_integral_value(rounding=decimal.ROUND_HALF_EVEN))


def parse_motion(stream: TextIO, path: str) -> Motion:
    """
    Read a motion table from an open text stream.

    :param stream: the CSV text, positioned at its header line.
    :param path: the file name to put in error messages.
    :returns: the validated Motion.
    :raises MotionError: empty file, missing or duplicate columns, a row with too few or
        too many cells, a non-numeric or non-finite cell, or t not strictly increasing.
    """
    reader = csv.reader(stream)
    try:
        header = next(reader, None)
        while header is not None and not any(cell.strip() for cell in header):
            header = next(reader, None)
        if header is None:
            raise MotionError(
                f'{path}: the file is empty; expected a header line naming '
                f'{TIME}, {", ".join(FAIRLEAD_COLUMNS)}')
        names, required, bollard_index = _header(path, header)
        columns = required + (bollard_index or [])
        times, stamps, values = [], [], []
        row = 0
        for cells in reader:
            line = reader.line_num
            if not any(cell.strip() for cell in cells):
                continue  # blank lines, e.g. at the end of the file
            row += 1
            if len(cells) != len(names):
                raise MotionError(
                    f'{_where(path, row, line)}: {len(cells)} cells, but the header has '
                    f'{len(names)} columns')
            numbers = [_number(path, row, line, names[i], cells[i]) for i in columns]
            ns = _nanoseconds(cells[columns[0]])
            if stamps and ns <= stamps[-1]:
                raise MotionError(
                    f'{_where(path, row, line, TIME)}: {cells[columns[0]].strip()} is not after '
                    f"the previous row's {times[-1]!r}; t must increase strictly (by 1 ns at "
                    'least)')
            times.append(numbers[0])
            stamps.append(ns)
            values.append(numbers[1:])
    except csv.Error as e:
        raise MotionError(f'{path}: file line {reader.line_num}: not valid CSV: {e}') from None
    except UnicodeDecodeError as e:
        raise MotionError(f'{path}: not a UTF-8 text file ({e.reason})') from None
    if not times:
        raise MotionError(f'{path}: the header has no data rows after it')
    table = np.array(values, dtype=float)
    has_bollard = BOLLARD_COLUMNS[0] in names
    winch = WINCH_SPEED in names
    return Motion(path, np.array(times), table[:, 0:3].copy(),
                  table[:, 3:6].copy() if has_bollard else None,
                  np.array(stamps, dtype=np.int64), table[:, -1].copy() if winch else None)


def read_motion(path) -> Motion:
    """
    Read and validate MOTION.csv.

    :param path: the file.
    :returns: the Motion.
    :raises MotionError: the file cannot be read or is not a valid motion table.
    """
    name = os.fspath(path)
    try:
        with open(name, newline='', encoding='utf-8-sig') as stream:
            return parse_motion(stream, name)
    except OSError as e:
        raise MotionError(f'cannot read motion file {name}: {e.strerror or e}') from None


class OutWriter:
    """
    Writes OUT.csv row by row (a context manager).

    Numbers are written with Python's shortest exact repr, so a row read back gives the
    very floats that were computed.
    """

    def __init__(self, path, payload: bool = False) -> None:
        """
        Open (create or overwrite) the file and write the header.

        :param path: the file.
        :param payload: add the PAYLOAD_COLUMNS.
        :raises OSError: it cannot be written.
        """
        self.path = os.fspath(path)
        self.payload = payload
        self._file = open(self.path, 'w', newline='', encoding='utf-8')
        self._writer = csv.writer(self._file, lineterminator='\n')
        self._writer.writerow(OUT_COLUMNS + (PAYLOAD_COLUMNS if payload else ()))
        self.rows = 0

    def write(self, t: float, out) -> None:
        """
        Append one row.

        :param t: output time [s].
        :param out: the simulator.Output of that time.
        """
        numbers = [t, *out.fairlead_force, out.fairlead_tension, *out.bollard_force,
                   out.bollard_tension, out.max_strain, out.fairlead_peak, out.bollard_peak,
                   out.line_length, float(out.parted)]
        if self.payload:
            numbers += list(out.payload_position)
        self._writer.writerow([repr(float(v)) for v in numbers])
        self.rows += 1

    def close(self) -> None:
        """Close the file."""
        self._file.close()

    def __enter__(self) -> 'OutWriter':
        """Return the open writer."""
        return self

    def __exit__(self, *exc) -> None:
        """Close the file."""
        self.close()
