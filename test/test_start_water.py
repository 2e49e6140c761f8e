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
The start in water and on the seabed: at rest in the model's equilibrium, against MoorDyn.

The references are MoorDyn 2.7.2's (test/data/water, README there): its validation chains
lying on a soft seabed (qschain_*), and the wire and the polyester line wholly in still
water (heave_ic.csv, current_static.csv's still-water columns) or in a current. MoorDyn has
no air (air_density 0 here) and one diameter for everything (volume_diameter = diameter).
"""

import csv
import math

import numpy as np
import pytest

from rope_sim_ros.model.objects import Environment, LineType, Point, single_line
from rope_sim_ros.model.rope import RopeProperties
from rope_sim_ros.model.statics.catenary import chain_equilibrium
from rope_sim_ros.model.statics.start import start_shape
from rope_sim_ros.model.superelastic import MAX_ITERATIONS
from rope_sim_ros.stepping.relax import relax
from rope_sim_ros.stepping.rules import automatic_time_step, contact_rates, stability_limit
from rope_sim_ros.stepping.step import step

G = 9.81


def _props(line_type: LineType, length: float, segments: int) -> RopeProperties:
    """Return the RopeProperties of a uniform line of line_type."""
    t = line_type
    return RopeProperties(
        segments=segments, length=length, mass_per_length=t.mass_per_length,
        axial_stiffness=t.axial_stiffness, axial_damping=t.axial_damping,
        diameter=t.diameter, volume_diameter=t.volume_diameter, normal_drag=t.normal_drag,
        tangential_drag=t.tangential_drag, normal_added_mass=t.normal_added_mass,
        tangential_added_mass=t.tangential_added_mass)


def _rows(reference_dir, name: str) -> list:
    with open(reference_dir / 'water' / name, newline='') as stream:
        return list(csv.DictReader(line for line in stream if not line.startswith('#')))


def _vector(row: dict, prefix: str) -> np.ndarray:
    return np.array([float(row[f'{prefix}{axis}_N']) for axis in 'xyz'])


def _start(line_type, environment, end_b, length, segments, end_a=(0.0, 0.0, 0.0)):
    """Build the line at its start shape, relax it; return (props, system, relaxed)."""
    props = _props(line_type, length, segments)
    shape = start_shape(line_type, environment, end_a, end_b, length, segments)
    system = single_line(line_type, environment, length, segments, shape,
                         Point('fixed', end_a), Point('fixed', end_b))
    return props, system, relax(props, system)


def _hold(system, integrator, dt, duration):
    """Step with every point held; return the end forces (steps, 2, 3) after each block."""
    drive_x, drive_v = system.drive_arrays(50)
    forces = []
    for _ in range(int(round(duration / dt)) // 50):
        step(system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS)
        forces.append(system.end_forces()[0])
    return np.array(forces)


# ------------------------------------------------------------------ the lines of the data

CHAIN_D = 0.252


def _chain(segment: float) -> LineType:
    """Return the validation chain of MoorDyn (BA -1: l sqrt(EA m), critical per segment)."""
    return LineType(mass_per_length=390.0, axial_stiffness=1.674e9,
                    axial_damping=segment * math.sqrt(1.674e9 * 390.0), diameter=CHAIN_D,
                    volume_diameter=CHAIN_D, normal_drag=1.37, tangential_drag=0.64,
                    normal_added_mass=1.0, tangential_added_mass=0.0)


WIRE = LineType(mass_per_length=6.5, axial_stiffness=1.0e8, axial_damping=6492.27,
                diameter=0.040, volume_diameter=0.040, normal_drag=1.2, tangential_drag=0.008,
                normal_added_mass=1.0, tangential_added_mass=0.0)
POLYESTER = LineType(mass_per_length=2.6, axial_stiffness=5.0e7, axial_damping=2903.43,
                     diameter=0.064, volume_diameter=0.064, normal_drag=1.2,
                     tangential_drag=0.008, normal_added_mass=1.0, tangential_added_mass=0.0)
LINES = {'wire': WIRE, 'polyester': POLYESTER}
END_B = np.array([36.0, 0.0, 8.0])


def _qschain_environment(height: float) -> Environment:
    return Environment(gravity=(0.0, 0.0, -G), air_density=0.0, water_level=height,
                       water_density=1025.0, seabed_level=0.0, seabed_stiffness=1.0e5,
                       seabed_damping=1.0e4, seabed_friction=0.5)


def _deep_water(current=(0.0, 0.0, 0.0)) -> Environment:
    """Return the water of the current and heave cases (surface 100 m above A)."""
    return Environment(gravity=(0.0, 0.0, -G), air_density=0.0, water_level=100.0,
                       water_density=1025.0, current=tuple(current), seabed_level=-900.0)


QSCHAIN = [('WD0050', 41), ('WD0200', 76), ('WD0600', 170)]


# --------------------------------------------------------------------- chains on the seabed


@pytest.mark.parametrize('case, segments', QSCHAIN)
def test_chain_on_the_seabed_starts_at_moordyns_rest(reference_dir, case, segments):
    row = next(r for r in _rows(reference_dir, 'qschain_static.csv')
               if r['case'] == case and r['run'] == 'N0')
    length, span = float(row['L0_m']), float(row['span_m'])
    height = float(row['fairlead_height_m'])
    _, system, relaxed = _start(_chain(length / segments), _qschain_environment(height),
                                [span, 0.0, height], length, segments)
    assert relaxed
    forces = system.end_forces()[0]
    for end, name in ((1, 'md_F_B'), (0, 'md_F_A')):
        want = _vector(row, name)
        error = np.linalg.norm(forces[end] - want) / np.linalg.norm(want)
        assert error < 0.005, (case, name, forces[end], want)
    nodes = np.loadtxt(reference_dir / 'water' / f'qschain_{case}_N{segments}_nodes.csv',
                       delimiter=',', skiprows=2)
    # MoorDyn's surface is a sharp cut (with a d/2 correction), ours a ramp one diameter
    # wide: the top segment's buoyancy differs a little, and with it the shape by mm
    assert np.abs(system.x - nodes[:, 4:7]).max() < 0.02


def test_chain_start_lies_where_the_soft_seabed_holds_it(reference_dir):
    # Before relax: the seabed catenary laid at the sink depth w / (k_b d), within a few
    # cm of the discrete rest everywhere (what relax has left to do).
    length, span, height, segments = 410.0, 400.0, 50.0, 41
    shape = start_shape(_chain(10.0), _qschain_environment(height), [0.0, 0.0, 0.0],
                        [span, 0.0, height], length, segments)
    nodes = np.loadtxt(reference_dir / 'water' / 'qschain_WD0050_N41_nodes.csv',
                       delimiter=',', skiprows=2)
    assert np.abs(shape - nodes[:, 4:7]).max() < 0.05
    sink = 3324.385105 / (1.0e5 * CHAIN_D)
    assert shape[:, 2].min() == pytest.approx(-sink, abs=1e-6)


# ------------------------------------------------------------------------- still water


def test_wire_in_still_water_starts_at_the_exact_rest(reference_dir):
    row = _rows(reference_dir, 'heave_ic.csv')[0]
    props, system, relaxed = _start(WIRE, _deep_water(), END_B, 40.0, 20)
    shape = start_shape(WIRE, _deep_water(), [0.0, 0.0, 0.0], END_B, 40.0, 20)
    forces = system.end_forces()[0]
    for end, name in ((1, 'disc_F_B'), (0, 'disc_F_A')):
        want = _vector(row, name)
        assert np.linalg.norm(forces[end] - want) < 1e-6 * np.linalg.norm(want)
    moordyn = _vector(row, 'ic_F_B')
    assert np.linalg.norm(forces[1] - moordyn) < 0.005 * np.linalg.norm(moordyn)
    nodes = np.loadtxt(reference_dir / 'water' / 'heave_wire_N20_initial_nodes.csv',
                       delimiter=',', skiprows=2)
    assert np.abs(shape - nodes[:, 4:7]).max() < 1e-6  # the start itself is the rest
    assert relaxed


@pytest.mark.parametrize('material', ['wire', 'polyester'])
@pytest.mark.parametrize('segments', [20, 50])
def test_still_water_start_matches_moordyns(reference_dir, material, segments):
    # MoorDyn's initial condition ignores the current: its ic_* forces are the still-water
    # rest. The polyester is lighter than water and arcs above its chord.
    row = next(r for r in _rows(reference_dir, 'current_static.csv')
               if r['material'] == material and int(r['N']) == segments)
    _, system, relaxed = _start(LINES[material], _deep_water(), END_B, 40.0, segments)
    assert relaxed
    want = _vector(row, 'ic_F_B')
    got = system.end_forces()[0, 1]
    assert np.linalg.norm(got - want) < 0.005 * np.linalg.norm(want), (got, want)
    if material == 'polyester':
        assert system.x[:, 2].max() > 11.0  # it floats up (11.42 m at N = 400)


@pytest.mark.parametrize('material', ['wire', 'polyester'])
def test_start_in_a_current_is_moordyns_settled_state(reference_dir, material):
    # relax brings the still-water shape to rest with the drag of the current at rest
    row = next(r for r in _rows(reference_dir, 'current_static.csv')
               if r['material'] == material and int(r['N']) == 20)
    _, system, relaxed = _start(LINES[material], _deep_water((0.0, 1.0, 0.0)), END_B, 40.0,
                                20)
    assert relaxed
    forces = system.end_forces()[0]
    for end, name in ((1, 'md_F_B'), (0, 'md_F_A')):
        want = _vector(row, name)
        assert np.linalg.norm(forces[end] - want) < 0.005 * np.linalg.norm(want)


# ------------------------------------------------------------------- no ringing at start


@pytest.mark.parametrize('integrator', ['improved_euler', 'implicit_euler'])
@pytest.mark.parametrize('case', ['wire', 'polyester', 'chain'])
def test_no_ringing_at_start(integrator, case):
    if case == 'chain':
        line_type, length, segments = _chain(10.0), 410.0, 41
        environment, end_b = _qschain_environment(50.0), np.array([400.0, 0.0, 50.0])
    else:
        line_type, length, segments = LINES[case], 40.0, 20
        environment, end_b = _deep_water(), END_B
    props, system, relaxed = _start(line_type, environment, end_b, length, segments)
    assert relaxed
    start = system.end_forces()[0]
    forces = _hold(system, integrator, automatic_time_step(props, environment, integrator),
                   5.0)
    drift = np.linalg.norm(forces - start, axis=2).max()
    assert drift < 1e-4 * np.linalg.norm(start[1]), drift


# --------------------------------------------------------------- steps with the ground


def _laid(line_type, environment, length, segments, span):
    """Return a line lying on the seabed at z = 0 between ends on it, its sag in the ground."""
    props = _props(line_type, length, segments)
    a, b = np.zeros(3), np.array([span, 0.0, 0.0])
    shape = start_shape(line_type, environment, a, b, length, segments)
    system = single_line(line_type, environment, length, segments, shape, Point('fixed', a),
                         Point('fixed', b))
    return props, system


def test_contact_damping_limits_the_explicit_step():
    # The polyester in 4 m segments lying on MoorDyn's default seabed: its contact damping
    # c_b d / m (7400 /s) allows Heun's method no more than 2 / 7400 s, below what its axial
    # modes allow. At the step that ignores the ground its particles chatter on the seabed
    # for as long as it runs (the ground never pulls, so the unstable mode saturates rather
    # than blows up); at the automatic step they lie still.
    environment = Environment(gravity=(0.0, 0.0, -G), seabed_level=0.0)
    air = Environment(gravity=(0.0, 0.0, -G))  # the free line's: no ground
    free = _props(POLYESTER, 40.0, 10)
    props, system = _laid(POLYESTER, environment, 40.0, 10, 39.0)
    stiffness, damping = contact_rates(props, environment)
    assert damping == pytest.approx(3.0e5 * 0.064 / 2.6)
    assert stiffness == pytest.approx(3.0e6 * 0.064 / 2.6)
    assert contact_rates(free, air) == (0.0, 0.0)
    assert stability_limit(props, environment) <= 2.0 / damping
    assert stability_limit(props, environment) < 0.9 * stability_limit(free, air)
    assert automatic_time_step(props, environment) < stability_limit(props, environment)
    assert automatic_time_step(free, air) > 2.0 / damping
    shape = system.x.copy()
    shape[1:-1, 2] += 1e-6 * np.sin(np.arange(1, 10))  # what rounding would grow from
    for dt, still in ((automatic_time_step(props, environment), True),
                      (automatic_time_step(free, air), False)):
        system.x[:] = shape
        system.v[:] = 0.0
        _hold(system, 'improved_euler', dt, 1.0)
        assert np.all(np.isfinite(system.x))
        assert (np.abs(system.v).max() < 1e-6) == still, np.abs(system.v).max()


def test_slack_dampers_limit_the_explicit_step():
    # MoorDyn's chain damping, BA = l sqrt(EA m) (critical per segment): where a segment is
    # slack its damper still acts and its spring does not, a pure damping of rate up to
    # 4 c / m that Heun's method takes only below m / (2 c). A slack chain let fall in air
    # at the step of its taut modes alone (0.97 ms) reached 800 m/s; at the automatic step
    # it falls as a chain does.
    line_type, length, segments = _chain(2.5), 50.0, 20
    environment = Environment(gravity=(0.0, 0.0, -G))
    props = _props(line_type, length, segments)
    slack_limit = props.particle_mass / (2.0 * props.structural_damping)
    assert stability_limit(props, environment) == pytest.approx(slack_limit, rel=1e-9)
    a, b = np.array([0.0, 0.0, 1.0]), np.array([40.0, 0.0, 1.0])
    shape = np.linspace(a, b, segments + 1)
    shape[:, 2] = 1.0 + 0.4 * np.sin(np.linspace(0.0, math.pi, segments + 1))
    system = single_line(line_type, environment, length, segments, shape, Point('fixed', a),
                         Point('fixed', b))
    forces = _hold(system, 'improved_euler', automatic_time_step(props, environment), 5.0)
    assert np.abs(system.v).max() < 20.0  # a fall of 13 m: 16 m/s
    hanging = np.linalg.norm(chain_equilibrium(a, b, length, segments, 390.0 * G,
                                               line_type.axial_stiffness,
                                               environment.gravity).force_b)
    assert np.linalg.norm(forces, axis=2).max() < 10.0 * hanging


@pytest.mark.parametrize('integrator', ['improved_euler', 'implicit_euler'])
@pytest.mark.parametrize('line', ['chain', 'polyester'])
def test_line_dropped_on_the_seabed_comes_to_rest(integrator, line):
    # Held at both ends 1 m above MoorDyn's default seabed (k_b 3e6, c_b 3e5), in air, and
    # let fall from a slack arc: at the automatic step it lands, stays finite and settles.
    if line == 'chain':
        line_type, length, segments, span = _chain(2.5), 50.0, 20, 40.0
    else:
        line_type, length, segments, span = POLYESTER, 40.0, 20, 30.0
    environment = Environment(gravity=(0.0, 0.0, -G), seabed_level=0.0)
    props = _props(line_type, length, segments)
    a, b = np.array([0.0, 0.0, 1.0]), np.array([span, 0.0, 1.0])
    shape = np.linspace(a, b, segments + 1)
    shape[:, 2] = 1.0 + 0.4 * np.sin(np.linspace(0.0, math.pi, segments + 1))  # no stretch
    system = single_line(line_type, environment, length, segments, shape, Point('fixed', a),
                         Point('fixed', b))
    dt = automatic_time_step(props, environment, integrator)
    _hold(system, integrator, dt, 20.0)
    assert np.all(np.isfinite(system.x))
    assert np.abs(system.v).max() < 1e-3
    sink = line_type.mass_per_length * G / (3.0e6 * line_type.diameter)
    assert system.x[:, 2].min() > -3.0 * sink
