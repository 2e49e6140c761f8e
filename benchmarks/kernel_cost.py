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
What the integrators' kernels cost a call here against another checkout, in one process.

The kernels alone (stepping/step.py's step on a System, no Mooring, no outputs): lines of
polyester-like rope (2.6 kg/m, EA 50 MN) sagging from a fixed point (or a free 1 t payload)
to a driven one held still, a run of 1 to 20 steps a call. Both trees' packages are imported
side by side, each under a name of its own with its compiled kernels in a cache of its own
(as benchmarks/one_line_cost.py does), and take turns in blocks of calls. Times are the
thread's CPU time (time.thread_time), which a machine shared with other work disturbs far
less than the wall clock: the table gives the fastest block and the median one. The
implicit step's paths differ by case: lines whose ends are fixed or driven step each alone,
a free end joins them into one system (the point system and its condensation).

    git worktree add /tmp/before main
    python benchmarks/kernel_cost.py --before /tmp/before [--rounds 40] [--calls 200]

The first run compiles both trees' kernels into --cache (a few minutes).
"""

import argparse
import importlib
import inspect
from pathlib import Path
import statistics
import tempfile
import time

from two_trees import import_both

# (integrator, lines, segments, free end, steps a call, step [s])
CASES = (
    ('implicit_euler', 1, 20, False, 1, 3e-3),
    ('implicit_euler', 8, 50, False, 1, 3e-3),
    ('implicit_euler', 8, 50, False, 5, 3e-3),
    ('implicit_euler', 1, 20, True, 1, 3e-3),
    ('implicit_euler', 1, 20, True, 20, 3e-3),
    ('implicit_euler', 8, 50, True, 5, 3e-3),
    ('improved_euler', 1, 20, False, 5, 1e-4),
    ('improved_euler', 8, 50, False, 5, 1e-4),
)


def system(package: str, lines: int, segments: int, free: bool):
    """Return a packed System of `package`: `lines` sagging lines side by side."""
    import numpy as np
    objects = importlib.import_module(f'{package}.model.objects')
    known = inspect.signature(objects.LineType).parameters
    rope = objects.LineType(**{name: value for name, value in dict(
        mass_per_length=2.6, axial_stiffness=5e7, axial_damping=3e5, diameter=0.064).items()
        if name in known})
    built = objects.System(objects.Environment(gravity=(0.0, 0.0, -9.81)))
    for k in range(lines):
        y = 5.0 * k
        a = built.add_point(objects.Point('free', [0.0, y, 0.0], mass=1000.0) if free
                            else objects.Point('fixed', [0.0, y, 0.0]))
        b = built.add_point(objects.Point('driven', [38.0, y, 8.0]))
        shape = np.linspace([0.0, y, 0.0], [38.0, y, 8.0], segments + 1)
        shape[1:-1, 2] -= np.sin(np.pi * np.arange(1, segments) / segments)
        built.add_line(objects.Line.uniform(rope, 40.0, segments, shape, (a, b)))
    built.pack()
    return built


def caller(package: str, case: tuple):
    """Return a function taking one kernel call of the case on a System of `package`."""
    integrator, lines, segments, free, steps, dt = case
    step = importlib.import_module(f'{package}.stepping.step').step
    stepped = system(package, lines, segments, free)
    drive_x, drive_v = stepped.drive_arrays(steps)

    def call():
        step(stepped, integrator, dt, drive_x, drive_v)

    call()  # (compiles or loads the kernels)
    return call


def compare(case: tuple, rounds: int, calls: int) -> dict:
    """Return each tree's CPU us a call of the case, every block's."""
    trees = {name: caller(name, case) for name in ('before_tree', 'this_tree')}
    times = {name: [] for name in trees}
    for r in range(rounds):
        for name in (('before_tree', 'this_tree') if r % 2 else ('this_tree', 'before_tree')):
            call = trees[name]
            start = time.thread_time()
            for _ in range(calls):
                call()
            times[name].append((time.thread_time() - start) / calls * 1e6)
    return times


def main() -> None:
    """Print a table: each case, both trees' CPU time a call, the ratios."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--before', required=True, type=Path,
                        help='a checkout of the tree to compare with (its rope_sim_ros/)')
    parser.add_argument('--rounds', type=int, default=40)
    parser.add_argument('--calls', type=int, default=200, help='calls a block')
    parser.add_argument('--cache', type=Path,
                        default=Path(tempfile.gettempdir()) / 'rope_sim_kernel_cost')
    args = parser.parse_args()
    import_both(parser, args.before, args.cache)  # before numba is imported
    print(f'## The kernels a call: {args.before} against this tree, thread CPU time, '
          f'{args.rounds} blocks of {args.calls} calls each, alternated')
    print()
    print('| integrator | lines x N | end | steps a call | before: us a call (fastest / '
          'median block) | this tree | this / before (fastest / median) |')
    print('|---|---|---|---|---|---|---|')
    for case in CASES:
        integrator, lines, segments, free, steps, _ = case
        times = compare(case, args.rounds, args.calls)
        cells = {name: (min(t), statistics.median(t)) for name, t in times.items()}
        before, this = cells['before_tree'], cells['this_tree']
        print(f'| {integrator} | {lines} x {segments} | {"free" if free else "fixed"} | '
              f'{steps} | {before[0]:.1f} / {before[1]:.1f} | {this[0]:.1f} / {this[1]:.1f} | '
              f'{this[0] / before[0]:.3f} / {this[1] / before[1]:.3f} |', flush=True)


if __name__ == '__main__':
    main()
