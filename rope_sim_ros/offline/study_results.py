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
A study's results: each case's summary of its OUT.csv, the case records, results.csv/.parquet.

A case's summary comes from its OUT.csv (sinks.py: an arrangement's columns), per line:

- ``<line>_max_tension`` [N]: the line's largest tension over the whole run: the larger of
  its two end tensions (as status.py's utilisation), taken from the peaks of every row (the
  largest since the previous row, over every integration step: a snap between rows counts);
- ``<line>_max_utilisation``: that over the line's MBL (its material at its diameter);
- ``<line>_time_of_max`` [s]: the time of the row that holds it (the first, if it repeats),
  in the time base of OUT.csv (the motion file's);
- ``<line>_mean_tension`` [N]: the mean over the rows of the larger end tension;
- ``<line>_parted``: 1 if the line parted during the run, else 0.

When OUT.csv holds the ship's pose (SHIP_POSE_COLUMNS: a free ship), ``max_surge``,
``max_sway`` [m] and ``max_yaw`` [rad]: the largest absolute excursion from the first row's
pose, along and across the ship's start heading (its start body axes) and about z.

Each finished case is recorded in DIR/cases/NNNN.json (its key, values, status, summary and
how its run went), written last and atomically: a case is done when its record is there with
the current key. results.csv and results.parquet are written from the records, one row per
case in case order; a failed case has its reason in `status` and empty cells. Numbers are
written with Python's shortest exact repr (JSON too): the same runs give the same bytes.
"""

import csv
import json
import math
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence

import numpy as np

from .study_file import format_value, Study
from ..mooring.status import Rating

OK = 'ok'
LINE_RESULTS = ('max_tension', 'max_utilisation', 'time_of_max', 'mean_tension', 'parted')
SHIP_POSE_COLUMNS = ('x', 'y', 'z', 'qx', 'qy', 'qz', 'qw')
SHIP_RESULTS = ('max_surge', 'max_sway', 'max_yaw')
CASES_DIR = 'cases'
RESULTS_CSV = 'results.csv'
RESULTS_PARQUET = 'results.parquet'


class SummaryError(ValueError):
    """An OUT.csv cannot be summarised (a column missing, a cell not a number)."""


def _column(table: Dict[str, np.ndarray], name: str, path: str) -> np.ndarray:
    try:
        return table[name]
    except KeyError:
        raise SummaryError(f'{path}: no column {name!r}') from None


def read_out(path) -> Dict[str, np.ndarray]:
    """Return an OUT.csv's columns as float arrays."""
    path = os.fspath(path)
    with open(path, newline='', encoding='utf-8') as stream:
        reader = csv.reader(stream)
        header = next(reader, None)
        if not header:
            raise SummaryError(f'{path}: empty file')
        rows = [row for row in reader if row]
    if not rows:
        raise SummaryError(f'{path}: no rows')
    try:
        table = np.array(rows, dtype=float)
    except ValueError:
        raise SummaryError(f'{path}: not a table of numbers') from None
    if table.shape != (len(rows), len(header)):
        raise SummaryError(f'{path}: rows of different lengths')
    return {name: table[:, k] for k, name in enumerate(header)}


def line_columns(names: Sequence[str]) -> List[str]:
    """Return the per-line result columns of these lines, in order."""
    return [f'{name}_{what}' for name in names for what in LINE_RESULTS]


def summarise(path, names: Sequence[str], ratings: Sequence[Rating]) -> Dict[str, Any]:
    """
    Return a case's summary from its OUT.csv (see the module docstring).

    :param names: the lines, as OUT.csv names them; ratings: their MBLs, in the same order.
    :raises SummaryError: a column is missing or a cell is not a number.
    """
    path = os.fspath(path)
    table = read_out(path)
    t = _column(table, 't', path)
    summary: Dict[str, Any] = {}
    for name, rating in zip(names, ratings):
        sample = np.maximum(_column(table, f'{name}_tension', path),
                            _column(table, f'{name}_bollard_tension', path))
        peak = np.maximum(_column(table, f'{name}_fairlead_peak_tension', path),
                          _column(table, f'{name}_bollard_peak_tension', path))
        peak = np.maximum(peak, sample)
        k = int(np.argmax(peak))
        largest = float(peak[k])
        summary[f'{name}_max_tension'] = largest
        summary[f'{name}_max_utilisation'] = float(rating.utilisation(largest))
        summary[f'{name}_time_of_max'] = float(t[k])
        summary[f'{name}_mean_tension'] = math.fsum(sample.tolist()) / len(sample)
        summary[f'{name}_parted'] = int(bool(np.any(_column(table, f'{name}_parted', path))))
    if all(column in table for column in SHIP_POSE_COLUMNS):
        summary.update(ship_excursions(table))
    for column, value in summary.items():
        if not math.isfinite(value):
            raise SummaryError(f'{path}: {column} is {value!r}, not a finite number')
    return summary


def ship_excursions(table: Mapping[str, np.ndarray]) -> Dict[str, float]:
    """
    Return max_surge, max_sway [m] and max_yaw [rad] of the ship's poses in a table.

    Excursions from the first row's pose: the position change in the first row's body axes
    (x forward, y to port) and the yaw of the rotation from the first orientation.
    """
    p = np.column_stack([table[c] for c in SHIP_POSE_COLUMNS[:3]])
    q = np.column_stack([table[c] for c in SHIP_POSE_COLUMNS[3:]])
    q = q / np.linalg.norm(q, axis=1)[:, None]
    x0, y0, z0, w0 = q[0]
    start = np.array([
        [1.0 - 2.0 * (y0 * y0 + z0 * z0), 2.0 * (x0 * y0 - z0 * w0), 2.0 * (x0 * z0 + y0 * w0)],
        [2.0 * (x0 * y0 + z0 * w0), 1.0 - 2.0 * (x0 * x0 + z0 * z0), 2.0 * (y0 * z0 - x0 * w0)],
        [2.0 * (x0 * z0 - y0 * w0), 2.0 * (y0 * z0 + x0 * w0), 1.0 - 2.0 * (x0 * x0 + y0 * y0)]])
    body = (p - p[0]) @ start  # R0^T (p - p0), row by row
    # the relative rotation conj(q0) q, then its yaw (z-y-x angles)
    x, y, z, w = q.T
    rw = w0 * w + x0 * x + y0 * y + z0 * z
    rx = w0 * x - x0 * w - y0 * z + z0 * y
    ry = w0 * y + x0 * z - y0 * w - z0 * x
    rz = w0 * z - x0 * y + y0 * x - z0 * w
    yaw = np.arctan2(2.0 * (rw * rz + rx * ry), 1.0 - 2.0 * (ry * ry + rz * rz))
    return {'max_surge': float(np.max(np.abs(body[:, 0]))),
            'max_sway': float(np.max(np.abs(body[:, 1]))),
            'max_yaw': float(np.max(np.abs(yaw)))}


def case_name(index: int, count: int) -> str:
    """Return a case's file stem: its number, zero-padded (0007)."""
    return f'{index:0{max(4, len(str(max(count - 1, 0))))}d}'


def record_path(folder, index: int, count: int) -> str:
    """Return where a case's record lives: DIR/cases/NNNN.json."""
    return os.path.join(os.fspath(folder), CASES_DIR, case_name(index, count) + '.json')


def write_atomic(path: str, data: bytes) -> None:
    """Write a file whole or not at all (a temporary file renamed over it)."""
    temporary = f'{path}.tmp{os.getpid()}'
    with open(temporary, 'wb') as stream:
        stream.write(data)
    os.replace(temporary, path)


def write_record(folder, count: int, record: Mapping[str, Any]) -> str:
    """Write a case's record (atomically); return its path."""
    path = record_path(folder, record['case'], count)
    write_atomic(path, (json.dumps(record, indent=1, allow_nan=False) + '\n').encode())
    return path


def read_record(folder, index: int, count: int) -> Optional[Dict[str, Any]]:
    """Return a case's record, or None if there is none or it cannot be read."""
    try:
        with open(record_path(folder, index, count), encoding='utf-8') as stream:
            record = json.load(stream)
    except (OSError, ValueError):
        return None
    return record if isinstance(record, dict) and record.get('case') == index else None


def result_columns(study: Study, lines: Sequence[str], ship: bool) -> List[str]:
    """Return the results' columns: case, the factors, status, per line, the ship's."""
    return (['case', *study.factors, 'status', *line_columns(lines)]
            + (list(SHIP_RESULTS) if ship else []))


def result_rows(study: Study,
                records: Mapping[int, Mapping[str, Any]]) -> List[Dict[str, Any]]:
    """Return one row per recorded case, in case order: case, factors, status, summary."""
    rows = []
    for case in study.cases:
        record = records.get(case.index)
        if record is None:
            continue
        row: Dict[str, Any] = {'case': case.index, **dict(case.values),
                               'status': record['status']}
        row.update(record.get('summary') or {})
        rows.append(row)
    return rows


def _csv_cell(value: Any) -> str:
    if value is None:
        return ''
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ''
    return format_value(value)


def write_results(folder, study: Study, records: Mapping[int, Mapping[str, Any]],
                  lines: Sequence[str]) -> List[str]:
    """
    Write results.csv and results.parquet from the case records (both atomically).

    :param lines: every line of the study's cases, in order of first appearance.
    :returns: the paths written.
    """
    rows = result_rows(study, records)
    ship = any(row.get(SHIP_RESULTS[0]) is not None for row in rows)
    columns = result_columns(study, lines, ship)
    folder = os.fspath(folder)
    text = [','.join(_quoted(c) for c in columns)]
    for row in rows:
        text.append(','.join(_quoted(_csv_cell(row.get(c))) for c in columns))
    csv_path = os.path.join(folder, RESULTS_CSV)
    write_atomic(csv_path, ('\n'.join(text) + '\n').encode())
    parquet_path = os.path.join(folder, RESULTS_PARQUET)
    write_parquet(parquet_path, columns, rows, study.factors)
    return [csv_path, parquet_path]


def _quoted(cell: str) -> str:
    if any(c in cell for c in ',"\n\r'):
        return '"' + cell.replace('"', '""') + '"'
    return cell


def write_parquet(path: str, columns: Sequence[str], rows: Sequence[Mapping[str, Any]],
                  factors: Sequence[str]) -> None:
    """Write the rows as a Parquet table: numbers as int64/float64, text as strings, gaps null."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    arrays, fields = [], []
    for column in columns:
        values = [row.get(column) for row in rows]
        if column in factors:
            array = _factor_array(values)
        elif column == 'case' or column.endswith('_parted'):
            array = pa.array(values, type=pa.int64())
        elif column == 'status':
            array = pa.array(values, type=pa.string())
        else:
            array = pa.array([v if v is None or math.isfinite(v) else None for v in values],
                             type=pa.float64())
        arrays.append(array)
        fields.append(pa.field(column, array.type))
    table = pa.Table.from_arrays(arrays, schema=pa.schema(fields))
    temporary = f'{path}.tmp{os.getpid()}'
    pq.write_table(table, temporary)
    os.replace(temporary, path)


def _factor_array(values: Sequence[Any]):
    """Return a factor's column: bool, int64 or float64 where every value is one, else text."""
    import pyarrow as pa

    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return pa.array(values, type=pa.bool_())
    if present and all(isinstance(v, int) and not isinstance(v, bool) for v in present):
        return pa.array(values, type=pa.int64())
    if present and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                       for v in present):
        return pa.array([None if v is None else float(v) for v in values], type=pa.float64())
    return pa.array([None if v is None else format_value(v) for v in values], type=pa.string())
