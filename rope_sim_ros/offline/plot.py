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
Look at a bag: ``rope_sim info`` (a summary) and ``rope_sim plot`` (pictures), of any bag.

A single line's bag (the mooring_line node's, or ``rope_sim run`` of a line): its fairlead
and bollard tensions over time, the magnitudes of the recorded wrenches' forces at their log
times, with the material's minimum breaking load (MBL) and working load limit (WLL), and a
few rope shapes (x-z) from rope/particles.

An arrangement's bag (the mooring node's): tensions.png, on linear scales, the ship's motion
(ship/pose: surge and sway from where it lay), every line's fairlead tension against its
WLL and its MBL (one panel each, its peak marked with its utilisation), and the total force
of the lines on the ship (ship/mooring_wrench, body frame); plan.png, the berth from above
at the moment of the highest utilisation: the quay, the ship (outlined from its fairleads),
every line coloured by its band (mooring/status.py: green below the WLL, amber past it, red
past 90 % of the MBL) and labelled with its utilisation then and its peak, at rest in grey,
and a passing ship (passing_ship.*) where it is then. event.png (draw_event: the berth
demo's, and `rope_sim plot`'s of a bag holding a passing ship's load) is an event on one
time axis: the loads on the ship in its body axes (a passing ship's, ship/passing_ship_wrench;
the tugs' sway push, ship/external_wrench as the node took it; the fenders' sway force, all
together, <fender>/reaction), the ship's motion from its first pose (surge, sway, yaw) and
every line's tension in % of its MBL against the WLL, with the passing ship's stagger on top.
Every picture over time marks each line-handling command and each quick-release of the bag's
events (the node's, or those of ``rope_sim run --commands``) with a dotted vertical line,
labelled as 'head_1 make fast' or 'let go all' (a command a run refused as 'stern stow
(refused)'). Times are the outputs' stamps (publish times), from the first output; the
arrangement is the one the bag stores. No ROS.
"""

from dataclasses import dataclass, field
import math
import os
import textwrap
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .line_events import event_label
from .resim import stored_setup
from ..bag import bag_info, BagError, BagInfo, read_messages
from ..bag.cdr import (decode_pose_array, decode_pose_stamped, decode_string, decode_wrench,
                       decode_wrench_stamped)
from ..messages.topics import (BOLLARD_TENSION, EXTERNAL_WRENCH, FAIRLEAD_TENSION,
                               FENDER_REACTION, LINE_NODE, MOORING_NODE, MOORING_WRENCH,
                               PARTICLES, PASSING_WRENCH, SHIP_POSE)
from ..model.ship.motions import (against_limits, ANGULAR, motion_ranges, motion_series,
                                  MotionLimits, MOTIONS)
from ..mooring.events import decode_event
from ..mooring.status import COLOURS, NEAR_BREAK_FRACTION, Rating, ratings
from ..params.arrangement import ArrangementParams, single_line
from ..params.ship import PassingShipParams
from ..params.table import LineParams

WRENCH = f'/{MOORING_WRENCH}'
PASSING = f'/{PASSING_WRENCH}'
EXTERNAL = f'/{EXTERNAL_WRENCH}'
EVENTS = f'/{MOORING_NODE.events}'
# The events marked on the time axes: a line-handling command, a quick-release hook's release.
MARKED = ('command', 'released')
MARK_COLOUR = '0.25'
ENDS = ('fairlead', 'bollard')
_TENSION_TOPICS = {'fairlead': FAIRLEAD_TENSION, 'bollard': BOLLARD_TENSION}


@dataclass(frozen=True)
class TensionSeries:
    """
    The tension recorded at one end.

    :param topic: the Wrench topic.
    :param times_ns: log times [ns], shape (n,).
    :param tension: |force| [N], shape (n,).
    """

    topic: str
    times_ns: np.ndarray
    tension: np.ndarray

    def peak(self) -> Tuple[float, int]:
        """Return the largest tension [N] and its log time [ns] (nan, 0 when empty)."""
        if not len(self.tension):
            return float('nan'), 0
        i = int(np.argmax(self.tension))
        return float(self.tension[i]), int(self.times_ns[i])


def tension_namespaces(info: BagInfo) -> List[str]:
    """Return the namespaces ('' = root) with a fairlead or bollard tension topic, sorted."""
    found = set()
    for name in info.topics:
        for relative in _TENSION_TOPICS.values():
            if name.endswith('/' + relative):
                found.add(name[:-len(relative) - 1])
    return sorted(found)


def read_tensions(path, namespace: str = '') -> Dict[str, TensionSeries]:
    """
    Return the tension series of both ends of one line (empty series for a missing topic).

    :raises BagError: the bag cannot be read.
    """
    series = {}
    for end in ENDS:
        topic = f'{namespace}/{_TENSION_TOPICS[end]}'
        times, values = [], []
        for message in read_messages(path, [topic]):
            force, _ = decode_wrench(message.data)
            times.append(message.log_time_ns)
            values.append(float(np.linalg.norm(force)))
        series[end] = TensionSeries(topic, np.array(times, dtype=np.int64),
                                    np.array(values, dtype=float))
    return series


def _seconds(ns: int) -> str:
    return f'{ns / 1e9:.3f} s'


def mark(text: str) -> Optional[str]:
    """Return the label of an event to mark on a time axis (MARKED), else None."""
    try:
        event = decode_event(text)
    except ValueError:
        return None  # not an event of ours: nothing to mark
    if event['event'] not in MARKED:
        return None
    return event_label(event['event'], str(event.get('line', '')), str(event.get('command', '')),
                       bool(event.get('refused', False)))


def read_marks(path, topic: str, start_ns: int) -> List[Tuple[float, str]]:
    """
    Return the commands and releases on a bag's events topic: (time [s], label), in order.

    The time is the event's publish time from start_ns.
    """
    marks = []
    for message in read_messages(path, [topic]):
        label = mark(decode_string(message.data))
        if label is not None:
            marks.append(((message.publish_time_ns - start_ns) / 1e9, label))
    return marks


def draw_marks(marks: Sequence[Tuple[float, str]], axes: Sequence[Any], labelled: Any) -> None:
    """Draw each mark as a dotted vertical line on every axis; its label on `labelled`."""
    for t, label in marks:
        for axis in axes:
            axis.axvline(t, color=MARK_COLOUR, linestyle=':', linewidth=1.0)
        labelled.annotate(label, (t, 1.0), xycoords=('data', 'axes fraction'),
                          textcoords='offset points', xytext=(-2, -3), rotation=90, ha='right',
                          va='top', fontsize='x-small', color=MARK_COLOUR)


def describe(path) -> str:
    """
    Return the text of ``rope_sim info``: topics, counts, duration, peak tensions.

    :raises BagError: path is not a readable bag.
    """
    info = bag_info(path)
    lines = [f'bag:       {os.fspath(path)}'
             + ('' if info.complete else
                f'  (cut short: not closed; `rope_sim recover {os.fspath(path)}` completes it)'),
             f'duration:  {_seconds(info.duration_ns)}  '
             f'(log time {_seconds(info.start_ns)} .. {_seconds(info.end_ns)})',
             f'messages:  {info.message_count}',
             'topics:']
    width = max([len(name) for name in info.topics] + [5])
    type_width = max([len(topic.type_name) for topic in info.topics.values()] + [4])
    for name in sorted(info.topics):
        topic = info.topics[name]
        lines.append(f'  {name:<{width}}  {topic.type_name:<{type_width}}  '
                     f'{topic.message_count:>8d}')
    for namespace in tension_namespaces(info):
        for end, series in read_tensions(path, namespace).items():
            if not len(series.tension):
                continue
            peak, at = series.peak()
            lines.append(
                f'peak {end} tension {series.topic}: {peak:.1f} N at log time {_seconds(at)} '
                f'({_seconds(at - info.start_ns)} after the start)')
    return '\n'.join(lines)


def _shapes(path, namespace: str, count: int,
            start_ns: int) -> List[Tuple[float, np.ndarray]]:
    topic = f'{namespace}/{PARTICLES}'
    messages = list(read_messages(path, [topic]))
    if not messages:
        return []
    picks = sorted(set(np.linspace(0, len(messages) - 1, count).round().astype(int).tolist()))
    shapes = []
    for i in picks:
        poses = decode_pose_array(messages[i].data)[3]
        # on the tension plot's time axis (a node bag's stamps are epoch times)
        stamp = (messages[i].log_time_ns - start_ns) / 1e9
        shapes.append((stamp, poses[:, :3]))
    return shapes


def plot_bag(path, out_path, params: LineParams, namespace: Optional[str] = None,
             shapes: int = 5) -> str:
    """
    Draw a bag's tensions with MBL and WLL, and rope shapes, into a PNG file.

    :param path: the bag.
    :param out_path: the image file to write.
    :param params: parameters giving the material and diameter (for MBL and WLL).
    :param namespace: the line's namespace ('' = root); None = the only one there is.
    :param shapes: how many rope shapes to draw, evenly spaced over the run.
    :returns: the image path.
    :raises BagError: unreadable bag, no tension topics, or several lines and none chosen.
    :raises OSError: the image cannot be written.
    """
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    info = bag_info(path)
    found = tension_namespaces(info)
    if namespace is None:
        if len(found) != 1:
            raise BagError(
                f'bag {os.fspath(path)} has tension topics in '
                f'{len(found) or "no"} namespace(s) {", ".join(repr(n or "/") for n in found)}'
                + ('; choose one with --namespace' if found else '; nothing to plot'))
        namespace = found[0]
    else:
        namespace = '/' + namespace.strip('/') if namespace.strip('/') else ''
        if namespace not in found:
            raise BagError(f'bag {os.fspath(path)} has no tension topics in namespace '
                           f'{namespace or "/"!r}')
    rating = ratings(single_line(params))[0]
    series = read_tensions(path, namespace)

    figure = Figure(figsize=(10, 8), dpi=100, layout='constrained')
    FigureCanvasAgg(figure)
    top, bottom = figure.subplots(2, 1, gridspec_kw={'height_ratios': [3, 2]})
    start = info.start_ns
    peak = 0.0
    for end, colour in zip(ENDS, ('tab:blue', 'tab:green')):
        s = series[end]
        if len(s.tension):
            top.plot((s.times_ns - start) / 1e9, s.tension / 1e3, color=colour,
                     label=f'{end} tension ({s.topic})')
            peak = max(peak, float(s.tension.max()))
    describe_line = f'{params.material} {params.diameter * 1e3:g} mm'
    top.axhline(rating.mbl / 1e3, color='tab:red', linestyle='--',
                label=f'MBL {rating.mbl / 1e3:.0f} kN ({describe_line})')
    top.axhline(rating.wll / 1e3, color='tab:orange', linestyle='--',
                label=f'working load limit {rating.wll / 1e3:.0f} kN')
    if 0.0 < peak < 0.1 * rating.wll:
        # On a linear axis the tension would be a flat line at the bottom.
        top.set_yscale('log')
        top.set_ylabel('tension [kN] (log scale)')
    else:
        top.set_ylabel('tension [kN]')
        top.set_ylim(bottom=0.0)
    draw_marks(read_marks(path, f'{namespace}/{LINE_NODE.events}', start), [top], top)
    top.set_xlabel(f'time since bag start [s] (start at log time {start / 1e9:.3f} s)')
    folder = os.path.normpath(os.fspath(path))
    title = os.path.join(os.path.basename(os.path.dirname(folder)), os.path.basename(folder))
    top.set_title(f'{title}: line tension')
    top.grid(True, which='both', alpha=0.3)
    top.legend(loc='best', fontsize='small')

    drawn = _shapes(path, namespace, shapes, start)
    cmap = matplotlib.colormaps['viridis']
    for k, (stamp, points) in enumerate(drawn):
        bottom.plot(points[:, 0], points[:, 2], '.-', markersize=3,
                    color=cmap(k / max(1, len(drawn) - 1)), label=f't = {stamp:.2f} s')
    bottom.set_xlabel(f'x [m] ({params.frame_id})')
    bottom.set_ylabel('z [m]')
    bottom.set_title('rope shapes (rope/particles)')
    bottom.set_aspect('equal', adjustable='datalim')
    bottom.grid(True, alpha=0.3)
    if drawn:
        bottom.legend(loc='best', fontsize='small')
    else:
        bottom.text(0.5, 0.5, 'no rope/particles recorded', ha='center', va='center',
                    transform=bottom.transAxes)
    figure.savefig(os.fspath(out_path))
    return os.fspath(out_path)


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
    :ivar passing_times: [s], (q,); passing_force (q, 3) [N], passing_moment (q, 3) [N m]:
        a passing ship's load on the ship (body axes, about its origin); empty without one.
    :ivar marks: (time [s], label) of every line-handling command and release (read_marks).
    :ivar push_times: [s], (e,); push_force (e, 3) [N]: the external load on a free ship
        (ship/external_wrench: tugs, thrusters) as the node took it, body axes; empty
        without one.
    :ivar fender_times: [s], (f,); fender_force (f, 3) [N]: the fenders' force on the ship,
        all together, body axes; empty without fenders.
    :ivar ship_orientation: the ship's orientation at ship_times, (p, 4) (x, y, z, w).
    """

    setup: ArrangementParams
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
    passing_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    passing_force: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    passing_moment: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    marks: Tuple[Tuple[float, str], ...] = ()
    push_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    push_force: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    fender_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    fender_force: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    ship_orientation: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))

    def peak(self, k: int) -> Tuple[float, float]:
        """Return line k's largest tension [N] and its time [s]."""
        i = int(np.argmax(self.tensions[:, k]))
        return float(self.tensions[i, k]), float(self.times[i])


def read_record(path, setup: Optional[ArrangementParams] = None) -> ArrangementRecord:
    """
    Read an arrangement's bag (its stored arrangement unless `setup` is given).

    :raises BagError: unreadable, not an arrangement's bag, or no line tension recorded.
    """
    setup = setup or stored_setup(path)
    if setup is None or setup.single:
        raise BagError(f'bag {os.fspath(path)} stores no arrangement (it was not recorded '
                       'by the mooring node)')
    series: Dict[str, List[Tuple[int, float]]] = {line: [] for line in setup.names}
    topics = {f'/{line}/{FAIRLEAD_TENSION}': line for line in setup.names}
    fenders = {f'/{fender.name}/{FENDER_REACTION}' for fender in setup.fenders}
    wrench, ship, passing, events, pushes = [], [], [], [], []
    fender_sums: Dict[int, np.ndarray] = {}
    for message in read_messages(path, [*topics, WRENCH, PASSING, f'/{SHIP_POSE}', EVENTS,
                                        EXTERNAL, *fenders]):
        if message.topic in fenders:
            sec, nanosec, _, force, _ = decode_wrench_stamped(message.data)
            stamp = sec * 1_000_000_000 + nanosec
            fender_sums[stamp] = fender_sums.get(stamp, 0.0) + np.asarray(force)
        elif message.topic == EXTERNAL:  # taken when the node logged it
            _, _, frame, force, _ = decode_wrench_stamped(message.data)
            pushes.append((message.publish_time_ns, force, frame == setup.ship_frame_id))
        elif message.topic == EVENTS:
            label = mark(decode_string(message.data))
            if label is not None:
                events.append((message.publish_time_ns, label))
        elif message.topic in topics:
            force, _ = decode_wrench(message.data)
            series[topics[message.topic]].append(
                (message.publish_time_ns, float(np.linalg.norm(force))))
        elif message.topic in (WRENCH, PASSING):
            sec, nanosec, _, force, moment = decode_wrench_stamped(message.data)
            (wrench if message.topic == WRENCH else passing).append(
                (sec * 1_000_000_000 + nanosec, force, moment))
        else:
            sec, nanosec, _, position, q = decode_pose_stamped(message.data)
            yaw = math.atan2(2.0 * (q[3] * q[2] + q[0] * q[1]),
                             1.0 - 2.0 * (q[1] ** 2 + q[2] ** 2))
            ship.append((sec * 1_000_000_000 + nanosec, position, yaw, q))
    count = min(len(s) for s in series.values())
    if not count:
        raise BagError(f'bag {os.fspath(path)} holds no fairlead tension of every line')
    stamps = np.array([t for t, _ in series[setup.names[0]][:count]], dtype=np.int64)
    start = int(stamps[0])
    tensions = np.array([[v for _, v in series[n][:count]] for n in setup.names]).T

    def seconds(ns):
        return (np.asarray(ns, dtype=np.int64) - start) / 1e9

    ship_times = seconds([s[0] for s in ship])
    yaws = np.unwrap([s[2] for s in ship])

    def body(times, forces, turn=True):
        """Return frame_id forces at these times [s] in the ship's body axes then."""
        forces = np.array(forces, dtype=float).reshape(-1, 3)
        if not len(ship_times):
            return forces
        yaw = np.interp(times, ship_times, yaws) * turn
        c, s = np.cos(yaw), np.sin(yaw)
        return np.column_stack([c * forces[:, 0] + s * forces[:, 1],
                                -s * forces[:, 0] + c * forces[:, 1], forces[:, 2]])

    push_times = seconds([p[0] for p in pushes])
    fender_times = seconds(sorted(fender_sums))
    return ArrangementRecord(
        setup, ratings(setup), seconds(stamps), tensions,
        seconds([w[0] for w in wrench]), np.array([w[1] for w in wrench]).reshape(-1, 3),
        np.array([w[2] for w in wrench]).reshape(-1, 3),
        seconds([s[0] for s in ship]), np.array([s[1] for s in ship]).reshape(-1, 3),
        np.array([s[2] for s in ship]), start,
        seconds([p[0] for p in passing]), np.array([p[1] for p in passing]).reshape(-1, 3),
        np.array([p[2] for p in passing]).reshape(-1, 3),
        tuple((float(seconds(ns)), label) for ns, label in events),
        push_times, body(push_times, [p[1] for p in pushes], np.array([not p[2] for p in pushes],
                                                                      dtype=bool)),
        fender_times, body(fender_times, [fender_sums[k] for k in sorted(fender_sums)]),
        np.array([s[3] for s in ship], dtype=float).reshape(-1, 4))


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
                plan: str = 'plan.png', setup: Optional[ArrangementParams] = None,
                event: str = 'event.png') -> List[str]:
    """
    Draw tensions.png and plan.png of an arrangement's bag into out_dir, and event.png.

    event.png (draw_event) only of a bag holding a passing ship's load on the ship: the
    cause of what the tensions show.

    :param story: what the run was, a sentence for the top of tensions.png ('' = none).
    :param tensions, plan, event: the images' file names.
    :param setup: the arrangement (default: the one the bag stores).
    :returns: the image paths.
    :raises BagError: see read_record. OSError: an image cannot be written.
    """
    record = read_record(path, setup)
    paths = _plot_with_plan(path, record, out_dir, draw_tensions, tensions, story, plan)
    if len(record.passing_times):
        paths.append(os.path.join(os.fspath(out_dir), event))
        draw_event(record, paths[-1], story)
    return paths


