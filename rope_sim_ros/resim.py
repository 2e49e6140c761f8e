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
Re-simulate a bag: its recorded input poses through a fresh line, offline.

The fairlead and bollard poses of a bag (stamps from their headers, end point = pose ⊕
offset as the node computes it) drive a line_driver.LineDriver, the node's own rules; the
new bag has the same layout (the input messages byte for byte, and the outputs). Nothing
depends on the wall clock, so the same bag and parameters give byte-identical payloads.

A bag the node recorded holds its clock-driven decisions too (rope/events: a stream taken
for silent, a skip ahead, a reset, a clock jump back, a pose dropped for its stamp, a
parameter set at run time). Such a bag is replayed in its recorded order: poses and events
go to the driver as the node handled them, and the rope is stepped to each output the node
recorded, so the outputs are the node's to round-off, across gaps and jumps too. A bag
without events (``rope_sim run``), or a re-simulation at another --rate, runs the poses in
stamp order as ``rope_sim run`` does.
"""

from collections import deque
from dataclasses import dataclass, field
import math
import os
import time
from typing import Dict, List, Optional, Tuple

import numpy as np

from .bag import bag_info, BagError, read_messages
from .bag.cdr import decode_pose_array, decode_pose_stamped, decode_string
from .bag.metadata import load_metadata, METADATA_FILE
from .line_driver import (BOLLARD, decode_event, EVENTS_TOPIC, FAIRLEAD, LineDriver,
                          parameters_from_yaml, PARAMETERS_KEY)
from .model.frames import pose_point, PoseError, stamp_ns
from .params.table import LineParams, ParameterError
from .runner import (BagSink, BOLLARD_POSE, check_line, DEFAULT_RATE, EndSamples,
                     FAIRLEAD_POSE, PARTICLES, POSE_TYPE, RunSummary, simulate, Tally,
                     topic_name)
from .trajectory import TrajectoryError

STRING_TYPE = 'std_msgs/msg/String'


@dataclass
class ResimSummary:
    """
    What a re-simulation did.

    :param run: the offline run's summary.
    :param namespace: namespace of the topics re-simulated ('' = root).
    :param rate: output rate used [Hz].
    :param skipped: input messages left out, with the reason.
    """

    run: RunSummary
    namespace: str
    rate: float
    skipped: List[str] = field(default_factory=list)


def bag_namespaces(path) -> List[str]:
    """
    Return the namespaces of the bag's fairlead/pose topics ('' = root), sorted.

    :raises BagError: path is not a readable bag.
    """
    suffix = '/' + FAIRLEAD_POSE
    return sorted(name[:-len(suffix)] for name, topic in bag_info(path).topics.items()
                  if name.endswith(suffix) and topic.type_name == POSE_TYPE)


def choose_namespace(path, namespace: Optional[str] = None) -> str:
    """
    Return the namespace of the line to use from a bag.

    :param path: the bag.
    :param namespace: the wanted one (e.g. '/ship/line1'), or None to take the only one.
    :raises BagError: no fairlead/pose topic, the wanted one is missing, or several lines
        are recorded and none was chosen.
    """
    found = bag_namespaces(path)
    shown = ', '.join(repr(ns or '/') for ns in found)
    if namespace is not None:
        wanted = '/' + namespace.strip('/') if namespace.strip('/') else ''
        if wanted not in found:
            raise BagError(
                f'bag {os.fspath(path)} has no {topic_name(wanted, FAIRLEAD_POSE)} '
                f'({POSE_TYPE}); its lines are in namespace(s): {shown or "none"}')
        return wanted
    if not found:
        raise BagError(
            f'bag {os.fspath(path)} has no .../{FAIRLEAD_POSE} topic of type {POSE_TYPE}; '
            'nothing to re-simulate')
    if len(found) > 1:
        raise BagError(
            f'bag {os.fspath(path)} records several lines (namespaces {shown}); choose one '
            'with --namespace')
    return found[0]


def stored_parameters(path) -> Optional[Dict]:
    """
    Return the parameters a bag was made with (metadata.yaml custom_data), or None.

    ``rope_sim run --bag`` and ``rope_sim resim`` store them; a bag without them (or
    without metadata.yaml, as a killed recording) gives None.
    """
    metadata_path = os.path.join(os.fspath(path), METADATA_FILE)
    if not os.path.isfile(metadata_path):
        return None
    try:
        custom = load_metadata(metadata_path).get('custom_data') or {}
    except BagError:
        return None
    text = custom.get(PARAMETERS_KEY) if isinstance(custom, dict) else None
    return parameters_from_yaml(text) if text else None


def _rounded_rate(interval_ns: float) -> float:
    rate = 1e9 / interval_ns
    digits = 3 - int(math.floor(math.log10(rate)))
    return round(rate, digits)


def recorded_rate(path, namespace: str = '') -> Optional[float]:
    """
    Return the output rate of a bag's rope/particles (3 significant digits), or None.

    The rate is the inverse of the median interval of the header stamps.
    """
    stamps = [stamp_ns(*decode_pose_array(m.data)[:2]) for m in read_messages(
        path, [topic_name(namespace, PARTICLES)])]
    intervals = np.diff(np.unique(stamps))
    if not len(intervals):
        return None
    return _rounded_rate(float(np.median(intervals)))


@dataclass
class _End:
    stamps: List[int] = field(default_factory=list)
    points: List[np.ndarray] = field(default_factory=list)
    levers: List[np.ndarray] = field(default_factory=list)
    raw: List[Tuple[int, str, bytes]] = field(default_factory=list)

    def samples(self) -> Optional[EndSamples]:
        if not self.stamps:
            return None
        return EndSamples(np.array(self.stamps, dtype=np.int64), np.array(self.points),
                          np.array(self.levers))


def _read_end(path, topic: str, offset: np.ndarray, skipped: List[str]) -> _End:
    records = []
    for message in read_messages(path, [topic]):
        sec, nanosec, _, position, orientation = decode_pose_stamped(message.data)
        records.append((stamp_ns(sec, nanosec), message.data, position, orientation))
    records.sort(key=lambda record: record[0])  # stable: equal stamps keep bag order
    end = _End()
    for ns, data, position, orientation in records:
        # The node's rules: pose ⊕ offset, no non-finite pose, strictly newer stamps.
        try:
            point = pose_point(position, orientation, offset)
        except PoseError as e:
            skipped.append(f'{topic} at {ns / 1e9:.9f} s: {e}')
            continue
        if end.stamps and ns <= end.stamps[-1]:
            skipped.append(f'{topic} at {ns / 1e9:.9f} s: stamp not after the previous one')
            continue
        if ns < 0:
            skipped.append(f'{topic} at {ns / 1e9:.9f} s: negative stamp')
            continue
        end.stamps.append(ns)
        end.points.append(point.point)
        end.levers.append(point.lever)
        end.raw.append((ns, topic, data))
    return end


def has_events(path, namespace: str = '') -> bool:
    """Tell whether a bag holds the node's decisions (rope/events): a node recording."""
    topic = bag_info(path).topics.get(topic_name(namespace, EVENTS_TOPIC))
    return topic is not None and topic.type_name == STRING_TYPE


