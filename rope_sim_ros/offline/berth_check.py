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
``rope_sim berth-check``: does the arrangement hold its ship in this wind and current.

For the wind from every direction (every 360 / directions degrees, measured as the wind
coefficients are: the direction it comes FROM, from the ship's bow toward port), at one
speed, with each current of the scenario, the ship's quasi-static equilibrium under its
lines, fenders, hydrostatics and the wind's and current's loads (mooring/statics.py, the
loads of model/ship/loads.py on the ship at rest). One row per direction and current in
berth_check.csv; berth_check.png draws, per direction, the most loaded line's share of its
MBL against its working load limit, the ship's offset and the fender loads, each the worst
over the currents.

The default scenario is OCIMF's standard environmental criteria for a tanker berth (Mooring
Equipment Guidelines, MEG3 2008 and MEG4 2018): a 60 knot wind from any direction, together
with a current of 3 knots from ahead or astern (0 or 180 degrees), of 2 knots at 10 or 170
degrees, or of 0.75 knots from the beam (90 or 270 degrees). The wind speed is the 30 s
mean at 10 m. --wind-speed and --current give another scenario.

An arrangement with waves (waves.*, on a ship with its hydrodynamic database) adds their
mean drift to every case's loads: the sea state it sets, from its direction, as the ship
heads in each equilibrium. The waves' oscillating part is a dynamic run's (rope_sim run).
"""

import csv
from dataclasses import dataclass, field, replace
import math
import os
from typing import Any, Callable, List, Optional, Sequence, Tuple

import numpy as np

from ..model.ship.loads import world_load
from ..model.ship.wind import Wind
from ..model.statics.ship import StaticsError
from ..mooring.ship import hydrodynamics, ship_loads
from ..mooring.statics import ship_statics
from ..mooring.status import ratings
from ..params.arrangement import ArrangementParams
from ..params.resolve import environment
from ..params.table import ParameterError

KNOT = 1852.0 / 3600.0  # [m/s]
MEG4_WIND = 60.0 * KNOT
# (speed [m/s], direction it comes from relative to the bow [deg]) of each current
MEG4_CURRENTS = ((3.0 * KNOT, 0.0), (3.0 * KNOT, 180.0), (2.0 * KNOT, 10.0),
                 (2.0 * KNOT, 170.0), (0.75 * KNOT, 90.0), (0.75 * KNOT, 270.0))
CSV_NAME = 'berth_check.csv'
PNG_NAME = 'berth_check.png'


@dataclass
class Case:
    """
    One equilibrium of the check.

    :ivar direction: where the wind comes from, from the bow toward port [deg].
    :ivar current: the current's speed [m/s] and where it comes from, as direction.
    :ivar status: 'ok' or why no equilibrium was found.
    :ivar offset: surge, sway [m] and yaw [rad] of the ship from its start pose, body axes.
    :ivar tensions: each line's largest end tension [N]; utilisation: its share of its MBL.
    :ivar fenders: each fender's reaction [N].
    """

    direction: float
    current: Tuple[float, float]
    status: str = 'ok'
    offset: np.ndarray = field(default_factory=lambda: np.full(3, np.nan))
    tensions: np.ndarray = field(default_factory=lambda: np.zeros(0))
    utilisation: np.ndarray = field(default_factory=lambda: np.zeros(0))
    fenders: np.ndarray = field(default_factory=lambda: np.zeros(0))


def parse_current(text: str) -> Tuple[float, float, float]:
    """
    Return --current X,Y,Z: the water's velocity (where it goes TO) in frame_id [m/s].

    :raises ParameterError: not three finite numbers.
    """
    try:
        values = tuple(float(part) for part in text.split(','))
    except ValueError:
        values = ()
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise ParameterError(f'--current {text!r} is not allowed: must be X,Y,Z, three numbers '
                             '[m/s]: the velocity of the water in frame_id')
    return values


def check(setup: ArrangementParams, wind_speed: float = MEG4_WIND,
          currents: Optional[Sequence[Tuple[float, float, float]]] = None,
          directions: int = 24, materials: Any = None,
          progress: Optional[Callable[[int, int], None]] = None) -> List[Case]:
    """
    Return the check's equilibria (see the module docstring), wind direction by direction.

    :param currents: the currents (velocities in frame_id [m/s]); None: MEG4's.
    :raises ParameterError: a bad count or speed, a line or table that cannot be built.
    """
    if not (isinstance(directions, int) and 1 <= directions <= 360):
        raise ParameterError(f'--directions {directions!r} is not allowed: must be 1 to 360')
    if not (math.isfinite(wind_speed) and 0.0 <= wind_speed <= 100.0):
        raise ParameterError(f'--wind-speed {wind_speed!r} is not allowed: must be 0 to 100 m/s')
    heading = setup.ship.start_yaw
    cases_of_current = _currents(currents, heading)
    loads = ship_loads(setup, hydrodynamics(setup))
    loads.passing = None  # a ship at rest: no passing ship in the check
    names_mbl = [rating.mbl for rating in ratings(setup)]
    weather = [environment(setup.shared, setup.ship)]  # each case's wind and current
    statics = ship_statics(setup, materials, load_function=_load_function(loads, weather))
    cases: List[Case] = []
    total = directions * len(cases_of_current)
    previous = None
    for i in range(directions):
        direction = 360.0 * i / directions
        wind = Wind(wind_speed, heading + math.radians(direction))
        for current, described in cases_of_current:
            weather[0] = replace(weather[0], wind=wind, current=tuple(current))
            case = Case(direction, described)
            try:
                found = statics.equilibrium(previous)
            except StaticsError as e:
                try:  # from the start pose, where the one before led it astray
                    found = statics.equilibrium()
                except StaticsError:
                    case.status = f'no equilibrium: {e}'.splitlines()[0]
                    cases.append(case)
                    continue
            previous = found.pose
            yaw = heading
            c, s = math.cos(yaw), math.sin(yaw)
            dx, dy = found.offset[0], found.offset[1]
            case.offset = np.array([c * dx + s * dy, -s * dx + c * dy, found.offset[5]])
            case.tensions = np.maximum(found.loads.fairlead_tensions,
                                       found.loads.bollard_tensions)
            case.utilisation = case.tensions / np.asarray(names_mbl)
            case.fenders = found.loads.fender_reactions
            cases.append(case)
            if progress is not None:
                progress(len(cases), total)
    return cases


def _currents(currents, heading: float) -> List[Tuple[Tuple[float, float, float],
                                                      Tuple[float, float]]]:
    """Return each current's velocity in frame_id and (speed, direction from the bow)."""
    if currents is not None:
        out = []
        for velocity in currents:
            speed = math.hypot(velocity[0], velocity[1])
            direction = math.degrees(math.atan2(-velocity[1], -velocity[0]) - heading) % 360.0
            out.append((tuple(velocity), (speed, direction if speed > 0.0 else 0.0)))
        return out
    out = []
    for speed, direction in MEG4_CURRENTS:
        angle = heading + math.radians(direction)  # where it comes from, in frame_id
        out.append(((-speed * math.cos(angle), -speed * math.sin(angle), 0.0),
                    (speed, direction)))
    return out


