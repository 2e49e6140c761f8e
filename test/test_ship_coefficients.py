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
OCIMF-form wind and current loads: the formula by hand, the angle convention, the CSV files.

The hand checks use tables written here with chosen values; the shipped wind table
(config/ship/wind_coefficients_tanker_loaded.csv) is checked for its signs, its symmetry and
for being exactly the output of the script that computes it from Blendermann (1994)
(test/data/ship_coefficients/blendermann_tanker_loaded.py); the shipped current table
(config/ship/current_coefficients_tanker_loaded.csv) likewise against DNV-ST-0111 (December
2021) [3.6] (test/data/ship_coefficients/dnv_current_tanker_loaded.py), and the shipped
tables at several water depths against UFC 4-159-03's depth factor
(test/data/ship_coefficients/ufc_depth_current_tanker_loaded.py). Tables by depth are
interpolated in the water depth / draft ratio, checked by hand between two tables.
"""

import importlib.util
import math
from pathlib import Path
import warnings

import numpy as np
import pytest

from rope_sim_ros.model.ship.coefficients import (
    CoefficientFileError, CoefficientTable, flow_angle_deg, ocimf_loads,
    parse_coefficient_csv, table_at_ratio)
from rope_sim_ros.params.ship import DEFAULT_CURRENT_TABLES, read_current_tables, ShipParams

REPO = Path(__file__).resolve().parent.parent
WIND_TABLE = REPO / 'config' / 'ship' / 'wind_coefficients_tanker_loaded.csv'
WIND_SCRIPT = REPO / 'test' / 'data' / 'ship_coefficients' / 'blendermann_tanker_loaded.py'
CURRENT_TABLE = REPO / 'config' / 'ship' / 'current_coefficients_tanker_loaded.csv'
CURRENT_SCRIPT = REPO / 'test' / 'data' / 'ship_coefficients' / 'dnv_current_tanker_loaded.py'
UFC_SCRIPT = REPO / 'test' / 'data' / 'ship_coefficients' / 'ufc_current_tanker_loaded.py'
DEPTH_SCRIPT = REPO / 'test' / 'data' / 'ship_coefficients' / 'ufc_depth_current_tanker_loaded.py'

RHO_AIR = 1.225  # kg/m^3
RHO_WATER = 1026.0  # kg/m^3, the value DNV-ST-0111 uses
# A table with round numbers, so that the interpolated coefficients are easy by hand.
SQUARE = CoefficientTable(angles_deg=[0.0, 90.0, 180.0, 270.0],
                          cx=[-1.0, 0.0, 0.5, 0.0],
                          cy=[0.0, -0.8, 0.0, 0.8],
                          cmz=[0.1, 0.0, -0.1, 0.0])


def flow_from(theta_deg, speed):
    """Return the relative fluid velocity (u_x, u_y) of a flow coming from theta [deg]."""
    theta = math.radians(theta_deg)
    return np.array([-speed * math.cos(theta), -speed * math.sin(theta)])


def load_script(path):
    """Import one of the scripts under test/data/ship_coefficients/ as a module."""
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_wind_script():
    """Import the script that computes the shipped wind table."""
    return load_script(WIND_SCRIPT)


def shipped_wind_table():
    """Return the shipped wind table, read here (the model layer does no I/O)."""
    return parse_coefficient_csv(WIND_TABLE.read_text(), str(WIND_TABLE))


def shipped_current_table():
    """Return the shipped current table, read here (the model layer does no I/O)."""
    return parse_coefficient_csv(CURRENT_TABLE.read_text(), str(CURRENT_TABLE))


# ---------------------------------------------------------------------- the angle


@pytest.mark.parametrize('velocity, theta', [
    ((-1.0, 0.0), 0.0),      # flow toward -x: a head wind
    ((0.0, -1.0), 90.0),     # flow toward -y: from port
    ((1.0, 0.0), 180.0),     # from astern
    ((0.0, 1.0), -90.0),     # from starboard (= 270)
    ((-1.0, -1.0), 45.0),    # from the port bow
    ((3.0, -3.0), 135.0),    # from the port quarter
])
def test_flow_angle_is_where_the_flow_comes_from(velocity, theta):
    assert flow_angle_deg(velocity) == pytest.approx(theta, abs=1e-12)


def test_ship_moving_ahead_in_still_air_feels_a_head_wind():
    # fluid velocity 0, ship velocity (1, 0) in body axes: u = 0 - ship = (-1, 0)
    relative = np.zeros(2) - np.array([1.0, 0.0])
    assert flow_angle_deg(relative) == 0.0
    fx, fy, mz = ocimf_loads(SQUARE, RHO_AIR, relative, area_front=100.0, area_side=400.0,
                             length=50.0)
    # 1/2 rho V^2 A_T C_x(0) with V = 1 m/s: a drag toward the stern
    assert fx == pytest.approx(0.5 * 1.225 * 1.0 * 100.0 * -1.0, rel=1e-15)
    assert fx < 0.0
    assert fy == 0.0
    assert mz == pytest.approx(0.5 * 1.225 * 1.0 * 400.0 * 50.0 * 0.1, rel=1e-15)


def test_zero_relative_velocity_gives_exactly_zero_loads():
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        loads = ocimf_loads(SQUARE, RHO_AIR, (0.0, 0.0), 100.0, 400.0, 50.0)
        arrays = ocimf_loads(SQUARE, RHO_AIR, np.zeros((3, 2)), 100.0, 400.0, 50.0)
    assert loads == (0.0, 0.0, 0.0)
    for array in arrays:
        np.testing.assert_array_equal(array, np.zeros(3))
    assert flow_angle_deg((-0.0, -0.0)) == 0.0


# ---------------------------------------------------------------------- the formula


def test_loads_between_rows_by_hand():
    # theta = 45: halfway between the rows at 0 and 90 -> C = (-0.5, -0.4, 0.05)
    fx, fy, mz = ocimf_loads(SQUARE, RHO_AIR, flow_from(45.0, 10.0), area_front=100.0,
                             area_side=400.0, length=50.0)
    q = 0.5 * 1.225 * 10.0 ** 2  # 61.25 Pa
    assert fx == pytest.approx(q * 100.0 * -0.5, rel=1e-12)  # -3062.5 N
    assert fy == pytest.approx(q * 400.0 * -0.4, rel=1e-12)  # -9800 N
    assert mz == pytest.approx(q * 400.0 * 50.0 * 0.05, rel=1e-12)  # 61250 N m
    assert (fx, fy, mz) == pytest.approx((-3062.5, -9800.0, 61250.0), rel=1e-12)
    # theta = 150 (from the port quarter): 2/3 of the way from 90 to 180
    cx, cy, cmz = SQUARE.at(150.0)
    assert (cx, cy, cmz) == pytest.approx((1.0 / 3.0, -0.8 / 3.0, -0.2 / 3.0), rel=1e-12)


def test_wrap_around_between_the_last_and_the_first_row():
    table = CoefficientTable(angles_deg=[10.0, 120.0, 250.0, 350.0],
                             cx=[1.0, 2.0, 3.0, 5.0],
                             cy=[-2.0, 0.0, 0.0, 2.0],
                             cmz=[0.4, 0.0, 0.0, 0.0])
    # 0 deg is halfway between 350 (5, 2, 0) and 370 = 10 (1, -2, 0.4)
    assert table.at(0.0) == pytest.approx((3.0, 0.0, 0.2), rel=1e-12)
    # 355 = 1/4 of the way from 350 to 370; -5 and 715 are the same direction
    for theta in (355.0, -5.0, 715.0):
        assert table.at(theta) == pytest.approx((4.0, 1.0, 0.1), rel=1e-12)
    # 5 = 3/4 of the way; 365 is the same direction
    for theta in (5.0, 365.0):
        assert table.at(theta) == pytest.approx((2.0, -1.0, 0.3), rel=1e-12)
    # on a row, its own values
    assert table.at(250.0) == (3.0, 0.0, 0.0)
    # the loads follow the wrapped coefficients through the formula
    fx, fy, mz = ocimf_loads(table, 1025.0, flow_from(0.0, 2.0), 10.0, 20.0, 30.0)
    q = 0.5 * 1025.0 * 4.0
    assert (fx, fy, mz) == pytest.approx((q * 10.0 * 3.0, 0.0, q * 20.0 * 30.0 * 0.2),
                                         rel=1e-12, abs=1e-9)


def test_a_table_listing_0_and_360_closes_once():
    table = CoefficientTable(angles_deg=[0.0, 180.0, 360.0], cx=[-1.0, 1.0, -1.0],
                             cy=[0.0, 0.0, 0.0], cmz=[0.0, 0.0, 0.0])
    assert table.at(270.0)[0] == pytest.approx(0.0, abs=1e-15)
    assert table.at(90.0)[0] == pytest.approx(0.0, abs=1e-15)
    assert table.at(360.0)[0] == -1.0
    with pytest.raises(ValueError, match='same direction'):
        CoefficientTable(angles_deg=[0.0, 180.0, 360.0], cx=[-1.0, 1.0, -0.9],
                         cy=[0.0, 0.0, 0.0], cmz=[0.0, 0.0, 0.0])


def test_loads_are_vectorised_over_velocities():
    velocities = np.array([flow_from(theta, speed) for theta, speed in
                           [(0.0, 1.0), (30.0, 5.0), (200.0, 12.0), (300.0, 0.5)]])
    fx, fy, mz = ocimf_loads(SQUARE, RHO_AIR, velocities, 100.0, 400.0, 50.0)
    assert fx.shape == fy.shape == mz.shape == (4,)
    for index, velocity in enumerate(velocities):
        single = ocimf_loads(SQUARE, RHO_AIR, velocity, 100.0, 400.0, 50.0)
        assert (fx[index], fy[index], mz[index]) == pytest.approx(single, rel=1e-14)
    # loads go with the square of the speed
    doubled = ocimf_loads(SQUARE, RHO_AIR, 2.0 * velocities, 100.0, 400.0, 50.0)
    np.testing.assert_allclose(doubled[1], 4.0 * fy, rtol=1e-14)


# ---------------------------------------------------------------------- bad input


@pytest.mark.parametrize('kwargs, match', [
    (dict(angles_deg=[0.0, 90.0, 90.0], cx=[0, 0, 0], cy=[0, 0, 0], cmz=[0, 0, 0]),
     'strictly increasing'),
    (dict(angles_deg=[0.0, 200.0, 370.0], cx=[0, 0, 0], cy=[0, 0, 0], cmz=[0, 0, 0]),
     'span at most 360'),
    (dict(angles_deg=[0.0, 90.0], cx=[0, 0, 0], cy=[0, 0], cmz=[0, 0]), 'cx has 3 rows'),
    (dict(angles_deg=[0.0, 90.0], cx=[0, math.nan], cy=[0, 0], cmz=[0, 0]), 'cx must hold'),
    (dict(angles_deg=[0.0], cx=[0], cy=[0], cmz=[0]), 'at least 2 rows'),
])
def test_bad_tables_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        CoefficientTable(**kwargs)


@pytest.mark.parametrize('argument, value', [
    ('density', 0.0), ('density', -1.0), ('density', math.nan), ('area_front', 0.0),
    ('area_side', math.inf), ('length', -5.0)])
def test_bad_load_arguments_are_refused(argument, value):
    kwargs = dict(density=RHO_AIR, area_front=1.0, area_side=1.0, length=1.0)
    kwargs[argument] = value
    with pytest.raises(ValueError, match=argument):
        ocimf_loads(SQUARE, relative_velocity_body_xy=(1.0, 0.0), **kwargs)


def test_bad_velocities_are_refused():
    with pytest.raises(ValueError, match='relative_velocity_body_xy'):
        ocimf_loads(SQUARE, RHO_AIR, (math.nan, 0.0), 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match='relative_velocity_body_xy'):
        ocimf_loads(SQUARE, RHO_AIR, (1.0, 0.0, 0.0), 1.0, 1.0, 1.0)


# ---------------------------------------------------------------------- tables by depth

# a shallow table with other angles than SQUARE's (45 degrees apart)
SHALLOW = CoefficientTable(angles_deg=[0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0],
                           cx=[-1.2, -0.8, 0.0, 0.4, 0.6, 0.4, 0.0, -0.8],
                           cy=[0.0, -2.0, -3.0, -2.0, 0.0, 2.0, 3.0, 2.0],
                           cmz=[0.0, -0.4, 0.0, 0.3, 0.0, -0.3, 0.0, 0.4])


def test_coefficients_between_two_tables_by_hand():
    """Depth / draft 1.2 (SHALLOW) and 3.0 (SQUARE): at 1.65, a quarter of the way."""
    table = table_at_ratio([(1.2, SHALLOW), (3.0, SQUARE)], 1.65)
    # the union of the angles: SHALLOW's eight
    np.testing.assert_array_equal(table.angles_deg, SHALLOW.angles_deg)
    # at 90 degrees both tables have a row: 0.75 * -3.0 + 0.25 * -0.8
    assert table.at(90.0) == pytest.approx((0.0, -2.45, 0.0), abs=1e-15)
    # at 45: SHALLOW's row and SQUARE between its rows (-0.5, -0.4, 0.05)
    assert table.at(45.0) == pytest.approx(
        (0.75 * -0.8 + 0.25 * -0.5, 0.75 * -2.0 + 0.25 * -0.4, 0.75 * -0.4 + 0.25 * 0.05),
        abs=1e-15)
    # at 100: between the union's rows 90 and 135, linear in the angle as any table
    expected = [a + (b - a) * 10.0 / 45.0 for a, b in zip(table.at(90.0), table.at(135.0))]
    assert table.at(100.0) == pytest.approx(expected, abs=1e-15)
    # the loads of a beam current go with the lateral coefficient: 2.45 / 0.8 of deep water's
    deep = ocimf_loads(SQUARE, RHO_WATER, flow_from(90.0, 1.0), 100.0, 400.0, 50.0)[1]
    here = ocimf_loads(table, RHO_WATER, flow_from(90.0, 1.0), 100.0, 400.0, 50.0)[1]
    assert here / deep == pytest.approx(2.45 / 0.8, rel=1e-14)


def test_tables_by_depth_hold_their_ends_and_their_rows():
    tables = [(1.2, SHALLOW), (3.0, SQUARE)]
    assert table_at_ratio(tables, 1.0) is SHALLOW  # keel nearer the bed than the first table
    assert table_at_ratio(tables, 1.2) is SHALLOW
    assert table_at_ratio(tables, 3.0) is SQUARE
    assert table_at_ratio(tables, math.inf) is SQUARE  # deep water: the deepest table
    assert table_at_ratio([(1.0, SQUARE)], 1.1) is SQUARE  # one table: every depth
    assert table_at_ratio(tables, 1.2 + 1e-12).at(90.0)[1] == pytest.approx(-3.0, abs=1e-11)


@pytest.mark.parametrize('tables, ratio, match', [
    ([], 2.0, 'at least one'),
    ([(1.5, SQUARE), (1.2, SHALLOW)], 2.0, 'rise strictly'),
    ([(0.9, SQUARE)], 2.0, '>= 1'),
    ([(math.inf, SQUARE)], 2.0, '>= 1'),
    ([(1.5, 'table.csv')], 2.0, 'CoefficientTable'),
    ([(1.5, SQUARE)], 0.0, 'ratio 0.0'),
    ([(1.5, SQUARE)], math.nan, 'ratio nan'),
])
def test_bad_tables_by_depth_are_refused(tables, ratio, match):
    with pytest.raises(ValueError, match=match):
        table_at_ratio(tables, ratio)


def test_shipped_depth_tables_are_the_output_of_their_script():
    script = load_script(DEPTH_SCRIPT)
    assert [ratio for ratio, _ in DEFAULT_CURRENT_TABLES] == [*script.RATIOS, script.DEEP_RATIO]
    for ratio, name in DEFAULT_CURRENT_TABLES[:-1]:
        assert name == script.file_name(ratio)
        assert (REPO / 'config' / 'ship' / name).read_text() == script.csv_text(ratio)
    assert DEFAULT_CURRENT_TABLES[-1][1] == CURRENT_TABLE.name  # the deep table


def test_shipped_depth_tables_are_ufcs_factor_on_the_deep_table():
    deep = shipped_current_table()
    tables = dict(read_current_tables(ShipParams()))
    for ratio in (1.1, 1.5, 5.0):
        factor = 1.0 + (3.2 / 0.6 - 1.0) / ratio ** 2  # UFC 4-159-03 eq. 11, C0 = 0.6
        table = tables[ratio]
        np.testing.assert_array_equal(table.angles_deg, deep.angles_deg)
        np.testing.assert_allclose(table.cx, deep.cx, atol=1e-15)
        # both tables' values rounded to 6 decimals, the deep one's then scaled
        rounding = 5e-7 * (1.0 + factor)
        np.testing.assert_allclose(table.cy, factor * deep.cy, atol=rounding)
        np.testing.assert_allclose(table.cmz, factor * deep.cmz, atol=rounding)
    # a beam current on the berth's loaded Panamax (14 m draft) in 15.4 m of water: 4.58
    # times the deep-water load, as the UFC's FFG-7 of its Table 4-6 at T/d = 0.96 (3.5x)
    assert tables[1.1].at(90.0)[1] / deep.at(90.0)[1] == pytest.approx(4.581, abs=1e-3)


def test_the_shipped_set_follows_ufcs_factor_at_every_depth():
    """Linear in the ratio between the tables: within the script's MAX_SET_ERROR of UFC's."""
    script = load_script(DEPTH_SCRIPT)
    tables = read_current_tables(ShipParams())
    ratios = np.linspace(1.1, 30.0, 3000)
    lateral = np.array([-table_at_ratio(tables, ratio).at(90.0)[1] for ratio in ratios])
    ufc = 0.6 + (3.2 - 0.6) / ratios ** 2
    error = lateral / ufc - 1.0
    assert np.abs(error).max() <= script.MAX_SET_ERROR
    assert error.max() > 0.05 and error.min() < -0.04  # the bound is the measured one
    assert -table_at_ratio(tables, math.inf).at(90.0)[1] == pytest.approx(0.6, abs=1e-12)


# ---------------------------------------------------------------------- the CSV reader


GOOD_CSV = """\
# a comment
angle_deg,cx,cy,cmz
0,-1.0,0.0,0.1

