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
The one offline loop: ``rope_sim run`` and ``rope_sim resim`` of a line or an arrangement.

The samples go into one Driver (mooring/driver.py), the nodes' own input and output rules,
in stamp order (a bollard sample before a ship pose of the same stamp, so that a line
starts between both), each stream taken for finished after its last sample: the ropes stay
one sample behind the streams, which moves the ends exactly as if the whole motion were
known. The ropes start at the first ship pose and outputs follow every 1 / rate s up to the
last one. Each output goes to the sinks (sinks.py: OUT.csv rows, a bag as the node records
it, a study's summary).

Line-handling commands (COMMANDS.csv, motion.py) go to the Driver's schedule: each is taken
before the steps of the first output interval that starts at or after its time (so the
first output to show it is the one after that), and what it did, or why it was refused, is
a LineEvent, as is a line that its quick-release hook let go. The events go to the event
sinks in time order with the outputs (the command line prints them) and, in a bag, on the
node's events topic (line_events.py).
"""

from collections import deque
from dataclasses import dataclass, field
import math
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .line_events import BagEvents, EventSink, LineEvent, RECORDED_BY
from .motion import LoadSchedule, MotionError, Streams
from .sinks import BagSink, CsvSink
from ..messages import topics
from ..messages.encode import encoder_for, pose_stamped
from ..messages.topics import Layout
from ..mooring.driver import Driver, SHIP
from ..mooring.records import Handled, Published, Report, ScheduledCommand
from ..mooring.ship import reports_ship_loads, reports_waves
from ..mooring.status import ratings
from ..params.arrangement import ArrangementParams, stored
from ..params.table import ParameterError

DEFAULT_RATE = 100.0

Sink = Callable[[Published], None]


@dataclass
class RunSummary:
    """
    What an offline run did.

    :ivar rows: outputs produced.
    :ivar start, end: first and last output time [s] (in the motion file's time base).
    :ivar time_step: the smallest integration step [s].
    :ivar restarts: (time [s], line, reason) of every restart of a line at rest ('non-finite
        state', 'unphysical state', 'back within reach').
    :ivar beyond_reach: (time [s], line, largest distance [m]) of every stretch of outputs
        during which a line's ends were farther apart than its reach (its fairlead was held
        at the reach).
    :ivar reach: each line's reach, L (1 + max_strain) [m], by name.
    :ivar events: the line events (commands taken or refused, releases), in time order.
    :ivar not_taken: the scheduled commands the run ended before.
    :ivar dropped: bag messages not recorded.
    :ivar wall: wall-clock seconds.
    """

    rows: int = 0
    start: float = math.nan
    end: float = math.nan
    time_step: float = math.nan
    restarts: List[Tuple[float, str, str]] = field(default_factory=list)
    beyond_reach: List[Tuple[float, str, float]] = field(default_factory=list)
    reach: Dict[str, float] = field(default_factory=dict)
    events: List[LineEvent] = field(default_factory=list)
    not_taken: List[ScheduledCommand] = field(default_factory=list)
    dropped: int = 0
    wall: float = 0.0


class Tally:
    """Counts outputs into a RunSummary: rows, first and last time, restarts, reach."""

    def __init__(self, summary: RunSummary, names: Sequence[str], origin: float = 0.0) -> None:
        """Count into `summary` the outputs of lines `names`; times from origin [s]."""
        self.summary = summary
        self.names = list(names)
        self.origin = origin
        self._held: Dict[int, int] = {}  # line: its stretch's index in beyond_reach

    def add(self, published: Published) -> None:
        """Count one output."""
        summary = self.summary
        t, advance = self.origin + published.output.t, published.advance
        if summary.rows == 0:
            summary.start = t
        summary.end = t
        summary.rows += 1
        beyond = advance.beyond_reach if advance is not None else {}
        if advance is not None:
            summary.restarts += [(t, self.names[k], why) for k, why in advance.restarted.items()]
        for k in list(self._held):
            if k not in beyond:
                del self._held[k]
        for k, distance in beyond.items():
            if k in self._held:
                i = self._held[k]
                start, name, before = summary.beyond_reach[i]
                summary.beyond_reach[i] = (start, name, max(before, distance))
            else:
                self._held[k] = len(summary.beyond_reach)
                summary.beyond_reach.append((t, self.names[k], distance))


class Delivery:
    """
    Hands a run's outputs to its sinks and its line events to theirs, in time order.

    A command taken at an output's time comes after that output (it acts on the steps
    after it); a release comes before the output whose steps it ended.
    """

    def __init__(self, driver: Driver, summary: RunSummary, origin: float,
                 sinks: Sequence[Sink], events: Sequence[EventSink],
                 progress: Optional[Callable[[int, int, float], None]], total: int) -> None:
        """Deliver to these sinks, counting into `summary` (times from origin [s])."""
        self.driver = driver
        self.summary = summary
        self.tally = Tally(summary, driver.names, origin)
        self.sinks = list(sinks)
        self.events = list(events)
        self.progress = progress
        self.total = total

    def __call__(self, report: Report) -> None:
        """Deliver what one call of the driver gave."""
        pending = deque(report.handled)
        for published in report.outputs:
            while pending and pending[0].t < published.output.t:
                self._send(self._taken(pending.popleft()))
            if published.advance is not None:
                for k, tension in published.advance.released.items():
                    self._send(self._released(k, tension, published.output.t))
            self.tally.add(published)
            for sink in self.sinks:
                sink(published)
            if self.progress is not None:
                rows = self.summary.rows
                self.progress(rows, max(self.total, rows), published.output.t)
        while pending:
            self._send(self._taken(pending.popleft()))

    def finish(self) -> None:
        """Keep the commands the run ended before (summary.not_taken)."""
        self.summary.not_taken = list(self.driver.command_schedule)

    def _send(self, event: LineEvent) -> None:
        self.summary.events.append(event)
        for sink in self.events:
            sink(event)

    def _taken(self, handled: Handled) -> LineEvent:
        scheduled = handled.scheduled
        return LineEvent('command', handled.t, self.driver.stamp_ns(handled.t), scheduled.line,
                         handled.text, scheduled.command, handled.refused, handled.bollard)

    def _released(self, k: int, tension: float, t: float) -> LineEvent:
        name = self.driver.names[k]
        load = self.driver.arrangement.lines[k].params.release_load
        text = (f'{"line " + name if name else "the line"} let go by its quick-release hook at '
                f'{tension / 1e3:.1f} kN (release_load {load / 1e3:g} kN)')
        return LineEvent('released', t, self.driver.stamp_ns(t), name, text, tension=tension)


def driver_for(setup: ArrangementParams, rate: float, materials: Any = None) -> Driver:
    """
    Return the Driver of an offline run: no clock, so no skip ahead; the whole motion kept.

    :raises ParameterError: a bad rate or a line that cannot be built (call it before any
        file is written: it refuses what simulate would).
    """
    return Driver(setup, materials, rate=rate, history=math.inf)


def free_driver(setup: ArrangementParams, loads: Optional[LoadSchedule], rate: float,
                materials: Any = None) -> Driver:
    """
    Return the Driver of a free ship's offline run, its loads scheduled.

    :raises ParameterError: a bad rate, a line that cannot be built, or a load past what
        any tug or thruster gives (naming LOADS.csv and the row).
    """
    driver = driver_for(setup, rate, materials)
    if loads is not None:
        try:
            driver.set_load_schedule(loads.times, loads.loads)
        except ValueError as e:
            raise ParameterError(f'--loads {loads.path}: {e}') from None
    return driver


def simulate(setup: ArrangementParams, streams: Streams, rate: float = DEFAULT_RATE,
             sinks: Sequence[Sink] = (),
             progress: Optional[Callable[[int, int, float], None]] = None,
             materials: Any = None, commands: Sequence[ScheduledCommand] = (),
             events: Sequence[EventSink] = ()) -> RunSummary:
    """
    Run the mooring through the streams and hand every output to the sinks.

    Simulated time 0 is the first stamp; outputs fall every 1 / rate s from the first ship
    pose to the last.

    :param commands: line-handling commands at their simulated times, in time order.
    :param events: where each LineEvent goes (also kept in the summary).
    :raises ParameterError: a bad rate, or a pretension no length gives at the first pose.
    :raises TrajectoryError, PoseError: a sample is not usable.
    """
    wall = time.monotonic()
    driver = driver_for(setup, rate, materials)
    driver.command_schedule.extend(commands)
    names = driver.names
    first_ns = min([int(streams.t_ns[0])] + [int(s[0][0]) for s in streams.bollards.values()])
    for name, speeds in streams.winch.items():
        driver.winch_schedules[names.index(name)] = (
            (np.asarray(streams.t_ns) - first_ns) / 1e9, np.asarray(speeds, dtype=float))
    order = sorted([(int(ns), 1, SHIP, i) for i, ns in enumerate(streams.t_ns.tolist())]
                   + [(int(ns), 0, name, i) for name, (stamps, _, _) in streams.bollards.items()
                      for i, ns in enumerate(stamps.tolist())])
    counts = {SHIP: len(streams), **{name: len(s[0]) for name, s in streams.bollards.items()}}
    last_ns = int(streams.t_ns[-1])
    total = int(math.floor((last_ns - int(streams.t_ns[0])) / 1e9 * rate + 1e-9)) + 1
    summary = RunSummary(time_step=driver.time_step,
                         reach=dict(zip(driver.names, driver.reaches)))
    take = Delivery(driver, summary, streams.origin, sinks, events, progress, total)
    for ns, _, stream, i in order:
        if stream == SHIP:
            driver.push_ship(ns, streams.position[i], streams.orientation[i])
        else:
            _, points, levers = streams.bollards[stream]
            driver.push_bollard(stream, ns, points[i], levers[i])
        if i == counts[stream] - 1:
            driver.silence(stream)  # its last sample: nothing more to wait for
        if driver.started:
            take(driver.advance(driver.seconds(last_ns), max_lag=math.inf))
    take(driver.advance(driver.seconds(last_ns), max_lag=math.inf))
    take.finish()
    summary.wall = time.monotonic() - wall
    return summary


def simulate_free(setup: ArrangementParams, duration: float, loads: Optional[LoadSchedule] = None,
                  rate: float = DEFAULT_RATE, sinks: Sequence[Sink] = (),
                  progress: Optional[Callable[[int, int, float], None]] = None,
                  materials: Any = None, commands: Sequence[ScheduledCommand] = (),
                  events: Sequence[EventSink] = ()) -> RunSummary:
    """
    Run a free ship from rest at its start pose for `duration` s under its loads.

    Outputs every 1 / rate s from 0 to duration, each to the sinks.

    :param loads: the external load over time (LOADS.csv); None: none.
    :param commands, events: as simulate's.
    :raises ParameterError: not a free ship, a bad rate or duration, or a pretension no
        length gives at the start pose.
    """
    wall = time.monotonic()
    if not setup.ship.free:
        raise ParameterError('a run without a motion file moves a free ship: set ship_mode: '
                             'free, or give --motion SHIP.csv for a driven one')
    if not (math.isfinite(duration) and duration > 0.0):
        raise ParameterError(f'--duration {duration!r} is not allowed: must be a number of '
                             'seconds > 0')
    driver = free_driver(setup, loads, rate, materials)
    driver.command_schedule.extend(commands)
    summary = RunSummary(time_step=driver.time_step,
                         reach=dict(zip(driver.names, driver.reaches)))
    total = int(math.floor(duration * rate + 1e-9)) + 1
    take = Delivery(driver, summary, 0.0, sinks, events, progress, total)
    driver.start_free(0)
    chunk = max(1.0, 10.0 / rate)  # outputs in chunks, so that progress shows
    t = 0.0
    while True:
        t = min(t + chunk, duration)
        take(driver.outputs_until(t))
        if t >= duration:
            break
    take.finish()
    summary.wall = time.monotonic() - wall
    return summary


def run_free(setup: ArrangementParams, duration: float, loads: Optional[LoadSchedule] = None,
             out_path=None, rate: float = DEFAULT_RATE, progress=None,
             materials: Any = None, sinks: Sequence[Sink] = (),
             commands: Sequence[ScheduledCommand] = (),
             events: Sequence[EventSink] = ()) -> RunSummary:
    """
    Run a free ship (simulate_free) into OUT.csv with its motion and fenders (sinks.py).

    :param sinks: more sinks every output goes to (a study's SummarySink).
    :param commands, events: as simulate's.
    :raises ParameterError: as simulate_free, before any file exists.
    :raises OSError: OUT.csv cannot be written.
    """
    free_driver(setup, loads, rate, materials)  # refuses a bad rate, line or load first
    writer = None
    outputs: List[Sink] = list(sinks)
    if out_path is not None:
        writer = CsvSink(out_path, setup.names, ratings(setup), free=True,
                         fenders=[(fender.name, fender.normal) for fender in setup.fenders],
                         loads=True, waves=reports_waves(setup))
        outputs.insert(0, writer)
    try:
        summary = simulate_free(setup, duration, loads, rate, outputs, progress, materials,
                                commands, events)
    finally:
        if writer is not None:
            writer.close()
    return summary


def input_messages(setup: ArrangementParams, streams: Streams) -> Tuple[list, dict]:
    """
    Return the poses of the streams as the node would receive them: (stamp, topic, CDR) rows.

    A bollard's pose is its point less its lever (its pose's origin), with identity
    orientation: a re-simulation that adds the bollard's offset finds the same point.
    """
    layout = layout_of(setup)
    frame_id = setup.shared.frame_id
    rows = [(ns, layout.ship_pose, pose_stamped(ns, frame_id, p, q))
            for ns, p, q in zip(streams.t_ns.tolist(), streams.position, streams.orientation)]
    types = {layout.ship_pose: topics.POSE_STAMPED}
    for name, (stamps, points, levers) in streams.bollards.items():
        topic = layout.line_topic(name, topics.BOLLARD_POSE)
        types[topic] = topics.POSE_STAMPED
        rows += [(ns, topic, pose_stamped(ns, frame_id, point - lever))
                 for ns, point, lever in zip(stamps.tolist(), points, levers)]
    return rows, types


def run_motion(setup: ArrangementParams, streams: Streams, out_path=None,
               rate: float = DEFAULT_RATE, bag_path=None, progress=None,
               materials: Any = None, sinks: Sequence[Sink] = (),
               commands: Sequence[ScheduledCommand] = (),
               events: Sequence[EventSink] = ()) -> RunSummary:
    """
    Run a motion: OUT.csv rows and/or a bag (sinks.py).

    :param sinks: more sinks every output goes to (a study's SummarySink).
    :param commands, events: as simulate's; a bag records the events too.
    :raises ParameterError: a bad rate or line (before any file exists).
    :raises MotionError: a bag cannot hold negative times.
    :raises BagError: the bag directory exists and is not empty, or recording failed.
    :raises OSError: OUT.csv cannot be written.
    """
    driver = driver_for(setup, rate, materials)  # refuses a bad rate or line first
    outputs: List[Sink] = list(sinks)
    listeners: List[EventSink] = list(events)
    bag = writer = None
    if bag_path is not None:
        if int(streams.t_ns[0]) < 0:
            raise MotionError(
                f'{streams.path}: data row 1, column {"t"!r}: {streams.origin!r} is negative; '
                'a bag stamps messages with the simulated time, which must be >= 0')
        inputs, types = input_messages(setup, streams)
        bag = run_bag(bag_path, setup, '', inputs, types, bool(commands))
        outputs.insert(0, bag)
        if bag_events(setup, bool(commands)):
            listeners.insert(0, BagEvents(bag, layout_of(setup)))
    try:
        if out_path is not None:
            writer = CsvSink(out_path, driver.names, driver.ratings,
                             payload=setup.single and setup.lines[0].params.has_payload,
                             origin=streams.origin,
                             fenders=[(fender.name, fender.normal)
                                      for fender in setup.fenders],
                             loads=reports_ship_loads(setup), waves=reports_waves(setup))
            outputs.insert(0, writer)
        summary = simulate(setup, streams, rate, outputs, progress, materials, commands,
                           listeners)
    except BaseException:
        # Ctrl-C or an error: keep what was computed, a complete bag up to here included.
        _close_quietly(writer, bag)
        raise
    if writer is not None:
        writer.close()
    if bag is not None:
        summary.dropped = bag.close()
    return summary


def layout_of(setup: ArrangementParams) -> Layout:
    """Return the topics of the node kind these parameters are for."""
    return topics.LINE_NODE if setup.single else topics.MOORING_NODE


def bag_events(setup: ArrangementParams, commands: bool) -> bool:
    """Tell whether a run's bag has an events topic: it has commands, or a hook may release."""
    return commands or any(line.params.release_load > 0.0 for line in setup.lines)


def run_bag(path, setup: ArrangementParams, namespace: str, inputs, input_topics,
            commands: bool) -> BagSink:
    """
    Return the BagSink of a run, as the node records, marked as a run's (RECORDED_BY).

    With the events topic if the run may have events (bag_events).
    """
    extra = {layout_of(setup).events: topics.STRING} if bag_events(setup, commands) else {}
    return BagSink(path, encoder_for(setup), namespace, inputs, input_topics,
                   {**stored(setup), RECORDED_BY[0]: RECORDED_BY[1]}, extra)


def _close_quietly(writer, bag) -> None:
    try:
        if writer is not None:
            writer.close()
    except OSError:
        pass
    if bag is not None:
        bag.abandon()