def _load_function(loads, weather: list):
    """
    Return the statics' load function of the wind, current and waves on a ship at rest.

    The waves' is their mean drift (the slow drift's mean: the part a static equilibrium
    holds); the arrangement's sea state, the same in every case.

    :param weather: [the environment of the case at hand]: its wind, current and waves.
    """
    still = np.zeros(3)

    def load(position, rotation):
        at_rest = loads.at(0.0, weather[0], position, rotation, still)
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        drift = loads.waves.mean_drift(weather[0].waves, yaw)
        return world_load(np.vstack([at_rest, drift]), rotation)

    return load


def write_csv(path, setup: ArrangementParams, cases: Sequence[Case]) -> None:
    """Write berth_check.csv: one row per wind direction and current."""
    names = setup.names
    fenders = [fender.name for fender in setup.fenders]
    header = (['wind_direction_deg', 'current_speed', 'current_direction_deg', 'status',
               'surge', 'sway', 'yaw']
              + [f'{name}_{column}' for name in names for column in ('tension', 'mbl_percent')]
              + [f'{name}_load' for name in fenders])
    with open(path, 'w', newline='', encoding='utf-8') as stream:
        writer = csv.writer(stream, lineterminator='\n')
        writer.writerow(header)
        for case in cases:
            row = [case.direction, case.current[0], case.current[1], case.status,
                   *case.offset]
            if case.status == 'ok':
                for tension, share in zip(case.tensions, case.utilisation):
                    row += [tension, 100.0 * share]
                row += list(case.fenders)
            else:
                row += [''] * (2 * len(names) + len(fenders))
            writer.writerow([f'{v:.6g}' if isinstance(v, float) else v for v in row])


def envelope(cases: Sequence[Case]) -> List[Tuple[float, Optional[Case], Optional[Case]]]:
    """Return per wind direction the case of its most loaded line and of its largest sway."""
    by_direction: dict = {}
    for case in cases:
        by_direction.setdefault(case.direction, []).append(case)
    out = []
    for direction, group in sorted(by_direction.items()):
        found = [case for case in group if case.status == 'ok']
        worst = max(found, key=lambda case: case.utilisation.max(), default=None)
        widest = max(found, key=lambda case: abs(case.offset[1]), default=None)
        out.append((direction, worst, widest))
    return out


