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
Lines with a tabulated strain-tension curve: statics, tension, Jacobian, dynamics, parameters.

The reference line is test/data/winch/'s nylon-like rope (README there): 64 mm, 585.15 d^2 =
2.3967744 kg/m, in air, T = MBL (e + 12 e^2) tabulated in nylon_table.csv, 40 m, N 20.
"""

import csv
import math
from pathlib import Path

import numpy as np
from one_line import OneLine
from physics_cases import nrmse, reference_params
import pytest

from rope_sim_ros.model.forces import assembly
from rope_sim_ros.model.forces.springs import spring_block_at
from rope_sim_ros.model.layout import INV_MASS, PARTED, REST, UNSTRETCHED
from rope_sim_ros.model.materials import MaterialError, MaterialLibrary
from rope_sim_ros.model.objects import Environment, LineType, Point, single_line, Winch
from rope_sim_ros.model.parting import check_segments
from rope_sim_ros.model.rope import RopeProperties, tension_bound
from rope_sim_ros.model.statics import catenary
from rope_sim_ros.model.tension_curve import TensionCurve
from rope_sim_ros.model.winch import quasi_static_stiffness, render
from rope_sim_ros.params.materials import load_materials
from rope_sim_ros.params.table import check, from_values, ParameterError
from rope_sim_ros.stepping.rules import automatic_time_step, stability_limit

DATA = Path(__file__).resolve().parent / 'data' / 'winch'
DIAMETER = 0.064
MASS = 585.15 * DIAMETER ** 2
AIR = 1.225
G = 9.81
W = (MASS - AIR * math.pi * DIAMETER ** 2 / 4.0) * G  # 23.473697 N/m (README)
LENGTH = 40.0
RISE = 8.0
BA = 601.138


def read_rows(path):
    """Read a reference CSV's rows as dicts of floats, past its '#' comment lines."""
    with open(path, newline='') as f:
        lines = [line for line in f if not line.startswith('#')]
    return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(lines)]


def _table():
    rows = read_rows(DATA / 'nylon_table.csv')
    return [(r['strain'], r['tension_N']) for r in rows]


TABLE = _table()
MBL = TABLE[-2][1]  # the table reaches MBL at 25 % strain
CURVE = TensionCurve.from_pairs(TABLE)
STATIC = read_rows(DATA / 'nonlinear_static.csv')


def _expected_tension(strain):
    """Return the table's tension at a strain, written out independently of the model."""
    strains = np.array([p[0] for p in TABLE])
    tensions = np.array([p[1] for p in TABLE])
    if strain <= 0.0:
        return 0.0
    if strain >= strains[-1]:
        slope = (tensions[-1] - tensions[-2]) / (strains[-1] - strains[-2])
        return tensions[-1] + slope * (strain - strains[-1])
    return float(np.interp(strain, strains, tensions))


def _library():
    """Make a materials file holding the reference rope: its table in fractions of MBL."""
    return MaterialLibrary({'nylon': dict(
        mass_per_length=[[585.15, 2]], mbl=[[MBL, 0]], axial_stiffness={'mbl_multiple': 5.0},
        working_load_fraction=0.5, volume_diameter_ratio=1.0, normal_drag_coefficient=1.2,
        tangential_drag_coefficient=0.008, normal_added_mass_coefficient=1.0,
        tangential_added_mass_coefficient=0.0,
        tension_curve={'mbl_fraction': [[e, t / MBL] for e, t in TABLE[1:]]})})


def _params(**overrides):
    values = dict(material='nylon', diameter=DIAMETER, volume_diameter=DIAMETER, length=LENGTH,
                  segments=20, load_extension='curve', axial_damping=BA, air_density=AIR,
                  bending_stiffness_ratio=0.0, bending_damping_ratio=0.0,
                  gravity=[0.0, 0.0, -G], bollard_position=[0.0, 0.0, 0.0])
    values.update(overrides)
    return from_values(values)


# -- statics ------------------------------------------------------------------------------

