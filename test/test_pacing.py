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
A live node's clock rules (mooring.pacing.Pacer), on a simulated node clock, without DDS.

A Session plays what a node meets: poses that arrive at given clock readings (their stamps
may differ: transport delays, stalls) and timer ticks, merged in time order, each handed to
the Pacer as the node hands them; it keeps what the Pacer decided and when. The node's own
tests over DDS (test_node_timing.py) show the same rules end to end.
"""

import heapq
import math

import numpy as np
import pytest
from rope_sim_ros.mooring.driver import Driver, SHIP
from rope_sim_ros.mooring.pacing import Pacer
from rope_sim_ros.params import arrangement
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import from_values

EPOCH = 1_767_225_600_000_000_000  # [ns] stamp of the first pose, and the clock then
MS = 1_000_000  # [ns]
FAIRLEAD = np.array([36.0, 0.0, 8.0])
LEVEL = (0.0, 0.0, 0.0, 1.0)


def surge(t: float) -> np.ndarray:
    return FAIRLEAD + [0.3 * math.sin(2.0 * t), 0.0, 0.0]


class Session:
    """One line's Driver and Pacer, fed poses and ticks in clock order."""

    def __init__(self, rate: float = 50.0, setup=None):
        setup = setup or single_line(from_values({'segments': 8}))
        self.driver = Driver(setup, rate=rate)
        self.pacer = Pacer(self.driver)
        self.events = []  # (clock [ns], kind, fields)
        self.published = []  # (clock [ns], output stamp [ns])
        self.dropped = []  # (clock [ns], why)

    def play(self, poses, until_ns: int, tick_ns=None) -> 'Session':
        """
        Run the node clock to until_ns: poses (stamp, arrival) [ns] arrive, the timer ticks.

        The ticks fall every tick_ns (default: the Pacer's period) from the first pose's
        arrival; a pose and a tick at the same reading: the pose first.
        """
        tick_ns = tick_ns or round(self.pacer.tick_period() * 1e9)
        queue = [(arrival, 0, stamp) for stamp, arrival in poses]
        first = min(arrival for _, arrival in poses) if poses else EPOCH
        queue += [(t, 1, 0) for t in range(first + tick_ns, until_ns + 1, tick_ns)]
        heapq.heapify(queue)
        while queue:
            now, kind, stamp = heapq.heappop(queue)
            self.pose(stamp, now) if kind == 0 else self.act(now, self.pacer.tick(now))
        return self

    def pose(self, stamp_ns: int, now_ns: int) -> None:
        """Take a ship pose as the node does: its stamp judged, pushed, then advance."""
        admission = self.pacer.admit(SHIP, stamp_ns, now_ns)
        self.events += [(now_ns, kind, fields) for kind, fields in admission.events]
        if admission.stamp_ns is None:
            self.dropped.append((now_ns, admission.problem))
            return
        t = (admission.stamp_ns - EPOCH) * 1e-9
        self.driver.push_ship(admission.stamp_ns, surge(t), LEVEL)
        self.pacer.arrived(SHIP, now_ns)
        self.act(now_ns, self.pacer.after_pose(SHIP, admission.stamp_ns, now_ns))

    def act(self, now_ns: int, pace) -> None:
        self.events += [(now_ns, kind, fields) for kind, fields in pace.events]
        self.published += [(now_ns, p.stamp_ns) for p in pace.publish]
        assert all(p.output.finite for p in pace.publish)

    def kinds(self, kind: str) -> list:
        return [(now, fields) for now, k, fields in self.events if k == kind]


def stream(rate: float, seconds: float, delay_ns: int = 0, start: float = 0.0) -> list:
    """Poses (stamp, arrival) at `rate` from `start` for `seconds`, each arriving delay_ns late."""
    period = round(1e9 / rate)
    first = EPOCH + round(start * 1e9)
    return [(first + k * period, first + k * period + delay_ns)
            for k in range(round(seconds * rate))]


