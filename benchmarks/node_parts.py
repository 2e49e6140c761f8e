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
Where the node's time goes: the mooring (or mooring_line) node run from this tree, its parts timed.

The node runs from the source tree (not the colcon install) in a process of its own, each of
its parts wrapped to add up the main thread's CPU time it takes (time.thread_time): the node's
callbacks, the Pacer, the Driver's pose in, advance and output, the Mooring's groups, the
kernels, and the messages' encoding and publishing. It is fed 100 Hz poses for --seconds as
benchmarks/node_floor.py feeds the floor (--line: one 50-segment mooring_line on its
fairlead/tension; else the sixteen polyester lines of arrangement_speed.py on
ship/mooring_wrench only). Printed: the node's share of a core over the fed time (/proc), then
each part in microseconds of thread CPU an output, over the outputs after the first hundred.
The wrappers add about a microsecond a call; the parts nest (a part's time includes its
callees').

--offline steps the same mooring with the same poses in this process without ROS, through
the same Driver, with the same parts wrapped: back to back (what the parts cost with warm
caches, the floor of the simulation's own parts), or paced (each pose at its time on the wall
clock, sleeping between outputs as the node does). The floor of the node's I/O (a pose in,
a wrench out) is benchmarks/node_floor.py's.

    python benchmarks/node_parts.py [--line] [--seconds 15] [--offline back-to-back|paced]
"""

import argparse
import atexit
import json
import os
from pathlib import Path
import subprocess
import sys
import tempfile
import time

import installed_node

# (module, class or None, function, label), outermost first
PARTS = (
    ('ros.node', 'MooringNode', '_on_pose', 'node: pose callback'),
    ('ros.node', 'MooringNode', '_on_tick', 'node: timer callback'),
    ('ros.conversions', None, 'unit_quaternion', 'node: pose checked'),
    ('ros.node', 'MooringNode', '_publish', 'node: publish an output'),
    ('messages.encode', 'OutputEncoder', 'messages', 'node: encode its messages'),
    ('mooring.pacing', 'Pacer', 'after_pose', 'pacer: after a pose'),
    ('mooring.pacing', 'Pacer', 'tick', 'pacer: at a tick'),
    ('mooring.driver', 'Driver', 'push_ship', 'driver: ship pose in'),
    ('mooring.driver', 'Driver', 'advance', 'driver: advance'),
    ('mooring.mooring', 'Mooring', 'advance_to', 'mooring: advance_to'),
    ('mooring.ends', 'Ends', 'drive_group', 'mooring: ends driven'),
    ('mooring.group', 'Group', 'advance', 'mooring: the groups advanced'),
    ('mooring.group', 'Group', '_run', 'mooring: a group run (its kernel and Python)'),
    ('stepping.kernels', None, 'run_kernel', 'kernels: the integrator runs'),
    ('mooring.group', 'Group', '_check', 'mooring: the state checks'),
    ('mooring.driver', 'Driver', '_emit', 'driver: output taken'),
    ('mooring.outputs', None, 'mooring_output', 'mooring: output gathered'),
)
RATE = 100.0  # poses and outputs a second
FIRST = 100  # outputs before the count starts (the start, the kernels loaded)


def instrument() -> tuple:
    """
    Wrap the PARTS to add up their thread CPU; return (totals, calls, before).

    `before` is filled with the totals and calls at the FIRST-th output, so that the counts
    start after the start; totals and calls keep adding up, 'outputs' among the calls.
    """
    import importlib
    totals, calls, before = {}, {}, {}
    clock = time.thread_time

    def wrap(owner, name, label):
        function = getattr(owner, name)
        totals[label], calls[label] = 0.0, 0

        def timed(*args, **kwargs):
            start = clock()
            try:
                return function(*args, **kwargs)
            finally:
                totals[label] += clock() - start
                calls[label] += 1
        setattr(owner, name, timed)

    for module, cls, name, label in PARTS:
        try:
            module = importlib.import_module(f'rope_sim_ros.{module}')
        except ImportError:  # (offline: the node's modules need not load)
            continue
        owner = getattr(module, cls) if cls else module
        if hasattr(owner, name):
            wrap(owner, name, label)
            # a module function its callers imported by name: theirs too
            for caller in ('stepping.adaptive', 'mooring.group', 'mooring.mooring'):
                caller = importlib.import_module(f'rope_sim_ros.{caller}')
                if cls is None and getattr(caller, name, None) is not None:
                    setattr(caller, name, getattr(owner, name))
    driver = importlib.import_module('rope_sim_ros.mooring.driver').Driver
    emit = driver._emit

    def counted_emit(self, *args):
        calls['outputs'] = calls.get('outputs', 0) + 1
        if calls['outputs'] == FIRST:
            before.update(totals=dict(totals), calls=dict(calls))
        return emit(self, *args)
    driver._emit = counted_emit
    return totals, calls, before


def counted(totals: dict, calls: dict, before: dict) -> dict:
    """Return the totals and calls since `before`."""
    return {'totals': {k: v - before['totals'][k] for k, v in totals.items()},
            'calls': {k: v - before['calls'].get(k, 0) for k, v in calls.items()}}


def child(line: bool, out: str) -> None:
    """Run the node with its parts wrapped; write their times to `out` as it ends."""
    import importlib
    totals, calls, before = instrument()

    def write():
        if not before or Path(out).exists():
            return
        Path(out).write_text(json.dumps(counted(totals, calls, before)))
    atexit.register(write)
    node = importlib.import_module('rope_sim_ros.ros.node')
    sys.argv = ['node'] + sys.argv[4:]
    try:
        (node.main_line if line else node.main_mooring)()
    finally:
        write()


def offline(line: bool, seconds: float, paced: bool) -> None:
    """
    Step the same mooring with the same poses in this process, without ROS; print its parts.

    Back to back, or paced: each pose taken at its time on the wall clock, sleeping between
    outputs as the node does.
    """
    import math
    import arrangement_speed
    sys.path.insert(0, str(installed_node.REPO))
    from rope_sim_ros.mooring.driver import Driver
    from rope_sim_ros.params.arrangement import from_values, read_setup
    if line:
        setup = read_setup(installed_node.REPO / 'config' / 'mooring_line.yaml',
                           {'publish_rate': RATE, 'segments': 50})

        def pose(t):
            return [32.0 + 0.5 * math.sin(2.0 * math.pi * 0.16 * t), 12.0, 6.0], [0, 0, 0, 1]
    else:
        setup = from_values({**arrangement_speed.berth('polyester'), 'publish_rate': RATE})
        pose = arrangement_speed.ship_pose
    totals, calls, before = instrument()
    driver = Driver(setup, rate=RATE)
    cpu = start = None
    steps = int(round(seconds * RATE))
    for i in range(steps + 1):
        t = i / RATE
        if i == FIRST:
            cpu, start = time.process_time(), time.monotonic() - t
        if paced and start is not None:
            time.sleep(max(0.0, start + t - time.monotonic()))
        position, orientation = pose(t)
        driver.push_ship(arrangement_speed.T0 + round(t * 1e9), position, orientation)
        driver.advance(math.inf, max_lag=math.inf)
    share = (time.process_time() - cpu) / ((steps - FIRST) / RATE)
    report(f'{"mooring_line" if line else "mooring, 16 lines"} offline, '
           f'{"paced" if paced else "back to back"}: {100 * share:.1f} % of one core over '
           f'{(steps - FIRST) / RATE:g} s simulated', counted(totals, calls, before))


def report(title: str, data: dict) -> None:
    """Print the parts' thread CPU an output."""
    outputs = data['calls'].pop('outputs')
    print(f'{title}; thread CPU an output over {outputs} outputs:')
    for label, total in data['totals'].items():
        if data['calls'][label]:
            print(f'  {label:40s} {1e6 * total / outputs:7.1f} us ({data["calls"][label]} '
                  'calls)')


