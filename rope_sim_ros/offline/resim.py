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
``rope_sim resim``: a bag's inputs through a fresh mooring, into a new bag of the same layout.

Every bag the nodes or ``rope_sim run`` record: a single line's (its poses on
``fairlead/pose``) or an arrangement's (``ship/pose``), in whatever namespace it was
recorded (the only one there is, or --namespace). The parameters are the ones the bag
stores (metadata.yaml's custom_data), else the file given. Nothing depends on the wall
clock, so the same bag and parameters give byte-identical payloads.

A bag a node recorded holds its clock-driven decisions too (its events: a stream taken
for silent, a skip ahead, a reset, a clock jump back, a pose dropped for its stamp, a
parameter set and a winch commanded at run time). Such a bag is replayed in its recorded
order: poses and events go to the driver as the node took them, and the ropes are stepped to
each output the node recorded, so the outputs are the node's to round-off, across gaps and
jumps too. A bag without events, a bag of ``rope_sim run`` (its metadata says so: its
events are the line-handling commands it took or refused and the releases), or a
re-simulation at another --rate, runs the poses in stamp order as ``rope_sim run`` does,
the recorded commands taken again at their times (line_events.py).
"""

from collections import deque
from dataclasses import dataclass, field
import math
import os
import time
from typing import Dict, List, Optional, Tuple

import numpy as np

from .line_events import BagEvents, RECORDED_BY, recorded_commands
from .motion import Streams
from .run import (bag_events, DEFAULT_RATE, driver_for, layout_of, run_bag, RunSummary,
                  simulate, Tally)
from .sinks import BagSink
from ..bag import bag_info, BagError, read_messages
from ..bag.cdr import decode_pose_array, decode_pose_stamped, decode_string
from ..bag.metadata import load_metadata, METADATA_FILE
from ..messages import topics
from ..messages.encode import encoder_for
from ..messages.topics import Layout, stream_of_event
from ..model.frames import pose_point, PoseError, stamp_ns
from ..mooring.driver import Driver, SHIP
from ..mooring.events import decode_event
from ..mooring.trajectory import TrajectoryError
from ..params.arrangement import ArrangementParams, from_stored, stored
from ..params.table import ParameterError


@dataclass
class ResimSummary:
    """
    What a re-simulation did.

    :ivar run: the run's summary.
    :ivar namespace: namespace of the topics re-simulated ('' = root).
    :ivar rate: output rate used [Hz].
    :ivar skipped: input messages left out, with the reason.
    """

    run: RunSummary
    namespace: str
    rate: float
    skipped: List[str] = field(default_factory=list)


def custom_data(path) -> dict:
    """Return the custom_data of a bag's metadata.yaml, or {} without that file."""
    metadata_path = os.path.join(os.fspath(path), METADATA_FILE)
    if not os.path.isfile(metadata_path):
        return {}
    try:
        custom = load_metadata(metadata_path).get('custom_data') or {}
    except BagError:
        return {}
    return custom if isinstance(custom, dict) else {}


def stored_setup(path, overrides: Optional[dict] = None) -> Optional[ArrangementParams]:
    """
    Return the parameters a bag was made with (either kind), or None.

    ``rope_sim run --bag``, ``resim`` and the nodes store them; a bag without them (or
    without metadata.yaml, as a killed recording) gives None.

    :raises ParameterError: stored parameters that are not allowed (with the overrides).
    """
    custom = custom_data(path)
    return from_stored(custom, overrides) if custom else None


def namespaces(path, layout: Layout) -> List[str]:
    """
    Return the namespaces of the bag's ship pose topics of this kind ('' = root), sorted.

    :raises BagError: path is not a readable bag.
    """
    suffix = '/' + layout.ship_pose
    return sorted(name[:-len(suffix)] for name, topic in bag_info(path).topics.items()
                  if name.endswith(suffix) and topic.type_name == topics.POSE_STAMPED)


def choose_namespace(path, layout: Layout, namespace: Optional[str] = None) -> str:
    """
    Return the namespace of the mooring to use from a bag.

    :param namespace: the wanted one (e.g. '/ship/line1'), or None to take the only one.
    :raises BagError: no ship pose topic, the wanted one is missing, or several are
        recorded and none was chosen.
    """
    found = namespaces(path, layout)
    shown = ', '.join(repr(ns or '/') for ns in found)
    if namespace is not None:
        wanted = '/' + namespace.strip('/') if namespace.strip('/') else ''
        if wanted not in found:
            raise BagError(
                f'bag {os.fspath(path)} has no {wanted}/{layout.ship_pose} '
                f'({topics.POSE_STAMPED}); its {layout.node_name} poses are in namespace(s): '
                f'{shown or "none"}')
        return wanted
    if not found:
        raise BagError(
            f'bag {os.fspath(path)} has no .../{layout.ship_pose} topic of type '
            f'{topics.POSE_STAMPED}; nothing to re-simulate')
    if len(found) > 1:
        raise BagError(f'bag {os.fspath(path)} records several of them (namespaces {shown}); '
                       'choose one with --namespace')
    return found[0]


def _rounded_rate(interval_ns: float) -> float:
    rate = 1e9 / interval_ns
    return round(rate, 3 - int(math.floor(math.log10(rate))))


def recorded_rate(path, setup: ArrangementParams, namespace: str = '') -> Optional[float]:
    """
    Return the output rate of a bag (3 significant digits), or None.

    The inverse of the median interval of the first line's rope/particles header stamps.
    """
    topic = f'{namespace}/{layout_of(setup).line_topic(setup.names[0], topics.PARTICLES)}'
    stamps = [stamp_ns(*decode_pose_array(m.data)[:2]) for m in read_messages(path, [topic])]
    intervals = np.diff(np.unique(stamps))
    if not len(intervals):
        return None
    return _rounded_rate(float(np.median(intervals)))


def has_events(path, setup: ArrangementParams, namespace: str = '') -> bool:
    """Tell whether a bag holds an events topic (a node's decisions, or a run's events)."""
    topic = bag_info(path).topics.get(f'{namespace}/{layout_of(setup).events}')
    return topic is not None and topic.type_name == topics.STRING


def is_node_recording(path, setup: ArrangementParams, namespace: str = '') -> bool:
    """Tell whether a bag is a node's recording: its events topic, and not a run's bag."""
    if custom_data(path).get(RECORDED_BY[0]) == RECORDED_BY[1]:
        return False
    return has_events(path, setup, namespace)


def read_streams(path, setup: ArrangementParams, namespace: str,
                 skipped: List[str]) -> Tuple[Streams, list, dict]:
    """
    Return the streams of a bag's poses by the node's rules, and their messages as recorded.

    The node's rules: a bollard's point is its pose ⊕ its bollard_offset; no non-finite
    pose, strictly newer stamps, no negative stamp. The rest is left out, with a reason in
    `skipped`.

    :returns: the Streams, (stamp, relative topic, data) of the poses used, {topic: type}.
    """
    layout = layout_of(setup)
    recorded = bag_info(path).topics
    wanted = {layout.ship_pose: SHIP}
    for line in setup.lines:
        topic = layout.line_topic(line.name, topics.BOLLARD_POSE)
        if f'{namespace}/{topic}' in recorded:
            wanted[topic] = line.name
    by_topic: Dict[str, List[tuple]] = {topic: [] for topic in wanted}
    resolved = {f'{namespace}/{topic}': topic for topic in wanted}
    for message in read_messages(path, list(resolved)):
        sec, nanosec, _, position, orientation = decode_pose_stamped(message.data)
        by_topic[resolved[message.topic]].append(
            (stamp_ns(sec, nanosec), message.data, position, orientation))
    inputs, types, kept = [], {}, {}
    for topic, stream in wanted.items():
        records = sorted(by_topic[topic], key=lambda record: record[0])  # stable
        offset = (np.zeros(3) if stream == SHIP else
                  np.asarray(setup.line(stream).params.bollard_offset, dtype=float))
        rows = []
        for ns, data, position, orientation in records:
            try:
                point = pose_point(position, orientation, offset)
            except PoseError as e:
                skipped.append(f'{namespace}/{topic} at {ns / 1e9:.9f} s: {e}')
                continue
            if rows and ns <= rows[-1][0]:
                skipped.append(f'{namespace}/{topic} at {ns / 1e9:.9f} s: stamp not after the '
                               'previous one')
                continue
            if ns < 0:
                skipped.append(f'{namespace}/{topic} at {ns / 1e9:.9f} s: negative stamp')
                continue
            rows.append((ns, position, orientation, point))
            inputs.append((ns, topic, data))
        if rows:
            types[topic] = topics.POSE_STAMPED
        kept[stream] = rows
    ship = kept[SHIP]
    if not ship:
        raise BagError(f'bag {os.fspath(path)} has no usable message on '
                       f'{namespace}/{layout.ship_pose}; nothing to re-simulate')
    bollards = {stream: (np.array([r[0] for r in rows], dtype=np.int64),
                         np.array([r[3].point for r in rows]),
                         np.array([r[3].lever for r in rows]))
                for stream, rows in kept.items() if stream != SHIP and rows}
    streams = Streams(os.fspath(path), np.array([r[0] for r in ship], dtype=np.int64),
                      np.array([r[1] for r in ship]), np.array([r[2] for r in ship]),
                      bollards, origin=ship[0][0] / 1e9)
    return streams, inputs, types


def resim(path, out_path, setup: ArrangementParams, rate: Optional[float] = None,
          namespace: Optional[str] = None, progress=None) -> ResimSummary:
    """
    Re-simulate a bag's inputs with the given parameters into a new bag (module docstring).

    :param rate: output rate [Hz]; None = the recorded one: a node recording is replayed at
        the node's own output times, another bag at the rate of its particles, else 100 Hz.
    :param namespace: the mooring's namespace in the bag; None = the only one there is.
    :raises BagError: the bag cannot be read, holds no usable ship pose, or the new bag
        cannot be written.
    :raises ParameterError: a bad rate or line.
    """
    layout = layout_of(setup)
    namespace = choose_namespace(path, layout, namespace)
    if rate is None and is_node_recording(path, setup, namespace):
        return _replay(path, out_path, setup, namespace, progress)
    skipped: List[str] = []
    streams, inputs, types = read_streams(path, setup, namespace, skipped)
    commands = (recorded_commands(path, f'{namespace}/{layout.events}')
                if has_events(path, setup, namespace) else [])
    if rate is None:
        rate = recorded_rate(path, setup, namespace) or DEFAULT_RATE
    driver_for(setup, rate)  # a refused line leaves no bag behind
    sink = run_bag(out_path, setup, namespace, inputs, types, bool(commands))
    events = [BagEvents(sink, layout)] if bag_events(setup, bool(commands)) else []
    try:
        summary = simulate(setup, streams, rate, [sink], progress, commands=commands,
                           events=events)
    except BaseException:
        sink.abandon()
        raise
    summary.dropped = sink.close()
    return ResimSummary(summary, namespace, rate, skipped)


def _replay(path, out_path, setup: ArrangementParams, namespace: str,
            progress) -> ResimSummary:
    """
    Replay a node recording in its recorded order (see the module docstring).

    The node records a pose as it takes it, an event as it decides, an output as it
    publishes it, with strictly increasing log times: read in log-time order, the bag is the
    node's own sequence. A pose the node dropped for its stamp follows its 'drop' event; an
    unstamped pose its 'restamp' event (the receive time the node used).
    """
    wall = time.monotonic()
    layout = layout_of(setup)
    # as the node: its rate, 5 s of samples kept (a refused line leaves no bag behind)
    driver = Driver(setup, rate=setup.shared.publish_rate)
    recorded = bag_info(path).topics
    streams = {} if setup.ship.free else {layout.ship_pose: SHIP}  # (a free ship's: output)
    for line in setup.lines:
        streams[layout.line_topic(line.name, topics.BOLLARD_POSE)] = line.name
    streams = {topic: stream for topic, stream in streams.items()
               if f'{namespace}/{topic}' in recorded}
    resolved = {f'{namespace}/{topic}': topic for topic in
                [*streams, layout.events,
                 layout.line_topic(setup.names[0], topics.PARTICLES)]}
    particles = layout.line_topic(setup.names[0], topics.PARTICLES)
    total = recorded[f'{namespace}/{particles}'].message_count \
        if f'{namespace}/{particles}' in recorded else 0
    sink = BagSink(out_path, encoder_for(setup), namespace, [],
                   {topic: topics.POSE_STAMPED for topic in streams}, stored(setup),
                   {layout.events: topics.STRING})
    summary = RunSummary(time_step=driver.time_step,
                         reach=dict(zip(driver.names, driver.reaches)))
    tally = Tally(summary, driver.names)
    skipped: List[str] = []
    dropped: Dict[str, deque] = {stream: deque() for stream in driver.streams}
    restamped: Dict[str, deque] = {stream: deque() for stream in driver.streams}
    ahead = Ahead(driver)
    first_ns = None
    try:
        for message in read_messages(path, list(resolved)):
            topic = resolved[message.topic]
            if topic == particles:
                if not driver.started:
                    continue
                output_ns = stamp_ns(*decode_pose_array(message.data)[:2])
                for published in ahead.until(output_ns):
                    tally.add(published)
                    sink.write_output(published, message.log_time_ns)
                    first_ns = published.stamp_ns if first_ns is None else first_ns
                    if progress is not None:
                        progress(summary.rows, max(total, summary.rows), published.output.t)
                continue
            sink.write(topic, message.data, message.log_time_ns)
            if topic == layout.events:
                _apply_event(driver, setup, decode_string(message.data), dropped, restamped,
                             ahead)
                continue
            stream = streams[topic]
            sec, nanosec, _, position, orientation = decode_pose_stamped(message.data)
            ns = stamp_ns(sec, nanosec)
            if dropped[stream] and dropped[stream][0] == ns:
                dropped[stream].popleft()
                skipped.append(f'{message.topic} at {ns / 1e9:.9f} s: dropped by the node for '
                               'its stamp')
                continue
            if ns == 0 and restamped[stream]:
                ns = restamped[stream].popleft()
            try:
                _push(driver, setup, stream, ns, position, orientation)
            except (PoseError, TrajectoryError, ParameterError) as e:
                skipped.append(f'{message.topic} at {ns / 1e9:.9f} s: {e}')
    except BaseException:
        sink.abandon()
        raise
    summary.dropped = sink.close()
    if summary.rows == 0:
        raise BagError(f'bag {os.fspath(path)}: the node published no output from its '
                       f'poses on {namespace}/{layout.ship_pose}; nothing to re-simulate')
    # Outputs in stamps: the epoch may change (a clock jump back), the first stamp not.
    summary.end = first_ns / 1e9 + (summary.end - summary.start)
    summary.start = first_ns / 1e9
    summary.wall = time.monotonic() - wall
    return ResimSummary(summary, namespace, driver.rate, skipped)


class Ahead:
    """
    The outputs the node reached before it published them, as the replay reaches them.

    A live node reaches outputs ahead of the clock and holds them for their time
    (mooring/pacing.py); a decision taken meanwhile (a command, a winch, a reset) is taken
    at its state time, after the outputs it holds, which are recorded after it. The replay
    steps to that time first (catch_up) and writes those outputs as their own recorded
    messages come (until).
    """

    def __init__(self, driver: Driver):
        """Start with nothing reached ahead."""
        self.driver = driver
        self.reached: deque = deque()

    def catch_up(self, t: float) -> None:
        """Step to the state time t [s] at which the node took a decision."""
        self.reached.extend(self.driver.outputs_until(t).outputs)

    def until(self, output_ns: int) -> list:
        """Return the outputs up to a recorded one (stamp [ns]), reaching it if need be."""
        self.reached.extend(self.driver.outputs_until(self.driver.seconds(output_ns)).outputs)
        done = []
        while self.reached and self.reached[0].stamp_ns <= output_ns:
            done.append(self.reached.popleft())
        return done

    def drop(self) -> None:
        """Forget the outputs reached ahead: the node never published them (a reset)."""
        self.reached.clear()


def _push(driver: Driver, setup: ArrangementParams, stream: str, ns: int, position,
          orientation) -> None:
    """Push one recorded pose as the node pushes it."""
    if stream == SHIP:
        driver.push_ship(ns, position, orientation)
        return
    point = pose_point(position, orientation, setup.line(stream).params.bollard_offset)
    driver.push_bollard(stream, ns, point.point, point.lever)


def _apply_event(driver: Driver, setup: ArrangementParams, text: str, dropped: Dict[str, deque],
                 restamped: Dict[str, deque], ahead: Ahead) -> None:
    """Take one of the node's decisions, as the node took it (at its state time)."""
    try:
        event = decode_event(text)
        kind = event['event']
        if kind in ('drop', 'restamp', 'silent'):
            stream = stream_of_event(event, setup.names[0])
            if stream not in dropped:
                raise ValueError(f'no stream in {text!r}')
            if kind == 'drop':
                dropped[stream].append(int(event['stamp']))
            elif kind == 'restamp':
                restamped[stream].append(int(event['stamp']))
            else:
                driver.silence(stream)
        elif kind == 'skip':
            if driver.started:
                driver.skip(float(event['t']))
        elif kind == 'reset':
            if driver.started:
                ahead.catch_up(float(event['t']))
                ahead.drop()  # the node's held outputs, of the lines before the reset
                driver.reset()
        elif kind == 'clock_back':
            ahead.drop()
            driver.clear()
        elif kind == 'start':  # a free ship's, at the node's first tick
            if not driver.started:
                driver.start_free(int(event['stamp']))
        elif kind == 'load':
            driver.set_external_load(event['force'], event['moment'], event['frame'] == 'body')
        elif kind == 'set':
            driver.update(event.get('line'), dict(event['values']))  # None: every line
        elif kind == 'winch':
            ahead.catch_up(float(event['t']))
            driver.command_winch(event.get('line', setup.names[0] if setup.single else None),
                                 float(event['speed']))
        elif kind == 'command':  # taken by the node, so taken again (a refusal is an error)
            ahead.catch_up(float(event['t']))
            command = str(event['command'])
            driver.command(None if command == 'let_go_all' else str(event['line']), command)
        # 'parted', 'ship_restart' and 'released' say what the model did: replayed, it does
        # it again
    except (ValueError, KeyError, TypeError, ParameterError) as e:
        raise BagError(f'{layout_of(setup).events}: cannot replay {text!r}: {e}') from None
