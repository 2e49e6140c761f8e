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
The input and output rules of one mooring line: the one home of them.

The mooring_line node, ``rope_sim run`` and ``rope_sim resim`` all drive a Simulator
through a LineDriver, so that the same samples give the same outputs at the same times:

- Time: simulated time 0 is the stamp of the first sample taken (of either end); sample
  stamps and output stamps are integer nanoseconds, simulated times are seconds from it.
- One sample behind: the rope never passes the second-newest sample of a live end. How an
  end moves up to a sample depends on the sample after it (the side of the secant at the
  sample instant, a spline's tangent there), so one sample behind the ends move exactly as
  if the whole motion were known. A stream the caller declares silent (silence()) no
  longer holds the rope back: its end coasts to a stop; its next sample makes it live.
- Outputs fall every 1 / rate from the last (re)start of the rope, whose state is output at
  once (a fresh output). The state time of an output within 1e-6 of a step of its due
  time is pinned to it (Simulator.skip_to), so rounding of the running sum of steps never
  adds up to a missed step. A rate change re-anchors the grid at the state time: the next
  output is due 1 / rate after the last one.
- Skip ahead: a rope more than MAX_LAG behind its target restarts there on the catenary
  instead of catching up. A clock more than MAX_LAG behind the rope starts it from scratch.
- Torque arms: an output's lever of an end is the lever of that end's newest sample at or
  before the output time (the first sample's before it). Output times on sample times,
  the usual case, get the lever of that very sample; between samples, a lever carried
  over from the sample before is what both the node and the re-simulation of its bag can
  know, and interpolating it would need the orientations (a linear blend of a rotated
  vector shortens it).

The clock-driven decisions are the caller's (a silent stream, a skip ahead, a reset, a
clock jump back, a sample dropped for its stamp): the node records them as events
(EVENTS_TOPIC, encode_event) and ``rope_sim resim`` replays them through the same methods.
No ROS, no files here.
"""

from collections import deque
from dataclasses import dataclass, field
import json
import math
from typing import Any, Dict, List, NamedTuple, Optional

import numpy as np
import yaml

from .params.table import LineParams, NODE_NAME, ParameterError
from .simulator import Advance, Output, Simulator

FAIRLEAD = 'fairlead'
BOLLARD = 'bollard'
ENDS = (FAIRLEAD, BOLLARD)
# Falling further behind than this [s] restarts the rope at the target instead of catching
# up; a clock this far behind the rope starts it from scratch.
MAX_LAG = 1.0
# An output's state time this close to its due time [steps] is pinned to it.
PIN_TOLERANCE = 1e-6
# Relative topic of the node's clock-driven decisions (std_msgs/String, one JSON object each).
EVENTS_TOPIC = 'rope/events'
PARTED_TOPIC = 'rope/parted'  # std_msgs/Bool, latched: whether the line has parted
EVENT_KINDS = ('silent', 'skip', 'reset', 'clock_back', 'drop', 'restamp', 'set', 'winch',
               'parted')
# custom_data key of metadata.yaml under which the node, run and resim store their parameters.
PARAMETERS_KEY = 'rope_sim_ros.parameters'


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


def encode_event(kind: str, **fields: Any) -> str:
    """Return one event as the JSON text of an EVENTS_TOPIC message."""
    return json.dumps({'event': kind, **fields}, sort_keys=True)


def decode_event(text: str) -> Dict[str, Any]:
    """
    Return an event of EVENTS_TOPIC as a dict with at least 'event'.

    :raises ValueError: not a JSON object naming one of EVENT_KINDS.
    """
    event = json.loads(text)
    if not isinstance(event, dict) or event.get('event') not in EVENT_KINDS:
        raise ValueError(f'not an event: {text!r}')
    return event


class Published(NamedTuple):
    """
    One output of the line.

    :ivar stamp_ns: its stamp [ns] (epoch + simulated time).
    :ivar output: the Simulator's output (output.t is the simulated time [s]).
    :ivar fairlead_lever: fairlead point minus its pose origin [m] (torque arm), shape (3,).
    :ivar bollard_lever: the same for the bollard.
    :ivar advance: the Simulator advance that reached it; None for a fresh output.
    """

    stamp_ns: int
    output: Output
    fairlead_lever: np.ndarray
    bollard_lever: np.ndarray
    advance: Optional[Advance]


@dataclass
class Report:
    """
    What one call that moves the rope on did.

    :ivar outputs: the outputs reached, in order.
    :ivar skipped: how far [s] the rope skipped ahead (0: no skip).
    :ivar skip_to: the simulated time it skipped to.
    :ivar clock_back: how far [s] the clock was behind the rope (0: it was not; else the
        line was cleared and waits for the next fairlead sample).
    :ivar faults: simulated times of states not output because they were not finite (the
        rope was restarted on the catenary).
    """

    outputs: List[Published] = field(default_factory=list)
    skipped: float = 0.0
    skip_to: float = math.nan
    clock_back: float = 0.0
    faults: List[float] = field(default_factory=list)


class LineDriver:
    """A Simulator fed from end samples, stepped from output time to output time."""

    def __init__(self, params: LineParams, materials: Any = None,
                 rate: Optional[float] = None, history: float = 5.0) -> None:
        """
        Build the line (see Simulator); the rope is placed by the first fairlead sample.

        :param params: validated parameters.
        :param materials: material library (default: config/materials.yaml).
        :param rate: outputs per simulated second; None = params.publish_rate.
        :param history: seconds of end samples the simulator keeps behind the newest.
        :raises ParameterError: the rate is not a positive finite number, or the line cannot
            be built (also MaterialError, ValueError).
        """
        rate = params.publish_rate if rate is None else float(rate)
        if not (math.isfinite(rate) and rate > 0.0):
            raise ParameterError(f'output rate {rate!r} Hz is not allowed: must be > 0')
        self.rate = rate
        self._materials = materials
        self._history = history
        self.simulator = self._new_simulator(params)
        self._reset_inputs()
        # (times [s of simulated time], speeds [m/s]): the winch's commands offline, each
        # from its time on; applied before every output's steps (None: commands come from
        # command_winch, the node's winch/command)
        self.winch_schedule = None

    def _new_simulator(self, params: LineParams) -> Simulator:
        # The step divides the output period, so that outputs fall on step times.
        return Simulator(params, self._materials, output_interval=1.0 / self.rate,
                         history=self._history)

    def _reset_inputs(self) -> None:
        self.epoch_ns: Optional[int] = None  # stamp of simulated time 0
        # times [s] of the two newest samples of each end, whether its stream is live
        self._recent = {end: deque(maxlen=2) for end in ENDS}
        self._live = {end: False for end in ENDS}
        self._levers = {end: deque() for end in ENDS}  # (time [s], lever) per sample
        self._fresh = False  # output the state at once: the rope was (re)started
        self._origin = 0.0  # simulated time [s] from which outputs are due
        self._count = 0  # outputs since then

    # -- state --------------------------------------------------------------------------

    @property
    def params(self) -> LineParams:
        """Return the parameters in force."""
        return self.simulator.params

    @property
    def payload(self) -> bool:
        """Tell whether the bollard end hangs free, a payload of payload_mass > 0 kg."""
        return self.params.has_payload

    @property
    def started(self) -> bool:
        """Tell whether the rope has been placed (by the first fairlead sample)."""
        return self.simulator.started

    @property
    def time(self) -> float:
        """Return the state time [s] (NaN before the start)."""
        return self.simulator.time

    def seconds(self, stamp_ns: int) -> float:
        """Return the simulated time [s] of a stamp [ns] (the epoch must be set)."""
        return (int(stamp_ns) - self.epoch_ns) / 1e9

    def stamp_ns(self, t: float) -> int:
        """Return the stamp [ns] of a simulated time [s] (nearest nanosecond)."""
        return self.epoch_ns + round(t * 1e9)

    def live(self, end: str) -> bool:
        """Tell whether an end's stream holds the rope back (it has samples, not silent)."""
        return self._live[end]

    def lever(self, end: str, t: float) -> np.ndarray:
        """Return the lever of the end's newest sample at or before t (zeros: none)."""
        levers = self._levers[end]
        if not levers:
            return np.zeros(3)
        chosen = levers[0][1]
        for time, lever in levers:
            if time > t:
                break
            chosen = lever
        return chosen

    # -- inputs -------------------------------------------------------------------------

    def push(self, end: str, stamp_ns: int, point, lever=None) -> str:
        """
        Take one sample of an end; its stream becomes live.

        :param end: FAIRLEAD or BOLLARD.
        :param stamp_ns: the sample's stamp [ns]; the first sample taken sets the epoch.
        :param point: the end point [m], shape (3,).
        :param lever: end point minus its pose origin [m] (torque arm); None = zero.
        :returns: 'start' (the first fairlead sample placed the rope), 'teleport' (a jump
            past teleport_distance restarted the rope at the state time, see
            Simulator.push_fairlead), 'ignored' (a bollard sample of a line whose bollard
            end is a free payload: nothing changed) or ''.
        :raises TrajectoryError: non-finite, or not after the end's newest sample (nothing
            changed).
        """
        if end == BOLLARD and self.payload:
            return 'ignored'
        if self.epoch_ns is None:
            self.epoch_ns = int(stamp_ns)
        t = self.seconds(stamp_ns)
        sim = self.simulator
        push = sim.push_fairlead if end == FAIRLEAD else sim.push_bollard
        event = push(t, point)
        recent = self._recent[end]
        if event == 'teleport':
            recent.clear()  # its samples before the jump are gone
        recent.append(t)
        self._live[end] = True
        levers = self._levers[end]
        levers.append((t, np.zeros(3) if lever is None else np.array(lever, dtype=float)))
        self._forget_levers(end)
        if end == FAIRLEAD and not sim.started:
            sim.start(t)
            self._fresh = True
            return 'start'
        return event

    def _forget_levers(self, end: str) -> None:
        """Drop levers no output can use: outputs come at or after the state time."""
        levers, now = self._levers[end], self.simulator.time
        while len(levers) > 1 and levers[1][0] <= now:
            levers.popleft()

    def silence(self, end: str) -> bool:
        """Take an end's stream for silent (no longer holding the rope); return if it was live."""
        was = self._live[end]
        self._live[end] = False
        return was

    def target(self, now: float) -> float:
        """Return now, but not past the second-newest sample of a live end (one behind)."""
        target = now
        for end in ENDS:
            if self._live[end] and self._recent[end]:
                target = min(target, self._recent[end][0])
        return target

    # -- time ---------------------------------------------------------------------------

    def advance(self, now: float, max_outputs: float = math.inf,
                max_lag: float = MAX_LAG) -> Report:
        """
        Move the rope on towards `now`, outputs included: the live node's one call.

        A clock more than max_lag behind the rope clears the line (report.clock_back); a
        target more than max_lag ahead of it skips there (report.skipped). Then the fresh
        output, if the rope was (re)started, and at most max_outputs outputs on the grid.

        :param now: the clock [s of simulated time]; math.inf = no clock.
        """
        report = Report()
        sim = self.simulator
        if not sim.started:
            return report
        if now < sim.time - max_lag:
            report.clock_back = sim.time - now
            self.clear()
            return report
        target = self.target(now)
        if math.isinf(target):
            return report
        if target - sim.time > max_lag:
            report.skipped, report.skip_to = target - sim.time, target
            self.skip(target)
        return self.outputs_until(target, max_outputs, report)

    def outputs_until(self, target: float, max_outputs: float = math.inf,
                      report: Optional[Report] = None) -> Report:
        """Output the fresh state, then step to every output due by target (at most max)."""
        report = Report() if report is None else report
        sim = self.simulator
        if not sim.started:
            return report
        if self._fresh:
            self._emit(None, report)
        dt = sim.time_step
        done = 0
        while done < max_outputs:
            due = self._origin + (self._count + 1) / self.rate
            steps = max(1, math.ceil((due - sim.time) / dt - 1e-9))
            if sim.time + (steps - PIN_TOLERANCE) * dt > target:
                break  # the input does not reach the next output time yet
            if self.winch_schedule is not None:
                times, speeds = self.winch_schedule
                row = max(int(np.searchsorted(times, sim.time + 0.5 * dt, 'right')) - 1, 0)
                sim.command_winch(float(speeds[row]))
            advance = sim.advance_to(sim.time + (steps + 0.5) * dt, max_steps=steps)
            self._count += 1
            done += 1
            if advance.restarted:
                self._fresh = True
            if abs(sim.time - due) < PIN_TOLERANCE * dt:
                sim.skip_to(due)
            self._emit(advance, report)
        return report

    def _emit(self, advance: Optional[Advance], report: Report) -> None:
        sim = self.simulator
        out = sim.output()
        levers = [self.lever(end, out.t) for end in ENDS]
        for end in ENDS:
            self._forget_levers(end)
        numbers = (out.positions, out.fairlead_force, out.bollard_force, *levers, [out.t])
        if not all(np.isfinite(np.asarray(a, dtype=float)).all() for a in numbers):
            sim.restart()
            self._fresh = True
            report.faults.append(out.t)
            return
        if self._fresh:  # a (re)started rope: the next outputs are due from here
            self._fresh = False
            self._origin, self._count = out.t, 0
        report.outputs.append(
            Published(self.stamp_ns(out.t), out, levers[0], levers[1], advance))

    def skip(self, t: float) -> None:
        """Skip the state to t and restart the rope there at rest (a skip ahead)."""
        self.simulator.skip_to(t)
        self.simulator.restart()
        self._fresh = True

    def reset(self) -> None:
        """Restart the rope whole, at its length, at rest on the catenary (~/reset)."""
        self.simulator.restore()
        self._fresh = True

    def command_winch(self, speed: float) -> None:
        """Command the winch's speed [m/s] (+ pays out) from the next step (winch/command)."""
        self.simulator.command_winch(speed)

    def clear(self) -> None:
        """Start from scratch (a clock jump back): a new line waiting for a fairlead sample."""
        self.simulator = self._new_simulator(self.simulator.params)
        self._reset_inputs()

    # -- parameters ---------------------------------------------------------------------

    def check_update(self, values: dict) -> None:
        """Refuse run-time parameter changes update() could not apply (see Simulator)."""
        self.simulator.check_update(values)

    def update(self, values: dict) -> None:
        """
        Apply run-time parameter changes; publish_rate changes the output rate.

        :raises ParameterError: as Simulator.update (nothing changed then).
        """
        self.simulator.update(values)
        if 'publish_rate' in values:
            self.set_rate(self.simulator.params.publish_rate)

    def set_rate(self, rate: float) -> None:
        """
        Make a new output rate take effect with the next output: no gap, no burst.

        The next output is due 1 / rate after the last one (the state time), and the step
        is chosen again to divide the new period. Counting on from the old origin at the
        new period put the next one up to seconds away (a skip ahead) or in the past (a
        burst).
        """
        self.rate = float(rate)
        sim = self.simulator
        sim.set_output_interval(1.0 / self.rate)
        if sim.started and not self._fresh:
            self._origin, self._count = sim.time, 0