def table(setup: ArrangementParams, cases: Sequence[Case]) -> List[str]:
    """Return the printed table: per direction, the worst over the currents."""
    wll = [rating.wll / rating.mbl for rating in ratings(setup)]
    names = setup.names
    lines = [f'{"wind from":>9}  {"most loaded":<14}{"% MBL":>7}  {"WLL":>4}  '
             f'{"surge":>7} {"sway":>7} {"yaw":>7}  {"fender max":>10}',
             f'{"[deg]":>9}  {"":<14}{"":>7}  {"":>4}  {"[m]":>7} {"[m]":>7} {"[deg]":>7}  '
             f'{"[kN]":>10}']
    for direction, worst, widest in envelope(cases):
        if worst is None:
            lines.append(f'{direction:9.0f}  no equilibrium')
            continue
        k = int(np.argmax(worst.utilisation))
        share = 100.0 * worst.utilisation[k]
        fenders = max((case.fenders.max(initial=0.0) for case in cases
                       if case.direction == direction and case.status == 'ok'), default=0.0)
        over = 'over' if share >= 100.0 * wll[k] else 'ok'
        lines.append(f'{direction:9.0f}  {names[k]:<14}{share:7.1f}  {over:>4}  '
                     f'{worst.offset[0]:7.2f} {widest.offset[1]:7.2f} '
                     f'{math.degrees(worst.offset[2]):7.2f}  {fenders / 1e3:10.0f}')
    return lines


def plot(path, setup: ArrangementParams, cases: Sequence[Case], wll: float,
         title: str) -> None:
    """Draw berth_check.png: line utilisation, offsets and fender loads on polar axes."""
    import matplotlib
    matplotlib.use('Agg')
    from matplotlib import pyplot
    rows = envelope(cases)
    angles = np.radians([row[0] for row in rows] + [rows[0][0]])
    figure = pyplot.figure(figsize=(13.5, 4.8))
    panels = [figure.add_subplot(1, 3, i + 1, projection='polar') for i in range(3)]
    for axes in panels:
        axes.set_theta_zero_location('N')  # the bow up, port to the left
        axes.set_theta_direction(1)
    names = setup.names

    def closed(values):
        return np.append(values, values[0])

    share = closed([100.0 * row[1].utilisation.max() if row[1] else np.nan for row in rows])
    axes = panels[0]
    for k, name in enumerate(names):
        each = closed([100.0 * max(case.utilisation[k] for case in cases
                                   if case.direction == row[0] and case.status == 'ok')
                       if row[1] else np.nan for row in rows])
        axes.plot(angles, each, linewidth=0.8, alpha=0.6, label=name)
    axes.plot(angles, share, color='black', linewidth=2.0, label='most loaded')
    circle = np.linspace(0.0, 2.0 * math.pi, 181)
    axes.plot(circle, np.full_like(circle, 100.0 * wll), 'k--', linewidth=1.0,
              label=f'WLL ({100.0 * wll:.0f} % MBL)')
    axes.set_title('line load [% of MBL]', pad=14)
    axes.legend(fontsize=6, loc='lower left', bbox_to_anchor=(-0.35, -0.2))
    axes = panels[1]
    for index, label in ((0, 'surge'), (1, 'sway')):
        values = closed([max(abs(case.offset[index]) for case in cases
                             if case.direction == row[0] and case.status == 'ok')
                         if row[1] else np.nan for row in rows])
        axes.plot(angles, values, label=label)
    axes.set_title('largest offset [m]', pad=14)
    axes.legend(fontsize=7, loc='lower left', bbox_to_anchor=(-0.2, -0.15))
    axes = panels[2]
    for f, fender in enumerate(setup.fenders):
        values = closed([max(case.fenders[f] for case in cases
                             if case.direction == row[0] and case.status == 'ok') / 1e3
                         if row[1] else np.nan for row in rows])
        axes.plot(angles, values, label=fender.name)
    axes.set_title('fender load [kN]', pad=14)
    if setup.fenders:
        axes.legend(fontsize=7, loc='lower left', bbox_to_anchor=(-0.2, -0.15))
    figure.suptitle(title + '   (wind from: the bow up, port to the left)', fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    pyplot.close(figure)


def working_load_fraction(setup: ArrangementParams) -> float:
    """Return the lowest of the lines' working load limits as a fraction of their MBL."""
    return min(rating.wll / rating.mbl for rating in ratings(setup))


def run(setup: ArrangementParams, out: str, wind_speed: float, current, directions: int,
        progress=None) -> Tuple[List[Case], List[str]]:
    """
    Run the check and write its files into folder `out` (created).

    :returns: the cases and the printed table.
    """
    currents = None if current is None else [current]
    cases = check(setup, wind_speed, currents, directions, progress=progress)
    os.makedirs(out, exist_ok=True)
    write_csv(os.path.join(out, CSV_NAME), setup, cases)
    wll = working_load_fraction(setup)
    what = 'MEG4 currents' if current is None else 'current ' + ', '.join(
        f'{v:g}' for v in current) + ' m/s'
    plot(os.path.join(out, PNG_NAME), setup, cases, wll,
         f'berth check: wind {wind_speed:.1f} m/s ({wind_speed / KNOT:.0f} kn), {what}')
    return cases, table(setup, cases)
