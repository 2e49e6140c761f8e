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

"""Elastic catenary and lumped-chain statics against test/data (MoorPy, MoorDyn)."""

import csv
import math
from pathlib import Path
import time

import numpy as np
import pytest
from rope_sim_ros.model.statics.catenary import (
    catenary_points, catenary_profile, CatenaryError, chain_equilibrium, initial_shape,
    loaded_chain_equilibrium, node_weights, seabed_profile, solve_catenary,
    solve_seabed_catenary, wetted_fraction)

# The base case of test/data/README.md.
END_A = np.zeros(3)
END_B = np.array([36.0, 0.0, 8.0])
LENGTH = 40.0
GRAVITY = np.array([0.0, 0.0, -9.81])
EA = {'polyester': 5e7, 'wire': 1e8}
W_POLYESTER = 25.467341


# Read at collection time (parametrize), so the conftest fixture cannot serve them.
REFERENCE_DIR = Path(__file__).resolve().parent / 'data'


def _rows(name: str) -> list:
    with open(REFERENCE_DIR / name, newline='') as stream:
        return list(csv.DictReader(stream))


def _relative(got: float, want: float) -> float:
    return abs(got - want) / abs(want)


def _rotation(axis, angle: float) -> np.ndarray:
    """Return the rotation matrix about axis by angle (Rodrigues)."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * cross + (1.0 - math.cos(angle)) * cross @ cross


def _material_weight(material: str) -> float:
    row = next(r for r in _rows('moordyn_static.csv') if r['material'] == material)
    return float(row['w_N_per_m'])


# ------------------------------------------------------------------------ solve_catenary


@pytest.mark.parametrize('row', _rows('catenary_vs_moorpy.csv'), ids=lambda row: row['case'])
def test_solve_catenary_matches_reference(row):
    solution = solve_catenary(float(row['h_m']), float(row['v_m']), float(row['L0_m']),
                              float(row['w_N_per_m']), float(row['EA_N']))
    got = {
        'H_N': solution.horizontal_tension,
        'V_A_N': solution.vertical_a,
        'V_B_N': solution.vertical_b,
        'T_A_N': solution.tension_a,
        'T_B_N': solution.tension_b,
    }
    for key, value in got.items():
        assert _relative(value, float(row[key])) < 1e-6, (key, value, row[key])


def test_vertical_hang_is_symmetric_and_stretched():
    w, ea = W_POLYESTER, 1e5
    solution = solve_catenary(0.0, 0.0, LENGTH, w, ea)
    # Both halves hang straight down, each carrying its own weight.
    assert solution.horizontal_tension < 1e-9 * w * LENGTH
    assert _relative(solution.vertical_b, 0.5 * w * LENGTH) < 1e-12
    assert _relative(solution.vertical_a, -0.5 * w * LENGTH) < 1e-12
    x, z = catenary_profile(solution, LENGTH, w, ea, [0.5 * LENGTH, LENGTH])
    # A hanging half of length l stretches by w l^2 / (2 EA) under its own weight.
    half = 0.5 * LENGTH
    assert z[0] == pytest.approx(-(half + w * half ** 2 / (2 * ea)), abs=1e-9)
    assert abs(z[1]) < 1e-9 and abs(x[1]) < 1e-7


def test_taut_vertical_line_carries_stretch_and_weight():
    w, ea, rise = W_POLYESTER, 1e6, 1.01 * LENGTH
    solution = solve_catenary(0.0, rise, LENGTH, w, ea)
    # Straight up: rise = L + (V_A L + w L^2 / 2) / EA, and V_A > 0 pulls A up.
    v_a = ea * (rise - LENGTH) / LENGTH - 0.5 * w * LENGTH
    assert _relative(solution.vertical_a, v_a) < 1e-9
    assert _relative(solution.vertical_b, v_a + w * LENGTH) < 1e-9


def test_b_below_a_mirrors_b_above_a():
    up = solve_catenary(30.0, 12.0, LENGTH, W_POLYESTER, 5e7)
    down = solve_catenary(30.0, -12.0, LENGTH, W_POLYESTER, 5e7)
    assert _relative(down.horizontal_tension, up.horizontal_tension) < 1e-10
    assert _relative(down.vertical_a, -up.vertical_b) < 1e-10
    assert _relative(down.tension_b, up.tension_a) < 1e-10


@pytest.mark.parametrize('span, rise', [
    (0.0, 40.0), (1e-6, 40.0), (1e-6, -39.99), (39.999, 0.0), (200.0, 60.0), (0.4, -60.0)])
@pytest.mark.parametrize('w, ea', [(0.01, 5e7), (25.0, 1e2), (1e4, 1e12)])
def test_solve_catenary_closes_on_hard_geometries(span, rise, w, ea):
    solution = solve_catenary(span, rise, LENGTH, w, ea)
    x, z = catenary_profile(solution, LENGTH, w, ea, [LENGTH])
    assert abs(x[0] - max(span, 1e-9 * LENGTH)) < 1e-10 * LENGTH
    assert abs(z[0] - rise) < 1e-10 * max(LENGTH, abs(rise))


# ---------------------------------------------------------------------- catenary_profile


@pytest.mark.parametrize('material', ['polyester', 'wire'])
def test_profile_matches_reference_shape(material):
    rows = _rows(f'catenary_{material}_shape.csv')
    w, ea = _material_weight(material), EA[material]
    solution = solve_catenary(36.0, 8.0, LENGTH, w, ea)
    s = np.array([float(r['s_m']) for r in rows])
    x, z = catenary_profile(solution, LENGTH, w, ea, s)
    assert np.max(np.abs(x - [float(r['x_m']) for r in rows])) < 1e-6
    assert np.max(np.abs(z - [float(r['z_m']) for r in rows])) < 1e-6
    assert _relative(solution.tension_a, float(rows[0]['T_N'])) < 1e-6
    assert _relative(solution.tension_b, float(rows[-1]['T_N'])) < 1e-6


# --------------------------------------------------------------------- chain_equilibrium


@pytest.mark.parametrize('row', _rows('moordyn_static.csv'),
                         ids=lambda row: f"{row['material']}-N{row['N']}")
def test_chain_matches_moordyn_static_disc(row):
    chain = chain_equilibrium(END_A, END_B, LENGTH, int(row['N']), float(row['w_N_per_m']),
                              EA[row['material']], GRAVITY)
    got = {
        'disc_F_A_N': np.linalg.norm(chain.force_a),
        'disc_F_B_N': np.linalg.norm(chain.force_b),
        'disc_Tseg_A_N': chain.segment_tension[0],
        'disc_Tseg_B_N': chain.segment_tension[-1],
        'disc_H_N': chain.force_a[0],
    }
    for key, value in got.items():
        assert _relative(value, float(row[key])) < 1e-6, (key, value, row[key])
    assert chain.horizontal_tension == pytest.approx(-chain.force_b[0], rel=1e-12)


@pytest.mark.parametrize('end_b, segments', [
    ((36.0, 0.0, 8.0), 20), ((20.0, 5.0, -15.0), 7), ((41.0, 0.0, 2.0), 50),
    ((5.0, 0.0, 0.0), 40)])
def test_chain_nodes_are_in_equilibrium(end_b, segments):
    w, ea = W_POLYESTER, 5e4
    chain = chain_equilibrium(END_A, end_b, LENGTH, segments, w, ea, GRAVITY)
    p = chain.positions
    assert p.shape == (segments + 1, 3)
    np.testing.assert_allclose(p[0], END_A, atol=1e-12)
    np.testing.assert_allclose(p[-1], end_b, atol=1e-9)
    # Spring forces from the positions alone: T = EA (l / l0 - 1) along each segment.
    l0 = LENGTH / segments
    delta = np.diff(p, axis=0)
    lengths = np.linalg.norm(delta, axis=1)
    tension = ea * (lengths / l0 - 1.0)
    np.testing.assert_allclose(tension, chain.segment_tension, rtol=1e-6)
    pull = tension[:, None] * delta / lengths[:, None]  # on each segment's first node
    net = pull[1:] - pull[:-1] + w * l0 * GRAVITY / 9.81
    assert np.max(np.abs(net)) < 1e-6 * np.max(tension)
    # The end forces: the end segment's pull plus the half segment's weight.
    half_weight = 0.5 * w * l0 * GRAVITY / 9.81
    np.testing.assert_allclose(chain.force_a, pull[0] + half_weight, atol=1e-6 * tension[0])
    np.testing.assert_allclose(chain.force_b, -pull[-1] + half_weight,
                               atol=1e-6 * tension[-1])


def test_chain_converges_to_catenary_end_tension():
    w, ea = _material_weight('polyester'), EA['polyester']
    exact = solve_catenary(36.0, 8.0, LENGTH, w, ea)
    errors = [abs(np.linalg.norm(chain_equilibrium(END_A, END_B, LENGTH, n, w, ea,
                                                   GRAVITY).force_b) - exact.tension_b)
              for n in (20, 40)]
    # Second order in N: halving the segment length quarters the error.
    assert errors[1] == pytest.approx(errors[0] / 4.0, rel=0.05)


def test_chain_weightless_is_straight():
    chord = np.array([30.0, 20.0, 0.0])
    taut = chain_equilibrium(END_A, chord * 1.5, LENGTH, 10, W_POLYESTER, 1e6, np.zeros(3))
    stretch = 1e6 * (np.linalg.norm(chord * 1.5) / LENGTH - 1.0)
    np.testing.assert_allclose(taut.segment_tension, stretch, rtol=1e-12)
    np.testing.assert_allclose(taut.force_a, stretch * chord / np.linalg.norm(chord),
                               rtol=1e-12)
    np.testing.assert_allclose(taut.force_b, -taut.force_a, rtol=1e-12)
    slack = chain_equilibrium(END_A, chord, LENGTH, 10, W_POLYESTER, 1e6, np.zeros(3))
    np.testing.assert_array_equal(slack.segment_tension, 0.0)
    np.testing.assert_allclose(np.diff(slack.positions, axis=0), np.tile(chord / 10, (10, 1)))


# -------------------------------------------------------------------------------- 3-D


def test_catenary_points_rotated_match_planar():
    w, ea = W_POLYESTER, EA['polyester']
    s = np.linspace(0.0, LENGTH, 41)
    planar = catenary_points(END_A, END_B, LENGTH, w, ea, GRAVITY, s)
    rotation = _rotation((1.0, -2.0, 0.5), 0.7)
    offset = np.array([100.0, -50.0, 3.0])
    a, b = rotation @ END_A + offset, rotation @ END_B + offset
    gravity = rotation @ GRAVITY
    rotated = catenary_points(a, b, LENGTH, w, ea, gravity, s)
    np.testing.assert_allclose(rotated, planar @ rotation.T + offset, atol=1e-9)
    np.testing.assert_allclose(rotated[0], a, atol=1e-9)
    np.testing.assert_allclose(rotated[-1], b, atol=1e-9)
    # The lowest point lies below both ends, along the rotated gravity.
    heights = rotated @ (-gravity / np.linalg.norm(gravity))
    assert heights.min() < heights[0] - 3.0
    chain = chain_equilibrium(END_A, END_B, LENGTH, 20, w, ea, GRAVITY)
    turned = chain_equilibrium(a, b, LENGTH, 20, w, ea, gravity)
    np.testing.assert_allclose(turned.force_a, rotation @ chain.force_a, rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(turned.force_b, rotation @ chain.force_b, rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(turned.segment_tension, chain.segment_tension, rtol=1e-9)
    np.testing.assert_allclose(turned.positions, chain.positions @ rotation.T + offset,
                               atol=1e-9)


@pytest.mark.parametrize('end_b', [(0.0, 0.0, 0.0), (0.0, 0.0, 10.0), (0.0, 0.0, -41.0),
                                   (3.0, 4.0, -12.0), (38.0, 10.0, 5.0)])
def test_catenary_points_reproduce_ends(end_b):
    s = np.linspace(0.0, LENGTH, 17)
    points = catenary_points(END_A, end_b, LENGTH, W_POLYESTER, 5e6, GRAVITY, s)
    assert points.shape == (17, 3) and np.all(np.isfinite(points))
    np.testing.assert_allclose(points[0], END_A, atol=1e-9)
    np.testing.assert_allclose(points[-1], end_b, atol=1e-9)


# ------------------------------------------------------------------------ initial_shape


@pytest.mark.parametrize('end_b, gravity', [
    ((0.0, 0.0, 0.0), GRAVITY),                      # slack vertical hang, span 0
    ((0.0, 0.0, 8.0), GRAVITY),                      # vertical hang the chain cannot take
    ((1.05 * LENGTH, 0.0, 0.0), GRAVITY),            # taut: chord 1.05 L
    ((36.0, 0.0, 8.0), np.zeros(3)),                 # zero gravity, slack
    ((0.0, 1.05 * LENGTH, 0.0), np.zeros(3)),        # zero gravity, stretched
])
def test_initial_shape_is_finite_and_fixed_at_the_ends(end_b, gravity):
    positions = initial_shape(END_A, end_b, LENGTH, 20, W_POLYESTER, 5e7, gravity)
    assert positions.shape == (21, 3)
    assert np.all(np.isfinite(positions))
    np.testing.assert_allclose(positions[0], END_A, atol=1e-9)
    np.testing.assert_allclose(positions[-1], end_b, atol=1e-9)


def test_initial_shape_is_the_chain_equilibrium():
    positions = initial_shape(END_A, END_B, LENGTH, 20, W_POLYESTER, 5e7, GRAVITY)
    chain = chain_equilibrium(END_A, END_B, LENGTH, 20, W_POLYESTER, 5e7, GRAVITY)
    np.testing.assert_array_equal(positions, chain.positions)


def test_initial_shape_falls_back_to_the_catenary():
    # Folded at a vertical hang the chain has no equilibrium (a segment would have to lie
    # flat); the sampled catenary is the start instead.
    end_b = np.array([0.0, 0.0, 8.0])
    with pytest.raises(CatenaryError):
        chain_equilibrium(END_A, end_b, LENGTH, 20, W_POLYESTER, 5e7, GRAVITY)
    positions = initial_shape(END_A, end_b, LENGTH, 20, W_POLYESTER, 5e7, GRAVITY)
    expected = catenary_points(END_A, end_b, LENGTH, W_POLYESTER, 5e7, GRAVITY,
                               np.linspace(0.0, LENGTH, 21))
    np.testing.assert_array_equal(positions, expected)
    assert positions[:, 2].min() == pytest.approx(-(LENGTH - 8.0) / 2.0, abs=1e-3)


def test_initial_shape_is_fast():
    timings = []
    for _ in range(5):
        start = time.perf_counter()
        initial_shape(END_A, END_B, LENGTH, 200, W_POLYESTER, 5e7, GRAVITY)
        timings.append(time.perf_counter() - start)
    # ~0.3 ms here; the bound only catches a solver that crawls (it runs on node restarts).
    assert min(timings) < 0.02


# ---------------------------------------------------------------------- water and seabed

# MoorDyn's validation chain and the wire in water (test/data/README.md, water/).
W_CHAIN = 3324.385105  # submerged [N/m]
EA_CHAIN = 1.674e9
D_CHAIN = 0.252
W_WIRE_WATER = 51.129200
W_WIRE_AIR = 6.5 * 9.81  # MoorDyn's water cases have no air


def _water_rows(name: str) -> list:
    with open(REFERENCE_DIR / 'water' / name, newline='') as stream:
        return list(csv.DictReader(line for line in stream if not line.startswith('#')))


def _nodes(name: str) -> np.ndarray:
    """Return the disc_x, disc_y, disc_z columns (the exact discrete rest) of a nodes file."""
    return np.loadtxt(REFERENCE_DIR / 'water' / name, delimiter=',', skiprows=2)[:, 4:7]


QSCHAIN_ROWS = [r for r in _water_rows('qschain_static.csv') if r['run'] == 'N0']


@pytest.mark.parametrize('row', QSCHAIN_ROWS, ids=lambda row: row['case'])
def test_seabed_catenary_matches_reference(row):
    # cont_*: the reference's own elastic catenary on a rigid frictionless seabed
    length, span = float(row['L0_m']), float(row['span_m'])
    rise = float(row['fairlead_height_m'])
    solution = solve_seabed_catenary(span, rise, 0.0, length, W_CHAIN, EA_CHAIN)
    assert _relative(solution.horizontal_tension, float(row['cont_H_N'])) < 1e-8
    assert _relative(solution.tension_b, float(row['cont_T_B_N'])) < 1e-8
    assert solution.laid_length == pytest.approx(float(row['cont_laid_length_m']), abs=1e-6)
    assert solution.suspended_a == 0.0 and solution.tension_a == solution.horizontal_tension
    x, z = seabed_profile(solution, W_CHAIN, EA_CHAIN, [0.0, 0.5 * solution.laid_length,
                                                        length])
    np.testing.assert_allclose(x, [0.0, 0.5 * solution.laid_length
                                   * (1.0 + solution.horizontal_tension / EA_CHAIN), span],
                               atol=1e-9 * length)
    np.testing.assert_allclose(z, [0.0, 0.0, rise], atol=1e-9 * length)


def test_seabed_catenary_u_shape_is_symmetric_and_closes():
    # Both ends 20 m above the seabed, 120 m of chain over 100 m: it lies in the middle.
    solution = solve_seabed_catenary(100.0, 0.0, -20.0, 120.0, W_CHAIN, EA_CHAIN)
    assert solution.suspended_a == pytest.approx(solution.suspended_b, rel=1e-9)
    assert solution.laid_length > 0.0
    s = np.linspace(0.0, 120.0, 241)
    x, z = seabed_profile(solution, W_CHAIN, EA_CHAIN, s)
    assert x[-1] == pytest.approx(100.0, abs=1e-7) and z[-1] == pytest.approx(0.0, abs=1e-7)
    assert z.min() == pytest.approx(-20.0, abs=1e-12)
    assert np.all(np.diff(x) > 0.0)  # no fold at touchdown or lift-off


def test_seabed_catenary_is_none_where_the_line_hangs_free_or_lies_slack():
    assert solve_seabed_catenary(36.0, 8.0, -50.0, 40.0, 25.0, 5e7) is None  # far above
    assert solve_seabed_catenary(10.0, 0.0, 0.0, 40.0, 25.0, 5e7) is None  # heaped slack


def test_wetted_fraction_is_the_mean_of_the_ramp():
    dv, level = 0.1, 2.0
    assert wetted_fraction(-5.0, -4.0, level, dv) == 1.0
    assert wetted_fraction(5.0, 4.0, level, dv) == 0.0
    assert wetted_fraction(level, level, level, dv) == pytest.approx(0.5)
    for z_a, z_b in ((1.9, 2.3), (2.04, 1.0), (1.97, 2.01), (2.0, 2.0 + 1e-10)):
        z = np.linspace(z_a, z_b, 200001)
        ramp = np.clip((level - z) / dv + 0.5, 0.0, 1.0)
        assert wetted_fraction(z_a, z_b, level, dv) == pytest.approx(ramp.mean(), abs=1e-5)
    # a segment sinking through the surface: no jump
    heights = np.linspace(1.5, 2.5, 2001)
    fractions = wetted_fraction(heights, heights + 0.3, level, dv)
    assert np.abs(np.diff(fractions)).max() < 2e-3
    assert np.all(wetted_fraction(0.0, 1.0, -np.inf, dv) == 0.0)


def test_loaded_chain_of_equal_weights_is_the_chain():
    chain = chain_equilibrium(END_A, END_B, LENGTH, 20, W_POLYESTER, 5e7, GRAVITY)
    weights = np.full(21, W_POLYESTER * LENGTH / 20)
    weights[[0, -1]] *= 0.5
    loaded = loaded_chain_equilibrium(END_A, END_B, LENGTH, weights, 5e7, GRAVITY)
    np.testing.assert_allclose(loaded.positions, chain.positions, atol=1e-9)
    np.testing.assert_allclose(loaded.force_b, chain.force_b, rtol=1e-9)
    # a buoyant line is the same line upside down
    floating = loaded_chain_equilibrium(END_A, END_B, LENGTH, -weights, 5e7, GRAVITY)
    flipped = chain_equilibrium(END_A, END_B, LENGTH, 20, W_POLYESTER, 5e7, -GRAVITY)
    np.testing.assert_allclose(floating.positions, flipped.positions, atol=1e-9)


def test_wire_wholly_in_water_starts_at_its_exact_rest():
    # heave_wire_N20_initial_nodes.csv: the surface 100 m above A
    positions = initial_shape(END_A, END_B, LENGTH, 20, W_WIRE_AIR, 1e8, GRAVITY,
                              submerged_weight_per_length=W_WIRE_WATER, water_level=100.0,
                              volume_diameter=0.04)
    np.testing.assert_allclose(positions, _nodes('heave_wire_N20_initial_nodes.csv'),
                               atol=1e-7)
    row = _water_rows('heave_ic.csv')[0]
    weights = node_weights(positions, np.full(20, 2.0), W_WIRE_AIR, W_WIRE_WATER, 100.0, 0.04)
    chain = loaded_chain_equilibrium(END_A, END_B, LENGTH, weights, 1e8, GRAVITY)
    want = [float(row[f'disc_F_B{axis}_N']) for axis in 'xyz']
    np.testing.assert_allclose(chain.force_b, want, rtol=1e-7, atol=1e-6)


def test_line_through_the_surface_rests_with_each_node_weighed_where_it_lies():
    # The wire with the water 3 m above A: its low part is wet, its ends dry.
    positions = initial_shape(END_A, END_B, LENGTH, 20, W_WIRE_AIR, 1e8, GRAVITY,
                              submerged_weight_per_length=W_WIRE_WATER, water_level=-1.0,
                              volume_diameter=0.04)
    weights = node_weights(positions, np.full(20, 2.0), W_WIRE_AIR, W_WIRE_WATER, -1.0, 0.04)
    inner = weights[1:-1]
    assert inner.min() == pytest.approx(2.0 * W_WIRE_WATER)  # some wet
    assert inner.max() == pytest.approx(2.0 * W_WIRE_AIR)  # some dry
    again = loaded_chain_equilibrium(END_A, END_B, LENGTH, weights, 1e8, GRAVITY)
    np.testing.assert_allclose(positions, again.positions, atol=1e-9)


def test_chain_start_lies_on_the_seabed_at_its_sink_depth():
    sink = W_CHAIN / (1.0e5 * D_CHAIN)
    positions = initial_shape(END_A, [400.0, 0.0, 50.0], 410.0, 41, 390.0 * 9.81, EA_CHAIN,
                              GRAVITY, submerged_weight_per_length=W_CHAIN, water_level=50.0,
                              volume_diameter=D_CHAIN, seabed_level=0.0, seabed_sink=sink)
    np.testing.assert_allclose(positions[[0, -1]], [END_A, [400.0, 0.0, 50.0]], atol=1e-9)
    assert positions[:, 2].min() == pytest.approx(-sink, abs=1e-9)
    # the exact discrete rest on the soft seabed (Newton on all nodes) is a few cm away
    assert np.abs(positions - _nodes('qschain_WD0050_N41_nodes.csv')).max() < 0.05


def test_buoyant_line_arcs_up_in_water():
    positions = initial_shape(END_A, END_B, LENGTH, 20, W_POLYESTER, 5e7, GRAVITY,
                              submerged_weight_per_length=-6.841648, water_level=100.0,
                              volume_diameter=0.064)
    assert positions[:, 2].max() > 11.0  # arcs above its chord (11.42 m at N = 400)


@pytest.mark.parametrize('kwargs, name', [
    ({'water_level': math.nan}, 'water_level'),
    ({'seabed_level': math.inf}, 'seabed_level'),
    ({'seabed_sink': -1.0}, 'seabed_sink'),
    ({'volume_diameter': -0.1}, 'volume_diameter'),
    ({'submerged_weight_per_length': math.nan, 'water_level': 1.0},
     'submerged_weight_per_length'),
])
def test_initial_shape_rejects_bad_water_and_seabed(kwargs, name):
    with pytest.raises(CatenaryError, match=name):
        initial_shape(END_A, END_B, LENGTH, 20, W_POLYESTER, 5e7, GRAVITY, **kwargs)


# -------------------------------------------------------------------------------- errors


@pytest.mark.parametrize('kwargs, name', [
    ({'length': -1.0}, 'length'),
    ({'length': 0.0}, 'length'),
    ({'weight_per_length': 0.0}, 'weight_per_length'),
    ({'weight_per_length': -3.0}, 'weight_per_length'),
    ({'axial_stiffness': 0.0}, 'axial_stiffness'),
    ({'axial_stiffness': -1e6}, 'axial_stiffness'),
    ({'span': -1.0}, 'span'),
    ({'rise': math.nan}, 'rise'),
])
def test_solve_catenary_rejects_bad_inputs(kwargs, name):
    args = {'span': 36.0, 'rise': 8.0, 'length': LENGTH, 'weight_per_length': W_POLYESTER,
            'axial_stiffness': 5e7}
    args.update(kwargs)
    with pytest.raises(CatenaryError, match=name):
        solve_catenary(**args)


@pytest.mark.parametrize('kwargs, name', [
    ({'length': -40.0}, 'length'),
    ({'segments': 0}, 'segments'),
    ({'weight_per_length': -1.0}, 'weight_per_length'),
    ({'axial_stiffness': 0.0}, 'axial_stiffness'),
    ({'end_b': (1.0, 2.0)}, 'end_b'),
    ({'end_a': (0.0, math.inf, 0.0)}, 'end_a'),
    ({'gravity': (0.0, 0.0, math.nan)}, 'gravity'),
])
@pytest.mark.parametrize('function', [chain_equilibrium, initial_shape])
def test_chain_functions_reject_bad_inputs(function, kwargs, name):
    args = {'end_a': END_A, 'end_b': END_B, 'length': LENGTH, 'segments': 10,
            'weight_per_length': W_POLYESTER, 'axial_stiffness': 5e7, 'gravity': GRAVITY}
    args.update(kwargs)
    with pytest.raises(CatenaryError, match=name):
        function(**args)


def test_catenary_error_is_a_value_error():
    with pytest.raises(ValueError):
        solve_catenary(36.0, 8.0, -LENGTH, W_POLYESTER, 5e7)
