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
A live node's clock rules: when a stream is silent, which stamps are taken, what goes out when.

The node reads its clock and hands each reading to a Pacer with what happened (a pose
arrived, the timer ticked); the Pacer moves the Driver on and says what to publish now and
which decisions to record. The rules need the node clock's readings and nothing of ROS, so
they are tested here in milliseconds; the node only wires topics to them.

- **Stamps.** A pose stamped zero takes its receive time (a `restamp` event); one stamped
  further than STAMP_AHEAD_LIMIT ahead of the clock or STAMP_BEHIND_LIMIT behind it is
  dropped (a `drop` event). Under use_sim_time the clock reads 0 until the first /clock:
  nothing to compare then.
- **Silence.** A stream is silent once no pose of it has arrived for LIVE_INPUT seconds of a
  node that was itself on time all that while (a tick more than LATE_TICK late starts the
  wait again, so that the poses queued while the node stalled are read first). Its ends then
  coast to a stop and the ropes go on with the clock (a `silent` event); its next pose makes
  it live again.
- **Outputs per call.** One call moves the ropes at most OUTPUTS_PER_CALL ticks' worth of
  outputs on, so that a node catching up stays responsive; further behind than MAX_LAG the
  ropes skip ahead (a `skip` event); a clock more than MAX_LAG behind them clears them (a
  `clock_back` event).
- **Even outputs.** Outputs that one pose lets through together (poses slower than the
  outputs) are held and published each LAG after its stamp on the node clock (see release),
  so that they go out evenly spaced; without a clock, at once.
