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
The input and output rules of a mooring arrangement: line_driver's rules, for many lines.

The mooring node and the offline commands drive a Mooring (mooring.py) through a
MooringDriver, with the rules LineDriver gives one line (see line_driver.py), so that an
arrangement and its lines run alone give the same outputs at the same times:

- Time: simulated time 0 is the stamp of the first sample taken (a ship pose or a bollard
  pose); stamps are integer nanoseconds, simulated times seconds from it.
- One sample behind: the ropes never pass the second-newest sample of a live stream (the
  ship's, or a line's bollard poses) until the caller takes that stream for silent.
- Outputs fall every 1 / rate from the last (re)start, whose state is output at once; a
  state time within PIN_TOLERANCE steps of its due time is pinned to it.
- Skip ahead past max_lag; a clock max_lag behind the ropes starts them from scratch.
- The ship pose of an output is the newest ship pose at or before the output time: its
  orientation turns the lines' forces into the ship's body frame (mooring.mooring_wrench).

No ROS, no files here.
"""

from collections import deque
from dataclasses import dataclass, field
import math
from typing import Any, Dict, List, NamedTuple, Optional

import numpy as np

from .line_driver import MAX_LAG, PIN_TOLERANCE
from .model.frames import rotation_matrix
from .mooring import Mooring, mooring_wrench, MooringAdvance, MooringOutput, to_world
from .params.arrangement import ArrangementParams
from .params.table import ParameterError

SHIP = 'ship'


class MooringPublished(NamedTuple):
    """
    One output of the arrangement.

    :ivar stamp_ns: its stamp [ns] (epoch + simulated time).
    :ivar output: the lines' state (output.t is the simulated time [s]).
    :ivar ship_position: the ship pose's origin at the output [m] (see the module docstring).
    :ivar ship_orientation: its unit quaternion (x, y, z, w).
    :ivar levers: each fairlead minus the ship's origin, in frame_id axes (L, 3) [m].
    :ivar force: total force of the lines on the ship, body frame (3,) [N].
    :ivar moment: their total moment about the ship's origin, body frame (3,) [N m].
    :ivar advance: the Mooring advance that reached it; None for a fresh output.
    """

    stamp_ns: int
    output: MooringOutput
    ship_position: np.ndarray
    ship_orientation: np.ndarray
    levers: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    advance: Optional[MooringAdvance]

    def world_wrench(self) -> tuple:
        """Return the force and the moment about the ship's origin in frame_id axes."""
        return to_world(self.ship_orientation, self.force, self.moment)


@dataclass
class MooringReport:
    """
    What one call that moves the ropes on did (see line_driver.Report).

    :ivar outputs: the outputs reached, in order.
    :ivar skipped: how far [s] the ropes skipped ahead (0: no skip).
    :ivar skip_to: the simulated time they skipped to.
    :ivar clock_back: how far [s] the clock was behind the ropes (0: it was not).
    :ivar faults: simulated times of states not output because a number was not finite.
    """

    outputs: List[MooringPublished] = field(default_factory=list)
    skipped: float = 0.0
    skip_to: float = math.nan
    clock_back: float = 0.0
    faults: List[float] = field(default_factory=list)


