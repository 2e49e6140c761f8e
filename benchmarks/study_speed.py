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
How fast a study runs its cases: cases per minute with 1 and 2 local workers, and its overhead.

The study: the berth (config/berth.yaml, eight lines of 20-30 segments) under the study
demo's passing-ship motions (examples/study/passing_*.csv) times the forward spring's
material, each case the first --duration s (default 30), run once on a local cluster of each
size in a fresh folder (48 cases by default: enough that the cluster's start, a cost per
study, does not hide the cost per case). Printed per size:

- cases/min: the cases over the run (first case sent to last result stored), and over the
  whole study (with the cluster's start and the results and plots);
- speed-up: against one worker;
- case time: the cases' own seconds on their workers, added up (each case's run and its
  summary); on CPU: the share of it their threads ran (below 100 %: the cores were shared
  with other work, and the speed-up says more about that work than about the study);
- overhead: the run's time beyond the cases' own time per worker (scheduling, sending the
  inputs and files, writing each case's files, and workers idle at the end), and the
  fixed costs of reading and checking the study and writing the results and plots, in % of
  the cases' time per worker; the cluster's start (processes, imports, kernels loaded from
  numba's cache) apart, a cost per study, not per case; the client's CPU seconds (the
  study's own process, with the local scheduler).

Each case's summary comes from its run's outputs (offline/sinks.py SummarySink); --keep says
what each case writes besides: csv (its OUT.csv, the default), none (nothing).

    python benchmarks/study_speed.py [--cases 48] [--duration 30] [--workers 1 2] [--repeat 1]
        [--keep csv]
"""

import argparse
import os
from pathlib import Path
import statistics
import tempfile
import time

from rope_sim_ros.offline.study import run_study

REPO_ROOT = Path(__file__).resolve().parent.parent
MOTIONS = ('passing_075.csv', 'passing_100.csv', 'passing_125.csv', 'passing_150.csv')
MATERIALS = ('hmpe', 'polyester', 'nylon', 'steel_wire')


def write_study(folder: Path, cases: int, duration: float, keep: str = 'csv') -> Path:
    """Write a study of `cases` cases (motion x material, in order) into folder."""
    examples = REPO_ROOT / 'examples' / 'study'
    lines = []
    for k in range(cases):
        motion = examples / MOTIONS[(k // len(MATERIALS)) % len(MOTIONS)]
        lines.append(f'    - {{motion: {motion}, spring_fwd.material: '
                     f'{MATERIALS[k % len(MATERIALS)]}}}')
    path = folder / 'study.yaml'
    path.write_text(
        f'study:\n  arrangement: {REPO_ROOT / "config" / "berth.yaml"}\n'
        f'  duration: {duration}\n  rate: 10.0\n  keep: {keep}\n  cases:\n'
        + '\n'.join(lines) + '\n')
    return path


def main() -> None:
    """Run the study with 1 and 2 workers (--repeat rounds, alternating); print the table."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--cases', type=int, default=48, help='cases in the study')
    parser.add_argument('--duration', type=float, default=30.0, help='seconds per case')
    parser.add_argument('--workers', type=int, nargs='+', default=[1, 2],
                        help='local cluster sizes to run')
    parser.add_argument('--repeat', type=int, default=1,
                        help='rounds, each running every size once in turn (this machine '
                        'varies by 20 %% from run to run)')
    parser.add_argument('--keep', choices=('csv', 'none'), default='csv',
                        help="each case's files: its OUT.csv (csv) or none")
    args = parser.parse_args()
    rounds = []
    with tempfile.TemporaryDirectory(prefix='study_speed_') as folder:
        study = write_study(Path(folder), args.cases, args.duration, args.keep)
        for round_ in range(args.repeat):
            results = {}
            for workers in args.workers:
                start, cpu = time.monotonic(), time.process_time()
                report = run_study(study, Path(folder) / f'round_{round_}_workers_{workers}',
                                   workers=workers, say=lambda text: None, progress=False)
                total, cpu = time.monotonic() - start, time.process_time() - cpu
                assert report.ran == args.cases and not report.failed and not report.lost, \
                    report
                results[workers] = (report, total, cpu)
            rounds.append(results)
    load = os.getloadavg()[0]
    print(f'study: {args.cases} cases of {args.duration:g} s (config/berth.yaml, 8 lines), '
          f'keep: {args.keep}, {os.cpu_count()} cores, load average {load:.2f} after the runs')
    header = ('workers', 'cases/min (run)', 'cases/min (study)', 'speed-up (run)',
              'speed-up (study)', 'case time [s]', 'on CPU', 'run [s]', 'overhead',
              'fixed', 'cluster start [s]', 'study [s]', 'client CPU [s]')
    print(' | '.join(header))
    speedups = {workers: [] for workers in args.workers}
    for results in rounds:
        base = None
        for workers, (report, total, cpu) in results.items():
            run = report.timings['run']
            per_worker = report.case_wall / workers
            overhead = run - per_worker
            finishing = sum(report.timings.get(stage, 0.0)
                            for stage in ('prepare', 'results', 'plots'))
            rate_run, rate_study = 60.0 * args.cases / run, 60.0 * args.cases / total
            if base is None:
                base = (rate_run, rate_study)
            speedups[workers].append(rate_study / base[1])
            print(' | '.join([
                f'{workers}', f'{rate_run:.1f}', f'{rate_study:.1f}',
                f'{rate_run / base[0]:.2f}', f'{rate_study / base[1]:.2f}',
                f'{report.case_wall:.1f}',
                f'{100.0 * report.case_cpu / report.case_wall:.0f} %', f'{run:.1f}',
                f'{overhead:.2f} s ({100.0 * overhead / per_worker:.1f} %)',
                f'{finishing:.2f} s ({100.0 * finishing / per_worker:.1f} %)',
                f'{report.timings["cluster"]:.1f}', f'{total:.1f}', f'{cpu:.1f}']))
    if len(rounds) > 1:
        for workers, values in list(speedups.items())[1:]:
            print(f'{workers} workers: speed-up (study) against {args.workers[0]} in the same '
                  f'round, median {statistics.median(values):.2f} '
                  f'({min(values):.2f}-{max(values):.2f}) over {len(values)} rounds')


if __name__ == '__main__':
    main()
