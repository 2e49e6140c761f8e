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
A preset's load-extension curve against its linear EA: a plot and a table.

Left: the preset's strain-tension curve (config/materials.yaml, load_extension: curve) in
fractions of its MBL, beside its linear EA (the default, load_extension: linear: 5 MBL for
nylon, 14 MBL for polyester). Right: what it does to the default 40 m line of 64 mm rope
(N 20, in air, bollard at the origin, fairlead 8 m up): the fairlead force at rest over a
range of spans, with either. The table printed is the right panel's numbers.

    python examples/nonlinear_rope.py [--material nylon] [--out docs/nonlinear_rope.png]
    python examples/nonlinear_rope.py --material polyester \
        --out docs/nonlinear_rope_polyester.png

(from the repository root, with the repository on PYTHONPATH, as `make` sets it).
"""

import argparse
import math
from pathlib import Path

import matplotlib
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
import numpy as np

from rope_sim_ros.model.tension_curve import TensionCurve
from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import from_values

RISE = 8.0
LEVEL = (0.0, 0.0, 0.0, 1.0)  # the ship's orientation: the fairlead is position + offset
# per material: the spans drawn, those printed, and the strains drawn [%] (a new polyester
# rope's published curve ends at 6 % strain, half its MBL; nylon's reaches MBL at 25 %)
CASES = {
    'nylon': (np.arange(34.0, 46.01, 0.5), (34.0, 38.0, 39.5, 40.0, 41.0, 42.0, 44.0, 46.0),
              30.0, 1.5),
    'polyester': (np.arange(34.0, 43.01, 0.25),
                  (34.0, 38.0, 39.5, 40.0, 40.5, 41.0, 42.0, 43.0), 10.0, 1.2)}


def settled_force(material, load_extension, span):
    """Return the fairlead force [N] of the default line of `material` at rest at a span."""
    params = from_values({'material': material, 'load_extension': load_extension})
    mooring = Mooring(single_line(params), history=math.inf)
    mooring.push_ship(0.0, np.subtract([span, 0.0, RISE], params.fairlead_offset), LEVEL)
    mooring.start(0.0)
    return mooring.output().fairlead_tensions[0], mooring.lines[0].props


def main():
    """Draw the figure and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--material', default='nylon', choices=sorted(CASES))
    parser.add_argument('--out', default='docs/nonlinear_rope.png')
    args = parser.parse_args()
    spans, printed, most_strain, most_tension = CASES[args.material]
    matplotlib.rcParams['font.size'] = 9
    linear = np.array([settled_force(args.material, 'linear', s)[0] for s in spans])
    curved = np.array([settled_force(args.material, 'curve', s)[0] for s in spans])
    props = settled_force(args.material, 'curve', spans[0])[1]
    mbl = props.mbl
    ea = props.axial_stiffness / mbl  # the linear preset's EA [MBL]
    curve = TensionCurve.from_pairs(props.tension_curve)
    strain = np.linspace(0.0, most_strain / 100.0, 301)

    figure = Figure(figsize=(8.0, 3.2))
    FigureCanvasAgg(figure)
    left, right = figure.subplots(1, 2)
    left.plot(100 * strain, curve.tension(strain) / mbl, label=f'curve ({args.material} preset)')
    left.plot(100 * strain, ea * strain, '--', label=f'linear EA = {ea:g} MBL')
    left.plot(100 * curve.strains, curve.tensions / mbl, '.', color='C0')
    left.set_xlabel('strain [%]')
    left.set_ylabel('tension / MBL')
    left.set_ylim(0.0, most_tension)
    left.legend(loc='upper left')
    left.grid(alpha=0.3)
    right.plot(spans, curved / 1e3, label='curve')
    right.plot(spans, linear / 1e3, '--', label='linear EA')
    right.set_xlabel('span [m] (40 m line, fairlead 8 m up)')
    right.set_ylabel('fairlead force at rest [kN]')
    right.legend(loc='upper left')
    right.grid(alpha=0.3)
    figure.tight_layout()
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(args.out, dpi=110)

    print(f'64 mm {args.material}, MBL {mbl / 1e3:.1f} kN; 40 m, N 20, fairlead at '
          f'(span, 0, {RISE:g})')
    print(f'| span [m] | curve [kN] | linear EA {ea:g} MBL [kN] | linear vs curve |')
    print('|---|---|---|---|')
    for span, c, lin in zip(spans, curved, linear):
        if span in printed:
            print(f'| {span:g} | {c / 1e3:.2f} | {lin / 1e3:.2f} | {100 * (lin / c - 1):+.1f} % |')
    print(f'wrote {args.out}')


if __name__ == '__main__':
    main()
