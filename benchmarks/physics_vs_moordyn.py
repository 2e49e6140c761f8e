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
Speed and accuracy of this model against MoorDyn, side by side, in one run.

The reference dynamic case of test/data (a 40 m line in air, bollard at the
origin, fairlead at (36, 0, 8) surging 2 m along the chord with a 10 s period after a 10 s
ramp), for polyester (the reference), steel wire (d 40 mm, EA 1e8) and HMPE (MoorPy 48 mm),
N = 20, 50, 100. Both models get the same motion, each through its own interface:
MoorDyn is stepped through its Python API with the start position and secant velocity of
each interval; this model receives the motion as 10 ms samples (the rows of the reference
CSV; it interpolates them with a cubic spline) and advances in 10 ms outputs.

MoorDyn moves a coupled point on a straight line within each Step, so its fairlead's
velocity jumps at every coupling step and the stiff end segment rings; Step returns the
force at the same phase of that ringing every time. Coupled every 1 ms, that biases its
fairlead force by up to a few per cent of the swing on these stiff lines (HMPE N 20:
2.84 % NRMSE against this model, 0.12 % when MoorDyn is coupled at its own step). So
MoorDyn runs twice: timed coupled every 1 ms (its speed as one would use it; coupling
at its step costs it twice the wall time in Python calls), and coupled at its own step for
the accuracy columns.

Reported per run: the time step, wall seconds per simulated second, real-time factor, the
ratio of real-time factors (ours / MoorDyn's), and the NRMSE of the fairlead force against
MoorDyn's over t = 10..60 s (RMS difference / RMS of MoorDyn's force about its mean).
MoorDyn's initial-condition solve is timed apart and not counted.

Then, with no peer: every preset at N = 50 (the default integrator), eight lines of an
arrangement stepped in one process at 100 Hz output, and per integrator the snap loads of a
jerked line and of a payload caught after falling slack beside its speed in ship motion.

    python benchmarks/physics_vs_moordyn.py [--duration 60] [--segments 20 50 100]
"""

import argparse
import contextlib
import csv
import math
import os
from pathlib import Path
import sys
import tempfile
import time

import numpy as np

from rope_sim_ros.model.rope import critical_axial_damping
from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.materials import load_materials
from rope_sim_ros.params.table import from_values, INTEGRATORS, MATERIALS

FAIRLEAD = np.array([36.0, 0.0, 8.0])
CHORD = FAIRLEAD / np.linalg.norm(FAIRLEAD)
LENGTH = 40.0
AIR = 1.225
GRAVITY = 9.81
COUPLING = 0.001  # MoorDyn's coupling step
SAMPLES = 0.01  # our input samples
OUTPUT = 0.01
LEVEL = (0.0, 0.0, 0.0, 1.0)  # the ship's orientation: a line's fairlead is position + offset


def _case(name):
    """Diameter, mass per length, EA and BA of a benchmark line."""
    if name == 'polyester':
        return 0.064, 2.6, 5.0e7, 2903.43
    if name == 'wire':
        return 0.040, 6.5, 1.0e8, 6492.27
    props = load_materials().properties('hmpe', 0.048)
    ba = critical_axial_damping(LENGTH, props.mass_per_length, props.axial_stiffness)
    return 0.048, props.mass_per_length, props.axial_stiffness, ba


def push_fairlead(mooring, t, point):
    """Give a mooring of one line the ship pose that puts its fairlead at point at time t."""
    mooring.push_ship(t, np.subtract(point, mooring.lines[0].params.fairlead_offset), LEVEL)


def fairlead_motion(t):
    """Return the reference motion: 2 m along the chord, 10 s period, 10 s ramp."""
    t = np.asarray(t, dtype=float)
    ramp = np.where(t < 10.0, 0.5 * (1.0 - np.cos(np.pi * t / 10.0)), 1.0)
    return FAIRLEAD + (2.0 * np.sin(2.0 * np.pi * t / 10.0) * ramp)[..., None] * CHORD


def line_values(case, segments, integrator) -> dict:
    """Return the parameters of a benchmark line: MoorDyn's line in air."""
    diameter, mass, ea, ba = _case(case)
    # MoorDyn's coefficients on one diameter (drag, buoyancy, added mass)
    return dict(
        segments=segments, length=LENGTH, diameter=diameter, mass_per_length=mass,
        axial_stiffness=ea, axial_damping=ba, bending_stiffness_ratio=0.0,
        bending_damping_ratio=0.0, integrator=integrator, gravity=[0.0, 0.0, -GRAVITY],
        air_density=AIR, normal_drag_coefficient=1.2, tangential_drag_coefficient=0.008,
        normal_added_mass_coefficient=1.0, tangential_added_mass_coefficient=0.0,
        volume_diameter=diameter)