def parent(line: bool, seconds: float) -> None:
    """Start the node, feed it, and print its parts."""
    from geometry_msgs.msg import Wrench, WrenchStamped
    import yaml
    import arrangement_speed
    import line_node_cpu
    os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % 101 + 1))
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    folder = Path(tempfile.mkdtemp())
    out = folder / 'parts.json'
    if line:
        args = ['--ros-args', '--params-file',
                str(installed_node.REPO / 'config' / 'mooring_line.yaml'),
                '-p', f'publish_rate:={RATE}', '-p', 'segments:=50']
        output, cls, topic = 'fairlead/tension', Wrench, 'fairlead/pose'
        place = line_node_cpu._place_fairlead
    else:
        params = folder / 'berth16.yaml'
        params.write_text(yaml.safe_dump({'mooring': {'ros__parameters': {
            **arrangement_speed.berth('polyester'), 'publish_rate': RATE}}}))
        args = ['--ros-args', '--params-file', str(params)]
        output, cls, topic = 'ship/mooring_wrench', WrenchStamped, 'ship/pose'
        place = arrangement_speed._place_ship
    env = dict(os.environ, PYTHONPATH=str(installed_node.REPO))
    node = subprocess.Popen([sys.executable, __file__, 'child', 'line' if line else 'ship',
                             str(out), *args], env=env, stdin=subprocess.DEVNULL)
    result = installed_node.feed(node, output, cls, topic, seconds, RATE, place)
    report(f'{"mooring_line" if line else "mooring, 16 lines"}: {100 * result["cpu"]:.1f} % '
           f'of one core, {result["outputs"]:.1f} outputs a second',
           json.loads(out.read_text()))


def main():
    if len(sys.argv) > 1 and sys.argv[1] == 'child':
        child(sys.argv[2] == 'line', sys.argv[3])
        return
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--line', action='store_true', help='one mooring_line node')
    parser.add_argument('--seconds', type=float, default=15.0)
    parser.add_argument('--offline', choices=('back-to-back', 'paced'),
                        help='the same mooring and poses stepped in this process, no ROS')
    args = parser.parse_args()
    if args.offline:
        offline(args.line, args.seconds, args.offline == 'paced')
    else:
        parent(args.line, args.seconds)


if __name__ == '__main__':
    main()
