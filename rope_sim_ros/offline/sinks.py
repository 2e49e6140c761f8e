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
Where an offline run's outputs go: OUT.csv, a bag as the node records it, a run's summary.

OUT.csv has one row per output. A single line's (the mooring_line node's parameters) has
LINE_COLUMNS: the forces of the line on both ends, the largest tension at each since the
previous row, the unstretched length and whether the line has parted, the payload's
position (PAYLOAD_COLUMNS) when the line ends in a free payload, and last the line's state
(STATE_COLUMN). An arrangement's has ARRANGEMENT_COLUMNS, the total force and moment of the
lines on the ship (body frame, about its origin), then each line's EACH_LINE_COLUMNS under
its name (NAME_tension, ..., NAME_state); a free ship's adds its motion (SHIP_COLUMNS: its
origin's pose as SHIP.csv names it and its velocity, frame_id axes) and each fender's
FENDER_COLUMNS under its name; where wind, current or a passing ship act (or the ship is
free), LOAD_COLUMNS: their loads on the ship, body axes about its origin; where waves are
set (waves.spectrum not none), WAVE_COLUMNS: their elevation at the ship's origin, their
first-order load and their slow drift on it, body axes about its origin.
Times are in the motion file's own time base; every number is written with Python's
shortest exact repr, so a row read back gives the very floats that were computed. A
line's state is a word, fast, free or stowed (mooring/handling.py): the one column that is
not a number, which a reader of numbers leaves out by its name.

The bag holds the inputs (the poses, as the node received them) and every output on the
topics, with the types and stamps, the node records (messages/encode.py), log time =
publish time = the output's stamp.

A run's summary (SummarySink: what a study keeps of each case) has, per line, LINE_RESULTS
under its name (NAME_max_tension, ...), and a free ship's SHIP_RESULTS, computed from the
outputs themselves: the same numbers as from its OUT.csv (whose rows hold those outputs'
very floats), whether OUT.csv is written or not.
"""

import csv
import math
import os
import time
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from ..bag import BagError, BagWriter, cdr
from ..messages.encode import OutputEncoder
from ..model.ship.motions import (against_limits, motion_ranges, motion_series, MotionLimits,
                                  MOTIONS)
from ..mooring.records import Published
from ..mooring.status import Rating

# A line's state in OUT.csv: 'fast', 'free' or 'stowed' (a word among the numbers).
STATE_COLUMN = 'state'
LINE_COLUMNS = (
    't', 'fairlead_fx', 'fairlead_fy', 'fairlead_fz', 'fairlead_tension',
    'bollard_fx', 'bollard_fy', 'bollard_fz', 'bollard_tension', 'max_strain',
    'fairlead_peak_tension', 'bollard_peak_tension', 'line_length', 'parted')
# Added after LINE_COLUMNS when the line ends in a free payload (payload_mass > 0).
PAYLOAD_COLUMNS = ('payload_x', 'payload_y', 'payload_z')
ARRANGEMENT_COLUMNS = ('t', 'force_x', 'force_y', 'force_z', 'moment_x', 'moment_y',
                       'moment_z')
# Each line's columns in an arrangement's OUT.csv, after ARRANGEMENT_COLUMNS: its tensions,
# its utilisation, and as a single line's, its peaks, its length, parted (0, 1) and state.
EACH_LINE_COLUMNS = ('tension', 'bollard_tension', 'utilisation', 'fairlead_peak_tension',
                     'bollard_peak_tension', 'line_length', 'parted', STATE_COLUMN)
# A free ship's motion after the lines' columns: its origin's position [m] and orientation,
# its origin's velocity [m/s] and its angular velocity [rad/s], frame_id axes.
SHIP_COLUMNS = ('x', 'y', 'z', 'qx', 'qy', 'qz', 'qw', 'vx', 'vy', 'vz', 'wx', 'wy', 'wz')
# Each fender's columns after those, under its name: its compression [m] (<= 0: untouched)
# and its reaction on the hull along its normal [N].
FENDER_COLUMNS = ('compression', 'reaction')
# The wind's, the current's and a passing ship's loads on the ship, body axes about its origin.
LOAD_COLUMNS = tuple(f'{source}_{column}' for source in ('wind', 'current', 'passing')
                     for column in ('force_x', 'force_y', 'moment_z'))
# The waves: their elevation at the ship's origin [m], their first-order load and their slow
# drift on the ship [N, N m], body axes about its origin.
WAVE_COLUMNS = ('wave_elevation', 'wave_force_x', 'wave_force_y', 'wave_force_z',
                'wave_moment_x', 'wave_moment_y', 'wave_moment_z', 'drift_force_x',
                'drift_force_y', 'drift_moment_z')
# A run's summary per line (SummarySink), under its name, and a free ship's.
LINE_RESULTS = ('max_tension', 'max_utilisation', 'time_of_max', 'mean_tension', 'parted')
SHIP_RESULTS = ('max_surge', 'max_sway', 'max_yaw', *(f'{name}_motion' for name in MOTIONS),
                'motion_share')


def _numbers(*values) -> List[str]:
    """Return numbers as OUT.csv writes them: Python's shortest exact repr of each float."""
    return [repr(float(v)) for v in values]