def test_a_steady_stream_is_never_silent_and_each_output_goes_out_with_its_pose():
    # 50 Hz poses, 50 Hz outputs, each pose 2 ms in transport: one output per pose, out as
    # its pose arrives (one sample behind: the output of the pose before)
    session = Session().play(stream(50.0, 4.0, 2 * MS), EPOCH + 4 * 10**9)
    assert session.kinds('silent') == []
    stamps = np.array([stamp for _, stamp in session.published])
    assert np.array_equal(stamps, EPOCH + 20 * MS * np.arange(len(stamps)))
    assert len(stamps) == 199  # 0 .. 3.96 s: the newest pose, 3.98 s, waits for the next
    latency = np.array([now - stamp for now, stamp in session.published[1:]])
    assert latency.max() == 22 * MS  # a pose period and its transport


def test_a_stream_that_stops_is_silent_after_live_input_and_live_again_at_its_next_pose():
    poses = stream(50.0, 2.0) + stream(50.0, 1.0, start=3.0)
    session = Session().play(poses, EPOCH + 4 * 10**9)
    (silent_at, fields), = session.kinds('silent')
    last = EPOCH + 1_980 * MS  # the last pose before the gap arrived then
    tick = round(session.pacer.tick_period() * 1e9)
    assert last + Pacer.LIVE_INPUT * 1e9 <= silent_at < last + Pacer.LIVE_INPUT * 1e9 + tick
    assert fields['stream'] == SHIP and fields['t'] == pytest.approx(1.96)
    # meanwhile the ropes went on with the clock, coasting, an output every 20 ms
    during = [stamp for now, stamp in session.published if silent_at <= now < EPOCH + 3 * 10**9]
    assert during == list(range(during[0], EPOCH + 3 * 10**9 - 20 * MS + 1, 20 * MS))
    assert session.driver.live(SHIP)  # the poses from 3 s on made it live again


def test_poses_that_arrive_late_in_a_burst_are_not_a_silence():
    # Delivery to a node with many endpoints stalls about 0.3 s while DDS discovers a new
    # participant (ros2 param, ros2 topic beside it): the stream's samples all come, late.
    # 20 Hz poses; those stamped in [1.0, 1.33] s arrive together at 1.33 s. (Taken for
    # silent at 1.20 s when silence was 0.25 s without a pose.)
    poses = [(stamp, max(arrival, EPOCH + 1_330 * MS) if stamp < EPOCH + 1_330 * MS
              and stamp >= EPOCH + 10**9 else arrival)
             for stamp, arrival in stream(20.0, 3.0, 1 * MS)]
    session = Session().play(poses, EPOCH + 3_200 * MS)  # (the held outputs out by then)
    assert session.kinds('silent') == [] and session.kinds('skip') == []
    stamps = np.array([stamp for _, stamp in session.published])
    assert np.array_equal(np.diff(stamps), np.full(len(stamps) - 1, 20 * MS))
    assert stamps[-1] == EPOCH + 2_900 * MS  # one sample behind the last pose, 2.95 s


def test_a_node_that_stalled_reads_the_poses_queued_meanwhile_before_judging_silence():
    # The node stops 0.6 s (no tick, no pose taken); the poses queue and are taken at its
    # first moment back, before its late ticks: a late tick starts the wait again.
    poses = [(stamp, max(arrival, EPOCH + 1_600 * MS) if EPOCH + 10**9 <= arrival
              < EPOCH + 1_600 * MS else arrival)
             for stamp, arrival in stream(50.0, 3.0, 1 * MS)]
    session = Session()
    tick = round(session.pacer.tick_period() * 1e9)
    ticks = [t for t in range(EPOCH + tick, EPOCH + 3 * 10**9, tick)
             if not EPOCH + 10**9 <= t < EPOCH + 1_600 * MS]
    for now, kind, stamp in sorted([(a, 0, s) for s, a in poses] + [(t, 1, 0) for t in ticks]):
        session.pose(stamp, now) if kind == 0 else session.act(now, session.pacer.tick(now))
    assert session.kinds('silent') == [] and session.kinds('skip') == []


