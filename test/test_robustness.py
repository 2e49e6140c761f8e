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

"""Every preset survives a long surge at every resolution; bad end samples change nothing."""

import math

import numpy as np
from one_line import OneLine
import pytest

from rope_sim_ros.model.frames import PoseError
from rope_sim_ros.mooring.trajectory import TrajectoryError
from rope_sim_ros.params.table import from_values, MATERIALS


def _surge(material, segments, integrator, duration):
    """Surge a 40 m, 64 mm line of the preset 2 m with an 8 s period."""
    params = from_values(dict(material=material, segments=segments, integrator=integrator))
    sim = OneLine(params, history=math.inf, output_interval=0.1)
    times = np.arange(0.0, duration + 0.05, 0.05)
    for t in times:
        surge = 2.0 * math.sin(2.0 * math.pi * t / 8.0) * min(t / 8.0, 1.0)
        sim.push_fairlead(float(t), [36.0 + surge, 0.0, 8.0])
    sim.start(0.0)
    peak = 0.0
    for t in np.arange(0.1, duration + 1e-9, 0.1):
        advance = sim.advance_to(float(t))
        assert advance.restarted == '', f'{material} N={segments} restarted at t={t:.1f}'
        out = sim.output()
        assert np.isfinite(out.positions).all()
        assert np.isfinite(out.fairlead_force).all() and np.isfinite(out.bollard_force).all()
        peak = max(peak, out.fairlead_tension)
    return sim, peak


@pytest.mark.parametrize('segments', [10, 50, 200])
@pytest.mark.parametrize('material', MATERIALS)
def test_default_integrator_survives_60_s(material, segments):
    sim, peak = _surge(material, segments, 'implicit_euler', 60.0)
    assert sim.time == pytest.approx(60.0)
    # the line stays a mooring line: tension well below breaking, strain small
    assert 0.0 < peak < sim.material.mbl
    assert sim.output().max_strain < 0.05


@pytest.mark.parametrize('segments', [10, 50])
@pytest.mark.parametrize('material', MATERIALS)
def test_improved_euler_automatic_step_survives_60_s(material, segments):
    sim, peak = _surge(material, segments, 'improved_euler', 60.0)
    assert 0.0 < peak < sim.material.mbl


@pytest.mark.parametrize('material', MATERIALS)
def test_improved_euler_automatic_step_is_stable_at_200_segments(material):
    # half a surge period is 5e4 to 4.5e5 explicit steps: an unstable step would have grown
    # from rounding to overflow many times over (60 s would cost the suite ~13 minutes)
    sim, peak = _surge(material, 200, 'improved_euler', 4.0)
    assert 0.0 < peak < sim.material.mbl


def test_nan_end_position_is_rejected_without_touching_the_state():
    sim = OneLine(from_values({}), history=math.inf)
    sim.push_fairlead(0.0, [36.0, 0.0, 8.0])
    sim.start(0.0)
    sim.advance_to(1.0)
    before = sim.output()
    for bad in ([math.nan, 0.0, 8.0], [36.0, math.inf, 8.0]):
        with pytest.raises(PoseError, match='non-finite'):
            sim.push_fairlead(2.0, bad)
    with pytest.raises(TrajectoryError, match='not after'):
        sim.push_fairlead(-1.0, [36.0, 0.0, 8.0])
    assert sim.push_fairlead(2.0, [36.0, 0.0, 8.0]) == ''  # no sample at 2 s was kept
    sim.advance_to(2.0)
    after = sim.output()
    assert np.isfinite(after.positions).all()
    assert after.fairlead_tension == pytest.approx(before.fairlead_tension, rel=1e-3)


def test_non_finite_state_restarts_on_the_catenary():
    sim = OneLine(from_values({}), history=math.inf)
    sim.push_fairlead(0.0, [36.0, 0.0, 8.0])
    sim.start(0.0)
    settled = sim.output().fairlead_tension
    sim.rope.v[5, 2] = math.nan
    advance = sim.advance_to(0.5)
    assert advance.restarted == 'non-finite state'
    out = sim.output()
    assert np.isfinite(out.positions).all()
    assert out.fairlead_tension == pytest.approx(settled, rel=1e-6)


def test_teleport_restarts_at_the_new_place():
    sim = OneLine(from_values({'teleport_distance': 5.0}), history=math.inf)
    sim.push_fairlead(0.0, [36.0, 0.0, 8.0])
    sim.start(0.0)
    sim.advance_to(1.0)
    assert sim.push_fairlead(1.0, [36.5, 0.0, 8.0]) == ''
    assert sim.push_fairlead(1.1, [20.0, 10.0, 8.0]) == 'teleport'
    out = sim.output()
    assert out.positions[-1] == pytest.approx([20.0, 10.0, 8.0])
    assert np.linalg.norm(out.positions[0]) == pytest.approx(0.0)


def _surge_with_late_samples(gap):
    """
    Run a node's way through a surge (up to 0.31 m/s) whose samples of [3, 3 + gap) s are late.

    While samples come the state stays one sample behind the newest; when none has come for
    0.25 s it runs on with the clock; the late ones all come at 3 + gap s. Returns the
    fairlead positions and tensions at every 10 ms output.
    """
    def motion(t):
        return [36.0 + 0.5 * (1.0 - math.cos(2.0 * math.pi * t / 10.0)), 0.0, 8.0]

    sim = OneLine(from_values({}), output_interval=0.01)
    times = np.round(np.arange(0.0, 6.0 + 1e-9, 0.01), 2)
    sim.push_fairlead(0.0, motion(0.0))
    sim.start(0.0)
    pushed, positions, tensions = 1, [], []
    for now in times[1:]:
        late = 3.0 <= times[pushed] < 3.0 + gap and now < 3.0 + gap
        while not late and pushed < len(times) and times[pushed] <= now:
            sim.push_fairlead(times[pushed], motion(times[pushed]))
            pushed += 1
        newest = times[pushed - 1]
        target = times[pushed - 2] if now - newest < 0.25 else now
        while sim.time + 0.01 <= target + 1e-9:
            sim.advance_to(sim.time + 0.01 + 0.5 * sim.time_step)
            positions.append(sim.rope.x[-1, 0])
            tensions.append(sim.output().fairlead_tension)
    return np.array(positions), np.array(tensions)


def test_late_samples_bring_the_end_back_without_a_jump():
    x, tensions = _surge_with_late_samples(0.0)
    late_x, late_tensions = _surge_with_late_samples(0.4)
    # the end coasted to a stop and was 2.7 cm short of its track when the samples came
    assert 0.02 < np.abs(late_x - x).max() < 0.035
    # it came back no faster than the surge itself moves, and with no jump (a 2.7 cm jump
    # in one 10 ms output would be an acceleration of 270 m/s^2; the surge's own is 0.2)
    speed, late_speed = np.diff(x) / 0.01, np.diff(late_x) / 0.01
    assert np.abs(late_speed).max() < 1.01 * np.abs(speed).max()
    assert np.abs(np.diff(late_speed)).max() / 0.01 < 1.0
    # stepping straight back cost 38.7 kN here; the smooth return costs 63 N on ~1.1 kN
    assert np.abs(late_tensions - tensions).max() < 150.0
    # a second after the return the end is on its track again
    assert np.abs(late_x[-100:] - x[-100:]).max() < 1e-12
