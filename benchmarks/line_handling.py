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
What a make fast or a let go costs the output it comes before, in the sixteen-line berth.

The sixteen 50-segment lines of benchmarks/arrangement_speed.py at 100 Hz ship poses and
outputs, one Driver, as the mooring node drives it (its Python and kernels, not DDS), one
line (head_4) starting stowed at 40 m. Poses are taken back to back; each iteration (push a
pose, advance to its output) is timed on the wall clock. At 3 s head_4 is made fast, at
6 s head_1 is let go, at 9 s every line is let go.

A live node takes the poses every 10 ms: an iteration that takes longer delays its output
and, until the node has caught up, the ones after it. From the iterations' times the
table works out that schedule (each output done at the later of its due time and the one
before's, plus its own time) and gives, for each command, the command's own time, its
output's, and the most any output from it on is late past the median iteration's time:
the delay the command adds. The first row is the same without a command: the machine's own
noise. The let go's outputs are dearer than the others for the
physics: a line let go snaps, and the adaptive integrator takes it in improved Euler until
it is calm. The aim: no command delays an output by more than one period.

    python benchmarks/line_handling.py [--repeat 5]
"""

import argparse
import math
import os
from pathlib import Path
import sys
import time

sys.path.insert(0, str(Path(__file__).resolve().parent))
from arrangement_speed import berth, RATE, ship_pose, T0  # noqa: E402
import numpy as np  # noqa: E402
from rope_sim_ros.mooring.driver import Driver  # noqa: E402
from rope_sim_ros.params import arrangement  # noqa: E402

DURATION = 10.0
COMMANDS = {3.0: ('head_4', 'make_fast'), 6.0: ('head_1', 'let_go'), 9.0: (None, 'let_go_all')}


def setup():
    """Return the berth's arrangement, head_4 stowed (see the module docstring)."""
    values = berth('polyester')
    head = values['head_4']
    del head['pretension']
    head.update(length=40.0, start_state='stowed')
    return arrangement.from_values(values)


def run() -> tuple:
    """Return every iteration's wall time [s] and {time: (command s, text)} of one run."""
    driver = Driver(setup(), rate=RATE)
    walls, commands = [], {}
    for i in range(int(round(DURATION * RATE)) + 1):
        t = i / RATE
        if t in COMMANDS:
            name, command = COMMANDS[t]
            start = time.perf_counter()
            text = driver.command(name, command)
            commands[len(walls)] = (time.perf_counter() - start, text)
        start = time.perf_counter()
        driver.push_ship(T0 + round(t * 1e9), *ship_pose(t))
        driver.advance(math.inf, max_lag=math.inf)
        walls.append(time.perf_counter() - start)
    return np.array(walls), commands


def late(walls: np.ndarray, period: float) -> np.ndarray:
    """Return how late each output is [s] when its iteration may start every `period`."""
    done = np.empty(len(walls))
    free = 0.0  # when the node is free again
    for i, wall in enumerate(walls):
        free = max(free, i * period) + wall
        done[i] = free - i * period
    return done


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--repeat', type=int, default=3,
                        help='runs; the table gives the worst delay of each command')
    args = parser.parse_args()
    os.environ.setdefault('NUMBA_NUM_THREADS', '1')
    run()  # every kernel loaded (or compiled) before timing
    period = 1.0 / RATE
    rows = {}
    for _ in range(args.repeat):
        walls, commands = run()
        typical = float(np.median(walls[1:]))
        spent = np.zeros(len(walls))
        for i, (seconds, _) in commands.items():
            spent[i] = seconds
        lateness = late(walls + spent, period) - typical
        first = min(commands)
        quiet = float(lateness[int(RATE):first].max())  # from 1 s to the first command
        if 0 not in rows or quiet > rows[0][3]:
            rows[0] = ('(none: 1 s to the first command)', 0.0, typical, quiet, typical)
        for i, (seconds, text) in commands.items():
            following = [j for j in commands if j > i]
            delay = float(lateness[i:min(following, default=len(walls))].max())
            if i not in rows or delay > rows[i][3]:
                rows[i] = (text, seconds, walls[i], delay, typical)
    print(f'## A command before an output: sixteen lines of 50 segments, {RATE:g} Hz, one '
          f'driver, worst of {args.repeat} runs')
    print()
    print('| command | command [ms] | its output [ms] | median output [ms] | most late [ms] | '
          '/ period |')
    print('|---|---|---|---|---|---|')
    for i in sorted(rows):
        text, spent, wall, delay, typical = rows[i]
        print(f'| {text} | {1e3 * spent:.2f} | {1e3 * wall:.2f} | {1e3 * typical:.2f} | '
              f'{1e3 * delay:.2f} | {delay / period:.2f} |')


if __name__ == '__main__':
    main()
