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
Passing-ship loads (Wang 1975, deep and finite depth) against independent programs, physics.

test/data/passing_ship/README.md says where the stored numbers come from: no published
example could be read, so they are saved outputs of three independent legacy programs of
the same method (a workbook, a worksheet and the US Navy's DYNMOOR 6.10), in deep water and
at a finite depth with the images n = -10..10. The other checks need no data: a brute-force
double sum, the far-field dipole limit, a long direct sum of the images, the symmetries,
the signs.
"""

import csv
import math

import numpy as np
import pytest

from rope_sim_ros.model.ship.passing import Hull, passing_loads

FT = 0.3048  # m, exact (international foot)
LBF = 4.4482216152605  # N, exact (international pound-force)
SLUG_PER_FT3 = LBF / FT / FT ** 3  # kg/m^3: a slug is 1 lbf s^2 / ft

MOORED = Hull(length=300.0, beam=48.0, draft=16.0, block_coefficient=0.80)
PASSING = Hull(length=250.0, beam=40.0, draft=14.0, block_coefficient=0.75)
SPEED = 5.0
SEPARATION = 60.0  # passing ship to starboard


def read_rows(path):
    """Return the rows of a CSV with '#' comment lines as dicts of floats."""
    with open(path, newline='') as stream:
        lines = [line for line in stream if not line.startswith('#')]
    return [{key: float(value) for key, value in row.items()} for row in csv.DictReader(lines)]


def area_hull(length_ft, area_ft2, beam):
    """Return a Hull with length and midship area as given (C_b = 2/3, so S_m = B T)."""
    return Hull(length=length_ft * FT, beam=beam, draft=area_ft2 * FT ** 2 / beam,
                block_coefficient=2.0 / 3.0)


def read_text_rows(path):
    """Return the rows of a CSV with '#' comment lines as dicts of the values' text."""
    with open(path, newline='') as stream:
        lines = [line for line in stream if not line.startswith('#')]
    return list(csv.DictReader(lines))


def half_unit(text):
    """Return half a unit of the last non-zero digit of a number as written ('1683.0': 0.5)."""
    mantissa = text.lstrip('-')
    whole, _, decimals = mantissa.partition('.')
    decimals = decimals.rstrip('0')
    if decimals:
        return 0.5 * 10.0 ** -len(decimals)
    return 0.5 * 10.0 ** (len(whole) - len(whole.rstrip('0')))


# ---------------------------------------------------------------------- the hull


def test_sectional_area_curve_holds_the_displaced_volume():
    hull = MOORED
    # 3-point Gauss-Legendre is exact for the quadratic S(x)
    t, w = np.polynomial.legendre.leggauss(3)
    half = hull.length / 2.0
    volume = half * float(np.dot(w, hull.sectional_area(half * t)))
    assert volume == pytest.approx(0.80 * 300.0 * 48.0 * 16.0, rel=1e-14)
    assert hull.volume == pytest.approx(volume, rel=1e-14)
    assert float(hull.sectional_area(0.0)) == pytest.approx(1.5 * 0.80 * 48.0 * 16.0, rel=1e-15)
    np.testing.assert_array_equal(hull.sectional_area([-half, half, 1.01 * half]), 0.0)
    # the slope is the derivative of the curve (central difference, exact for a parabola)
    x = np.array([-140.0, -30.0, 0.0, 75.0])
    step = 1e-3
    difference = (hull.sectional_area(x + step) - hull.sectional_area(x - step)) / (2 * step)
    np.testing.assert_allclose(hull.sectional_area_slope(x), difference, rtol=1e-9, atol=1e-9)
    assert float(hull.sectional_area_slope(1.01 * half)) == 0.0


@pytest.mark.parametrize('field, value', [
    ('length', 0.0), ('length', -10.0), ('length', math.nan), ('length', math.inf),
    ('beam', 0.0), ('draft', -1.0), ('block_coefficient', 0.0),
    ('block_coefficient', 1.2), ('block_coefficient', math.nan), ('beam', 'wide')])
def test_hull_rejects_bad_particulars(field, value):
    particulars = dict(length=300.0, beam=48.0, draft=16.0, block_coefficient=0.8)
    particulars[field] = value
    with pytest.raises(ValueError, match=field):
        Hull(**particulars)


# ---------------------------------------------------------------------- stored values


def test_matches_the_legacy_workbook_table(reference_dir):
    rows = read_rows(reference_dir / 'passing_ship' / 'legacy_workbook_deep.csv')
    hull = area_hull(941.10892388451441, 8103.8790549803316, beam=40.0)
    stagger = np.array([row['stagger_ft'] for row in rows]) * FT
    surge, sway, yaw = passing_loads(hull, hull, 6.0 * FT, 364.04199475065616 * FT, stagger,
                                     water_density=1.9905 * SLUG_PER_FT3)
    # passing ship to starboard: body sway and yaw are minus Wang's (toward the passing ship)
    computed = {'surge_lbf': surge / LBF, 'sway_lbf': -sway / LBF,
                'yaw_ft_lbf': -yaw / (LBF * FT)}
    for column, values in computed.items():
        stored = np.array([row[column] for row in rows])
        # stored to 3 decimals or 4 significant figures: within half a unit of the last digit
        np.testing.assert_allclose(values, stored, rtol=5e-4, atol=5e-4, err_msg=column)
    # the values are not trivially small: abeam attraction 15020 lbf, yaw 701600 ft lbf
    assert computed['sway_lbf'][10] == pytest.approx(15020.0, rel=5e-4)
    assert computed['yaw_ft_lbf'][9] == pytest.approx(701600.0, rel=5e-4)


def test_matches_the_legacy_worksheet_sway(reference_dir):
    (row,) = read_rows(reference_dir / 'passing_ship' / 'legacy_worksheet_deep_sway.csv')
    moored = area_hull(row['moored_length_ft'], row['moored_midship_area_ft2'], beam=30.0)
    passing = area_hull(row['passing_length_ft'], row['passing_midship_area_ft2'], beam=40.0)
    separation = row['separation_over_moored_length'] * moored.length
    # passing ship to port: body sway is Wang's, toward the passing ship
    _, sway, _ = passing_loads(moored, passing, SPEED, -separation, row['stagger_ft'] * FT)
    scale = 1025.0 * SPEED ** 2 * moored.midship_area * passing.midship_area / moored.length ** 2
    # the worksheet's own integrator: 1e-6 (the module agrees to 1.0e-7)
    assert sway / scale == pytest.approx(row['sway_nondimensional'], rel=1e-6)


# ---------------------------------------------------------------------- at a finite depth

# the worksheet's case (test/data/passing_ship/legacy_worksheet_depth_47ft.csv); the beams
# are free (only L and S_m = B T count): wide enough for drafts under the depth
WORKSHEET_MOORED = area_hull(658.0, 3936.299, beam=30.0)
WORKSHEET_PASSING = area_hull(902.2, 7099.888, beam=60.0)
WORKSHEET = dict(moored=WORKSHEET_MOORED, passing=WORKSHEET_PASSING, speed=5.0 * FT,
                 separation=-221.8 * FT, depth=47.0 * FT, water_density=1.9905 * SLUG_PER_FT3)
# the workbook's: two equal hulls, 55 ft of water
WORKBOOK_HULL = area_hull(941.10892388451441, 8103.8790549803316, beam=60.0)
WORKBOOK = dict(moored=WORKBOOK_HULL, passing=WORKBOOK_HULL, speed=6.0 * FT,
                separation=364.04199475065616 * FT, depth=55.0 * FT,
                water_density=1.9905 * SLUG_PER_FT3)
# DYNMOOR's: a 600 ft barge, a 650 ft ship passing at 5.5 kn through the water, 50 ft of water
DYNMOOR_SPEED = 6.0 * 1.6888 - 0.5 * 1.6889  # [ft/s] 6 kn over the ground, 0.5 kn of current
DYNMOOR = dict(moored=area_hull(600.0, 3000.0, beam=100.0 * FT),
               passing=area_hull(650.0, 3200.0, beam=100.0 * FT), speed=DYNMOOR_SPEED * FT,
               separation=-300.0 * FT, depth=50.0 * FT, water_density=1.9905 * SLUG_PER_FT3)
DYNMOOR_PI = 3.1415279  # PARSHIP divides by this value of pi (sic)


def wang_frame(loads, separation):
    """Return body-axes loads in Wang's frame: sway and yaw toward the passing ship."""
    surge, sway, yaw = (np.asarray(load) for load in loads)
    toward = -math.copysign(1.0, separation)  # body y of the passing ship's side
    return surge, toward * sway, toward * yaw


def test_matches_the_legacy_worksheet_depth_sweep(reference_dir):
    rows = read_rows(reference_dir / 'passing_ship' / 'legacy_worksheet_depth_47ft.csv')
    stagger = np.array([row['stagger_ft'] for row in rows]) * FT
    surge, sway, yaw = wang_frame(passing_loads(stagger=stagger, image_pairs=10, **WORKSHEET),
                                  WORKSHEET['separation'])
    computed = {'surge_lbf': surge / LBF, 'sway_lbf': sway / LBF,
                'yaw_ft_lbf': yaw / (LBF * FT)}
    for column, values in computed.items():
        stored = np.array([row[column] for row in rows])
        peak = np.abs(stored).max()
        # the worksheet's own integrator; measured 8e-12 (sway) to 9e-11 (surge) of the peak
        assert np.abs(values - stored).max() < 1e-6 * peak, column
    assert computed['sway_lbf'][10] == pytest.approx(48031.032627547444, rel=1e-9)


def test_matches_the_legacy_workbook_depth_columns(reference_dir):
    rows = read_text_rows(reference_dir / 'passing_ship' / 'legacy_workbook_depth_55ft.csv')
    stagger = np.array([float(row['stagger_ft']) for row in rows]) * FT
    surge, sway, yaw = wang_frame(passing_loads(stagger=stagger, image_pairs=10, **WORKBOOK),
                                  WORKBOOK['separation'])
    computed = {'surge_lbf': surge / LBF, 'sway_lbf': sway / LBF,
                'yaw_ft_lbf': yaw / (LBF * FT)}
    for column, values in computed.items():
        stored = [row[column] for row in rows]
        peak = max(abs(float(text)) for text in stored)
        for value, text in zip(values, stored):
            if float(text) == 0.0:  # zero by symmetry, stored as such
                assert abs(value) < 1e-9 * peak, (column, text, value)
            else:  # within half a unit of the last digit stored
                assert abs(value - float(text)) <= half_unit(text), (column, text, value)


def test_matches_dynmoor_passing_a_barge_in_50_ft_of_water(reference_dir):
    rows = read_rows(reference_dir / 'passing_ship' / 'legacy_dynmoor_parallel_50ft.csv')
    length, ground = 600.0, 6.0 * 1.6888  # [ft], [ft/s]
    # x = DIR ((i - 10) SOG - 2 L), DIR = -1: the printed x / L, to its 3 decimals
    stagger = np.array([2.0 * length - (row['step'] - 10.0) * ground for row in rows])
    np.testing.assert_allclose(stagger / length, [row['x_over_l'] for row in rows],
                               atol=5e-4)
    loads = wang_frame(passing_loads(stagger=stagger * FT, image_pairs=10, **DYNMOOR),
                       DYNMOOR['separation'])
    typo = math.pi / DYNMOOR_PI
    units = (1e3 * LBF, 1e3 * LBF, 1e3 * LBF * FT)  # kips, kip ft
    for column, values, unit in zip(('surge_kips', 'sway_kips', 'yaw_kip_ft'), loads, units):
        stored = np.array([row[column] for row in rows])
        # printed with one decimal from single precision: half its unit, and 1e-5 of the
        # value for its REAL*4 sums (measured: 0.0499, 0.04995 and 0.0447 at most)
        error = np.abs(typo * values / unit - stored)
        assert (error <= 0.05 + 1e-5 * np.abs(stored)).all(), (column, error)


def direct_sum(case, stagger, pairs):
    """Return the loads of a case summed over the images -pairs..pairs, as (3, n)."""
    return np.array(passing_loads(stagger=stagger, image_pairs=pairs, **case))


@pytest.mark.parametrize('case, legacy_low', [(WORKSHEET, 0.0064), (WORKBOOK, 0.0122),
                                              (DYNMOOR, 0.0067)])
def test_the_converged_sum_and_the_legacy_truncation(case, legacy_low):
    """The direct sum converges as N^-4 to the default; n = -10..10 is 0.6-1.2 % low abeam."""
    abeam = np.array([0.0])
    converged = np.array(passing_loads(stagger=abeam, **case))[1, 0]
    errors = [abs(direct_sum(case, abeam, pairs)[1, 0] / converged - 1.0)
              for pairs in (10, 20, 40, 80, 160, 20000)]
    # the legacy truncation: the abeam sway 0.64 %, 1.22 % and 0.67 % low
    assert errors[0] == pytest.approx(legacy_low, abs=0.0005)
    # each doubling divides the error by 11 to 19: the n^-5 terms' tail, N^-4
    ratios = np.array(errors[:4]) / np.array(errors[1:5])
    assert (ratios > 10.0).all() and (ratios[1:] > 13.0).all(), ratios
    # 20 000 pairs (images 570 to 670 km off): measured 3e-8 to 5e-8 from the default
    assert errors[4] < 5e-7 and errors[5] < 1e-7


# the berth's: config/berth.yaml's ship, the default passing ship, 16 m of water
BERTH_SHIP = Hull(225.0, 32.2, 14.0, 0.85)
BERTH_PASSER = Hull(200.0, 32.0, 12.0, 0.8)


@pytest.mark.parametrize('separation', [40.0, 70.0, -150.0])
def test_the_converged_sum_agrees_with_a_long_direct_sum(separation):
    """From abeam to 13 ship lengths off, within 1e-5 of each load (its peak where zero)."""
    stagger = np.array([0.0, 37.0, 112.5, 300.0, 600.0, -1000.0, 3000.0])
    case = dict(moored=BERTH_SHIP, passing=BERTH_PASSER, speed=3.0, separation=separation,
                depth=16.0)
    converged = np.array(passing_loads(stagger=stagger, **case))
    reference = direct_sum(case, stagger, 20000)  # images 640 km off
    peak = np.abs(reference).max(axis=1, keepdims=True)
    error = np.abs(converged - reference) / np.maximum(np.abs(reference), 1e-3 * peak)
    # measured 1.7e-6 at most (surge 300 m ahead, 150 m off, near its sign change)
    assert error.max() < 1e-5, error


def test_deep_water_is_recovered_as_the_depth_grows():
    stagger = np.array([-400.0, -90.0, 0.0, 60.0, 333.0])
    deep = loads(stagger)
    peak = np.abs(deep).max(axis=1, keepdims=True)
    departures = [np.abs(loads(stagger, depth=depth) - deep).max() / peak.min()
                  for depth in (60.0, 120.0, 240.0, 480.0, 1e5)]
    assert all(b < a for a, b in zip(departures, departures[1:])), departures
    assert departures[0] > 0.05 and departures[-1] < 1e-9


def test_the_loads_grow_as_the_keel_nears_the_bed():
    """Abeam sway and the peaks over a passage, for the berth's ships, rise as depth falls."""
    stagger = np.linspace(-600.0, 600.0, 241)
    case = dict(moored=BERTH_SHIP, passing=BERTH_PASSER, speed=3.0, separation=70.0,
                stagger=stagger)
    deep = np.abs(passing_loads(**case)).max(axis=1)
    factors = [np.abs(passing_loads(depth=depth, **case)).max(axis=1) / deep
               for depth in (42.0, 21.0, 16.0)]
    for shallower, deeper in zip(factors[1:], factors):
        assert (shallower > deeper).all()
    # at 16 m (depth / draft 1.14): surge 5.6, sway 4.1, yaw 3.7 times the deep peaks
    np.testing.assert_allclose(factors[-1], [5.56, 4.06, 3.71], rtol=0.01)


def test_at_a_finite_depth_the_symmetries_and_speed_squared_hold():
    stagger = np.linspace(25.0, 1200.0, 24)
    ahead, astern = loads(stagger, depth=20.0), loads(-stagger, depth=20.0)
    peak = np.abs(ahead).max(axis=1)
    np.testing.assert_allclose(astern[0], -ahead[0], rtol=0.0, atol=1e-12 * peak[0])
    np.testing.assert_allclose(astern[1], ahead[1], rtol=0.0, atol=1e-12 * peak[1])
    np.testing.assert_allclose(astern[2], -ahead[2], rtol=0.0, atol=1e-12 * peak[2])
    surge, sway, yaw = loads(0.0, depth=20.0)
    assert abs(surge) < 1e-12 * peak[0] and abs(yaw) < 1e-12 * peak[2] and sway < -1e6
    np.testing.assert_allclose(loads(stagger, depth=20.0, speed=2.5 * SPEED), 6.25 * ahead,
                               rtol=1e-13, atol=1e-13 * peak.max())
    np.testing.assert_allclose(loads(stagger, depth=20.0, water_density=1000.0),
                               ahead * 1000.0 / 1025.0, rtol=1e-13, atol=1e-13 * peak.max())
    port = loads(stagger, depth=20.0, separation=-SEPARATION)
    np.testing.assert_array_equal(port, ahead * np.array([[1.0], [-1.0], [-1.0]]))
    np.testing.assert_array_equal(loads(stagger, depth=20.0, direction=-1), ahead)


# ---------------------------------------------------------------------- numerics


def wang_by_brute_force(moored, passing, speed, separation, stagger, density=1025.0):
    """
    Wang's loads in body axes, the double integrals by a plain double Gauss-Legendre sum.

    Written out again from the formulas (no closed form, no change of variable): panels no
    wider than eta / 2, 8 nodes each, on both ships.
    """
    eta = abs(separation)
    t, w = np.polynomial.legendre.leggauss(8)

    def nodes(hull):
        panels = max(40, int(math.ceil(2.0 * hull.length / eta)))
        edges = np.linspace(-hull.length / 2.0, hull.length / 2.0, panels + 1)
        half = 0.5 * np.diff(edges)[:, None]
        middle = 0.5 * (edges[1:] + edges[:-1])[:, None]
        return (middle + half * t).ravel(), (half * w).ravel()

    x1, w1 = nodes(moored)
    x2, w2 = nodes(passing)
    slope1 = w1 * moored.sectional_area_slope(x1)
    yaw1 = w1 * (x1 * moored.sectional_area_slope(x1) + moored.sectional_area(x1))
    slope2 = w2 * passing.sectional_area_slope(x2)
    toward = -math.copysign(1.0, separation)  # body y of the passing ship's side
    result = []
    for xi in stagger:
        r = x2[None, :] - x1[:, None] + xi
        kernel = (r * r + eta * eta) ** -1.5
        result.append((slope1 @ (r * kernel) @ slope2 / (2.0 * math.pi),
                       toward * eta / math.pi * (slope1 @ kernel @ slope2),
                       toward * eta / math.pi * (yaw1 @ kernel @ slope2)))
    return density * speed ** 2 * np.array(result).T


STAGGERS = np.array([-700.0, -275.0, -137.5, -40.0, 0.0, 12.5, 125.0, 150.0, 275.0, 900.0])


@pytest.mark.parametrize('separation', [45.0, -120.0, 150.0, 600.0])
def test_agrees_with_a_brute_force_double_sum(separation):
    computed = np.array(passing_loads(MOORED, PASSING, SPEED, separation, STAGGERS))
    reference = wang_by_brute_force(MOORED, PASSING, SPEED, separation, STAGGERS)
    peak = np.abs(reference).max(axis=1)
    # measured 7e-16 to 4e-14 of the peak; 1e-10 leaves room for the brute force's own error
    assert (np.abs(computed - reference).max(axis=1) / peak).max() < 1e-10


@pytest.mark.parametrize('separation', [44.0, 60.0, 100.0, 300.0])
def test_quadrature_converges(separation):
    stagger = np.linspace(-2.0, 2.0, 41) * MOORED.length + 3.7  # off the panel breakpoints
    default = np.array(passing_loads(MOORED, PASSING, SPEED, separation, stagger))
    fine = np.array(passing_loads(MOORED, PASSING, SPEED, separation, stagger, nodes=64))
    coarse = np.array(passing_loads(MOORED, PASSING, SPEED, separation, stagger, nodes=4))
    peak = np.abs(fine).max(axis=1)
    error = (np.abs(default - fine).max(axis=1) / peak).max()
    # measured 7e-16 to 8e-15 (eta / L = 0.15 to 1)
    assert error < 1e-10
    # converging, not stuck: 4 nodes a panel are off by 8e-5 to 8e-4
    assert (np.abs(coarse - fine).max(axis=1) / peak).max() > 10.0 * error


def test_quadrature_converges_where_the_kernel_is_sharpest():
    """At eta / L = 0.02 (closer than real hulls allow) the sinh map still converges."""
    thin = Hull(length=300.0, beam=6.0, draft=16.0, block_coefficient=0.8)
    stagger = np.linspace(-1.5, 1.5, 31) * thin.length + 3.7
    default = np.array(passing_loads(thin, thin, SPEED, 6.0, stagger))
    fine = np.array(passing_loads(thin, thin, SPEED, 6.0, stagger, nodes=64))
    peak = np.abs(fine).max(axis=1)
    assert (np.abs(default - fine).max(axis=1) / peak).max() < 1e-10  # measured 5e-12


def kernel_derivatives(xi, eta):
    """K_x'' and K_x of K_x = R s^-3/2, K_y to K_y of K_y = s^-3/2, s = R^2 + eta^2."""
    s = xi * xi + eta * eta
    kx2 = -9.0 * xi * s ** -2.5 + 15.0 * xi ** 3 * s ** -3.5
    kx4 = 225.0 * xi * s ** -3.5 - 1050.0 * xi ** 3 * s ** -4.5 + 945.0 * xi ** 5 * s ** -5.5
    ky2 = -3.0 * s ** -2.5 + 15.0 * xi ** 2 * s ** -3.5
    ky3 = 45.0 * xi * s ** -3.5 - 105.0 * xi ** 3 * s ** -4.5
    ky4 = 45.0 * s ** -3.5 - 630.0 * xi ** 2 * s ** -4.5 + 945.0 * xi ** 4 * s ** -5.5
    return kx2, kx4, ky2, ky3, ky4


def test_kernel_derivatives_are_right():
    xi, eta, step = 173.0, 60.0, 0.25

    def kx(r):
        return r * (r * r + eta * eta) ** -1.5

    def ky(r):
        return (r * r + eta * eta) ** -1.5

    def difference(function, order):
        return sum((-1) ** k * math.comb(order, k) * function(xi + (order / 2 - k) * step)
                   for k in range(order + 1)) / step ** order

    kx2, kx4, ky2, ky3, ky4 = kernel_derivatives(xi, eta)
    for exact, function, order in [(kx2, kx, 2), (kx4, kx, 4), (ky2, ky, 2), (ky3, ky, 3),
                                   (ky4, ky, 4)]:
        assert difference(function, order) == pytest.approx(exact, rel=1e-4)


def test_far_field_is_two_dipoles():
    """Far off, each ship is a dipole of its displaced volume; the error falls as xi^-4."""
    eta = SEPARATION
    dynamic = 1025.0 * SPEED ** 2
    v1, v2 = MOORED.volume, PASSING.volume
    spread = (MOORED.length ** 2 + PASSING.length ** 2) / 40.0
    errors = []
    for xi in (10.0 * MOORED.length, 20.0 * MOORED.length):
        kx2, kx4, ky2, ky3, ky4 = kernel_derivatives(xi, eta)
        surge = dynamic / (2.0 * math.pi) * -v1 * v2 * (kx2 + spread * kx4)
        # passing ship to starboard: body sway and yaw are minus Wang's
        sway = -dynamic * eta / math.pi * -v1 * v2 * (ky2 + spread * ky4)
        yaw = -dynamic * eta / math.pi * v2 * MOORED.midship_area * MOORED.length ** 3 / 30.0 \
            * ky3
        computed = passing_loads(MOORED, PASSING, SPEED, SEPARATION, xi)
        errors.append([abs(c / e - 1.0) for c, e in zip(computed, (surge, sway, yaw))])
    near, far = np.array(errors)
    # measured at 20 L: 4.0e-6, 8.0e-6 and 3.7e-3 (the yaw term is one order shorter)
    assert far[:2].max() < 2e-5 and far[2] < 5e-3
    # doubling the distance divides the error by 2^4 (surge, sway) and 2^2 (yaw)
    np.testing.assert_allclose(near / far, [16.0, 16.0, 4.0], rtol=0.1)


# ---------------------------------------------------------------------- symmetry and physics


def loads(stagger, **overrides):
    """Return the loads for the standard pair as three arrays."""
    arguments = dict(moored=MOORED, passing=PASSING, speed=SPEED, separation=SEPARATION,
                     stagger=stagger)
    arguments.update(overrides)
    return np.array(passing_loads(**arguments))


def test_sway_is_even_and_surge_and_yaw_odd_in_stagger():
    stagger = np.linspace(25.0, 1200.0, 48)
    ahead, astern = loads(stagger), loads(-stagger)
    peak = np.abs(ahead).max(axis=1)
    np.testing.assert_allclose(astern[0], -ahead[0], rtol=0.0, atol=1e-12 * peak[0])
    np.testing.assert_allclose(astern[1], ahead[1], rtol=0.0, atol=1e-12 * peak[1])
    np.testing.assert_allclose(astern[2], -ahead[2], rtol=0.0, atol=1e-12 * peak[2])
    surge, sway, yaw = loads(0.0)
    assert abs(surge) < 1e-12 * peak[0] and abs(yaw) < 1e-12 * peak[2]
    assert abs(sway) > 1e5  # 1.5 MN of suction


def test_loads_scale_with_speed_squared_and_density():
    stagger = np.array([-400.0, -90.0, 0.0, 60.0, 333.0])
    base = loads(stagger)
    np.testing.assert_allclose(loads(stagger, speed=2.5 * SPEED), 6.25 * base, rtol=1e-13,
                               atol=1e-13 * np.abs(base).max())
    np.testing.assert_allclose(loads(stagger, water_density=1000.0), base * 1000.0 / 1025.0,
                               rtol=1e-13, atol=1e-13 * np.abs(base).max())


def test_a_ship_on_the_other_side_mirrors_sway_and_yaw():
    stagger = np.array([-500.0, -150.0, 0.0, 80.0, 260.0])
    starboard = loads(stagger)
    port = loads(stagger, separation=-SEPARATION)
    np.testing.assert_array_equal(port[0], starboard[0])
    np.testing.assert_array_equal(port[1], -starboard[1])
    np.testing.assert_array_equal(port[2], -starboard[2])


def test_passing_direction_only_reverses_the_order():
    """Mirroring x maps (direction +1, stagger xi) to (-1, -xi) with surge and yaw reversed."""
    stagger = np.array([-450.0, -120.0, 35.0, 210.0])
    ahead = loads(stagger)
    reverse = loads(-stagger, direction=-1)
    scale = np.abs(ahead).max(axis=1, keepdims=True)
    np.testing.assert_allclose(reverse * np.array([[-1.0], [1.0], [-1.0]]), ahead, rtol=0.0,
                               atol=1e-12 * scale.max())
    # the pressure goes with the velocity squared: same loads at the same stagger
    np.testing.assert_array_equal(loads(stagger, direction=-1), ahead)


def test_abeam_the_moored_ship_is_drawn_toward_the_passing_ship():
    _, sway_starboard, _ = passing_loads(MOORED, PASSING, SPEED, SEPARATION, 0.0)
    _, sway_port, _ = passing_loads(MOORED, PASSING, SPEED, -SEPARATION, 0.0)
    assert sway_starboard < -1e6  # toward -y, the starboard side where the passing ship is
    assert sway_port > 1e6
    # a ship length off, the same formulas push it away (sway reverses sign)
    _, sway_off, _ = passing_loads(MOORED, PASSING, SPEED, SEPARATION, MOORED.length)
    assert sway_off > 0.0


def test_surge_and_yaw_follow_the_low_pressure_alongside_the_passing_midship():
    # passing midship a quarter length ahead: the moored bow is in its low pressure
    surge, _, yaw = passing_loads(MOORED, PASSING, SPEED, SEPARATION, 0.25 * MOORED.length)
    assert surge > 1e5  # drawn forward
    assert yaw < -1e7  # bow drawn to starboard, toward the passing ship
    surge, _, yaw = passing_loads(MOORED, PASSING, SPEED, SEPARATION, -0.25 * MOORED.length)
    assert surge < -1e5 and yaw > 1e7


def test_loads_fall_off_with_separation():
    stagger = np.linspace(-2.0, 2.0, 401) * MOORED.length
    peaks = [np.abs(loads(stagger, separation=s)).max(axis=1) for s in (50.0, 80.0, 150.0, 400.0)]
    for closer, farther in zip(peaks, peaks[1:]):
        assert (farther < 0.8 * closer).all()


def test_array_of_staggers_matches_single_calls():
    stagger = np.array([[-300.0, -10.0, 0.0], [45.0, 150.0, 700.0]])
    surge, sway, yaw = passing_loads(MOORED, PASSING, SPEED, SEPARATION, stagger)
    assert surge.shape == sway.shape == yaw.shape == (2, 3)
    for index in np.ndindex(stagger.shape):
        single = passing_loads(MOORED, PASSING, SPEED, SEPARATION, float(stagger[index]))
        assert all(isinstance(value, float) for value in single)
        assert single == pytest.approx((surge[index], sway[index], yaw[index]), rel=1e-13,
                                       abs=1e-6)


# ---------------------------------------------------------------------- bad input


@pytest.mark.parametrize('argument, value', [
    ('speed', 0.0), ('speed', -3.0), ('speed', math.nan),
    ('separation', 40.0), ('separation', -43.9), ('separation', math.inf),
    ('separation', math.nan), ('stagger', math.nan), ('stagger', np.array([0.0, math.inf])),
    ('depth', 16.0), ('depth', 10.0), ('depth', 0.0), ('depth', math.nan),
    ('depth', -math.inf), ('image_pairs', -1), ('image_pairs', 2.5), ('image_pairs', True),
    ('water_density', 0.0), ('direction', 0), ('direction', 2), ('nodes', 1),
    ('nodes', 8.0), ('moored', 'tanker'), ('separation', None), ('depth', 'deep'),
    ('stagger', 'abeam')])
def test_bad_arguments_are_named(argument, value):
    arguments = dict(moored=MOORED, passing=PASSING, speed=SPEED, separation=SEPARATION,
                     stagger=0.0)
    arguments[argument] = value
    with pytest.raises(ValueError, match=argument):
        passing_loads(**arguments)
