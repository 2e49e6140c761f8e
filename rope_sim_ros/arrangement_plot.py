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
Look at an arrangement's bag: what happened at the berth, in two pictures.

tensions.png, on linear scales: the ship's motion (ship/pose: surge and sway from where it
lay), every line's fairlead tension against its working load limit and its MBL (one panel
each, its peak marked with its utilisation), and the total force of the lines on the ship
(ship/mooring_wrench, body frame). plan.png: the berth from above at the moment of the
highest utilisation: the quay, the ship (outlined from its fairleads), every line coloured
by its band (line_status: green below the WLL, amber past it, red past 90 % of the MBL)
and labelled with its utilisation then and its peak, at rest in grey.

Times are the outputs' stamps (publish times), from the first output. The arrangement comes
from the bag's metadata (the mooring node stores it, arrangement.PARAMETERS_KEY). No ROS.
"""

from dataclasses import dataclass
import math
import os
from typing import Dict, List, Optional, Tuple

import numpy as np

from .bag import BagError, read_messages
from .bag.cdr import decode_pose_array, decode_pose_stamped, decode_wrench, \
    decode_wrench_stamped
from .bag.metadata import load_metadata, METADATA_FILE
from .line_status import COLOURS, NEAR_BREAK_FRACTION, Rating
from .params import arrangement
from .params.materials import load_materials

SHIP_POSE = '/ship/pose'
WRENCH = '/ship/mooring_wrench'


@dataclass(frozen=True)
class ArrangementRecord:
    """
    What a mooring node's bag holds, as numbers.

    :ivar setup: the arrangement (pretensioned lines with their lengths unresolved).
    :ivar ratings: each line's MBL and WLL.
    :ivar times: output stamps [s] from the first, (n,).
    :ivar tensions: each line's fairlead tension at each output (n, L) [N].
    :ivar wrench_times: [s], (m,); force, moment: the total on the ship, body frame (m, 3).
    :ivar ship_times: [s], (p,); ship_position (p, 3) [m]; ship_yaw (p,) [rad].
    :ivar start_ns: the first output's stamp [ns].
    """

    setup: arrangement.ArrangementParams
    ratings: List[Rating]
    times: np.ndarray
    tensions: np.ndarray
    wrench_times: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    ship_times: np.ndarray
    ship_position: np.ndarray
    ship_yaw: np.ndarray
    start_ns: int

    def peak(self, k: int) -> Tuple[float, float]:
        """Return line k's largest tension [N] and its time [s]."""
        i = int(np.argmax(self.tensions[:, k]))
        return float(self.tensions[i, k]), float(self.times[i])


def stored_arrangement(path) -> Optional[arrangement.ArrangementParams]:
    """Return the arrangement a mooring node's bag stores, or None (not such a bag)."""
    metadata_path = os.path.join(os.fspath(path), METADATA_FILE)
    if not os.path.isfile(metadata_path):
        return None
    try:
        custom = load_metadata(metadata_path).get('custom_data') or {}
    except BagError:
        return None
    text = custom.get(arrangement.PARAMETERS_KEY) if isinstance(custom, dict) else None
    return arrangement.parameters_from_yaml(text) if text else None