def test_stamps_zero_far_ahead_or_far_behind_are_restamped_or_dropped():
    pacer = Session().pacer
    now = EPOCH + 5 * 10**9
    zero = pacer.admit(SHIP, 0, now)
    assert zero.stamp_ns == now and zero.events == [('restamp', {'stream': SHIP, 'stamp': now})]
    ahead = pacer.admit(SHIP, now + 1_001 * MS, now)
    assert ahead.stamp_ns is None and ahead.events[0][0] == 'drop'
    assert 'ahead of the node clock by 1.001 s, more than 1 s' in ahead.problem
    behind = pacer.admit(SHIP, now - 10_001 * MS, now)
    assert behind.stamp_ns is None and 'behind the node clock by 10.001 s' in behind.problem
    assert pacer.admit(SHIP, now + 999 * MS, now).stamp_ns == now + 999 * MS
    # under use_sim_time before the first /clock the clock reads 0: nothing to compare
    assert pacer.admit(SHIP, now + 3600 * 10**9, 0).stamp_ns == now + 3600 * 10**9


def test_one_call_reaches_at_most_two_ticks_of_outputs_and_a_node_far_behind_skips():
    session = Session(rate=100.0)
    session.play(stream(100.0, 0.5), EPOCH + 500 * MS)
    session.driver.silence(SHIP)  # the stream stopped: the ropes go with the clock
    pace = session.pacer.tick(EPOCH + 800 * MS)
    assert len(pace.reached) == 2 and not pace.skipped  # 10 ms ticks: 2 x 1 output
    pace = session.pacer.tick(EPOCH + 2_500 * MS)  # 2 s behind: restart at now
    assert pace.skipped == pytest.approx(2.0, abs=1e-9)  # from the 0.5 s reached above
    assert pace.events == [('skip', {'t': 2.5})]
    assert pace.reached[0].stamp_ns == EPOCH + 2_500 * MS  # the restart's fresh output


def test_a_clock_jump_back_clears_the_ropes():
    session = Session().play(stream(50.0, 2.0), EPOCH + 2 * 10**9)
    pace = session.pacer.tick(EPOCH + 500 * MS)
    assert pace.clock_back == pytest.approx(1.46) and pace.events[0][0] == 'clock_back'
    assert not session.driver.started and pace.publish == []


def test_outputs_between_slower_poses_go_out_evenly_on_the_clock():
    # 20 Hz poses, 50 Hz outputs: each pose lets 2 or 3 through; held, they go out one a tick
    session = Session().play(stream(20.0, 6.0, 2 * MS), EPOCH + 6 * 10**9)
    later = np.array([now for now, stamp in session.published if stamp > EPOCH + 3 * 10**9])
    gaps = np.diff(later)
    assert np.median(gaps) == 20 * MS and gaps.min() >= 10 * MS, np.unique(gaps)
    lags = np.array([now - stamp for now, stamp in session.published
                     if stamp > EPOCH + 3 * 10**9])
    assert lags.max() - lags.min() <= 20 * MS  # each the same time after its stamp, +- a tick


def test_without_a_clock_each_pose_publishes_every_output_it_reaches_at_once():
    session = Session()
    for stamp, _ in stream(20.0, 2.0):
        session.pose(stamp, 0)  # use_sim_time, no /clock: every reading 0
    stamps = [stamp for _, stamp in session.published]
    assert stamps == list(range(EPOCH, EPOCH + 1_900 * MS + 1, 20 * MS))
    assert session.pacer.after_pose(SHIP, EPOCH + 2 * 10**9, 0).no_clock


def test_a_free_ship_starts_at_the_first_tick_of_a_running_clock(repo_root):
    setup = arrangement.read_setup(repo_root / 'config' / 'berth.yaml',
                                   {'ship_mode': 'free', 'segments': 8})
    session = Session(setup=setup)
    assert session.pacer.tick(0).started is None  # sim time before the first /clock
    pace = session.pacer.tick(EPOCH)
    assert sorted(pace.started) == list(range(8))  # every line's length for its pretension
    assert pace.events == [('start', {'stamp': EPOCH})]
    assert [p.stamp_ns for p in pace.publish] == [EPOCH]
