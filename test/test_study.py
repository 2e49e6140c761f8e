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
rope_sim study: a small study of a four-line berth on a local cluster and on a Dask scheduler.

The study: config/berth.yaml cut to four lines of 8 segments, 4 s of the passing ship's
motion, head_1's pretension (one level no length gives: a case that fails) times the forward
spring's material: 8 cases. Run on a local cluster of two processes, then on a `dask
scheduler` with two `dask worker` processes started here, both killed mid-study and the study
interrupted, then started again with two new workers: it runs only the missing cases and
gives byte-identical results. Every case's maxima are those of `rope_sim run` of the case.
"""

import csv
from dataclasses import replace
import io
import json
import math
import os
from pathlib import Path
import signal
import socket
import subprocess
import sys
import time
from types import SimpleNamespace

import numpy as np
import pyarrow.parquet as pq
import pytest
from rope_sim_ros.model.ship.motions import MOTION_CRITERIA
from rope_sim_ros.mooring import scenario
from rope_sim_ros.mooring.status import Rating, ratings
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.sinks import ship_excursions, ship_motions, SummarySink
from rope_sim_ros.offline.study import run_study
from rope_sim_ros.offline.study.cluster import job_of, run_case, StudyProgress
from rope_sim_ros.offline.study.file import prepare, read_study
from rope_sim_ros.offline.study.plots import _heat_grid
from rope_sim_ros.offline.study.results import OK
from rope_sim_ros.params.arrangement import read_setup
import yaml

REPO_ROOT = Path(__file__).resolve().parent.parent
LINES = ['head_1', 'spring_fwd', 'spring_aft', 'stern_1']
PRETENSIONS = [60000, 126000, 5.0e6, 90000]  # 5 MN: above what head_1 pulls at its reach
MATERIALS = ['hmpe', 'polyester']
SECONDS = 4.0
RATE = 20.0
CASES = len(PRETENSIONS) * len(MATERIALS)
FAILING = {2 * len(MATERIALS), 2 * len(MATERIALS) + 1}  # the 5 MN cases
PER_LINE = ('max_tension', 'max_utilisation', 'time_of_max', 'mean_tension', 'parted')
DEADLINE = 90.0  # [s] for a subprocess step that takes a few seconds


def write_study(folder: Path, factors: str) -> Path:
    """Write the berth of four lines, the ship's motion and a study of them into folder."""
    values = yaml.safe_load((REPO_ROOT / 'config' / 'berth.yaml').read_text())
    params = values['/**/mooring']['ros__parameters']
    for name in params['lines']:
        if name not in LINES:
            del params[name]
    params['lines'] = LINES
    params['segments'] = 8
    (folder / 'berth4.yaml').write_text(yaml.safe_dump(values))
    with open(folder / 'ship.csv', 'w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(['t', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw'])
        for i in range(int(SECONDS * 10) + 1):
            t = i / 10.0
            # the passing ship's strongest push, 20 s into its effect
            position, orientation = scenario.ship_pose(scenario.START + 20.0 + t)
            writer.writerow([repr(t)] + [repr(v) for v in position + orientation])
    path = folder / 'study.yaml'
    path.write_text(f'study:\n  arrangement: berth4.yaml\n  duration: {SECONDS}\n'
                    f'  motion: ship.csv\n  rate: {RATE}\n{factors}')
    return path


FACTORS = (f'  factors:\n    head_1.pretension: {json.dumps(PRETENSIONS)}\n'
           f'    spring_fwd.material: {json.dumps(MATERIALS)}\n')


@pytest.fixture(scope='module')
def local_run(tmp_path_factory):
    """Run the study on a local cluster of two processes."""
    folder = tmp_path_factory.mktemp('study')
    study = write_study(folder, FACTORS)
    said = []
    report = run_study(study, folder / 'local', workers=2, say=said.append, progress=False)
    return folder, study, report, said


def read_results(path: Path):
    """Return results.csv as a header and rows of text."""
    with open(path, newline='') as stream:
        rows = list(csv.reader(stream))
    return rows[0], rows[1:]


def summarise(path, names, ratings_):
    """
    Return a case's summary worked out from its OUT.csv (the rules of sinks.py SummarySink).

    The reference a study's summary, made from the run's outputs, is checked against.
    """
    with open(path, newline='') as stream:
        rows = list(csv.DictReader(stream))

    def column(name):
        return np.array([float(row[name]) for row in rows])

    t, summary = column('t'), {}
    for name, rating in zip(names, ratings_):
        sample = np.maximum(column(f'{name}_tension'), column(f'{name}_bollard_tension'))
        peak = np.maximum(np.maximum(column(f'{name}_fairlead_peak_tension'),
                                     column(f'{name}_bollard_peak_tension')), sample)
        k = int(np.argmax(peak))
        summary[f'{name}_max_tension'] = float(peak[k])
        summary[f'{name}_max_utilisation'] = rating.utilisation(float(peak[k]))
        summary[f'{name}_time_of_max'] = float(t[k])
        summary[f'{name}_mean_tension'] = math.fsum(sample.tolist()) / len(sample)
        summary[f'{name}_parted'] = int(bool(np.any(column(f'{name}_parted'))))
    if 'qw' in rows[0]:  # a free ship's pose
        summary.update(ship_excursions(np.column_stack([column(c) for c in ('x', 'y', 'z')]),
                                       np.column_stack([column(c) for c in
                                                        ('qx', 'qy', 'qz', 'qw')])))
        summary.update(ship_motions(np.column_stack([column(c) for c in ('x', 'y', 'z')]),
                                    np.column_stack([column(c) for c in
                                                     ('qx', 'qy', 'qz', 'qw')]),
                                    MOTION_CRITERIA['bulk_cranes']))
    return summary


def test_results_have_a_row_per_case_and_the_failures_reason(local_run):
    folder, _, report, said = local_run
    header, rows = read_results(folder / 'local' / 'results.csv')
    assert header == ['case', 'head_1.pretension', 'spring_fwd.material', 'status'] + [
        f'{line}_{what}' for line in LINES for what in PER_LINE]
    assert [int(row[0]) for row in rows] == list(range(CASES))
    assert report.ran == CASES and report.done_before == 0 and not report.lost
    for k, row in enumerate(rows):
        assert row[1] == str(PRETENSIONS[k // 2]) or float(row[1]) == PRETENSIONS[k // 2]
        assert row[2] == MATERIALS[k % 2]
        if k in FAILING:
            # recorded with its one-line reason; the study went on
            assert row[3] == ("line 'head_1': pretension 5000000 N is not below what the "
                              'line pulls at its reach (4415488 N at its strain limit)')
            assert row[4:] == [''] * (len(header) - 4)
        else:
            assert row[3] == 'ok'
            values = dict(zip(header, row))
            for line in LINES:
                assert 0.02 < float(values[f'{line}_max_utilisation']) < 0.9
                assert values[f'{line}_parted'] == '0'
    assert [index for index, _ in report.failed] == sorted(FAILING)
    # the parquet table holds the same values, typed
    table = pq.read_table(folder / 'local' / 'results.parquet').to_pylist()
    assert len(table) == CASES
    for row, text in zip(table, rows):
        assert row['case'] == int(text[0]) and row['status'] == text[3]
        assert row['spring_fwd.material'] == text[2]
        for line in LINES:
            value = row[f'{line}_max_tension']
            assert (value is None) == (text[3] != 'ok')
            if value is not None:
                assert repr(value) == text[header.index(f'{line}_max_tension')]
                assert row[f'{line}_parted'] == 0
    for name in ('utilisation.png', 'heatmap.png'):
        assert (folder / 'local' / name).read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    assert any('local cluster of 2 processes' in line for line in said)


def test_maxima_are_those_of_rope_sim_run_case_by_case(local_run, tmp_path):
    folder, study, _, _ = local_run
    header, rows = read_results(folder / 'local' / 'results.csv')
    for k in (0, 3, 7):
        values = dict(zip(header, rows[k]))
        out = tmp_path / f'case{k}.csv'
        code = cli.main(['run', '--params', str(folder / 'berth4.yaml'), '--motion',
                         str(folder / 'ship.csv'), '--out', str(out), '--rate', str(RATE),
                         '--set', f'head_1.pretension={PRETENSIONS[k // 2]}',
                         '--set', f'spring_fwd.material={MATERIALS[k % 2]}', '--quiet'])
        assert code == 0
        # the kept OUT.csv is the very file rope_sim run writes
        assert (folder / 'local' / 'cases' / f'{k:04d}.csv').read_bytes() == out.read_bytes()
        with open(out, newline='') as stream:
            table = list(csv.DictReader(stream))
        setup = read_setup(folder / 'berth4.yaml', {
            'head_1.pretension': PRETENSIONS[k // 2], 'spring_fwd.material': MATERIALS[k % 2]})
        for line, rating in zip(LINES, ratings(setup)):
            peaks = [max(float(r[f'{line}_fairlead_peak_tension']),
                         float(r[f'{line}_bollard_peak_tension']),
                         float(r[f'{line}_tension']), float(r[f'{line}_bollard_tension']))
                     for r in table]
            largest = max(peaks)
            assert float(values[f'{line}_max_tension']) == largest
            assert float(values[f'{line}_max_utilisation']) == largest / rating.mbl
            assert float(values[f'{line}_time_of_max']) == float(
                table[peaks.index(largest)]['t'])
            tensions = [max(float(r[f'{line}_tension']), float(r[f'{line}_bollard_tension']))
                        for r in table]
            assert float(values[f'{line}_mean_tension']) == pytest.approx(
                sum(tensions) / len(tensions), rel=1e-14)
    # the spring's material matters: polyester 48 mm breaks at less than HMPE 48 mm
    assert float(dict(zip(header, rows[1]))['spring_fwd_max_utilisation']) > float(
        dict(zip(header, rows[0]))['spring_fwd_max_utilisation'])


def test_every_case_loaded_its_kernels_and_ran_on_one_thread(local_run):
    folder, _, report, said = local_run
    workers = set()
    for k in range(CASES):
        record = json.loads((folder / 'local' / 'cases' / f'{k:04d}.json').read_text())
        assert record['compiled'] == 0, k  # loaded by the worker's warm-up, never per case
        assert record['threads'] == {'numba': 1, 'blas': 1}
        assert record['wall'] > 0.0
        workers.add(record['worker'])
    assert len(workers) == 2  # both processes ran cases
    assert any("kernels loaded from numba's cache on 2 worker(s)" in line for line in said)
    assert 0.0 < report.case_wall < report.wall * 2


def test_dry_run_lists_the_cases_and_what_is_done(local_run, capsys):
    folder, study, _, _ = local_run
    assert cli.main(['study', str(study), '--out', str(folder / 'local'), '--dry-run']) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].endswith(f'{CASES} cases (4 x 2 factorial), 4 s each at 20 Hz; '
                             f'{CASES} done, 0 to run')
    assert len(lines) == 1 + CASES
    assert lines[1] == '  case    0  head_1.pretension=60000, spring_fwd.material=hmpe  [done]'
    assert "[failed: line 'head_1': pretension 5000000 N" in lines[1 + min(FAILING)]
    assert cli.main(['study', str(study), '--out', str(folder / 'fresh'), '--dry-run']) == 0
    assert capsys.readouterr().out.count('[to run]') == CASES
    assert not (folder / 'fresh').exists()


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


class DaskProcesses:
    """The `dask scheduler` and `dask worker` processes a test starts (and only ends)."""

    def __init__(self, folder: Path) -> None:
        """Start a scheduler on a free local port."""
        self.folder = folder
        self.env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            [str(REPO_ROOT)] + [p for p in os.environ.get('PYTHONPATH', '').split(os.pathsep)
                                if p]))
        self.address = f'tcp://127.0.0.1:{_free_port()}'
        self.workers = []
        self.scheduler = self._start(['scheduler', '--host', '127.0.0.1', '--port',
                                      self.address.rsplit(':', 1)[1], '--no-dashboard'],
                                     'scheduler')

    def _start(self, arguments, name) -> subprocess.Popen:
        log = open(self.folder / f'{name}.log', 'w')
        return subprocess.Popen([sys.executable, '-m', 'dask', *arguments], env=self.env,
                                stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                start_new_session=True)

    def start_workers(self, count: int) -> None:
        """Start `count` workers of one thread and wait until they have joined."""
        from distributed import Client
        first = len(self.workers)
        for k in range(first, first + count):
            self.workers.append(self._start(
                ['worker', self.address, '--nthreads', '1', '--nworkers', '1', '--host',
                 '127.0.0.1', '--no-dashboard', '--name', f'w{k}'], f'worker{k}'))
        with Client(self.address, timeout=DEADLINE) as client:
            client.wait_for_workers(count, timeout=DEADLINE)

    def kill(self, process: subprocess.Popen) -> None:
        """Kill a process this object started, with its children (its session)."""
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
        process.wait(timeout=DEADLINE)

    def kill_workers(self) -> None:
        """Kill every worker started so far (a lost machine: no goodbye)."""
        for worker in self.workers:
            self.kill(worker)

    def close(self) -> None:
        """End everything this object started."""
        self.kill_workers()
        self.kill(self.scheduler)


@pytest.fixture
def dask_processes(tmp_path):
    processes = DaskProcesses(tmp_path)
    yield processes
    processes.close()


def _records(folder: Path):
    cases = folder / 'cases'
    return sorted(cases.glob('*.json')) if cases.is_dir() else []


def test_on_a_scheduler_killed_and_started_again_it_completes_the_same_results(
        local_run, dask_processes, tmp_path):
    folder, study, _, _ = local_run
    out = tmp_path / 'cluster'
    dask_processes.start_workers(2)
    command = [sys.executable, '-m', 'rope_sim_ros', 'study', str(study), '--out', str(out),
               '--scheduler', dask_processes.address, '--quiet']
    first = subprocess.Popen(command, env=dask_processes.env, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + DEADLINE
        while not _records(out) and first.poll() is None and time.monotonic() < deadline:
            time.sleep(0.01)  # poll for the first finished case
        dask_processes.kill_workers()  # mid-study: cases in flight are lost with them
        assert first.poll() is None, first.communicate()
        first.send_signal(signal.SIGINT)
        _, stderr = first.communicate(timeout=DEADLINE)
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
    assert first.returncode == 130, stderr
    done = len(_records(out))
    assert 1 <= done < CASES
    assert f'interrupted: {done} of {CASES} cases done' in stderr
    _, partial = read_results(out / 'results.csv')
    assert len(partial) == done
    before = {path.name: path.stat().st_mtime_ns for path in _records(out)}

    dask_processes.start_workers(2)
    said = []
    report = run_study(study, out, scheduler=dask_processes.address, say=said.append,
                       progress=False)
    assert report.done_before == done and report.ran == CASES - done and not report.lost
    assert {path.name: path.stat().st_mtime_ns for path in _records(out)
            if path.name in before} == before  # the cases done were not run again
    assert any(f'{CASES - done} to run, {done} done before' in line for line in said)
    # identical to the local cluster's results, byte for byte
    local = folder / 'local'
    assert (out / 'results.csv').read_bytes() == (local / 'results.csv').read_bytes()
    assert pq.read_table(out / 'results.parquet').equals(
        pq.read_table(local / 'results.parquet'))
    for k in range(CASES):
        if k not in FAILING:
            name = f'{k:04d}.csv'
            assert (out / 'cases' / name).read_bytes() == (local / 'cases' / name).read_bytes()


def test_a_bad_factor_refuses_the_study_at_once(tmp_path, capsys):
    study = write_study(tmp_path, '  factors:\n    head_1.pretension: [100000]\n'
                        '    time_step: [0.001, 0.5]\n')
    assert cli.main(['study', str(study), '--out', str(tmp_path / 'out')]) == 2
    err = capsys.readouterr().err
    assert err == (f'rope_sim study: error: {study}: case 1 (head_1.pretension=100000, '
                   "time_step=0.5): parameter 'time_step' = 0.5 is not allowed: must be >= 0 "
                   'and <= 0.1 s\n')
    assert not (tmp_path / 'out').exists()


@pytest.mark.parametrize('factors, message', [
    ('  factors:\n    head_9.length: [40]\n', "parameter 'head_9.length' is for no line"),
    ('  factors:\n    head_1.pretension: 100000\n',
     'study.factors.head_1.pretension = 100000 is not allowed: must be a list'),
    ('  cases: [{head_1.material: kevlar}]\n', 'kevlar'),
    ('  factors:\n    motion: [ship.csv, missing.csv]\n', 'missing.csv'),
    ('  factors: {head_1.length: [40]}\n  cases: [{}]\n', 'not both'),
    ('  factors: {head_1.pretension: [1.0e5]}\n  speed: 3\n', 'unknown key(s) speed'),
])
def test_what_a_study_refuses_is_one_line(tmp_path, capsys, factors, message):
    study = write_study(tmp_path, factors)
    assert cli.main(['study', str(study), '--out', str(tmp_path / 'out')]) == 2
    err = capsys.readouterr().err
    assert err.startswith('rope_sim study: error: ') and err.count('\n') == 1
    assert message in err


@pytest.mark.parametrize('options, message', [
    (['--workers', '0'], '--workers 0: must be >= 1'),
    (['--workers', '2', '--scheduler', 'tcp://127.0.0.1:8786'], 'not both'),
])
def test_bad_cluster_options_are_one_line(tmp_path, capsys, options, message):
    study = write_study(tmp_path, FACTORS)
    assert cli.main(['study', str(study), '--out', str(tmp_path / 'out'), *options]) == 2
    err = capsys.readouterr().err
    assert err.startswith('rope_sim study: error: ') and err.count('\n') == 1
    assert message in err
    assert not (tmp_path / 'out').exists()


def test_a_motion_shorter_than_the_duration_is_refused(tmp_path):
    study = write_study(tmp_path, '  factors: {head_1.pretension: [1.0e5]}\n')
    study.write_text(study.read_text().replace(f'duration: {SECONDS}', 'duration: 10'))
    with pytest.raises(ValueError, match=r'covers 4 s from its first row, less than the '
                       r"study's duration of 10 s"):
        prepare(read_study(study))


def test_cases_list_and_per_case_files(tmp_path):
    study = write_study(tmp_path, '  cases:\n    - {head_1.pretension: 1.0e5}\n'
                        '    - {motion: ship.csv, stern_1: {material: nylon}}\n')
    read = read_study(study)
    assert read.factors == ('head_1.pretension', 'motion', 'stern_1.material')
    assert [case.values for case in read.cases] == [
        (('head_1.pretension', 1.0e5),), (('motion', 'ship.csv'), ('stern_1.material', 'nylon'))]
    prepared = prepare(read)
    assert prepared[1].setup.line('stern_1').params.material == 'nylon'
    assert prepared[0].key != prepared[1].key
    # the key follows the inputs: the same case again has the same key
    assert prepare(read_study(study))[0].key == prepared[0].key


def test_ship_excursions_and_line_summary_of_synthetic_outputs():
    # a free ship's outputs: heading +y (yaw 90 deg) at (10, 20, 0), then moving
    yaw0 = math.pi / 2.0
    sink = SummarySink(['a'], [Rating(20000.0, 10000.0)],
                       criteria=MOTION_CRITERIA['bulk_cranes'])
    motions = [(0.0, 0.0, 0.0), (-3.0, 0.5, 0.05), (1.0, -0.2, -0.02), (0.0, 0.0, 0.0)]
    # fairlead and bollard tension, their peaks since the previous output, parted
    tensions = [(1000.0, 900.0, 1100.0, 950.0, 0.0), (5000.0, 5200.0, 5400.0, 5300.0, 0.0),
                (0.0, 0.0, 6000.0, 0.0, 1.0), (0.0, 0.0, 0.0, 0.0, 1.0)]
    for k, ((dx, dy, dyaw), tension) in enumerate(zip(motions, tensions)):
        yaw = yaw0 + dyaw
        ship = SimpleNamespace(position=np.array([10.0 + dx, 20.0 + dy, 0.0]),
                               orientation=np.array([0.0, 0.0, math.sin(yaw / 2.0),
                                                     math.cos(yaw / 2.0)]))
        fairlead, bollard, fairlead_peak, bollard_peak, parted = ([v] for v in tension)
        sink(SimpleNamespace(output=SimpleNamespace(
            t=0.5 * k, fairlead_tensions=np.array(fairlead), bollard_tensions=np.array(bollard),
            fairlead_peaks=np.array(fairlead_peak), bollard_peaks=np.array(bollard_peak),
            parted=np.array(parted, dtype=bool), ship=ship)))
    summary = sink.summary()
    assert summary['a_max_tension'] == 6000.0  # a peak between rows, as the line parted
    assert summary['a_time_of_max'] == 1.0
    assert summary['a_max_utilisation'] == 0.3
    assert summary['a_mean_tension'] == (1000.0 + 5200.0) / 4.0
    assert summary['a_parted'] == 1
    # along the start heading (+y) 0.5 m; across it (port = -x) 3 m; the yaw change 0.05
    assert summary['max_surge'] == pytest.approx(0.5, abs=1e-12)
    assert summary['max_sway'] == pytest.approx(3.0, abs=1e-12)
    assert summary['max_yaw'] == pytest.approx(0.05, abs=1e-12)
    # peak to peak: surge 0.5 to -0.2, yaw 0.05 to -0.02; sway zero to peak: 3 m from its
    # mean 0.5 m (-0.0, 3, -1, -0.0); nothing in heave, roll, pitch
    assert summary['surge_motion'] == pytest.approx(0.7, abs=1e-12)
    assert summary['sway_motion'] == pytest.approx(2.5, abs=1e-12)
    assert summary['yaw_motion'] == pytest.approx(0.07, abs=1e-12)
    assert summary['heave_motion'] == summary['roll_motion'] == summary['pitch_motion'] == 0.0
    # against a bulk carrier's cranes (sway 1 m, yaw 2 deg): sway's 2.5 is the largest share
    assert summary['motion_share'] == pytest.approx(2.5, abs=1e-12)


def test_the_progress_bar_counts_cases():
    stream = io.StringIO()
    bar = StudyProgress(4, stream, width=8, enabled=True)
    bar.update()
    bar.update(failed=True)
    assert bar.text().startswith('[####....] 2/4 cases, 1 failed, 0:00')
    bar.finish()
    assert stream.getvalue().endswith('\n') and stream.getvalue().count('\r') == 2


def test_a_free_ships_case_runs_under_its_loads_and_reports_its_excursions(tmp_path):
    # The berth's four lines on a free ship pushed off the quay for 4 s (LOADS.csv), as two
    # cases of the spring's material: each case's summary is the free run's own OUT.csv's.
    write_study(tmp_path, '')
    with open(tmp_path / 'loads.csv', 'w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(['t', 'force_x', 'force_y', 'force_z', 'moment_x', 'moment_y',
                         'moment_z'])
        writer.writerow([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        writer.writerow([1.0, 2.0e6, -2.0e6, 0.0, 0.0, 0.0, 0.0])
    path = tmp_path / 'free.yaml'
    path.write_text(f'study:\n  arrangement: berth4.yaml\n  duration: {SECONDS}\n'
                    f'  loads: loads.csv\n  rate: {RATE}\n  set: {{ship_mode: free}}\n'
                    f'  factors:\n    spring_fwd.material: {json.dumps(MATERIALS)}\n')
    study = read_study(path)
    prepared = prepare(study)
    assert [item.streams for item in prepared] == [None, None]  # no motion: free runs
    outcomes = [run_case(job_of(study, item), None) for item in prepared]
    assert [o.status for o in outcomes] == [OK, OK], [o.status for o in outcomes]
    for item, outcome in zip(prepared, outcomes):
        out = tmp_path / f'case_{item.case.index}.csv'
        out.write_bytes(outcome.csv)
        assert outcome.summary == summarise(out, LINES, ratings(item.setup))
        # 2 MN ahead and off the quay for 3 s move the ship ahead and off
        assert 0.01 < outcome.summary['max_surge'] < 0.5, outcome.summary
        assert 0.01 < outcome.summary['max_sway'] < 0.5, outcome.summary
    assert outcomes[0].summary != outcomes[1].summary  # the spring's material counts


def test_a_case_that_keeps_no_csv_writes_none_and_gives_the_same_summary(
        tmp_path, monkeypatch):
    # One case of the driven berth run twice: keeping its OUT.csv, then with keep: none
    # while OUT.csv's writer refuses to start. Both summaries are the kept OUT.csv's.
    from rope_sim_ros.offline import run as offline_run
    path = write_study(tmp_path, '  cases: [{spring_fwd.material: polyester}]\n  keep: none\n')
    study = read_study(path)
    item = prepare(study)[0]
    job = job_of(study, item)
    assert not job.csv and not job.bag
    kept = run_case(replace(job, csv=True), item.streams)
    assert kept.status == OK, kept.status
    out = tmp_path / 'kept.csv'
    out.write_bytes(kept.csv)
    assert kept.summary == summarise(out, LINES, ratings(item.setup))

    def no_csv(*args, **kwargs):
        raise AssertionError('OUT.csv written')

    monkeypatch.setattr(offline_run, 'CsvSink', no_csv)
    outcome = run_case(job, item.streams)
    assert outcome.status == OK, outcome.status
    assert outcome.csv is None and outcome.bag is None
    assert outcome.summary == kept.summary
    assert 0.02 < outcome.summary['spring_fwd_max_utilisation'] < 0.9


def test_a_heat_map_cell_is_its_worst_case_and_says_what_parted_or_failed():
    """Two speeds by two separations, a third factor's two cases in one cell."""
    def row(speed, separation, fwd, aft, parted=0, status=OK):
        return {'speed': speed, 'separation': separation, 'status': status,
                'breast_fwd_max_utilisation': fwd, 'breast_aft_max_utilisation': aft,
                'breast_fwd_parted': parted, 'breast_aft_parted': 0}

    rows = [row(2.0, 70.0, 0.3, 0.2), row(2.0, 70.0, 0.4, 0.1),  # two depths, one cell
            row(3.0, 70.0, 1.0, 0.5, parted=1), row(2.0, 100.0, 0.1, 0.15),
            row(3.0, 100.0, None, None, status='no equilibrium')]
    grid, labels = _heat_grid(rows, ['breast_fwd', 'breast_aft'], 'speed', 'separation',
                              [2.0, 3.0], [70.0, 100.0])
    assert grid[0, 0] == pytest.approx(40.0) and labels[(0, 0)] == '40 %\nbreast_fwd'
    assert labels[(0, 1)] == '100 %\nbreast_fwd\na line parted'
    assert grid[1, 0] == pytest.approx(15.0) and labels[(1, 0)].endswith('breast_aft')
    assert math.isnan(grid[1, 1]) and labels[(1, 1)] == 'failed'


def test_a_case_takes_its_commands_file_as_rope_sim_run_does(tmp_path, capsys):
    # two cases of the berth's four lines: no commands, then head_1 let go at 1 s (a
    # commands file per case, as a motion file)
    write_study(tmp_path, '')
    (tmp_path / 'let_go.csv').write_text('t,line,command\n1.0,head_1,let_go\n')
    path = tmp_path / 'commands.yaml'
    path.write_text(f'study:\n  arrangement: berth4.yaml\n  duration: {SECONDS}\n'
                    f'  motion: ship.csv\n  rate: {RATE}\n'
                    '  cases: [{}, {commands: let_go.csv}]\n')
    study = read_study(path)
    assert study.cases[1].commands == str(tmp_path / 'let_go.csv')
    prepared = prepare(study)
    assert [[(c.t, c.line, c.command) for c in item.commands] for item in prepared] == [
        [], [(1.0, 'head_1', 'let_go')]]
    assert prepared[0].key != prepared[1].key
    outcomes = [run_case(job_of(study, item), item.streams) for item in prepared]
    assert [o.status for o in outcomes] == [OK, OK], [o.status for o in outcomes]
    tables = []
    for item, outcome in zip(prepared, outcomes):
        out = tmp_path / f'case_{item.case.index}.csv'
        out.write_bytes(outcome.csv)
        assert outcome.summary == summarise(out, LINES, ratings(item.setup))
        with open(out, newline='') as stream:
            tables.append(list(csv.DictReader(stream)))
    # the case's OUT.csv is rope_sim run's with the same file
    run_out = tmp_path / 'run.csv'
    assert cli.main(['run', '--params', str(tmp_path / 'berth4.yaml'), '--motion',
                     str(tmp_path / 'ship.csv'), '--commands', str(tmp_path / 'let_go.csv'),
                     '--out', str(run_out), '--rate', str(RATE), '--quiet']) == 0
    lines = run_out.read_text().splitlines()
    assert outcomes[1].csv.decode().splitlines() == lines[:len(tables[1]) + 1]
    held, let_go = tables
    for row, free in zip(held, let_go):
        t = float(row['t'])
        assert row['head_1_state'] == 'fast'
        assert free['head_1_state'] == ('fast' if t <= 1.0 + 1e-9 else 'free')
    # let go after 1 s of the 4: head_1's mean pull falls to a quarter (141.9 -> 34.0 kN)
    mean_held = outcomes[0].summary['head_1_mean_tension']
    assert outcomes[1].summary['head_1_mean_tension'] < 0.3 * mean_held


@pytest.mark.parametrize('rows, message', [
    ('1.0,head_9,let_go\n', "'head_9' is not a line: one of head_1, spring_fwd, spring_aft, "
     "stern_1; did you mean 'head_1'?"),
    ('4.0,head_1,let_go\n', "data row 1, column 't': 4 s is not before the study's duration "
     'of 4 s: the command would never be taken'),
])
def test_a_bad_commands_file_refuses_the_study_naming_the_case(tmp_path, capsys, rows,
                                                               message):
    study = write_study(tmp_path, '  cases: [{}, {commands: bad.csv}]\n')
    (tmp_path / 'bad.csv').write_text('t,line,command\n' + rows)
    assert cli.main(['study', str(study), '--out', str(tmp_path / 'out')]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f'rope_sim study: error: {study}: case 1 (commands=bad.csv): '
                          f'{tmp_path / "bad.csv"}: ') and err.count('\n') == 1, err
    assert message in err
    assert not (tmp_path / 'out').exists()


def test_waves_are_factors_and_the_studys_seed_is_the_seas(tmp_path):
    # A free ship with the berth's hydrodynamic database in a JONSWAP swell: waves.height a
    # case's value like any parameter's, and the study's seed the sea's draw unless the case
    # sets waves.seed itself (no wind: the sea is the only random input here). The database
    # is named relative to the arrangement file, as rope_sim run --set takes it.
    write_study(tmp_path, '')
    database = REPO_ROOT / 'test' / 'data' / 'hydro' / 'berth_ship.nc'
    path = tmp_path / 'swell.yaml'
    path.write_text(
        f'study:\n  arrangement: berth4.yaml\n  duration: 2.0\n  rate: 10.0\n'
        f'  set: {{ship_mode: free, ship.hydrodynamics: {os.path.relpath(database, tmp_path)},'
        f' waves.spectrum: jonswap,'
        f' waves.period: 10.0, waves.direction: -0.7854}}\n'
        f'  cases:\n    - {{waves.height: 0.5, seed: 1}}\n    - {{waves.height: 1.0, seed: 1}}\n'
        f'    - {{waves.height: 1.0, seed: 2}}\n'
        f'    - {{waves.height: 1.0, seed: 2, waves.seed: 1}}\n')
    study = read_study(path)
    prepared = prepare(study)
    # the database beside the default damping (which counts the waves' damping again): said
    # once for the cases it concerns, before they run
    said = []
    run_study(path, tmp_path / 'dry', None, None, True, said.append, progress=False)
    warned = [line for line in said if 'ship.linear_damping is at its defaults' in line]
    assert len(warned) == 1 and warned[0].startswith('warning: 4 of 4 cases (0, 1, 2, 3): '), said
    assert [item.setup.ship.waves_height for item in prepared] == [0.5, 1.0, 1.0, 1.0]
    assert [item.setup.ship.waves_seed for item in prepared] == [0, 0, 0, 1]
    named = prepared[0].setup.ship.hydrodynamics  # absolute: a worker's directory is any
    assert os.path.isabs(named) and os.path.samefile(named, database), named
    # the key holds the database's contents: solved again at the same path, the cases run
    # again when the study is taken up
    copy = tmp_path / 'ship.nc'
    copy.write_bytes(database.read_bytes())
    again = path.read_text().replace(os.path.relpath(database, tmp_path), 'ship.nc')
    path.write_text(again)
    before = [item.key for item in prepare(read_study(path))]
    copy.write_bytes(database.read_bytes() + b'\0')
    after = [item.key for item in prepare(read_study(path))]
    assert all(a != b for a, b in zip(before, after))
    outcomes = [run_case(job_of(study, item), None) for item in prepared]
    assert [o.status for o in outcomes] == [OK] * 4, [o.status for o in outcomes]
    # the first-order load scales with the height: 1 m of the same sea sways the ship from
    # rest over 2 s 2.3 times as far as 0.5 m
    sway = [o.summary['max_sway'] for o in outcomes]
    assert sway[1] > 1.5 * sway[0] > 0.0, sway
    assert outcomes[2].summary != outcomes[1].summary  # another seed, another sea
    assert outcomes[3].summary == outcomes[1].summary  # waves.seed 1 set: seed 1's sea