def read_record(path, setup: Optional[arrangement.ArrangementParams] = None
                ) -> ArrangementRecord:
    """
    Read an arrangement's bag (its stored arrangement unless `setup` is given).

    :raises BagError: unreadable, not an arrangement's bag, or no line tension recorded.
    """
    setup = setup or stored_arrangement(path)
    if setup is None:
        raise BagError(f'bag {os.fspath(path)} stores no arrangement (it was not recorded '
                       'by the mooring node)')
    library = load_materials()
    ratings = []
    for line in setup.lines:
        material = library.properties(line.params.material, line.params.diameter)
        ratings.append(Rating(material.mbl, material.working_load_limit))
    series: Dict[str, List[Tuple[int, float]]] = {line: [] for line in setup.names}
    topics = {f'/{line}/fairlead/tension': line for line in setup.names}
    wrench, ship = [], []
    for message in read_messages(path, [*topics, WRENCH, SHIP_POSE]):
        if message.topic in topics:
            force, _ = decode_wrench(message.data)
            series[topics[message.topic]].append(
                (message.publish_time_ns, float(np.linalg.norm(force))))
        elif message.topic == WRENCH:
            sec, nanosec, _, force, moment = decode_wrench_stamped(message.data)
            wrench.append((sec * 1_000_000_000 + nanosec, force, moment))
        else:
            sec, nanosec, _, position, q = decode_pose_stamped(message.data)
            yaw = math.atan2(2.0 * (q[3] * q[2] + q[0] * q[1]),
                             1.0 - 2.0 * (q[1] ** 2 + q[2] ** 2))
            ship.append((sec * 1_000_000_000 + nanosec, position, yaw))
    count = min(len(s) for s in series.values())
    if not count:
        raise BagError(f'bag {os.fspath(path)} holds no fairlead tension of every line')
    stamps = np.array([t for t, _ in series[setup.names[0]][:count]], dtype=np.int64)
    start = int(stamps[0])
    tensions = np.array([[v for _, v in series[n][:count]] for n in setup.names]).T

    def seconds(ns):
        return (np.asarray(ns, dtype=np.int64) - start) / 1e9

    return ArrangementRecord(
        setup, ratings, seconds(stamps), tensions,
        seconds([w[0] for w in wrench]), np.array([w[1] for w in wrench]).reshape(-1, 3),
        np.array([w[2] for w in wrench]).reshape(-1, 3),
        seconds([s[0] for s in ship]), np.array([s[1] for s in ship]).reshape(-1, 3),
        np.array([s[2] for s in ship]), start)


def _shapes_at(path, record: ArrangementRecord, t: float) -> List[np.ndarray]:
    """Return each line's particles at the output nearest t [s] (x, y, z rows)."""
    wanted = record.start_ns + round(t * 1e9)
    best: Dict[str, Tuple[int, np.ndarray]] = {}
    topics = {f'/{line}/rope/particles': line for line in record.setup.names}
    for message in read_messages(path, list(topics)):
        line = topics[message.topic]
        gap = abs(message.publish_time_ns - wanted)
        if line not in best or gap < best[line][0]:
            best[line] = (gap, decode_pose_array(message.data)[3][:, :3])
    return [best[name][1] for name in record.setup.names]


def _hull(record: ArrangementRecord) -> np.ndarray:
    """Return a ship outline in its body frame (x forward, y to port) from its fairleads."""
    offsets = np.array([line.params.fairlead_offset for line in record.setup.lines])
    aft, fore = offsets[:, 0].min() - 6.0, offsets[:, 0].max() + 6.0
    half = np.abs(offsets[:, 1]).max() + 1.5
    shoulder = fore - 0.12 * (fore - aft)
    return np.array([[aft, -half], [shoulder, -half], [fore + 6.0, 0.0], [shoulder, half],
                     [aft, half], [aft, -half]])


