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
The figures of docs/free_ship.md and docs/ship_loads.md, made again from the package.

    python docs/figures.py [FIGURE ...]   (ship_angles, passing_depth, free_ship,
                                           berth_check; all four by default)

From the repository root, in the venv (matplotlib's Agg backend: no display). Each figure is
the package's own output, through the rope_sim command line where there is one:

- docs/ship_angles.png: the angle convention of the wind and current coefficient tables (a
  sketch), and the shipped tables of config/ship/ read with the package's reader (the
  current's in deep water and at config/berth.yaml's depth).
- docs/passing_ship_depth.png: the passing ship's loads on config/berth.yaml's ship against
  the stagger, at the berth's depth, two deeper ones and in deep water
  (model/ship/passing.py).
- docs/free_ship_step.png: config/berth.yaml's ship, free (--set ship_mode=free), under a
  step load off the quay from LOADS.csv: `rope_sim run --loads --duration`; its dashed lines
  are the quasi-static equilibria of mooring/statics.py under the same loads.
- docs/berth_check.png: `rope_sim berth-check config/berth.yaml` (OCIMF MEG4's criteria),
  copied from its output folder.

About a minute on two cores once the kernels are compiled (the free run takes most of it).
"""

import argparse
import csv
import math
import os
from pathlib import Path
import shutil
import subprocess
import sys
import tempfile

REPO = Path(__file__).resolve().parent.parent
DOCS = REPO / 'docs'
sys.path.insert(0, str(REPO))

import matplotlib  # noqa: E402
matplotlib.use('Agg')
from matplotlib import pyplot  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402
import numpy as np  # noqa: E402
from rope_sim_ros.model.ship.coefficients import table_at_ratio  # noqa: E402
from rope_sim_ros.model.ship.passing import Hull, passing_loads  # noqa: E402
from rope_sim_ros.mooring.ship import water_depth  # noqa: E402
from rope_sim_ros.mooring.statics import ship_equilibrium  # noqa: E402
from rope_sim_ros.params.arrangement import read_setup  # noqa: E402
from rope_sim_ros.params.ship import (DEFAULT_TABLES, read_coefficients,  # noqa: E402
                                      read_current_tables, ShipParams)

BERTH = REPO / 'config' / 'berth.yaml'
# The free ship's step load: force ahead and off the quay and a yawing moment about the ship's
# origin (frame_id axes), ramped in over 1 s at LOAD_ON and out over 1 s at LOAD_OFF.
STEP_LOAD = (2.0e5, -6.0e5, 0.0, 0.0, 0.0, -1.5e7)
LOAD_ON, LOAD_OFF, DURATION = 30.0, 150.0, 270.0
RATE = 10.0  # [Hz] OUT.csv rows


def rope_sim(*arguments: str) -> None:
    """Run `python -m rope_sim_ros ARGUMENTS` in the repository root, its output unshown."""
    environment = dict(os.environ, PYTHONPATH=str(REPO))
    subprocess.run([sys.executable, '-m', 'rope_sim_ros', *arguments], cwd=REPO, check=True,
                   env=environment, stdout=subprocess.DEVNULL)


def read_out(path: Path) -> dict:
    """Return the columns of numbers of an OUT.csv by name, as arrays (not the lines' states)."""
    with open(path, newline='', encoding='utf-8') as stream:
        rows = list(csv.reader(stream))
    numbers = [i for i, name in enumerate(rows[0]) if not name.endswith('state')]
    values = np.array([[row[i] for i in numbers] for row in rows[1:]], dtype=float)
    return {rows[0][i]: values[:, j] for j, i in enumerate(numbers)}


# ---------------------------------------------------------------------- the angle sketch


def ship_angles(path: Path) -> None:
    """Draw the body axes, the angle theta a flow comes FROM, and the shipped tables."""
    figure, (sketch, curves) = pyplot.subplots(1, 2, figsize=(12.5, 5.9),
                                               gridspec_kw={'width_ratios': [1.0, 1.25]})
    # the ship from above, bow to the right (+x), port up (+y): length 10, beam 1.6
    hull = [(-5.0, -0.8), (3.2, -0.8), (5.0, 0.0), (3.2, 0.8), (-5.0, 0.8)]
    sketch.add_patch(Polygon(hull, closed=True, facecolor='0.88', edgecolor='0.3'))
    sketch.text(-4.7, 0.4, 'stern', va='center', fontsize=8, color='0.35')
    sketch.text(4.3, 0.4, 'bow', va='center', ha='right', fontsize=8, color='0.35')
    sketch.annotate('', xy=(6.6, 0.0), xytext=(0.0, 0.0),
                    arrowprops={'arrowstyle': '-|>', 'color': 'black', 'lw': 1.4})
    sketch.text(6.6, -0.8, 'x (forward)', ha='center', va='top', fontsize=9)
    sketch.annotate('', xy=(0.0, 5.6), xytext=(0.0, 0.0),
                    arrowprops={'arrowstyle': '-|>', 'color': 'black', 'lw': 1.4})
    sketch.text(-0.3, 5.6, 'y (port)', ha='right', va='center', fontsize=9)
    sketch.plot(0.0, 0.0, 'ko', markersize=4)
    sketch.text(0.0, -1.2, 'origin (midship)', ha='center', va='top', fontsize=7)
    theta = math.radians(50.0)
    radius = 2.6
    arc = np.linspace(0.0, theta, 60)
    sketch.plot(radius * np.cos(arc), radius * np.sin(arc), color='tab:blue', lw=1.3)
    sketch.annotate('', xy=(radius * math.cos(theta), radius * math.sin(theta)),
                    xytext=(radius * math.cos(0.96 * theta), radius * math.sin(0.96 * theta)),
                    arrowprops={'arrowstyle': '-|>', 'color': 'tab:blue'})
    middle = 0.5 * theta
    sketch.text(1.08 * radius * math.cos(middle), 1.08 * radius * math.sin(middle), 'θ',
                color='tab:blue', fontsize=15)
    # the wind comes FROM direction theta, blowing toward the ship
    direction = np.array([math.cos(theta), math.sin(theta)])
    sketch.plot([0.0, 7.0 * direction[0]], [0.0, 7.0 * direction[1]], ':', color='tab:red',
                lw=1.0)
    sketch.annotate('', xy=tuple(4.4 * direction), xytext=tuple(7.4 * direction),
                    arrowprops={'arrowstyle': '-|>', 'color': 'tab:red', 'lw': 3.0})
    sketch.text(*(7.6 * direction + [0.2, 0.0]), 'wind (or current)\ncomes FROM θ',
                color='tab:red', fontsize=9, va='center')
    for angle, label in ((0.0, '0: head'), (90.0, '90: from port'), (180.0, '180: from astern'),
                         (270.0, '270: from starboard')):
        point = 8.6 * np.array([math.cos(math.radians(angle)), math.sin(math.radians(angle))])
        sketch.text(point[0], point[1], f'θ = {label}', ha='center', va='center',
                    fontsize=8, color='0.25', rotation=90.0 if angle in (0.0, 180.0) else 0.0)
    sketch.set_xlim(-9.4, 10.6)
    sketch.set_ylim(-9.4, 9.4)
    sketch.set_aspect('equal')
    sketch.axis('off')
    sketch.set_title('the body frame from above (z up, out of the page)', fontsize=10)
    ship = ShipParams()
    setup = read_setup(BERTH)
    ratio = water_depth(setup.shared) / setup.ship.draft
    tables = (('wind', '-', read_coefficients(ship, 'wind_coefficients')),
              ('current, deep', '--', read_coefficients(ship, 'current_coefficients')),
              (f'current, {ratio:.2f} T deep', ':',
               table_at_ratio(read_current_tables(ship), ratio)))
    for what, style, table in tables:
        angles = np.linspace(0.0, 360.0, 361)
        cx, cy, cmz = table.at(angles)
        curves.plot(angles, cx, style, color='tab:blue', label=f'{what} C_x')
        curves.plot(angles, cy, style, color='tab:orange', label=f'{what} C_y')
        curves.plot(angles, cmz, style, color='tab:green', label=f'{what} C_mz')
    curves.axhline(0.0, color='0.5', lw=0.6)
    curves.set_xticks(range(0, 361, 45))
    curves.set_xlim(0.0, 360.0)
    curves.set_xlabel('θ: where the flow comes from, from the bow toward port [deg]')
    curves.set_ylabel('coefficient [-]')
    names = ', '.join(sorted(DEFAULT_TABLES.values()))
    curves.set_title(f'the shipped tables (config/ship/): {names};\nthe current also at '
                     f"config/berth.yaml's depth, {ratio:.2f} times the draft", fontsize=7)
    curves.legend(fontsize=7, ncol=3, loc='upper center', bbox_to_anchor=(0.5, -0.13))
    curves.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    pyplot.close(figure)


# ---------------------------------------------------------------------- the passing ship


def passing_depth(path: Path) -> None:
    """Draw the passing ship's loads on the berth's ship against the stagger, four depths."""
    setup = read_setup(BERTH)
    ship, passing = setup.ship, setup.passing
    moored = Hull(ship.length, ship.beam, ship.draft, ship.block_coefficient)
    passer = Hull(passing.length, passing.beam, passing.draft, passing.block_coefficient)
    speed, separation = 3.0, 70.0
    berth = water_depth(setup.shared)
    stagger = np.linspace(-600.0, 600.0, 1201)
    figure, axes = pyplot.subplots(3, 1, figsize=(9.0, 9.0), sharex=True)
    deep = np.array(passing_loads(moored, passer, speed, separation, stagger))
    cases = [(berth, '-', 'tab:red', f'{berth:g} m (the berth: {berth / ship.draft:.2f} T)'),
             (1.5 * ship.draft, '-', 'tab:orange', f'{1.5 * ship.draft:g} m (1.5 T)'),
             (3.0 * ship.draft, '-', 'tab:green', f'{3.0 * ship.draft:g} m (3 T)'),
             (math.inf, '--', 'tab:blue', 'deep water')]
    for depth, style, colour, label in cases:
        loads = deep if depth == math.inf else np.array(
            passing_loads(moored, passer, speed, separation, stagger, depth))
        peaks = np.abs(loads).max(axis=1) / np.abs(deep).max(axis=1)
        factors = '' if depth == math.inf else (
            f': peaks {peaks[0]:.1f}, {peaks[1]:.1f}, {peaks[2]:.1f} x deep')
        for axis, values, scale in zip(axes, loads, (1e3, 1e3, 1e6)):
            axis.plot(stagger, values / scale, style, color=colour, lw=1.4,
                      label=label + factors)
    legacy = np.array(passing_loads(moored, passer, speed, separation, stagger, berth,
                                    image_pairs=10))
    axes[1].plot(stagger, legacy[1] / 1e3, ':', color='black', lw=1.0,
                 label=f'{berth:g} m, images -10..10 only (the legacy programs)')
    for axis, name in zip(axes, ('surge force F_x [kN]', 'sway force F_y [kN]',
                                 'yaw moment M_z [MN m]')):
        axis.axhline(0.0, color='0.5', lw=0.6)
        axis.set_ylabel(name)
        axis.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc='upper left')
    axes[1].legend(fontsize=7, loc='lower left')
    axes[2].set_xlabel('stagger: the passing midship ahead (+) of the moored one [m]')
    axes[0].set_title(f'config/berth.yaml: a {passing.length:g} m ship passing at {speed:g} m/s, '
                      f'{separation:g} m off to starboard; body axes (x forward, y to port)',
                      fontsize=9)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    pyplot.close(figure)


# ---------------------------------------------------------------------- the free ship


def write_loads(path: Path) -> None:
    """Write LOADS.csv: nothing until LOAD_ON, STEP_LOAD from LOAD_ON + 1 s to LOAD_OFF."""
    on = ','.join(f'{value:g}' for value in STEP_LOAD)
    off = ','.join('0' for _ in STEP_LOAD)
    with open(path, 'w', encoding='utf-8') as stream:
        stream.write('t,force_x,force_y,force_z,moment_x,moment_y,moment_z\n'
                     f'{LOAD_ON:g},{off}\n{LOAD_ON + 1:g},{on}\n'
                     f'{LOAD_OFF:g},{on}\n{LOAD_OFF + 1:g},{off}\n')


def yaw_of(out: dict) -> np.ndarray:
    """Return the ship's yaw [rad] from OUT.csv's quaternion columns (Z-Y-X)."""
    x, y, z, w = out['qx'], out['qy'], out['qz'], out['qw']
    return np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def free_ship(path: Path) -> None:
    """Run the berth's ship free under a step load and draw its motion, lines and fenders."""
    setup = read_setup(BERTH, {'ship_mode': 'free'})
    start = np.array(setup.ship.start_position)
    with tempfile.TemporaryDirectory() as folder:
        loads, out_path = Path(folder) / 'loads.csv', Path(folder) / 'out.csv'
        write_loads(loads)
        rope_sim('run', '--params', str(BERTH), '--set', 'ship_mode=free', '--loads',
                 str(loads), '--duration', f'{DURATION:g}', '--rate', f'{RATE:g}', '--out',
                 str(out_path), '--quiet')
        out = read_out(out_path)
    resting = ship_equilibrium(setup).offset
    loaded = ship_equilibrium(setup, STEP_LOAD).offset
    t = out['t']
    figure, axes = pyplot.subplots(5, 1, figsize=(9.0, 11.5), sharex=True,
                                   gridspec_kw={'height_ratios': [0.7, 1.0, 0.8, 1.5, 0.9]})
    load = np.interp(t, [LOAD_ON, LOAD_ON + 1, LOAD_OFF, LOAD_OFF + 1], [0.0, 1.0, 1.0, 0.0])
    axes[0].plot(t, load * STEP_LOAD[0] / 1e3, label='force_x')
    axes[0].plot(t, load * STEP_LOAD[1] / 1e3, label='force_y')
    axes[0].plot(t, load * STEP_LOAD[5] / 1e5, label='moment_z / 100 m')
    axes[0].set_ylabel('LOADS.csv\n[kN]')
    axes[0].legend(fontsize=7, ncol=3, loc='lower left')

    def statics(ax, index, scale):
        """Draw the quasi-static offset (index) without and under the load, dashed."""
        for (begin, end), offset in (((0.0, LOAD_ON), resting), ((LOAD_ON, LOAD_OFF), loaded),
                                     ((LOAD_OFF, DURATION), resting)):
            ax.plot([begin, end], [scale * offset[index]] * 2, '--', color='0.4', lw=0.9)

    axes[1].plot(t, out['x'] - start[0], label='surge (x)')
    axes[1].plot(t, out['y'] - start[1], label='sway (y)')
    statics(axes[1], 0, 1.0)
    statics(axes[1], 1, 1.0)
    axes[1].set_ylabel('offset from\nthe start [m]')
    axes[1].legend(fontsize=7, loc='lower left')
    axes[2].plot(t, np.degrees(yaw_of(out)), color='tab:green', label='yaw')
    statics(axes[2], 5, 180.0 / math.pi)
    axes[2].set_ylabel('yaw [deg]')
    axes[2].legend(fontsize=7, loc='lower left')
    for name in setup.names:
        axes[3].plot(t, out[f'{name}_tension'] / 1e3, lw=1.0, label=name)
    axes[3].set_ylabel('fairlead\ntension [kN]')
    axes[3].legend(fontsize=7, ncol=4, loc='upper right')
    for fender in setup.fenders:
        axes[4].plot(t, out[f'{fender.name}_reaction'] / 1e3, lw=1.0, label=fender.name)
    axes[4].set_ylabel('fender\nreaction [kN]')
    axes[4].legend(fontsize=7, ncol=4, loc='upper right')
    axes[4].set_xlabel('t [s]')
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.axvspan(LOAD_ON, LOAD_OFF + 1, color='0.93', zorder=0)
    axes[0].set_title('config/berth.yaml, ship_mode free: a step load off the quay (shaded); '
                      'dashed: the static equilibria', fontsize=9)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    pyplot.close(figure)


# ---------------------------------------------------------------------- the berth check


def berth_check(path: Path) -> None:
    """Run rope_sim berth-check on config/berth.yaml (MEG4's criteria) and keep its plot."""
    with tempfile.TemporaryDirectory() as folder:
        rope_sim('berth-check', str(BERTH), '--out', folder, '--quiet')
        shutil.copyfile(Path(folder) / 'berth_check.png', path)


FIGURES = {'ship_angles': ship_angles, 'passing_depth': passing_depth, 'free_ship': free_ship,
           'berth_check': berth_check}
FILES = {'ship_angles': 'ship_angles.png', 'passing_depth': 'passing_ship_depth.png',
         'free_ship': 'free_ship_step.png', 'berth_check': 'berth_check.png'}


def main() -> None:
    """Make the figures asked for (all by default) in docs/."""
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('figures', nargs='*', metavar='FIGURE',
                        help=f'any of {", ".join(FIGURES)} (default: all)')
    names = parser.parse_args().figures or list(FIGURES)
    unknown = [name for name in names if name not in FIGURES]
    if unknown:
        parser.error(f'unknown figure {unknown[0]!r}: choose from {", ".join(FIGURES)}')
    for name in names:
        path = DOCS / FILES[name]
        FIGURES[name](path)
        print(path.relative_to(REPO))


if __name__ == '__main__':
    main()
