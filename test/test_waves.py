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
The sea state and its loads on a hull (rope_sim_ros.model.ship.waves).

The hull is a synthetic HydroDatabase made here: its excitation and drift are linear in the
frequency and in the heading between the table's points, so that the loads interpolated at
any frequency and heading are known in closed form.
"""

import math

import numpy as np
import pytest
from rope_sim_ros.model.ship.hydro import HydroDatabase
from rope_sim_ros.model.ship.waves import (
    about_origin, jonswap_spectrum, Sea, ShipWaves, WaveLoads, wavenumber, Waves)
from scipy.signal import welch

G = 9.81
DEPTH = 20.0
OMEGA = np.linspace(0.2, 3.0, 29)  # [rad/s], 0.1 apart
HEADINGS = np.linspace(-math.pi, math.pi, 25)  # 15 degrees apart, the full circle
CG = np.array([2.0, 0.5, -3.0])


def linear_excitation(omega, heading):
    """X per metre: linear in omega and in heading on a table point's interval (any shape)."""
    omega, heading = np.broadcast_arrays(np.asarray(omega, float), np.asarray(heading, float))
    scale = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]) * 1e5
    real = (1.0 + omega[..., None]) * (1.0 + 0.3 * heading[..., None]) * scale
    imag = (0.5 - omega[..., None]) * (2.0 - 0.2 * heading[..., None]) * scale
    return real + 1j * imag


def linear_drift(omega, heading):
    """D per square metre, of both signs: linear in omega and heading likewise."""
    omega, heading = np.broadcast_arrays(np.asarray(omega, float), np.asarray(heading, float))
    return np.stack([-2e4 * (1.0 + omega) * (1.0 + 0.1 * heading),
                     3e4 * (omega - 1.0) * (2.0 + 0.1 * heading),
                     5e5 * (1.0 + 0.2 * heading) * omega], axis=-1)


def database(headings=HEADINGS, excitation=linear_excitation, drift=linear_drift):
    """Return the synthetic hull's database at the tables' points."""
    h, w = np.meshgrid(headings, OMEGA, indexing='ij')
    zeros = np.zeros((OMEGA.size, 6, 6))
    return HydroDatabase(OMEGA, zeros, zeros, np.zeros((6, 6)), headings, excitation(w, h),
                         drift(w, h), CG, DEPTH, 1025.0, G)


def regular(height=2.0, period=8.0, direction=0.0):
    return Waves.make('regular', height, period, direction, 3.3, 0, DEPTH, G)


# ---------------------------------------------------------------------- the sea state


def test_the_wavenumber_solves_the_finite_depth_dispersion():
    omega = np.array([0.2, 0.785, 1.5, 4.0])
    k = wavenumber(omega, DEPTH, G)
    np.testing.assert_allclose(G * k * np.tanh(k * DEPTH), omega ** 2, rtol=1e-13)
    np.testing.assert_allclose(wavenumber(omega, math.inf, G), omega ** 2 / G, rtol=0)
    assert k[0] > omega[0] ** 2 / G * 1.5  # shallow water: far shorter than deep water's


def test_a_regular_wave_has_its_amplitude_and_period_exactly():
    waves = regular(height=3.0, period=9.0, direction=0.4)
    sea = waves.sea
    t = np.linspace(0.0, 9.0, 9001)
    eta = sea.elevation(t, 12.0, -7.0)
    k = wavenumber(2.0 * math.pi / 9.0, DEPTH, G)
    travel = 0.4 + math.pi
    along = 12.0 * math.cos(travel) - 7.0 * math.sin(travel)
    expected = 1.5 * np.cos(k * along - 2.0 * math.pi / 9.0 * t)
    np.testing.assert_allclose(eta, expected, rtol=0, atol=1e-12)
    assert sea.elevation(3.3, 12.0, -7.0) == pytest.approx(sea.elevation(12.3, 12.0, -7.0),
                                                           abs=1e-12)
    assert eta.max() == pytest.approx(1.5, abs=1e-6)
    assert sea.elevation(0.0) == 1.5  # a crest at the origin at t = 0