def plot_event(path, out_dir, story: str = '', event: str = 'event.png',
               plan: str = 'plan.png', setup: Optional[ArrangementParams] = None) -> List[str]:
    """
    Draw event.png (draw_event) and plan.png of an arrangement's bag into out_dir.

    Arguments and errors as plot_record's.
    """
    return _plot_with_plan(path, read_record(path, setup), out_dir, draw_event, event, story,
                           plan)


def _plot_with_plan(path, record: ArrangementRecord, out_dir, draw, name: str, story: str,
                    plan: str) -> List[str]:
    """Draw draw(record, out_dir/name, story) and the plan view; return both paths."""
    os.makedirs(os.fspath(out_dir), exist_ok=True)
    first = os.path.join(os.fspath(out_dir), name)
    plan = os.path.join(os.fspath(out_dir), plan)
    draw(record, first, story)
    draw_plan(path, record, plan)
    return [first, plan]


def stagger(passing: PassingShipParams, t) -> np.ndarray:
    """
    Return a passing ship's stagger [m] at times t [s] (0 = the mooring's start).

    Its midship's place along the moored ship's start heading from the moored ship's start
    position, + ahead: its track as the loads take it (model/ship/loads.py).
    """
    return passing.start_x + passing.direction * passing.speed * np.asarray(t, dtype=float)