def row_time(origin: float, t: float) -> float:
    """Return an output's time in the motion file's time base: origin + simulated time t."""
    return origin + t if origin else t


class CsvSink:
    """Writes OUT.csv row by row (see the module docstring); a context manager."""

    def __init__(self, path, names: Sequence[str], ratings: Sequence[Rating],
                 payload: bool = False, origin: float = 0.0, free: bool = False,
                 fenders: Sequence[Tuple[str, Sequence[float]]] = (),
                 loads: bool = False, waves: bool = False) -> None:
        """
        Open (create or overwrite) the file and write the header.

        :param names: the line names: one unnamed line gives a single line's columns.
        :param ratings: each line's MBL and WLL (an arrangement's utilisation).
        :param payload: a single line that ends in a payload (PAYLOAD_COLUMNS).
        :param origin: the motion file's first time [s]: a row's t is origin plus the
            output's simulated time.
        :param free: a free ship's run (SHIP_COLUMNS).
        :param fenders: each fender's name and normal (FENDER_COLUMNS).
        :param loads: the wind, current and passing-ship loads (LOAD_COLUMNS).
        :param waves: the waves' elevation and loads (WAVE_COLUMNS).
        :raises OSError: it cannot be written.
        """
        self.path = os.fspath(path)
        self.single = list(names) == ['']
        self.ratings = list(ratings)
        self.payload = payload
        self.origin = origin
        self.free = free
        self.loads = loads
        self.waves = waves
        self.normals = [tuple(normal) for _, normal in fenders]
        self._file = open(self.path, 'w', newline='', encoding='utf-8')
        self._writer = csv.writer(self._file, lineterminator='\n')
        if self.single:
            header = LINE_COLUMNS + (PAYLOAD_COLUMNS if payload else ()) + (STATE_COLUMN,)
        else:
            header = ARRANGEMENT_COLUMNS + tuple(f'{name}_{column}' for name in names
                                                 for column in EACH_LINE_COLUMNS)
            header += SHIP_COLUMNS if free else ()
            header += tuple(f'{name}_{column}' for name, _ in fenders
                            for column in FENDER_COLUMNS)
            header += LOAD_COLUMNS if loads else ()
            header += WAVE_COLUMNS if waves else ()
        self._writer.writerow(header)
        self.rows = 0

    def __call__(self, published: Published) -> None:
        """Append one output's row."""
        out = published.output
        t = row_time(self.origin, out.t)
        if self.single:
            cells = _numbers(t, *out.fairlead_forces[0], out.fairlead_tensions[0],
                             *out.bollard_forces[0], out.bollard_tensions[0], out.max_strains[0],
                             out.fairlead_peaks[0], out.bollard_peaks[0], out.line_lengths[0],
                             out.parted[0])
            if self.payload:
                cells += _numbers(*out.payload_positions[0])
            cells.append(out.states[0])
        else:
            cells = _numbers(t, *published.force, *published.moment)
            for k, rating in enumerate(self.ratings):
                fairlead, bollard = out.fairlead_tensions[k], out.bollard_tensions[k]
                cells += _numbers(fairlead, bollard, rating.utilisation(max(fairlead, bollard)),
                                  out.fairlead_peaks[k], out.bollard_peaks[k],
                                  out.line_lengths[k], out.parted[k])
                cells.append(out.states[k])
            numbers = []
            if self.free:
                ship = out.ship
                numbers += [*ship.position, *ship.orientation, *ship.velocity, *ship.omega]
            for f, normal in enumerate(self.normals):
                numbers += [out.fender_compressions[f], float(np.dot(out.fender_forces[f],
                                                                     normal))]
            if self.loads:
                numbers += out.ship_loads.ravel().tolist()
            if self.waves:
                drift = out.wave_loads[1]
                numbers += [out.wave_elevation, *out.wave_loads[0], drift[0], drift[1], drift[5]]
            cells += _numbers(*numbers)
        self._writer.writerow(cells)
        self.rows += 1

    def close(self) -> None:
        """Close the file."""
        self._file.close()

    def __enter__(self) -> 'CsvSink':
        """Return the open writer."""
        return self

    def __exit__(self, *exc) -> None:
        """Close the file."""
        self.close()