90,0.0,-0.8,0.0
# a comment between rows
180,0.5,0.0,-0.1
270,0.0,0.8,0.0
"""


def test_parse_reads_rows_and_skips_comments():
    table = parse_coefficient_csv(GOOD_CSV, 'good.csv')
    np.testing.assert_array_equal(table.angles_deg, [0.0, 90.0, 180.0, 270.0])
    np.testing.assert_array_equal(table.cy, [0.0, -0.8, 0.0, 0.8])
    assert table.at(45.0) == SQUARE.at(45.0)
    # column order is free, extra columns are ignored
    shuffled = 'cmz,source,cy,cx,angle_deg\n0.1,a,0,-1,0\n0,b,-0.8,0,90\n'
    other = parse_coefficient_csv(shuffled, 'shuffled.csv')
    np.testing.assert_array_equal(other.cx, [-1.0, 0.0])
    np.testing.assert_array_equal(other.cmz, [0.1, 0.0])


@pytest.mark.parametrize('text, line, column, words', [
    ('# c\nangle_deg,cx,cmz\n0,1,2\n', 2, 'cy', 'missing column'),
    ('angle_deg,cx,cy,cmz\n0,1,2,3\n90,1,x,3\n', 3, 'cy', "'x' is not a number"),
    ('angle_deg,cx,cy,cmz\n0,1,2,3\n90,1,2,nan\n', 3, 'cmz', 'not finite'),
    ('angle_deg,cx,cy,cmz\n0,1,2,3\n\n0,1,2,3\n', 4, 'angle_deg', 'does not increase'),
    ('angle_deg,cx,cy,cmz\n0,1,2,3\n90,1,2\n', 3, 'cy', '3 fields'),
    ('angle_deg,cx,cy,cmz\n0,1,2,3\n200,1,2,3\n361,1,2,3\n', 4, 'angle_deg', 'span'),
    ('angle_deg,cx,cy,cmz\n0,1,2,3\n', 1, 'angle_deg', 'at least 2 data rows'),
    ('# only comments\n\n', 1, 'angle_deg', 'no header'),
])
def test_parse_errors_name_file_line_and_column(text, line, column, words):
    with pytest.raises(CoefficientFileError) as caught:
        parse_coefficient_csv(text, 'config/ship/bad.csv')
    message = str(caught.value)
    assert isinstance(caught.value, ValueError)
    assert message.startswith(f'config/ship/bad.csv: line {line}, column {column}: ')
    assert words in message
    assert '\n' not in message


# ---------------------------------------------------------------------- the shipped table


def test_shipped_wind_table_is_the_output_of_its_script():
    assert WIND_TABLE.read_text() == load_wind_script().csv_text()


def test_shipped_wind_table_signs():
    table = shipped_wind_table()
    # a head wind pushes the ship astern
    cx, cy, cmz = table.at(0.0)
    assert cx == pytest.approx(-0.90, abs=1e-12)  # -CD_l,AF(0) of Blendermann's tanker
    assert cy == 0.0 and cmz == 0.0
    # a beam wind from port pushes it to starboard: F_y < 0
    fx, fy, mz = ocimf_loads(table, RHO_AIR, flow_from(90.0, 20.0), area_front=1000.0,
                             area_side=5000.0, length=320.0)
    assert fy == pytest.approx(0.5 * 1.225 * 400.0 * 5000.0 * -0.70, rel=1e-12)  # CD_t 0.70
    assert fy < 0.0
    assert fx == pytest.approx(0.0, abs=1e-9) and mz == pytest.approx(0.0, abs=1e-9)
    # from starboard the other way; from astern the push is forward (CD_l,AF(180) = 0.55)
    assert table.at(270.0)[1] == pytest.approx(0.70, abs=1e-12)
    assert table.at(180.0)[0] == pytest.approx(0.55, abs=1e-12)
    # a wind from the port bow turns the bow to starboard (negative yaw moment, z up)
    assert table.at(30.0)[2] < 0.0


def test_shipped_wind_table_is_port_starboard_symmetric():
    table = shipped_wind_table()
    angles = np.arange(0.0, 360.0, 5.0)
    cx, cy, cmz = table.at(angles)
    mirror = table.at(360.0 - angles)
    np.testing.assert_allclose(mirror[0], cx, atol=1e-12)
    np.testing.assert_allclose(mirror[1], -cy, atol=1e-12)
    np.testing.assert_allclose(mirror[2], -cmz, atol=1e-12)


def test_wind_script_reproduces_blendermann_at_a_row_by_hand():
    # theta = 40 deg, the script's constants: CD_t 0.70, CD_l,AF 0.90, delta 0.40,
    # A_F/A_L = 58/320, s_L = 0, converted with cy = -CY and cmz = -CN.
    gamma = math.radians(40.0)
    den = 1.0 - 0.5 * 0.40 * (1.0 - 0.90 * (58.0 / 320.0) / 0.70) * math.sin(2 * gamma) ** 2
    cx = -0.90 * math.cos(gamma) / den
    cy = -(0.70 * math.sin(gamma) / den)
    cmz = (0.0 - 0.18 * (gamma - math.pi / 2)) * cy
    assert shipped_wind_table().at(40.0) == pytest.approx((cx, cy, cmz), abs=5e-7)
    assert (cx, cy, cmz) == pytest.approx((-0.809931, -0.528588, -0.083030), abs=5e-7)


# ---------------------------------------------------------------------- the shipped current table

# KVLCC2, full scale, loaded (Yasukawa and Yoshimura 2015, Table 1): a ship to turn the
# coefficients into loads; the table itself does not depend on it.
KVLCC2_LPP, KVLCC2_BEAM, KVLCC2_DRAFT = 320.0, 58.0, 20.8  # m


def test_shipped_current_table_is_the_output_of_its_script():
    assert CURRENT_TABLE.read_text() == load_script(CURRENT_SCRIPT).csv_text()


def test_shipped_current_table_parses_with_the_package_reader():
    table = shipped_current_table()
    np.testing.assert_array_equal(table.angles_deg, np.arange(0.0, 360.0, 10.0))
    # every value within DNV's bounds: |cx| <= 0.07, |cy| <= 0.6, |cmz| <= 0.25 * 0.6
    assert np.max(np.abs(table.cx)) == pytest.approx(0.07, abs=1e-12)
    assert np.max(np.abs(table.cy)) == pytest.approx(0.6, abs=1e-12)
    assert np.max(np.abs(table.cmz)) < 0.15


def test_shipped_current_table_is_port_starboard_symmetric():
    table = shipped_current_table()
    angles = np.arange(0.0, 360.0, 2.5)  # rows and points between them
    cx, cy, cmz = table.at(angles)
    mirror = table.at(-angles)
    np.testing.assert_allclose(mirror[0], cx, atol=1e-12)  # cx even in theta
    np.testing.assert_allclose(mirror[1], -cy, atol=1e-12)  # cy odd
    np.testing.assert_allclose(mirror[2], -cmz, atol=1e-12)  # cmz odd
    # a symmetric ship feels no side force or moment in a head or stern current
    assert table.at(0.0)[1:] == (0.0, 0.0)
    assert table.at(180.0)[1:] == (0.0, 0.0)


def test_shipped_current_table_signs():
    table = shipped_current_table()
    area_front = KVLCC2_BEAM * KVLCC2_DRAFT  # A_T = B T
    area_side = KVLCC2_LPP * KVLCC2_DRAFT  # A_L = L T
    # a current from port (theta = 90) pushes the ship to starboard: F_y < 0, with DNV's
    # coefficient 0.6 on the side area, and no moment about midship (x_L,current = 0)
    assert table.at(90.0) == pytest.approx((0.0, -0.6, 0.0), abs=1e-12)
    fx, fy, mz = ocimf_loads(table, RHO_WATER, flow_from(90.0, 1.0), area_front, area_side,
                             KVLCC2_LPP)
    assert fy == pytest.approx(-0.5 * 1026.0 * 6656.0 * 0.6, rel=1e-12)  # -2.049 MN
    assert fy < 0.0
    # from starboard the other way
    assert table.at(270.0)[1] == pytest.approx(0.6, abs=1e-12)
    # a head current pushes the ship astern, a stern current ahead (0.07 on B T)
    assert table.at(0.0)[0] == pytest.approx(-0.07, abs=1e-12)
    assert table.at(180.0)[0] == pytest.approx(0.07, abs=1e-12)
    fx, fy, mz = ocimf_loads(table, RHO_WATER, flow_from(0.0, 1.0), area_front, area_side,
                             KVLCC2_LPP)
    assert fx == pytest.approx(-0.5 * 1026.0 * 1206.4 * 0.07, rel=1e-12)  # -43.3 kN
    # a current on the port bow pushes the bow to starboard (negative yaw, z up) ...
    assert table.at(30.0)[2] < 0.0
    # ... and one on the port quarter pushes the stern to starboard (bow to port)
    assert table.at(150.0)[2] > 0.0


def test_shipped_current_table_reproduces_dnv_at_two_rows_by_hand():
    table = shipped_current_table()
    # DNV-ST-0111 [3.6] in its own frame: beta = 30 deg, clockwise, i.e. from the starboard
    # bow; dir = pi/6, lever min(0.4 (1 - 2 dir/pi), 0.25) = min(0.2667, 0.25) = 0.25.
    # For A_T = B T, A_L = L T (A_L,current = L T) and x_L,current = 0 the coefficients are
    # F_X/(q B T) = -0.07 cos 30, F_Y/(q L T) = 0.6 sin 30, M_Z/(q L T L) = 0.25 F_Y/(q L T),
    # all in axes with y to port; the project's angle is 360 - 30 = 330.
    beta = math.radians(30.0)
    expected = (-0.07 * math.cos(beta), 0.6 * math.sin(beta), 0.25 * 0.6 * math.sin(beta))
    assert expected == pytest.approx((-0.060622, 0.3, 0.075), abs=5e-7)
    assert table.at(330.0) == pytest.approx(expected, abs=5e-7)
    # beta = 240 deg (from the port quarter): dir = 2 pi - 4 pi/3 = 2 pi/3, unclipped lever
    # 0.4 (1 - 4/3) = -0.1333; project angle 360 - 240 = 120.
    beta = math.radians(240.0)
    sway = 0.6 * math.sin(beta)
    expected = (-0.07 * math.cos(beta), sway, 0.4 * (1.0 - 4.0 / 3.0) * sway)
    assert expected == pytest.approx((0.035, -0.519615, 0.069282), abs=5e-7)
    assert table.at(120.0) == pytest.approx(expected, abs=5e-7)
    # the same as loads on KVLCC2 in a 1.5 m/s current, moment about midship
    q = 0.5 * RHO_WATER * 1.5 ** 2
    fx, fy, mz = ocimf_loads(table, RHO_WATER, flow_from(120.0, 1.5),
                             KVLCC2_BEAM * KVLCC2_DRAFT, KVLCC2_LPP * KVLCC2_DRAFT,
                             KVLCC2_LPP)
    lever = -0.4 / 3.0 * KVLCC2_LPP  # -42.67 m: the force acts aft of midship
    assert fx == pytest.approx(q * KVLCC2_BEAM * KVLCC2_DRAFT * 0.035, rel=1e-5)
    assert fy == pytest.approx(q * KVLCC2_LPP * KVLCC2_DRAFT * sway, rel=1e-5)
    assert mz == pytest.approx(fy * lever, rel=1e-5)


def test_shipped_current_table_interpolation_error_is_bounded():
    # Between rows the table is linear; the formula is not, and its lever has kinks at 33.75
    # and 135 deg. The script's MAX_INTERPOLATION_ERROR states the largest departure.
    script = load_script(CURRENT_SCRIPT)
    table = shipped_current_table()
    angles = np.arange(0.0, 360.0, 0.05)
    interpolated = np.array(table.at(angles))
    exact = np.array([script.coefficients(angle) for angle in angles]).T
    error = np.max(np.abs(interpolated - exact), axis=1)
    assert error[0] < 3e-4  # cx
    assert error[1] < 2.5e-3  # cy
    assert 5.0e-3 < error[2] <= script.MAX_INTERPOLATION_ERROR  # cmz, at the 135 deg kink
    assert script.coefficients(135.0)[2] == pytest.approx(-0.2 * -0.6 * math.sin(math.radians(
        135.0)), abs=1e-12)


def test_dnv_beam_current_coefficient_agrees_with_ufc_4_159_03_for_kvlcc2():
    # Two independent sources for the sway coefficient: UFC 4-159-03 eqs. 11-13 for KVLCC2 in
    # deep water (T/d = 0: C_yc = C0 = 0.22 sqrt(chi), chi = L^2 A_m / (B V) = 6.81) give
    # 0.574; DNV-ST-0111 gives 0.6 for every monohull. They agree within 5 %.
    ufc = load_script(UFC_SCRIPT)
    c_yc = ufc.transverse_coefficient(0.0)
    assert c_yc == pytest.approx(0.5743, abs=1e-4)
    dnv = -shipped_current_table().at(90.0)[1]
    assert abs(dnv - c_yc) / c_yc < 0.05


# ---------------------------------------------------------------------- a published example


def test_ufc_4_159_03_table_4_6_transverse_current_on_ffg7():
    # UFC 4-159-03 "Design: Moorings" (US DoD, 3 October 2005), section 4-5.1, Table 4-6
    # (page 87): transverse current force on an FFG-7 for a current of 1.5 m/s on the beam,
    # for five ratios of draft to water depth T/d. The force is 1/2 rho V^2 L_wL T C_yc
    # (the OCIMF form with A_L = L_wL T) and C_yc = C0 + (C1 - C0) (T/d)^K, with C1 = 3.2 and
    # K = 2 (its equation 11). The ship's L_wL and C0 are on a page not read for this work,
    # so they are fitted to the deepest and the shallowest rows; the three rows between are
    # then predictions, and must match the published forces to their printed digits.
    published = {0.096: 0.55e6, 0.288: 0.66e6, 0.576: 1.03e6, 0.72: 1.30e6, 0.96: 1.90e6}
    deep, shallow = 0.096, 0.96
    ratio = published[shallow] / published[deep]
    c0 = 3.2 * (ratio * deep ** 2 - shallow ** 2) / ((1 - shallow ** 2) - ratio * (1 - deep ** 2))
    assert c0 == pytest.approx(0.8514, abs=1e-4)

    def c_yc(t_over_d):
        return c0 + (3.2 - c0) * t_over_d ** 2

    rho, speed = 1025.0, 1.5
    area = published[deep] / (0.5 * rho * speed ** 2 * c_yc(deep))  # L_wL T [m^2]
    # the fitted area is the FFG-7's: T = 0.096 * 45.7 m = 4.39 m, so L_wL = 124.5 m
    assert area == pytest.approx(546.3, abs=0.1)
    assert area / (0.096 * 45.7) == pytest.approx(124.5, abs=0.1)
    for t_over_d, force in published.items():
        # a current from port (theta = 90) pushes to starboard: C_y(90) = -C_yc
        table = CoefficientTable(angles_deg=[0.0, 90.0, 180.0, 270.0],
                                 cx=[0.0, 0.0, 0.0, 0.0],
                                 cy=[0.0, -c_yc(t_over_d), 0.0, c_yc(t_over_d)],
                                 cmz=[0.0, 0.0, 0.0, 0.0])
        fx, fy, mz = ocimf_loads(table, rho, flow_from(90.0, speed), area_front=area,
                                 area_side=area, length=area / 4.39)
        assert fy < 0.0
        # published to 0.01 MN
        assert -fy == pytest.approx(force, abs=0.005e6)
