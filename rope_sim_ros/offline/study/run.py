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
run_study: a study from its file to its results, the parts of study/ tied together.

1. read the study and validate every case (a bad value refuses the study at once);
2. find the cases already done in DIR (their record holds the current key): a study
   started again runs only the others;
3. run the rest on the cluster, each case's files and record written as it arrives, with a
   progress bar;
4. write DIR/results.csv, DIR/results.parquet and the plots.

Interrupted (Ctrl-C), it writes the results of the cases done so far and raises
KeyboardInterrupt; a study killed outright keeps its case records, and the next start
completes it.
"""

from dataclasses import dataclass, field
import json
import os
import shutil
import threading
import time
from typing import Any, Callable, Dict, List, Optional, Tuple

from .file import prepare, PreparedCase, read_study, Study, StudyError
from .plots import load_matplotlib, plot_study
from .results import (case_name, CASES_DIR, OK, read_record, result_rows, write_atomic,
                      write_record, write_results)
from ...mooring.ship import damping_advice
from ...mooring.status import ratings

Say = Callable[[str], None]


@dataclass
class StudyReport:
    """
    What a study did.

    :ivar study: the study read.
    :ivar cases: its cases; done_before: those found done in DIR at the start.
    :ivar ran: cases run now; failed: (case, reason) of every failed case (now or before).
    :ivar lost: (case, why) of the cases left undone by lost workers.
    :ivar files: results and plots written.
    :ivar wall: seconds from the start to the end.
    :ivar cluster: what the workers were; kernels: how they got their kernels.
    :ivar case_wall: seconds the cases run now took on their workers, added up; case_cpu:
        the CPU seconds they used meanwhile.
    :ivar timings: seconds of each stage: prepare (read and validate), cluster (start or
        join it, the workers' kernels), run (first case sent to last result stored),
        results, plots.
    """

    study: Study
    cases: int = 0
    done_before: int = 0
    ran: int = 0
    failed: List[Tuple[int, str]] = field(default_factory=list)
    lost: List[Tuple[int, str]] = field(default_factory=list)
    files: List[str] = field(default_factory=list)
    wall: float = 0.0
    cluster: str = ''
    kernels: str = ''
    case_wall: float = 0.0
    case_cpu: float = 0.0
    timings: Dict[str, float] = field(default_factory=dict)


class StudyInterrupted(KeyboardInterrupt):
    """The study was interrupted; the report says what was done (results written)."""

    def __init__(self, report: StudyReport) -> None:
        """Keep the report."""
        super().__init__('interrupted')
        self.report = report


def _lines(prepared: List[PreparedCase]) -> List[str]:
    names: List[str] = []
    for item in prepared:
        for name in item.setup.names:
            if name not in names:
                names.append(name)
    return names


def _wll_fraction(prepared: List[PreparedCase]) -> Optional[float]:
    fractions = []
    seen = set()
    for item in prepared:
        materials = tuple((line.params.material, line.params.diameter)
                          for line in item.setup.lines)
        if materials in seen:
            continue
        seen.add(materials)
        fractions += [r.wll / r.mbl for r in ratings(item.setup) if r.mbl > 0.0]
    return min(fractions) if fractions else None


def done_records(folder: str, prepared: List[PreparedCase]) -> Dict[int, Dict[str, Any]]:
    """Return the records in DIR/cases of the cases done with their current key."""
    count = len(prepared)
    records = {}
    for item in prepared:
        record = read_record(folder, item.case.index, count)
        if record is not None and record.get('key') == item.key:
            records[item.case.index] = record
    return records


def listing(study: Study, prepared: List[PreparedCase],
            records: Dict[int, Dict[str, Any]]) -> List[str]:
    """Return the lines of --dry-run: every case, its values and whether it is done."""
    lines = [f'{study.path}: {len(prepared)} cases ({study.shape()}), {study.duration:g} s '
             f'each at {study.rate:g} Hz; {len(records)} done, '
             f'{len(prepared) - len(records)} to run']
    for item in prepared:
        record = records.get(item.case.index)
        if record is None:
            state = 'to run'
        elif record['status'] == OK:
            state = 'done'
        else:
            state = f'failed: {record["status"]}'
        what = item.case.describe(120) or '(the base parameters)'
        lines.append(f'  case {item.case.index:>4}  {what}  [{state}]')
    return lines


def _store(folder: str, count: int, prepared: Dict[int, PreparedCase],
           records: Dict[int, Dict[str, Any]], report: StudyReport):
    def store(outcome) -> None:
        item = prepared[outcome.index]
        stem = os.path.join(folder, CASES_DIR, case_name(outcome.index, count))
        if outcome.csv is not None:
            write_atomic(stem + '.csv', outcome.csv)
        if outcome.bag is not None:
            _write_bag(stem + '_bag', outcome.bag)
        record = {
            'case': outcome.index, 'key': outcome.key,
            'values': {name: value for name, value in item.case.values},
            'status': outcome.status, 'summary': outcome.summary,
            'wall': outcome.wall, 'cpu': outcome.cpu, 'compiled': outcome.compiled,
            'threads': outcome.threads,
            'worker': outcome.worker,
        }
        # values YAML gave that JSON has not (a date) are kept as their text
        record['values'] = json.loads(json.dumps(record['values'], default=str))
        write_record(folder, count, record)
        records[outcome.index] = record
        report.ran += 1
        report.case_wall += outcome.wall
        report.case_cpu += outcome.cpu
    return store


def _write_bag(path: str, files: Dict[str, bytes]) -> None:
    temporary = f'{path}.tmp{os.getpid()}'
    shutil.rmtree(temporary, ignore_errors=True)
    os.makedirs(temporary)
    for name, data in files.items():
        with open(os.path.join(temporary, name), 'wb') as stream:
            stream.write(data)
    shutil.rmtree(path, ignore_errors=True)
    os.replace(temporary, path)


def damping_warnings(prepared: List[PreparedCase]) -> List[str]:
    """Return a warning for the cases of a free ship with a database and the default damping."""
    warned = [(item.case.index, advice) for item in prepared
              if (advice := damping_advice(item.setup))]
    if not warned:
        return []
    cases = ', '.join(str(index) for index, _ in warned[:10])
    more = ', ...' if len(warned) > 10 else ''
    return [f'warning: {len(warned)} of {len(prepared)} cases ({cases}{more}): {warned[0][1]}']


def run_study(path, out, workers: Optional[int] = None, scheduler: Optional[str] = None,
              dry_run: bool = False, say: Say = print, progress: bool = True,
              plots: bool = True) -> StudyReport:
    """
    Run a study (see the module docstring).

    :param path: STUDY.yaml; out: the study's folder (created).
    :param workers: local cluster processes (default one per core); scheduler: a Dask
        scheduler's address (tcp://HOST:PORT) to use instead.
    :param dry_run: list the cases (and which are done) and run nothing.
    :param say: where the summary lines go.
    :param progress: draw a progress bar (on a TTY).
    :raises StudyError, MotionError: the study cannot be run (one line), before anything runs;
        workers below 1.
    :raises StudyInterrupted: Ctrl-C; the results of the cases done are written.
    """
    from .cluster import check_runnable
    start = time.monotonic()
    if workers is not None and workers < 1:
        raise StudyError(f'--workers {workers}: must be >= 1')
    study = read_study(path)
    prepared = prepare(study)
    check_runnable(study, prepared)
    for line in damping_warnings(prepared):
        say(line)
    folder = os.fspath(out)
    report = StudyReport(study, cases=len(prepared))
    report.timings['prepare'] = time.monotonic() - start
    if dry_run:
        records = done_records(folder, prepared) if os.path.isdir(folder) else {}
        for line in listing(study, prepared, records):
            say(line)
        report.done_before = len(records)
        return report
    os.makedirs(os.path.join(folder, CASES_DIR), exist_ok=True)
    records = done_records(folder, prepared)
    report.done_before = len(records)
    todo = [item for item in prepared if item.case.index not in records]
    say(f'{study.path}: {len(prepared)} cases ({study.shape()}), {study.duration:g} s each; '
        f'{len(todo)} to run' + (f', {len(records)} done before' if records else '')
        + f' -> {folder}')
    lines = _lines(prepared)
    if plots and todo:
        # matplotlib takes about a second to import: while the workers run the cases, the
        # study's own process waits on them, so the plots at the end need not wait for it
        threading.Thread(target=load_matplotlib, daemon=True).start()
    try:  # a Ctrl-C after the cases ran is an interruption like one during them
        if todo:
            _run(study, prepared, todo, folder, records, report, workers, scheduler, say,
                 progress, lines)
        report.failed = [(index, records[index]['status']) for index in sorted(records)
                         if records[index]['status'] != OK]
        mark = time.monotonic()
        report.files = write_results(folder, study, records, lines)
        report.timings['results'] = time.monotonic() - mark
        if plots:
            mark = time.monotonic()
            rows = result_rows(study, records)
            report.files += plot_study(folder, study, rows, lines, _wll_fraction(prepared))
            report.timings['plots'] = time.monotonic() - mark
    except StudyInterrupted:
        raise
    except KeyboardInterrupt:
        report.files = write_results(folder, study, records, lines)
        raise StudyInterrupted(report) from None
    report.wall = time.monotonic() - start
    return report


def _run(study: Study, prepared: List[PreparedCase], todo: List[PreparedCase], folder: str,
         records: Dict[int, Dict[str, Any]], report: StudyReport, workers: Optional[int],
         scheduler: Optional[str], say: Say, progress: bool, lines: List[str]) -> None:
    from .cluster import open_cluster, run_on_cluster, StudyProgress, warm_up_text
    by_index = {item.case.index: item for item in prepared}
    store = _store(folder, len(prepared), by_index, records, report)
    bar = StudyProgress(len(todo), enabled=None if progress else False)
    cluster = None
    try:
        mark = time.monotonic()
        cluster = open_cluster(workers, scheduler, say)
        report.timings['cluster'] = time.monotonic() - mark
        report.cluster = cluster.description
        report.kernels = warm_up_text(cluster.warm_ups)
        say(f'workers: {report.cluster}; {report.kernels}')
        bar.draw()
        mark = time.monotonic()
        report.lost = run_on_cluster(cluster, study, todo, store, bar)
        report.timings['run'] = time.monotonic() - mark
    except KeyboardInterrupt:
        bar.finish()
        report.failed = [(index, records[index]['status']) for index in sorted(records)
                         if records[index]['status'] != OK]
        report.files = write_results(folder, study, records, lines)
        raise StudyInterrupted(report) from None
    finally:
        bar.finish()
        if cluster is not None:
            cluster.close()


def summary_lines(report: StudyReport) -> List[str]:
    """Return the closing lines of a study: counts, failures, lost cases, files."""
    done = report.done_before + report.ran
    failed = report.failed
    text = [f'{done} of {report.cases} cases done ({report.ran} now, {report.done_before} '
            f'before): {done - len(failed)} ok, {len(failed)} failed, in {report.wall:.1f} s']
    for index, why in failed[:10]:
        text.append(f'  case {index} failed: {why}')
    if len(failed) > 10:
        text.append(f'  ... and {len(failed) - 10} more (results.csv, column status)')
    for index, why in report.lost:
        text.append(f'  case {index} not done: its worker was lost ({why}); run the study '
                    'again to run it')
    if report.files:
        text.append('results: ' + ', '.join(report.files))
    return text
