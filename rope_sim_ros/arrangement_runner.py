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
The offline commands of an arrangement: `rope_sim run`, `resim` and `info` of many lines.

The ship's poses go into one mooring_driver.MooringDriver, the node's own rules, in stamp
order (with the bollard poses of a ship-to-ship bag), each stream taken for finished after
its last sample; outputs every 1 / rate s from the first ship pose to the last. Each output
goes to OUT.csv (OUT_COLUMNS, then each line's LINE_COLUMNS: NAME_tension, ...,
NAME_parted) and/or a bag with the topics, types and stamps the mooring node records
(log time = publish time = the output stamp). The node's clock decisions (mooring/events:
a silent stream, a skip, a reset) are not replayed: a bag of a steady stream re-simulates
to the node's own outputs.

SHIP.csv has a header: `t` [s], the ship's origin `x, y, z` [m] in frame_id, and its
orientation as `qx, qy, qz, qw`, or as `yaw` [rad] (about z; roll and pitch zero), or
neither (heading along x). No ROS here.
"""

import csv
from dataclasses import dataclass, field
import math
import os
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .arrangement_plot import stored_arrangement
from .bag import BagError, read_messages
from .bag.cdr import decode_pose_stamped, decode_wrench
from .line_driver import PARTED_TOPIC
from .line_status import Rating
from .model.frames import lines_tangent_quaternions, pose_point, split_ns
from .mooring_driver import MooringDriver, MooringPublished, SHIP
from .motion import MotionError
from .params import arrangement
from .params.files import read_params_file
from .params.materials import load_materials
from .params.table import ParameterError
from .runner import pose_stamped_cdr, wrench_cdr

SHIP_POSE = '/ship/pose'
WRENCH = '/ship/mooring_wrench'
WORLD_WRENCH = '/ship/mooring_wrench_world'
POSE_TYPE = 'geometry_msgs/msg/PoseStamped'
OUT_COLUMNS = ('t', 'force_x', 'force_y', 'force_z', 'moment_x', 'moment_y', 'moment_z')
# Each line's columns, after OUT_COLUMNS: the tensions, the utilisation, and as the single-line
# OUT.csv (motion.OUT_COLUMNS) the peaks since the previous row, the length and parted (0, 1).
LINE_COLUMNS = ('tension', 'bollard_tension', 'utilisation', 'fairlead_peak_tension',
                'bollard_peak_tension', 'line_length', 'parted')
# Each line's Float64 topics, as the node publishes them.
FLOAT_TOPICS = ('fairlead/peak_tension', 'bollard/peak_tension', 'winch/length')
QUATERNION = ('qx', 'qy', 'qz', 'qw')
DEFAULT_RATE = 100.0


@dataclass(frozen=True)
class ShipMotion:
    """
    The ship's poses: t [s] (n,), t_ns (n,) [ns], position (n, 3) [m], orientation (n, 4).

    :ivar bollards: {line: (t_ns (m,), points (m, 3))} of bollards that move (a bag's).
    """

    path: str
    t_ns: np.ndarray
    position: np.ndarray
    orientation: np.ndarray
    bollards: Dict[str, Tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)

    def __len__(self) -> int:
        """Return the number of ship poses."""
        return len(self.t_ns)


@dataclass
class ArrangementSummary:
    """What an offline arrangement run did: rows, times [s], restarts and holds by line."""

    rows: int = 0
    start: float = math.nan
    end: float = math.nan
    restarts: List[Tuple[float, str, str]] = field(default_factory=list)
    beyond_reach: Dict[str, float] = field(default_factory=dict)
    wall: float = 0.0


def load_arrangement(path, overrides: Optional[Dict[str, Any]] = None
                     ) -> arrangement.ArrangementParams:
    """
    Read an arrangement's parameter file, `--set` overrides on top (head_1.length=40).

    :raises ParameterError: unreadable file, no `mooring:` section, or a bad value.
    """
    values = arrangement.flatten(read_params_file(path, arrangement.NODE_NAME))
    values.update(overrides or {})
    return arrangement.from_values(values)


def with_overrides(setup: arrangement.ArrangementParams,
                   overrides: Optional[Dict[str, Any]]) -> arrangement.ArrangementParams:
    """Return a stored arrangement with `--set` overrides applied."""
    if not overrides:
        return setup
    values = arrangement.flatten(setup.values())
    values.update(overrides)
    return arrangement.from_values(values)


def is_arrangement_file(path) -> bool:
    """
    Tell whether a parameter file holds an arrangement: `lines` for the mooring node.

    A `/**:` section reaches every node: it is an arrangement only with `lines` in it.
    """
    try:
        return arrangement.LINES in read_params_file(path, arrangement.NODE_NAME)
    except ParameterError:
        return False


def read_ship_motion(path) -> ShipMotion:
    """
    Read SHIP.csv (see the module docstring).

    :raises MotionError: unreadable, a column missing, a cell not a finite number, t not
        increasing, a zero quaternion; named with the file, row and column.
    """
    try:
        with open(path, newline='', encoding='utf-8') as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise MotionError(f'{path}: cannot read: {e.strerror}') from None
    if not rows:
        raise MotionError(f'{path}: empty file; expected a header with t, x, y, z')
    header = [name.strip() for name in rows[0]]
    missing = [name for name in ('t', 'x', 'y', 'z') if name not in header]
    if missing:
        raise MotionError(f'{path}: header {header} lacks {", ".join(missing)}; expected t, '
                          'x, y, z and optionally qx, qy, qz, qw or yaw')
    quaternion = all(name in header for name in QUATERNION)
    columns = ['t', 'x', 'y', 'z'] + (list(QUATERNION) if quaternion else
                                      ['yaw'] if 'yaw' in header else [])
    index = [header.index(name) for name in columns]
    values = np.empty((len(rows) - 1, len(columns)))
    for r, row in enumerate(rows[1:]):
        for c, (name, i) in enumerate(zip(columns, index)):
            try:
                values[r, c] = float(row[i])
            except (IndexError, ValueError):
                values[r, c] = math.nan
            if not math.isfinite(values[r, c]):
                raise MotionError(f'{path}: data row {r + 1} (line {r + 2}), column {name!r}: '
                                  f'{row[i] if i < len(row) else "missing"!r} is not a finite '
                                  'number')
    if not len(values):
        raise MotionError(f'{path}: no data rows')
    t_ns = np.round(values[:, 0] * 1e9).astype(np.int64)
    if len(t_ns) > 1 and not (np.diff(t_ns) > 0).all():
        r = int(np.flatnonzero(np.diff(t_ns) <= 0)[0]) + 2
        raise MotionError(f"{path}: data row {r} (line {r + 1}), column 't': times must "
                          'increase strictly')
    if quaternion:
        orientation = values[:, 4:8]
        if (np.linalg.norm(orientation, axis=1) < 1e-6).any():
            r = int(np.flatnonzero(np.linalg.norm(orientation, axis=1) < 1e-6)[0]) + 1
            raise MotionError(f'{path}: data row {r} (line {r + 1}): zero quaternion')
    else:
        yaw = values[:, 4] if 'yaw' in columns else np.zeros(len(values))
        orientation = np.column_stack([np.zeros(len(yaw)), np.zeros(len(yaw)),
                                       np.sin(yaw / 2.0), np.cos(yaw / 2.0)])
    return ShipMotion(os.fspath(path), t_ns, values[:, 1:4], orientation)


def simulate(setup: arrangement.ArrangementParams, ship: ShipMotion, rate: float,
             sinks: Sequence[Callable[[MooringPublished], None]] = (),
             progress: Optional[Callable[[int, int, float], None]] = None,
             materials: Any = None) -> ArrangementSummary:
    """
    Run the arrangement through the ship's poses; hand every output to the sinks.

    :raises ParameterError: a bad rate, or a pretension no length gives at the first pose.
    :raises TrajectoryError, PoseError: a pose is not usable.
    """
    wall = time.monotonic()
    driver = MooringDriver(setup, materials, rate=rate, history=math.inf)
    names = driver.mooring.names
    order = sorted([(int(ns), 1, SHIP, i) for i, ns in enumerate(ship.t_ns.tolist())]
                   + [(int(ns), 0, line, i) for line, (stamps, _) in ship.bollards.items()
                      for i, ns in enumerate(stamps.tolist())])
    counts = {SHIP: len(ship), **{line: len(s[0]) for line, s in ship.bollards.items()}}
    last_ns = int(ship.t_ns[-1])
    total = int(math.floor((last_ns - int(ship.t_ns[0])) / 1e9 * rate + 1e-9)) + 1
    summary = ArrangementSummary()

    def take(report) -> None:
        for published in report.outputs:
            t = published.output.t
            if summary.rows == 0:
                summary.start = t
            summary.rows += 1
            summary.end = t
            advance = published.advance
            if advance is not None:
                summary.restarts += [(t, names[k], why) for k, why in advance.restarted.items()]
                for k, distance in advance.beyond_reach.items():
                    summary.beyond_reach[names[k]] = max(
                        summary.beyond_reach.get(names[k], 0.0), distance)
            for sink in sinks:
                sink(published)
            if progress is not None:
                progress(summary.rows, max(total, summary.rows), t)

    for ns, _, stream, i in order:
        if stream == SHIP:
            driver.push_ship(ns, ship.position[i], ship.orientation[i])
        else:
            driver.push_bollard(stream, ns, ship.bollards[stream][1][i])
        if i == counts[stream] - 1:
            driver.silence(stream)  # its last sample: nothing more to wait for
        if driver.started:
            take(driver.advance(driver.seconds(last_ns), max_lag=math.inf))
    take(driver.advance(driver.seconds(last_ns), max_lag=math.inf))
    summary.wall = time.monotonic() - wall
    return summary


class ArrangementBag:
    """Records an offline run as the mooring node does: the poses in, every output."""

    QUEUE_SIZE = 20000

    def __init__(self, path, setup: arrangement.ArrangementParams, ship: ShipMotion):
        """Create the bag (refusing an existing non-empty directory) and its topics."""
        from .bag import BagWriter
        self.setup = setup
        self.frame_id = setup.shared.frame_id
        self.writer = BagWriter(path, queue_size=self.QUEUE_SIZE, custom_data={
            arrangement.PARAMETERS_KEY: arrangement.parameters_yaml(setup)})
        self._inputs = sorted(
            [(int(ns), SHIP_POSE, pose_stamped_cdr_full(ns, self.frame_id, p, q))
             for ns, p, q in zip(ship.t_ns.tolist(), ship.position, ship.orientation)]
            + [(int(ns), f'/{line}/bollard/pose', pose_stamped_cdr(ns, self.frame_id, point))
               for line, (stamps, points) in ship.bollards.items()
               for ns, point in zip(stamps.tolist(), points)], key=lambda item: item[0])
        self._next = 0
        self.writer.add_topic(SHIP_POSE, POSE_TYPE)
        for line in ship.bollards:
            self.writer.add_topic(f'/{line}/bollard/pose', POSE_TYPE)
        for line in setup.names:
            self.writer.add_topic(f'/{line}/rope/particles', 'geometry_msgs/msg/PoseArray')
            for end in ('fairlead', 'bollard'):
                self.writer.add_topic(f'/{line}/{end}/tension', 'geometry_msgs/msg/Wrench')
            for relative in FLOAT_TOPICS:
                self.writer.add_topic(f'/{line}/{relative}', 'std_msgs/msg/Float64')
            self.writer.add_topic(f'/{line}/{PARTED_TOPIC}', 'std_msgs/msg/Bool')
        self._parted_said: List[Optional[bool]] = [None] * len(setup.names)
        for topic in (WRENCH, WORLD_WRENCH):
            self.writer.add_topic(topic, 'geometry_msgs/msg/WrenchStamped')

    def _write(self, topic: str, data: bytes, ns: int) -> None:
        while not self.writer.write(topic, data, ns):  # offline: wait for room, never drop
            if self.writer.error is not None:
                raise self.writer.error
            if self.writer.closed:
                raise BagError(f'bag {self.writer.path} was closed during the run')
            time.sleep(0.001)

    def _write_inputs(self, until_ns: float) -> None:
        while self._next < len(self._inputs) and self._inputs[self._next][0] <= until_ns:
            ns, topic, data = self._inputs[self._next]
            self._write(topic, data, ns)
            self._next += 1

    def __call__(self, published: MooringPublished) -> None:
        """Record the inputs up to the output's stamp, then the output."""
        from .bag import cdr
        ns, out = published.stamp_ns, published.output
        self._write_inputs(ns)
        sec, nanosec = split_ns(ns)
        positions = np.concatenate(out.positions)
        starts = np.cumsum([0] + [len(x) for x in out.positions])
        poses = np.concatenate([positions, lines_tangent_quaternions(positions, starts)], 1)
        for k, line in enumerate(self.setup.names):
            self._write(f'/{line}/rope/particles',
                        cdr.pose_array(sec, nanosec, self.frame_id,
                                       poses[starts[k]:starts[k + 1]]), ns)
            self._write(f'/{line}/fairlead/tension',
                        wrench_cdr(out.fairlead_forces[k], published.levers[k]), ns)
            self._write(f'/{line}/bollard/tension', wrench_cdr(out.bollard_forces[k]), ns)
            for relative, value in zip(FLOAT_TOPICS, (out.fairlead_peaks[k],
                                                      out.bollard_peaks[k], out.line_lengths[k])):
                self._write(f'/{line}/{relative}', cdr.float64(value), ns)
            parted = bool(out.parted[k])
            if parted is not self._parted_said[k]:  # as the node: when it changes
                self._parted_said[k] = parted
                self._write(f'/{line}/{PARTED_TOPIC}', cdr.boolean(parted), ns)
        world = published.world_wrench()
        for topic, frame, (force, moment) in (
                (WRENCH, self.setup.ship_frame_id, (published.force, published.moment)),
                (WORLD_WRENCH, self.frame_id, world)):
            self._write(topic, cdr.wrench_stamped(sec, nanosec, frame, force, moment), ns)

    def close(self, complete: bool = True) -> None:
        """Record the remaining inputs (if complete) and complete the bag."""
        try:
            if complete:
                self._write_inputs(math.inf)
        finally:
            self.writer.close()


def pose_stamped_cdr_full(ns: int, frame_id: str, position, orientation) -> bytes:
    """Return a PoseStamped of a full pose (position and orientation) as CDR bytes."""
    from .bag import cdr
    sec, nanosec = split_ns(ns)
    return cdr.pose_stamped(sec, nanosec, frame_id, [*map(float, position),
                                                     *map(float, orientation)])


def run_ship_motion(setup: arrangement.ArrangementParams, ship: ShipMotion, out_path=None,
                    rate: float = DEFAULT_RATE, bag_path=None,
                    progress=None) -> ArrangementSummary:
    """
    Run a ship motion through the arrangement: OUT.csv rows and/or a bag.

    :raises BagError: the bag directory exists and is not empty, or recording failed.
    :raises OSError: OUT.csv cannot be written.
    """
    MooringDriver(setup, rate=rate)  # refuses a bad rate or line before any file exists
    sinks, bag, out = [], None, None
    if bag_path is not None:
        bag = ArrangementBag(bag_path, setup, ship)
        sinks.append(bag)
    try:
        if out_path is not None:
            out = open(out_path, 'w', newline='', encoding='utf-8')
            sinks.insert(0, _csv_sink(out, setup))
        summary = simulate(setup, ship, rate, sinks, progress)
    except BaseException:
        if out is not None:
            out.close()
        if bag is not None:
            try:
                bag.close(complete=False)
            except BagError:
                pass
        raise
    if out is not None:
        out.close()
    if bag is not None:
        bag.close()
    return summary


def _csv_sink(stream, setup: arrangement.ArrangementParams):
    ratings = _ratings(setup)
    writer = csv.writer(stream)
    writer.writerow(list(OUT_COLUMNS) + [f'{line}_{column}' for line in setup.names
                                         for column in LINE_COLUMNS])

    def sink(published: MooringPublished) -> None:
        out = published.output
        row = [f'{out.t:.6f}'] + [f'{v:.6g}' for v in (*published.force, *published.moment)]
        for k in range(len(setup.names)):
            fairlead, bollard = out.fairlead_tensions[k], out.bollard_tensions[k]
            row += [f'{fairlead:.6g}', f'{bollard:.6g}',
                    f'{ratings[k].utilisation(max(fairlead, bollard)):.6g}',
                    f'{out.fairlead_peaks[k]:.6g}', f'{out.bollard_peaks[k]:.6g}',
                    f'{out.line_lengths[k]:.6g}', str(int(out.parted[k]))]
        writer.writerow(row)
    return sink


def _ratings(setup: arrangement.ArrangementParams) -> List[Rating]:
    library = load_materials()
    ratings = []
    for line in setup.lines:
        material = library.properties(line.params.material, line.params.diameter)
        ratings.append(Rating(material.mbl, material.working_load_limit))
    return ratings


def bag_ship_motion(path, setup: arrangement.ArrangementParams) -> ShipMotion:
    """
    Read the ship poses (and any bollard poses) a mooring node's bag recorded.

    :raises BagError: unreadable, or no ship pose recorded.
    """
    ship: List[Tuple[int, np.ndarray, np.ndarray]] = []
    bollards: Dict[str, List[Tuple[int, np.ndarray]]] = {}
    topics = {f'/{line}/bollard/pose': line for line in setup.names}
    for message in read_messages(path, [SHIP_POSE, *topics]):
        sec, nanosec, _, position, orientation = decode_pose_stamped(message.data)
        ns = sec * 1_000_000_000 + nanosec
        if message.topic == SHIP_POSE:
            if not ship or ns > ship[-1][0]:  # the node dropped a pose not after the newest
                ship.append((ns, position, orientation))
        else:
            line = topics[message.topic]
            k = setup.names.index(line)
            point = pose_point(position, orientation, setup.lines[k].params.bollard_offset)
            samples = bollards.setdefault(line, [])
            if not samples or ns > samples[-1][0]:
                samples.append((ns, point.point))
    if not ship:
        raise BagError(f'bag {os.fspath(path)} recorded no {SHIP_POSE}: nothing to simulate')
    return ShipMotion(
        os.fspath(path), np.array([s[0] for s in ship], dtype=np.int64),
        np.array([s[1] for s in ship]), np.array([s[2] for s in ship]),
        {line: (np.array([s[0] for s in samples], dtype=np.int64),
                np.array([s[1] for s in samples])) for line, samples in bollards.items()})


def recorded_rate(path, setup: arrangement.ArrangementParams) -> Optional[float]:
    """Return the output rate of a mooring node's bag (its first line's tensions), or None."""
    stamps = [m.publish_time_ns for m in read_messages(
        path, [f'/{setup.names[0]}/fairlead/tension'])]
    if len(stamps) < 3:
        return None
    interval = float(np.median(np.diff(stamps)))
    rate = 1e9 / interval
    return round(rate, 3 - int(math.floor(math.log10(rate))))


def resim(path, out_path, setup: Optional[arrangement.ArrangementParams] = None,
          rate: Optional[float] = None, progress=None) -> Tuple[ArrangementSummary, float]:
    """
    Re-simulate a mooring node's bag (its stored arrangement unless setup is given).

    :returns: the summary and the rate used.
    :raises BagError: not an arrangement's bag, unreadable, nothing to simulate.
    """
    setup = setup or stored_arrangement(path)
    if setup is None:
        raise BagError(f'bag {os.fspath(path)} stores no arrangement: give --params')
    rate = rate or recorded_rate(path, setup) or DEFAULT_RATE
    ship = bag_ship_motion(path, setup)
    return run_ship_motion(setup, ship, None, rate, out_path, progress), rate


def describe_lines(path) -> str:
    """
    Return each line's peak tension, utilisation and band of an arrangement's bag.

    :raises BagError: not an arrangement's bag, or unreadable.
    """
    from .arrangement_plot import read_record
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
    return '\n'.join(rows)


def decode_tensions(path, line: str) -> np.ndarray:
    """Return one line's recorded fairlead tensions in order (for tests and tools)."""
    return np.array([float(np.linalg.norm(decode_wrench(m.data)[0]))
                     for m in read_messages(path, [f'/{line}/fairlead/tension'])])
