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
the Pacer as the node hands them; it keeps what the Pacer decided and when. The node tests'
scenarios are played here with their numbers; over DDS a test of each rule shows the
wiring end to end: silence, even outputs and no clock (test_node_timing.py), stamps and a
publish_rate change (test_node_guards.py), skips (test_node_mooring_line.py).
"""

import heapq
import math

import numpy as np
from one_line import OneLine
import pytest
from rope_sim_ros.mooring.driver import Driver, SHIP
from rope_sim_ros.mooring.pacing import Pacer
from rope_sim_ros.params import arrangement
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.files import load_params
from rope_sim_ros.params.table import from_values

EPOCH = 1_767_225_600_000_000_000  # [ns] stamp of the first pose, and the clock then
MS = 1_000_000  # [ns]
FAIRLEAD = np.array([36.0, 0.0, 8.0])
LEVEL = (0.0, 0.0, 0.0, 1.0)


def surge(t: float) -> np.ndarray:
    return FAIRLEAD + [0.3 * math.sin(2.0 * t), 0.0, 0.0]


class Session:
    """One line's Driver and Pacer, fed poses and ticks in clock order."""

    def __init__(self, rate: float = 50.0, setup=None, motion=surge):
        """Pace a line (setup: a mooring) whose fairlead is at motion(t) at t [s]."""
        setup = setup or single_line(from_values({'segments': 8}))
        self.driver = Driver(setup, rate=rate)
        self.pacer = Pacer(self.driver)
        self.motion = motion
        self.events = []  # (clock [ns], kind, fields)
        self.published = []  # (clock [ns], output stamp [ns])
        self.outputs = []  # the outputs published (Published), in order
        self.dropped = []  # (clock [ns], why)
        self.skipped = []  # how far [s] each skip ahead went

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

    def run(self, poses, ticks) -> 'Session':
        """
        Hand poses (stamp, arrival) [ns] and ticks (clock readings [ns]) over in clock order.

        A tick due at a pose's arrival goes first: rclpy's executor takes a timer that is
        due before a subscription's messages (after a stall: the late tick, then the poses
        queued meanwhile).
        """
        merged = sorted([(arrival, 1, stamp) for stamp, arrival in poses]
                        + [(now, 0, 0) for now in ticks])
        for now, kind, stamp in merged:
            self.pose(stamp, now) if kind == 1 else self.act(now, self.pacer.tick(now))
        return self

    def ticks(self, start_ns: int, end_ns: int, stalls=()) -> list:
        """Return the timer's ticks from start_ns to end_ns, none in a stall [(from, to)) [ns]."""
        tick = round(self.pacer.tick_period() * 1e9)
        return [t for t in range(start_ns + tick, end_ns + 1, tick)
                if not any(begin <= t < end for begin, end in stalls)]

    def pose(self, stamp_ns: int, now_ns: int) -> None:
        """Take a ship pose as the node does: its stamp judged, pushed, then advance."""
        admission = self.pacer.admit(SHIP, stamp_ns, now_ns)
        self.events += [(now_ns, kind, fields) for kind, fields in admission.events]
        if admission.stamp_ns is None:
            self.dropped.append((now_ns, admission.problem))
            return
        t = (admission.stamp_ns - EPOCH) * 1e-9
        self.driver.push_ship(admission.stamp_ns, self.motion(t), LEVEL)
        self.pacer.arrived(SHIP, now_ns)
        self.act(now_ns, self.pacer.after_pose(SHIP, admission.stamp_ns, now_ns))

    def act(self, now_ns: int, pace) -> None:
        self.events += [(now_ns, kind, fields) for kind, fields in pace.events]
        self.published += [(now_ns, p.stamp_ns) for p in pace.publish]
        self.outputs += pace.publish
        self.skipped += [pace.skipped] if pace.skipped else []
        assert all(p.output.finite for p in pace.publish)

    def kinds(self, kind: str) -> list:
        return [(now, fields) for now, k, fields in self.events if k == kind]


def at(t: float) -> int:
    """Return the clock reading (or stamp) [ns] t [s] after EPOCH."""
    return EPOCH + round(t * 1e9)


def queued(poses, begin_ns: int, end_ns: int, until_ns=None) -> list:
    """Poses (stamp, arrival) whose arrival falls in [begin_ns, end_ns) arrive at until_ns."""
    until_ns = end_ns if until_ns is None else until_ns
    return [(stamp, until_ns if begin_ns <= arrival < end_ns else arrival)
            for stamp, arrival in poses]


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


# -- the node tests' scenarios, with their numbers (test_node_*.py: over DDS, end to end) --