class BagSink:
    """
    Records a run as the node does: the input poses and every output message.

    Inputs are written in stamp order interleaved with the outputs (an input stamped at or
    before an output is written before that output).
    """

    # Messages the writer thread may hold; write() waits for room instead of dropping.
    QUEUE_SIZE = 20000

    def __init__(self, path, encoder: OutputEncoder, namespace: str,
                 inputs: Sequence[Tuple[int, str, bytes]], input_topics: Mapping[str, str],
                 custom_data: Mapping[str, str], extra_topics: Optional[Mapping[str, str]] = None
                 ) -> None:
        """
        Create the bag (refusing an existing non-empty directory) and its topics.

        :param encoder: the outputs' topics and messages (its layout's node kind).
        :param namespace: the namespace the topics are recorded in ('' = root).
        :param inputs: (stamp_ns, relative topic, CDR bytes) of every input message.
        :param input_topics: {relative topic: type} of the inputs.
        :param custom_data: metadata.yaml's custom_data (the parameters of the run).
        :param extra_topics: {relative topic: type} of other topics (the events).
        :raises BagError: the directory exists and is not empty, or cannot be created.
        """
        self.encoder = encoder
        self.namespace = namespace.rstrip('/')
        self._inputs = sorted(inputs, key=lambda item: item[0])
        self._next_input = 0
        self._retries = 0
        self.writer = BagWriter(path, queue_size=self.QUEUE_SIZE, custom_data=dict(custom_data))
        topics = {**input_topics, **(extra_topics or {}), **encoder.types}
        for topic, type_name in topics.items():
            self.writer.add_topic(self.resolved(topic), type_name)

    @property
    def path(self) -> str:
        """Return the bag directory."""
        return self.writer.path

    def resolved(self, relative: str) -> str:
        """Return a relative topic's name in the bag (its namespace in front)."""
        return relative if relative.startswith('/') else f'{self.namespace}/{relative}'

    def _write(self, topic: str, message: Any, ns: int) -> None:
        # The writer drops on a full queue (right for a live node); offline, wait instead.
        while not self.writer.write(self.resolved(topic), message, ns):
            if self.writer.error is not None:
                raise self.writer.error
            if self.writer.closed:
                raise BagError(f'bag {self.writer.path} was closed during the run')
            self._retries += 1  # the writer counted it as dropped
            time.sleep(0.001)

    def _write_inputs(self, until_ns: float) -> None:
        while (self._next_input < len(self._inputs)
               and self._inputs[self._next_input][0] <= until_ns):
            ns, topic, message = self._inputs[self._next_input]
            self._write(topic, message, ns)
            self._next_input += 1

    def __call__(self, published: Published, log_ns: Optional[int] = None) -> None:
        """Record the inputs up to the output's stamp, then the output (log time log_ns)."""
        self._write_inputs(published.stamp_ns)
        self.write_output(published, published.stamp_ns if log_ns is None else log_ns)

    def write(self, topic: str, data: bytes, log_ns: int) -> None:
        """Record one message (CDR bytes) now, on a relative topic."""
        self._write(topic, data, log_ns)

    def write_output(self, published: Published, log_ns: int) -> None:
        """Record one output: every line's messages, the ship's, a parted flag that changed."""
        for topic, data in self.encoder.messages(published):
            self._write(topic, data, log_ns)
        for topic, flag in self.encoder.parted_changes(published.output.parted):
            self._write(topic, cdr.boolean(flag), log_ns)

    def close(self, complete: bool = True) -> int:
        """
        Record the remaining inputs (if complete), complete the bag, return its dropped count.

        :param complete: False after an interruption: inputs stamped after the last output
            are left out, as a recorder stopped there would have left them.
        :raises BagError: recording failed.
        """
        try:
            if complete:
                self._write_inputs(math.inf)
        finally:
            self.writer.close()
        return self.writer.dropped - self._retries

    def abandon(self) -> None:
        """
        Close the bag after an interruption or an error: keep what was recorded so far.

        A failure to close is not reported: the interruption is what the caller raises.
        """
        try:
            self.close(complete=False)
        except BagError:
            pass