@pytest.mark.parametrize('row', STATIC, ids=lambda r: f"span{r['span_m']:g}")
def test_catenary_matches_the_analytic_solution(row):
    """The continuous nonlinear catenary (closed form per piece) against the reference's."""
    solution = catenary.solve_catenary(row['span_m'], RISE, LENGTH, W, 5.0 * MBL, CURVE)
    # measured within 4.0e-10 (the reference integrated with Simpson on 20 001 points)
    assert solution.horizontal_tension == pytest.approx(row['an_H_N'], rel=1e-9)
    assert solution.tension_a == pytest.approx(row['an_T_A_N'], rel=1e-9)
    assert solution.tension_b == pytest.approx(row['an_T_B_N'], rel=1e-9)
    assert float(CURVE.strain_at(solution.tension_b)) == pytest.approx(row['an_strain_B'],
                                                                       abs=1e-10)
    # the profile closes on B: x = int (1 + e(T)) H / T ds, z = int (1 + e(T)) V / T ds
    x, z = catenary.catenary_profile(solution, LENGTH, W, 5.0 * MBL, [0.0, LENGTH], CURVE)
    assert x[-1] == pytest.approx(row['span_m'], abs=1e-9)
    assert z[-1] == pytest.approx(RISE, abs=1e-9)


@pytest.mark.parametrize('row', STATIC, ids=lambda r: f"span{r['span_m']:g}")
def test_chain_matches_the_exact_discrete_equilibrium(row):
    """The start shape's chain (each segment stretched by the curve) against disc_*."""
    chain = catenary.chain_equilibrium([0.0, 0.0, 0.0], [row['span_m'], 0.0, RISE], LENGTH, 20,
                                       W, 5.0 * MBL, [0.0, 0.0, -G], CURVE)
    # measured within 6.6e-10
    assert np.linalg.norm(chain.force_b) == pytest.approx(row['disc_F_B_N'], rel=2e-9)
    assert np.linalg.norm(chain.force_a) == pytest.approx(row['disc_F_A_N'], rel=2e-9)
    assert chain.segment_tension[-1] == pytest.approx(row['disc_Tseg_B_N'], rel=2e-9)


@pytest.mark.parametrize('integrator', ['implicit_euler', 'improved_euler'])
def test_settled_fairlead_force_matches_the_references(integrator):
    """The simulator's line at rest, then held 0.5 s: the discrete and continuous forces."""
    worst_discrete = worst_analytic = 0.0
    for row in STATIC:
        sim = OneLine(_params(integrator=integrator), _library(), history=math.inf)
        sim.push_fairlead(0.0, [row['span_m'], 0.0, RISE])
        sim.start(0.0)
        sim.advance_to(0.5)
        force = sim.output().fairlead_tension
        worst_discrete = max(worst_discrete, abs(force / row['disc_F_B_N'] - 1.0))
        worst_analytic = max(worst_analytic, abs(force / row['an_T_B_N'] - 1.0))
    # measured: 5.3e-10 of the exact discrete equilibrium (30 to 44 m, slack to 11.8 %
    # strain), both integrators; 0.097 % of the continuous curve at worst (39 m): the
    # N = 20 lumping
    assert worst_discrete <= 2e-9
    assert worst_analytic <= 1e-3


# -- the tension follows the table ---------------------------------------------------------

STRAINS = [-0.02, 0.0, 0.004, 0.01, 0.0375, 0.0688, 0.12, 0.25, 0.2712, 0.30, 0.33, 0.37]


def _line(x, rest):
    """Make a curve line of segments of `rest` [m] at positions x, at rest, no gravity."""
    line_type = LineType(mass_per_length=MASS, axial_stiffness=5.0 * MBL, axial_damping=BA,
                         max_strain=1.0, tension_curve=TABLE)
    segments = len(x) - 1
    return single_line(line_type, Environment(gravity=(0.0, 0.0, 0.0), air_density=0.0),
                       rest * segments, segments, x, Point('fixed', x[0]), Point('fixed', x[-1]))


def _straight_line(strains):
    """Make a line along x whose segments (rest 2 m) sit at `strains`."""
    x = np.zeros((len(strains) + 1, 3))
    x[1:, 0] = np.cumsum(2.0 * (1.0 + np.array(strains)))
    return _line(x, 2.0)