def test_a_stream_beside_stalls_and_late_deliveries_is_silent_only_in_its_real_gap():
    # test_node_timing.py's steady stream (over DDS: calls beside it, a stall, a real gap)
    # with late deliveries besides: 50 Hz poses for 20 s, each 1 ms on its way; the node
    # stopped for 0.4 s at 7 s (SIGSTOP); the poses of 13.5-13.85 s and of 15-15.35 s held
    # back and delivered with the next one (as while DDS discovers a new participant); none
    # in 17-17.9 s: the one real silence.
    poses = [pose for pose in stream(50.0, 20.0, 1 * MS) if not at(17.0) <= pose[0] < at(17.9)]
    poses = queued(poses, at(7.0), at(7.4))
    poses = queued(poses, at(13.5), at(13.86), at(13.86) + MS)
    poses = queued(poses, at(15.0), at(15.36), at(15.36) + MS)
    session = Session()
    session.run(poses, session.ticks(EPOCH, at(20.1), stalls=[(at(7.0), at(7.4))]))
    (when, fields), = session.kinds('silent')
    assert fields['stream'] == SHIP and 16.8 < fields['t'] < 17.9, fields
    assert at(16.98) + Pacer.LIVE_INPUT * 1e9 <= when < at(17.9)
    assert session.kinds('skip') == [] and session.dropped == []


def test_a_node_stopped_for_0_8_s_takes_its_queued_poses_and_misses_no_output():
    # test_node_mooring_line.py's stall: 20 Hz poses; the node stopped from 0.5 s to 1.3 s
    # (SIGSTOP) takes the poses queued meanwhile after its late tick. No silence, no skip,
    # no restart: no event at all; every output on the 20 ms grid, through the stall.
    session = Session()
    poses = queued(stream(20.0, 2.35, 1 * MS), at(0.5), at(1.3))
    session.run(poses, session.ticks(EPOCH, at(2.4), stalls=[(at(0.5), at(1.3))]))
    assert session.events == []
    stamps = np.array([stamp for _, stamp in session.published])
    assert np.array_equal(stamps, EPOCH + 20 * MS * np.arange(len(stamps)))
    assert len(stamps) > 70 and stamps[-1] > at(2.3) - 300 * MS


def test_a_node_stopped_for_1_5_s_after_its_stream_fell_silent_skips_ahead_once():
    # test_node_mooring_line.py's skip: 20 Hz poses for 0.5 s, none for 0.8 s (silent), the
    # node stopped for 1.5 s (SIGSTOP), then a second of poses: 1.5-2 s behind the clock, the
    # ropes skip ahead once and are back at the clock's pace at once.
    session = Session()
    poses = stream(20.0, 0.55) + stream(20.0, 1.05, start=2.8)
    session.run(poses, session.ticks(EPOCH, at(3.8), stalls=[(at(1.3), at(2.8))]))
    (silent_at, _), = session.kinds('silent')
    assert at(1.0) <= silent_at < at(1.3)
    (skip_at, _), = session.kinds('skip')
    assert skip_at == at(2.8) and len(session.skipped) == 1 and 1.5 < session.skipped[0] < 2.0
    after = [stamp for now, stamp in session.published if now >= at(2.8)]
    assert len(after) > 35 and after[-1] > at(3.8) - 300 * MS


@pytest.mark.parametrize('rate, count', [(50.0, 51), (20.0, 161)])
def test_without_a_clock_the_ropes_stay_one_pose_behind_without_a_skip(rate, count):
    # use_sim_time, no /clock (every reading 0): 51 poses at 50 Hz (test_node_mooring_line.py
    # before) and 161 at 20 Hz, 8 s of stamps (test_node_timing.py: a skip ahead every 4.8 s,
    # 2 outputs a pose where 2.5 were due). Every output to the second-newest pose's stamp.
    session = Session()
    stamps = [EPOCH + round(k * 1e9 / rate) for k in range(count)]
    for stamp in stamps:
        session.pose(stamp, 0)
    published = [stamp for _, stamp in session.published]
    assert published == list(range(EPOCH, stamps[-2] + 1, 20 * MS))
    assert session.events == [] and session.skipped == []
    assert session.pacer.after_pose(SHIP, stamps[-1], 0).no_clock


def test_poses_stamped_hours_or_seconds_off_the_clock_are_dropped_and_the_stream_goes_on():
    # test_node_guards.py's strays: 50 Hz poses for 5 s; before the very first and before
    # those of 1 s, 2 s and 3 s, a pose stamped 1 h ahead, 1 h ahead, 15 s ahead and 1 h
    # behind the clock, which reads the previous sample's time then (each froze the fairlead
    # for that long, or held the outputs back).
    good = stream(50.0, 5.02)
    strays = [(at(t + offset), at(t) - (20 * MS if t else 1))
              for t, offset in ((0.0, 3600.0), (1.0, 3600.0), (2.0, 15.0), (3.0, -3600.0))]
    session = Session()
    session.run(good + strays, session.ticks(EPOCH - 1, at(5.1)))
    stamps = np.array([stamp for _, stamp in session.published])
    assert np.array_equal(stamps, EPOCH + 20 * MS * np.arange(250))  # to 4.98 s
    assert session.driver.epoch_ns == EPOCH  # started on the first good pose
    assert [kind for _, kind, _ in session.events] == ['drop'] * 4
    why = [problem for _, problem in session.dropped]
    assert 'stamp ahead of the node clock by 3600.000 s, more than 1 s' in why[0]
    assert 'ahead of the node clock by 3600.020 s' in why[1]
    assert 'ahead of the node clock by 15.020 s' in why[2]
    assert 'behind the node clock by 3599.980 s, more than 10 s' in why[3]