class SummaryError(ValueError):
    """A run cannot be summarised: it gave no output, or a result is not a finite number."""


class SummarySink:
    """
    Summarises a run from its outputs: per line and, for a free ship, its excursions.

    Per line, under its name:

    - ``max_tension`` [N]: the line's largest tension over the run: the larger of its two end
      tensions (the one its utilisation counts), at every output and the peaks since the
      previous one (every integration step's: a snap between outputs counts);
    - ``max_utilisation``: that over the line's MBL (its material at its diameter);
    - ``time_of_max`` [s]: the time of the output that holds it (the first, if it repeats),
      in the motion file's time base (OUT.csv's t);
    - ``mean_tension`` [N]: the mean over the outputs of the larger end tension;
    - ``parted``: 1 if the line parted during the run, else 0.

    A free ship's ``max_surge``, ``max_sway`` [m] and ``max_yaw`` [rad]: its largest absolute
    excursion from its pose at the first output, along and across its start heading (its
    start body axes) and about z (ship_excursions); and its motions against the criteria of
    safe cargo handling it is given (ship_motions: ``surge_motion`` ... ``yaw_motion``,
    ``motion_share``).

    It keeps, per output, its time and each line's larger end tension and peak (and a free
    ship's pose): 8 (1 + 2 L) bytes (L lines; 56 more for a free ship), 0.6 MB for the berth's
    8 lines over 420 s at 10 Hz; the mean is summed exactly (math.fsum) when asked.
    """

    def __init__(self, names: Sequence[str], ratings: Sequence[Rating], origin: float = 0.0,
                 criteria: Optional[MotionLimits] = None) -> None:
        """
        Prepare the summary of a run of these lines.

        :param names: the line names; ratings: their MBLs, in the same order.
        :param origin: the motion file's first time [s] (as CsvSink's).
        :param criteria: a free ship's run: its motions are held to these limits (and its
            excursions summarised too); None: the ship is driven.
        """
        self.names = list(names)
        self.ratings = list(ratings)
        self.origin = origin
        self.criteria = criteria
        self.free = criteria is not None
        count = len(self.names)
        # columns: t, each line's larger end tension, its peak, the ship's pose (free)
        self._sample = slice(1, 1 + count)
        self._peak = slice(1 + count, 1 + 2 * count)
        self._pose = slice(1 + 2 * count, 8 + 2 * count)  # position (3), orientation (4)
        self._table = np.empty((64, self._pose.stop if self.free else self._peak.stop))
        self._parted = np.zeros(count, dtype=bool)
        self.rows = 0

    def __call__(self, published: Published) -> None:
        """Keep what the summary needs of one output."""
        if self.rows == len(self._table):
            self._table = np.concatenate([self._table, np.empty_like(self._table)])
        row = self._table[self.rows]
        out = published.output
        row[0] = row_time(self.origin, out.t)
        sample, peak = row[self._sample], row[self._peak]
        np.maximum(out.fairlead_tensions, out.bollard_tensions, out=sample)
        np.maximum(out.fairlead_peaks, out.bollard_peaks, out=peak)
        np.maximum(peak, sample, out=peak)
        np.logical_or(self._parted, out.parted, out=self._parted)
        if self.free:
            row[self._pose] = (*out.ship.position, *out.ship.orientation)
        self.rows += 1

    def summary(self) -> Dict[str, Any]:
        """
        Return the summary of the outputs so far (see the class docstring).

        :raises SummaryError: no output yet, or a result that is not a finite number.
        """
        if self.rows == 0:
            raise SummaryError('the run gave no output to summarise')
        table = self._table[:self.rows]
        t, samples, peaks = table[:, 0], table[:, self._sample], table[:, self._peak]
        summary: Dict[str, Any] = {}
        for k, (name, rating) in enumerate(zip(self.names, self.ratings)):
            i = int(np.argmax(peaks[:, k]))
            largest = float(peaks[i, k])
            summary[f'{name}_max_tension'] = largest
            summary[f'{name}_max_utilisation'] = float(rating.utilisation(largest))
            summary[f'{name}_time_of_max'] = float(t[i])
            summary[f'{name}_mean_tension'] = math.fsum(samples[:, k].tolist()) / self.rows
            summary[f'{name}_parted'] = int(self._parted[k])
        if self.free:
            pose = table[:, self._pose]
            summary.update(ship_excursions(pose[:, :3], pose[:, 3:]))
            summary.update(ship_motions(pose[:, :3], pose[:, 3:], self.criteria))
        for column, value in summary.items():
            if not math.isfinite(value):
                raise SummaryError(f'{column} is {value!r}, not a finite number')
        return summary


def ship_excursions(positions: np.ndarray, orientations: np.ndarray) -> Dict[str, float]:
    """
    Return max_surge, max_sway [m] and max_yaw [rad] of a ship's poses, one a row.

    Excursions from the first pose: the largest absolute surge, sway and yaw of
    model/ship/motions.py's motion_series.

    :param positions: (N, 3) [m]; orientations: (N, 4) quaternions (x, y, z, w).
    """
    series = motion_series(positions, orientations)
    return {f'max_{name}': float(np.max(np.abs(series[name])))
            for name in ('surge', 'sway', 'yaw')}


def ship_motions(positions: np.ndarray, orientations: np.ndarray,
                 criteria: MotionLimits) -> Dict[str, float]:
    """
    Return a ship's motions over its poses and their largest share of the criteria's limits.

    NAME_motion for each of surge, sway, heave [m], roll, pitch, yaw [rad]: peak to peak,
    sway zero to peak (model/ship/motions.py); motion_share: the largest motion's share of
    its limit (cargo handling stops at 1).
    """
    ranges = motion_ranges(motion_series(positions, orientations))
    _, share = against_limits(ranges, criteria)
    return {**{f'{name}_motion': ranges[name] for name in MOTIONS}, 'motion_share': share}