def test_segment_tensions_follow_the_table():
    """Each segment pulls the interpolated table at its strain; none at strain <= 0."""
    system = _straight_line(STRAINS)
    forces = np.empty_like(system.x)
    assembly.line_forces(system.x, system.v, forces, system.particles, system.lines_table,
                         system.line_real)
    # particle i feels +T_i from segment i and -T_(i-1) from the one before: T_i sums them
    tensions = np.cumsum(forces[:-1, 0])
    expected = [_expected_tension(e) for e in STRAINS]
    assert tensions == pytest.approx(expected, rel=1e-12, abs=1e-6)
    assert abs(forces[:-1, 1:]).max() == 0.0
    # the state check's load is the tension at the largest strain, past the table here
    finite, largest = system.largest_load()
    assert finite and largest == pytest.approx(_expected_tension(max(STRAINS)), rel=1e-12)
    # the elastic energy: rest length times the integral of the curve up to each strain
    _, _, elastic = system.energy()
    stored = 0.0
    for strain in STRAINS:
        grid = np.linspace(0.0, max(strain, 0.0), 20001)
        stored += 2.0 * np.trapezoid([_expected_tension(e) for e in grid], grid)
    assert elastic == pytest.approx(stored, rel=1e-9)


def test_curve_inverse_and_stiffest_tangent():
    """strain_at inverts the tension, also past the table; stiffest takes the last slope."""
    strains = np.array([e for e in STRAINS if e > 0.0])
    assert CURVE.strain_at(CURVE.tension(strains)) == pytest.approx(strains, rel=1e-12)
    assert CURVE.strain_at([-5.0, 0.0]) == pytest.approx([0.0, 0.0])
    last_slope = (TABLE[-1][1] - TABLE[-2][1]) / (TABLE[-1][0] - TABLE[-2][0])
    assert CURVE.stiffest(0.5) == pytest.approx(last_slope)
    assert CURVE.stiffest(0.005) == pytest.approx(TABLE[1][1] / TABLE[1][0])


# -- the implicit step's Jacobian ---------------------------------------------------------

def _one_segment(x):
    """Make a one-segment curve line (rest 2 m) at positions x (2, 3), at rest."""
    return _line(x, 2.0)


def _force_on_first(system, x):
    """Return the force of the line's springs on its particle 0, its particles at x."""
    out = np.empty_like(x)
    assembly.line_forces(x, np.zeros_like(x), out, system.particles, system.lines_table,
                         system.line_real)
    return out[0].copy()


def _block(system, x):
    """Return the segment's block S + C at step factors h^2 / 2 = 1, h = 0: S alone."""
    block = np.empty((3, 3))
    spring_block_at(x, system.particles, 0, False, 1.0, 0.0, True, block,
                    system.line_real[0])
    return block


@pytest.mark.parametrize('strain', [0.004, 0.0375, 0.0688, 0.1725, 0.2712, 0.33])
def test_spring_block_is_the_force_jacobian(strain):
    """The block of a taut segment of a curve line is minus the force's derivative."""
    direction = np.array([0.48, -0.36, 0.8])
    x = np.array([0.3, -0.2, 1.1]) + np.outer([0.0, 1.0], direction) * (2.0 * (1.0 + strain))
    system = _one_segment(x)
    block = _block(system, x)
    numeric = np.empty((3, 3))
    step = 1e-7
    for k in range(3):
        plus, minus = x.copy(), x.copy()
        plus[0, k] += step
        minus[0, k] -= step
        numeric[:, k] = -(_force_on_first(system, plus) - _force_on_first(system, minus)) / (
            2.0 * step)
    assert block == pytest.approx(numeric, rel=1e-6, abs=1e-6 * np.abs(numeric).max())
    # along the segment: the table's tangent over the rest length
    assert direction @ block @ direction == pytest.approx(float(CURVE.tangent(strain)) / 2.0,
                                                          rel=1e-12)


def test_spring_block_of_a_slack_segment_keeps_the_first_slope():
    """Slack, the block holds the stiffness the segment meets as it pulls again."""
    x = np.array([[0.0, 0.0, 0.0], [1.9, 0.0, 0.0]])
    block = _block(_one_segment(x), x)
    first = TABLE[1][1] / TABLE[1][0] / 2.0
    assert block == pytest.approx(np.diag([first, 0.0, 0.0]), abs=1e-9 * first)


# -- the step rules -------------------------------------------------------------------------

IN_AIR = Environment()  # what the line hangs in: air, standard gravity


