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
A moored ship in swell: the waves' spectrum and the ship's six motions' spectra, a plot.

config/berth.yaml's 225 m bulk carrier, free (`ship_mode: free`) with its hydrodynamic
database (test/data/hydro/berth_ship.nc: the Cummins equation, the radiation memory), lies
on its eight lines at the quay in a JONSWAP swell, Hs 1.5 m, Tp 11 s, gamma 3.3, coming
from 45 degrees off the bow on the starboard side: from the open water (the quay is on the
port side, y > 0). It runs --duration s (default 20 min) with outputs at 5 Hz (the
database's shortest wave, 3.1 s, gets 16 outputs a period; the sea's shortest component,
2.75 s, 14); the first --settle s (default 120) are left out of the analysis.

The picture: Welch spectra (scipy.signal.welch) of the wave elevation at the ship's origin
and of the ship's surge, sway, heave (m) and roll, pitch, yaw (deg), per rad/s. At the wave
frequencies each motion follows the waves (the first-order response); at low frequency
surge, sway and yaw swing at their natural frequencies on the lines, driven by the slow
drift (Newman's difference-frequency loads), where the waves have no energy at all. Shaded:
the waves' band (the JONSWAP spectrum above 2 % of its peak); dotted: the uncoupled natural
periods of surge, sway and yaw on the lines and of roll, 2 pi sqrt((M + A) / K) with the
lines' and fenders' stiffness at the start pose (`rope_sim stiffness --hydrostatics`).

Printed: each motion's significant value (4 standard deviations) and its PIANC range
(peak to peak, sway zero to peak, model/ship/motions.py) as a share of the limits of
`ship.motion_criteria` (default bulk_cranes), and each line's largest tension as % of MBL.

    python examples/waves_response.py [--out docs/waves_response.png] [--duration 1200]

(from the repository root, with the repository on PYTHONPATH, as `make` sets it). The
1200 s run takes 67 s of wall time on the two-core development machine alone, 140 s when
it is shared (the kernels cached).
"""

import argparse
import math
from pathlib import Path
import time

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
import numpy as np

from rope_sim_ros.model.ship.motions import against_limits, motion_ranges, motion_series, MOTIONS
from rope_sim_ros.model.ship.waves import jonswap_spectrum
from rope_sim_ros.mooring.statics import ship_stiffness
from rope_sim_ros.mooring.status import ratings
from rope_sim_ros.offline.run import run_free
from rope_sim_ros.params.arrangement import flatten, read_setup
from rope_sim_ros.params.hydro_file import read_hydro_database
from scipy.signal import welch

REPO = Path(__file__).resolve().parent.parent
DATABASE = REPO / 'test' / 'data' / 'hydro' / 'berth_ship.nc'
HS, TP, GAMMA = 1.5, 11.0, 3.3  # [m], [s], JONSWAP's peak enhancement
FROM = -math.pi / 4  # where the waves come from: 45 degrees off the bow, starboard (sea) side
RATE = 5.0  # [Hz] outputs
XMAX = 1.6  # [rad/s] the plots' right edge
SEGMENT_SECONDS = 400.0  # Welch's segment [s]: resolves 0.016 rad/s


def setup_of():
    """Return the berth's arrangement, free, in the swell."""
    overrides = {
        'ship_mode': 'free', 'publish_rate': RATE, 'ship': {'hydrodynamics': str(DATABASE)},
        'waves': {'spectrum': 'jonswap', 'height': HS, 'period': TP, 'direction': FROM,
                  'peak_enhancement': GAMMA, 'seed': 1}}
    return read_setup(REPO / 'config' / 'berth.yaml', flatten(overrides))


def run(setup, duration: float) -> dict:
    """Run the ship; return its times, poses, wave elevation and line tensions."""
    t, position, orientation, eta, tension = [], [], [], [], []

    def keep(published) -> None:
        out = published.output
        t.append(out.t)
        position.append(out.ship.position)
        orientation.append(out.ship.orientation)
        eta.append(out.wave_elevation)
        tension.append(np.maximum(np.maximum(out.fairlead_peaks, out.bollard_peaks),
                                  np.maximum(out.fairlead_tensions, out.bollard_tensions)))

    wall = time.monotonic()
    run_free(setup, duration, rate=RATE, sinks=[keep])
    return {'t': np.array(t), 'position': np.array(position),
            'orientation': np.array(orientation), 'eta': np.array(eta),
            'tension': np.array(tension), 'wall': time.monotonic() - wall}


def analyse(setup, record: dict, settle: float) -> dict:
    """Return the motions, their spectra and ranges, and the tensions, past `settle` s."""
    kept = record['t'] >= settle
    series = motion_series(record['position'][kept], record['orientation'][kept])
    n = min(int(SEGMENT_SECONDS * RATE), int(kept.sum()))
    spectra = {}
    for name, values in [('eta', record['eta'][kept])] + list(series.items()):
        scale = math.degrees(1.0) if name in ('roll', 'pitch', 'yaw') else 1.0
        f, s = welch(scale * (values - values.mean()), fs=RATE, nperseg=n)
        spectra[name] = s / (2.0 * math.pi)  # per rad/s
    omega = 2.0 * math.pi * f
    ranges = motion_ranges(series)
    shares, worst = against_limits(ranges, setup.ship.motion_limits)
    mbl = np.array([rating.mbl for rating in ratings(setup)])
    return {'omega': omega, 'spectra': spectra, 'series': series, 'ranges': ranges,
            'shares': shares, 'worst': worst, 'eta': record['eta'][kept],
            'utilisation': record['tension'][kept].max(axis=0) / mbl,
            'seconds': float(record['t'][kept][-1] - record['t'][kept][0])}


def natural_periods(setup) -> dict:
    """
    Return the uncoupled natural periods [s] of surge, sway and yaw on the lines, and roll.

    2 pi sqrt((M_ii + A_ii(omega)) / K_ii): the lines' and fenders' stiffness at the start
    pose (roll's with the hydrostatics), the database's added mass at the frequency found
    (a few fixed-point rounds; its lowest frequency below the band).
    """
    database = read_hydro_database(setup.ship.hydrodynamics)
    stiffness = ship_stiffness(setup, hydrostatics=True)
    mass, radii = setup.ship.mass, setup.ship.radii_of_gyration
    inertia = [mass, mass, mass] + [mass * r * r for r in radii]
    periods = {}
    for name, i in [('surge', 0), ('sway', 1), ('roll', 3), ('yaw', 5)]:
        omega = database.omega[0]
        for _ in range(5):
            added = np.interp(omega, database.omega, database.added_mass[:, i, i])
            omega = math.sqrt(stiffness[i, i] / (inertia[i] + added))
        periods[name] = 2.0 * math.pi / omega
    return periods


def plot(result: dict, periods: dict, out: Path) -> None:
    """Draw the elevation's and the six motions' spectra into out (PNG)."""
    omega, spectra = result['omega'], result['spectra']
    figure = Figure(figsize=(10, 10), layout='constrained')
    FigureCanvasAgg(figure)
    sea, translations, rotations = figure.subplots(3, 1, sharex=True)
    target = jonswap_spectrum(np.maximum(omega, 1e-6), HS, TP, GAMMA)
    sea.plot(omega, spectra['eta'], color='tab:blue', lw=1.2, label='at the ship (Welch)')
    sea.plot(omega, target, color='k', lw=0.8, ls='--',
             label=f'JONSWAP Hs {HS:g} m, Tp {TP:g} s, gamma {GAMMA:g}')
    band = omega[target > 0.02 * target.max()]  # the waves' band: shaded below
    hs = 4.0 * result['eta'].std()
    sea.set_title(f'Wave elevation: Hs {hs:.2f} m measured, from 45° off the starboard bow')
    sea.set_ylabel('S [m² s/rad]')
    for axes, names, unit in [(translations, ('surge', 'sway', 'heave'), 'm² s/rad'),
                              (rotations, ('roll', 'pitch', 'yaw'), 'deg² s/rad')]:
        for name, colour in zip(names, ('tab:red', 'tab:green', 'tab:purple')):
            axes.semilogy(omega[1:], spectra[name][1:], color=colour, lw=1.1, label=name)
        axes.set_ylabel(f'S [{unit}]')
        shown = (omega > 0.0) & (omega <= XMAX)
        top = max(spectra[name][shown].max() for name in names)
        axes.set_ylim(top * 1e-7, top * 5.0)
        axes.axvspan(band.min(), band.max(), color='tab:blue', alpha=0.07, lw=0)
    for name, axes, place in [('surge', translations, 0.93), ('sway', translations, 0.78),
                              ('roll', rotations, 0.93), ('yaw', rotations, 0.78)]:
        omega_n = 2.0 * math.pi / periods[name]
        axes.axvline(omega_n, color='0.4', lw=0.8, ls=':')
        what = 'roll' if name == 'roll' else f'{name} on the lines'
        axes.text(omega_n + 0.01, place, f'{what}\n{periods[name]:.0f} s',
                  transform=axes.get_xaxis_transform(), fontsize=8, va='top')
    translations.set_title('Translations: the slow drift on the lines at low frequency, '
                           "the first-order response in the waves' band (shaded)")
    rotations.set_title("Rotations: roll at its own period in the waves' low tail, yaw slowly "
                        'on the lines')
    rotations.set_xlabel('ω [rad/s]')
    rotations.set_xlim(0.0, XMAX)
    for axes in (sea, translations, rotations):
        axes.grid(alpha=0.3)
        axes.legend(loc='upper right', fontsize=8)
    figure.savefig(out, dpi=100)


def report(setup, result: dict) -> None:
    """Print the significant motions, their PIANC shares and the lines' largest tensions."""
    limits = setup.ship.motion_limits
    print(f'{result["seconds"]:.0f} s analysed; Hs at the ship {4 * result["eta"].std():.2f} m; '
          f'PIANC {setup.ship.motion_criteria} ({limits.ship}, {limits.handling})')
    print(f'{"motion":<7} {"4 sigma":>9} {"range":>9} {"limit":>7} {"share":>6}')
    for name in MOTIONS:
        angular = name in ('roll', 'pitch', 'yaw')
        scale, unit = (math.degrees(1.0), 'deg') if angular else (1.0, 'm')
        limit, share = limits.limits[name], result['shares'][name]
        print(f'{name:<7} {4 * scale * result["series"][name].std():7.3f}{unit:>3} '
              f'{scale * result["ranges"][name]:7.3f}{unit:>3} '
              + (f'{scale * limit:7.2f} {100 * share:5.0f}%' if limit else f'{"-":>7}'))
    print(f'largest share of a limit: {100 * result["worst"]:.0f} %')
    print('largest tension, % MBL: ' + ', '.join(
        f'{name} {100 * u:.1f}' for name, u in zip(setup.names, result['utilisation'])))


def main() -> None:
    """Run, analyse and plot."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--out', type=Path, default=Path('docs/waves_response.png'))
    parser.add_argument('--duration', type=float, default=1200.0)
    parser.add_argument('--settle', type=float, default=120.0)
    args = parser.parse_args()
    setup = setup_of()
    record = run(setup, args.duration)
    print(f'ran {args.duration:g} s in {record["wall"]:.0f} s of wall time')
    result = analyse(setup, record, args.settle)
    report(setup, result)
    plot(result, natural_periods(setup), args.out)
    print(f'wrote {args.out}')


if __name__ == '__main__':
    main()
