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
The input and output rules of a mooring: the one home of them.

Both nodes, ``rope_sim run`` and ``rope_sim resim`` drive a Mooring through a Driver, so
that the same samples give the same outputs at the same times:

- Streams: the ship's poses (SHIP: every fairlead is the pose ⊕ its offset; the single-line
  node's fairlead/pose is this stream) and each line's bollard poses (named by the line).
- Time: simulated time 0 is the stamp of the first sample taken (of any stream); stamps
  are integer nanoseconds, simulated times seconds from it.
- One sample behind: the ropes never pass the second-newest sample of a live stream. How an
  end moves up to a sample depends on the sample after it (the side of the secant at the
  sample instant, a spline's tangent there), so one sample behind the ends move exactly as
  if the whole motion were known. A stream the caller declares silent (silence()) no longer
  holds the ropes back: its ends coast to a stop; its next sample makes it live.
- Outputs fall every 1 / rate from the last (re)start of the ropes, whose state is output at
  once (a fresh output). A state time within PIN_TOLERANCE steps of its due time is pinned
  to it (Mooring.skip_to), so rounding of the running sum of steps never adds up to a missed
  step. A rate change re-anchors the grid at the state time: the next output is due
  1 / rate after the last one.
- Skip ahead: ropes more than max_lag behind their target restart there at rest instead of
  catching up. A clock more than max_lag behind the ropes starts them from scratch.
- Levers: an output's fairlead levers are the fairlead offsets rotated by the newest ship
  pose at or before the output time, and a bollard's lever is that of its newest sample at
  or before it (the first sample's before it). Output times on sample times, the usual
  case, get the lever of that very sample; between samples, a lever carried over from the
  sample before is what both the node and the re-simulation of its bag can know.
- A state with a number that is not finite is never output: the ropes restart at rest.

The clock-driven decisions are the caller's (a silent stream, a skip ahead, a reset, a
clock jump back, a sample dropped for its stamp): the nodes record them as events
(events.py) and ``rope_sim resim`` replays them through the same methods. The Driver is the
one door to the Mooring from outside mooring/: what the nodes and the offline commands need
to know of the lines (their names, ratings, reach, partings) it answers too.
No ROS, no files here.
"""

from collections import deque
import math
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from .line import Parting
from .mooring import Mooring
from .records import Handled, MooringAdvance, Published, Report
from .statics import stiffness_now
from .status import bollard_loads, Rating, ratings
from ..params.arrangement import ArrangementParams
from ..params.table import ParameterError

SHIP = 'ship'  # the ship's pose stream; a bollard's stream is named by its line
# Falling further behind than this [s] restarts the ropes at the target instead of catching
# up; a clock this far behind the ropes starts them from scratch.
MAX_LAG = 1.0
# An output's state time this close to its due time [steps] is pinned to it.
PIN_TOLERANCE = 1e-6


class Driver:
    """A Mooring fed from pose streams, stepped from output time to output time."""

    def __init__(self, arrangement: ArrangementParams, materials: Any = None,
                 rate: Optional[float] = None, history: float = 5.0) -> None:
        """
        Build every line (see Mooring); the ropes are placed by the first ship pose.

        :param rate: outputs per simulated second; None = publish_rate.
        :param history: seconds of samples kept behind the newest (math.inf offline).
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
        # the winch commands offline: {line index: (times [s of simulated time], speeds
        # [m/s])}, each from its time on, applied before every output's steps (the nodes
        # command through command_winch instead)
        self.winch_schedules: Dict[int, Tuple[np.ndarray, np.ndarray]] = {}
        # the line-handling commands offline, in time order, each taken before the first
        # output's steps that start at or after its time (the nodes call command instead)
        self.command_schedule: deque = deque()
        self._reset_inputs()

    def _reset_inputs(self) -> None:
        self.epoch_ns: Optional[int] = None  # stamp of simulated time 0
        # times [s] of the two newest samples of each stream, whether it holds the ropes
        self._recent = {stream: deque(maxlen=2) for stream in self.streams}
        self._live = {stream: False for stream in self.streams}
        # each line's bollard levers: (time [s], lever) per sample
        self._bollard_levers: List[deque] = [deque() for _ in self.mooring.lines]
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
    def names(self) -> List[str]:
        """Return the line names, in order ('' for the single line of a line node)."""
        return self.mooring.names

    @property
    def free(self) -> bool:
        """Tell whether the ship is free, its pose an output (ship_mode free)."""
        return self.mooring.free

    @property
    def time_step(self) -> float:
        """Return the smallest of the lines' steps [s]."""
        return self.mooring.time_step

    @property
    def ratings(self) -> List[Rating]:
        """Return each line's MBL and WLL (its material at its diameter)."""
        return ratings(self.arrangement, self._materials)

    @property
    def reaches(self) -> List[float]:
        """Return how far each line's ends can be apart now [m] (inf once parted)."""
        return [line.reach for line in self.mooring.lines]

    @property
    def partings(self) -> List[Optional[Parting]]:
        """Return how each line parted (None: whole)."""
        return [line.parting for line in self.mooring.lines]

    @property
    def last_jumps(self) -> np.ndarray:
        """Return how far each line's newest end sample jumped [m] (L,)."""
        return self.mooring.last_jumps.copy()

    def fairlead(self, k: int) -> np.ndarray:
        """Return where line k's fairlead is now, at the state time [m] (3,)."""
        return self.mooring.free_ends(k, [self.mooring.time])[0][0, 1]

    def stiffness(self, position, orientation) -> np.ndarray:
        """
        Return the 6x6 stiffness of the lines and fenders with the ship at this pose.

        About the ship's origin in frame_id axes (mooring/statics.py stiffness_now), the
        lines as they are now.

        :raises ParameterError: a payload line; StaticsError: a catenary not found there.
        """
        return stiffness_now(self.mooring, position, orientation)

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

    def last_sample(self, stream: str) -> float:
        """Return the time [s] of a stream's newest sample (-inf: none yet)."""
        recent = self._recent[stream]
        return recent[-1] if recent else -math.inf

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
        if teleported and len(teleported) == len(self.mooring.lines):
            recent.clear()  # the ship's samples before the jump are gone
        recent.append(t)
        self._live[SHIP] = True
        if not self.started:
            lengths = self.mooring.start(t)
            self._fresh = True
            return {'start': lengths}
        return {'teleport': teleported} if teleported else {}

    def push_bollard(self, name: str, stamp_ns: int, point, lever=None) -> str:
        """
        Take a bollard sample of the named line; its stream becomes live.

        :param lever: the bollard point minus its pose's origin [m] (its torque arm); None:
            zero.
        :returns: 'teleport' if a jump restarted the line, 'ignored' for a payload line
            (its bollard end hangs free: nothing changed), else ''.
        :raises ValueError: no line of that name.
        :raises TrajectoryError: non-finite, or not after its newest sample.
        """
        k = self.mooring.names.index(name)
        if self.mooring.lines[k].payload:
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
        self._bollard_levers[k].append(
            (t, np.zeros(3) if lever is None else np.array(lever, dtype=float)))
        return event

    def start_free(self, stamp_ns: int) -> Dict[int, float]:
        """
        Start a free ship's mooring at this stamp (simulated time 0 if none is set yet).

        A free ship needs no pose to start: it floats at rest at its start pose.

        :returns: {line index: length chosen} of the pretensioned lines.
        :raises ParameterError: a pretension no length gives at the start pose.
        """
        if self.epoch_ns is None:
            self.epoch_ns = int(stamp_ns)
        lengths = self.mooring.start(self.seconds(stamp_ns))
        self._fresh = True
        return lengths

    def set_external_load(self, force, moment, body_axes: bool) -> None:
        """
        Hold an external load on a free ship until the next one (ship/external_wrench).

        :param force, moment: [N], [N m] about the ship's origin, in the ship's body axes
            (they turn with it) or in frame_id axes.
        :raises ValueError: a number that is not finite, or a load past what any tug or
            thruster gives this ship.
        """
        self.mooring.set_external_load(force, moment, body_axes)

    def set_load_schedule(self, times, loads) -> None:
        """
        Take the external loads on a free ship over time (offline: LOADS.csv).

        :param times: [s of simulated time] (n,); loads: force [N], moment about the ship's
            origin [N m], world axes (n, 6), linear between the times.
        :raises ValueError: a load past what any tug or thruster gives, naming its row.
        """
        self.mooring.set_load_schedule(times, loads)

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
                max_lag: float = MAX_LAG) -> Report:
        """
        Move the ropes on towards `now`, outputs included: the live node's one call.

        A clock more than max_lag behind the ropes clears the mooring (report.clock_back);
        a target more than max_lag ahead of it skips there (report.skipped). Then the fresh
        output, if the ropes were (re)started, and at most max_outputs outputs on the grid.

        :param now: the clock [s of simulated time]; math.inf = no clock.
        """
        report = Report()
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

    def next_due(self) -> float:
        """Return the simulated time [s] the next output is due at."""
        return self._origin + (self._count + 1) / self.rate

    def outputs_until(self, target: float, max_outputs: float = math.inf,
                      report: Optional[Report] = None) -> Report:
        """Output the fresh state, then step to every output due by target (at most max)."""
        report = Report() if report is None else report
        mooring = self.mooring
        if not mooring.started:
            return report
        if self._fresh:
            self._emit(None, report)
        done = 0
        while done < max_outputs:
            dt = mooring.time_step
            due = self.next_due()
            steps = max(1, math.ceil((due - mooring.time) / dt - 1e-9))
            if mooring.time + (steps - PIN_TOLERANCE) * dt > target:
                break  # the input does not reach the next output time yet
            self._command_scheduled_winches()
            self._take_scheduled_commands(report)
            advance = mooring.advance_to(due)
            self._count += 1
            done += 1
            if advance.restarted:
                self._fresh = True
            if abs(mooring.time - due) < PIN_TOLERANCE * dt:
                mooring.skip_to(due)
            self._emit(advance, report)
        return report

    def _command_scheduled_winches(self) -> None:
        """Command each scheduled winch the speed its schedule gives for the coming steps."""
        mooring = self.mooring
        middle = mooring.time + 0.5 * mooring.time_step
        for k, (times, speeds) in self.winch_schedules.items():
            row = max(int(np.searchsorted(times, middle, 'right')) - 1, 0)
            mooring.command_winch(k, float(speeds[row]))

    def _take_scheduled_commands(self, report: Report) -> None:
        """Take every scheduled command due before the coming steps' middle (report.handled)."""
        schedule = self.command_schedule
        middle = self.mooring.time + 0.5 * self.mooring.time_step
        while schedule and schedule[0].t < middle:
            scheduled = schedule.popleft()
            bollard = ''
            try:
                if scheduled.bollard:
                    self.update(scheduled.line, {'bollard': scheduled.bollard})
                    bollard = scheduled.bollard
                text = self.command(scheduled.line or None, scheduled.command)
                refused = False
            except ValueError as e:  # CommandError, ParameterError: said, and the run goes on
                text, refused = str(e), True
            report.handled.append(Handled(self.mooring.time, scheduled, text, refused, bollard))

    def _emit(self, advance: Optional[MooringAdvance], report: Report) -> None:
        mooring = self.mooring
        out = mooring.output()
        position, orientation = mooring.ship_pose(out.t)
        mooring.forget_ship()
        bollard_levers = self._bollard_levers_at(out.t)
        # the levers and the wrench are made of the forces, the offsets and the pose: finite
        # with them
        if not out.finite:
            mooring.restart()
            self._fresh = True
            report.faults.append(out.t)
            return
        if self._fresh:  # (re)started ropes: the next outputs are due from here
            self._fresh = False
            self._origin, self._count = out.t, 0
        # the lines fast on each bollard now: a line's bollard changes only while it is not
        bollards = (bollard_loads(mooring.arrangement, out.states, out.bollard_forces)
                    if mooring.arrangement.bollards else ())
        report.outputs.append(Published(self.stamp_ns(out.t), out, position, orientation,
                                        mooring.offsets, bollard_levers, advance,
                                        tuple(bollards)))

    def _bollard_levers_at(self, t: float) -> np.ndarray:
        """Return each bollard's lever at time t (its newest sample's at or before it)."""
        levers = np.zeros((len(self.mooring.lines), 3))
        now = self.mooring.time
        for k, samples in enumerate(self._bollard_levers):
            if not samples:
                continue
            chosen = samples[0][1]
            for time, lever in samples:
                if time > t:
                    break
                chosen = lever
            levers[k] = chosen
            while len(samples) > 1 and samples[1][0] <= now:  # none older is ever asked
                samples.popleft()
        return levers

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

    def command(self, name: Optional[str], command: str) -> str:
        """
        Take a line-handling command now, at the state time (mooring/handling.py).

        :param name: the line ('' for a line node's); None for let_go_all.
        :returns: one line saying what was done.
        :raises ValueError: no line of that name.
        :raises CommandError: an unknown command, or one that does not fit the line's state
            (the message names the state or the numbers); nothing changed then.
        """
        k = 0 if name is None else self.mooring.names.index(name)
        return self.mooring.command(k, command)

    def clear(self) -> None:
        """Start from scratch (a clock jump back): new lines waiting for a ship pose."""
        self.mooring = Mooring(self.mooring.arrangement, self._materials, 1.0 / self.rate,
                               self._history)
        self._reset_inputs()

    # -- parameters -----------------------------------------------------------------------

    def check_update(self, name: Optional[str], values: dict) -> None:
        """Refuse run-time changes of one line's parameters (None: every line's)."""
        self.mooring.check_update(self._index(name), values)

    def update(self, name: Optional[str], values: dict) -> None:
        """
        Apply run-time changes of one line's parameters (None: a shared one, every line).

        publish_rate changes the output rate (see set_rate); current, the wind's and the
        waves' settings (None only) the mooring's one environment (Mooring.update).
        """
        self.mooring.update(self._index(name), values)
        if 'publish_rate' in values:
            self.set_rate(self.mooring.lines[0].params.publish_rate)

    def _index(self, name: Optional[str]) -> Optional[int]:
        return None if name is None else self.mooring.names.index(name)

    def set_rate(self, rate: float) -> None:
        """
        Make a new output rate take effect with the next output: no gap, no burst.

        The next output is due 1 / rate after the last one (the state time), and the steps
        are chosen again to divide the new period. Counting on from the old origin at the
        new period put the next one up to seconds away (a skip ahead) or in the past (a
        burst).
        """
        self.rate = float(rate)
        mooring = self.mooring
        mooring.set_output_interval(1.0 / self.rate)
        if mooring.started and not self._fresh:
            self._origin, self._count = mooring.time, 0