def _props(**overrides):
    values = dict(segments=20, length=LENGTH, mass_per_length=MASS, axial_stiffness=5.0 * MBL,
                  axial_damping=BA, mbl=MBL, tension_curve=TABLE)
    values.update(overrides)
    return RopeProperties(**values)


def test_strain_limit_leaves_the_curve_to_twice_the_breaking_load():
    """The curve line's strain limit: where it pulls 2 MBL, past the table's 30 %."""
    props = _props()
    last_slope = (TABLE[-1][1] - TABLE[-2][1]) / (TABLE[-1][0] - TABLE[-2][0])
    expected = TABLE[-1][0] + (2.0 * MBL - TABLE[-1][1]) / last_slope
    assert props.strain_limit == pytest.approx(expected)  # 0.3816
    assert props.line_type.max_strain == pytest.approx(expected)
    assert props.reach == pytest.approx(LENGTH * (1.0 + expected))
    assert props.limit_tension == pytest.approx(2.0 * MBL)
    # a larger max_strain stands; a linear line keeps its own
    assert _props(max_strain=0.5).strain_limit == 0.5
    assert _props(tension_curve=()).strain_limit == 0.25


def test_step_rules_take_the_stiffest_tangent():
    """The explicit step and the state check see the curve's stiffest slope, not EA."""
    curved = _props()
    stiffest = curved.stiffest_axial_stiffness
    assert stiffest == pytest.approx((TABLE[-1][1] - TABLE[-2][1]) / 0.05)
    linear = _props(tension_curve=(), axial_stiffness=stiffest)
    assert stability_limit(curved, IN_AIR) == pytest.approx(stability_limit(linear, IN_AIR),
                                                            rel=1e-12)
    assert automatic_time_step(curved, IN_AIR) == pytest.approx(
        automatic_time_step(linear, IN_AIR), rel=1e-12)
    assert automatic_time_step(curved, IN_AIR, 'implicit_euler') == pytest.approx(
        automatic_time_step(linear, IN_AIR, 'implicit_euler'), rel=1e-12)
    # the state check's bound: twice the pull at the limit, 2 x 2 MBL, and the dampers at
    # the fastest wave's speed (11 % more here)
    assert 4.0 * MBL < tension_bound(curved, IN_AIR) < 1.2 * 4.0 * MBL


def test_a_stretch_to_the_reach_stays_stable_at_the_automatic_step():
    """The fairlead pulled past the reach in 1 s: finite, within the bound, at the limit."""
    # parting off: at its default break load, the MBL, the line would part half way there
    params = _params(integrator='improved_euler', air_density=0.0, parting=False)
    sim = OneLine(params, _library(), history=math.inf)
    times = np.linspace(0.0, 2.0, 201)
    for t in times:
        sim.push_fairlead(float(t), [38.0 + 22.0 * min(t, 1.0), 0.0, RISE])
    sim.start(0.0)
    peak = 0.0
    for t in times[1:]:
        advance = sim.advance_to(float(t))
        assert not advance.restarted
        output = sim.output()
        peak = max(peak, output.fairlead_tension)
        # held at its reach, the projection's sweeps leave a segment up to 1e-6 over
        assert output.max_strain <= sim.props.strain_limit * (1.0 + 1e-5)
    # held at the reach, the line pulls its curve's tension at the limit, 2 MBL (measured
    # peak 2.000012 MBL), far inside the state check's bound (4.5 MBL at 22 m/s)
    assert peak == pytest.approx(2.0 * MBL, rel=1e-4)
    assert output.fairlead_tension == pytest.approx(2.0 * MBL, rel=1e-4)
    assert peak < tension_bound(sim.props, sim.environment, 22.0)


# -- a dynamic case against MoorDyn ---------------------------------------------------------

def _moordyn_run():
    rows = read_rows(DATA / 'nonlinear_dynamic.csv')
    nodes = read_rows(DATA / 'nonlinear_dynamic_initial_nodes.csv')
    t = np.array([r['t_s'] for r in rows])
    fairlead = np.array([[r['xB_m'], 0.0, r['zB_m']] for r in rows])
    shape = np.array([[n['x_m'], n['y_m'], n['z_m']] for n in nodes])
    return t, fairlead, shape, np.array([r['F_B_N'] for r in rows])