def run_ours(case, segments, integrator, duration):
    """Fairlead force magnitudes at 100 Hz, wall seconds and the step of this model."""
    params = from_values(line_values(case, segments, integrator))
    mooring = Mooring(single_line(params), output_interval=OUTPUT)
    samples = np.arange(0.0, duration + 2 * SAMPLES, SAMPLES)
    positions = fairlead_motion(samples)
    outputs = np.arange(OUTPUT, duration + 1e-9, OUTPUT)
    push_fairlead(mooring, 0.0, positions[0])
    mooring.start(0.0)
    force = np.empty(len(outputs))
    pushed = 1
    start = time.perf_counter()
    for k, t in enumerate(outputs):
        # samples arrive as in a live stream: up to one sample ahead of the output
        while pushed < len(samples) and samples[pushed] <= t + SAMPLES + 1e-12:
            push_fairlead(mooring, samples[pushed], positions[pushed])
            pushed += 1
        mooring.advance_to(t)
        force[k] = mooring.output().fairlead_tensions[0]
    return force, time.perf_counter() - start, mooring.time_step


MOORDYN_INPUT = """--------------------- MoorDyn Input File ------------------------------------
benchmark line in air (rope_sim_ros benchmarks/physics_vs_moordyn.py)
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam     Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)      (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
line       {d}      {m}        {ea}       {ba}        0.0        1.2    1      0.008   0
---------------------- POINT PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass    Volume      CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)    (m^3)       (m^2)  (-)
1     Coupled   0.0     0.0     -100    0.0     0.0         0.0    0.0
2     Coupled   36      0.0     -92     0.0     0.0         0.0    0.0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)     (#)      (#)      (m)       (-)      (-)
1    line       1        2        40        {n}      -
---------------------- OPTIONS -----------------------------------------
0             writeLog      no log file
{dtm}         dtM           coupling/model time step (s)
9.81          g             gravity (m/s^2)
1.225         WtrDnsty      fluid density: air (kg/m^3)
1000          WtrDpth       depth (m): seabed far below the line
RK2           tScheme       time integration scheme (MoorDyn default)
1             ICgenDynamic  1 = legacy dynamic relaxation IC
1000          CdScaleIC     drag scale factor during IC
60            TmaxIC        max IC time (s)
1             dtIC          IC convergence interval (s)
1e-07         threshIC      IC convergence threshold (-)
1             disableOutput no console output while stepping
1             disableOutTime no console time print
------------------------- need this line --------------------------------------
"""


def moordyn_step(case, segments):
    """
    Choose the RK2 step of MoorDyn: a quarter of an axial wave's segment crossing time.

    Its automatic (CFL) step blew up on these stiff lines (test/data/README.md); a quarter
    of l0 sqrt(m/EA) matches the largest stable steps found there, rounded down.
    """
    _, mass, ea, _ = _case(case)
    step = 0.25 * LENGTH / segments * math.sqrt(mass / ea)
    return float(f'{step:.0e}') if f'{step:.0e}'[0] == '1' else float(f'{step:.1e}')


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


def fine_coupling(case, segments):
    """Return the largest coupling step at most MoorDyn's dtM that divides OUTPUT."""
    return OUTPUT / math.ceil(OUTPUT / moordyn_step(case, segments) - 1e-9)


