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
A wire through the water surface onto the seabed, lifting off as the ship surges: a plot.

A 120 m steel wire (40 mm) runs from an anchor on a seabed 20 m below the still water to a
fairlead 3 m above it, 110 m away, in a 0.5 m/s current towards the anchor, on a seabed
with a friction coefficient of 0.5. As the ship surges 4 m back and forth (12 s period,
ramped in over the first period) the wire lifts off the ground up to 60 m from the anchor
and lays down again to 90 m, and the tensions swing with it. The ripples as it lays down
and is pulled taut again are the line's first axial modes (about 9 Hz): MoorDyn shows the
same, to a few per cent, on this case. A Mooring of the one line runs 60 s and the picture
shows the wire's shape at eight instants of the last period, the tensions at both ends, and
where the wire leaves the seabed.

    python examples/water_line.py [--out examples/water_line.png] [--duration 60]

(from the repository root, with the repository on PYTHONPATH, as `make` sets it).
"""

import argparse
import math
from pathlib import Path

import matplotlib
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
import numpy as np

from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import from_values

WATER_LEVEL = 0.0
SEABED = -20.0
ANCHOR = np.array([0.0, 0.0, SEABED])
FAIRLEAD = np.array([110.0, 0.0, 3.0])
SURGE = 4.0  # amplitude [m]
PERIOD = 12.0  # [s]
OUTPUT = 0.05  # [s]
LEVEL = (0.0, 0.0, 0.0, 1.0)  # the ship's orientation: the fairlead is position + offset


def fairlead_at(t):
    """Return the fairlead at times t: a surge along x, ramped in over the first period."""
    t = np.asarray(t, dtype=float)
    ramp = np.where(t < PERIOD, 0.5 * (1.0 - np.cos(np.pi * t / PERIOD)), 1.0)
    surge = SURGE * np.sin(2.0 * np.pi * t / PERIOD) * ramp
    return FAIRLEAD + surge[..., None] * np.array([1.0, 0.0, 0.0])


def simulate(duration):
    """Run the line; return output times, particles (n, N+1, 3) and end tensions (n, 2)."""
    params = from_values(dict(
        material='steel_wire', diameter=0.040, segments=50, length=120.0,
        bollard_position=ANCHOR.tolist(), water_level=WATER_LEVEL, seabed_level=SEABED,
        current=[-0.5, 0.0, 0.0], seabed_friction=0.5))
    mooring = Mooring(single_line(params), output_interval=OUTPUT, history=math.inf)
    samples = np.arange(0.0, duration + 0.1, 0.02)  # a ship's pose stream at 50 Hz
    for t, fairlead in zip(samples, fairlead_at(samples)):
        mooring.push_ship(float(t), fairlead - params.fairlead_offset, LEVEL)
    mooring.start(0.0)  # at rest on the catenary that knows the water and the seabed
    times = np.arange(0, int(round(duration / OUTPUT)) + 1) * OUTPUT
    shapes = np.empty((len(times), params.segments + 1, 3))
    tensions = np.empty((len(times), 2))
    for k, t in enumerate(times):
        mooring.advance_to(float(t))
        out = mooring.output()
        shapes[k] = out.positions[0]
        tensions[k] = out.fairlead_tensions[0], out.bollard_tensions[0]
    return times, shapes, tensions


def lift_off(shape, tolerance=0.05):
    """Return x of the last particle on the seabed (within tolerance [m]), or nan."""
    lying = np.flatnonzero(shape[:, 2] < SEABED + tolerance)
    return float(shape[lying[-1], 0]) if lying.size else math.nan


def plot(times, shapes, tensions, path):
    """Draw the shapes, the tensions and the lift-off point into a PNG at path."""
    # the Agg canvas draws into files only: no display, no pyplot state
    fig = Figure(figsize=(9, 10))
    FigureCanvasAgg(fig)
    top, middle, bottom = fig.subplots(3, 1, gridspec_kw=dict(height_ratios=[2.2, 1, 1]))
    last = np.flatnonzero(times >= times[-1] - PERIOD + 1e-9)
    cmap = matplotlib.colormaps['viridis']
    for j, k in enumerate(last[::max(1, len(last) // 8)][:8]):
        top.plot(shapes[k, :, 0], shapes[k, :, 2], '.-', ms=3, lw=1.2, color=cmap(j / 7),
                 label=f't = {times[k]:.1f} s')
    top.axhline(WATER_LEVEL, color='tab:blue', lw=1.0)
    top.fill_between([-5, 120], SEABED, WATER_LEVEL, color='tab:blue', alpha=0.08)
    top.fill_between([-5, 120], SEABED - 3, SEABED, color='peru', alpha=0.5)
    top.text(-3, WATER_LEVEL + 0.6, 'still water level', color='tab:blue', fontsize=9)
    top.text(-3, SEABED - 2.2, 'seabed', color='saddlebrown', fontsize=9)
    top.set_xlim(-5, 120)
    top.set_ylim(SEABED - 3, FAIRLEAD[2] + 4)
    top.set_xlabel('x [m]')
    top.set_ylabel('z [m]')
    top.set_title('120 m steel wire, 50 segments: anchor on the seabed, fairlead surging '
                  f'{SURGE:g} m / {PERIOD:g} s\n(current 0.5 m/s along -x; shapes over the '
                  'last period)', fontsize=10)
    top.legend(fontsize=8, ncol=2, loc='upper left', bbox_to_anchor=(0.0, 0.93))
    middle.plot(times, tensions[:, 0] / 1e3, label='fairlead')
    middle.plot(times, tensions[:, 1] / 1e3, label='anchor')
    middle.set_ylabel('tension [kN]')
    middle.legend(fontsize=8)
    middle.grid(alpha=0.3)
    bottom.plot(times, [lift_off(s) for s in shapes], color='saddlebrown')
    bottom.set_ylabel('lift-off point x [m]')
    bottom.set_xlabel('t [s]')
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--out', type=Path,
                        default=Path(__file__).resolve().parent / 'water_line.png')
    parser.add_argument('--duration', type=float, default=60.0)
    args = parser.parse_args()
    times, shapes, tensions = simulate(args.duration)
    plot(times, shapes, tensions, args.out)
    laid = [lift_off(s) for s in shapes[times >= times[-1] - PERIOD]]
    print(f'{args.out}: fairlead tension {tensions[:, 0].min() / 1e3:.1f} to '
          f'{tensions[:, 0].max() / 1e3:.1f} kN; lift-off point between '
          f'x = {np.nanmin(laid):.1f} and {np.nanmax(laid):.1f} m in the last period')


if __name__ == '__main__':
    main()