@pytest.mark.parametrize('integrator, bound', [
    # measured 0.37 % (0.009 % at MoorDyn's own 0.1 ms step)
    ('improved_euler', 0.0045),
    # measured 1.79 %: backward Euler at its 5 ms step damps the ringing as the line snaps
    # taut out of its sag near 38.5 m (1.3 % at 1 ms; a linear line on this motion 2.5 %)
    ('implicit_euler', 0.022)])
def test_fairlead_force_matches_moordyn(integrator, bound):
    """The table's line between 38.5 and 42 m span against MoorDyn 2.7.2 on the same table."""
    t, fairlead, shape, moordyn = _moordyn_run()
    sim = OneLine(_params(integrator=integrator), _library(), history=math.inf)
    for time, position in zip(t, fairlead):
        sim.push_fairlead(float(time), position)
    sim.start(0.0, shape)
    force = []
    for time in t:
        sim.advance_to(float(time))
        force.append(sim.output().fairlead_tension)
    force = np.array(force)
    assert force[0] == pytest.approx(moordyn[0], rel=1e-6)  # both start at rest, exactly
    assert np.isfinite(force).all()
    assert nrmse(force, moordyn) <= bound


# -- parameters and presets -----------------------------------------------------------------

def test_load_extension_parameter_is_checked():
    """A bad value and a material without a curve: one line naming what is allowed."""
    assert check('load_extension', 'curve') == 'curve'
    with pytest.raises(ParameterError, match="'load_extension' = 'cubic'.*linear, curve"):
        check('load_extension', 'cubic')
    with pytest.raises(ParameterError, match="'load_extension' = 'curve'.*'hmpe'.*"
                                             'no tension_curve'):
        OneLine(from_values({'material': 'hmpe', 'load_extension': 'curve'}))


def test_bad_curves_are_refused():
    """A table that does not rise, a tension at strain 0, a curve of words: named errors."""
    with pytest.raises(ValueError, match='must both increase'):
        LineType(mass_per_length=1.0, axial_stiffness=1.0, axial_damping=1.0,
                 tension_curve=[(0.1, 100.0), (0.2, 50.0)])
    with pytest.raises(ValueError, match='a tension of 0 at strain 0'):
        TensionCurve.from_pairs([(0.0, 10.0), (0.1, 100.0)])
    entry = dict(_library()._entries['nylon'], tension_curve={'mbl_fraction': 'steep'})
    with pytest.raises(MaterialError, match="material 'nylon'"):
        MaterialLibrary({'nylon': entry}).properties('nylon', DIAMETER)


def test_presets():
    """Nylon's curve reaches its MBL at 25 % strain; hmpe has none; linear by default."""
    library = load_materials()
    nylon = library.properties('nylon', DIAMETER)
    curve = TensionCurve.from_pairs(nylon.tension_curve)
    assert float(curve.tension(0.25)) == pytest.approx(nylon.mbl)
    # the two published values it was fitted to: 50 % MBL at 0.5 / 3.54 strain
    assert float(curve.strain_at(0.5 * nylon.mbl)) == pytest.approx(0.5 / 3.54, rel=2e-3)
    assert library.properties('hmpe', DIAMETER).tension_curve == ()
    default = OneLine(from_values({'material': 'nylon'}))
    assert default.props.tension_curve == () and default.props.strain_limit == 0.25
    curved = OneLine(from_values({'material': 'nylon', 'load_extension': 'curve'}))
    assert curved.props.tension_curve == nylon.tension_curve
    assert curved.props.strain_limit == pytest.approx(0.452, abs=1e-3)


# -- the polyester preset -------------------------------------------------------------------

