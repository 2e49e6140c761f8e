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

"""The seed's position and velocity adjustment keeps every spring within max_strain."""

import math

import numpy as np
from one_line import OneLine
import pytest

from rope_sim_ros.model.superelastic import adjust, MAX_ITERATIONS
from rope_sim_ros.params.table import from_values

MAX_STRAIN = 0.25


def _jerk(integrator, adjusting):
    """Jerk the end of a soft 10 m line, slack at 9 m, to 12 m (1.2 L) in 0.1 s."""
    params = from_values(dict(
        segments=20, length=10.0, mass_per_length=1.0, axial_stiffness=2.0e4,
        axial_damping=1.0, max_strain=MAX_STRAIN, superelastic_adjustment=adjusting,
        integrator=integrator))
    sim = OneLine(params, history=math.inf)
    for t, x in ((0.0, 9.0), (0.5, 9.0), (0.6, 12.0), (3.0, 12.0)):
        sim.push_fairlead(t, [x, 0.0, 0.0])
    sim.start(0.0)
    worst = 0.0
    while sim.time < 2.0:
        sim.advance_to(sim.time + sim.time_step)
        worst = max(worst, float(sim.rope.strains().max()))
    return worst


@pytest.mark.parametrize('integrator', ['improved_euler', 'implicit_euler'])
def test_jerked_end_never_overstretches(integrator):
    assert _jerk(integrator, True) <= MAX_STRAIN * (1.0 + 1e-6)


@pytest.mark.parametrize('integrator', ['improved_euler', 'implicit_euler'])
def test_without_adjustment_the_jerk_overshoots(integrator):
    assert _jerk(integrator, False) > MAX_STRAIN * 1.5


def test_single_spring_moves_both_particles_half_way():
    x = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.5, 0.0, 0.0], [3.5, 0.0, 0.0]])
    v = np.array([[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
    inv_mass = np.array([0.0, 1.0, 1.0, 0.0])
    # spring 1-2 is 1.5 long against a limit of 1.25: each particle moves 0.125
    assert adjust(x, v, inv_mass, np.ones(3), 0.25, MAX_ITERATIONS) >= 1
    assert x[1, 0] == pytest.approx(1.125)
    assert x[2, 0] == pytest.approx(2.375)
    # relative velocity along the spring removed, the pair's momentum and the sideways
    # component kept
    assert v[1, 0] == pytest.approx(0.5, rel=1e-5)
    assert v[2, 0] == pytest.approx(0.5, rel=1e-5)
    assert v[2, 1] == pytest.approx(1.0)


def test_kinematic_end_is_never_moved():
    x = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 0.0, -2.5]])
    v = np.zeros_like(x)
    inv_mass = np.array([0.0, 1.0, 0.0])
    adjust(x, v, inv_mass, np.ones(2), 0.25, MAX_ITERATIONS)
    assert x[0] == pytest.approx([0.0, 0.0, 0.0])
    assert x[2] == pytest.approx([0.0, 0.0, -2.5])
    lengths = np.linalg.norm(np.diff(x, axis=0), axis=1)
    assert lengths.max() <= 1.25 * (1.0 + 1e-9)


def test_line_pulled_past_its_total_limit_stays_finite():
    """Ends 4 m apart on three 1.25 m limits: infeasible; the adjustment spreads the excess."""
    x = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.5, 0.0, 0.0], [4.0, 0.0, 0.0]])
    v = np.ones_like(x)
    inv_mass = np.array([0.0, 1.0, 1.0, 0.0])
    assert adjust(x, v, inv_mass, np.ones(3), 0.25, MAX_ITERATIONS) == MAX_ITERATIONS
    assert np.isfinite(x).all() and np.isfinite(v).all()
    lengths = np.linalg.norm(np.diff(x, axis=0), axis=1)
    assert lengths.sum() == pytest.approx(4.0)
    assert lengths.min() > 1.25 and lengths.max() < 1.5