def test_the_jonswap_record_has_the_spectrum_it_was_drawn_from():
    hs, tp = 2.5, 9.0
    sea = Waves.make('jonswap', hs, tp, 0.0, 3.3, 7, DEPTH, G).sea
    dt = 0.5
    t = np.arange(0.0, 3 * 3600.0, dt)
    eta = sea.elevation(t)
    # the record's own Hs: 4 sqrt(m0) from its variance, within 2 % of the one asked for
    assert 4.0 * eta.std() == pytest.approx(hs, rel=0.02)
    frequency, density = welch(eta, fs=1.0 / dt, nperseg=2048)
    omega = 2.0 * math.pi * frequency
    measured = density / (2.0 * math.pi)  # per rad/s
    wp = 2.0 * math.pi / tp
    # the peak where Tp puts it (the Welch bins are 0.0061 rad/s apart)
    assert omega[np.argmax(measured)] == pytest.approx(wp, rel=0.03)
    # the spectrum's integral over bands around the peak and on its flanks: a 3-hour
    # record estimates the 0.1 rad/s wide band at the peak to 1 / sqrt(B T) = 8 % (one
    # standard deviation, B T = 0.016 Hz x 10800 s); 15 % is two of them
    expected = jonswap_spectrum(omega, hs, tp, 3.3)
    for low, high in ((0.7, 0.95), (0.95, 1.1), (1.1, 1.5), (1.5, 2.5)):
        band = (omega >= low * wp) & (omega < high * wp)
        assert measured[band].sum() == pytest.approx(expected[band].sum(), rel=0.15)
    # and the definition's m0 is Hs^2 / 16
    w = np.linspace(0.01, 30.0, 300001)
    assert np.trapezoid(jonswap_spectrum(w, hs, tp, 3.3), w) == pytest.approx(hs ** 2 / 16.0,
                                                                              rel=1e-6)


def test_a_sea_repeats_with_its_seed_and_differs_with_another():
    one = Waves.make('jonswap', 2.0, 8.0, 0.0, 3.3, 11, DEPTH, G).sea
    again = Waves.make('jonswap', 2.0, 8.0, 0.0, 3.3, 11, DEPTH, G).sea
    other = Waves.make('jonswap', 2.0, 8.0, 0.0, 3.3, 12, DEPTH, G).sea
    t = np.linspace(0.0, 600.0, 1201)
    np.testing.assert_array_equal(one.elevation(t), again.elevation(t))
    assert np.abs(one.elevation(t) - other.elevation(t)).max() > 0.5


def test_the_components_fill_one_hour_bins_and_do_not_repeat():
    sea = Waves.make('jonswap', 2.0, 8.0, 0.0, 3.3, 3, DEPTH, G).sea
    step = 2.0 * math.pi / 3600.0
    wp = 2.0 * math.pi / 8.0
    assert sea.omega.size == 1575
    bins = np.floor((sea.omega - 0.5 * wp) / step)
    np.testing.assert_array_equal(bins, np.arange(sea.omega.size))  # one in each bin
    # not on the bins' centres: no common period (an equally spaced sum repeats after 1 h)
    t = np.linspace(0.0, 300.0, 601)
    assert np.abs(sea.elevation(t) - sea.elevation(t + 3600.0)).max() > 0.5


def test_calm_and_none_make_no_sea():
    assert Waves.make('none', 2.0, 8.0, 0.0, 3.3, 0, DEPTH, G).sea is None
    assert Waves.make('jonswap', 0.0, 8.0, 0.0, 3.3, 0, DEPTH, G).sea is None
    assert Waves.make('jonswap', 0.0, 8.0, 0.0, 3.3, 0, DEPTH, G).configured


# ---------------------------------------------------------------------- the loads


