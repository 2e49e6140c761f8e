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
What it costs to hand a System's arrays to a compiled kernel: positional, or as one record.

A kernel call from Python pays numba's dispatch: it types every argument, looks up the
specialisation and unboxes each array. The kernels step a System's 13 arrays
(state: x, v, point_x, point_v, accel, point_accel; tables: particles, lines, line_real,
points, env, bodies, fenders), plus the call's drive arrays, dt and settings. This times a
kernel of no work (it only touches its arrays, so that none is optimised away) taking them

- positional: 20 arguments, as implicit_euler_run took them;
- tuple: one plain tuple of the 13 arrays (fields by index), then the 7 per-call arguments;
- namedtuple: one typing.NamedTuple of the 13 arrays, then the same 7;
- structref: the project's record, a numba StructRef (rope_sim_ros/model/record.py SystemArrays);
- jitclass: one numba jitclass of the 13 arrays;

interleaved in blocks so that a shared machine slows all alike, and prints the median
microseconds a call, and what making the record costs (a System makes its own once, the
adaptive integrator one for each line it takes again with improved Euler, each step). It also
says, for each, whether the kernel's Python code (``.py_func``, what the tests run as the
reference) runs on the record and writes into the System's own arrays, and whether numba
loads a kernel that takes it from its cache (cache=True, in a temporary directory).

    python benchmarks/record_overhead.py [--calls 20000] [--rounds 15]
"""

import argparse
import os
from pathlib import Path
import statistics
import subprocess
import sys
import tempfile
import time

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # this tree's rope_sim_ros (its record)
FIELDS = ('x', 'v', 'point_x', 'point_v', 'accel', 'point_accel', 'particles', 'lines',
          'line_real', 'points', 'env', 'bodies', 'fenders')


def makers() -> dict:
    """Return, by variant, its kernel and a function of the arrays giving the call's arguments."""
    import record_variants as variants
    from rope_sim_ros.model.record import SystemArrays

    def tail(a):
        return (a['drive_x'], a['drive_v'], 1e-3, 10, False, 1.0, 0.5)

    def fields(a):
        return [a[name] for name in FIELDS]

    return {
        'positional': (variants.positional, lambda a: (
            a['x'], a['v'], a['point_x'], a['point_v'], a['drive_x'], a['drive_v'], 1e-3,
            a['particles'], a['lines'], a['line_real'], a['points'], a['env'], a['bodies'],
            a['fenders'], 10, False, 1.0, 0.5, a['accel'], a['point_accel'])),
        'tuple': (variants.plain, lambda a: (tuple(fields(a)),) + tail(a)),
        'namedtuple': (variants.record, lambda a: (variants.Record(*fields(a)),) + tail(a)),
        'structref': (variants.record, lambda a: (SystemArrays(*fields(a)),) + tail(a)),
        'jitclass': (variants.record, lambda a: (variants.JitRecord(*fields(a)),) + tail(a)),
    }


def fresh_arrays() -> dict:
    """Return a System's arrays and a run of no steps' drive arrays."""
    import numpy as np
    import record_variants
    a = record_variants.arrays()
    a['drive_x'] = np.zeros((0, 2, 3))
    a['drive_v'] = np.zeros((0, 2, 3))
    return a


def interpreted_writes(kernel, make) -> bool:
    """Tell whether the kernel's Python code on the record writes the System's own x."""
    import numpy as np
    a = fresh_arrays()
    a['drive_x'] = np.zeros((3, 2, 3))
    try:
        kernel.py_func(*make(a))
    except Exception:  # noqa: B902 (any failure means: it does not work)
        return False
    return bool(a['x'][0, 0] == 3e-3)


CACHE_PROBE = (
    'import record_overhead\n'
    'kernel, make = record_overhead.makers()[{name!r}]\n'
    'kernel(*make(record_overhead.fresh_arrays()))\n'
    'print(sum(kernel.stats.cache_hits.values()), sum(kernel.stats.cache_misses.values()))\n')


def caches(name: str) -> str:
    """Compile the variant with cache=True in a fresh process, then load it in another."""
    with tempfile.TemporaryDirectory() as folder:
        env = dict(os.environ, NUMBA_CACHE_DIR=folder, RECORD_VARIANTS_CACHE='1',
                   PYTHONPATH=os.pathsep.join([str(HERE), str(HERE.parent)]))
        said = []
        for _ in range(2):
            run = subprocess.run([sys.executable, '-c', CACHE_PROBE.format(name=name)],
                                 env=env, capture_output=True, text=True)
            if run.returncode:
                return 'no: ' + (run.stderr.strip().splitlines() or ['?'])[-1][:60]
            said.append(run.stdout.split())
        return 'yes' if said[1] == ['1', '0'] else f'no (compiled again: {said[1]})'


def main() -> None:
    """Print the table: each variant's median us a call, py_func, cache."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--calls', type=int, default=20000, help='calls a block')
    parser.add_argument('--rounds', type=int, default=15)
    args = parser.parse_args()
    variants = makers()
    calls = {}
    for name, (kernel, make) in variants.items():
        a = fresh_arrays()
        arguments = make(a)
        kernel(*arguments)  # compile
        calls[name] = (kernel, arguments)
    times = {name: [] for name in variants}
    for r in range(args.rounds):
        order = list(calls.items())
        for name, (kernel, arguments) in (order if r % 2 else order[::-1]):
            start = time.perf_counter()
            for _ in range(args.calls):
                kernel(*arguments)
            times[name].append((time.perf_counter() - start) / args.calls * 1e6)
    made = {}
    for name, (kernel, make) in variants.items():
        a = fresh_arrays()
        make(a)  # (the first may compile a constructor)
        start = time.perf_counter()
        for _ in range(args.calls // 10):
            make(a)
        made[name] = (time.perf_counter() - start) / (args.calls // 10) * 1e6
    base = statistics.median(times['positional'])
    print(f'## A kernel of no work on a 50-segment System: median of {args.rounds} blocks of '
          f'{args.calls} calls')
    print()
    print('| arguments | us a call | / positional | us to make the arguments '
          '| .py_func on it writes the arrays | cache=True loads |')
    print('|---|---|---|---|---|---|')
    for name, (kernel, make) in variants.items():
        median = statistics.median(times[name])
        print(f'| {name} | {median:.2f} | {median / base:.2f} | {made[name]:.2f} | '
              f'{"yes" if interpreted_writes(kernel, make) else "no"} | '
              f'{caches(name)} |', flush=True)


if __name__ == '__main__':
    main()