def run_moordyn(case, segments, duration, coupling=COUPLING):
    """Fairlead force magnitudes at 100 Hz, stepping and init wall seconds, dtM."""
    import moordyn  # a benchmark dependency only
    diameter, mass, ea, ba = _case(case)
    dtm = moordyn_step(case, segments)
    offset = np.array([0.0, 0.0, -100.0])
    with tempfile.TemporaryDirectory() as folder, _quiet():
        path = Path(folder) / 'line.txt'
        path.write_text(MOORDYN_INPUT.format(d=diameter, m=mass, ea=ea, ba=ba, n=segments,
                                             dtm=dtm))
        system = moordyn.Create(str(path))
        start = time.perf_counter()
        moordyn.Init(system, list(offset) + list(FAIRLEAD + offset), [0.0] * 6)
        init = time.perf_counter() - start
    steps = int(round(duration / coupling))
    per_output = int(round(OUTPUT / coupling))
    positions = fairlead_motion(np.arange(steps + 1) * coupling) + offset
    force = np.empty(steps // per_output)
    start = time.perf_counter()
    for k in range(steps):
        velocity = (positions[k + 1] - positions[k]) / coupling
        # MoorDyn moves a coupled point from the position given with the velocity given
        f = moordyn.Step(system, list(offset) + list(positions[k]),
                         [0.0, 0.0, 0.0] + list(velocity), k * coupling, coupling)
        if (k + 1) % per_output == 0:
            force[(k + 1) // per_output - 1] = math.sqrt(f[3] ** 2 + f[4] ** 2 + f[5] ** 2)
    wall = time.perf_counter() - start
    moordyn.Close(system)
    return force, wall, init, dtm


def nrmse(series, reference):
    """RMS difference over the RMS of the reference about its mean."""
    return float(np.sqrt(np.mean((series - reference) ** 2)) / np.std(reference))


def compare(duration, segment_counts):
    """Print the table against MoorDyn."""
    print(f'## This model vs MoorDyn 2.7.2, {duration:g} s of the reference motion, one core')
    print()
    print('| line | N | model | step [s] | wall s / sim s | real-time factor | '
          'vs MoorDyn | NRMSE vs MoorDyn | NRMSE vs improved_euler |')
    print('|---|---|---|---|---|---|---|---|---|')
    window = slice(int(round(10.0 / OUTPUT)) - 1, None)
    for case in ('polyester', 'wire', 'hmpe'):
        for segments in segment_counts:
            _, md_wall, md_init, dtm = run_moordyn(case, segments, duration)
            md_rtf = duration / md_wall
            # the accuracy against MoorDyn coupled at its own step (see the module's doc)
            md_force, _, _, _ = run_moordyn(case, segments, duration,
                                            fine_coupling(case, segments))
            print(f'| {case} | {segments} | MoorDyn RK2 (init {md_init:.1f} s) | {dtm:.0e} | '
                  f'{md_wall / duration:.4f} | {md_rtf:.1f} | 1.0 | - | - |', flush=True)
            # improved_euler at its stability-limited step (15-50x below the implicit one) is
            # this model's converged reference
            reference = None
            for integrator in ('improved_euler', 'implicit_euler', 'adaptive'):
                force, wall, dt = run_ours(case, segments, integrator, duration)
                rtf = duration / wall
                error = nrmse(force[window], md_force[window])
                own = '-' if reference is None else \
                    f'{100 * nrmse(force[window], reference[window]):.2f} %'
                reference = force if reference is None else reference
                print(f'| {case} | {segments} | {integrator} | {dt:.1e} | '
                      f'{wall / duration:.4f} | {rtf:.1f} | {rtf / md_rtf:.1f}x | '
                      f'{100 * error:.2f} % | {own} |', flush=True)
    print()


def surge_params(material, segments=50):
    """Make a preset line at 64 mm with the default integrator."""
    return from_values(dict(material=material, segments=segments))


def run_surge(moorings, duration):
    """
    Drive moorings of one line with a 2 m, 8 s surge (50 Hz samples, 100 Hz outputs); CPU s.

    Each sample is given two sample periods ahead of the outputs: the cubic end curve between
    two samples needs the one after them, and fed just in time every new sample bent the curve
    the line was already on, a jump of the end's velocity every 20 ms that set off an axial
    wave (the adaptive integrator rightly took them for snaps).
    """
    samples = np.arange(0.0, duration + 0.05, 0.02)
    surge = 2.0 * np.sin(2.0 * np.pi * samples / 8.0) * np.minimum(samples / 8.0, 1.0)
    for mooring, fairlead in moorings:
        push_fairlead(mooring, 0.0, fairlead)
        mooring.start(0.0)
    pushed = 1
    cpu = time.process_time()
    for t in np.arange(OUTPUT, duration + 1e-9, OUTPUT):
        while pushed < len(samples) and samples[pushed] <= t + 0.04 + 1e-9:
            for mooring, fairlead in moorings:
                push_fairlead(mooring, samples[pushed], fairlead + [surge[pushed], 0.0, 0.0])
            pushed += 1
        for mooring, _ in moorings:
            mooring.advance_to(t)
            mooring.output()
    return time.process_time() - cpu


def presets(duration):
    """Real-time factor of every preset at N = 50."""
    print(f'## Every preset at N = 50 (64 mm, default integrator), {duration:g} s surge, '
          '100 Hz output')
    print()
    print('| material | step [s] | CPU s / sim s | real-time factor |')
    print('|---|---|---|---|')
    for material in MATERIALS:
        mooring = Mooring(single_line(surge_params(material)), output_interval=OUTPUT)
        cpu = run_surge([(mooring, FAIRLEAD)], duration)
        print(f'| {material} | {mooring.time_step:.1e} | {cpu / duration:.4f} | '
              f'{duration / cpu:.0f} |', flush=True)
    print()


ARRANGEMENT = (  # (name, material, bollard, fairlead): one ship's lines, 50 segments each
    ('head line', 'polyester', (-60.0, 20.0, 2.0), (-40.0, 8.0, 8.0)),
    ('forward breast', 'nylon', (-20.0, 25.0, 2.0), (-20.0, 8.0, 8.0)),
    ('forward spring', 'hmpe', (-5.0, 22.0, 2.0), (-30.0, 8.0, 8.0)),
    ('forward spring 2', 'steel_wire', (0.0, 22.0, 2.0), (-25.0, 8.0, 8.0)),
    ('aft spring', 'hmpe', (5.0, 22.0, 2.0), (30.0, 8.0, 8.0)),
    ('aft spring 2', 'steel_wire', (0.0, 22.0, 2.0), (25.0, 8.0, 8.0)),
    ('aft breast', 'nylon', (20.0, 25.0, 2.0), (20.0, 8.0, 8.0)),
    ('stern line', 'polyester', (60.0, 20.0, 2.0), (40.0, 8.0, 8.0)),
)


def arrangement(duration):
    """Eight lines of one ship in one process, each a mooring of its own."""
    moorings = []
    for _, material, bollard, fairlead in ARRANGEMENT:
        chord = np.linalg.norm(np.subtract(fairlead, bollard))
        params = from_values(dict(material=material, segments=50, length=1.02 * chord,
                                  bollard_position=list(bollard)))
        moorings.append((Mooring(single_line(params), output_interval=OUTPUT),
                         np.array(fairlead)))
    cpu = run_surge(moorings, duration)
    print(f'## Arrangement: 8 lines x 50 segments (2 each of polyester, nylon, HMPE, wire), '
          f'{duration:g} s surge, 100 Hz output')
    print()
    print(f'CPU: {100 * cpu / duration:.1f} % of one core '
          f'({cpu:.2f} CPU s for {duration:g} s simulated; goal < 25 %)')
    print()


JERK = ((0.0, 38.0), (0.5, 38.0), (0.7, 39.5), (3.0, 39.5))  # (t [s], fairlead x [m])
DATA = Path(__file__).resolve().parent.parent / 'test' / 'data'


def jerk_peak(integrator, step=0.0):
    """Peak fairlead tension [N] and CPU s of the slack polyester line jerked taut."""
    params = from_values(dict(material='polyester', segments=50, integrator=integrator,
                              time_step=step))
    mooring = Mooring(single_line(params), output_interval=OUTPUT)
    for t, x in JERK:
        push_fairlead(mooring, t, [x, 0.0, 0.0])
    mooring.start(0.0)
    peak = 0.0
    cpu = time.process_time()
    for t in np.arange(OUTPUT, 2.0, OUTPUT):
        mooring.advance_to(t)
        peak = max(peak, mooring.output().fairlead_peaks[0])  # every step's largest, held
    return peak, time.process_time() - cpu


def _number(text):
    """Return a CSV field as a float where it is one, else as it is."""
    try:
        return float(text)
    except ValueError:
        return text


def _rows(name):
    """Read one of test/data/payload's CSV files as dicts (numbers as floats)."""
    with open(DATA / 'payload' / name, newline='') as f:
        return [{k: _number(v) for k, v in row.items()} for row in csv.DictReader(f)]


def snatch_peaks(integrator):
    """
    Errors of the first three snatches of a 5 t payload heaved 2 m in 2 s, against MoorDyn.

    The case of test/data/payload (50 m wire, N 20): the payload falls slack and is caught
    three times in 6.5 s. Each snatch's largest tension on MoorDyn's 5 ms rows, as a fraction
    of MoorDyn's (whose own step converged it to 3e-5).
    """
    summary = next(r for r in _rows('payload_summary.csv') if r['case'] == 'snatch')
    amplitude, period, ramp = summary['A_m'], summary['T_s'], summary['T_ramp_s']
    params = from_values(dict(
        payload_mass=5000.0, length=50.0, segments=20, mass_per_length=6.5,
        axial_stiffness=1.0e8, axial_damping=2.0 * 0.01 * 50.0 * math.sqrt(6.5e8) / math.pi,
        bending_stiffness_ratio=0.0, bending_damping_ratio=0.0, gravity=[0.0, 0.0, -GRAVITY],
        air_density=0.0, integrator=integrator, parting=False))
    mooring = Mooring(single_line(params), history=math.inf)
    for t in np.arange(0.0, 6.51, 0.001):
        ramped = 0.5 * (1.0 - math.cos(math.pi * t / ramp)) if t < ramp else 1.0
        push_fairlead(mooring, float(t), [0.0, 0.0, amplitude
                                          * math.sin(2 * math.pi * t / period) * ramped])
    mooring.start(0.0)
    times = np.array([r['t_s'] for r in _rows('payload_snatch.csv') if r['t_s'] <= 6.5])
    force = []
    for t in times:
        mooring.advance_to(t)
        force.append(mooring.output().fairlead_tensions[0])
    force = np.array(force)
    errors = []
    for peak in _rows('payload_snatch_peaks.csv'):
        if peak['case'] == 'snatch' and peak['t_peak_s'] <= 6.5:
            window = (times >= peak['t_start_s']) & (times <= peak['t_end_s'])
            errors.append(force[window].max() / peak['F_top_peak_sampled_N'] - 1.0)
    return errors


def snap_load(duration):
    """Snap peaks against converged runs, and the speed in ship motion, per integrator."""
    print('## Snap loads and speed, each integrator at its automatic step')
    print()
    print('Jerk: a slack 40 m polyester line (N 50) jerked 1.5 m taut in 0.2 s, its peak '
          'fairlead tension against improved_euler at 2e-5 s. Snatches: a 5 t payload on a '
          '50 m wire heaved 2 m in 2 s, caught three times after falling slack, against '
          'MoorDyn. Ship motion: the polyester preset (N 50) in the 2 m, 8 s surge above.')
    print()
    converged, _ = jerk_peak('improved_euler', 2e-5)
    print('| integrator | jerk peak [N] | vs converged | snatches vs MoorDyn | jerk CPU s '
          '/ sim s | ship motion: real-time factor |')
    print('|---|---|---|---|---|---|')
    for integrator in INTEGRATORS:
        peak, cpu = jerk_peak(integrator)
        snatches = ' / '.join(f'{100 * e:+.1f} %' for e in snatch_peaks(integrator))
        mooring = Mooring(single_line(from_values(dict(
            material='polyester', segments=50, integrator=integrator))), output_interval=OUTPUT)
        ship = run_surge([(mooring, FAIRLEAD)], duration)
        print(f'| {integrator} | {peak:.0f} | {100 * (peak / converged - 1.0):+.1f} % | '
              f'{snatches} | {cpu / 2.0:.3f} | {duration / ship:.0f} |', flush=True)
    print(f'\nConverged jerk peak: {converged:.0f} N.')
    print()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--duration', type=float, default=60.0)
    parser.add_argument('--segments', type=int, nargs='+', default=[20, 50, 100])
    parser.add_argument('--skip-moordyn', action='store_true')
    args = parser.parse_args()
    os.environ.setdefault('NUMBA_NUM_THREADS', '1')
    # compile every kernel before timing anything
    run_ours('polyester', 20, 'improved_euler', 0.05)
    run_ours('polyester', 20, 'implicit_euler', 0.05)
    if not args.skip_moordyn:
        compare(args.duration, args.segments)
    presets(args.duration)
    arrangement(args.duration)
    snap_load(args.duration)


if __name__ == '__main__':
    main()
