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

"""The implicit step's linear solvers against a dense solve, and its stability."""

import math

import numpy as np
from one_line import OneLine
import pytest

from rope_sim_ros.model import linalg
from rope_sim_ros.model.objects import Environment
from rope_sim_ros.model.rope import RopeProperties
from rope_sim_ros.params.table import from_values
from rope_sim_ros.stepping import kernels
from rope_sim_ros.stepping.rules import automatic_time_step, stability_limit


def _spd_blocks(m, rng):
    diagonal = np.array([np.eye(3) * 10.0 + 0.1 * rng.normal(size=(3, 3)) for _ in range(m)])
    diagonal = 0.5 * (diagonal + diagonal.transpose(0, 2, 1))
    lower = rng.normal(size=(m - 1, 3, 3))
    dense = np.zeros((3 * m, 3 * m))
    for i in range(m):
        dense[3 * i:3 * i + 3, 3 * i:3 * i + 3] = diagonal[i]
    for i in range(m - 1):
        dense[3 * i + 3:3 * i + 6, 3 * i:3 * i + 3] = lower[i]
        dense[3 * i:3 * i + 3, 3 * i + 3:3 * i + 6] = lower[i].T
    return diagonal, lower, dense


def test_block_thomas_solves_the_chain_system():
    rng = np.random.default_rng(1)
    diagonal, lower, dense = _spd_blocks(40, rng)
    rhs = rng.normal(size=(40, 3))
    expected = np.linalg.solve(dense, rhs.ravel())
    inverse, multiplier = np.empty((40, 3, 3)), np.empty((40, 3, 3))
    kernels._block_thomas_factor(diagonal, lower, inverse, multiplier, 40)
    kernels._block_thomas_solve(lower, inverse, multiplier, rhs, 40)
    assert rhs.ravel() == pytest.approx(expected, rel=1e-10, abs=1e-12)


def test_banded_cholesky_solves_the_bending_system():
    rng = np.random.default_rng(2)
    n, width = 60, 8
    dense = rng.normal(size=(n, n))
    dense = dense @ dense.T + n * np.eye(n)
    dense[np.abs(np.subtract.outer(np.arange(n), np.arange(n))) > width] = 0.0
    dense += 10.0 * n * np.eye(n)
    band = np.array([[dense[i, i - d] if i >= d else 0.0 for d in range(width + 1)]
                     for i in range(n)])
    rhs = rng.normal(size=n)
    expected = np.linalg.solve(dense, rhs)
    kernels._cholesky_factor(band, n)
    kernels._cholesky_band_solve(band, rhs, n)
    assert rhs == pytest.approx(expected, rel=1e-10)


def test_dense_cholesky_solves_the_point_system():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(9, 9))
    a = a @ a.T + 9.0 * np.eye(9)
    b = rng.normal(size=9)
    expected = np.linalg.solve(a, b)
    linalg.dense_cholesky_solve(a.copy(), b)
    assert b == pytest.approx(expected, rel=1e-10)


def test_improved_euler_needs_damping():
    air = Environment()
    undamped = RopeProperties(20, 40.0, 2.6, 5e7, 0.0)
    assert stability_limit(undamped, air) == 0.0
    with pytest.raises(ValueError, match='axial_damping > 0'):
        automatic_time_step(undamped, air)
    damped = RopeProperties(20, 40.0, 2.6, 5e7, 2903.0)
    wave = 2.0 * math.sqrt(2.6 / 5e7)
    assert 0.0 < automatic_time_step(damped, air) < wave


def _settle(bending, time_step, gust):
    params = from_values({'material': 'steel_wire', 'segments': 50, 'time_step': time_step,
                          'bending_stiffness_ratio': bending})
    sim = OneLine(params, history=math.inf)
    sim.push_fairlead(0.0, [36.0, 0.0, 8.0])
    sim.start(0.0)
    sim.rope.v[1:-1, 1] = gust
    for t in np.arange(0.5, 30.0, 0.5):
        sim.advance_to(t)
        assert np.isfinite(sim.output().positions).all()
    return sim.output().fairlead_tension


@pytest.mark.parametrize('bending', [1e-4, 1e-1])
def test_implicit_step_is_stable_far_past_the_explicit_limit(bending):
    """20 ms steps, 100 times the explicit limit, after a sideways gust: settles as at 2 ms."""
    assert _settle(bending, 0.02, 0.5) == pytest.approx(_settle(bending, 0.002, 0.0), rel=0.01)