# The published original working curve (config/materials.yaml): ESOMOOR D5.1's owc.dat
# (strain, tension [N]) at its MBL of 2.354e7 N, every point, as the file gives them.
ESOMOOR_MBL = 2.354e7
ESOMOOR_OWC = [
    (2.0690e-3, 4.6581e5), (4.1379e-3, 8.9750e5), (6.2069e-3, 1.2984e6), (8.2759e-3, 1.6719e6),
    (1.0345e-2, 2.0213e6), (1.2414e-2, 2.3500e6), (1.4483e-2, 2.6613e6), (1.6552e-2, 2.9585e6),
    (1.8621e-2, 3.2451e6), (2.0690e-2, 3.5244e6), (2.2759e-2, 3.7997e6), (2.4828e-2, 4.0744e6),
    (2.6897e-2, 4.3518e6), (2.8966e-2, 4.6352e6), (3.1035e-2, 4.9281e6), (3.3103e-2, 5.2337e6),
    (3.5172e-2, 5.5555e6), (3.7241e-2, 5.8968e6), (3.9310e-2, 6.2608e6), (4.1379e-2, 6.6511e6),
    (4.3448e-2, 7.0709e6), (4.5517e-2, 7.5235e6), (4.7586e-2, 8.0124e6), (4.9655e-2, 8.5408e6),
    (5.1724e-2, 9.1121e6), (5.3793e-2, 9.7298e6), (5.5862e-2, 1.0397e7), (5.7931e-2, 1.1117e7),
    (6.0000e-2, 1.1894e7)]


def _owc_tolerance(strain):
    """Return how far [MBL] the preset's 6-decimal fractions may leave the file's curve."""
    # 5e-7 at each point; past the table its last slope carries up to 1e-6 / 0.002069
    return 1e-6 + 5e-4 * max(strain - 0.06, 0.0)


def _owc_fraction(strain):
    """Return the published curve's T / MBL at a strain: interpolated, last slope past it."""
    strains = np.array([0.0] + [p[0] for p in ESOMOOR_OWC])
    fractions = np.array([0.0] + [p[1] for p in ESOMOOR_OWC]) / ESOMOOR_MBL
    if strain <= 0.0:
        return 0.0
    if strain >= strains[-1]:
        slope = (fractions[-1] - fractions[-2]) / (strains[-1] - strains[-2])
        return fractions[-1] + slope * (strain - strains[-1])
    return float(np.interp(strain, strains, fractions))


def test_polyester_preset_is_the_published_working_curve():
    """Every published point at the preset's MBL; linear between; its last slope past 6 %."""
    polyester = load_materials().properties('polyester', DIAMETER)
    curve = TensionCurve.from_pairs(polyester.tension_curve)
    assert len(polyester.tension_curve) == 30  # (0, 0) and the file's 29 points
    for strain, tension in ESOMOOR_OWC:  # the fractions are kept to 6 decimals
        assert float(curve.tension(strain)) / polyester.mbl == pytest.approx(
            tension / ESOMOOR_MBL, abs=5e-7)
    # MoorDyn's Syrope test has the same curve: 4.38601e6 N at 6 %, MBL 885 t
    assert float(curve.tension(0.06)) / polyester.mbl == pytest.approx(
        4.38601e6 / (885.0e3 * 9.80665), rel=3e-4)
    for strain in (0.001, 0.0235, 0.0425, 0.0595, 0.07, 0.09101):
        assert float(curve.tension(strain)) / polyester.mbl == pytest.approx(
            _owc_fraction(strain), abs=_owc_tolerance(strain))
    # the S of a new rope's first pull: 9.6 MBL at the toe, 5.6 MBL while its construction
    # beds in, 16.0 MBL at 6 %, which goes on past the table: MBL at 9.10 % strain
    tangents = curve.slopes / polyester.mbl
    assert tangents[0] == pytest.approx(9.564, abs=1e-3)
    assert tangents.min() == pytest.approx(5.640, abs=1e-3)
    assert tangents[-1] == pytest.approx(15.954, abs=1e-3)
    assert float(curve.strain_at(polyester.mbl)) == pytest.approx(0.09101, abs=1e-5)
    # with load_extension: curve the line takes it; its 2 MBL strain, 15.4 %, leaves the
    # 25 % max_strain standing
    sim = OneLine(from_values({'material': 'polyester', 'load_extension': 'curve'}))
    assert sim.props.tension_curve == polyester.tension_curve
    assert float(curve.strain_at(2.0 * polyester.mbl)) == pytest.approx(0.1537, abs=1e-4)
    assert sim.props.strain_limit == 0.25