def test_first_order_force_of_a_regular_wave_is_re_a_x_exp():
    period, direction, yaw = 2.0 * math.pi / 0.75, 2.0, 0.3  # omega between table points
    waves = regular(height=2.0, period=period, direction=direction)
    loads = WaveLoads(database(), waves.sea)
    omega, k = 0.75, wavenumber(0.75, DEPTH, G)
    travel = direction + math.pi
    heading = (travel - yaw + math.pi) % (2.0 * math.pi) - math.pi
    x, y = 30.0, -12.0
    for t in (0.0, 1.7, 5.2):
        first, _ = loads.at(t, x, y, yaw)
        phase = k * (x * math.cos(travel) + y * math.sin(travel)) - omega * t
        expected = np.real(1.0 * linear_excitation(omega, heading) * np.exp(1j * phase))
        np.testing.assert_allclose(first, expected, rtol=1e-12, atol=1e-6)


def test_newman_drift_in_a_regular_wave_is_the_mean_drift_times_a_squared():
    waves = regular(height=3.0, period=2.0 * math.pi / 1.23, direction=-0.7)
    loads = WaveLoads(database(), waves.sea)
    yaw = 0.1
    heading = -0.7 + math.pi - yaw  # within [-pi, pi]
    expected = linear_drift(1.23, heading) * 1.5 ** 2
    drift = np.array([loads.at(t, 0.0, 0.0, yaw)[1] for t in np.linspace(0.0, 5.1, 40)])
    np.testing.assert_allclose(drift.mean(axis=0), expected, rtol=0.01)
    np.testing.assert_allclose(drift, np.repeat(expected[None], 40, axis=0), rtol=1e-12)


def test_newman_drift_in_irregular_waves_has_the_components_mean():
    sea = Waves.make('jonswap', 2.0, 10.0, 0.5, 3.3, 5, DEPTH, G).sea
    loads = WaveLoads(database(), sea)
    t = np.arange(0.0, 3600.0, 1.0)
    drift = np.array([loads.at(s, 0.0, 0.0, 0.0)[1] for s in t])
    heading = 0.5 + math.pi - 2.0 * math.pi
    mean = (sea.amplitude[:, None] ** 2 * linear_drift(sea.omega, heading)).sum(axis=0)
    # over an hour, the difference-frequency terms average out to a few per cent
    np.testing.assert_allclose(drift.mean(axis=0), mean, rtol=0.08)
    assert drift[:, 0].std() > 0.3 * abs(mean[0])  # and it varies slowly about it


def test_the_mean_drift_is_the_components_sum_at_the_ships_heading():
    # what the berth check holds a ship at rest with: sum a_i^2 D_i, at its heading
    sea = Waves.make('jonswap', 2.0, 10.0, 0.5, 3.3, 5, DEPTH, G).sea
    loads = WaveLoads(database(), sea)
    for yaw in (0.0, 0.4):
        heading = 0.5 + math.pi - yaw - 2.0 * math.pi
        mean = (sea.amplitude[:, None] ** 2 * linear_drift(sea.omega, heading)).sum(axis=0)
        np.testing.assert_allclose(loads.mean_drift(yaw), mean, rtol=1e-9)
    # and in a regular wave it is the slow drift itself, at every instant
    waves = regular(height=3.0, period=2.0 * math.pi / 1.23, direction=-0.7)
    loads = WaveLoads(database(), waves.sea)
    np.testing.assert_allclose(loads.mean_drift(0.1), loads.at(1.7, 0.0, 0.0, 0.1)[1],
                               rtol=1e-12)


def test_the_heading_in_body_axes_follows_the_ship_yaw():
    direction, yaw = 0.9, 0.6
    turned = WaveLoads(database(), regular(direction=direction).sea)
    # the same sea turned by -yaw, on a ship that does not turn: the same loads
    still = WaveLoads(database(), regular(direction=direction - yaw).sea)
    first, drift = turned.at(0.0, 0.0, 0.0, yaw)
    first_still, drift_still = still.at(0.0, 0.0, 0.0, 0.0)
    np.testing.assert_allclose(first, first_still, rtol=1e-12)
    np.testing.assert_allclose(drift, drift_still, rtol=1e-12)
    # and a ship heading another way takes another load
    assert np.abs(turned.at(0.0, 0.0, 0.0, 0.0)[0] - first).max() > 1e4