def abeam_time(passing: PassingShipParams) -> Optional[float]:
    """Return when a passing ship's midship is abeam of the moored ship's start [s], or None."""
    if not passing.present or passing.start_x * passing.direction > 0.0:
        return None  # no passing ship, or one moving away
    return -passing.start_x * passing.direction / passing.speed


def ship_offsets(record: ArrangementRecord) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """
    Return the ship's surge and sway [m] and yaw [deg] from its first recorded pose.

    Surge and sway in that pose's body axes (x forward, y to port), each (p,).
    """
    if not len(record.ship_times):
        empty = np.zeros(0)
        return empty, empty, empty
    moved = record.ship_position[:, :2] - record.ship_position[0, :2]
    c, s = math.cos(record.ship_yaw[0]), math.sin(record.ship_yaw[0])
    yaw = np.unwrap(record.ship_yaw)
    return (c * moved[:, 0] + s * moved[:, 1], -s * moved[:, 0] + c * moved[:, 1],
            np.degrees(yaw - yaw[0]))


def line_kinds(record: ArrangementRecord) -> List[str]:
    """
    Return each line's kind from its lead at the first pose: 'breast', 'spring' or 'end'.

    A breast line leads more across the ship than along it; a spring leads along it towards
    midships (its bollard nearer amidships than its fairlead); head and stern lines ('end')
    lead along it away from midships.
    """
    ship = record.setup.ship
    position, yaw = ship.start_position, ship.start_yaw
    if len(record.ship_times):
        position, yaw = record.ship_position[0], record.ship_yaw[0]
    c, s = math.cos(yaw), math.sin(yaw)
    kinds = []
    for line in record.setup.lines:
        offset = line.params.fairlead_offset
        fairlead = (position[0] + c * offset[0] - s * offset[1],
                    position[1] + s * offset[0] + c * offset[1])
        lead = np.subtract(line.params.bollard_position[:2], fairlead)
        along, across = c * lead[0] + s * lead[1], -s * lead[0] + c * lead[1]
        if abs(across) > abs(along):
            kinds.append('breast')
        else:
            kinds.append('spring' if along * offset[0] < 0.0 else 'end')
    return kinds


