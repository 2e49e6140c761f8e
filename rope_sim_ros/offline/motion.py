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
The files an offline run reads: MOTION.csv, SHIP.csv, LOADS.csv and COMMANDS.csv.

MOTION.csv moves a single line, SHIP.csv a ship, LOADS.csv pushes a free ship, and
COMMANDS.csv handles the lines.

All are CSV tables with a header naming their columns; other columns are ignored. Every
cell of the columns of numbers must be a finite number. In the motion and loads files ``t``
[s] must increase strictly; it is read to the exact nanosecond (a decimal, not a float:
epoch times keep their digits). Errors name the file, the data row (1-based, header
excluded), the file line and the column.

- MOTION.csv: ``t`` and the world-frame fairlead point ``fairlead_x, fairlead_y,
  fairlead_z`` [m], optionally the bollard point ``bollard_x, bollard_y, bollard_z`` (all
  three or none) and ``winch_speed`` [m/s] (+ pays out), which commands the fairlead's winch
  (winch_mode speed) from its row's time to the next row's.
- SHIP.csv: ``t``, the ship's origin ``x, y, z`` [m] in frame_id, and its orientation as
  ``qx, qy, qz, qw``, or as ``yaw`` [rad] (about z; roll and pitch zero), or neither
  (heading along x).
- LOADS.csv: ``t`` and the external load on a free ship (ship_mode free): ``force_x,
  force_y, force_z`` [N] and ``moment_x, moment_y, moment_z`` [N m] about the ship's origin,
  in frame_id axes; linear between rows, held after the last.
- COMMANDS.csv: line-handling commands (mooring/handling.py): ``t`` [s of simulated time
  from the run's start, the first row of MOTION.csv or SHIP.csv being 0], ``line`` (empty
  for let_go_all, and for a single line, which has no name), ``command`` (make_fast,
  let_go, stow or let_go_all) and optionally ``bollard`` (for make_fast: the bollard to
  make the line fast to, else its own). Times may repeat but not go back.