class MooringDriver:
    """A Mooring fed from ship and bollard poses, stepped from output time to output time."""

    def __init__(self, arrangement: ArrangementParams, materials: Any = None,
                 rate: Optional[float] = None, history: float = 5.0) -> None:
        """
        Build every line (see Mooring); the ropes are placed by the first ship pose.

        :param rate: outputs per simulated second; None = publish_rate.
        :raises ParameterError: the rate is not a positive finite number, or a line cannot
            be built (also MaterialError, ValueError).
        """
        rate = arrangement.shared.publish_rate if rate is None else float(rate)
        if not (math.isfinite(rate) and rate > 0.0):
            raise ParameterError(f'output rate {rate!r} Hz is not allowed: must be > 0')
        self.rate = rate
        self._materials = materials
        self._history = history
        self.mooring = Mooring(arrangement, materials, 1.0 / rate, history)
        self._reset_inputs()

    def _reset_inputs(self) -> None:
        self.epoch_ns: Optional[int] = None  # stamp of simulated time 0
        # times [s] of the two newest samples of each stream, whether it holds the ropes
        self._recent = {stream: deque(maxlen=2) for stream in self.streams}
        self._live = {stream: False for stream in self.streams}
        self._fresh = False  # output the state at once: the ropes were (re)started
        self._origin = 0.0  # simulated time [s] from which outputs are due
        self._count = 0  # outputs since then

    # -- state ----------------------------------------------------------------------------

    @property
    def streams(self) -> List[str]:
        """Return the input streams: the ship's, then each line's bollard poses (its name)."""
        return [SHIP] + self.mooring.names

    @property
    def arrangement(self) -> ArrangementParams:
        """Return the parameters in force (pretensioned lines with their lengths once started)."""
        return self.mooring.arrangement

    @property
    def started(self) -> bool:
        """Tell whether the ropes have been placed (by the first ship pose)."""
        return self.mooring.started

    @property
    def time(self) -> float:
        """Return the state time [s] (NaN before the start)."""
        return self.mooring.time

    def seconds(self, stamp_ns: int) -> float:
        """Return the simulated time [s] of a stamp [ns] (the epoch must be set)."""
        return (int(stamp_ns) - self.epoch_ns) / 1e9

    def stamp_ns(self, t: float) -> int:
        """Return the stamp [ns] of a simulated time [s] (nearest nanosecond)."""
        return self.epoch_ns + round(t * 1e9)

    def live(self, stream: str) -> bool:
        """Tell whether a stream holds the ropes back (it has samples and is not silent)."""
        return self._live[stream]

    # -- inputs ---------------------------------------------------------------------------

    def push_ship(self, stamp_ns: int, position, orientation) -> Dict[str, Any]:
        """
        Take a ship pose; the ship's stream becomes live.

        :returns: {'start': {line index: length chosen}} when it placed the ropes,
            {'teleport': [line indices]} when a jump restarted lines, else {}.
        :raises PoseError: non-finite pose or zero quaternion (nothing changed).
        :raises TrajectoryError: not after the newest ship pose (nothing changed).
        :raises ParameterError: a pretension no length gives at this pose (the ropes wait
            for the next one).
        """
        epoch = self.epoch_ns
        if epoch is None:
            self.epoch_ns = int(stamp_ns)
        t = self.seconds(stamp_ns)
        try:
            teleported = self.mooring.push_ship(t, position, orientation)
        except ValueError:
            self.epoch_ns = epoch
            raise
        recent = self._recent[SHIP]
        if teleported and len(teleported) == len(self.mooring.sims):
            recent.clear()  # the ship's samples before the jump are gone
        recent.append(t)
        self._live[SHIP] = True
        if not self.started:
            lengths = self.mooring.start(t)
            self._fresh = True
            return {'start': lengths}
        return {'teleport': teleported} if teleported else {}

    def push_bollard(self, name: str, stamp_ns: int, point) -> str:
        """
        Take a bollard sample of the named line; its stream becomes live.

        :returns: 'teleport' if a jump restarted the line, 'ignored' for a payload line
            (its bollard end hangs free), else ''.
        :raises KeyError: no line of that name.
        :raises TrajectoryError: non-finite, or not after its newest sample.
        """
        k = self.mooring.names.index(name)
        if self.mooring.sims[k].payload:
            return 'ignored'
        if self.epoch_ns is None:
            self.epoch_ns = int(stamp_ns)
        t = self.seconds(stamp_ns)
        event = self.mooring.push_bollard(k, t, point)
        recent = self._recent[name]
        if event == 'teleport':
            recent.clear()
        recent.append(t)
        self._live[name] = True
        return event

    def silence(self, stream: str) -> bool:
        """Take a stream for silent (no longer holding the ropes); return if it was live."""
        was = self._live[stream]
        self._live[stream] = False
        return was

    def target(self, now: float) -> float:
        """Return now, but not past the second-newest sample of a live stream (one behind)."""
        target = now
        for stream in self.streams:
            if self._live[stream] and self._recent[stream]:
                target = min(target, self._recent[stream][0])
        return target

    # -- time -----------------------------------------------------------------------------

    def advance(self, now: float, max_outputs: float = math.inf,
                max_lag: float = MAX_LAG) -> MooringReport:
        """Move the ropes on towards `now`, outputs included (LineDriver.advance's rules)."""
        report = MooringReport()
        mooring = self.mooring
        if not mooring.started:
            return report
        if now < mooring.time - max_lag:
            report.clock_back = mooring.time - now
            self.clear()
            return report
        target = self.target(now)
        if math.isinf(target):
            return report
        if target - mooring.time > max_lag:
            report.skipped, report.skip_to = target - mooring.time, target
            self.skip(target)
        return self.outputs_until(target, max_outputs, report)

    def outputs_until(self, target: float, max_outputs: float = math.inf,
                      report: Optional[MooringReport] = None) -> MooringReport:
        """Output the fresh state, then step to every output due by target (at most max)."""
        report = MooringReport() if report is None else report
        mooring = self.mooring
        if not mooring.started:
            return report
        if self._fresh:
            self._emit(None, report)
        done = 0
        while done < max_outputs:
            dt = mooring.time_step
            due = self._origin + (self._count + 1) / self.rate
            steps = max(1, math.ceil((due - mooring.time) / dt - 1e-9))
            if mooring.time + (steps - PIN_TOLERANCE) * dt > target:
                break  # the input does not reach the next output time yet
            advance = mooring.advance_to(due)
            self._count += 1
            done += 1
            if advance.restarted:
                self._fresh = True
            if abs(mooring.time - due) < PIN_TOLERANCE * dt:
                mooring.skip_to(due)
            self._emit(advance, report)
        return report

    def _emit(self, advance: Optional[MooringAdvance], report: MooringReport) -> None:
        mooring = self.mooring
        out = mooring.output()
        position, orientation = mooring.ship_pose(out.t)
        mooring.forget_ship()
        offsets = mooring.offsets
        force, moment = mooring_wrench(out.fairlead_forces, offsets, orientation)
        # one sum is finite only if every number is (an overflow to inf is refused too)
        total = (float(np.concatenate(out.positions).sum()) + float(out.fairlead_forces.sum())
                 + float(out.bollard_forces.sum()) + float(force.sum()) + float(moment.sum())
                 + float(out.fairlead_peaks.sum()) + float(out.bollard_peaks.sum())
                 + float(out.line_lengths.sum()))
        if not math.isfinite(total):
            mooring.restart()
            self._fresh = True
            report.faults.append(out.t)
            return
        if self._fresh:  # (re)started ropes: the next outputs are due from here
            self._fresh = False
            self._origin, self._count = out.t, 0
        report.outputs.append(MooringPublished(
            self.stamp_ns(out.t), out, position, orientation,
            offsets @ rotation_matrix(orientation).T, force, moment, advance))

    def skip(self, t: float) -> None:
        """Skip the state to t and restart every rope there at rest (a skip ahead)."""
        self.mooring.skip_to(t)
        self.mooring.restart()
        self._fresh = True

    def reset(self) -> None:
        """Restart every rope whole, at its length, at rest on its catenary (~/reset)."""
        self.mooring.restore()
        self._fresh = True

    def command_winch(self, name: str, speed: float) -> None:
        """
        Command the named line's winch speed [m/s] (+ pays out) from its next step.

        :raises ValueError: no line of that name.
        :raises ParameterError: speed is not a finite number.
        """
        self.mooring.command_winch(self.mooring.names.index(name), speed)

    def clear(self) -> None:
        """Start from scratch (a clock jump back): new lines waiting for a ship pose."""
        self.mooring = Mooring(self.mooring.arrangement, self._materials, 1.0 / self.rate,
                               self._history)
        self._reset_inputs()

    # -- parameters -----------------------------------------------------------------------

    def check_update(self, name: Optional[str], values: dict) -> None:
        """Refuse run-time changes of one line's parameters (None: every line's)."""
        for k in self._indices(name):
            self.mooring.check_update(k, values)

    def update(self, name: Optional[str], values: dict) -> None:
        """
        Apply run-time changes of one line's parameters (None: a shared one, every line).

        publish_rate changes the output rate (see set_rate).
        """
        for k in self._indices(name):
            self.mooring.update(k, values)
        if 'publish_rate' in values:
            self.set_rate(self.mooring.sims[0].params.publish_rate)

    def _indices(self, name: Optional[str]) -> range:
        if name is None:
            return range(len(self.mooring.sims))
        k = self.mooring.names.index(name)
        return range(k, k + 1)

    def set_rate(self, rate: float) -> None:
        """Make a new output rate take effect with the next output (LineDriver.set_rate)."""
        self.rate = float(rate)
        mooring = self.mooring
        mooring.set_output_interval(1.0 / self.rate)
        if mooring.started and not self._fresh:
            self._origin, self._count = mooring.time, 0
