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
What a process that sleeps between outputs pays for waking: the same work back to back and paced.

A fixed piece of Python and numpy work (a few hundred bytecodes and forty small array sums,
nothing of this package) is done --count times back to back, then --count times at --rate on
the wall clock, sleeping between, as a live node does. Printed: its thread CPU each time,
both ways, and their ratio. On a shared virtual machine the paced work costs two to three
times as much (cold caches and a vCPU woken from halt): every part of a live node pays this
on top of its back-to-back cost (benchmarks/node_parts.py --offline paced shows it on the
node's own parts).

    python benchmarks/wake_cost.py [--rate 100] [--count 500] [--repeat 3]
"""

import argparse
import time

import numpy as np

ARRAY = np.linspace(0.0, 1.0, 150).reshape(50, 3)


def work() -> float:
    """Do the fixed piece of work; return its result (so that nothing is optimised away)."""
    total = 0.0
    for k in range(40):
        total += float((ARRAY * 1.0001 + ARRAY).sum())
        record = {'k': k, 'total': total}
        total += record['k']
    return total


def cost(count: int, rate: float) -> float:
    """Return the work's thread CPU [us] each time, done count times (rate 0: back to back)."""
    start_cpu, start = time.thread_time(), time.monotonic()
    for i in range(count):
        if rate:
            time.sleep(max(0.0, start + i / rate - time.monotonic()))
        work()
    return 1e6 * (time.thread_time() - start_cpu) / count


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--rate', type=float, default=100.0, help='paced work a second')
    parser.add_argument('--count', type=int, default=500)
    parser.add_argument('--repeat', type=int, default=3)
    args = parser.parse_args()
    print(f'| back to back [us] | paced at {args.rate:g} Hz [us] | ratio |')
    print('|---|---|---|')
    for _ in range(args.repeat):
        alone, paced = cost(args.count, 0.0), cost(args.count, args.rate)
        print(f'| {alone:.1f} | {paced:.1f} | {paced / alone:.2f} |', flush=True)


if __name__ == '__main__':
    main()
