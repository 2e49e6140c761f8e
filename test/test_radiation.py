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

"""The retardation function K(t) of a radiation damping, Ogilvie's relations, its modes."""

import math

from hydro_cases import database, kernel, transfer
import numpy as np
import pytest

from rope_sim_ros.model.ship.radiation import (cosine_weights, database_modes, ogilvie,
                                               retardation, retardation_function)


def within(found: np.ndarray, expected: np.ndarray, fraction: float) -> float:
    """Return the largest misfit (n, 6, 6) as a fraction of each entry's peak, checked."""
    peak = np.abs(expected).max(axis=0)
    held = peak > 1e-9 * peak.max()  # entries that are 0 by the hull's symmetry: absolutely
    misfit = np.abs(found - expected).max(axis=0)
    worst = float((misfit[held] / peak[held]).max())
    assert worst <= fraction
    assert misfit[~held].max(initial=0.0) <= fraction * 1e-9 * peak.max()
    return worst


def test_the_cosine_transform_of_a_line_is_exact():
    """A triangle 0 -> 1 -> 0 on [0, 2]: int cos(w t) = cos t 4 sin^2(t / 2) / t^2; 1 at 0."""
    nodes = np.array([0.0, 1.0, 2.0])
    t = np.array([0.0, 1e-6, 5e-4, 0.5, 3.0, 40.0])
    found = cosine_weights(nodes, t) @ np.array([0.0, 1.0, 0.0])
    safe = np.where(t == 0.0, 1.0, t)
    expected = np.where(t == 0.0, 1.0, np.cos(t) * 4.0 * np.sin(0.5 * safe) ** 2 / safe ** 2)
    np.testing.assert_allclose(found, expected, rtol=1e-9, atol=1e-12)


def test_the_retardation_function_of_an_analytic_damping_is_its_closed_form():
    """K from the tabulated B(omega) against K known in closed form (hydro_cases.py)."""
    db = database()
    t = np.linspace(0.5, 30.0, 300)
    found = retardation(db.omega, db.radiation_damping, t)
    scale = np.sqrt(np.outer(*(2 * [np.abs(np.diagonal(kernel([0.0])[0]))])))
    # 0.5 % of each entry's scale past 0.5 s (B linear between the frequencies; at t = 0 the
    # tail past 80 rad/s, left out, counts too: 1.4 %)
    assert np.abs((found - kernel(t)) / scale).max() <= 0.005


def test_ogilvie_gives_the_analytic_database_back_within_1_percent():
    """B = int K cos, A - A_inf = -(1 / omega) int K sin, at each of its frequencies."""
    db = database()
    function = retardation_function(db.omega, db.radiation_damping)
    assert 10.0 < function.memory < 60.0
    damping, added = ogilvie(function, db.omega)
    print(f'memory {function.memory:.1f} s; B within '
          f'{within(damping, db.radiation_damping, 0.01):.2%}, A - A_inf within '
          f'{within(added, db.added_mass - db.added_mass_infinite, 0.01):.2%}')


def test_ogilvie_finds_a_database_whose_added_mass_does_not_match_its_damping():
    """The check can fail: A_inf 5 % off the diagonal's high-frequency limit."""
    db = database()
    function = retardation_function(db.omega, db.radiation_damping)
    _, added = ogilvie(function, db.omega)
    wrong = db.added_mass - db.added_mass_infinite * 0.95
    with pytest.raises(AssertionError):
        within(added, wrong, 0.01)


def test_the_modes_fit_the_database_within_2_percent():
    """
    The modes' B(omega) and A(omega) - A_inf against the database's, every entry.

    2 % of each entry's own peak: they fit K within 1 % of each entry's scale
    sqrt(K_ii(0) K_jj(0)), of which a coupling's own peak may be a part.
    """
    db = database()
    modes = database_modes(db)
    assert 0 < modes.poles.size <= 48 and (modes.poles.real < 0.0).all()
    h = modes.transfer(db.omega)
    within(h.real, db.radiation_damping, 0.02)
    within(h.imag / db.omega[:, None, None], db.added_mass - db.added_mass_infinite, 0.02)
    exact = transfer(db.omega)
    assert np.abs(h - exact).max() <= 0.01 * np.abs(exact).max()
    assert math.isfinite(modes.error) and modes.error <= 0.01
