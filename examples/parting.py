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
A mooring line pulled past its break load parts, and its pieces fly back: a plot.

A 40 m, 24 mm polyester line (MBL 163 kN) hangs between a bollard and a fairlead 38 m away
and 8 m up. From t = 0.5 s the ship pulls the fairlead 6 m away in 1 s: the line comes taut,
its tension climbs to the MBL, and the segment that first passes it parts. The two pieces
recoil with the energy the stretched rope stored, the piece on the fairlead whipping back
past it. The picture shows the tension at both ends (every output's value and the peak since
the previous one, which catches the parting load between outputs) and the line at instants
around the parting, side view.

    python examples/parting.py [--out docs/parting.png]

(from the repository root, with the repository on PYTHONPATH, as `make` sets it).
"""

import argparse
import math
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
import numpy as np

from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import from_values

START = np.array([38.0, 0.0, 8.0])
LEVEL = (0.0, 0.0, 0.0, 1.0)  # the ship's orientation: the fairlead is position + offset
PULL = 6.0  # [m] over 1 s, from 0.5 s
OUTPUT = 0.02  # [s]: 50 Hz, the node's default
DURATION = 3.0  # [s]


def fairlead_at(t: float) -> np.ndarray:
    """Return the fairlead at time t: pulled PULL m along x from 0.5 s, smoothly, over 1 s."""
    s = min(max(t - 0.5, 0.0), 1.0)
    return START + [PULL * 0.5 * (1.0 - math.cos(math.pi * s)), 0.0, 0.0]


def run() -> tuple:
    """Run the line; return times, tensions, peaks, shapes and the parting."""
    params = from_values(dict(diameter=0.024, length=40.0, segments=40))
    mooring = Mooring(single_line(params), history=math.inf)  # the line alone: line 0
    for t in np.arange(0.0, DURATION + 0.5, 0.01):
        mooring.push_ship(float(t), fairlead_at(float(t)) - params.fairlead_offset, LEVEL)
    mooring.start(0.0)
    rows, shapes, parting = [], {}, None
    for t in np.arange(OUTPUT, DURATION + 1e-9, OUTPUT):
        advance = mooring.advance_to(float(t))
        out = mooring.output()
        parting = parting or advance.parted.get(0)
        rows.append((out.t, out.fairlead_tensions[0], out.fairlead_peaks[0],
                     out.bollard_tensions[0], out.bollard_peaks[0]))
        shapes[round(out.t, 2)] = out.positions[0]
    return np.array(rows), shapes, parting, mooring.lines[0].props.mbl


def plot(rows, shapes, parting, mbl, out: Path) -> None:
    """Draw the tensions and the line's shapes into out (PNG)."""
    figure = Figure(figsize=(10, 7.5), layout='constrained')
    FigureCanvasAgg(figure)
    tension, side = figure.subplots(2, 1, height_ratios=[1, 1.2])
    t = rows[:, 0]
    tension.plot(t, rows[:, 2] / 1e3, color='tab:red', lw=1, label='fairlead, peak since the '
                 'previous output')
    tension.plot(t, rows[:, 1] / 1e3, '.', color='tab:red', ms=3,
                 label='fairlead, at each 50 Hz output')
    tension.plot(t, rows[:, 4] / 1e3, color='tab:blue', lw=1, label='bollard, peak')
    tension.axhline(mbl / 1e3, color='k', ls='--', lw=1, label=f'MBL {mbl / 1e3:.0f} kN')
    if parting is not None:
        tension.axvline(parting.t, color='0.5', lw=1)
        tension.annotate(f'parted at {parting.t:.3f} s, segment {parting.segment}',
                         (parting.t, mbl / 1e3), xytext=(8, -14), textcoords='offset points')
    tension.set_xlabel('time [s]')
    tension.set_ylabel('tension [kN]')
    tension.set_title('Tension at the ends: the pull reaches the MBL and the line parts')
    tension.legend(loc='upper right', fontsize=8)
    tension.grid(alpha=0.3)
    moments = [0.5]
    if parting is not None:
        moments += [round(parting.t + dt, 2) for dt in (0.0, 0.06, 0.14, 0.3, 0.6)]
    colours = ['0.6', 'k', 'tab:red', 'tab:orange', 'tab:green', 'tab:blue']
    for when, colour in zip(moments, colours):
        key = min(shapes, key=lambda k: abs(k - when))
        pieces = [shapes[key]]
        if parting is not None and key >= parting.t - 1e-9:  # drawn apart at the break
            cut = parting.segment + 1
            pieces = [shapes[key][:cut], shapes[key][cut:]]
        for n, x in enumerate(pieces):
            side.plot(x[:, 0], x[:, 2], '.-', color=colour, lw=1, ms=3,
                      label=f't = {key:.2f} s' if n == 0 else None)
    side.plot([0.0], [0.0], 's', color='k', ms=7)
    side.annotate('bollard', (0.0, 0.0), xytext=(6, -12), textcoords='offset points')
    side.set_xlabel('x [m]')
    side.set_ylabel('z [m]')
    side.set_aspect('equal', adjustable='datalim')
    side.set_title('The line, side view: taut, parting, the pieces recoiling')
    side.legend(loc='lower right', fontsize=8)
    side.grid(alpha=0.3)
    figure.savefig(out, dpi=110)


def main() -> None:
    """Run and plot."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--out', type=Path, default=Path('docs/parting.png'))
    args = parser.parse_args()
    rows, shapes, parting, mbl = run()
    if parting is None:
        raise SystemExit('the line did not part')
    print(f'parted at t = {parting.t:.3f} s, segment {parting.segment}; peak fairlead '
          f'tension {rows[:, 2].max() / 1e3:.1f} kN (MBL {mbl / 1e3:.1f} kN), largest at an '
          f'output {rows[:, 1].max() / 1e3:.1f} kN')
    plot(rows, shapes, parting, mbl, args.out)
    print(f'wrote {args.out}')


if __name__ == '__main__':
    main()
