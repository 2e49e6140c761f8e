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
The input and output rules of mooring.driver.Driver on a single line, a mooring of one line.

One sample behind a live stream, outputs pinned to their grid, skip ahead past MAX_LAG, a
clock jump back, a rate change re-anchoring the grid, and the torque arm of each output.
The fairlead is the ship's pose with the line's fairlead_offset (none here but in the lever
test): a level pose at the fairlead point.
"""

import math

import numpy as np
from one_line import OneLine
import pytest
from rope_sim_ros.model.frames import rotation_matrix, unit_quaternion
from rope_sim_ros.mooring.driver import Driver, MAX_LAG, SHIP
from rope_sim_ros.mooring.events import decode_event, encode_event
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import from_values, ParameterError

EPOCH = 1_767_225_600_000_000_000  # [ns] stamp of the first sample
FAIRLEAD_POINT = np.array([36.0, 0.0, 8.0])
SECOND = 1_000_000_000
LEVEL = (0.0, 0.0, 0.0, 1.0)
BOLLARD = ''  # the single line's name: its bollard's stream


def line(**values):
    return from_values({'segments': 8, **values})


def one_line(params, rate=None, history=5.0) -> Driver:
    """Return a Driver of a mooring of this one line."""
    return Driver(single_line(params), rate=rate, history=history)


def push(driver: Driver, stamp_ns: int, point) -> dict:
    """Take a fairlead sample: a level ship pose at the point (no fairlead_offset)."""
    return driver.push_ship(stamp_ns, point, LEVEL)


def surge(t: float) -> np.ndarray:
    return FAIRLEAD_POINT + [0.3 * math.sin(2.0 * t), 0.0, 0.1 * math.sin(3.0 * t)]


def stamps(report) -> list:
    return [(p.stamp_ns - EPOCH) for p in report.outputs]


def test_the_rope_stays_one_sample_behind_a_live_stream():
    driver = one_line(line(), rate=50.0)
    assert push(driver, EPOCH, surge(0.0)) == {'start': {}}
    # a single sample: the fresh output at the start, nothing past it
    assert stamps(driver.advance(math.inf)) == [0]
    push(driver, EPOCH + 100_000_000, surge(0.1))
    # the newest sample (0.1 s) is not reached: its motion up to it needs the next one
    assert stamps(driver.advance(math.inf)) == []
    push(driver, EPOCH + 200_000_000, surge(0.2))
    assert stamps(driver.advance(math.inf)) == [20_000_000 * k for k in range(1, 6)]
    # a clock behind the samples holds the rope back too
    push(driver, EPOCH + 300_000_000, surge(0.3))
    assert stamps(driver.advance(0.15)) == [120_000_000, 140_000_000]
    # a silent stream no longer holds it: the rope goes on with the clock, coasting
    assert driver.silence(SHIP) and not driver.live(SHIP)
    assert stamps(driver.advance(0.5))[-1] == 500_000_000
    push(driver, EPOCH + 600_000_000, surge(0.6))
    assert driver.live(SHIP)


@pytest.mark.parametrize('integrator, bound', [('implicit_euler', 1e-6), ('adaptive', 1e-3)])
def test_one_sample_behind_is_the_whole_motion_known(integrator, bound):
    """
    Fed sample by sample, the outputs are those of the line given every sample first.

    To round-off: the driver pins its steps to the output grid (0.2 s), the line alone adds
    them up (0.19999999999999998 s). The adaptive integrator's snap watch (this surge keeps
    it in improved Euler most of the time) can tip either way on such a difference: 8.5e-5 N.
    """
    params = line(integrator=integrator)
    driver = one_line(params, rate=50.0)
    whole = OneLine(params, output_interval=0.02, history=math.inf)
    times = np.arange(0, 101) * 0.02
    live = []
    for k, t in enumerate(times):
        push(driver, EPOCH + k * 20_000_000, surge(t))
        whole.push_fairlead(k * 20_000_000 / 1e9, surge(t))
        live += [p.output.fairlead_forces[0] for p in driver.advance(math.inf).outputs]
    whole.start(0.0)
    offline = []
    for k in range(len(live)):
        whole.advance_to(k / 50.0 + 0.5 * whole.time_step)
        offline.append(whole.output().fairlead_force)
    assert len(live) == 100  # up to the second-newest sample
    difference = np.abs(np.subtract(live, offline)).max()
    assert difference < bound, difference


def test_outputs_are_pinned_to_their_grid():
    # 30 Hz does not divide the 20 ms samples; the step is chosen to divide 1/30 s: each
    # output's state time is exactly k / 30 s, not a running sum of steps
    driver = one_line(line(), rate=30.0)
    times = []
    for k in range(301):
        push(driver, EPOCH + k * 20_000_000, surge(k * 0.02))
        times += [p.output.t for p in driver.advance(math.inf).outputs]
    assert len(times) == 180  # 0 .. 5.96 s: to the second-newest sample
    assert times == [k / 30.0 for k in range(180)]
    assert driver.time == times[-1]


def test_a_lag_past_max_lag_skips_ahead_and_restarts_there():
    driver = one_line(line(), rate=50.0)
    for k in range(6):
        push(driver, EPOCH + k * 20_000_000, surge(k * 0.02))
    assert stamps(driver.advance(math.inf))[-1] == 80_000_000
    driver.silence(SHIP)
    report = driver.advance(0.08 + MAX_LAG + 0.5)
    assert report.skipped == pytest.approx(MAX_LAG + 0.5) and report.skip_to == 1.58
    # the fresh state at the skip, then the grid from there (here at most 3 per call)
    assert stamps(report) == [1_580_000_000] and report.outputs[0].advance is None
    report = driver.advance(1.7, max_outputs=3)
    assert stamps(report) == [1_600_000_000, 1_620_000_000, 1_640_000_000]
    assert report.skipped == 0.0 and report.outputs[0].advance.steps > 0
    # within MAX_LAG: no skip, it catches up
    assert driver.advance(1.64 + 0.9).skipped == 0.0
    # without a limit on the lag (offline): never a skip
    assert driver.advance(10.0, max_lag=math.inf).skipped == 0.0
    assert driver.time == pytest.approx(10.0)


def test_a_clock_jump_back_clears_the_line():
    driver = one_line(line(), rate=50.0)
    push(driver, EPOCH, surge(0.0))
    push(driver, EPOCH + SECOND, surge(0.0))
    driver.silence(SHIP)
    driver.advance(3.0, max_lag=math.inf)
    report = driver.advance(3.0 - MAX_LAG - 0.1)
    assert report.clock_back == pytest.approx(MAX_LAG + 0.1) and report.outputs == []
    assert not driver.started and driver.epoch_ns is None
    # the next fairlead sample starts it again, its stamp the new epoch
    assert push(driver, EPOCH - 5 * SECOND, surge(0.0)) == {'start': {}}
    assert stamps(driver.advance(math.inf)) == [-5 * SECOND]


def test_a_rate_change_re_anchors_the_grid_at_the_last_output():
    driver = one_line(line(), rate=50.0)
    outputs = []
    for k in range(101):
        if k == 50:  # the last output so far is at 0.96 s
            driver.update(None, {'publish_rate': 30.0})
            assert driver.rate == 30.0
        push(driver, EPOCH + k * 20_000_000, surge(k * 0.02))
        outputs += stamps(driver.advance(math.inf))
    before = [k * 20_000_000 for k in range(49)]
    after = [960_000_000 + round(k / 30.0 * 1e9) for k in range(1, 31)]
    assert outputs == before + after  # no gap, no burst: 1/30 s after 0.96 s, and on
    # the step divides the new period
    period = 1.0 / 30.0 / driver.mooring.time_step
    assert period == pytest.approx(round(period), abs=1e-9)


def lever_of(offset, orientation) -> np.ndarray:
    """Return the fairlead's lever of a pose: its offset turned by the pose's orientation."""
    return (np.array([offset]) @ rotation_matrix(unit_quaternion(orientation)[0]).T)[0]


def test_the_lever_is_the_newest_samples_at_or_before_the_output():
    # The pose rolls: each sample has its own lever. An output gets the lever of the
    # newest sample at or before its time, not of the newest sample taken (one ahead).
    offset = [2.0, 1.0, 3.0]
    driver = one_line(line(fairlead_offset=offset), rate=20.0)
    rolls = {k: [math.sin(0.05 * k), 0.0, 0.0, math.cos(0.05 * k)] for k in range(8)}
    levers = {k: lever_of(offset, rolls[k]) for k in range(8)}
    got = []
    for k in range(8):  # the fairlead at the surge point, the pose's origin a lever from it
        driver.push_ship(EPOCH + k * 100_000_000, surge(0.1 * k) - levers[k], rolls[k])
        for p in driver.advance(math.inf).outputs:
            got.append((p.stamp_ns - EPOCH, p.fairlead_levers[0], p.bollard_levers[0]))
    # outputs every 50 ms up to the second-newest sample (0.6 s)
    assert [ns for ns, _, _ in got] == [50_000_000 * k for k in range(13)]
    for ns, fairlead, bollard in got:
        assert np.array_equal(fairlead, levers[ns // 100_000_000]), ns
        assert np.array_equal(bollard, np.zeros(3))  # no bollard sample: no arm
    oldest = driver.mooring.ship_pose(-1.0)[1]  # the oldest kept
    assert np.array_equal(lever_of(offset, oldest), levers[6])
    assert np.array_equal(driver._bollard_levers_at(0.3)[0], np.zeros(3))


def test_a_bollard_stream_holds_the_rope_back_too():
    driver = one_line(line(), rate=50.0)
    driver.push_bollard(BOLLARD, EPOCH, [0.0, 0.0, 0.0])
    push(driver, EPOCH, surge(0.0))
    for k in range(1, 11):
        push(driver, EPOCH + k * 20_000_000, surge(k * 0.02))
    driver.push_bollard(BOLLARD, EPOCH + 100_000_000, [0.0, 0.0, 0.0])
    # the fairlead reached 0.2 s, the bollard is at its first sample still
    assert stamps(driver.advance(math.inf)) == [0]
    driver.push_bollard(BOLLARD, EPOCH + 200_000_000, [0.0, 0.0, 0.0])
    assert stamps(driver.advance(math.inf))[-1] == 100_000_000


def test_reset_restarts_at_the_state_time_and_re_anchors():
    driver = one_line(line(), rate=50.0)
    for k in range(11):
        push(driver, EPOCH + k * 20_000_000, surge(k * 0.02))
    driver.advance(math.inf)
    driver.reset()
    report = driver.advance(math.inf)
    assert stamps(report) == [180_000_000]  # the fresh state, where the rope was
    assert report.outputs[0].advance is None


def test_events_round_trip_and_bad_rates_are_refused():
    text = encode_event('skip', t=1.25)
    assert decode_event(text) == {'event': 'skip', 't': 1.25}
    with pytest.raises(ValueError):
        decode_event('{"event": "explode"}')
    for rate in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ParameterError, match='output rate'):
            one_line(line(), rate=rate)


# ------------------------------------------------------------------ restarts that part


def teleport_run(driver: Driver, jump, bollard=None) -> tuple:
    """
    Hold the ship still 1 s, then jump it (or the bollard) by `jump`; 1 s more at 50 Hz.

    :returns: the outputs before the jump, and those after it.
    """
    start = driver.arrangement.lines[0].params
    rest = np.array([0.0, -17.6, 0.0]) if driver.mooring.names[0] else FAIRLEAD_POINT
    outputs, before = [], []
    for k in range(101):
        if k == 50:
            before, outputs = outputs, []
        t = k / 50.0
        moved = t >= 1.0
        push(driver, EPOCH + k * SECOND // 50, rest + (jump if moved and bollard is None else 0))
        if bollard is not None and k >= 25:
            driver.push_bollard('', EPOCH + k * SECOND // 50,
                                np.asarray(start.bollard_position) + (jump if moved else 0))
        outputs += driver.advance(t).outputs
    return before, outputs


def test_a_teleport_puts_no_load_of_its_own_in_an_output_or_a_peak(repo_root):
    # The berth's ship jumps 50 m ahead (issue: five lines parted as designed, but
    # spring_aft, whole, reported a peak of 19.7 MN, what a line held at its reach pulls,
    # and stern_1 sent 4.13 MN as a fairlead tension, 3.3 times its break load). The lines
    # past their break load at the new place part as they restart, at rest in two pieces;
    # the others restart at rest; no number of the jump reaches an output or a peak.
    from rope_sim_ros.params.arrangement import read_arrangement_file
    driver = Driver(read_arrangement_file(repo_root / 'config' / 'berth.yaml'))
    before, after = teleport_run(driver, np.array([50.0, 0.0, 0.0]))
    names = driver.mooring.names
    breaks = np.array([line.break_load for line in driver.mooring.lines])
    assert not before[-1].output.parted.any()
    parted = [names[k] for k in np.flatnonzero(after[0].output.parted)]
    assert parted == ['breast_fwd', 'spring_fwd', 'breast_aft', 'stern_1', 'stern_2'], parted
    largest = np.max([np.maximum.reduce([p.output.fairlead_tensions,
                                         p.output.bollard_tensions, p.output.peaks])
                      for p in after], axis=0)
    print('largest tension or peak after the jump [kN]:',
          dict(zip(names, np.round(largest / 1e3, 1))))
    assert (largest < 0.05 * breaks).all(), dict(zip(names, largest))
    for p in after:  # neither beyond reach nor restarted: the parted lines are in pieces
        assert not p.advance or not (p.advance.beyond_reach or p.advance.restarted), p.advance


def test_a_bollard_teleport_past_the_reach_parts_the_line_at_rest():
    # The single line's bollard jumps 20 m, its ends then 56.6 m apart, past the 50 m its
    # 40 m reach (issue: 4.4 MN on bollard/peak_tension, EA x max_strain). It parts as it
    # restarts: no peak above the pieces' weight.
    driver = one_line(from_values({}))
    _, outputs = teleport_run(driver, np.array([-20.0, 0.0, 0.0]), bollard=True)
    after = [p.output for p in outputs]
    assert after[0].parted[0] and driver.mooring.lines[0].parting.t == pytest.approx(0.96)
    largest = max(max(o.peaks[0], o.fairlead_tensions[0], o.bollard_tensions[0]) for o in after)
    print(f'largest tension or peak after the jump: {largest:.0f} N')
    assert largest < 2000.0  # 40 m of 2.6 kg/m: the pieces hang
    assert all(not p.advance or not p.advance.restarted for p in outputs)


def test_a_line_pulled_past_its_reach_parts_and_is_held_no_more():
    # The fairlead runs off 26 m in 3 s: the line is held at its reach, pulls its break
    # load and parts. From then on it is neither beyond reach (its reach is infinite) nor
    # restarted 'back within reach' (issue: both logged for a parted line).
    driver = one_line(from_values({}))
    parted_at, later = None, []
    for k in range(251):
        t = k / 50.0
        push(driver, EPOCH + k * SECOND // 50,
             FAIRLEAD_POINT + [26.0 * min(max(t - 1.0, 0.0) / 3.0, 1.0), 0.0, 0.0])
        for p in driver.advance(t).outputs:
            if p.advance and p.advance.parted:
                parted_at = p.output.t
            elif parted_at is not None and p.advance:
                later.append(p.advance)
    assert parted_at is not None and 1.0 < parted_at < 4.0, parted_at
    assert len(later) > 50 and not any(a.beyond_reach or a.restarted for a in later)
