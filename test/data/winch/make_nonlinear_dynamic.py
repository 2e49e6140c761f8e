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
Compute nonlinear_dynamic.csv with MoorDyn 2.7.2: the nylon table's line under a moving fairlead.

The line of nonlinear_static.csv (40 m, N 20, the load-extension of nylon_table.csv, 64 mm,
2.3967744 kg/m, in air) hangs from A at the origin to a fairlead B at (x_B, 0, 8) that moves
x_B(t) = 40.25 + 1.75 cos(2 pi t / 10 s) for 30 s: from the 42 m span (114 kN) down to
38.5 m (1.5 kN, sagging) and back, three times. MoorDyn starts at the exact static
equilibrium of its 20-segment chain at the 42 m span (solved here, independently of the
project's code, and loaded through a state file) and is stepped at its own time step dtM:
MoorDyn moves a coupled point on a straight line within a Step, so coupling it every 1 ms
would put kinks into the fairlead's path that ring the stiff end segment. Run it from the
repository root with the project's virtual environment:

    .venv/bin/python test/data/winch/make_nonlinear_dynamic.py

It writes nonlinear_dynamic.csv, nonlinear_dynamic_initial_nodes.csv and MoorDyn's input
files (moordyn_inputs/nonlinear_dynamic.txt and its table nylon_table.txt) in about 10 s.
It is deterministic (MoorDyn is single-threaded, nothing is random) and is not imported by
any test; the tests read only the CSV files.
"""

import contextlib
import csv
import math
import os
import struct
import sys
import tempfile

import moordyn
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
INPUTS = os.path.join(HERE, 'moordyn_inputs')

G = 9.81
AIR = 1.225
DIAMETER = 0.064
MASS_PER_LENGTH = 585.15 * DIAMETER ** 2  # MoorPy's nylon mass coefficient: 2.3967744 kg/m
LENGTH = 40.0
SEGMENTS = 20
BA = 601.138  # as nonlinear_static.csv: 1 % of critical at the 42 m position's tangent
RISE = 8.0
DEPTH = 100.0  # MoorDyn's frame: A at z = -100 m, the seabed 1000 m deep, far below
MEAN, AMPLITUDE, PERIOD, DURATION = 40.25, 1.75, 10.0, 30.0
DTM = 1.0e-4
ROW = 0.01


def table():
    """Return the strains and tensions [N] of nylon_table.csv."""
    with open(os.path.join(HERE, 'nylon_table.csv'), newline='') as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith('#')))
    return (np.array([float(r['strain']) for r in rows]),
            np.array([float(r['tension_N']) for r in rows]))


def strain_at(tension, strains, tensions):
    """Return the strain at a tension: the table's inverse, its last slope past its end."""
    if tension <= tensions[-1]:
        return float(np.interp(tension, tensions, strains))
    slope = (tensions[-1] - tensions[-2]) / (strains[-1] - strains[-2])
    return float(strains[-1] + (tension - tensions[-1]) / slope)


def weight_per_length():
    """Return the line's weight in air less the air's buoyancy on the nominal diameter."""
    return (MASS_PER_LENGTH - AIR * math.pi * DIAMETER ** 2 / 4.0) * G


def equilibrium(span, strains, tensions):
    """
    Return the node positions (N + 1, 2) (x, z) of the chain at rest between A and B.

    MoorDyn's lumping: N equal segments of rest length L / N, every inner node carrying a
    segment's weight. Newton on the closure at B in (H, V_0), the first segment's horizontal
    and vertical tension, with a central-difference Jacobian.
    """
    l0 = LENGTH / SEGMENTS
    load = weight_per_length() * l0

    def nodes(unknowns):
        h, v0 = unknowns
        v = v0 + load * np.arange(SEGMENTS)
        t = np.hypot(h, v)
        length = l0 * (1.0 + np.array([strain_at(ti, strains, tensions) for ti in t]))
        steps = np.column_stack([length * h / t, length * v / t])
        return np.vstack([[0.0, 0.0], np.cumsum(steps, axis=0)])

    def closure(unknowns):
        return nodes(unknowns)[-1] - np.array([span, RISE])

    chord = math.hypot(span, RISE)
    pull = float(np.interp(chord / LENGTH - 1.0, strains, tensions))
    x = np.array([pull * span / chord, pull * RISE / chord - 0.5 * load * (SEGMENTS - 1)])
    for _ in range(50):
        f = closure(x)
        if np.abs(f).max() < 1e-13 * LENGTH:
            break
        jac = np.empty((2, 2))
        for k in range(2):
            dx = np.zeros(2)
            dx[k] = 1e-6 * abs(x[k]) + 1e-9
            jac[:, k] = (closure(x + dx) - closure(x - dx)) / (2.0 * dx[k])
        x = x - np.linalg.solve(jac, f)
    else:
        raise RuntimeError('the static chain did not converge')
    return nodes(x)


def fairlead_x(t):
    """Return the fairlead's horizontal position x_B(t) [m]."""
    return MEAN + AMPLITUDE * math.cos(2.0 * math.pi * t / PERIOD)


def write_inputs(folder, strains, tensions, span):
    """Write MoorDyn's input file and its table file (which must not end with a newline)."""
    lines = ['--- nylon-like rope, 64 mm: the points of test/data/winch/nylon_table.csv ---',
             'Strain    Tension', '(-)       (N)']
    lines += [f'{e:.4f}    {t:.6f}' for e, t in zip(strains, tensions)]
    with open(os.path.join(folder, 'nylon_table.txt'), 'w') as f:
        f.write('\n'.join(lines))  # MoorDyn 2.7.2 takes a last empty line for a bad point
    text = f"""--------------------- MoorDyn Input File ------------------------------------
Nonlinear-EA line (nylon table) under a moving fairlead (make_nonlinear_dynamic.py)
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam     Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)      (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
nylon      {DIAMETER}    {MASS_PER_LENGTH:.10g}  nylon_table.txt {BA}  0.0  1.2  1  0.008  0
---------------------- POINT PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass    Volume      CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)    (m^3)       (m^2)  (-)
1     Fixed     0       0       {-DEPTH}    0       0           0      0
2     Coupled   {span}   0       {-DEPTH + RISE}     0       0           0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)     (#)      (#)      (m)       (-)      (-)
1    nylon      1        2        {LENGTH}        {SEGMENTS}       -
---------------------- OPTIONS -----------------------------------------
0             writeLog      no log file
{DTM}        dtM           model time step (s)
{G}          g             gravity (m/s^2)
{AIR}         WtrDnsty      fluid density (kg/m^3): the line is in air
1000          WtrDpth       depth (m): seabed far below
RK2           tScheme       time integration scheme (MoorDyn default)
1             disableOutput no console output while stepping
1             disableOutTime no console time print
------------------------- need this line --------------------------------------
"""
    path = os.path.join(folder, 'nonlinear_dynamic.txt')
    with open(path, 'w') as f:
        f.write(text)
    return path


def write_state(path, nodes):
    """
    Write a MoorDyn 2.7 state file of the chain at rest at `nodes` (x, z in the local frame).

    moordyn.SaveState's layout for this system: 'MoorDyn', two version bytes, the number of
    8-byte words that follow plus one, the number of blocks, then per block (rows, columns,
    row-major doubles): point A (1 x 6), point B (1 x 6) and the line's inner nodes
    ((N - 1) x 6), each row position then velocity.
    """
    rows = np.zeros((len(nodes), 6))
    rows[:, 0] = nodes[:, 0]
    rows[:, 2] = nodes[:, 1] - DEPTH
    blocks = [rows[:1], rows[-1:], rows[1:-1]]
    data = b''
    for b in blocks:
        data += struct.pack('<QQ', *b.shape) + b.astype('<f8').tobytes()
    with open(path, 'wb') as f:
        f.write(b'MoorDyn' + struct.pack('<BB', 2, 7))
        f.write(struct.pack('<QQ', len(data) // 8 + 1, len(blocks)))
        f.write(data)


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


def simulate(input_path, state_path, dtm, coupling, static):
    """
    Run the motion; return rows [t, x_B, z_B, F_B, F_Bx, F_Bz] every ROW seconds.

    :param dtm: MoorDyn's step [s] (SetDt).
    :param coupling: the interval of Step calls [s]; the fairlead's secant velocity.
    :param static: the force (x, z) on B at rest at the start, the t = 0 row's: MoorDyn
        has computed none before its first Step.
    """
    x0 = fairlead_x(0.0)
    with quiet():
        system = moordyn.Create(input_path)
        moordyn.SetDt(system, dtm)
        moordyn.Init_NoIC(system, [x0, 0.0, RISE - DEPTH], [0.0, 0.0, 0.0])
        moordyn.LoadState(system, state_path)
    steps = int(round(DURATION / coupling))
    every = int(round(ROW / coupling))
    rows = [[0.0, x0, RISE, np.linalg.norm(static), static[0], static[1]]]
    for j in range(steps):
        t = j * coupling
        xa, xb = fairlead_x(t), fairlead_x(t + coupling)
        force = np.array(moordyn.Step(system, [xb, 0.0, RISE - DEPTH],
                                      [(xb - xa) / coupling, 0.0, 0.0], t, coupling))
        if (j + 1) % every == 0:
            rows.append([t + coupling, xb, RISE, np.linalg.norm(force), force[0], force[2]])
    with quiet():
        moordyn.Close(system)
    return np.array(rows)


def main():
    """Write the reference files of this case."""
    strains, tensions = table()
    nodes = equilibrium(fairlead_x(0.0), strains, tensions)
    # the chain's force on B at rest: its last segment's pull and half a segment's weight
    last = nodes[-1] - nodes[-2]
    l0 = LENGTH / SEGMENTS
    t_last = float(np.interp(np.linalg.norm(last) / l0 - 1.0, strains, tensions))
    static = -t_last * last / np.linalg.norm(last) - np.array(
        [0.0, 0.5 * weight_per_length() * l0])
    os.makedirs(INPUTS, exist_ok=True)
    write_inputs(INPUTS, strains, tensions, fairlead_x(0.0))
    with tempfile.TemporaryDirectory() as workdir:
        # MoorDyn writes its .out file beside its input: run a copy, keep the folder clean
        input_path = write_inputs(workdir, strains, tensions, fairlead_x(0.0))
        state = os.path.join(workdir, 'start.state')
        write_state(state, nodes)
        rows = simulate(input_path, state, DTM, DTM, static)
        half = simulate(input_path, state, DTM / 2.0, DTM / 2.0, static)
        coarse = simulate(input_path, state, DTM, 1.0e-3, static)
    spread = float(np.std(rows[:, 3]))
    comments = [
        f'A at (0, 0, 0), B at (x_B(t), 0, {RISE}), x_B = {MEAN} + {AMPLITUDE} cos(2 pi t / '
        f'{PERIOD} s); L0 {LENGTH} m, N {SEGMENTS}, nylon_table.csv, d {DIAMETER} m, m '
        f'{MASS_PER_LENGTH:.7f} kg/m, BA {BA} N s, Cd 1.2, CdAx 0.008, Ca 1, CaAx 0, air '
        f'{AIR} kg/m^3, g {G}',
        f'MoorDyn 2.7.2 RK2, dtM {DTM} s, one Step per dtM, from the exact static chain at '
        f'x_B = {fairlead_x(0.0)} m (|F_B| {np.linalg.norm(static):.3f} N)',
        f'convergence: dtM / 2 changes F_B by at most '
        f'{np.abs(half[:, 3] - rows[:, 3]).max():.3g} N, RMS '
        f"{np.sqrt(np.mean((half[:, 3] - rows[:, 3]) ** 2)) / spread:.2e} of F_B's RMS about "
        f'its mean; a Step every 1 ms instead, at most '
        f'{np.abs(coarse[:, 3] - rows[:, 3]).max():.3g} N, RMS '
        f'{np.sqrt(np.mean((coarse[:, 3] - rows[:, 3]) ** 2)) / spread:.2e}',
    ]
    with open(os.path.join(HERE, 'nonlinear_dynamic.csv'), 'w', newline='') as f:
        for c in comments:
            f.write(f'# {c}\n')
        writer = csv.writer(f, lineterminator='\n')
        writer.writerow(['t_s', 'xB_m', 'zB_m', 'F_B_N', 'F_Bx_N', 'F_Bz_N'])
        writer.writerows([[f'{r[0]:.2f}', f'{r[1]:.9f}', f'{r[2]:g}', f'{r[3]:.4f}',
                           f'{r[4]:.4f}', f'{r[5]:.4f}'] for r in rows])
    with open(os.path.join(HERE, 'nonlinear_dynamic_initial_nodes.csv'), 'w',
              newline='') as f:
        writer = csv.writer(f, lineterminator='\n')
        writer.writerow(['node', 'x_m', 'y_m', 'z_m'])
        writer.writerows([[i, f'{p[0]:.12f}', 0, f'{p[1]:.12f}'] for i, p in enumerate(nodes)])
    for c in comments:
        print(c)


if __name__ == '__main__':
    main()
