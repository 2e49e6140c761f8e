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
Speed and accuracy of this model against MoorDyn in water, side by side, in one run.

The water cases of test/data/water/ (MoorDyn 2.7.2's input files are in its moordyn_inputs/):
the base line (A at the origin, B at (36, 0, 8), 40 m) fully submerged, 100 m below the
surface with nothing above it,

- current: wire and polyester, N 20 and 50, both ends held, a 1 m/s current across the
  line's plane switched on at t = 0 (MoorDyn's initial condition ignores the current);
- heave: the wire at N 20, fairlead heaving 1.5 m with an 8 s period after an 8 s ramp.

MoorDyn runs its initial-condition solve (timed apart, not counted), then is stepped through
its Python API (every 10 ms while the ends are held, every 1 ms with the start position and
secant velocity of the interval under heave). MoorDyn moves a coupled point on a straight
line within each Step: the kinks every 1 ms ring the stiff end segment and bias the force
it returns by 2.2 N RMS on the heave case (1.1 % of the range without drag). Under heave it
is therefore run twice: timed coupled every 1 ms, and coupled at its own step (0.1 ms, as
the reference files of test/data/water are made) for the accuracy columns. This model
starts from MoorDyn's initial node positions (so both begin in the same state), receives the
fairlead as 10 ms samples and advances in 10 ms outputs. Reported per run: the time step,
wall seconds per simulated second, real-time factor, the ratio of real-time factors (ours /
MoorDyn's), the NRMSE of |F_B| against MoorDyn's over the whole run (RMS difference / range
of MoorDyn's force, as test/test_water_reference.py measures it), and the difference of the
settled (last 10 s mean) |F_B| relative to MoorDyn's.

Then, with no peer: a 50-segment line through the surface, lying on the seabed, in a
current, with the default integrator, timed on one core.

    python benchmarks/water_vs_moordyn.py [--duration 60] [--segments 20 50]
"""

import argparse
import contextlib
import math
import os
from pathlib import Path
import shutil
import sys
import tempfile
import time

import numpy as np

from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import from_values, INTEGRATORS

REPO = Path(__file__).resolve().parent.parent
INPUTS = REPO / 'test' / 'data' / 'water' / 'moordyn_inputs'
FAIRLEAD = np.array([36.0, 0.0, 8.0])
OFFSET = np.array([0.0, 0.0, -100.0])  # our frame to MoorDyn's (surface at z = 0 there)
CURRENT = [0.0, 1.0, 0.0]
OUTPUT = 0.01
LEVEL = (0.0, 0.0, 0.0, 1.0)  # the ship's orientation: a line's fairlead is position + offset
HOLD_COUPLING = 0.01  # MoorDyn's Step while the ends are held
MOTION_COUPLING = 0.001  # ... while the fairlead moves
LINES = {  # MoorDyn's line types of these cases: d, m, EA, BA
    'wire': dict(material='steel_wire', diameter=0.040, mass_per_length=6.5,
                 axial_stiffness=1.0e8, axial_damping=6492.27),
    'polyester': dict(material='polyester', diameter=0.064, mass_per_length=2.6,
                      axial_stiffness=5.0e7, axial_damping=2903.43),
}
DTM = {20: 1e-4, 50: 5e-5}  # MoorDyn's RK2 step of these files


def push_fairlead(mooring, t, point):
    """Give a mooring of one line the ship pose that puts its fairlead at point at time t."""
    mooring.push_ship(t, np.subtract(point, mooring.lines[0].params.fairlead_offset), LEVEL)


def heave_motion(t):
    """Return the fairlead of the heave case: 1.5 m, 8 s, with an 8 s cosine ramp."""
    t = np.asarray(t, dtype=float)
    ramp = np.where(t < 8.0, 0.5 * (1.0 - np.cos(np.pi * t / 8.0)), 1.0)
    return FAIRLEAD + (1.5 * np.sin(2.0 * np.pi * t / 8.0) * ramp)[..., None] * [0, 0, 1.0]


def held(t):
    """Return the fairlead held at its place."""
    return np.broadcast_to(FAIRLEAD, np.shape(t) + (3,))


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


def run_moordyn(input_name, motion, coupling, duration):
    """
    Run one MoorDyn input file of test/data/water/moordyn_inputs.

    :returns: |F_B| at OUTPUT intervals, stepping wall seconds, init wall seconds, and
        MoorDyn's node positions after its initial condition in our frame, (N+1, 3).
    """
    import moordyn  # a benchmark dependency only
    with tempfile.TemporaryDirectory() as folder, _quiet():
        path = Path(folder) / 'line.txt'
        shutil.copy(INPUTS / f'{input_name}.txt', path)
        profile = INPUTS / f'{input_name}_current_profile.txt'
        if profile.exists():  # Currents 1 reads current_profile.txt next to the input
            shutil.copy(profile, Path(folder) / 'current_profile.txt')
        system = moordyn.Create(str(path))
        start = time.perf_counter()
        moordyn.Init(system, list(OFFSET) + list(FAIRLEAD + OFFSET), [0.0] * 6)
        init = time.perf_counter() - start
    line = moordyn.GetLine(system, 1)
    shape = np.array([moordyn.GetLineNodePos(line, i)
                      for i in range(moordyn.GetLineN(line) + 1)]) - OFFSET
    steps = int(round(duration / coupling))
    per_output = int(round(OUTPUT / coupling))
    positions = motion(np.arange(steps + 1) * coupling) + OFFSET
    force = np.empty(steps // per_output)
    start = time.perf_counter()
    for k in range(steps):
        velocity = (positions[k + 1] - positions[k]) / coupling
        f = moordyn.Step(system, list(OFFSET) + list(positions[k]),
                         [0.0, 0.0, 0.0] + list(velocity), k * coupling, coupling)
        if (k + 1) % per_output == 0:
            force[(k + 1) // per_output - 1] = math.sqrt(f[3] ** 2 + f[4] ** 2 + f[5] ** 2)
    wall = time.perf_counter() - start
    moordyn.Close(system)
    return force, wall, init, shape


def water_params(line, segments, integrator, current=(0.0, 0.0, 0.0)):
    """Parameters of a MoorDyn water case: submerged, no air, MoorDyn's coefficients."""
    return from_values(dict(
        LINES[line], segments=segments, length=40.0, bending_stiffness_ratio=0.0,
        bending_damping_ratio=0.0, air_drag_coefficient=0.0, gravity=[0.0, 0.0, -9.81],
        integrator=integrator, water_level=100.0, water_density=1025.0, air_density=0.0,
        current=list(current), normal_drag_coefficient=1.2, tangential_drag_coefficient=0.008,
        normal_added_mass_coefficient=1.0, tangential_added_mass_coefficient=0.0,
        volume_diameter=LINES[line]['diameter']))


def run_ours(params, motion, duration, shape=None):
    """|F_B| at OUTPUT intervals, wall seconds and the step of this model."""
    mooring = Mooring(single_line(params), output_interval=OUTPUT, history=math.inf)
    samples = np.arange(0.0, duration + 3 * OUTPUT, OUTPUT)
    positions = motion(samples)
    for t, p in zip(samples, positions):
        push_fairlead(mooring, float(t), p)
    mooring.start(0.0)
    if shape is not None:  # MoorDyn's initial node positions
        mooring.place_line(0, shape)
    outputs = np.arange(1, int(round(duration / OUTPUT)) + 1) * OUTPUT
    force = np.empty(len(outputs))
    start = time.perf_counter()
    for k, t in enumerate(outputs):
        mooring.advance_to(float(t))
        force[k] = mooring.output().fairlead_tensions[0]
    return force, time.perf_counter() - start, mooring.time_step


def range_error(series, reference):
    """RMS difference over the range of the reference."""
    return float(np.sqrt(np.mean((series - reference) ** 2)) / np.ptp(reference))


def compare(duration, segment_counts):
    """Print the table against MoorDyn."""
    print(f'## This model vs MoorDyn 2.7.2 in water, {duration:g} s per case, one core')
    print()
    print('| case | model | step [s] | wall s / sim s | real-time factor | vs MoorDyn | '
          'NRMSE of F_B (range) | settled F_B vs MoorDyn |')
    print('|---|---|---|---|---|---|---|---|')
    cases = [(f'current {line} N{n}', f'current_{line}_N{n}', line, n, held, HOLD_COUPLING,
              CURRENT) for line in ('wire', 'polyester') for n in segment_counts]
    cases.append(('heave wire N20 (ref)', 'heave_wire_N20_ic', 'wire', 20, heave_motion,
                  MOTION_COUPLING, (0.0, 0.0, 0.0)))
    settled = slice(-int(round(10.0 / OUTPUT)), None)
    for name, input_name, line, n, motion, coupling, current in cases:
        md_force, md_wall, md_init, shape = run_moordyn(input_name, motion, coupling,
                                                        duration)
        md_rtf = duration / md_wall
        if coupling != HOLD_COUPLING:  # the accuracy against MoorDyn coupled at its step
            md_force, _, _, _ = run_moordyn(input_name, motion, DTM[n], duration)
        print(f'| {name} | MoorDyn RK2 (init {md_init:.1f} s) | {DTM[n]:.0e} | '
              f'{md_wall / duration:.4f} | {md_rtf:.1f} | 1.0 | - | - |', flush=True)
        for integrator in INTEGRATORS:
            params = water_params(line, n, integrator, current)
            force, wall, dt = run_ours(params, motion, duration, shape)
            rtf = duration / wall
            end = np.mean(force[settled]) / np.mean(md_force[settled]) - 1.0
            print(f'| {name} | {integrator} | {dt:.1e} | {wall / duration:.4f} | '
                  f'{rtf:.1f} | {rtf / md_rtf:.1f}x | '
                  f'{100 * range_error(force, md_force):.2f} % | {100 * end:+.3f} % |',
                  flush=True)
    print()


def seabed_line(duration):
    """Real-time factor of a 50-segment line through the surface onto the seabed."""
    # examples/water_line.py's case: a 120 m wire from an anchor on the seabed, 20 m down,
    # to a fairlead 3 m above the water and 110 m away, 60 to 90 m of it lying on the
    # ground; the ship surges 4 m with a 12 s period in a 0.5 m/s current along the line
    params = from_values(dict(
        material='steel_wire', diameter=0.040, segments=50, length=120.0,
        bollard_position=[0.0, 0.0, -20.0], water_level=0.0, seabed_level=-20.0,
        current=[-0.5, 0.0, 0.0], seabed_friction=0.5))
    fairlead = np.array([110.0, 0.0, 3.0])

    def surge(t):
        t = np.asarray(t, dtype=float)
        ramp = np.minimum(t / 12.0, 1.0)
        return fairlead + (4.0 * np.sin(2.0 * np.pi * t / 12.0) * ramp)[..., None] * [1, 0, 0]

    mooring = Mooring(single_line(params), output_interval=OUTPUT, history=math.inf)
    samples = np.arange(0.0, duration + 3 * OUTPUT, 0.02)
    for t, p in zip(samples, surge(samples)):
        push_fairlead(mooring, float(t), p)
    mooring.start(0.0)
    cpu = time.process_time()
    for t in np.arange(1, int(round(duration / OUTPUT)) + 1) * OUTPUT:
        mooring.advance_to(float(t))
        out = mooring.output()
    cpu = time.process_time() - cpu
    lying = int(np.sum(out.positions[0][:, 2] < -20.0 + 0.01))
    print(f'## A 50-segment wire with water, current and seabed on (default integrator, '
          f'{params.integrator}), {duration:g} s surge, 100 Hz output')
    print()
    print('| step [s] | CPU s / sim s | real-time factor | particles on the seabed at the end |')
    print('|---|---|---|---|')
    print(f'| {mooring.time_step:.1e} | {cpu / duration:.4f} | {duration / cpu:.0f} | '
          f'{lying} of 51 |')
    print()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--duration', type=float, default=60.0)
    parser.add_argument('--segments', type=int, nargs='+', default=[20, 50],
                        choices=sorted(DTM))
    parser.add_argument('--skip-moordyn', action='store_true')
    args = parser.parse_args()
    # compile every kernel before timing anything
    for integrator in INTEGRATORS:
        run_ours(water_params('wire', 20, integrator, CURRENT), held, 0.05)
    if not args.skip_moordyn:
        compare(args.duration, args.segments)
    seabed_line(args.duration)


if __name__ == '__main__':
    main()
