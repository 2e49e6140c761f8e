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
What the waves cost a free ship: the berth's 8 lines with and without them, as a share of a core.

config/berth.yaml's ship, free, its eight lines (at the default publish_rate of 50 Hz), run by
one Driver back to back for --seconds of simulated time, three ways in turn, --repeat rounds:

- `calm`: no hydrodynamic database (constant added mass and damping), no waves;
- `memory`: the shipped database of this ship (test/data/hydro/berth_ship.nc): its
  infinite-frequency added mass and the radiation memory, no waves;
- `swell`: the same in a JONSWAP swell, Hs 1.5 m, Tp 10 s, from 30 degrees off the bow on
  the ship's starboard side (its first-order and slow-drift loads).

Printed per way: the process's CPU per simulated second (the share of one core the run would
take in real time), the median over the rounds and their range, and its ratio to `calm`.
The issue the waves came with asks that the memory's cost not rival the lines'.

    python benchmarks/waves.py [--seconds 60] [--repeat 3]
"""

import argparse
from pathlib import Path
import statistics
import sys
import time

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from rope_sim_ros.mooring.driver import Driver  # noqa: E402
from rope_sim_ros.params.arrangement import flatten, read_setup  # noqa: E402

DATABASE = REPO / 'test' / 'data' / 'hydro' / 'berth_ship.nc'
SWELL = {'spectrum': 'jonswap', 'height': 1.5, 'period': 10.0, 'direction': -0.5236,
         'seed': 1}
WAYS = {
    'calm': {},
    'memory': {'ship': {'hydrodynamics': str(DATABASE)}},
    'swell': {'ship': {'hydrodynamics': str(DATABASE)}, 'waves': SWELL},
}


def run(way: str, seconds: float) -> float:
    """Return the CPU seconds [s] of one run of this way, its set-up and start left out."""
    overrides = {'ship_mode': 'free', **WAYS[way]}
    setup = read_setup(REPO / 'config' / 'berth.yaml', flatten(overrides))
    driver = Driver(setup)
    driver.start_free(0)
    driver.outputs_until(1.0)  # the start: the kernels loaded, the first steps taken
    start = time.process_time()
    report = driver.outputs_until(1.0 + seconds)
    cpu = time.process_time() - start
    if not report.outputs or not all(p.output.finite for p in report.outputs):
        raise SystemExit(f'{way}: the run gave no finite output')
    return cpu


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--seconds', type=float, default=60.0)
    parser.add_argument('--repeat', type=int, default=3)
    args = parser.parse_args()
    run('swell', 2.0)  # compile or load what each way needs before any is timed
    shares = {way: [] for way in WAYS}
    for _ in range(args.repeat):
        for way in WAYS:
            shares[way].append(run(way, args.seconds) / args.seconds)
    calm = statistics.median(shares['calm'])
    print(f'free ship, 8 lines, {args.seconds:g} s simulated, {args.repeat} rounds '
          'alternated: CPU per simulated second (share of one core)')
    print(f'{"way":<8} {"median":>8} {"range":>17} {"vs calm":>8}')
    for way, values in shares.items():
        median = statistics.median(values)
        print(f'{way:<8} {median:8.3f} {min(values):8.3f}-{max(values):<8.3f} '
              f'{median / calm:8.2f}')


if __name__ == '__main__':
    main()