def test_publish_rate_changes_take_effect_with_the_next_output():
    # test_node_guards.py's rate changes: 50 Hz poses, the fairlead still; publish_rate 50
    # -> 30 -> 1000 -> 137 Hz, each set once the outputs up to the newest pose but one are
    # out (40 ms of the clock after it), the ticks at the new rate from then (at most
    # MAX_TICK_RATE). 30 and 137 Hz divide neither the pose period nor the step.
    session = Session(motion=lambda t: FAIRLEAD)
    clock = EPOCH
    for rate, start, end in ((50.0, 0.0, 1.0), (30.0, 1.0, 2.0), (1000.0, 2.0, 2.5),
                             (137.0, 2.5, 3.5)):
        session.driver.update(None, {'publish_rate': rate})
        first = round(start * 50) + (start > 0)  # the stamps 0, 20 ms, ... `end` s
        poses = [(at(k / 50), at(k / 50) + MS) for k in range(first, round(end * 50) + 1)]
        tick = round(session.pacer.tick_period() * 1e9)
        ticks = list(range(clock + tick, at(end) + 40 * MS + 1, tick))
        session.run(poses, ticks)
        clock = ticks[-1]
        # every output up to the newest pose but one is out: the change lands after it
        assert at(end - 0.02) - 1e9 / rate < session.published[-1][1] <= at(end - 0.02)
    stamps = np.array([stamp for _, stamp in session.published])
    # runs of equal periods, in order: every output 1 / rate after the one before it, the
    # rate of the time it was published at (no gap, no burst at a change)
    runs = []
    for period in np.diff(stamps) * 1e-9:
        if runs and abs(period - runs[-1][0]) < 5e-9:
            runs[-1][1] += 1
        else:
            runs.append([period, 1])
    assert [round(1.0 / p, 3) for p, _ in runs] == [50.0, 30.0, 1000.0, 137.0], runs
    # from 0 to 0.98 s, to 1.98 s, to 2.48 s (1000 Hz: every ms), to 3.48 s
    assert [n for _, n in runs] == [49, 30, 500, 137], runs
    assert session.events == [] and session.skipped == []
    # the step changed under a rope at rest: nothing moved
    tensions = np.array([p.output.fairlead_tensions[0] for p in session.outputs])
    assert np.ptp(tensions) < 1e-6 * tensions.mean(), (tensions.min(), tensions.max())


def test_poses_late_past_the_silence_limit_rejoin_without_a_jerk(repo_root):
    # A 5 s surge at up to 0.31 m/s, 50 Hz poses; those of [2.5, 3.15) s arrive together at
    # 3.15 s, as after a transport hiccup longer than LIVE_INPUT. The ropes go on without
    # them (a silent stream), then must bring the fairlead back onto its track smoothly:
    # stepping straight back cost 11 kN (on the replay test's motion with 100 Hz poses).
    line = load_params(repo_root / 'config' / 'mooring_line.yaml')
    chord = FAIRLEAD / np.linalg.norm(FAIRLEAD)

    def motion(t):
        return FAIRLEAD + 0.5 * (1.0 - math.cos(2.0 * math.pi * t / 10.0)) * chord

    sent = stream(50.0, 5.02)
    session = Session(rate=line.publish_rate, setup=single_line(line), motion=motion)
    session.play(queued(sent, at(2.5), at(3.15)), at(5.1))
    assert session.kinds('silent')
    live = {p.stamp_ns: float(p.output.fairlead_tensions[0]) for p in session.outputs}
    assert len(live) > 200
    offline = OneLine(line, output_interval=1.0 / line.publish_rate, history=math.inf)
    for stamp, _ in sent:
        offline.push_fairlead((stamp - EPOCH) * 1e-9, motion((stamp - EPOCH) * 1e-9))
    offline.start(0.0)
    errors = []
    for ns in sorted(live):
        offline.advance_to((ns - EPOCH) * 1e-9 + 0.5 * offline.time_step)
        errors.append(((ns - EPOCH) * 1e-9, live[ns] - offline.output().fairlead_tension))
    times, errors = np.array(errors).T
    worst = np.argmax(np.abs(errors))
    print(f'late poses: worst tension error {errors[worst]:+.0f} N at t = {times[worst]:.2f} '
          f's; RMS {np.sqrt(np.mean(errors ** 2)):.1f} N over {len(errors)} outputs')
    # up to the last output that had the pose after it (the velocity at a sample instant is
    # that of the interval after it), the ropes are the offline run
    assert np.abs(errors[times < 2.47]).max() < 1e-3, 'the ropes differ before the gap'
    assert np.abs(errors).max() < 300.0