def resim(path, out_path, params: LineParams, rate: Optional[float] = None,
          namespace: Optional[str] = None, progress=None) -> ResimSummary:
    """
    Re-simulate a bag's inputs with the given parameters into a new bag.

    :param path: the recorded bag.
    :param out_path: the new bag directory (must not exist or be empty).
    :param params: validated parameters for the fresh line.
    :param rate: output rate [Hz]; None = the recorded one: a node recording (with
        rope/events) is replayed at the node's own output times, another bag at the rate
        of its rope/particles, else 100 Hz.
    :param namespace: the line's namespace in the bag; None = the only one there is.
    :param progress: callable progress(done, total, t), or None.
    :returns: the ResimSummary.
    :raises BagError: the bag cannot be read, holds no usable fairlead pose, or the new
        bag cannot be written.
    :raises ParameterError: a bad rate.
    """
    namespace = choose_namespace(path, namespace)
    if rate is None and has_events(path, namespace):
        return _replay(path, out_path, params, namespace, progress)
    skipped: List[str] = []
    fairlead = _read_end(path, topic_name(namespace, FAIRLEAD_POSE),
                         np.asarray(params.fairlead_offset, dtype=float), skipped)
    bollard_topic = topic_name(namespace, BOLLARD_POSE)
    has_bollard = bollard_topic in bag_info(path).topics
    bollard = _read_end(path, bollard_topic, np.asarray(params.bollard_offset, dtype=float),
                        skipped) if has_bollard else _End()
    if not fairlead.stamps:
        raise BagError(
            f'bag {os.fspath(path)} has no usable message on '
            f'{topic_name(namespace, FAIRLEAD_POSE)}; nothing to re-simulate')
    if rate is None:
        rate = recorded_rate(path, namespace) or DEFAULT_RATE
    base_ns = fairlead.stamps[0]
    topics = {topic_name(namespace, FAIRLEAD_POSE): POSE_TYPE}
    if has_bollard:
        topics[bollard_topic] = POSE_TYPE
    check_line(params, rate)  # a refused line leaves no bag behind
    sink = BagSink(out_path, params, fairlead.raw + bollard.raw, topics, namespace)
    try:
        summary = simulate(params, fairlead.samples(), bollard.samples(), rate, [sink],
                           progress)
    except BaseException:
        sink.abandon()
        raise
    summary.dropped = sink.close()
    summary.start += base_ns / 1e9
    summary.end += base_ns / 1e9
    return ResimSummary(summary, namespace, rate, skipped)