def _placed(outline: np.ndarray, position, yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.column_stack([position[0] + c * outline[:, 0] - s * outline[:, 1],
                            position[1] + s * outline[:, 0] + c * outline[:, 1]])


def plot_record(path, out_dir, story: str = '', tensions: str = 'tensions.png',
                plan: str = 'plan.png') -> List[str]:
    """
    Draw tensions.png and plan.png of an arrangement's bag into out_dir.

    :param story: what the run was, a sentence for the top of tensions.png ('' = none).
    :param tensions, plan: the images' file names.
    :returns: the two image paths.
    :raises BagError: see read_record. OSError: an image cannot be written.
    """
    record = read_record(path)
    os.makedirs(os.fspath(out_dir), exist_ok=True)
    tensions = os.path.join(os.fspath(out_dir), tensions)
    plan = os.path.join(os.fspath(out_dir), plan)
    draw_tensions(record, tensions, story)
    draw_plan(path, record, plan)
    return [tensions, plan]


def summary(record: ArrangementRecord) -> str:
    """Return a sentence on the most loaded line: its peak, utilisation and WLL."""
    utilisation = record.tensions / np.array([r.mbl for r in record.ratings])
    i, k = np.unravel_index(int(np.argmax(utilisation)), utilisation.shape)
    rating, name = record.ratings[k], record.setup.names[k]
    peak = record.tensions[i, k]
    verdict = {'ok': 'below', 'above_wll': 'past', 'near_break': 'far past'}[rating.band(peak)]
    return (f'Most loaded: {name}, {peak / 1e3:.0f} kN at t = {record.times[i]:.1f} s = '
            f'{100 * utilisation[i, k]:.0f} % of its MBL ({rating.mbl / 1e3:.0f} kN), '
            f'{verdict} its working load limit ({rating.wll / 1e3:.0f} kN)')


def draw_tensions(record: ArrangementRecord, out_path, story: str = '') -> None:
    """Draw the ship's motion, every line's tension with its WLL and MBL, and the wrench."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    names = record.setup.names
    rows = math.ceil(len(names) / 2)
    figure = Figure(figsize=(12, 4.0 + 2.1 * rows), dpi=100, layout='constrained')
    FigureCanvasAgg(figure)
    figure.suptitle('\n'.join(part for part in (story, summary(record)) if part),
                    fontsize='large')
    grid = figure.add_gridspec(rows + 2, 2, height_ratios=[1.2] + [1.0] * rows + [1.2])
    motion = figure.add_subplot(grid[0, :])
    if len(record.ship_times):
        rest = record.ship_position[0]
        motion.plot(record.ship_times, record.ship_position[:, 0] - rest[0], color='tab:blue',
                    label='surge (x, along the quay) [m]')
        motion.plot(record.ship_times, record.ship_position[:, 1] - rest[1],
                    color='tab:purple', label='sway (y, + towards the quay) [m]')
    motion.axhline(0.0, color='0.6', linewidth=0.8)
    motion.set_ylabel('ship moved [m]')
    motion.set_title('What happened: the ship moved (ship/pose), its lines took the load')
    motion.legend(loc='upper right', fontsize='small')
    motion.grid(True, alpha=0.3)
    limit = max(rating.mbl for rating in record.ratings) * 1.05 / 1e3
    for k, name in enumerate(names):
        axis = figure.add_subplot(grid[1 + k // 2, k % 2], sharex=motion)
        rating = record.ratings[k]
        axis.plot(record.times, record.tensions[:, k] / 1e3, color='tab:blue')
        axis.axhline(rating.wll / 1e3, color='tab:orange', linestyle='--',
                     label=f'WLL {rating.wll / 1e3:.0f} kN')
        axis.axhline(rating.mbl / 1e3, color='tab:red', linestyle='--',
                     label=f'MBL {rating.mbl / 1e3:.0f} kN')
        peak, when = record.peak(k)
        band = rating.band(peak)
        axis.plot([when], [peak / 1e3], 'o', color=COLOURS[band])
        axis.annotate(f'peak {100 * rating.utilisation(peak):.0f} % of MBL', (when, peak / 1e3),
                      textcoords='offset points', xytext=(6, 6), fontsize='small')
        line = record.setup.lines[k].params
        axis.set_title(f'{name}: {line.material} {line.diameter * 1e3:g} mm', fontsize='medium')
        axis.set_ylim(0.0, limit)
        axis.set_ylabel('tension [kN]')
        axis.grid(True, alpha=0.3)
        axis.legend(loc='upper left', fontsize='x-small')
    load = figure.add_subplot(grid[rows + 1, :], sharex=motion)
    if len(record.wrench_times):
        for column, label, colour in ((0, 'Fx (surge)', 'tab:blue'),
                                      (1, 'Fy (sway)', 'tab:purple')):
            load.plot(record.wrench_times, record.force[:, column] / 1e3, color=colour,
                      label=label)
    load.axhline(0.0, color='0.6', linewidth=0.8)
    load.set_ylabel('force [kN]')
    load.set_xlabel('time [s]')
    load.set_title('Total force of the lines on the ship (ship/mooring_wrench, body frame: '
                   'x forward, y to port)')
    load.legend(loc='upper right', fontsize='small')
    load.grid(True, alpha=0.3)
    figure.savefig(os.fspath(out_path))


def draw_plan(path, record: ArrangementRecord, out_path) -> None:
    """Draw the berth from above at the moment of the highest utilisation (see the module)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    names = record.setup.names
    utilisation = record.tensions / np.array([r.mbl for r in record.ratings])
    i, worst = np.unravel_index(int(np.argmax(utilisation)), utilisation.shape)
    t = float(record.times[i])
    shapes, rest = _shapes_at(path, record, t), _shapes_at(path, record, 0.0)
    hull = _hull(record)
    outlines = []
    if len(record.ship_times):
        j = int(np.argmin(np.abs(record.ship_times - t)))
        moved = record.ship_position[j] - record.ship_position[0]
        outlines = [(_placed(hull, record.ship_position[0], record.ship_yaw[0]),
                     dict(color='0.6', linestyle=':', label='ship at rest')),
                    (_placed(hull, record.ship_position[j], record.ship_yaw[j]),
                     dict(color='k', linestyle='-', label=f'ship at t = {t:.1f} s: moved '
                          f'{moved[0]:+.2f} m along, {moved[1]:+.2f} m across'))]
    points = np.concatenate([p[:, :2] for p in shapes + rest] + [o for o, _ in outlines])
    left, right = points[:, 0].min() - 20.0, points[:, 0].max() + 20.0
    bottom, top = points[:, 1].min() - 22.0, max(points[:, 1].max() + 10.0, 15.0)
    width = 14.0
    figure = Figure(figsize=(width, min(max(width * (top - bottom) / (right - left), 4.0),
                                        10.0) + 1.2), dpi=100, layout='constrained')
    FigureCanvasAgg(figure)
    axis = figure.add_subplot(1, 1, 1)
    axis.fill_between([left, right], 0.0, top, color='0.85', zorder=0)
    axis.axhline(0.0, color='0.3', linewidth=1.5, zorder=1)
    axis.text(left + 3.0, top - 5.0, 'quay', fontsize='large', color='0.3')
    for outline, style in outlines:
        axis.plot(outline[:, 0], outline[:, 1], linewidth=1.5, **style)
    for k, name in enumerate(names):
        rating = record.ratings[k]
        tension = record.tensions[i, k]
        band = rating.band(tension)
        axis.plot(rest[k][:, 0], rest[k][:, 1], color='0.7', linewidth=1.0)
        axis.plot(shapes[k][:, 0], shapes[k][:, 1], color=COLOURS[band], linewidth=2.5)
        axis.plot(*shapes[k][0, :2], 's', color='tab:blue', markersize=6)
        axis.plot(*shapes[k][-1, :2], 'o', color='k', markersize=4)
        middle = shapes[k][len(shapes[k]) // 2]
        peak, _ = record.peak(k)
        axis.annotate(f'{name}\n{100 * rating.utilisation(tension):.0f} % '
                      f'(peak {100 * rating.utilisation(peak):.0f} %)', middle[:2],
                      textcoords='offset points', xytext=(0, 9 if k % 2 else -24),
                      ha='center', fontsize='small')
    legend = [Line2D([], [], color=COLOURS['ok'], linewidth=2.5, label='below the WLL'),
              Line2D([], [], color=COLOURS['above_wll'], linewidth=2.5, label='past the WLL'),
              Line2D([], [], color=COLOURS['near_break'], linewidth=2.5,
                     label=f'past {100 * NEAR_BREAK_FRACTION:g} % of the MBL'),
              Line2D([], [], color='0.7', label='lines at rest'),
              Line2D([], [], marker='s', color='tab:blue', linestyle='', label='bollard'),
              Line2D([], [], marker='o', color='k', linestyle='', label='fairlead')]
    handles, _ = axis.get_legend_handles_labels()
    axis.legend(handles=handles + legend, loc='lower left', fontsize='small', ncol=4)
    axis.set_xlim(left, right)
    axis.set_ylim(bottom, top)
    axis.set_aspect('equal', adjustable='box')
    axis.set_xlabel(f'x [m] ({record.setup.shared.frame_id}, along the quay)')
    axis.set_ylabel('y [m]')
    axis.set_title(f'The berth from above at t = {t:.1f} s, the most loaded moment: {names[worst]}'
                   f' at {100 * utilisation[i, worst]:.0f} % of its MBL '
                   '(utilisation = tension / MBL)')
    axis.grid(True, alpha=0.3)
    figure.savefig(os.fspath(out_path), bbox_inches='tight')  # the equal axes leave margins
