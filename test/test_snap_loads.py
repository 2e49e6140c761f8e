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

"""Snap loads: the adaptive integrator against converged runs (its snatches: test_payload)."""

import math

import numpy as np
from one_line import OneLine
import pytest

from rope_sim_ros.model.layout import PARTED_STEP, PEAK_B
from rope_sim_ros.params.table import from_values
from rope_sim_ros.stepping import adaptive

JERK = ((0.0, 38.0), (0.5, 38.0), (0.7, 39.5), (3.0, 39.5))  # (t [s], fairlead x [m])


def _jerk(integrator=None, time_step=0.0, **values):
    """Return the jerked line's peak fairlead tension [N] over 2 s and its Simulator."""
    if integrator is not None:  # else the parameter's default
        values['integrator'] = integrator
    params = from_values(dict(material='polyester', segments=50, time_step=time_step,
                              **values))
    sim = OneLine(params, output_interval=0.01)
    for t, x in JERK:
        sim.push_fairlead(t, [x, 0.0, 0.0])
    sim.start(0.0)
    peak = 0.0
    for t in np.arange(0.01, 2.0, 0.01):
        sim.advance_to(t)
        peak = max(peak, sim.output().fairlead_peak)
    return peak, sim


@pytest.fixture(scope='module')
def converged_jerk():
    """improved_euler at 2e-5 s (its automatic 2.1e-4 s gives the same peak to 0.1 %)."""
    return _jerk('improved_euler', 2e-5)[0]


def test_a_slack_line_jerked_taut_peaks_as_the_converged_run(converged_jerk):
    """A 40 m polyester line sagging between ends 38 m apart, its fairlead pulled 1.5 m."""
    peak, sim = _jerk()  # default settings: the adaptive integrator
    assert sim.params.integrator == 'adaptive'
    # -0.1 % measured (converged 101.26 kN); implicit_euler at the same 5 ms: -30.9 %
    assert peak == pytest.approx(converged_jerk, rel=0.05)
    assert _jerk('implicit_euler')[0] < 0.8 * converged_jerk


def test_ship_motion_takes_implicit_steps_only(monkeypatch):
    """A 2 m, 8 s surge of the polyester line: no step is taken again with improved Euler."""
    taken = []
    take = adaptive._take

    def counting(system, integrator, *args, **kwargs):
        taken.append(integrator)
        return take(system, integrator, *args, **kwargs)

    monkeypatch.setattr(adaptive, '_take', counting)
    sim = OneLine(from_values(dict(material='polyester', segments=50, integrator='adaptive')),
                  output_interval=0.01, history=math.inf)
    fairlead = np.array([36.0, 0.0, 8.0])
    samples = np.arange(0.0, 12.05, 0.02)
    for t in samples:
        surge = 2.0 * math.sin(2.0 * math.pi * t / 8.0) * min(t / 8.0, 1.0)
        sim.push_fairlead(float(t), fairlead + [surge, 0.0, 0.0])
    sim.start(0.0)
    tensions = []
    for t in np.arange(0.01, 12.0, 0.01):
        sim.advance_to(t)
        tensions.append(sim.output().fairlead_tension)
    assert len(taken) > 1000 and set(taken) == {'implicit_euler'}
    assert 900.0 < min(tensions) and max(tensions) < 1400.0  # 1.33 kN converged


def test_a_step_taken_again_starts_from_everything_it_changed():
    """save_state and load_state, which take a snapping step back, restore all a step writes."""
    _, sim = _jerk('adaptive')
    system = sim.system
    saved = system.save_state()
    system.line_real[0, PEAK_B] = 1.0e9
    system.x += 1.0
    system.load_state(saved)
    for kept, now in zip(saved, (system.x, system.v, system.point_x, system.point_v,
                                 system.particles, system.line_real, system.accel,
                                 system.point_accel)):
        np.testing.assert_array_equal(kept, now)


def test_improved_euler_steps_follow_the_end_on_its_cubic():
    """The substeps' ends lie on the cubic through the samples' positions and velocities."""
    def cubic(t):
        return np.stack([t ** 3 - t, 2.0 * t * t, 0.5 * t]), np.stack(
            [3.0 * t * t - 1.0, 4.0 * t, 0.5 + 0.0 * t])

    dt, parts = 0.2, 5
    steps = np.array([0.2, 0.4])
    x0, v0 = cubic(np.array(0.0))
    xs, vs = cubic(steps)
    fine_x, fine_v = adaptive.hermite(x0.reshape(1, 3), v0.reshape(1, 3),
                                      xs.T.reshape(2, 1, 3), vs.T.reshape(2, 1, 3), dt, parts)
    t = np.arange(1, 2 * parts + 1) * dt / parts
    x, v = cubic(t)
    np.testing.assert_allclose(fine_x[:, 0], x.T, atol=1e-12)
    np.testing.assert_allclose(fine_v[:, 0], v.T, atol=1e-12)


def test_a_line_parting_in_improved_euler_steps_is_timed_within_the_run():
    """A break load the jerk passes: the parting's step is a fraction of the run's steps."""
    peak, sim = _jerk('adaptive', break_load=50.0e3)
    assert sim.parting is not None
    # the converged jerk passes 50 kN at about 0.98 s; the parting is timed to an improved
    # Euler step (0.21 ms), not to the 5 ms step of the run
    step = float(sim.system.line_real[0, PARTED_STEP])
    assert 0.9 < sim.parting.t < 1.05
    assert step != round(step)
    assert np.isfinite(sim.rope.x).all() and peak < 1.2 * 50.0e3
