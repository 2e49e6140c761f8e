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

End samples go into one Simulator a sample ahead of the state (see _Feed), which moves the
ends exactly as if the whole motion were known.
The rope starts on the catenary between the first samples' end points, and the state is
advanced from output time to output time (every 1/rate s from the first sample time to the
last). Each output goes to sinks: OUT.csv rows (motion.OutWriter) and/or a bag (BagSink)
with the same topics, types and stamps the node records, log time = publish time =
simulated time.
"""

from dataclasses import dataclass, field
import math
import os
import sys
import time
from typing import Any, Callable, List, Mapping, Optional, Sequence, Tuple

import numpy as np
import yaml

from .bag import cdr
from .params import LineParams, load_params, NODE_NAME, ParameterError, read_params_file
from .simulator import default_config_dir, Output, Simulator

DEFAULT_RATE = 100.0
PARAMS_FILE = 'mooring_line.yaml'
# custom_data key of metadata.yaml under which run and resim store their parameters.
PARAMETERS_KEY = 'rope_sim_ros.parameters'

FAIRLEAD_POSE = 'fairlead/pose'
BOLLARD_POSE = 'bollard/pose'
PARTICLES = 'rope/particles'
FAIRLEAD_TENSION = 'fairlead/tension'
BOLLARD_TENSION = 'bollard/tension'
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


def parameters_yaml(params: LineParams) -> str:
    """Return the parameters as a one-line ROS parameter file (stored in bags)."""
    values = params.as_dict()
    values.pop('record_path', None)
    return yaml.safe_dump({NODE_NAME: {'ros__parameters': values}},
                          default_flow_style=True, sort_keys=True, width=2**31).strip()


def parameters_from_yaml(text: str) -> dict:
    """
    Return the parameter values of a ``parameters_yaml`` text.

    :raises ParameterError: it is not such a text.
    """
    try:
        data = yaml.safe_load(text)
        values = data[NODE_NAME]['ros__parameters']
    except (yaml.YAMLError, KeyError, TypeError):
        raise ParameterError(f'stored parameters are not a parameter map: {text!r}') from None
    if not isinstance(values, dict):
        raise ParameterError(f'stored parameters are not a parameter map: {text!r}')
    return values


# -- messages -------------------------------------------------------------------------------


def stamp_ns(t: float) -> int:
    """Return a time in seconds as integer nanoseconds (nearest)."""
    return int(round(t * 1e9))


# Messages are built exactly as the node builds them (ros/conversions.py); only the input
# PoseStamped, which the node receives rather than builds, is made here.


def pose_stamped(ns: int, frame_id: str, position: Sequence[float]):
    """Return a PoseStamped at position with identity orientation."""
    from geometry_msgs.msg import PoseStamped
    from .ros.conversions import ns_to_stamp
    msg = PoseStamped()
    msg.header.stamp = ns_to_stamp(ns)
    msg.header.frame_id = frame_id
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (
        float(v) for v in position)
    msg.pose.orientation.w = 1.0
    return msg


def particles_message(ns: int, frame_id: str, positions: np.ndarray):
    """Return the PoseArray of the particles, each oriented along the rope tangent."""
    from .ros.conversions import pose_array
    return pose_array(positions, frame_id, ns)


def pose_stamped_cdr(ns: int, frame_id: str, position: Sequence[float]) -> bytes:
    """Return pose_stamped(...) (identity orientation) as zero-padded CDR bytes (bag.cdr)."""
    sec, nanosec = divmod(int(ns), 1_000_000_000)
    return cdr.pose_stamped(sec, nanosec, frame_id, [*map(float, position), 0.0, 0.0, 0.0, 1.0])


def particles_cdr(ns: int, frame_id: str, positions: np.ndarray) -> bytes:
    """Return particles_message(...) as zero-padded CDR bytes, built with numpy (bag.cdr)."""
    from .ros.conversions import tangent_quaternions
    points = np.asarray(positions, dtype=float)
    sec, nanosec = divmod(int(ns), 1_000_000_000)
    return cdr.pose_array(sec, nanosec, frame_id,
                          np.concatenate([points, tangent_quaternions(points)], axis=1))


def wrench_message(force: Sequence[float], lever: Sequence[float] = (0.0, 0.0, 0.0)):
    """
    Return the Wrench of the line's force on an end, torque about the pose origin.

    :param force: force of the line on the end [N].
    :param lever: end point minus the pose origin [m].
    """
    from .ros.conversions import wrench
    return wrench(force, lever)


# -- the loop -------------------------------------------------------------------------------


@dataclass
class EndSamples:
    """
    Samples of one end: times [s] and world points [m] the simulator follows.

    :param t: strictly increasing times, shape (n,).
    :param points: end points, shape (n, 3).
    :param levers: end point minus pose origin per sample (torque arm), shape (n, 3), or
        None for zero.
    """

    t: np.ndarray
    points: np.ndarray
    levers: Optional[np.ndarray] = None

    def lever_at(self, t: float) -> np.ndarray:
        """Return the torque arm of the newest sample at or before t (first before)."""
        if self.levers is None:
            return np.zeros(3)
        i = max(0, int(np.searchsorted(self.t, t, side='right')) - 1)
        return self.levers[i]


def output_times(start: float, end: float, rate: float) -> np.ndarray:
    """Return start + k / rate for k = 0, 1, ... up to end (inclusive, to 1e-9 of a step)."""
    count = int(math.floor((end - start) * rate + 1e-9)) + 1
    return start + np.arange(count) / rate


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


Sink = Callable[[float, Output], None]


def simulate(params: LineParams, fairlead: EndSamples, bollard: Optional[EndSamples] = None,
             rate: float = DEFAULT_RATE, sinks: Sequence[Sink] = (),
             progress: Optional[Callable[[int, int, float], None]] = None,
             materials: Any = None) -> RunSummary:
    """
    Run the line through the end samples and hand every output to the sinks.

    Outputs fall every 1/rate s from the first fairlead sample time to the last; the rope
    starts at rest on the catenary between the end points at the first time. Without
    bollard samples the bollard stays at params.bollard_position. Give times relative to
    the start (0 = first sample): a large origin such as an epoch stamp, resolved to
    2e-7 s in a float, would cost the steps their precision. Sinks, the summary and the
    progress see the same times.

    :param params: validated parameters.
    :param fairlead: fairlead samples (at least one).
    :param bollard: bollard samples, or None.
    :param rate: outputs per simulated second.
    :param sinks: callables sink(t, output) called in order for every output.
    :param progress: callable progress(done, total, t), or None.
    :param materials: material library (default: config/materials.yaml).
    :returns: the RunSummary.
    :raises ParameterError: rate is not a positive finite number.
    :raises TrajectoryError: a sample is non-finite or out of order.
    """
    if not (math.isfinite(rate) and rate > 0.0):
        raise ParameterError(f'output rate {rate!r} Hz is not allowed: must be > 0')
    wall = time.monotonic()
    # Samples are pushed as the state approaches them (_Feed): the default history of end
    # samples suffices.
    sim = Simulator(params, materials, output_interval=1.0 / rate)
    ends = [_Feed(sim.push_fairlead, fairlead)]
    if bollard is not None:
        ends.append(_Feed(sim.push_bollard, bollard))
    times = output_times(float(fairlead.t[0]), float(fairlead.t[-1]), rate).tolist()
    summary = RunSummary(start=times[0], end=times[-1], time_step=sim.time_step,
                         reach=sim.reach)
    for end in ends:
        end.feed(times[0])
    sim.start(times[0])
    dt = sim.time_step
    total = len(times)
    held = False
    for k, t in enumerate(times):
        for end in ends:
            end.feed(t)
        advance = sim.advance_to(t)
        if advance.restarted:
            summary.restarts.append((t, advance.restarted))
        if advance.beyond_reach:
            if held:
                summary.beyond_reach[-1] = (summary.beyond_reach[-1][0], max(
                    summary.beyond_reach[-1][1], advance.beyond_reach))
            else:
                summary.beyond_reach.append((t, advance.beyond_reach))
        held = advance.beyond_reach > 0.0
        if abs(sim.time - t) < 1e-6 * dt:
            # The state time is a running sum of steps; pin it to the exact output time
            # so rounding never accumulates into a missed step on long runs.
            sim.skip_to(t)
        out = sim.output()
        for sink in sinks:
            sink(t, out)
        summary.rows += 1
        if progress is not None:
            progress(k + 1, total, t)
    summary.wall = time.monotonic() - wall
    return summary


def check_line(params: LineParams, rate: float = DEFAULT_RATE, materials: Any = None) -> None:
    """
    Refuse a line or an output rate that simulate() would refuse; call it before any output.

    :raises ParameterError: rate is not a positive finite number, or the time step is not
        allowed for the line (e.g. above improved_euler's stability limit).
    :raises MaterialError: the material cannot be built.
    """
    if not (math.isfinite(rate) and rate > 0.0):
        raise ParameterError(f'output rate {rate!r} Hz is not allowed: must be > 0')
    Simulator(params, materials, output_interval=1.0 / rate)  # raises what simulate() would


class _Feed:
    """
    Pushes one end's samples into the simulator one sample ahead of the state.

    How an end moves up to a sample depends on the sample after it (the secant's side at
    the sample instant, a spline's tangent there). Knowing one sample beyond the state is
    as good as knowing them all, keeps the simulator's sample buffer short (pushing stays
    O(1) per sample) and gives the same steps as a live node that stays one sample behind
    its newest pose.
    """

    def __init__(self, push: Callable, samples: EndSamples) -> None:
        self.push = push
        self.t = samples.t.tolist()
        self.points = samples.points
        self.next = 0

    def feed(self, until: float) -> None:
        """Push samples until one after the first sample at or after `until` is known."""
        while self.next < len(self.t) and (self.next < 2 or self.t[self.next - 2] < until):
            self.push(self.t[self.next], self.points[self.next])
            self.next += 1


class BagSink:
    """
    Records a run as the node does: input poses and output particles and tensions.

    Inputs are written in stamp order interleaved with the outputs (an input stamped at or
    before an output time is written before that output). Log time = publish time =
    simulated time.
    """

    # Messages the writer thread may hold; write() waits for room instead of dropping.
    QUEUE_SIZE = 20000

    def __init__(self, path, params: LineParams, inputs: Sequence[Tuple[int, str, Any]],
                 input_topics: Mapping[str, str], namespace: str = '',
                 fairlead: Optional[EndSamples] = None,
                 bollard: Optional[EndSamples] = None, base_ns: int = 0) -> None:
        """
        Create the bag (refusing an existing non-empty directory) and its topics.

        :param path: the new bag directory.
        :param params: the run's parameters (frame_id; stored in custom_data).
        :param inputs: (stamp_ns, topic, message or CDR bytes) of every input message.
        :param input_topics: {topic: type} of the inputs.
        :param namespace: namespace of the output topics ('' = root).
        :param fairlead: fairlead samples (for the torque arm), or None.
        :param bollard: bollard samples (for the torque arm), or None.
        :param base_ns: stamp [ns] of simulated time 0 (output stamp = base_ns + t).
        :raises BagError: the directory exists and is not empty, or cannot be created.
        """
        from .bag import BagWriter
        self.frame_id = params.frame_id
        self._inputs = sorted(inputs, key=lambda item: item[0])
        self._next_input = 0
        self._retries = 0
        self._fairlead = fairlead
        self._bollard = bollard
        self._base_ns = int(base_ns)
        self.particles = topic_name(namespace, PARTICLES)
        self.fairlead_tension = topic_name(namespace, FAIRLEAD_TENSION)
        self.bollard_tension = topic_name(namespace, BOLLARD_TENSION)
        self.writer = BagWriter(path, queue_size=self.QUEUE_SIZE,
                                custom_data={PARAMETERS_KEY: parameters_yaml(params)})
        for topic, type_name in input_topics.items():
            self.writer.add_topic(topic, type_name)
        self.writer.add_topic(self.particles, PARTICLES_TYPE)
        self.writer.add_topic(self.fairlead_tension, WRENCH_TYPE)
        self.writer.add_topic(self.bollard_tension, WRENCH_TYPE)

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

    def __call__(self, t: float, out: Output) -> None:
        """Record the inputs up to t, then the outputs at t."""
        ns = self._base_ns + stamp_ns(t)
        self._write_inputs(ns)
        fairlead_lever = self._fairlead.lever_at(t) if self._fairlead else np.zeros(3)
        bollard_lever = self._bollard.lever_at(t) if self._bollard else np.zeros(3)
        self._write(self.particles, particles_cdr(ns, self.frame_id, out.positions), ns)
        self._write(self.fairlead_tension, wrench_message(out.fairlead_force, fairlead_lever),
                    ns)
        self._write(self.bollard_tension, wrench_message(out.bollard_force, bollard_lever), ns)

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
    relative = (motion.t_ns - base_ns) / 1e9
    fairlead = EndSamples(relative, motion.fairlead,
                          np.repeat([fairlead_offset], len(motion), axis=0))
    bollard = None
    if motion.bollard is not None:
        bollard = EndSamples(relative, motion.bollard,
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
        bag = BagSink(bag_path, params, inputs, topics, '', fairlead, bollard, base_ns)
        sinks.append(bag)
    writer = None
    try:
        if out_path is not None:
            writer = OutWriter(out_path)
            sinks.insert(0, lambda t, o: writer.write(
                origin + t if origin else t, o.fairlead_force, o.fairlead_tension,
                o.bollard_force, o.bollard_tension, o.max_strain))
        summary = simulate(params, fairlead, bollard, rate, sinks, progress)
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
    from .bag import BagError
    try:
        if writer is not None:
            writer.close()
    except OSError:
        pass
    try:
        if bag is not None:
            bag.close(complete=False)
    except BagError:
        pass
