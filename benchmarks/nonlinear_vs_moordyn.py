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
Speed and accuracy of a line with a strain-tension curve against MoorDyn, in one run.

The case of test/data/winch/nonlinear_dynamic.csv: the nylon table's 40 m line (N 20) in
air, its fairlead swinging between 38.5 and 42 m span with a 10 s period, 30 s. MoorDyn
2.7.2 runs live on its input file (test/data/winch/moordyn_inputs/), timed coupled every
1 ms through its Python API (its initial-condition solve timed apart); its accuracy is the
reference CSV's, coupled at its own step. This model runs with load_extension curve, both
integrators, and the same line with a linear EA (the secant at the 42 m span, EA 1.66 MN,
nonlinear_static.csv's linsec) to show what the curve costs and what it buys. NRMSE: the
RMS difference of the fairlead force from the reference over the RMS of the reference about
its mean.

    python benchmarks/nonlinear_vs_moordyn.py
"""

import contextlib
import csv
import math
import os
from pathlib import Path
import shutil
import sys
import tempfile
import time

import numpy as np

from rope_sim_ros.model.materials import MaterialLibrary
from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import from_values

DATA = Path(__file__).resolve().parent.parent / 'test' / 'data' / 'winch'
LINEAR_EA = 1.66054e6  # nonlinear_static.csv's linsec: the secant at the 42 m span
COUPLING = 1.0e-3
MOORDYN_STEP = 1.0e-4  # its input file's dtM
LEVEL = (0.0, 0.0, 0.0, 1.0)  # the ship's orientation: a line's fairlead is position + offset


def rows(name):
    """Read a CSV of the data folder, past its '#' lines, as a dict of float columns."""
    with open(DATA / name, newline='') as f:
        table = list(csv.DictReader(line for line in f if not line.startswith('#')))
    return {k: np.array([float(r[k]) for r in table]) for k in table[0]}


def library():
    """Return a materials file holding the reference rope, its table in fractions of MBL."""
    table = rows('nylon_table.csv')
    mbl = float(table['tension_N'][table['strain'] == 0.25][0])
    return MaterialLibrary({'nylon': dict(
        mass_per_length=[[585.15, 2]], mbl=[[mbl, 0]], axial_stiffness={'mbl_multiple': 5.0},
        working_load_fraction=0.5, volume_diameter_ratio=1.0, normal_drag_coefficient=1.2,
        tangential_drag_coefficient=0.008, normal_added_mass_coefficient=1.0,
        tangential_added_mass_coefficient=0.0,
        tension_curve={'mbl_fraction': [[e, t / mbl] for e, t in
                                        zip(table['strain'][1:], table['tension_N'][1:])]})})


def run_ours(reference, nodes, integrator, load_extension):
    """Run the motion; return the fairlead force at the reference rows, wall s and step."""
    params = from_values(dict(
        material='nylon', diameter=0.064, volume_diameter=0.064, length=40.0, segments=20,
        load_extension=load_extension,
        axial_stiffness=LINEAR_EA if load_extension == 'linear' else 0.0,
        axial_damping=601.138, air_density=1.225, bending_stiffness_ratio=0.0,
        bending_damping_ratio=0.0, integrator=integrator, bollard_position=[0.0, 0.0, 0.0]))
    t = reference['t_s']
    start = time.perf_counter()
    mooring = Mooring(single_line(params), library(), history=math.inf)
    for ti, x, z in zip(t, reference['xB_m'], reference['zB_m']):
        mooring.push_ship(float(ti), np.subtract([x, 0.0, z], params.fairlead_offset), LEVEL)
    mooring.start(0.0)
    mooring.place_line(0, np.column_stack([nodes['x_m'], nodes['y_m'], nodes['z_m']]))
    force = []
    for ti in t:
        mooring.advance_to(float(ti))
        force.append(mooring.output().fairlead_tensions[0])
    return np.array(force), time.perf_counter() - start, mooring.time_step


@contextlib.contextmanager
def quiet():
    """Silence MoorDyn's console output, which goes straight to file descriptor 1."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, 'w') as null:
        os.dup2(null.fileno(), 1)
        try:
            yield
        finally:
            os.dup2(saved, 1)
            os.close(saved)


def run_moordyn(reference):
    """Time MoorDyn coupled every 1 ms on the motion; return (init s, wall s, step)."""
    import moordyn  # a benchmark dependency only

    duration = float(reference['t_s'][-1])
    workdir = tempfile.mkdtemp()  # MoorDyn writes its .out file beside its input
    for name in ('nonlinear_dynamic.txt', 'nylon_table.txt'):
        shutil.copy(DATA / 'moordyn_inputs' / name, workdir)
    with quiet():
        start = time.perf_counter()
        system = moordyn.Create(os.path.join(workdir, 'nonlinear_dynamic.txt'))
        moordyn.Init(system, [reference['xB_m'][0], 0.0, -92.0], [0.0, 0.0, 0.0])
        init = time.perf_counter() - start
    start = time.perf_counter()
    steps = int(round(duration / COUPLING))
    for j in range(steps):
        t = j * COUPLING
        # the fairlead between the 10 ms rows of a smooth cosine: linear is close enough
        xa = np.interp(t, reference['t_s'], reference['xB_m'])
        xb = np.interp(t + COUPLING, reference['t_s'], reference['xB_m'])
        moordyn.Step(system, [xb, 0.0, -92.0], [(xb - xa) / COUPLING, 0.0, 0.0], t, COUPLING)
    wall = time.perf_counter() - start
    with quiet():
        moordyn.Close(system)
    shutil.rmtree(workdir)
    return init, wall, MOORDYN_STEP


def nrmse(series, reference):
    """Return the RMS difference over the RMS of the reference about its mean."""
    return float(np.sqrt(np.mean((series - reference) ** 2)) / np.std(reference))


def main():
    """Print the table."""
    reference = rows('nonlinear_dynamic.csv')
    nodes = rows('nonlinear_dynamic_initial_nodes.csv')
    duration = float(reference['t_s'][-1])
    run_ours(reference, nodes, 'improved_euler', 'curve')  # compile (or load) the kernels
    init, wall, dtm = run_moordyn(reference)
    md_speed = wall / duration
    print(f'nylon table line, N 20, {duration:g} s; MoorDyn init (not counted) {init:.1f} s')
    print('| model | load-extension | step [s] | wall s / sim s | real-time factor | '
          'vs MoorDyn | NRMSE of F_B vs MoorDyn | largest abs error [N] |')
    print('|---|---|---|---|---|---|---|---|')
    print(f'| MoorDyn RK2 | table | {dtm:.0e} | {md_speed:.4f} | {1.0 / md_speed:.1f} | 1.0 | '
          '- | - |')
    for integrator in ('improved_euler', 'implicit_euler'):
        for load_extension in ('curve', 'linear'):
            force, wall, dt = run_ours(reference, nodes, integrator, load_extension)
            speed = wall / duration
            label = 'curve' if load_extension == 'curve' else 'linear EA 1.66 MN'
            error = np.abs(force - reference['F_B_N']).max()
            print(f'| {integrator} | {label} | {dt:.1e} | {speed:.4f} | {1.0 / speed:.1f} | '
                  f'{md_speed / speed:.1f}x | {100 * nrmse(force, reference["F_B_N"]):.2f} % | '
                  f'{error:.0f} |')


if __name__ == '__main__':
    main()
