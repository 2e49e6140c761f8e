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
Compute the payload reference data in this folder with MoorDyn 2.7.2.

A steel wire hangs from a crane tip (a MoorDyn coupled point driven from here) and carries a
5 t payload (a MoorDyn free point) at its lower end. The script solves the exact static
equilibrium of the lumped-mass chain, starts MoorDyn there through its state file, heaves the
tip and writes the time series, the static figures and the time-step convergence. Run it from
the repository root with the project's virtual environment:

    .venv/bin/python test/data/payload/make_reference.py

It is deterministic (MoorDyn is single-threaded, nothing is random) and is not imported by any
test; the tests read only the CSV files it writes.
"""

import argparse
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

G = 9.81
RHO_WATER = 1025.0
DIAMETER = 0.040
MASS_PER_LENGTH = 6.5
EA = 1.0e8
LENGTH = 50.0
SEGMENTS = 20
# 1 % of critical damping on the first axial mode of the line alone, as
# rope_sim_ros.model.rope.critical_axial_damping computes it.
BA = 2.0 * 0.01 * LENGTH * math.sqrt(EA * MASS_PER_LENGTH) / math.pi
PAYLOAD_MASS = 5000.0

# In water (the later issue): the wire keeps MoorDyn's usual coefficients and the payload
# gets a volume, a drag area and an added mass; the tip stays 10 m under the surface so
# that no part of the system ever crosses it.
WATER_LINE_COEFFS = {'Cd': 1.2, 'Ca': 1.0, 'CdAx': 0.008, 'CaAx': 0.0}
AIR_LINE_COEFFS = {'Cd': 0.0, 'Ca': 0.0, 'CdAx': 0.0, 'CaAx': 0.0}
PAYLOAD_VOLUME_WATER = 1.0
PAYLOAD_CDA_WATER = 2.0
PAYLOAD_CA_WATER = 1.0
WATER_TIP_DEPTH = 10.0
DEPTH = 1000.0

COUPLING_DT = 1.0e-3
DTM = 2.5e-5

CASES = {
    # name: amplitude [m], period [s], ramp [s], duration [s], row interval [s]
    'gentle': (1.0, 8.0, 8.0, 30.0, 0.02),
    'snatch': (2.0, 2.0, 4.0, 20.0, 0.005),
}


def tip_z(t, amplitude, period, ramp):
    """Return the tip height z(t) = A sin(2 pi t / T) r(t) with the cosine ramp r."""
    r = 0.5 * (1.0 - math.cos(math.pi * t / ramp)) if t < ramp else 1.0
    return amplitude * math.sin(2.0 * math.pi * t / period) * r


def static_chain(water):
    """
    Return the exact static equilibrium of the lumped-mass chain hanging from the tip.

    Node 0 is the tip and node N the payload. MoorDyn lumps half a segment on each end node
    and the payload's node also carries the payload. Returns the node heights below the tip,
    the segment tensions (segment j joins nodes j and j + 1), the force of the line on the tip
    and the payload's net downward load.
    """
    seg = LENGTH / SEGMENTS
    w = MASS_PER_LENGTH * G
    payload_load = PAYLOAD_MASS * G
    if water:
        w -= RHO_WATER * math.pi / 4.0 * DIAMETER ** 2 * G
        payload_load -= RHO_WATER * PAYLOAD_VOLUME_WATER * G
    tension = np.array([payload_load + w * seg * (0.5 + SEGMENTS - 1 - j)
                        for j in range(SEGMENTS)])
    stretched = seg * (1.0 + tension / EA)
    z = np.concatenate(([0.0], -np.cumsum(stretched)))
    f_top = tension[0] + w * seg / 2.0
    return z, tension, f_top, payload_load


def input_file(path, water, dtm):
    """Write the MoorDyn input file of the case."""
    coeffs = WATER_LINE_COEFFS if water else AIR_LINE_COEFFS
    z0 = -WATER_TIP_DEPTH if water else 0.0
    z, _, _, _ = static_chain(water)
    volume = PAYLOAD_VOLUME_WATER if water else 0.0
    cda = PAYLOAD_CDA_WATER if water else 0.0
    ca = PAYLOAD_CA_WATER if water else 0.0
    rho = RHO_WATER if water else 0.0
    text = f"""--------------------- MoorDyn Input File ------------------------------------