"""

from collections import deque
from dataclasses import dataclass, field
import math
from typing import Any, Deque, Dict, List, Optional, Tuple

from .driver import Driver, MAX_LAG, SHIP
from .records import Published
from ..params.table import ParameterError


@dataclass
class Pace:
    """
    What one reading of the node clock decided, in the order the node acts on it.

    :ivar events: decisions to publish and record as (kind, fields), before the outputs.
    :ivar silenced: the streams taken for silent now.
    :ivar started: a free ship's lines started at this tick: {line index: the length chosen
        for its pretension}; None: they did not start now.
    :ivar start_error: why a free ship's lines could not start at this tick ('' if they did).
    :ivar skipped: how far [s] the ropes skipped ahead (0: no skip).
    :ivar clock_back: how far [s] the clock jumped back behind the ropes (0: it did not).
    :ivar faults: simulated times of states not output (a number not finite).
    :ivar reached: the outputs the ropes reached in this call, in order.
    :ivar publish: the outputs to publish now, in order (some reached earlier).
    :ivar no_clock: the poses set the pace because the clock has not started (use_sim_time
        with no /clock yet).
    """

    events: List[Tuple[str, Dict[str, Any]]] = field(default_factory=list)
    silenced: List[str] = field(default_factory=list)
    started: Optional[Dict[int, float]] = None
    start_error: str = ''
    skipped: float = 0.0
    clock_back: float = 0.0
    faults: List[float] = field(default_factory=list)
    reached: List[Published] = field(default_factory=list)
    publish: List[Published] = field(default_factory=list)
    no_clock: bool = False


@dataclass
class Admission:
    """
    Whether a pose's stamp is taken, and the stamp it is taken with.

    :ivar stamp_ns: the sample's stamp [ns]; None: the pose is dropped.
    :ivar events: the decisions to record before the pose (restamp, drop).
    :ivar problem: why it is dropped, or what was done to it ('' if nothing).
    """

    stamp_ns: Optional[int]
    events: List[Tuple[str, Dict[str, Any]]] = field(default_factory=list)
    problem: str = ''


class Pacer:
    """The clock rules of a live node over its Driver (see the module docstring)."""

    # A pose stream is live until the node has run this long [s] without a new sample of it:
    # the ropes wait for its next sample instead of guessing. Delivery to a node with many
    # endpoints stalls while DDS discovers a new participant (`ros2 param`, `ros2 topic`
    # beside it): the mooring node took no pose for 0.30-0.33 s, 1-4 times a minute, while
    # the stamps stepped on and another process got every pose. A stream whose poses all
    # come, late, is not silent: this waits out half again the longest such stall, and half
    # of MAX_LAG, so that the ropes catch up after a real silence without a skip ahead.
    LIVE_INPUT = 0.5
    # A tick more than this [s] after its due time starts the wait again: the node itself
    # was stalled (its timer late, its ticks run back to back after it) and first reads the
    # poses queued meanwhile. Counting ticks took a burst of late ticks for a silence.
    LATE_TICK = 0.0625
    # Outputs held back to go out evenly (see release) are published this early [ticks].
    EARLY = 0.5
    # The lag of the outputs behind the clock is the largest of the last LAG_WINDOW [s].
    LAG_WINDOW = 2.0
    # Falling further behind than this [s] restarts the ropes at now instead of catching up.
    MAX_LAG = MAX_LAG
    # One tick or pose callback simulates and publishes at most this many output periods of
    # a tick, so that a node catching up stays responsive (ticks and poses together catch up
    # fast enough).
    OUTPUTS_PER_CALL = 2
    # The timer ticks at publish_rate, but no faster than this [Hz]; faster rates publish
    # several outputs per tick, their stamps still 1 / rate apart. At publish_rate 1000 with
    # 50 Hz poses the single-line node took 54 % of a core with 1 kHz ticks, 38 % with these
    # (both delivered 1000 outputs a second).
    MAX_TICK_RATE = 200.0
    # A pose stamped further than this [s] ahead of the node clock is dropped. One stamped
    # 1 h ahead froze the fairlead for the hour (every later pose was not after the newest
    # one), one 15 s ahead for 15 s, then a 335 kN spike. Poses do not come from the future:
    # this allows for clocks a little out of sync (NTP keeps them within milliseconds).
    STAMP_AHEAD_LIMIT = 1.0
    # ... or further than this [s] behind it. A late pose is mostly harmless (the ropes
    # follow the stream, late), but a stream that late holds the outputs back as long
    # after each silence. Poses wait for the node in transport and in its queue: the node
    # took the last of a burst of 10,000 1.9 s after its stamp (3.7 s while recording).
    STAMP_BEHIND_LIMIT = 10.0

    def __init__(self, driver: Driver):
        """Pace this driver's mooring; nothing has arrived yet."""
        self.driver = driver
        # clock [ns] at each stream's newest pose; the clock since which the node was on time
        self._arrived: Dict[str, int] = {stream: 0 for stream in driver.streams}
        self._on_time_since = 0
        self._last_tick = 0
        # outputs computed, not yet published (see release), and (clock, lag) [ns] of the
        # oldest output each pose let through
        self._held: Deque[Published] = deque()
        self._lags: Deque[Tuple[int, int]] = deque()
        self._pose_stamps: Dict[Optional[str], int] = {}  # each stream's newest stamp [ns]

    def tick_period(self, rate: Optional[float] = None) -> float:
        """Return the timer period [s] at publish_rate `rate` (now: the driver's)."""
        return 1.0 / min(self.driver.rate if rate is None else rate, self.MAX_TICK_RATE)

    # -- inputs ---------------------------------------------------------------------------

    def admit(self, stream: str, stamp_ns: int, now_ns: int) -> Admission:
        """
        Take a pose's stamp [ns] at clock reading now_ns, or drop it for its stamp.

        Both decisions depend on the node clock: they are events.
        """
        admission = Admission(stamp_ns)
        if stamp_ns == 0 and now_ns:  # (a bag replayed from time 0 has both at 0 at first)
            admission.stamp_ns = stamp_ns = now_ns
            admission.events.append(('restamp', {'stream': stream, 'stamp': now_ns}))
            admission.problem = 'header.stamp is zero: using the receive time as the sample time'
        # Under use_sim_time the clock reads 0 until the first /clock: nothing to compare.
        skew = (stamp_ns - now_ns) * 1e-9
        if now_ns and not -self.STAMP_BEHIND_LIMIT <= skew <= self.STAMP_AHEAD_LIMIT:
            side, limit = (('ahead of', self.STAMP_AHEAD_LIMIT) if skew > 0
                           else ('behind', self.STAMP_BEHIND_LIMIT))
            admission.events.append(('drop', {'stream': stream, 'stamp': stamp_ns}))
            admission.stamp_ns = None
            admission.problem = (f'stamp {side} the node clock by {abs(skew):.3f} s, more than '
                                 f'{limit:g} s: are the clocks in sync (use_sim_time)?')
        return admission

    def arrived(self, stream: str, now_ns: int) -> None:
        """Note that a pose of a stream was taken at clock reading now_ns."""
        self._arrived[stream] = now_ns

    def after_pose(self, stream: str, pose_ns: int, now_ns: int) -> Pace:
        """Move the ropes on after a pose of a stream (stamped pose_ns) was taken."""
        pace = Pace()
        self._advance(pace, now_ns, pose_ns, stream)
        return pace

    def reset(self) -> None:
        """Forget the outputs held for their time: they are of the lines before a reset."""
        self._held.clear()

    # -- time -----------------------------------------------------------------------------

    def tick(self, now_ns: int) -> Pace:
        """
        Start a free ship, judge the streams' silence and advance, at a tick at now_ns.

        A stream is silent if it brought no pose while the node was on time (see LATE_TICK).
        """
        pace = Pace()
        driver = self.driver
        if not self._last_tick or not 0 <= now_ns - self._last_tick <= (
                self.tick_period() + self.LATE_TICK) * 1e9:
            self._on_time_since = now_ns  # a late tick (or a clock jump): wait anew
        self._last_tick = now_ns
        if not driver.started:
            if driver.mooring.free and now_ns:  # under use_sim_time: once /clock runs
                try:
                    pace.started = driver.start_free(now_ns)
                except ParameterError as e:  # a pretension no length gives at the start pose
                    pace.start_error = str(e)
                    return pace
                pace.events.append(('start', {'stamp': now_ns}))
                self._advance(pace, now_ns)
            return pace
        for stream in driver.streams:
            waited = now_ns - max(self._arrived[stream], self._on_time_since)
            if driver.live(stream) and waited >= self.LIVE_INPUT * 1e9:
                driver.silence(stream)
                pace.events.append(('silent', {'stream': stream, 't': driver.time}))
                pace.silenced.append(stream)
        self._advance(pace, now_ns)
        return pace

    def _advance(self, pace: Pace, clock_ns: int, pose_ns: int = 0,
                 stream: Optional[str] = None) -> None:
        """
        Advance the ropes towards the clock, holding each output they reach for its time.

        Outputs are reached as soon as the input lets them: from a pose when a pose stream is
        live, else from the tick. One call reaches at most OUTPUTS_PER_CALL ticks' worth of
        them; a node further behind than MAX_LAG skips ahead instead of catching up.

        :param pose_ns: the stamp of the pose that called (0: a tick); stream: its stream.
        """
        driver = self.driver
        # With use_sim_time the clock reads 0 until the first /clock message: until then
        # the poses alone say how far the ropes may go.
        now = driver.seconds(clock_ns) if clock_ns and driver.epoch_ns is not None else math.inf
        pace.no_clock = not clock_ns and driver.last_sample(SHIP) > self.LIVE_INPUT
        rate = driver.rate
        # without a clock no tick runs: a pose must take every output it lets through
        limit = math.inf if math.isinf(now) else self.OUTPUTS_PER_CALL * math.ceil(
            rate * self.tick_period(rate) - 1e-9)
        report = driver.advance(now, limit, self.MAX_LAG)
        if report.clock_back:
            self._held.clear()
            self._lags.clear()
            pace.clock_back = report.clock_back
            pace.events.append(('clock_back', {'back': report.clock_back}))
            return
        if report.skipped:
            pace.skipped = report.skipped
            pace.events.append(('skip', {'t': report.skip_to}))
        pace.faults = report.faults
        if report.outputs and pose_ns:
            # the next pose's outputs come: those of the one before are due by now, whatever
            # a clock out of step with the stamps says (never held past a pose period)
            pace.publish.extend(self._held)
            self._held.clear()
            grid = [p for p in report.outputs if p.advance is not None]  # (not a restart's)
            # poses slower than the outputs, not a burst of queued poses (a node that stalled
            # at its start): the lag of such a burst held a stream's last outputs while a
            # paused sim clock stood still
            slower = pose_ns - self._pose_stamps.get(stream, pose_ns) > 1.5e9 / rate
            if len(grid) > 1 and clock_ns and slower:
                self._lags.append((clock_ns, pose_ns - grid[0].stamp_ns))
        if pose_ns:
            self._pose_stamps[stream] = pose_ns
        pace.reached = report.outputs
        self._held.extend(report.outputs)
        self._release(pace, clock_ns)

    def _release(self, pace: Pace, clock_ns: int) -> None:
        """
        Publish the outputs held back whose time has come on the node clock.

        Poses slower than the outputs let several through at once (20 Hz poses, 50 Hz
        outputs: 41 % of the gaps under 5 ms). Each output is then due LAG after its stamp,
        LAG the longest any output of the last LAG_WINDOW seconds let through with others
        waited for its pose, in stamps (the pose's stamp less the output's: how the stream
        is sampled, not how late it came): spread over the ticks. Outputs a stalled node
        computes late are overdue and go out at once; with poses as fast as the outputs
        (one output a pose) LAG is 0 and every output goes out as its pose arrives, as
        without a clock.
        """
        held = self._held
        if not held:
            return
        lags = self._lags
        while lags and lags[0][0] < clock_ns - self.LAG_WINDOW * 1e9:
            lags.popleft()
        lag = max((lag for _, lag in lags), default=0)
        early = self.EARLY * self.tick_period() * 1e9
        while held and (not clock_ns or held[0].stamp_ns + lag - early <= clock_ns):
            pace.publish.append(held.popleft())