@pytest.mark.parametrize('integrator', ['implicit_euler', 'improved_euler'])
def test_polyester_line_settles_on_its_published_curve(integrator):
    """The preset's 40 m line at rest from its sag to past the table: statics and table."""
    polyester = load_materials().properties('polyester', DIAMETER)
    curve = TensionCurve.from_pairs(polyester.tension_curve)
    weight = 25.467341  # the reference line's w (physics_cases, test/data/README.md)
    for span, strain_b in ((38.0, 1.1e-4), (40.5, 0.0321), (42.0, 0.0689)):
        fairlead = [span, 0.0, RISE]
        params = reference_params('polyester', 20, load_extension='curve',
                                  integrator=integrator)
        sim = OneLine(params, history=math.inf)
        sim.push_fairlead(0.0, fairlead)
        sim.start(0.0)
        sim.advance_to(0.5)
        force = sim.output().fairlead_tension
        chain = catenary.chain_equilibrium([0.0, 0.0, 0.0], fairlead, LENGTH, 20, weight,
                                           params.axial_stiffness, [0.0, 0.0, -G], curve)
        solution = catenary.solve_catenary(span, RISE, LENGTH, weight,
                                           params.axial_stiffness, curve)
        # measured: within 1.3e-11 of the exact discrete equilibrium, and 0.090 % (38 m,
        # nearly slack: the N = 20 lumping) to 4e-9 of the continuous curve
        assert force == pytest.approx(np.linalg.norm(chain.force_b), rel=1e-9)
        assert force == pytest.approx(solution.tension_b, rel=1e-3)
        # the top segment pulls the published table at its strain (past it, at 42 m)
        x = sim.rope.x
        strain = np.linalg.norm(x[-1] - x[-2]) / (LENGTH / 20) - 1.0
        assert strain == pytest.approx(strain_b, abs=1e-4)
        assert chain.segment_tension[-1] == pytest.approx(
            _owc_fraction(strain) * polyester.mbl, abs=_owc_tolerance(strain) * polyester.mbl)


# -- the winch and parting on a curve line ------------------------------------------------

def _wound_line(strains, **line):
    """Make _straight_line's line with its winch and break load set (Line's attributes)."""
    system = _straight_line(strains)
    for name, value in line.items():
        setattr(system.lines[0], name, value)
    system.refresh()
    return system


def test_a_curve_line_parts_where_its_table_passes_the_break_load():
    """At 24 % the table pulls 0.93 MBL (EA, 5 MBL, would pull 1.2 MBL); at 25.5 % past MBL."""
    for strain, parted in ((0.24, -1.0), (0.255, 1.0)):
        system = _wound_line([0.1, strain, 0.1], break_load=MBL)
        rest = system.particles[:, REST].copy()
        check_segments(system.x, system.v, system.particles, system.lines_table,
                       system.line_real, rest, 0)
        assert system.line_real[0, PARTED] == parted


def test_a_curve_line_brake_renders_to_the_table_s_holding_strain():
    """The brake pays out until the winch segment pulls its load by the curve, not by EA."""
    system = _wound_line([0.05, 0.05, 0.2], winch=Winch(mode='brake', brake_load=0.5 * MBL))
    rest, inv_mass = system.particles[:, REST].copy(), system.particles[:, INV_MASS].copy()
    render(system.x, system.particles, system.lines_table, system.line_real,
           system.points_table, rest, inv_mass, 0.01)
    length = np.linalg.norm(system.x[3] - system.x[2])
    strain = length / system.particles[2, REST] - 1.0
    # the table pulls 0.5 MBL at e = 0.1666 (EA, 5 MBL, would have left e = 0.1)
    assert _expected_tension(strain) == pytest.approx(0.5 * MBL, rel=1e-9)
    assert strain == pytest.approx(0.1666, abs=1e-4)
    assert system.line_real[0, UNSTRETCHED] > 6.0


def test_constant_tension_steers_by_the_tangents_of_the_curve():
    """Without weight the quasi-static stiffness is the segments' tangents in series."""
    strains = [0.025, 0.105, 0.195]  # between the table's points, where one slope holds
    system = _wound_line(strains)
    stiffness = quasi_static_stiffness(system.x, system.particles, system.lines_table,
                                       system.line_real, 0, 1.0, 0.0)
    tangents = [float(CURVE.tangent(e)) for e in strains]
    assert stiffness == pytest.approx(1.0 / sum(2.0 / k for k in tangents), rel=1e-12)
    # tangents 1.60, 3.52 and 5.68 MBL; EA's L / EA would say 5 MBL / 6 m, 1.81 times this
    assert 5.0 * MBL / 6.0 / stiffness == pytest.approx(1.8086, abs=1e-4)