def _zero_in_the_middle(*axes) -> None:
    """Give each axis limits symmetric about 0: a twin axis's 0 then lies on its parent's."""
    for axis in axes:
        reach = max(abs(limit) for limit in axis.get_ylim()) or 1.0
        axis.set_ylim(-reach, reach)


def draw_event(record: ArrangementRecord, out_path, story: str = '') -> None:
    """Draw the loads on the ship, its motion and the lines' tensions (module)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(12, 11), dpi=100, layout='constrained')
    FigureCanvasAgg(figure)
    figure.suptitle('\n'.join(textwrap.fill(part, 130) for part in (story, summary(record))
                              if part), fontsize='medium', fontweight='bold')
    force, motion, tension = figure.subplots(3, 1, sharex=True,
                                             gridspec_kw=dict(height_ratios=[1.0, 1.0, 1.5]))
    passing = record.setup.passing
    if len(record.passing_times):
        force.plot(record.passing_times, record.passing_force[:, 0] / 1e3, color='tab:blue',
                   label='passing ship: surge force Fx (+ ahead)')
        force.plot(record.passing_times, record.passing_force[:, 1] / 1e3, color='tab:purple',
                   label='passing ship: sway force Fy (+ to port)')
    if len(record.push_times):  # each load holds until the next
        force.step(np.append(record.push_times, record.times[-1]),
                   np.append(record.push_force[:, 1], record.push_force[-1, 1]) / 1e3,
                   where='post', color='tab:green', label="tugs' sway push (ship/external_wrench)")
    if np.any(record.fender_force):
        force.plot(record.fender_times, record.fender_force[:, 1] / 1e3, color='tab:brown',
                   linewidth=0.9, label="fenders' sway force, all")
    handles = force.get_lines()
    if len(record.passing_times):
        moment = force.twinx()
        moment.plot(record.passing_times, record.passing_moment[:, 2] / 1e6, color='0.45',
                    linestyle=':', label='passing ship: yaw moment Mz (+ bow to port)')
        moment.set_ylabel('yaw moment [MN m]')
        _zero_in_the_middle(force, moment)
        handles += moment.get_lines()
    if handles:  # (the top is for the marks' labels)
        force.legend(handles=handles, loc='lower left', fontsize='small')
    else:
        force.text(0.5, 0.5, 'no passing ship, tugs or fenders recorded',
                   transform=force.transAxes, ha='center', color='0.4')
    force.axhline(0.0, color='0.6', linewidth=0.8)
    force.set_ylabel('force [kN]')
    force.set_title("The loads on the ship, body axes: a passing ship's "
                    "(ship/passing_ship_wrench), the tugs', the fenders'")
    if passing.present:
        v = passing.direction * passing.speed
        top = force.secondary_xaxis('top', functions=(lambda t: stagger(passing, t),
                                                      lambda x: (x - passing.start_x) / v))
        top.set_xlabel(f'passing ship ({passing.length:g} m at {passing.speed:g} m/s, '
                       f'{passing.separation:g} m off her start): its midship ahead of the '
                       "moored ship's [m]")

    surge, sway, yaw = ship_offsets(record)
    if len(surge):
        motion.plot(record.ship_times, surge, color='tab:blue', label='surge (+ ahead) [m]')
        motion.plot(record.ship_times, sway, color='tab:purple',
                    label='sway (+ to port) [m]')
        turn = motion.twinx()
        turn.plot(record.ship_times, yaw, color='0.45', linestyle=':',
                  label='yaw (+ bow to port) [deg]')
        turn.set_ylabel('yaw [deg]')
        _zero_in_the_middle(motion, turn)
        motion.legend(handles=motion.get_lines() + turn.get_lines(), loc='upper left',
                      fontsize='small')
    motion.axhline(0.0, color='0.6', linewidth=0.8)
    motion.set_ylabel('moved [m]')
    motion.set_title("The ship's motion from where it lay (ship/pose, in its axes then)")

    kinds = line_kinds(record)
    styles = {'spring': dict(linewidth=2.2), 'breast': dict(linewidth=1.2, linestyle='--'),
              'end': dict(linewidth=0.9)}
    mbl = np.array([rating.mbl for rating in record.ratings])
    share = 100.0 * record.tensions / mbl
    for k, name in enumerate(record.setup.names):
        tension.plot(record.times, share[:, k], label=f'{name} ({kinds[k]})', **styles[kinds[k]])
    limits = sorted({round(100.0 * r.wll / r.mbl, 1) for r in record.ratings
                     if math.isfinite(r.mbl) and r.mbl > 0.0})
    for limit in limits:
        tension.axhline(limit, color='tab:red', linestyle='--', linewidth=1.2)
        tension.annotate(f'WLL ({limit:g} % of MBL)', (1.0, limit), xycoords=('axes fraction',
                         'data'), textcoords='offset points', xytext=(-4, 3), ha='right',
                         color='tab:red', fontsize='small')
    tension.set_ylim(0.0, max([1.15 * float(np.nanmax(share))] + [1.15 * x for x in limits]))
    tension.set_ylabel('tension [% of MBL]')
    tension.set_xlabel('time [s]')
    tension.set_title("Every line's fairlead tension (springs thick, breast lines dashed, head "
                      'and stern lines thin)')
    tension.legend(loc='upper left', fontsize='small', ncol=4)
    when = abeam_time(passing)
    for axis in (force, motion, tension):
        axis.grid(True, alpha=0.3)
        if when is not None and when <= record.times[-1]:
            axis.axvline(when, color='0.3', linestyle='-.', linewidth=1.0)
    if when is not None and when <= record.times[-1]:
        force.annotate('abeam', (when, 1.0), xycoords=('data', 'axes fraction'),
                       textcoords='offset points', xytext=(3, -12), fontsize='small')
    draw_marks(record.marks, [force, motion, tension], force)
    figure.savefig(os.fspath(out_path))


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
    timed = [motion]
    for k, name in enumerate(names):
        axis = figure.add_subplot(grid[1 + k // 2, k % 2], sharex=motion)
        timed.append(axis)
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
    draw_marks(record.marks, timed + [load], motion)
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
    passer = _passing_outline(record, t)
    if passer is not None:
        outline, track, _ = passer
        near = outline[(outline[:, 0] >= left) & (outline[:, 0] <= right)]
        points = np.concatenate([points, track, near])
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
    if passer is not None:
        _draw_passing(axis, record, passer, left, right)
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


def _passing_outline(record: ArrangementRecord, t: float):
    """
    Return a passing ship's outline at time t, its track (2 points) and stagger, or None.

    Its track runs along the moored ship's start heading, separation off its start position
    (model/ship/loads.py); frame_id x, y rows.
    """
    passing, ship = record.setup.passing, record.setup.ship
    if not passing.present:
        return None
    half, beam = 0.5 * passing.length, 0.5 * passing.beam
    shoulder = half - 0.15 * passing.length
    outline = np.array([[-half, -beam], [shoulder, -beam], [half, 0.0], [shoulder, beam],
                        [-half, beam], [-half, -beam]])
    outline[:, 0] *= passing.direction  # its bow where it goes
    ahead = float(stagger(passing, t))
    yaw = ship.start_yaw
    start = np.asarray(ship.start_position[:2], dtype=float)
    across = np.array([math.sin(yaw), -math.cos(yaw)]) * passing.separation  # to starboard
    along = np.array([math.cos(yaw), math.sin(yaw)])
    midship = start + across + ahead * along
    track = np.array([start + across - 1.0e4 * along, start + across + 1.0e4 * along])
    return _placed(outline, midship, yaw), track, ahead


def _draw_passing(axis, record: ArrangementRecord, passer, left: float, right: float) -> None:
    """Draw the passing ship's track and the ship (or where it is, when off the plan)."""
    outline, track, ahead = passer
    passing = record.setup.passing
    axis.plot(track[:, 0], track[:, 1], color='tab:cyan', linestyle='--', linewidth=0.8)
    inside = (outline[:, 0] >= left) & (outline[:, 0] <= right)
    label = (f'passing ship: {passing.length:g} m at {passing.speed:g} m/s, '
             f'{passing.separation:g} m off her start, {abs(ahead):.0f} m '
             f'{"ahead" if ahead >= 0.0 else "astern"}')
    if inside.any():  # on the plan (the axes clip what sticks out)
        axis.fill(outline[:, 0], outline[:, 1], color='tab:cyan', alpha=0.35, label=label)
        axis.plot(outline[:, 0], outline[:, 1], color='tab:cyan', linewidth=1.2)
        return
    edge = (right - 4.0, 'right') if outline[:, 0].min() > right else (left + 4.0, 'left')
    y = float(np.interp(edge[0], *track[np.argsort(track[:, 0])].T))
    arrow = '\u2192' if edge[1] == 'right' else '\u2190'
    text = f'{label} {arrow}' if edge[1] == 'right' else f'{arrow} {label}'
    axis.annotate(text, (edge[0], y), textcoords='offset points', xytext=(0, 5),
                  ha=edge[1], fontsize='small', color='tab:blue')


