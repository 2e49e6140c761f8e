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
A study's results: the case records, results.csv and results.parquet.

A case's summary is its run's (sinks.py SummarySink: per line LINE_RESULTS, a free ship's
SHIP_RESULTS), computed on its worker from the outputs the run publishes.

Each finished case is recorded in DIR/cases/NNNN.json (its key, values, status, summary and
how its run went), written last and atomically: a case is done when its record is there with
the current key. results.csv and results.parquet are written from the records, one row per
case in case order; a failed case has its reason in `status` and empty cells. Numbers are
written with Python's shortest exact repr (JSON too): the same runs give the same bytes.
"""

import json
import math
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence

from .file import format_value, Study
from ..sinks import LINE_RESULTS, SHIP_RESULTS

OK = 'ok'
CASES_DIR = 'cases'
RESULTS_CSV = 'results.csv'
RESULTS_PARQUET = 'results.parquet'


def line_columns(names: Sequence[str]) -> List[str]:
    """Return the per-line result columns of these lines, in order."""
    return [f'{name}_{what}' for name in names for what in LINE_RESULTS]


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
