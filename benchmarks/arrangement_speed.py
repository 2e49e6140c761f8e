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
What a whole arrangement costs: sixteen lines of 50 segments at 100 Hz output.

A VLCC-sized ship (fairleads along 320 m of its port side, 15 m above the water) on sixteen
lines to a quay: four head lines, two forward breasts, two forward springs, two aft springs,
two aft breasts, four stern lines, each at 10 % of its MBL. The ship surges 0.5 m (30 s
period), sways 0.3 m (45 s) and yaws 0.002 rad (60 s); its pose comes at 100 Hz, the outputs
(every line's particles and end forces, the total wrench) at 100 Hz.

Two sets of lines: sixteen 64 mm polyester lines, and a mix (64 mm polyester head and stern
lines, 64 mm nylon breasts, 44 mm HMPE springs, whose stiffness asks for a shorter step).
For each, CPU seconds per simulated second (one core = 100 %) of:

- the mooring's simulation as its node runs it (mooring.driver.Driver: every line in one
  process, one kernel call per step group);
- the same sixteen lines as sixteen single-line drivers (a Driver of a mooring of one line,
  params.arrangement.single_line, each) in one process, fed the same ship poses: what
  sixteen mooring_line nodes simulate, without their ROS overhead;
- MoorDyn 2.7.2 with the same sixteen lines in one system (its RK2 at a quarter of the
  stiffest line's segment wave time, coupled every 10 ms), over a shorter run.

Then the node itself (`--node`, needs `make build`): the installed mooring executable fed
the ship pose at 100 Hz for --node-seconds of wall time, its process CPU read from
/proc, and the outputs it delivered. Twice: with ship/mooring_wrench subscribed only (a ship
simulator: the node builds no output nobody takes), and with every output subscribed (every
line's topics, the world wrench and the markers: a Foxglove session showing it all).

    python benchmarks/arrangement_speed.py [--duration 60] [--moordyn-duration 5] [--node]
        [--integrator adaptive] [--paced] [--repeat 1]

--paced takes the poses at their times on the wall clock, as a live node does, instead of
back to back. On a shared VM a process that sleeps between outputs finds its caches cold at
each wake-up and spends more CPU on the same work.
"""

import argparse
import contextlib
import math
import os
from pathlib import Path
import sys
import tempfile
import time

import installed_node
import numpy as np
from rope_sim_ros.model.frames import pose_point
from rope_sim_ros.mooring.driver import Driver
from rope_sim_ros.params import arrangement
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import SPECS

RATE = 100.0  # ship poses and outputs per second
SEGMENTS = 50
SHIP_Y = -28.5  # centreline off the quay face (beam 55 m, fenders 1 m)
T0 = 1_000_000_000
# (group, fairlead x [m] of the first, bollard x offset from it [m], count)
GROUPS = (('head', 150.0, 60.0, 4), ('breast_fwd', 120.0, 5.0, 2),
          ('spring_fwd', 80.0, -45.0, 2), ('spring_aft', -80.0, 45.0, 2),
          ('breast_aft', -120.0, -5.0, 2), ('stern', -150.0, -60.0, 4))
MATERIALS = {
    'polyester': lambda group: ('polyester', 0.064),
    'mixed': lambda group: (('nylon', 0.064) if 'breast' in group else
                            ('hmpe', 0.044) if 'spring' in group else ('polyester', 0.064)),
}
MBL_FRACTION = 0.10


def berth(kind: str) -> dict:
    """Return the sixteen lines' parameter values (see the module docstring)."""
    from rope_sim_ros.params.materials import load_materials
    library = load_materials()
    lines = {}
    for group, x, dx, count in GROUPS:
        for i in range(count):
            material, diameter = MATERIALS[kind](group)
            mbl = library.properties(material, diameter).mbl
            shift = (i - (count - 1) / 2.0)
            lines[f'{group}_{i + 1}'] = dict(
                material=material, diameter=diameter, segments=SEGMENTS,
                fairlead_offset=[x + 3.0 * shift, 27.0, 15.0],
                bollard_position=[x + dx + 6.0 * shift, 18.0 if 'breast' in group else 4.0,
                                  3.5],
                pretension=round(MBL_FRACTION * mbl, 0))
    return {'lines': list(lines), **lines}


def ship_pose(t: float):
    """Return the ship's (position, quaternion (x, y, z, w)) at t [s]."""
    yaw = 0.002 * math.sin(2.0 * math.pi * t / 60.0)
    return ([0.5 * math.sin(2.0 * math.pi * t / 30.0),
             SHIP_Y + 0.3 * math.sin(2.0 * math.pi * t / 45.0), 0.0],
            [0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)])


def run_mooring(values: dict, duration: float, paced: bool = False) -> tuple:
    """
    Return CPU seconds of the arrangement over `duration`, its driver and outputs.

    :param paced: take each pose at its time on the wall clock, as a live node does.
    """
    driver = Driver(arrangement.from_values(values), rate=RATE)
    outputs = 0
    cpu = 0.0
    for i in range(int(round(duration * RATE)) + 1):
        t = i / RATE
        position, orientation = ship_pose(t)
        if i == 1:  # after the start (the pretensions' lengths, the ropes at rest)
            cpu, start = time.process_time(), time.monotonic() - t
        if paced and i:
            _wait_until(start + t)
        driver.push_ship(T0 + round(t * 1e9), position, orientation)
        outputs += len(driver.advance(math.inf, max_lag=math.inf).outputs)
    return time.process_time() - cpu, driver, outputs


def run_separate(setup, duration: float, paced: bool = False) -> float:
    """
    Return CPU seconds of the same lines as single-line drivers, each fed the ship's poses.

    Each line's fairlead is the pose ⊕ its fairlead_offset, the very point the mooring's
    driver gives it; its length the one the mooring chose for its pretension.
    """
    drivers = [Driver(single_line(line.params), rate=RATE) for line in setup.lines]
    cpu = 0.0
    for i in range(int(round(duration * RATE)) + 1):
        t = i / RATE
        position, orientation = ship_pose(t)
        if i == 1:
            cpu, start = time.process_time(), time.monotonic() - t
        if paced and i:
            _wait_until(start + t)
        for driver in drivers:
            driver.push_ship(T0 + round(t * 1e9), position, orientation)
            driver.advance(math.inf, max_lag=math.inf)
    return time.process_time() - cpu


def _wait_until(wall: float) -> None:
    """Sleep until time.monotonic() reaches `wall` (at once if it has)."""
    time.sleep(max(0.0, wall - time.monotonic()))


MOORDYN_HEAD = """--------------------- MoorDyn Input File ------------------------------------
sixteen lines of a berth (rope_sim_ros benchmarks/arrangement_speed.py)
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam     Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)      (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
"""


@contextlib.contextmanager
def _quiet():
    """Silence MoorDyn's console output (it prints from C++, below sys.stdout)."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, 'w') as null:
        os.dup2(null.fileno(), 1)
        try:
            yield
        finally:
            os.dup2(saved, 1)
            os.close(saved)


def run_moordyn(driver: Driver, duration: float) -> tuple:
    """Return MoorDyn's wall seconds over `duration`, its init seconds and its step."""
    import moordyn  # a benchmark dependency only
    lines = driver.mooring.lines  # (their lengths the ones chosen for their pretensions)
    depth = np.array([0.0, 0.0, -100.0])  # MoorDyn's water surface is z = 0: lift the air
    types, points, rows = [], [], []
    position, orientation = ship_pose(0.0)
    for k, line in enumerate(lines):
        p = line.props
        types.append(f'type{k} {p.diameter} {p.mass_per_length} {p.axial_stiffness} '
                     f'{p.axial_damping} 0.0 {p.normal_drag} {p.normal_added_mass} '
                     f'{p.tangential_drag} {p.tangential_added_mass}')
        bollard = np.asarray(line.params.bollard_position) + depth
        fairlead = pose_point(position, orientation, line.params.fairlead_offset).point + depth
        points.append(f'{2 * k + 1} Fixed {bollard[0]} {bollard[1]} {bollard[2]} 0 0 0 0')
        points.append(f'{2 * k + 2} Coupled {fairlead[0]} {fairlead[1]} {fairlead[2]} 0 0 0 0')
        rows.append(f'{k + 1} type{k} {2 * k + 1} {2 * k + 2} {p.length} {p.segments} -')
    step = min(0.25 * line.props.segment_length
               * math.sqrt(line.props.mass_per_length / line.props.axial_stiffness)
               for line in lines)
    step = float(f'{step:.1e}')
    text = (MOORDYN_HEAD + '\n'.join(types) + '\n'
            '---------------------- POINT PROPERTIES --------------------------------\n'
            'ID    Type      X       Y       Z       Mass    Volume      CdA    Ca\n'
            '(#)   (-)       (m)     (m)     (m)     (kg)    (m^3)       (m^2)  (-)\n'
            + '\n'.join(points) + '\n'
            '---------------------- LINES ----------------------------------------\n'
            'ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs\n'
            '(#)  (name)     (#)      (#)      (m)       (-)      (-)\n'
            + '\n'.join(rows) + '\n'
            '---------------------- OPTIONS -----------------------------------------\n'
            f'0 writeLog\n{step} dtM\n9.81 g\n1.225 WtrDnsty\n1000 WtrDpth\nRK2 tScheme\n'
            '0 ICgenDynamic\n1 disableOutput\n1 disableOutTime\n'
            '------------------------- need this line --------------------------------------\n')
    with tempfile.TemporaryDirectory() as folder, _quiet():
        path = Path(folder) / 'berth.txt'
        path.write_text(text)
        system = moordyn.Create(str(path))

        def fairleads(t):
            position, orientation = ship_pose(t)
            return [c for line in lines for c in
                    pose_point(position, orientation, line.params.fairlead_offset).point + depth]

        start = time.perf_counter()
        moordyn.Init(system, fairleads(0.0), [0.0] * (3 * len(lines)))
        init = time.perf_counter() - start
        coupling = 1.0 / RATE
        start = time.perf_counter()
        for k in range(int(round(duration * RATE))):
            here = np.array(fairleads(k * coupling))
            there = np.array(fairleads((k + 1) * coupling))
            moordyn.Step(system, list(here), list((there - here) / coupling), k * coupling,
                         coupling)
        wall = time.perf_counter() - start
        moordyn.Close(system)
    return wall, init, step


def node_run(values: dict, seconds: float, every_output: bool,
             late_stamps: bool = False) -> dict:
    """
    Run the installed mooring node on the lines, fed 100 Hz ship poses for `seconds`.

    :param every_output: subscribe to every output, not only ship/mooring_wrench (raw: the
        messages are not deserialised here, so this process takes less of the other core).

    :returns: its CPU share while fed, the outputs received and the poses sent.
    """
    from geometry_msgs.msg import PoseArray, Wrench, WrenchStamped
    from std_msgs.msg import Float64
    from visualization_msgs.msg import MarkerArray
    import yaml
    with tempfile.TemporaryDirectory() as folder:
        params = Path(folder) / 'berth16.yaml'
        params.write_text(yaml.safe_dump(
            {'mooring': {'ros__parameters': {**values, 'publish_rate': RATE}}}))
        node = installed_node.start('mooring', ['--ros-args', '--params-file', str(params)])
        also = []
        if every_output:
            types = {'rope/particles': PoseArray, 'fairlead/tension': Wrench,
                     'bollard/tension': Wrench, 'fairlead/peak_tension': Float64,
                     'bollard/peak_tension': Float64, 'winch/length': Float64}
            also = [(f'{name}/{relative}', cls) for name in values['lines']
                    for relative, cls in types.items()]
            also += [('ship/mooring_wrench_world', WrenchStamped),
                     ('mooring/markers', MarkerArray)]
        return installed_node.feed(node, 'ship/mooring_wrench', WrenchStamped, 'ship/pose',
                                   seconds, RATE, _place_ship, late_stamps, also)


def _place_ship(pose, t: float) -> None:
    """Set a geometry_msgs/Pose to the ship's pose at t [s]."""
    position, orientation = ship_pose(t)
    pose.position.x, pose.position.y, pose.position.z = position
    (pose.orientation.x, pose.orientation.y, pose.orientation.z,
     pose.orientation.w) = orientation


def _percent(shares: list) -> str:
    """Return runs' CPU shares of one core in % as the median (and the range of several)."""
    spread = f' ({100 * min(shares):.1f}-{100 * max(shares):.1f})' if len(shares) > 1 else ''
    return f'{100 * float(np.median(shares)):.1f}{spread}'


def _cells(shares: list) -> str:
    """Return a row's CPU s / sim s and % of one core cells."""
    return f'{float(np.median(shares)):.4f} | {_percent(shares)}'


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--duration', type=float, default=60.0)
    parser.add_argument('--moordyn-duration', type=float, default=5.0)
    parser.add_argument('--skip-moordyn', action='store_true')
    parser.add_argument('--integrator', default=SPECS['integrator'].default,
                        help="every line's integrator (default: the parameter's, "
                        f"{SPECS['integrator'].default})")
    parser.add_argument('--paced', action='store_true',
                        help='take the poses at 100 Hz of wall time, as a live node does '
                        '(the process sleeps between them), not back to back')
    parser.add_argument('--repeat', type=int, default=1,
                        help='run each driver row this many times and print the median, with '
                        'the range (on a shared machine one run can move by 10-20 %%)')
    parser.add_argument('--node', action='store_true', help='also time the mooring node')
    parser.add_argument('--node-seconds', type=float, default=30.0)
    parser.add_argument('--late-stamps', action='store_true',
                        help='stamp each ship pose when sent, a millisecond or two after the '
                        'time it is the pose of (see benchmarks/installed_node.py feed)')
    args = parser.parse_args()
    os.environ.setdefault('NUMBA_NUM_THREADS', '1')
    run_mooring(berth('mixed'), 0.1)  # every kernel loaded (or compiled) before timing
    print(f'## Sixteen lines of {SEGMENTS} segments, {RATE:g} Hz ship poses and outputs, '
          f'{args.duration:g} s simulated, one process')
    print()
    print('| lines | model | steps [ms] | kernel calls per output | CPU s / sim s | '
          '% of one core |')
    print('|---|---|---|---|---|---|')
    for kind in MATERIALS:
        shares = []
        for _ in range(args.repeat):
            cpu, driver, outputs = run_mooring(dict(berth(kind), integrator=args.integrator),
                                               args.duration, args.paced)
            # the start's and one per period, the last pose's held back (one pose behind)
            assert outputs == int(round(args.duration * RATE)), outputs
            shares.append(cpu / args.duration)
        mooring = driver.mooring
        steps = ', '.join(f'{1e3 * group.step:.2f}' for group in mooring.groups)
        paced = ', paced' if args.paced else ''
        print(f'| {kind} | mooring (one driver){paced} | {steps} | {mooring.kernel_calls} | '
              f'{_cells(shares)} |', flush=True)
        shares = [run_separate(driver.arrangement, args.duration, args.paced) / args.duration
                  for _ in range(args.repeat)]
        print(f'| {kind} | 16 single-line drivers{paced} | {steps} | 16 | {_cells(shares)} |',
              flush=True)
        if not args.skip_moordyn:
            wall, init, step = run_moordyn(driver, args.moordyn_duration)
            print(f'| {kind} | MoorDyn 2.7.2 RK2, {args.moordyn_duration:g} s (init '
                  f'{init:.1f} s) | {1e3 * step:.3f} | 100 | {wall / args.moordyn_duration:.4f} | '
                  f'{100 * wall / args.moordyn_duration:.1f} |', flush=True)
    print()
    if args.node:
        for kind, every_output in ((kind, every) for kind in MATERIALS for every in (0, 1)):
            results = [node_run(dict(berth(kind), integrator=args.integrator),
                                args.node_seconds, every_output, args.late_stamps)
                       for _ in range(args.repeat)]
            taken = 'every output' if every_output else 'ship/mooring_wrench only'
            share = _percent([result['cpu'] for result in results])
            print(f'mooring node, {kind}, {taken} subscribed: {share} % of one core while '
                  f'fed {RATE:g} Hz ship poses for {args.node_seconds:g} s; at least '
                  f'{min(result["outputs"] for result in results):.1f} outputs per second '
                  f'received ({results[0]["sent"]} poses sent a run)', flush=True)


if __name__ == '__main__':
    main()