def describe_lines(path) -> str:
    """
    Return each line's peak tension, utilisation and band of an arrangement's bag.

    :raises BagError: not an arrangement's bag, or unreadable.
    """
    record = read_record(path)
    rows = ['lines (peak fairlead tension, % of MBL, against the WLL):']
    width = max(len(name) for name in record.setup.names)
    for k, name in enumerate(record.setup.names):
        peak, when = record.peak(k)
        rating = record.ratings[k]
        rows.append(f'  {name:<{width}}  {peak / 1e3:9.1f} kN at {when:8.2f} s  '
                    f'{100 * rating.utilisation(peak):5.1f} % of MBL {rating.mbl / 1e3:.0f} kN  '
                    f'{"PAST" if peak >= rating.wll else "below"} the WLL '
                    f'{rating.wll / 1e3:.0f} kN')
    if len(record.wrench_times):
        horizontal = np.hypot(record.force[:, 0], record.force[:, 1])
        i = int(np.argmax(horizontal))
        fx, fy = record.force[i, :2] / 1e3
        rows.append(f'peak horizontal force on the ship: {horizontal[i] / 1e3:.1f} kN at '
                    f'{record.wrench_times[i]:.2f} s (body frame: Fx {fx:.1f}, Fy {fy:.1f} kN)')
    if len(record.ship_times) > 1:
        rows.extend(describe_motions(record.ship_position, record.ship_orientation,
                                     record.setup.ship.motion_limits))
    return '\n'.join(rows)


