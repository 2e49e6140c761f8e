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
What one line costs an output here against another checkout, interleaved in one process.

The line of physics_vs_moordyn.py (40 m in air, MoorDyn's drag and added mass), its fairlead
surging 2 m along the chord, a sample every 10 ms one sample ahead of the outputs, an output
every 10 ms: a ship pose in, the state advanced to the output, the output taken. Both trees'
packages are imported side by side (each under a name of its own, its compiled kernels in a
cache of their own) and take turns in blocks of 200 outputs, so that a machine shared with
other work slows both alike. Both trees take the same outputs (six surge periods in 30
rounds), and an output's cost depends on where in the surge it falls, differently in each
tree: the ratio is of their totals. A run of whole benchmarks one after the other cannot
see a 10 % difference here: their speed drifts by 20-50 % from one minute to the next.

The other tree may be the one before the one stack (commit 5f3625f: a line was a Simulator
fed fairlead points) or a later one (a Mooring of one line fed ship poses).

    git worktree add /tmp/before 5f3625f
    python benchmarks/one_line_cost.py --before /tmp/before [--segments 20 50]
        [--integrators adaptive implicit_euler improved_euler] [--rounds 30]

The first run compiles both trees' kernels into --cache (a few minutes).
"""

import argparse
from pathlib import Path
import statistics
import tempfile
import time

from two_trees import import_both

BLOCK = 200  # outputs a turn
CASES = ('polyester', 'wire', 'hmpe')  # physics_vs_moordyn.py's lines


class Line:
    """One line of one tree, stepped an output at a time; its time in three parts [s]."""

    def __init__(self, package: str, values: dict, points):
        """Start the line of `package` (a Mooring of one line, or the older Simulator)."""
        import importlib
        table = importlib.import_module(f'{package}.params.table')
        self.points = points
        self.parts = [0.0, 0.0, 0.0]  # pose in, advance, output
        try:
            mooring = importlib.import_module(f'{package}.mooring.mooring')
        except ImportError:
            simulator = importlib.import_module(f'{package}.simulator')
            self.line = simulator.Simulator(table.from_values(values), output_interval=0.01)
            self.push = lambda t, point: self.line.push_fairlead(t, point.tolist())
            self.tension = lambda out: out.fairlead_tension
        else:
            single_line = importlib.import_module(f'{package}.params.arrangement').single_line
            self.line = mooring.Mooring(single_line(table.from_values(values)),
                                        output_interval=0.01)
            offset = self.line.lines[0].params.fairlead_offset
            level = (0.0, 0.0, 0.0, 1.0)
            self.push = lambda t, point: self.line.push_ship(t, (point - offset).tolist(), level)
            self.tension = lambda out: out.fairlead_tensions[0]
        self.push(0.0, points[0])
        self.push(0.01, points[1])
        self.line.start(0.0)

    def run(self, first: int, count: int) -> float:
        """Take outputs first - 1 .. first + count - 2 (the sample one ahead); return wall s."""
        clock, parts, line = time.perf_counter, self.parts, self.line
        start = clock()
        for k in range(first, first + count):
            t0 = clock()
            self.push(k * 0.01, self.points[k])
            t1 = clock()
            line.advance_to((k - 1) * 0.01)
            t2 = clock()
            self.tension(line.output())
            t3 = clock()
            parts[0] += t1 - t0
            parts[1] += t2 - t1
            parts[2] += t3 - t2
        return clock() - start


def compare(values: dict, rounds: int) -> dict:
    """Return each tree's mean us an output, its parts, and the ratio of their totals."""
    import numpy as np
    from physics_vs_moordyn import fairlead_motion
    points = fairlead_motion(np.arange((rounds + 3) * BLOCK + 2) * 0.01)
    lines = {name: Line(name, values, points) for name in ('before_tree', 'this_tree')}
    blocks = {name: [] for name in lines}
    first = 2
    for r in range(rounds + 1):
        for name, line in (lines.items() if r % 2 else reversed(list(lines.items()))):
            seconds = line.run(first, BLOCK)
            if r:  # (the first round warms up)
                blocks[name].append(seconds / BLOCK * 1e6)
        if not r:
            for line in lines.values():
                line.parts = [0.0, 0.0, 0.0]
        first += BLOCK
    return {name: (statistics.fmean(blocks[name]),
                   [p / (rounds * BLOCK) * 1e6 for p in lines[name].parts])
            for name in lines} | {'ratio': sum(blocks['this_tree']) / sum(blocks['before_tree'])}


def main() -> None:
    """Print a table: each case, the other tree's and this tree's cost, the ratio."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--before', required=True, type=Path,
                        help='a checkout of the tree to compare with (its rope_sim_ros/)')
    parser.add_argument('--segments', type=int, nargs='+', default=[20, 50])
    parser.add_argument('--cases', nargs='+', default=['polyester', 'wire'], choices=CASES)
    parser.add_argument('--integrators', nargs='+',
                        default=['adaptive', 'implicit_euler', 'improved_euler'])
    parser.add_argument('--rounds', type=int, default=30)
    parser.add_argument('--cache', type=Path,
                        default=Path(tempfile.gettempdir()) / 'rope_sim_one_line_cost')
    args = parser.parse_args()
    import_both(parser, args.before, args.cache)  # before numba is imported
    # the benchmark's line (this tree's package under its own name beside the two)
    from physics_vs_moordyn import line_values
    print(f'## One line an output: {args.before} against this tree, interleaved in blocks of '
          f'{BLOCK} outputs, {args.rounds} rounds')
    print()
    print('| line | N | integrator | before: us an output (pose in / advance / output) '
          '| this tree | this / before |')
    print('|---|---|---|---|---|---|')
    for case in args.cases:
        for segments in args.segments:
            for integrator in args.integrators:
                result = compare(line_values(case, segments, integrator), args.rounds)
                cells = [f'{result[name][0]:.1f} ('
                         + ' / '.join(f'{p:.1f}' for p in result[name][1]) + ')'
                         for name in ('before_tree', 'this_tree')]
                print(f'| {case} | {segments} | {integrator} | {cells[0]} | {cells[1]} | '
                      f'{result["ratio"]:.2f} |', flush=True)


if __name__ == '__main__':
    main()