def symmetric_excitation(omega, heading):
    """Return a port-starboard symmetric hull's X: even in heading in surge, heave, pitch."""
    even = (1.0 + omega[..., None]) * (1.0 + 0.3 * np.abs(heading[..., None]))
    odd = np.sin(heading[..., None]) * (0.5 + omega[..., None])
    sign = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])
    use = np.where(sign > 0, even, odd) * (1.0 + 0.5j) * 1e5
    return use


def symmetric_drift(omega, heading):
    """Return a symmetric hull's drift: surge even in heading, sway and yaw odd."""
    return np.stack([-1e4 * (1.0 + np.cos(heading)) * omega,
                     2e4 * np.sin(heading) * omega, 3e5 * np.sin(2.0 * heading)], axis=-1)


def test_a_half_circle_database_is_completed_by_symmetry():
    half = database(HEADINGS[HEADINGS >= 0.0], symmetric_excitation, symmetric_drift)
    full = database(HEADINGS, symmetric_excitation, symmetric_drift)
    sea = Waves.make('jonswap', 2.0, 8.0, 0.0, 3.3, 2, DEPTH, G).sea
    for yaw in (0.0, 2.0, 4.0, -0.3):
        np.testing.assert_allclose(WaveLoads(half, sea).at(3.0, 1.0, 2.0, yaw)[0],
                                   WaveLoads(full, sea).at(3.0, 1.0, 2.0, yaw)[0], rtol=1e-9,
                                   atol=1e-3)
        np.testing.assert_allclose(WaveLoads(half, sea).at(3.0, 1.0, 2.0, yaw)[1],
                                   WaveLoads(full, sea).at(3.0, 1.0, 2.0, yaw)[1], rtol=1e-9,
                                   atol=1e-3)


def test_the_loads_are_moved_from_the_cg_to_the_origin():
    first = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    drift = np.array([10.0, 20.0, 30.0])
    moved, turned = about_origin(first, drift, CG)
    np.testing.assert_allclose(moved[:3], first[:3])
    np.testing.assert_allclose(moved[3:], first[3:] + np.cross(CG, first[:3]))
    assert turned[2] == pytest.approx(30.0 + CG[0] * 20.0 - CG[1] * 10.0)
    waves = regular()
    elevation, loads = ShipWaves(database()).at(1.0, waves, [5.0, 1.0, 0.0], 0.2)
    first, drift = WaveLoads(database(), waves.sea).at(1.0, 5.0, 1.0, 0.2)
    np.testing.assert_allclose(loads[0], about_origin(first, drift, CG)[0])
    np.testing.assert_allclose(loads[1, [0, 1, 5]], about_origin(first, drift, CG)[1])
    assert elevation == waves.sea.elevation(1.0, 5.0, 1.0)


def test_frequencies_outside_the_database_take_no_load():
    sea = regular(period=2.0 * math.pi / 3.5).sea  # above the table's 3.0 rad/s
    assert sea.outside_share(OMEGA[0], OMEGA[-1]) == 1.0
    first, drift = WaveLoads(database(), sea).at(0.0, 0.0, 0.0, 0.0)
    assert not first.any() and not drift.any()
    assert ShipWaves(None).at(0.0, regular(), [0.0, 0.0, 0.0], 0.0)[1].sum() == 0.0


@pytest.mark.parametrize('arguments, message', [
    (('storm', 2.0, 8.0), "wave spectrum 'storm' is unknown; allowed: regular, jonswap"),
    (('regular', 2.0, 0.0), 'wave period 0.0 must be a finite number > 0'),
    (('jonswap', math.nan, 8.0), 'wave height nan must be a finite number > 0'),
])
def test_a_bad_sea_is_refused(arguments, message):
    with pytest.raises(ValueError, match=message):
        Sea.make(*arguments, 0.0, DEPTH, G)