def describe_motions(positions: np.ndarray, orientations: np.ndarray,
                     criteria: MotionLimits) -> List[str]:
    """Return the rows that hold a ship's motions over its poses to the criteria's limits."""
    ranges = motion_ranges(motion_series(positions, orientations))
    shares, largest = against_limits(ranges, criteria)
    rows = [f'ship motions against PIANC (1995) for a {criteria.ship}, {criteria.handling}:']
    for name in MOTIONS:
        scale, unit = (180.0 / math.pi, 'deg') if name in ANGULAR else (1.0, 'm')
        kind = 'zero to peak' if name == 'sway' else 'peak to peak'
        limit = criteria.limits[name]
        against = ('no limit given' if limit is None else
                   f'limit {limit * scale:.1f} {unit}: {100 * shares[name]:5.1f} %')
        rows.append(f'  {name:<6} {ranges[name] * scale:7.2f} {unit:<3} {kind}   {against}')
    worst = max((n for n in MOTIONS if shares[n] is not None), key=lambda n: shares[n],
                default=None)
    if worst is None:
        rows.append('cargo handling: no limit given for this ship')
    elif largest < 1.0:
        rows.append(f'cargo handling can go on: every motion within its limit (the largest '
                    f'share {100 * largest:.0f} %, {worst})')
    else:
        rows.append(f'cargo handling stops: {worst} at {100 * largest:.0f} % of its limit')
    return rows
