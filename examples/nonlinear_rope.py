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
The nylon preset's load-extension curve against its linear EA: a plot and a table.

Left: the preset's strain-tension curve (config/materials.yaml, load_extension: curve) in
fractions of its MBL, beside its linear EA of 5 MBL (the default, load_extension: linear).
Right: what it does to the default 40 m line of 64 mm nylon (N 20, in air, bollard at the
origin, fairlead 8 m up): the fairlead force at rest for spans from 34 to 46 m, with either.
The table printed is the right panel's numbers.

    python examples/nonlinear_rope.py [--out docs/nonlinear_rope.png]

(from the repository root, with the repository on PYTHONPATH, as `make` sets it).
"""

import argparse
import math
from pathlib import Path

import matplotlib
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
import numpy as np

from rope_sim_ros.params import from_values
from rope_sim_ros.physics.tension_curve import TensionCurve
from rope_sim_ros.simulator import Simulator

SPANS = np.arange(34.0, 46.01, 0.5)
RISE = 8.0


def settled_force(load_extension, span):
    """Return the fairlead force [N] of the default nylon line at rest at a span."""
    sim = Simulator(from_values({'material': 'nylon', 'load_extension': load_extension}),
                    history=math.inf)
    sim.push_fairlead(0.0, [span, 0.0, RISE])
    sim.start(0.0)
    return sim.output().fairlead_tension, sim.props


def main():
    """Draw the figure and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--out', default='docs/nonlinear_rope.png')
    args = parser.parse_args()
    matplotlib.rcParams['font.size'] = 9
    linear = np.array([settled_force('linear', s)[0] for s in SPANS])
    curved = np.array([settled_force('curve', s)[0] for s in SPANS])
    props = settled_force('curve', SPANS[0])[1]
    mbl = props.mbl
    curve = TensionCurve.from_pairs(props.tension_curve)
    strain = np.linspace(0.0, 0.3, 301)

    figure = Figure(figsize=(8.0, 3.2))
    FigureCanvasAgg(figure)
    left, right = figure.subplots(1, 2)
    left.plot(100 * strain, curve.tension(strain) / mbl, label='curve (nylon preset)')
    left.plot(100 * strain, 5.0 * strain, '--', label='linear EA = 5 MBL')
    left.plot(100 * curve.strains, curve.tensions / mbl, '.', color='C0')
    left.set_xlabel('strain [%]')
    left.set_ylabel('tension / MBL')
    left.set_ylim(0.0, 1.5)
    left.legend(loc='upper left')
    left.grid(alpha=0.3)
    right.plot(SPANS, curved / 1e3, label='curve')
    right.plot(SPANS, linear / 1e3, '--', label='linear EA')
    right.set_xlabel('span [m] (40 m line, fairlead 8 m up)')
    right.set_ylabel('fairlead force at rest [kN]')
    right.legend(loc='upper left')
    right.grid(alpha=0.3)
    figure.tight_layout()
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(args.out, dpi=110)

    print(f'64 mm nylon, MBL {mbl / 1e3:.1f} kN; 40 m, N 20, fairlead at (span, 0, {RISE:g})')
    print('| span [m] | curve [kN] | linear EA 5 MBL [kN] | linear vs curve |')
    print('|---|---|---|---|')
    for span, c, lin in zip(SPANS, curved, linear):
        if span in (34.0, 38.0, 39.5, 40.0, 41.0, 42.0, 44.0, 46.0):
            print(f'| {span:g} | {c / 1e3:.2f} | {lin / 1e3:.2f} | {100 * (lin / c - 1):+.1f} % |')
    print(f'wrote {args.out}')


if __name__ == '__main__':
    main()
