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
The cases of a study on Dask: a local cluster of processes by default, a scheduler's workers.

Each case is one task (run_case) on a worker of one thread: the worker gets the case's
validated parameters and its motion (sent once per motion file, shared by its cases), runs
it as ``rope_sim run`` does (offline/run.py run_motion, run_free), its outputs summarised
as they come (sinks.py SummarySink) and written to OUT.csv or a bag only where the study
keeps them, and sends back the summary and the files kept. The workers need the package,
not the study's files: a cluster of other machines needs no shared file system. The client
writes every file, each case's record last.

Threads: concurrent cases with threaded kernels slow each other down (each run's threads
fight for the same cores), so every worker runs one case at a time with one thread for numba
and for BLAS/OpenMP: the local cluster's processes start with NUMBA_NUM_THREADS,
OMP_NUM_THREADS, OPENBLAS_NUM_THREADS and MKL_NUM_THREADS at 1 (WORKER_ENV), and every case
sets the limits again where it runs (limit_threads: threadpoolctl for BLAS, numba's own),
for workers started by hand.

Kernels: a worker loads the compiled numba kernels when it joins (KernelWarmup, a worker
plugin: once per worker process, the runs of mooring/precompile.py, which load them from
numba's cache), never in a case; each case counts the compilations during its run and
records them (`compiled`: 0 unless a case needed a kernel specialisation the warm-up did
not load).

A case that raises (a refused parameter, a pretension no length gives, a blow-up refusal) is
a result: its status is the one-line reason. A worker lost during a case (killed, out of
memory) is not the case's fault: the scheduler runs the case again on another worker; after
several losses the case is left undone and reported, and the next start runs it again.
"""

from contextlib import contextmanager
from dataclasses import dataclass, field, replace
import importlib
import logging
import os
import tempfile
import time
from typing import Any, Callable, Dict, Iterator, List, Optional, Tuple

from distributed.diagnostics.plugin import WorkerPlugin

from .file import PreparedCase, Study, StudyError
from .results import OK
from ..motion import MotionError, read_loads, Streams
from ..progress import Progress
from ..run import run_free, run_motion
from ..sinks import SummarySink
from ...bag import BagError
from ...model.materials import MaterialError
from ...model.statics.pretension import PretensionError
from ...mooring.status import ratings
from ...mooring.trajectory import TrajectoryError
from ...params.arrangement import ArrangementParams
from ...params.ship import SHIP_SPECS
from ...params.table import ParameterError

WORKER_ENV = {'NUMBA_NUM_THREADS': '1', 'OMP_NUM_THREADS': '1', 'OPENBLAS_NUM_THREADS': '1',
              'MKL_NUM_THREADS': '1'}
PLUGIN_NAME = 'rope_sim_ros-kernels'
# Failures whose message says it all (the user's input); others are named by their type.
INPUT_ERRORS = (ParameterError, PretensionError, MaterialError, TrajectoryError, MotionError,
                BagError)
CONNECT_TIMEOUT = 10.0  # [s] to reach a scheduler
# A free ship's case keeps its OUT.csv; its bags are the mooring node's to record.
FREE_SHIP_KEEPS = ("a free ship's case keeps OUT.csv (keep: csv); record a free ship's bag "
                   'with the mooring node')


@dataclass(frozen=True)
class Job:
    """
    What a worker needs to run one case (its motion comes separately, shared).

    :ivar index: the case's number; key: its key (file.py).
    :ivar setup: its validated parameters.
    :ivar duration: [s]; rate: outputs per simulated second [Hz].
    :ivar loads: the free ship's loads file (None: none).
    :ivar seed: the seed of its random inputs.
    :ivar csv, bag: send back its OUT.csv, its bag.
    :ivar commands: its line-handling commands (ScheduledCommand), in time order.
    """

    index: int
    key: str
    setup: ArrangementParams
    duration: float
    rate: float
    loads: Optional[str]
    seed: int
    csv: bool
    bag: bool
    commands: Tuple[Any, ...] = ()


@dataclass
class Outcome:
    """
    What a case's run gives back to the client.

    :ivar index, key: the case's.
    :ivar status: OK or the one-line reason it failed.
    :ivar summary: its results (sinks.py SummarySink), empty if it failed.
    :ivar csv: its OUT.csv bytes (if kept); bag: {file name: bytes} of its bag (if kept).
    :ivar wall: seconds the case took on its worker (the run and its summary).
    :ivar cpu: CPU seconds its thread used meanwhile (below wall: the core was shared).
    :ivar compiled: numba compilations during the case (0: every kernel came loaded).
    :ivar threads: the thread limits in force during the run: {'numba': n, 'blas': n}.
    :ivar worker: the worker's address.
    """

    index: int
    key: str
    status: str = OK
    summary: Dict[str, Any] = field(default_factory=dict)
    csv: Optional[bytes] = None
    bag: Optional[Dict[str, bytes]] = None
    wall: float = 0.0
    cpu: float = 0.0
    compiled: int = 0
    threads: Dict[str, int] = field(default_factory=dict)
    worker: str = ''


def _numba():
    # By name: this module compiles nothing, and mooring/precompile.py takes a module that
    # imports numba for a source of the kernels (an edit here would drop their cache).
    return importlib.import_module('numba')


def limit_threads() -> Dict[str, int]:
    """
    Hold numba and BLAS/OpenMP to one thread in this process (numba's: in this thread).

    :returns: the limits now in force: {'numba': threads, 'blas': largest pool}.
    """
    numba = _numba()
    from threadpoolctl import threadpool_info, threadpool_limits
    threadpool_limits(1)
    if numba.config.NUMBA_NUM_THREADS > 1 and numba.get_num_threads() != 1:
        numba.set_num_threads(1)
    blas = [pool['num_threads'] for pool in threadpool_info()]
    return {'numba': int(numba.get_num_threads()) if numba.config.NUMBA_NUM_THREADS > 1 else 1,
            'blas': max(blas) if blas else 1}


@contextmanager
def counting_compilations() -> Iterator[List[int]]:
    """Count numba's compilations within the block (loading from the cache is none)."""
    event = importlib.import_module('numba.core.event')
    count = [0]

    class Counter(event.Listener):
        def on_start(self, _event) -> None:
            count[0] += 1

        def on_end(self, _event) -> None:
            pass

    with event.install_listener('numba:compile', Counter()):
        yield count


def warm_up() -> Dict[str, Any]:
    """
    Load (or, without a cache, compile once) every kernel specialisation in this process.

    :returns: {'compiled': compilations, 'loaded': specialisations loaded from numba's
        cache, 'seconds': time taken}.
    """
    start = time.monotonic()
    limit_threads()
    from ...mooring import precompile
    with counting_compilations() as compiled:
        for values in precompile.CONFIGURATIONS:
            precompile.exercise(values)
        precompile.exercise_mooring()
    loaded = sum(sum(d.stats.cache_hits.values()) for d in precompile.dispatchers().values())
    return {'compiled': compiled[0], 'loaded': loaded, 'seconds': time.monotonic() - start}


class KernelWarmup(WorkerPlugin):
    """A worker plugin: every worker that joins loads the kernels once (warm_up)."""

    name = PLUGIN_NAME

    def setup(self, worker) -> None:
        """Warm the worker up; keep what happened for report_warm_up."""
        for name, value in WORKER_ENV.items():
            os.environ.setdefault(name, value)  # before numba is imported, if it is not yet
        try:
            worker.rope_sim_warm_up = warm_up()
        except Exception as e:  # noqa: B902 (reported to the client as one line)
            worker.rope_sim_warm_up = {'error': reason(e)}


def report_warm_up(dask_worker=None) -> Dict[str, Any]:
    """Return what the warm-up did on this worker (run through Client.run)."""
    return getattr(dask_worker, 'rope_sim_warm_up', {})


def reason(error: BaseException) -> str:
    """Return an error as one line: its message for an input error, else its type too."""
    text = ' '.join(str(error).split())
    if isinstance(error, INPUT_ERRORS) and text:
        return text
    return f'{type(error).__name__}: {text}' if text else type(error).__name__


def run_case(job: Job, streams: Optional[Streams]) -> Outcome:
    """
    Run one case on this worker; return its summary and the files to keep (a task).

    Whatever the run raises is the case's result (its status), not the study's failure.
    """
    start, cpu = time.monotonic(), time.thread_time()
    outcome = Outcome(job.index, job.key)
    outcome.threads = limit_threads()
    try:
        from distributed import get_worker
        outcome.worker = get_worker().address
    except ValueError:  # not on a worker (run in the client: tests, a sequential run)
        outcome.worker = ''
    with tempfile.TemporaryDirectory(prefix='rope_sim_case_') as folder:
        out_path = os.path.join(folder, 'out.csv') if job.csv else None
        bag_path = os.path.join(folder, 'bag') if job.bag else None
        with counting_compilations() as compiled:
            try:
                summary = SummarySink(job.setup.names, ratings(job.setup),
                                      origin=streams.origin if streams is not None else 0.0,
                                      criteria=job.setup.ship.motion_limits
                                      if streams is None else None)
                if streams is not None:
                    run_motion(job.setup, streams, out_path, job.rate, bag_path,
                               sinks=[summary], commands=job.commands)
                else:
                    _free_ship(job, out_path, summary)
                outcome.summary = summary.summary()
            except Exception as e:  # noqa: B902 (every failure of a case is its result)
                outcome.status = reason(e)
                outcome.summary = {}
        outcome.compiled = compiled[0]
        if out_path is not None and os.path.exists(out_path):
            with open(out_path, 'rb') as stream:
                outcome.csv = stream.read()
        if bag_path is not None and os.path.isdir(bag_path):
            outcome.bag = {}
            for name in sorted(os.listdir(bag_path)):
                with open(os.path.join(bag_path, name), 'rb') as stream:
                    outcome.bag[name] = stream.read()
    outcome.wall = time.monotonic() - start
    outcome.cpu = time.thread_time() - cpu
    return outcome


def _free_ship(job: Job, out_path: Optional[str], summary: SummarySink) -> None:
    """
    Run a free ship's case from rest under its loads file (if any): its summary, OUT.csv.

    The case's seed is its gusts' (wind_seed) and its irregular sea's (waves.seed), each
    unless the case sets it itself.
    """
    setup = job.setup
    if setup.ship.wind_seed == SHIP_SPECS['wind_seed'].default:
        setup = replace(setup, ship=replace(setup.ship, wind_seed=job.seed))
    if setup.ship.waves_seed == SHIP_SPECS['waves.seed'].default:
        setup = replace(setup, ship=replace(setup.ship, waves_seed=job.seed))
    loads = read_loads(job.loads) if job.loads else None
    run_free(setup, job.duration, loads, out_path, job.rate, sinks=[summary],
             commands=job.commands)


def check_runnable(study: Study, prepared: List[PreparedCase]) -> None:
    """
    Refuse at once a study with a case this runner cannot run (a free ship's bag).

    :raises StudyError: one line naming the first such case.
    """
    for item in prepared:
        if item.streams is None and study.keep in ('bag', 'both'):
            raise StudyError(f'{study.path}: case {item.case.index} ({item.case.describe()}): '
                             f'{FREE_SHIP_KEEPS}')


def job_of(study: Study, item: PreparedCase) -> Job:
    """Return the job of a prepared case."""
    return Job(item.case.index, item.key, item.setup, study.duration, study.rate,
               item.case.loads, item.case.seed, study.keep in ('csv', 'both'),
               study.keep in ('bag', 'both'), item.commands)


def default_workers() -> int:
    """Return the cores this process may use: one worker each."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


@dataclass
class Cluster:
    """
    The client of the study's cluster, and the local cluster it owns (if any).

    :ivar description: what the workers are, for the user.
    :ivar warm_ups: each worker's warm-up report, by address.
    """

    client: Any
    local: Any = None
    description: str = ''
    warm_ups: Dict[str, Dict[str, Any]] = field(default_factory=dict)

    def close(self) -> None:
        """Close the client, and the local cluster if this study started it."""
        try:
            self.client.close()
        finally:
            if self.local is not None:
                self.local.close()


def quiet_dask_logs() -> None:
    """Keep distributed's informational logs off the user's terminal (errors stay)."""
    for name in ('distributed', 'distributed.client', 'distributed.scheduler',
                 'distributed.worker', 'distributed.nanny', 'distributed.core'):
        logging.getLogger(name).setLevel(logging.ERROR)


def open_cluster(workers: Optional[int], scheduler: Optional[str],
                 say: Callable[[str], None] = lambda text: None) -> Cluster:
    """
    Start a local cluster of `workers` processes (default: one per core), or join a scheduler.

    Registers KernelWarmup (every worker loads the kernels once, now and when it joins).

    :raises StudyError: the scheduler cannot be reached, or workers is below 1.
    """
    from distributed import Client, LocalCluster
    quiet_dask_logs()
    if scheduler is not None:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as e:
            raise StudyError(f'cannot reach the Dask scheduler at {scheduler}: '
                             f'{" ".join(str(e).split())}') from None
        cluster = Cluster(client, None, f'the workers of {scheduler}')
        if not client.scheduler_info().get('workers'):
            say(f'waiting for workers to join {scheduler} (dask worker {scheduler} '
                '--nthreads 1)')
    else:
        count = default_workers() if workers is None else workers
        if count < 1:
            raise StudyError(f'--workers {count}: must be >= 1')
        local = LocalCluster(n_workers=count, threads_per_worker=1, processes=True,
                             dashboard_address=None, silence_logs=logging.ERROR,
                             env=dict(WORKER_ENV))
        client = Client(local)
        cluster = Cluster(client, local, f'a local cluster of {count} processes, '
                          '1 thread each')
    try:
        client.register_plugin(KernelWarmup(), name=PLUGIN_NAME)
        cluster.warm_ups = client.run(report_warm_up)
        for address, report in cluster.warm_ups.items():
            if 'error' in report:
                raise StudyError(f'worker {address} cannot run the kernels: '
                                 f'{report["error"]}')
    except BaseException:
        cluster.close()
        raise
    return cluster


def warm_up_text(warm_ups: Dict[str, Dict[str, Any]]) -> str:
    """Say how the workers got their kernels: loaded from numba's cache or compiled."""
    if not warm_ups:
        return 'kernels: loaded by each worker as it joins'
    compiled = [address for address, report in warm_ups.items() if report.get('compiled')]
    seconds = max(report.get('seconds', 0.0) for report in warm_ups.values())
    if not compiled:
        return (f"kernels loaded from numba's cache on {len(warm_ups)} worker(s) in "
                f'{seconds:.1f} s')
    return (f'kernels compiled once on {len(compiled)} of {len(warm_ups)} worker(s) (numba '
            f'had no cache there: python3 -m rope_sim_ros.mooring.precompile prepares it) in '
            f'{seconds:.0f} s')


class StudyProgress(Progress):
    """The study's progress bar (progress.py): cases done of total, failed, time left."""

    def __init__(self, total: int, stream=None, width: int = 30,
                 enabled: Optional[bool] = None) -> None:
        """Prepare the bar for `total` cases to run (drawn only on a TTY unless enabled)."""
        super().__init__(stream, delay=0.0, width=width, enabled=enabled, interval=0.0)
        self.total = total
        self.done = 0
        self.failed = 0

    def update(self, failed: bool = False) -> None:
        """Count one more case done (failed or not) and redraw."""
        self.done += 1
        self.failed += int(failed)
        self.draw()

    def _what(self) -> str:
        failed = f', {self.failed} failed' if self.failed else ''
        return f'{self.done}/{self.total} cases{failed}'

    def text(self) -> str:
        """Return the bar's line."""
        return self.line(self.done, self.total, self._what())

    def draw(self) -> None:
        """Rewrite the line (on a TTY)."""
        self.show(self.done, self.total, self._what())


def run_on_cluster(cluster: Cluster, study: Study, todo: List[PreparedCase],
                   store: Callable[[Outcome], None],
                   progress: Optional[StudyProgress] = None) -> List[Tuple[int, str]]:
    """
    Run the cases on the cluster; hand each outcome to `store` as it arrives.

    Each distinct motion is sent to the cluster once. On KeyboardInterrupt the cases not
    finished are cancelled and the interruption raised.

    :returns: (case, why) of the cases left undone by lost workers.
    """
    from distributed import as_completed
    client = cluster.client
    motions: Dict[int, Any] = {}
    futures = {}
    lost: List[Tuple[int, str]] = []
    try:
        for item in todo:
            streams = item.streams
            if streams is not None and id(streams) not in motions:
                motions[id(streams)] = client.scatter(streams, broadcast=False, hash=False)
            future = client.submit(run_case, job_of(study, item),
                                   motions[id(streams)] if streams is not None else None,
                                   pure=False, key=f'rope_sim-case-{item.case.index}-'
                                   f'{item.key[:12]}-{os.getpid()}-{time.time_ns()}')
            futures[future] = item.case.index
        for future in as_completed(list(futures)):
            index = futures[future]
            try:
                outcome = future.result()
            except Exception as e:  # noqa: B902 (a lost worker, a cancelled task)
                lost.append((index, reason(e)))
                continue
            finally:
                future.release()
            store(outcome)
            if progress is not None:
                progress.update(outcome.status != OK)
    except BaseException:
        client.cancel(list(futures))
        raise
    return lost