A line's motion is a ship's: its fairlead point is the pose whose origin plus the
fairlead_offset (identity orientation) is that point, so the node fed with the recorded
poses follows the same points.
"""

import csv
from dataclasses import dataclass, field
import decimal
import difflib
import math
import os
from typing import Any, Dict, Iterator, List, Optional, Sequence, Tuple

import numpy as np

from ..params.bollards import BOLLARDS

TIME = 't'
FAIRLEAD_COLUMNS = ('fairlead_x', 'fairlead_y', 'fairlead_z')
BOLLARD_COLUMNS = ('bollard_x', 'bollard_y', 'bollard_z')
WINCH_SPEED = 'winch_speed'
POSITION = ('x', 'y', 'z')
QUATERNION = ('qx', 'qy', 'qz', 'qw')
YAW = 'yaw'


class MotionError(ValueError):
    """A motion file cannot be used; the message names the file, row and column."""


@dataclass(frozen=True)
class Streams:
    """
    What an offline run is fed: the ship's poses and each moving bollard's samples.

    :ivar path: the file they were read from.
    :ivar t_ns: the ship poses' stamps [ns], strictly increasing, (n,).
    :ivar position: the ship's origin (n, 3) [m]; orientation: (x, y, z, w) (n, 4).
    :ivar bollards: {line name: (stamps [ns] (m,), points (m, 3) [m], levers (m, 3) [m])} of
        the bollards that move (a lever: the point minus its pose's origin).
    :ivar winch: {line name: the winch speed commanded from each ship pose on (n,) [m/s]}.
    :ivar origin: the first row's time as written [s] (an output's time in the file's base
        is origin plus its simulated time).
    """

    path: str
    t_ns: np.ndarray
    position: np.ndarray
    orientation: np.ndarray
    bollards: Dict[str, Tuple[np.ndarray, np.ndarray, np.ndarray]] = field(
        default_factory=dict)
    winch: Dict[str, np.ndarray] = field(default_factory=dict)
    origin: float = 0.0

    def __len__(self) -> int:
        """Return the number of ship poses."""
        return len(self.t_ns)


def _where(path: str, row: int, line: int, column: Optional[str] = None) -> str:
    place = f'{path}: data row {row} (file line {line})'
    return place + (f', column {column!r}' if column else '')


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


def read_table(path, required: Sequence[str], optional: Sequence[str],
               expected: str) -> Tuple[Dict[str, np.ndarray], np.ndarray]:
    """
    Read a CSV table with a header: the required columns and those optional ones present.

    :param expected: what the header must name, for the error message.
    :returns: ({column: values (n,)}, the t column's stamps [ns] (n,)).
    :raises MotionError: unreadable or empty file, a duplicate or missing column, a row
        with too few or too many cells, a non-numeric or non-finite cell, t not
        increasing strictly.
    """
    return _read_csv(path, 'motion file', lambda reader, name: _parse(
        reader, name, required, optional, expected))


def _read_csv(path, what: str, parse):
    """Return parse(csv reader, file name) of a file, its failures to read as MotionError."""
    name = os.fspath(path)
    try:
        with open(name, newline='', encoding='utf-8-sig') as stream:
            return parse(csv.reader(stream), name)
    except OSError as e:
        raise MotionError(f'cannot read {what} {name}: {e.strerror or e}') from None
    except csv.Error as e:
        raise MotionError(f'{name}: not valid CSV: {e}') from None
    except UnicodeDecodeError as e:
        raise MotionError(f'{name}: not a UTF-8 text file ({e.reason})') from None


def _header(reader, path: str, required: Sequence[str], expected: str) -> List[str]:
    """Return the header's column names: no duplicate, every required one there."""
    header = next(reader, None)
    while header is not None and not any(cell.strip() for cell in header):
        header = next(reader, None)
    if header is None:
        raise MotionError(f'{path}: the file is empty; expected a header line naming {expected}')
    names = [cell.strip() for cell in header]
    seen = set()
    for column in names:
        if column and column in seen:
            raise MotionError(f'{path}: file line 1 (header): column {column!r} appears twice')
        seen.add(column)
    missing = [column for column in required if column not in seen]
    if missing:
        raise MotionError(
            f'{path}: file line 1 (header): missing column(s) {", ".join(missing)}; the header '
            f'must name {expected} (found: {", ".join(names) or "nothing"})')
    return names


def _rows(reader, path: str, names: Sequence[str]) -> Iterator[Tuple[int, int, List[str]]]:
    """Yield (data row, file line, cells) of every row that is not blank, of full width."""
    row = 0
    for cells in reader:
        if not any(cell.strip() for cell in cells):
            continue  # blank lines, e.g. at the end of the file
        row += 1
        if len(cells) != len(names):
            raise MotionError(f'{_where(path, row, reader.line_num)}: {len(cells)} cells, but '
                              f'the header has {len(names)} columns')
        yield row, reader.line_num, cells


def _parse(reader, path: str, required: Sequence[str], optional: Sequence[str],
           expected: str) -> Tuple[Dict[str, np.ndarray], np.ndarray]:
    names = _header(reader, path, required, expected)
    columns = list(required) + [column for column in optional if column in names]
    index = [names.index(column) for column in columns]
    stamps: List[int] = []
    rows: List[List[float]] = []
    for row, line, cells in _rows(reader, path, names):
        values = [_number(path, row, line, column, cells[i]) for column, i in zip(columns, index)]
        ns = _nanoseconds(cells[index[0]])
        if stamps and ns <= stamps[-1]:
            raise MotionError(
                f'{_where(path, row, line, TIME)}: {cells[index[0]].strip()} is not after the '
                f"previous row's {rows[-1][0]!r}; t must increase strictly (by 1 ns at least)")
        stamps.append(ns)
        rows.append(values)
    if not rows:
        raise MotionError(f'{path}: the header has no data rows after it')
    table = np.array(rows, dtype=float)
    return ({column: table[:, c].copy() for c, column in enumerate(columns)},
            np.array(stamps, dtype=np.int64))


def read_motion(path, fairlead_offset: Sequence[float] = (0.0, 0.0, 0.0),
                bollard_offset: Sequence[float] = (0.0, 0.0, 0.0), line: str = '') -> Streams:
    """
    Read MOTION.csv: a single line's fairlead (and bollard) points (see the module docstring).

    :param fairlead_offset, bollard_offset: the line's offsets (the ship's pose is the
        fairlead point less its offset; a bollard's lever is its offset).
    :param line: the line's name (the single line's: '').
    :raises MotionError: the file cannot be read or is not a valid motion table.
    """
    name = os.fspath(path)
    optional = BOLLARD_COLUMNS + (WINCH_SPEED,)
    expected = f'{TIME}, {", ".join(FAIRLEAD_COLUMNS)} and optionally ' + ', '.join(
        BOLLARD_COLUMNS)
    columns, t_ns = read_table(name, (TIME,) + FAIRLEAD_COLUMNS, optional, expected)
    present = [column for column in BOLLARD_COLUMNS if column in columns]
    if present and len(present) < 3:
        missing = [column for column in BOLLARD_COLUMNS if column not in columns]
        raise MotionError(f'{name}: file line 1 (header): has {", ".join(present)} but not '
                          f'{", ".join(missing)}; give all three bollard columns or none')
    fairlead = np.column_stack([columns[column] for column in FAIRLEAD_COLUMNS])
    count = len(t_ns)
    bollards = {}
    if present:
        points = np.column_stack([columns[column] for column in BOLLARD_COLUMNS])
        bollards[line] = (t_ns, points, np.repeat([np.asarray(bollard_offset, dtype=float)],
                                                  count, axis=0))
    winch = {line: columns[WINCH_SPEED]} if WINCH_SPEED in columns else {}
    orientation = np.repeat([[0.0, 0.0, 0.0, 1.0]], count, axis=0)
    return Streams(name, t_ns, fairlead - np.asarray(fairlead_offset, dtype=float),
                   orientation, bollards, winch, float(columns[TIME][0]))


def read_ship_motion(path) -> Streams:
    """
    Read SHIP.csv: the ship's poses (see the module docstring).

    :raises MotionError: unreadable, a column missing, a cell not a finite number, t not
        increasing, a zero quaternion; named with the file, row and column.
    """
    name = os.fspath(path)
    expected = f'{TIME}, {", ".join(POSITION)} and optionally {", ".join(QUATERNION)} or {YAW}'
    columns, t_ns = read_table(name, (TIME,) + POSITION, QUATERNION + (YAW,), expected)
    count = len(t_ns)
    if all(column in columns for column in QUATERNION):
        orientation = np.column_stack([columns[column] for column in QUATERNION])
        norms = np.linalg.norm(orientation, axis=1)
        if (norms < 1e-6).any():
            r = int(np.flatnonzero(norms < 1e-6)[0]) + 1
            raise MotionError(f'{name}: data row {r} (file line {r + 1}): zero quaternion')
    else:
        yaw = columns[YAW] if YAW in columns else np.zeros(count)
        orientation = np.column_stack([np.zeros(count), np.zeros(count), np.sin(yaw / 2.0),
                                       np.cos(yaw / 2.0)])
    position = np.column_stack([columns[column] for column in POSITION])
    return Streams(name, t_ns, position, orientation, origin=float(columns[TIME][0]))


LOAD_COLUMNS = ('force_x', 'force_y', 'force_z', 'moment_x', 'moment_y', 'moment_z')


@dataclass(frozen=True)
class LoadSchedule:
    """
    LOADS.csv: the external load on a free ship over time.

    :ivar path: the file.
    :ivar times: each row's t [s] (n,).
    :ivar loads: each row's force [N] and moment about the ship's origin [N m], world axes
        (n, 6); linear between rows, held before the first and after the last.
    """

    path: str
    times: np.ndarray
    loads: np.ndarray


def read_loads(path) -> LoadSchedule:
    """
    Read LOADS.csv: t, force_x, force_y, force_z, moment_x, moment_y, moment_z.

    :raises MotionError: unreadable, a column missing, a cell not a finite number, t not
        increasing; named with the file, row and column.
    """
    name = os.fspath(path)
    columns, _ = read_table(name, (TIME,) + LOAD_COLUMNS, (),
                            f'{TIME}, {", ".join(LOAD_COLUMNS)}')
    return LoadSchedule(name, np.asarray(columns[TIME], dtype=float),
                        np.column_stack([columns[column] for column in LOAD_COLUMNS]))


LINE = 'line'
COMMAND = 'command'
BOLLARD = 'bollard'
COMMAND_COLUMNS = (TIME, LINE, COMMAND)


@dataclass(frozen=True)
class CommandSchedule:
    """
    COMMANDS.csv: line-handling commands at their times, checked against the mooring.

    :ivar path: the file.
    :ivar commands: the commands in time order (mooring/records.py ScheduledCommand).
    :ivar rows: each command's data row in the file (1-based).
    """

    path: str
    commands: Tuple[Any, ...]
    rows: Tuple[int, ...]


def read_commands(path, lines: Sequence[str], bollards: Sequence[str]) -> CommandSchedule:
    """
    Read COMMANDS.csv: t, line, command and optionally bollard (see the module docstring).

    :param lines: the mooring's line names (a single line's: ['']).
    :param bollards: the names of its bollards.
    :raises MotionError: unreadable, a column missing, a time not a finite number >= 0 or
        before the previous row's, an unknown command, line or bollard (the nearest name
        said), a line named with let_go_all or none with another command, a bollard with
        another command than make_fast; named with the file, row and column.
    """
    # here, not at the top: mooring.handling and mooring.records load numba (1.1 s), which
    # every rope_sim command would pay for this module's MotionError
    from ..mooring.handling import COMMANDS
    from ..mooring.records import ScheduledCommand
    expected = f'{", ".join(COMMAND_COLUMNS)} and optionally {BOLLARD}'

    def parse(reader, name: str) -> CommandSchedule:
        names = _header(reader, name, COMMAND_COLUMNS, expected)
        index = {column: names.index(column) for column in COMMAND_COLUMNS + (BOLLARD,)
                 if column in names}
        commands: List[Any] = []
        rows: List[int] = []
        for row, line, cells in _rows(reader, name, names):
            def cell(column: str) -> str:
                return cells[index[column]].strip() if column in index else ''

            t = _number(name, row, line, TIME, cells[index[TIME]])
            if t < 0.0:
                raise MotionError(f'{_where(name, row, line, TIME)}: {cell(TIME)} is before '
                                  "the run's start: give seconds from it, >= 0")
            if commands and t < commands[-1].t:
                raise MotionError(
                    f'{_where(name, row, line, TIME)}: {cell(TIME)} is before the previous '
                    f"row's {commands[-1].t:g}; the commands are taken in time order: sort "
                    'the rows by t')
            command = _one_of(_where(name, row, line, COMMAND), cell(COMMAND), COMMAND,
                              COMMANDS)
            target = _line(_where(name, row, line, LINE), cell(LINE), command, lines)
            bollard = cell(BOLLARD)
            if bollard:
                _bollard(_where(name, row, line, BOLLARD), bollard, command, bollards)
            commands.append(ScheduledCommand(t, target, command, bollard))
            rows.append(row)
        if not commands:
            raise MotionError(f'{name}: the header has no data rows after it')
        return CommandSchedule(name, tuple(commands), tuple(rows))

    return _read_csv(path, 'commands file', parse)


def _one_of(where: str, name: str, what: str, names: Sequence[str]) -> str:
    """Return name if it is one of names; else refuse it, naming the nearest one."""
    if name in names:
        return name
    shown = repr(name) if name else 'an empty cell'
    found = difflib.get_close_matches(name, list(names), n=1, cutoff=0.6)
    near = f'; did you mean {found[0]!r}?' if found else ''
    raise MotionError(f'{where}: {shown} is not a {what}: one of {", ".join(names)}{near}')


def _line(where: str, name: str, command: str, lines: Sequence[str]) -> str:
    if command == 'let_go_all':
        if name:
            raise MotionError(f'{where}: {name!r} with let_go_all, which lets every fast line '
                              'go: leave the line empty')
        return ''
    if list(lines) == ['']:
        if name:
            raise MotionError(f'{where}: {name!r}, but the single line has no name: leave the '
                              'line empty')
        return ''
    return _one_of(where, name, 'line', lines)


def _bollard(where: str, name: str, command: str, bollards: Sequence[str]) -> None:
    if command != 'make_fast':
        raise MotionError(f'{where}: {name!r} with {command}: a bollard is named for make_fast '
                          'only; leave it empty')
    if not bollards:
        raise MotionError(f'{where}: {name!r}, but the arrangement has no bollards; list them '
                          f'in {BOLLARDS!r}, each with its position')
    _one_of(where, name, 'bollard', bollards)