Payload on a wire under a heaving crane tip (rope_sim_ros test/data/payload)
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam     Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)      (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
wire       {DIAMETER}    {MASS_PER_LENGTH}    {EA:.6e}    {BA:.10g}    0.0    {coeffs['Cd']}    \
{coeffs['Ca']}    {coeffs['CdAx']}    {coeffs['CaAx']}
---------------------- POINT PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass    Volume      CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)    (m^3)       (m^2)  (-)
1     Coupled   0.0     0.0     {z0:.12g}     0.0     0.0         0.0    0.0
2     Free      0.0     0.0     {z0 + z[-1]:.12g}    {PAYLOAD_MASS}    {volume}    {cda}    {ca}
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)     (#)      (#)      (m)       (-)      (-)
1    wire       1        2        {LENGTH}       {SEGMENTS}       -
---------------------- OPTIONS -----------------------------------------
0             writeLog
{dtm:.6g}        dtM
{G}          g
{rho}          WtrDnsty
{DEPTH}          WtrDpth
RK2           tScheme
1             disableOutput
1             disableOutTime
------------------------- need this line --------------------------------------
"""
    with open(path, 'w') as f:
        f.write(text)


def state_file(path, water):
    """
    Write a MoorDyn 2.7 state file holding the exact static equilibrium at rest.

    The layout is the one moordyn.SaveState writes for this system: 'MoorDyn', two version
    bytes, the number of 8-byte words that follow plus one, the number of blocks, then per
    block (rows, columns, row-major doubles): the coupled tip (1 x 6), the free payload
    (1 x 6) and the line's inner nodes ((N - 1) x 6), each row position then velocity.
    """
    z0 = -WATER_TIP_DEPTH if water else 0.0
    z, _, _, _ = static_chain(water)
    blocks = [np.array([[0.0, 0.0, z0, 0.0, 0.0, 0.0]]),
              np.array([[0.0, 0.0, z0 + z[-1], 0.0, 0.0, 0.0]]),
              np.column_stack([np.zeros((SEGMENTS - 1, 2)), z0 + z[1:-1],
                               np.zeros((SEGMENTS - 1, 3))])]
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


class Run:
    """One MoorDyn system of the case, started at the exact static equilibrium."""

    def __init__(self, workdir, water, dtm, moordyn_ic=False):
        """Create the system; start it from MoorDyn's own IC if moordyn_ic, else exactly."""
        tag = f"{'water' if water else 'air'}_{dtm:.3g}_{int(moordyn_ic)}"
        self.z0 = -WATER_TIP_DEPTH if water else 0.0
        inp = os.path.join(workdir, f'{tag}.txt')
        input_file(inp, water, dtm)
        with quiet():
            self.system = moordyn.Create(inp)
            if moordyn_ic:
                moordyn.Init(self.system, [0.0, 0.0, self.z0], [0.0, 0.0, 0.0])
            else:
                moordyn.Init_NoIC(self.system, [0.0, 0.0, self.z0], [0.0, 0.0, 0.0])
                st = os.path.join(workdir, f'{tag}.state')
                state_file(st, water)
                moordyn.LoadState(self.system, st)
        self.payload = moordyn.GetPoint(self.system, 2)
        self.line = moordyn.GetLine(self.system, 1)

    def step(self, z_start, z_end, t):
        """Advance one coupling interval with the tip at z_start and its secant velocity."""
        v = (z_end - z_start) / COUPLING_DT
        f = moordyn.Step(self.system, [0.0, 0.0, self.z0 + z_start], [0.0, 0.0, v],
                         t, COUPLING_DT)
        return np.array(f)

    def payload_state(self):
        """Return the payload position (in the local frame, tip at rest at 0) and velocity."""
        p = np.array(moordyn.GetPointPos(self.payload))
        p[2] -= self.z0
        return p, np.array(moordyn.GetPointVel(self.payload))

    def nodes(self):
        """Return the line's node positions in the local frame, node 0 at the tip."""
        r = np.array([moordyn.GetLineNodePos(self.line, i) for i in range(SEGMENTS + 1)])
        r[:, 2] -= self.z0
        return r

    def close(self):
        """Release the MoorDyn system."""
        with quiet():
            moordyn.Close(self.system)


def simulate(workdir, water, dtm, case):
    """Run one heave case; return every-1-ms rows [t, tip_z, F_x, F_y, F_z, payload xyz, vz]."""
    amplitude, period, ramp, duration, _ = CASES[case]
    run = Run(workdir, water, dtm)
    _, _, f_top, _ = static_chain(water)
    steps = int(round(duration / COUPLING_DT))
    rows = np.empty((steps + 1, 9))
    p, v = run.payload_state()
    # Nothing has been stepped at t = 0: the force is the static one the state was built from.
    rows[0] = [0.0, 0.0, 0.0, 0.0, -f_top, p[0], p[1], p[2], v[2]]
    for j in range(steps):
        t = j * COUPLING_DT
        za = tip_z(t, amplitude, period, ramp)
        zb = tip_z(t + COUPLING_DT, amplitude, period, ramp)
        f = run.step(za, zb, t)
        p, v = run.payload_state()
        rows[j + 1] = [t + COUPLING_DT, zb, f[0], f[1], f[2], p[0], p[1], p[2], v[2]]
    run.close()
    return rows


def write_csv(name, header, rows, comments=()):
    """Write rows (already formatted strings or numbers) with a header."""
    with open(os.path.join(HERE, name), 'w', newline='') as f:
        for c in comments:
            f.write(f'# {c}\n')
        w = csv.writer(f, lineterminator='\n')
        w.writerow(header)
        w.writerows(rows)


def fmt(x, digits):
    """Format x with a fixed number of decimals, without a negative zero."""
    s = f'{x:.{digits}f}'
    return '0' if float(s) == 0.0 else s.rstrip('0').rstrip('.') if '.' in s else s


def series_rows(rows, interval):
    """Decimate the 1 ms rows to `interval` and format them."""
    stride = int(round(interval / COUPLING_DT))
    out = []
    for r in rows[::stride]:
        fmag = math.sqrt(r[2] ** 2 + r[3] ** 2 + r[4] ** 2)
        out.append([fmt(r[0], 3), fmt(r[1], 6), fmt(fmag, 1), fmt(r[4], 1),
                    fmt(r[5], 6), fmt(r[6], 6), fmt(r[7], 6), fmt(r[8], 4)])
    return out


def snatch_events(rows, threshold):
    """
    Return (start, end) row ranges of the snatches: F_top above threshold.

    A snatch rings at the line's axial wave period (2 L / c = 25 ms here), so its force can dip
    below the threshold for a few milliseconds; dips shorter than 0.1 s are merged.
    """
    fmag = np.linalg.norm(rows[:, 2:5], axis=1)
    above = np.flatnonzero(fmag > threshold)
    if above.size == 0:
        return []
    events = [[above[0], above[0]]]
    for k in above[1:]:
        if rows[k, 0] - rows[events[-1][1], 0] < 0.1:
            events[-1][1] = k
        else:
            events.append([k, k])
    return [(a, b + 1) for a, b in events]


def bounce_frequency(rows, t_from):
    """Return the frequency [Hz] of the strongest F_top oscillation above 1 Hz after t_from."""
    keep = rows[:, 0] >= t_from
    f = np.linalg.norm(rows[keep, 2:5], axis=1)
    f = (f - f.mean()) * np.hanning(f.size)
    n = 64 * f.size
    spectrum = np.abs(np.fft.rfft(f, n))
    freq = np.fft.rfftfreq(n, COUPLING_DT)
    spectrum[freq < 1.0] = 0.0
    return float(freq[int(np.argmax(spectrum))])


def static_check(workdir, water):
    """Return MoorDyn's own IC and a 5 s hold from the exact equilibrium."""
    z, _, f_top, _ = static_chain(water)
    run = Run(workdir, water, DTM, moordyn_ic=True)
    ic_z = run.payload_state()[0][2]
    ic_nodes = run.nodes()
    f_ic = np.linalg.norm(run.step(0.0, 0.0, 0.0))
    run.close()
    run = Run(workdir, water, DTM)
    forces, pz = [], []
    for j in range(5000):
        forces.append(np.linalg.norm(run.step(0.0, 0.0, j * COUPLING_DT)))
        pz.append(run.payload_state()[0][2])
        if j == 0:
            # MoorDyn refreshes the node positions it reports only when it steps.
            start_nodes = run.nodes()
    run.close()
    return {
        'md_ic_payload_z_m': ic_z,
        'md_ic_max_node_dz_m': float(np.max(np.abs(ic_nodes[:, 2] - z))),
        'md_ic_F_top_after_1ms_N': f_ic,
        'md_hold_1ms_max_node_dz_m': float(np.max(np.abs(start_nodes[:, 2] - z))),
        'md_hold_F_top_min_N': min(forces), 'md_hold_F_top_max_N': max(forces),
        'md_hold_payload_z_min_m': min(pz), 'md_hold_payload_z_max_m': max(pz),
        'md_hold_F_top_relerr': max(abs(min(forces) - f_top), abs(max(forces) - f_top)) / f_top,
    }


def main():
    """Write every file of this folder."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--water-series', action='store_true',
                        help='also write the in-water time series (about 0.38 MB, not kept)')
    args = parser.parse_args()
    summary = []
    convergence = []
    peaks = []
    with tempfile.TemporaryDirectory() as workdir:
        static_rows = []
        for water in (False, True):
            medium = 'water' if water else 'air'
            z, tension, f_top, payload_load = static_chain(water)
            check = static_check(workdir, water)
            row = {'medium': medium, 'payload_load_N': payload_load,
                   'line_load_N': f_top - payload_load, 'F_top_N': f_top,
                   'Tseg_top_N': tension[0], 'Tseg_bottom_N': tension[-1],
                   'payload_z_m': z[-1], 'stretch_m': -z[-1] - LENGTH}
            row.update(check)
            static_rows.append(row)
            suffix = '_water' if water else ''
            write_csv(f'payload{suffix}_initial_nodes.csv', ['node', 'x_m', 'y_m', 'z_m'],
                      [[i, 0, 0, f'{zi:.10f}'] for i, zi in enumerate(z)])
        header = list(static_rows[0].keys())
        write_csv('payload_static.csv', header,
                  [[r[k] if isinstance(r[k], str) else f'{r[k]:.10g}' for k in header]
                   for r in static_rows])

        for water in (False, True):
            medium = 'water' if water else 'air'
            suffix = '_water' if water else ''
            for case, (amplitude, period, ramp, duration, interval) in CASES.items():
                rows = simulate(workdir, water, DTM, case)
                half = simulate(workdir, water, DTM / 2.0, case)
                fmag = np.linalg.norm(rows[:, 2:5], axis=1)
                fmag_half = np.linalg.norm(half[:, 2:5], axis=1)
                if not water or args.water_series:
                    write_csv(f'payload_{case}{suffix}.csv',
                              ['t_s', 'tip_z_m', 'F_top_N', 'F_top_z_N', 'payload_x_m',
                               'payload_y_m', 'payload_z_m', 'payload_vz_m_s'],
                              series_rows(rows, interval))
                _, _, f_top, _ = static_chain(water)
                stride = int(round(interval / COUPLING_DT))
                for i, (a, b) in enumerate(snatch_events(rows, 2.0 * f_top)):
                    k = a + int(np.argmax(fmag[a:b]))
                    # The same snatch at dtM / 2, searched 50 ms around it.
                    lo, hi = max(a - 50, 0), min(b + 50, len(half))
                    kh = lo + int(np.argmax(fmag_half[lo:hi]))
                    sampled = [j for j in range(a, b) if j % stride == 0]
                    ks = sampled[int(np.argmax(fmag[sampled]))] if sampled else k
                    peaks.append({
                        'case': f'{case}{suffix}', 'event': i + 1, 't_start_s': rows[a, 0],
                        't_end_s': rows[b - 1, 0], 't_peak_s': rows[k, 0],
                        'F_top_peak_N': fmag[k], 'peak_over_static': fmag[k] / f_top,
                        'payload_vz_at_start_m_s': rows[a, 8],
                        'tip_vz_at_start_m_s': (rows[a, 1] - rows[a - 1, 1]) / COUPLING_DT,
                        'F_top_peak_sampled_N': fmag[ks], 't_peak_sampled_s': rows[ks, 0],
                        't_peak_half_s': half[kh, 0], 'F_top_peak_half_N': fmag_half[kh],
                        'peak_relchange_half': (fmag_half[kh] - fmag[k]) / fmag[k],
                    })
                k = int(np.argmax(fmag))
                kh = int(np.argmax(fmag_half))
                summary.append({
                    'case': f'{case}{suffix}', 'medium': medium, 'A_m': amplitude,
                    'T_s': period, 'T_ramp_s': ramp, 'duration_s': duration,
                    'row_interval_s': interval, 'dtM_s': DTM,
                    'F_top_static_N': f_top, 'F_top_max_N': fmag[k], 't_F_top_max_s': rows[k, 0],
                    'F_top_min_N': fmag.min(), 't_F_top_min_s': rows[int(np.argmin(fmag)), 0],
                    'F_top_max_sampled_N': fmag[::int(round(interval / COUPLING_DT))].max(),
                    'payload_z_min_m': rows[:, 7].min(), 'payload_z_max_m': rows[:, 7].max(),
                    'bounce_Hz': bounce_frequency(rows, ramp + 2.0) if case == 'gentle'
                    else '',
                })
                convergence.append({
                    'case': f'{case}{suffix}', 'dtM_s': DTM, 'dtM_half_s': DTM / 2.0,
                    'F_top_max_N': fmag[k], 'F_top_max_half_N': fmag_half[kh],
                    't_max_s': rows[k, 0], 't_max_half_s': half[kh, 0],
                    'peak_relchange': (fmag_half[kh] - fmag[k]) / fmag[k],
                    'max_abs_dF_N': float(np.max(np.abs(fmag_half - fmag))),
                    'max_abs_dF_rel_static': float(np.max(np.abs(fmag_half - fmag))) / f_top,
                    'max_abs_dz_payload_m': float(np.max(np.abs(half[:, 7] - rows[:, 7]))),
                })
                print(summary[-1])
                print(convergence[-1])
    for name, table in (('payload_summary.csv', summary),
                        ('payload_convergence.csv', convergence),
                        ('payload_snatch_peaks.csv', peaks)):
        header = list(table[0].keys())
        write_csv(name, header, [[r[k] if isinstance(r[k], str) else f'{r[k]:.10g}'
                                  for k in header] for r in table])


if __name__ == '__main__':
    main()