def _replay(path, out_path, params: LineParams, namespace: str, progress) -> ResimSummary:
    """
    Replay a node recording in its recorded order (see the module docstring).

    The node records a pose as it takes it, an event as it decides, an output as it
    publishes it, with strictly increasing log times: read in log-time order, the bag is
    the node's own sequence. A pose the node dropped for its stamp follows its 'drop'
    event; an unstamped pose its 'restamp' event (the receive time the node used).
    """
    wall = time.monotonic()
    check_line(params, params.publish_rate)  # a refused line leaves no bag behind
    topics = {end: topic_name(namespace, relative) for end, relative in (
        (FAIRLEAD, FAIRLEAD_POSE), (BOLLARD, BOLLARD_POSE))}
    ends = {topic: end for end, topic in topics.items()}
    offsets = {FAIRLEAD: np.asarray(params.fairlead_offset, dtype=float),
               BOLLARD: np.asarray(params.bollard_offset, dtype=float)}
    events_topic = topic_name(namespace, EVENTS_TOPIC)
    particles_topic = topic_name(namespace, PARTICLES)
    recorded = bag_info(path).topics
    inputs = {topic: POSE_TYPE for topic in topics.values() if topic in recorded}
    total = recorded[particles_topic].message_count if particles_topic in recorded else 0
    driver = LineDriver(params)
    sink = BagSink(out_path, params, [], inputs, namespace, {events_topic: STRING_TYPE})
    summary = RunSummary(time_step=driver.simulator.time_step, reach=driver.simulator.reach)
    tally = Tally(summary)
    skipped: List[str] = []
    dropped: Dict[str, deque] = {FAIRLEAD: deque(), BOLLARD: deque()}
    restamped: Dict[str, deque] = {FAIRLEAD: deque(), BOLLARD: deque()}
    first_ns = None
    try:
        for message in read_messages(path, [*inputs, events_topic, particles_topic]):
            topic = message.topic
            if topic == particles_topic:
                if not driver.started:
                    continue
                output_ns = stamp_ns(*decode_pose_array(message.data)[:2])
                report = driver.outputs_until(driver.seconds(output_ns))
                for published in report.outputs:
                    tally.add(published)
                    sink.write_output(published, message.log_time_ns)
                    first_ns = published.stamp_ns if first_ns is None else first_ns
                    if progress is not None:
                        progress(summary.rows, max(total, summary.rows), published.output.t)
                continue
            sink.write(topic, message.data, message.log_time_ns)
            if topic == events_topic:
                _apply_event(driver, decode_string(message.data), dropped, restamped)
                continue
            end = ends[topic]
            sec, nanosec, _, position, orientation = decode_pose_stamped(message.data)
            ns = stamp_ns(sec, nanosec)
            if dropped[end] and dropped[end][0] == ns:
                dropped[end].popleft()
                skipped.append(f'{topic} at {ns / 1e9:.9f} s: dropped by the node for its '
                               'stamp')
                continue
            if ns == 0 and restamped[end]:
                ns = restamped[end].popleft()
            try:
                point = pose_point(position, orientation, offsets[end])
                driver.push(end, ns, point.point, point.lever)
            except (PoseError, TrajectoryError) as e:
                skipped.append(f'{topic} at {ns / 1e9:.9f} s: {e}')
    except BaseException:
        sink.abandon()
        raise
    summary.dropped = sink.close()
    if summary.rows == 0:
        raise BagError(f'bag {os.fspath(path)}: the node published no output from its '
                       f'poses on {topics[FAIRLEAD]}; nothing to re-simulate')
    # Outputs in stamps: the epoch may change (a clock jump back), the first stamp not.
    summary.end = first_ns / 1e9 + (summary.end - summary.start)
    summary.start = first_ns / 1e9
    summary.wall = time.monotonic() - wall
    return ResimSummary(summary, namespace, driver.rate, skipped)


def _apply_event(driver: LineDriver, text: str, dropped: Dict[str, deque],
                 restamped: Dict[str, deque]) -> None:
    """Take one of the node's decisions, as the node took it."""
    try:
        event = decode_event(text)
        kind = event['event']
        if kind in ('drop', 'restamp', 'silent') and event.get('end') not in (FAIRLEAD,
                                                                              BOLLARD):
            raise ValueError(f'no end in {text!r}')
        if kind == 'drop':
            dropped[event['end']].append(int(event['stamp']))
        elif kind == 'restamp':
            restamped[event['end']].append(int(event['stamp']))
        elif kind == 'silent':
            driver.silence(event['end'])
        elif kind == 'skip':
            if driver.started:
                driver.skip(float(event['t']))
        elif kind == 'reset':
            if driver.started:
                driver.reset()
        elif kind == 'clock_back':
            driver.clear()
        elif kind == 'set':
            driver.update(dict(event['values']))
        elif kind == 'winch':
            driver.command_winch(float(event['speed']))
        # 'parted' says what the model did: replayed, the model does it again
    except (ValueError, KeyError, TypeError, ParameterError) as e:
        raise BagError(f'rope/events: cannot replay {text!r}: {e}') from None
