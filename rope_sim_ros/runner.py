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
The offline loop shared by ``rope_sim run`` and ``rope_sim resim``.

End samples go into one line_driver.LineDriver, the node's own input and output rules, in
stamp order: the rope stays one sample behind them, which moves the ends exactly as if the
whole motion were known. The rope starts on the catenary at the first fairlead sample and
outputs follow every 1/rate s up to the last fairlead sample. Each output goes to sinks:
OUT.csv rows (motion.OutWriter) and/or a bag (BagSink) with the same topics, types and
stamps the node records, log time = publish time = the output stamp.
"""

from dataclasses import dataclass, field
import math
import os
import sys
import time
from typing import Any, Callable, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from .bag import cdr
from .line_driver import BOLLARD, FAIRLEAD, LineDriver, PARAMETERS_KEY, parameters_yaml, Published
from .model.frames import split_ns, tangent_quaternions
from .params.files import load_params, read_params_file
from .params.materials import default_config_dir
from .params.table import LineParams

DEFAULT_RATE = 100.0
PARAMS_FILE = 'mooring_line.yaml'

FAIRLEAD_POSE = 'fairlead/pose'
BOLLARD_POSE = 'bollard/pose'
PARTICLES = 'rope/particles'
FAIRLEAD_TENSION = 'fairlead/tension'
BOLLARD_TENSION = 'bollard/tension'
PAYLOAD_POSE = 'payload/pose'
POSE_TYPE = 'geometry_msgs/msg/PoseStamped'
PARTICLES_TYPE = 'geometry_msgs/msg/PoseArray'
WRENCH_TYPE = 'geometry_msgs/msg/Wrench'


def topic_name(namespace: str, relative: str) -> str:
    """Return the resolved name of a relative topic in a namespace ('' = root)."""
    return namespace.rstrip('/') + '/' + relative


# -- parameters ---------------------------------------------------------------------------


def default_params_file() -> str:
    """Return config/mooring_line.yaml (source tree, else installed share)."""
    return os.path.join(default_config_dir(), PARAMS_FILE)


def resolve_params(path: Optional[str] = None, overrides: Optional[Mapping] = None,
                   fallback: Optional[Mapping] = None) -> LineParams:
    """
    Return validated parameters: a file, or fallback values, or the default file.

    :param path: a ROS parameter file (``mooring_line: ros__parameters:``); None = use
        ``fallback``, else config/mooring_line.yaml, else the built-in defaults.
    :param overrides: values applied on top (e.g. from ``--set``).
    :param fallback: parameter values to use when no file is given (e.g. stored in a bag).
    :returns: the parameters.
    :raises ParameterError: unreadable file or a bad value, named.
    """
    if path is not None:
        return load_params(path, overrides)
    values = dict(fallback) if fallback is not None else None
    if values is None:
        default = default_params_file()
        values = read_params_file(default) if os.path.exists(default) else {}
    values.update(overrides or {})
    return LineParams().with_values(values)


# -- messages -------------------------------------------------------------------------------


def stamp_ns(t: float) -> int:
    """Return a time in seconds as integer nanoseconds (nearest)."""
    return int(round(t * 1e9))


def pose_stamped_cdr(ns: int, frame_id: str, position: Sequence[float]) -> bytes:
    """Return a PoseStamped at position, identity orientation, as zero-padded CDR bytes."""
    sec, nanosec = split_ns(ns)
    return cdr.pose_stamped(sec, nanosec, frame_id, [*map(float, position), 0.0, 0.0, 0.0, 1.0])


def particles_cdr(ns: int, frame_id: str, positions: np.ndarray) -> bytes:
    """Return the particles as a PoseArray (each along the rope tangent) in CDR bytes."""
    points = np.asarray(positions, dtype=float)
    sec, nanosec = split_ns(ns)
    return cdr.pose_array(sec, nanosec, frame_id,
                          np.concatenate([points, tangent_quaternions(points)], axis=1))


def wrench_cdr(force: Sequence[float], lever: Sequence[float] = (0.0, 0.0, 0.0)) -> bytes:
    """
    Return the Wrench of the line's force on an end, torque about the pose origin (CDR).

    :param force: force of the line on the end [N].
    :param lever: end point minus the pose origin [m].
    """
    force = np.asarray(force, dtype=float)
    return cdr.wrench(force, np.cross(np.asarray(lever, dtype=float), force))


# -- the loop -------------------------------------------------------------------------------


@dataclass
class EndSamples:
    """
    Samples of one end: stamps [ns] and world points [m] the line follows.

    :param t_ns: strictly increasing stamps [ns], shape (n,).
    :param points: end points, shape (n, 3).
    :param levers: end point minus pose origin per sample (torque arm), shape (n, 3), or
        None for zero.
    """

    t_ns: np.ndarray
    points: np.ndarray
    levers: Optional[np.ndarray] = None


@dataclass
class RunSummary:
    """
    What an offline run did.

    :param rows: outputs produced.
    :param start: first output time [s].
    :param end: last output time [s].
    :param time_step: integration step [s].
    :param restarts: (simulated time, reason) of every restart of the rope at rest
        (Advance.restarted: 'non-finite state', 'unphysical state', 'back within reach').
    :param beyond_reach: (simulated time, largest distance [m]) of every stretch of outputs
        during which the ends were farther apart than the line's reach (the rope held the
        fairlead at the reach).
    :param reach: the line's reach, L (1 + max_strain) [m].
    :param dropped: bag messages not recorded.
    :param wall: wall-clock seconds.
    """

    rows: int = 0
    start: float = math.nan
    end: float = math.nan
    time_step: float = math.nan
    restarts: List[Tuple[float, str]] = field(default_factory=list)
    beyond_reach: List[Tuple[float, float]] = field(default_factory=list)
    reach: float = math.nan
    dropped: int = 0
    wall: float = 0.0


class Progress:
    """
    A text progress bar on a stream, shown only when the run is slow and stream a TTY.

    Updates rewrite the line (carriage return) at most ten times a second, once ``delay`` seconds
    have passed; finish() ends the line with a newline if anything was drawn.
    """

    def __init__(self, stream=None, delay: float = 2.0, width: int = 30,
                 enabled: Optional[bool] = None) -> None:
        """
        Prepare the bar.

        :param stream: where to draw (default sys.stderr).
        :param delay: seconds before the first drawing.
        :param width: characters of the bar.
        :param enabled: force on/off; None = only when the stream is a TTY.
        """
        self.stream = stream if stream is not None else sys.stderr
        if enabled is None:
            isatty = getattr(self.stream, 'isatty', None)
            enabled = bool(isatty and isatty())
        self.enabled = enabled
        self.delay = delay
        self.width = width
        self._start = time.monotonic()
        self._last = -math.inf
        self._drawn = False

    def __call__(self, done: int, total: int, t: float) -> None:
        """Report done of total outputs, at simulated time t."""
        if not self.enabled:
            return
        now = time.monotonic()
        elapsed = now - self._start
        if elapsed < self.delay or (now - self._last < 0.1 and done < total):
            return
        self._last = now
        fraction = done / total if total else 1.0
        filled = int(round(self.width * fraction))
        remaining = elapsed * (1.0 - fraction) / fraction if fraction > 0 else math.inf
        eta = f'{remaining:5.0f} s left' if math.isfinite(remaining) else ''
        self.stream.write(
            f'\r[{"#" * filled}{"." * (self.width - filled)}] {100 * fraction:5.1f} % '
            f't = {t:.2f} s {eta}')
        self.stream.flush()
        self._drawn = True

    def finish(self) -> None:
        """End the line if the bar was drawn."""
        if self._drawn:
            self.stream.write('\n')
            self.stream.flush()
            self._drawn = False


Sink = Callable[[Published], None]


class Tally:
    """Counts outputs into a RunSummary: rows, first and last time, restarts, reach."""

    def __init__(self, summary: RunSummary) -> None:
        """Count into `summary`."""
        self.summary = summary
        self._held = False

    def add(self, published: Published) -> None:
        """Count one output."""
        summary = self.summary
        t, advance = published.output.t, published.advance
        if summary.rows == 0:
            summary.start = t
        summary.end = t
        summary.rows += 1
        if advance is not None and advance.restarted:
            summary.restarts.append((t, advance.restarted))
        beyond = advance.beyond_reach if advance is not None else 0.0
        if beyond:
            if self._held:
                summary.beyond_reach[-1] = (summary.beyond_reach[-1][0],
                                            max(summary.beyond_reach[-1][1], beyond))
            else:
                summary.beyond_reach.append((t, beyond))
        self._held = beyond > 0.0


def simulate(params: LineParams, fairlead: EndSamples, bollard: Optional[EndSamples] = None,
             rate: float = DEFAULT_RATE, sinks: Sequence[Sink] = (),
             progress: Optional[Callable[[int, int, float], None]] = None,
             materials: Any = None, winch_speed: Optional[np.ndarray] = None) -> RunSummary:
    """
    Run the line through the end samples and hand every output to the sinks.

    The samples go to a LineDriver in stamp order (a bollard sample before a fairlead one
    of the same stamp, so that the rope starts between both), an end's stream taken for
    finished after its last sample. Simulated time 0 is the first stamp; outputs fall
    every 1/rate s from the first fairlead sample to the last; without bollard samples the
    bollard stays at params.bollard_position.

    :param params: validated parameters.
    :param fairlead: fairlead samples (at least one).
    :param bollard: bollard samples, or None.
    :param rate: outputs per simulated second.
    :param sinks: callables sink(published) called in order for every output.
    :param progress: callable progress(done, total, t), or None.
    :param materials: material library (default: config/materials.yaml).
    :param winch_speed: the winch speed commanded from each fairlead sample's time on
        [m/s], or None (LineDriver.winch_schedule).
    :returns: the RunSummary (times in simulated seconds).
    :raises ParameterError: rate is not a positive finite number.
    :raises TrajectoryError: a sample is non-finite or out of order.
    """
    wall = time.monotonic()
    # No skip ahead offline: the samples, not a clock, say how far the rope may go.
    driver = LineDriver(params, materials, rate=rate)
    if winch_speed is not None:
        first = min([int(fairlead.t_ns[0])] + ([] if bollard is None else [int(bollard.t_ns[0])]))
        driver.winch_schedule = ((np.asarray(fairlead.t_ns) - first) / 1e9,
                                 np.asarray(winch_speed, dtype=float))
    ends = [(FAIRLEAD, fairlead)] + ([(BOLLARD, bollard)] if bollard is not None else [])
    order = sorted((int(ns), 0 if end == BOLLARD else 1, end, i)
                   for end, samples in ends for i, ns in enumerate(samples.t_ns.tolist()))
    by_end = dict(ends)
    counts = {end: len(samples.t_ns) for end, samples in ends}
    first_ns, last_ns = int(fairlead.t_ns[0]), int(fairlead.t_ns[-1])
    total = int(math.floor((last_ns - first_ns) / 1e9 * rate + 1e-9)) + 1
    summary = RunSummary(time_step=driver.simulator.time_step, reach=driver.simulator.reach)
    tally = Tally(summary)

    def take(report) -> None:
        for published in report.outputs:
            tally.add(published)
            for sink in sinks:
                sink(published)
            if progress is not None:
                progress(summary.rows, max(total, summary.rows), published.output.t)

    for ns, _, end, i in order:
        samples = by_end[end]
        lever = None if samples.levers is None else samples.levers[i]
        driver.push(end, ns, samples.points[i], lever)
        if i == counts[end] - 1:
            driver.silence(end)  # its last sample: nothing more to wait for
        if driver.started:
            take(driver.advance(driver.seconds(last_ns), max_lag=math.inf))
    take(driver.advance(driver.seconds(last_ns), max_lag=math.inf))
    summary.wall = time.monotonic() - wall
    return summary


def check_line(params: LineParams, rate: float = DEFAULT_RATE, materials: Any = None) -> None:
    """
    Refuse a line or an output rate that simulate() would refuse; call it before any output.

    :raises ParameterError: rate is not a positive finite number, or the time step is not
        allowed for the line (e.g. above improved_euler's stability limit).
    :raises MaterialError: the material cannot be built.
    """
    LineDriver(params, materials, rate=rate)  # raises what simulate() would


class BagSink:
    """
    Records a run as the node does: input poses and output particles and tensions.

    Inputs are written in stamp order interleaved with the outputs (an input stamped at or
    before an output is written before that output). Log time = publish time = the stamp.
    A line with a payload records payload/pose at every output too.
    """

    # Messages the writer thread may hold; write() waits for room instead of dropping.
    QUEUE_SIZE = 20000

    def __init__(self, path, params: LineParams, inputs: Sequence[Tuple[int, str, Any]],
                 input_topics: Mapping[str, str], namespace: str = '',
                 extra_topics: Optional[Mapping[str, str]] = None) -> None:
        """
        Create the bag (refusing an existing non-empty directory) and its topics.

        :param path: the new bag directory.
        :param params: the run's parameters (frame_id; stored in custom_data).
        :param inputs: (stamp_ns, topic, CDR bytes) of every input message.
        :param input_topics: {topic: type} of the inputs.
        :param namespace: namespace of the output topics ('' = root).
        :param extra_topics: {topic: type} of other topics to register (e.g. events).
        :raises BagError: the directory exists and is not empty, or cannot be created.
        """
        from .bag import BagWriter
        self.frame_id = params.frame_id
        self._inputs = sorted(inputs, key=lambda item: item[0])
        self._next_input = 0
        self._retries = 0
        self.particles = topic_name(namespace, PARTICLES)
        self.fairlead_tension = topic_name(namespace, FAIRLEAD_TENSION)
        self.bollard_tension = topic_name(namespace, BOLLARD_TENSION)
        self.payload = topic_name(namespace, PAYLOAD_POSE)
        self.writer = BagWriter(path, queue_size=self.QUEUE_SIZE,
                                custom_data={PARAMETERS_KEY: parameters_yaml(params)})
        for topic, type_name in {**input_topics, **(extra_topics or {})}.items():
            self.writer.add_topic(topic, type_name)
        self.writer.add_topic(self.particles, PARTICLES_TYPE)
        self.writer.add_topic(self.fairlead_tension, WRENCH_TYPE)
        self.writer.add_topic(self.bollard_tension, WRENCH_TYPE)
        if params.has_payload:
            self.writer.add_topic(self.payload, POSE_TYPE)

    @property
    def path(self) -> str:
        """Return the bag directory."""
        return self.writer.path

    def _write(self, topic: str, message: Any, ns: int) -> None:
        from .bag import BagError
        # The writer drops on a full queue (right for a live node); offline, wait instead.
        while not self.writer.write(topic, message, ns):
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
        ns = published.stamp_ns
        log_ns = ns if log_ns is None else log_ns
        self._write_inputs(ns)
        self.write_output(published, log_ns)

    def write(self, topic: str, data: bytes, log_ns: int) -> None:
        """Record one message (CDR bytes) now."""
        self._write(topic, data, log_ns)

    def write_output(self, published: Published, log_ns: int) -> None:
        """Record one output: particles, both tensions (and the payload pose)."""
        out, ns = published.output, published.stamp_ns
        self._write(self.particles, particles_cdr(ns, self.frame_id, out.positions), log_ns)
        self._write(self.fairlead_tension,
                    wrench_cdr(out.fairlead_force, published.fairlead_lever), log_ns)
        self._write(self.bollard_tension,
                    wrench_cdr(out.bollard_force, published.bollard_lever), log_ns)
        if out.payload_position is not None:
            self._write(self.payload, pose_stamped_cdr(ns, self.frame_id, out.payload_position),
                        log_ns)

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
        from .bag import BagError
        try:
            self.close(complete=False)
        except BagError:
            pass


# -- rope_sim run ---------------------------------------------------------------------------


def run_motion(params: LineParams, motion, out_path=None, rate: float = DEFAULT_RATE,
               bag_path=None, progress=None) -> RunSummary:
    """
    Run a motion table: OUT.csv rows and/or a bag.

    The motion's points are the world-frame end points themselves. A recorded pose is the
    pose whose origin plus the end's offset (fairlead_offset, bollard_offset; identity
    orientation) is that point, so the node fed with the bag follows the same points.

    :param params: validated parameters.
    :param motion: a motion.Motion.
    :param out_path: OUT.csv to write (overwritten), or None.
    :param rate: outputs per simulated second.
    :param bag_path: new bag directory, or None.
    :param progress: callable progress(done, total, t), or None.
    :returns: the RunSummary.
    :raises MotionError: a bag cannot hold negative times.
    :raises BagError: the bag directory exists and is not empty, or recording failed.
    :raises OSError: OUT.csv cannot be written.
    """
    from .motion import MotionError, OutWriter
    check_line(params, rate)  # before OUT.csv or the bag exists
    fairlead_offset = np.asarray(params.fairlead_offset, dtype=float)
    bollard_offset = np.asarray(params.bollard_offset, dtype=float)
    # Simulated time runs from 0 at the first row; the rows' exact nanoseconds give the
    # stamps, so a bag of epoch-stamped rows re-simulates to the same numbers.
    base_ns = int(motion.t_ns[0])
    origin = float(motion.t[0])
    fairlead = EndSamples(motion.t_ns, motion.fairlead,
                          np.repeat([fairlead_offset], len(motion), axis=0))
    bollard = None
    if motion.bollard is not None:
        bollard = EndSamples(motion.t_ns, motion.bollard,
                             np.repeat([bollard_offset], len(motion), axis=0))
    sinks = []
    bag = None
    if bag_path is not None:
        if base_ns < 0:
            raise MotionError(
                f'{motion.path}: data row 1, column {"t"!r}: {motion.t[0]!r} is negative; '
                'a bag stamps messages with the simulated time, which must be >= 0')
        inputs, topics = [], {}
        ends = [(FAIRLEAD_POSE, motion.fairlead, fairlead_offset)]
        if motion.bollard is not None:
            ends.append((BOLLARD_POSE, motion.bollard, bollard_offset))
        for relative_name, points, offset in ends:
            topic = topic_name('', relative_name)
            topics[topic] = POSE_TYPE
            inputs += [(ns, topic, pose_stamped_cdr(ns, params.frame_id, p - offset))
                       for ns, p in zip(motion.t_ns.tolist(), points)]
        bag = BagSink(bag_path, params, inputs, topics, '')
        sinks.append(bag)
    writer = None
    try:
        if out_path is not None:
            writer = OutWriter(out_path, payload=params.has_payload)
            sinks.insert(0, lambda p: writer.write(
                origin + p.output.t if origin else p.output.t, p.output))
        summary = simulate(params, fairlead, bollard, rate, sinks, progress,
                           winch_speed=motion.winch_speed)
    except BaseException:
        # Ctrl-C or an error: keep what was computed, a complete bag up to here included.
        _close_quietly(writer, bag)
        raise
    if writer is not None:
        writer.close()
    if bag is not None:
        summary.dropped = bag.close()
    summary.start += origin
    summary.end += origin
    return summary


def _close_quietly(writer, bag) -> None:
    try:
        if writer is not None:
            writer.close()
    except OSError:
        pass
    if bag is not None:
        bag.abandon()
