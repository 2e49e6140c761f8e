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
Water and air on a line, each term on its own: buoyancy, drag, added mass, the surface.

The terms' functions (forces/fluid.py) against finite differences and closed forms; then
whole systems against analytic answers: a buoyant line arches as an upside-down catenary, a
line in a current deflects by the drag balance, added mass slows a payload's heave by the
mass ratio, a line lowered through the surface feels its buoyancy grow without a jump, and
both integrators agree on a line heaving in the water.
"""

import math

import numpy as np
import pytest

from rope_sim_ros.model import parting
from rope_sim_ros.model.forces import assembly
from rope_sim_ros.model.forces import fluid
from rope_sim_ros.model.layout import REST
from rope_sim_ros.model.objects import (Environment, Line, LineType, Point, single_line,
                                        System)
from rope_sim_ros.model.statics.catenary import chain_equilibrium
from rope_sim_ros.model.superelastic import MAX_ITERATIONS
from rope_sim_ros.stepping.step import step

G = 9.81
RHO = 1025.0
GRAVITY = (0.0, 0.0, -G)
# polyester 64 mm, one diameter for everything (MoorDyn's convention): lighter than water
POLYESTER = LineType(mass_per_length=2.6, axial_stiffness=5.0e7, axial_damping=2903.43,
                     diameter=0.064, volume_diameter=0.064)
WIRE = LineType(mass_per_length=6.5, axial_stiffness=1.0e8, axial_damping=6492.27,
                diameter=0.040, normal_drag=1.2, tangential_drag=0.008,
                normal_added_mass=1.0, tangential_added_mass=0.0)
A = np.array([0.0, 0.0, 0.0])
B = np.array([36.0, 0.0, 8.0])


def _settle(system, iterations=80):
    """Newton-like pseudo-steps: implicit steps of 1 s from rest (as integrators.relax)."""
    drive_x, drive_v = system.drive_arrays(1)
    for _ in range(iterations):
        system.v[:] = 0.0
        system.point_v[:] = 0.0
        step(system, 'implicit_euler', 1.0, drive_x, drive_v, MAX_ITERATIONS)
    system.v[:] = 0.0
    system.point_v[:] = 0.0


# -- the terms ---------------------------------------------------------------------------

def test_a_segments_wetted_fraction_is_the_mean_of_the_surface_ramp():
    width, level = 0.064, 1.0
    fraction = fluid.wetted_fraction.py_func

    def quadrature(z_a, z_b):
        t = (np.arange(200000) + 0.5) / 200000
        r = (level - (z_a + t * (z_b - z_a))) / width + 0.5
        return float(np.clip(r, 0.0, 1.0).mean())

    for z_a, z_b in ((0.0, 2.0), (0.99, 1.01), (1.02, 0.97), (0.5, 0.9), (1.1, 1.5),
                     (0.98, 0.99), (1.0, 1.0 + 1e-12)):
        assert fraction(z_a, z_b, level, width) == pytest.approx(quadrature(z_a, z_b),
                                                                 abs=1e-6)
    # deep, dry, and continuous across the surface: a level segment lowered through it
    assert fraction(-5.0, -3.0, level, width) == 1.0
    assert fraction(3.0, 5.0, level, width) == 0.0
    heights = np.linspace(level - width, level + width, 2001)
    wet = np.array([fraction(z, z + 1e-10, level, width) for z in heights])
    assert np.abs(np.diff(wet)).max() < 1.01 * (heights[1] - heights[0]) / width


def test_the_submerged_lengths_add_up_to_the_wetted_length():
    """A straight line from 3 m below the surface to 5 m above it: 3/8 of it is wet."""
    system = single_line(WIRE, Environment(water_level=0.0), 40.0, 16,
                         np.linspace([0.0, 0.0, -3.0], [0.0, 0.0, 5.0], 17),
                         Point('fixed', [0.0, 0.0, -3.0]), Point('fixed', [0.0, 0.0, 5.0]))
    sub = np.zeros(17)
    tangent = np.zeros((17, 3))
    assembly.line_passes.py_func(system.x, system.particles, system.lines_table,
                                 system.line_real, system.env, sub, tangent)
    assert sub.sum() == pytest.approx(40.0 * 3.0 / 8.0, rel=1e-12)
    assert tangent == pytest.approx(np.tile([0.0, 0.0, 1.0], (17, 1)), abs=1e-15)
    assert sub[0] == pytest.approx(1.25) and sub[-1] == 0.0


def test_a_parted_segments_halves_are_wetted_each_at_its_own_end():
    """The line above parted at the surface: each half of that segment wet at its own end."""
    x = np.linspace([0.0, 0.0, -3.0], [0.0, 0.0, 5.0], 17)
    system = single_line(WIRE, Environment(water_level=0.0), 40.0, 16, x,
                         Point('fixed', x[0]), Point('fixed', x[-1]))
    sub, parted_sub = np.zeros(17), np.zeros(17)
    tangent = np.zeros((17, 3))
    tables = (system.particles, system.lines_table, system.line_real, system.env)
    assembly.line_passes(system.x, *tables, sub, tangent)
    # segment 6, z from 0 (at the surface) to 0.5 m, parts: its rest length is now 1e300 m
    parting.part(system.particles, system.lines_table, system.particles[:, REST].copy(), 0, 6)
    assembly.line_passes(system.x, *tables, parted_sub, tangent)
    # whole, it was wet over the ramp's upper half (0.02 m of its 0.5 m rise): 1 % of 2.5 m
    whole = fluid.wetted_fraction.py_func(0.0, 0.5, 0.0, WIRE.diameter) * 2.5
    assert WIRE.diameter == 0.04 and whole == pytest.approx(0.025)
    expected = sub.copy()
    expected[6] += 0.5 * 2.5 * 0.5 - 0.5 * whole  # its end on the surface: half of 1.25 m
    expected[7] -= 0.5 * whole  # its other end 0.5 m above: dry
    assert parted_sub == pytest.approx(expected, rel=1e-12)
    assert parted_sub.sum() == pytest.approx(40.0 * 3.0 / 8.0 - whole + 0.625, rel=1e-12)


def _drag(v, q, c_n, c_t, current):
    out = np.zeros((1, 3))
    fluid.add_line_drag.py_func(v[None], 0, q[None], 0, c_n, c_t, *current, out, 0)
    return out[0]


@pytest.mark.parametrize('v, q', [
    ([0.3, -1.2, 0.5], [1.0, 0.0, 0.0]),
    ([2.0, 0.1, -0.4], [0.6, 0.0, 0.8]),
    ([0.0, 0.7, 0.7], [0.0, 0.6, 0.8]),  # mostly along the line
])
def test_the_drags_velocity_jacobian_is_its_finite_difference(v, q):
    v, q = np.array(v), np.array(q)
    c_n, c_t, current = 39.36, 1.2, (0.2, 1.0, 0.0)
    h = 0.01
    block = np.zeros((3, 3))
    fluid.add_line_drag_block.py_func(v[None], 0, q[None], 0, c_n, c_t, *current, h, block)
    numeric = np.zeros((3, 3))
    for p in range(3):
        step = np.zeros(3)
        step[p] = 1e-6
        numeric[:, p] = (_drag(v + step, q, c_n, c_t, current)
                         - _drag(v - step, q, c_n, c_t, current)) / 2e-6
    assert block == pytest.approx(-h * numeric, rel=1e-6, abs=1e-9)
    assert block == pytest.approx(block.T, abs=1e-12)
    # MoorDyn's force itself: 1/2 rho Cd d |u_n| u_n + 1/2 rho CdAx pi d |u_t| u_t
    u = np.array(current) - v
    along = (u @ q) * q
    normal = u - along
    expected = c_n * np.linalg.norm(normal) * normal + c_t * np.linalg.norm(along) * along
    assert _drag(v, q, c_n, c_t, current) == pytest.approx(expected, rel=1e-12)


def test_the_point_drags_jacobian_is_its_finite_difference():
    v = np.array([0.4, -0.3, 1.1])
    c, current, h = 250.0, (0.0, 0.8, 0.0), 0.02

    def drag(w):
        out = np.zeros((1, 3))
        fluid.add_point_drag.py_func(w[None], 0, c, *current, out, 0)
        return out[0]

    block = np.zeros((3, 3))
    fluid.add_point_drag_block.py_func(v[None], 0, c, *current, h, block)
    numeric = np.column_stack([(drag(v + e) - drag(v - e)) / 2e-6 for e in np.eye(3) * 1e-6])
    assert block == pytest.approx(-h * numeric, rel=1e-6)


def test_the_added_mass_inverse_is_the_inverse():
    q = np.array([[0.48, -0.6, 0.64]])
    a, b, weight = 3.1, -1.4, 2.2
    mass = a * np.eye(3) + b * np.outer(q[0], q[0])
    block = np.zeros((3, 3))
    fluid.add_mass_block.py_func(a, b, q, 0, block)
    assert block == pytest.approx(mass, rel=1e-15)
    force = np.array([[4.0, -2.0, 7.0]])
    gravity = np.array([0.0, 0.0, -G])
    out = force.copy()
    fluid.accelerate.py_func(a, b, q, 0, weight, gravity, out, 0)
    assert out[0] == pytest.approx(np.linalg.solve(mass, force[0] + weight * gravity),
                                   rel=1e-13)


# -- whole lines -------------------------------------------------------------------------

@pytest.mark.parametrize('segments', [20, 50])
def test_a_buoyant_line_arches_up_as_an_upside_down_catenary(segments):
    """Polyester 64 mm wholly under water: its net weight -6.84 N/m points up."""
    environment = Environment(gravity=GRAVITY, water_level=100.0)
    area = math.pi * 0.064 ** 2 / 4.0
    lift = (RHO * area - 2.6) * G  # upward net load per metre
    assert lift == pytest.approx(6.841648, rel=1e-6)
    # start from a line sagging down (its shape in air), so that it has to turn over
    start = chain_equilibrium(A, B, 40.0, segments, 2.6 * G, 5.0e7, GRAVITY)
    system = single_line(POLYESTER, environment, 40.0, segments, start.positions,
                         Point('fixed', A), Point('fixed', B))
    _settle(system)
    arch = chain_equilibrium(A, B, 40.0, segments, lift, 5.0e7, (0.0, 0.0, G))
    forces = system.end_forces()[0]
    assert forces[0] == pytest.approx(arch.force_a, rel=1e-6, abs=1e-6)
    assert forces[1] == pytest.approx(arch.force_b, rel=1e-6, abs=1e-6)
    assert system.x == pytest.approx(arch.positions, abs=1e-6)
    # it rose above the chord: the top of the arch 3.4 m over the chord's middle
    assert system.x[:, 2].max() > 11.0
    # the whole line's net lift is what the ends hold down
    assert forces[0, 2] + forces[1, 2] == pytest.approx(lift * 40.0, rel=1e-9)


@pytest.mark.parametrize('tangential_drag', [0.0, 0.008])
def test_a_taut_line_in_a_current_deflects_by_the_drag_balance(tangential_drag):
    """
    A neutrally buoyant line held taut across a current of 1 m/s.

    Drag per unstretched metre f = 1/2 rho Cd d U^2 across it, f L / S per metre of span
    S; the tension H holds it in a parabola of depth f L S / (8 H), each end holding f L / 2.
    """
    d, cd, speed, span = 0.064, 1.2, 1.0, 40.2
    neutral = math.sqrt(4.0 * 2.6 / (math.pi * RHO))  # displaces its own mass
    line_type = LineType(mass_per_length=2.6, axial_stiffness=5.0e6, axial_damping=2000.0,
                         diameter=d, volume_diameter=neutral, normal_drag=cd,
                         tangential_drag=tangential_drag)
    environment = Environment(gravity=GRAVITY, water_level=50.0, current=(0.0, speed, 0.0))
    end_b = [span, 0.0, 0.0]
    system = single_line(line_type, environment, 40.0, 20, np.linspace(A, end_b, 21),
                         Point('fixed', A), Point('fixed', end_b))
    _settle(system)
    forces = system.end_forces()[0]
    f = 0.5 * RHO * cd * d * speed ** 2
    # the line turns by at most 3 degrees: the normal drag falls by cos^3 at most 0.4 %
    assert forces[0, 1] == pytest.approx(0.5 * f * 40.0, rel=3e-3)
    assert forces[1, 1] == pytest.approx(forces[0, 1], rel=1e-9)
    horizontal = forces[0, 0]
    depth = system.x[:, 1].max()
    assert depth == pytest.approx(f * 40.0 * span / (8.0 * horizontal), rel=5e-3)
    assert depth > 0.3  # downstream
    # no net vertical load: buoyancy balances the weight
    assert np.abs(forces[:, 2]).max() < 1e-6 * horizontal
    # the same line without the current lies straight
    system.set_current([0.0, 0.0, 0.0])
    _settle(system)
    assert np.abs(system.x[:, 1]).max() < 1e-9


def _payload(added_mass):
    """Hang a 2 t, 1 m^3 payload on a 10 m, 10 kg line of 1e6 N EA, wholly under water."""
    environment = Environment(gravity=GRAVITY, water_level=10.0)
    light = LineType(mass_per_length=1.0, axial_stiffness=1.0e6, axial_damping=100.0)
    system = System(environment)
    system.add_point(Point('fixed', [0.0, 0.0, 0.0]))
    system.add_point(Point('free', [0.0, 0.0, -10.0], mass=2000.0, volume=1.0,
                           added_mass=added_mass))
    system.add_line(Line.uniform(light, 10.0, 10, np.linspace([0.0, 0.0, 0.0],
                                                              [0.0, 0.0, -10.0], 11), (0, 1)))
    system.pack()
    return system


@pytest.mark.parametrize('integrator, dt', [('improved_euler', 1e-4),
                                            ('implicit_euler', 5e-4)])
def test_added_mass_slows_a_hanging_payloads_heave_by_the_mass_ratio(integrator, dt):
    periods = []
    for added_mass in (0.0, 1.0):
        system = _payload(added_mass)
        _settle(system)
        # hanging still: the line holds the payload's weight less its buoyancy, and its own
        hold = (2000.0 - RHO * 1.0 + 10.0) * G
        assert system.end_forces()[0, 0, 2] == pytest.approx(-hold, rel=1e-9)
        rest = system.point_x[1, 2]
        assert rest == pytest.approx(-10.0 - (2000.0 - RHO + 5.0) * G * 10.0 / 1.0e6,
                                     abs=1e-4)
        # pulled 5 cm down, the line stretched evenly with it
        system.point_x[1, 2] -= 0.05
        system.lines[0].x[:, 2] += np.linspace(0.0, -0.05, 11)
        assembly.set_ends(system.x, system.v, system.lines_table, system.point_x,
                          system.point_v)
        steps = int(round(0.005 / dt))
        drive_x, drive_v = system.drive_arrays(steps)
        t, z = [], []
        for k in range(1000):
            step(system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS)
            t.append((k + 1) * 0.005)
            z.append(system.point_x[1, 2] - rest)
        t, z = np.array(t), np.array(z)
        up = np.flatnonzero((z[:-1] < 0.0) & (z[1:] >= 0.0))
        times = t[up] - z[up] * 0.005 / (z[up + 1] - z[up])
        periods.append(np.mean(np.diff(times)))
    # the line's own 10 kg adds a third of itself to the mass that moves
    # (both within 5e-6 measured, with both integrators)
    moving = 2000.0 + 10.0 / 3.0
    assert periods[0] == pytest.approx(2.0 * math.pi * math.sqrt(moving / 1.0e5), rel=2e-4)
    assert periods[0] / periods[1] == pytest.approx(
        math.sqrt(moving / (moving + RHO * 1.0)), rel=2e-4)


def test_a_line_lowered_through_the_surface_gains_its_buoyancy_without_a_jump():
    """
    A vertical 10 m line held taut between two points lowered together at 0.5 m/s.

    The vertical force of the line on both points together is its weight less its
    buoyancy; each particle crossing the surface at once would step it by rho g A_v l
    (a tenth of the whole change).
    """
    environment = Environment(gravity=GRAVITY, water_level=0.0)
    line_type = LineType(mass_per_length=2.6, axial_stiffness=5.0e7, axial_damping=2903.43,
                         diameter=0.064, volume_diameter=0.064, normal_drag=1.2,
                         normal_added_mass=1.0)
    bottom, top = np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 11.005])
    system = single_line(line_type, environment, 10.0, 10, np.linspace(bottom, top, 11),
                         Point('driven', bottom), Point('driven', top))
    _settle(system)
    dt, every, speed = 1e-3, 10, 0.5
    duration = 26.0
    n = int(round(duration / dt))
    t = np.arange(1, n + 1) * dt
    ramp = 2.0  # half-cosine start of the speed over the first 2 s
    drop = np.where(t < ramp, speed * (t - ramp / math.pi * np.sin(math.pi * t / ramp)) / 2.0,
                    speed * (t - ramp / 2.0))
    rate = np.where(t < ramp, speed * (1.0 - np.cos(math.pi * t / ramp)) / 2.0, speed)
    drive_x = np.zeros((n, 2, 3))
    drive_v = np.zeros((n, 2, 3))
    for e, start in enumerate((bottom, top)):
        drive_x[:, e] = start
        drive_x[:, e, 2] -= drop
        drive_v[:, e, 2] = -rate
    vertical = []
    for k in range(0, n, every):
        step(system, 'implicit_euler', dt, drive_x[k:k + every], drive_v[k:k + every],
             MAX_ITERATIONS)
        forces = system.end_forces()[0]
        vertical.append(forces[0, 2] + forces[1, 2])
    vertical = np.array(vertical)
    buoyancy = RHO * math.pi * 0.064 ** 2 / 4.0 * 10.0 * G
    assert vertical[0] == pytest.approx(-(2.6 - 1.225 * math.pi * 0.064 ** 2 / 4.0) * 10.0 * G,
                                        rel=1e-3)
    assert vertical[-1] - vertical[0] == pytest.approx(buoyancy * (1.0 - 1.225 / RHO),
                                                       rel=2e-3)
    # 5 mm per output: 5e-4 of the change (5.0e-4 measured); a particle at a time would
    # step by 0.1
    assert np.abs(np.diff(vertical)).max() < 1e-3 * buoyancy


def _heave_run(integrator, dt, payload):
    """Heave the wire's fairlead under water by 1.5 m over 8 s for 6 s; return |F_B| (10 ms)."""
    environment = Environment(gravity=GRAVITY, water_level=100.0, current=(0.0, 0.3, 0.0))
    segments = 10 if payload else 20
    if payload:
        system = System(environment)
        system.add_point(Point('free', [30.0, 0.0, -10.0], mass=300.0, volume=0.2,
                               drag_area=0.8, added_mass=0.5))
        system.add_point(Point('driven', B))
        start = np.linspace([30.0, 0.0, -10.0], B, segments + 1)
        system.add_line(Line.uniform(WIRE, 20.0, segments, start, (0, 1)))
        system.pack()
    else:
        start = chain_equilibrium(A, B, 40.0, segments, 51.1292, 1.0e8, GRAVITY).positions
        system = single_line(WIRE, environment, 40.0, segments, start, Point('fixed', A),
                             Point('driven', B))
    _settle(system)
    every = int(round(0.01 / dt))
    n = 600 * every
    t = np.arange(1, n + 1) * dt
    ramp = 0.5 * (1.0 - np.cos(np.pi * np.minimum(t / 8.0, 1.0)))
    omega = 2.0 * np.pi / 8.0
    drive_x, drive_v = system.drive_arrays(n)
    drive_x[:, 1, 2] += 1.5 * np.sin(omega * t) * ramp
    drive_v[:, 1, 2] = 1.5 * omega * np.cos(omega * t) * ramp  # the ramp's own rate is small
    force = []
    for k in range(0, n, every):
        step(system, integrator, dt, drive_x[k:k + every], drive_v[k:k + every],
             MAX_ITERATIONS)
        force.append(np.linalg.norm(system.end_forces()[0, 1]))
    return np.array(force)


@pytest.mark.parametrize('payload', [False, True])
def test_both_integrators_agree_on_a_line_heaving_in_the_water(payload):
    explicit = _heave_run('improved_euler', 1e-4, payload)
    implicit = _heave_run('implicit_euler', 2e-4, payload)
    span = explicit.max() - explicit.min()
    assert span > 20.0  # the heave and the drag load the line
    # 1.4e-4 (line alone) and 4.3e-4 (with the payload) measured
    assert np.sqrt(np.mean((implicit - explicit) ** 2)) < 2e-3 * span


def test_set_current_changes_the_drag_in_place():
    environment = Environment(gravity=GRAVITY, water_level=100.0)
    start = chain_equilibrium(A, B, 40.0, 20, 51.1292, 1.0e8, GRAVITY).positions
    system = single_line(WIRE, environment, 40.0, 20, start, Point('fixed', A),
                         Point('fixed', B))
    arrays = system.arrays
    before, _ = system.loads()
    system.set_current([0.0, 1.0, 0.0])
    assert system.arrays is arrays  # nothing rebuilt
    after, _ = system.loads()
    # at rest in a current of 1 m/s across the line, each end particle (1 m of it) feels
    # its drag at once
    drag = 0.5 * RHO * 1.2 * 0.04 * 1.0 ** 2 * 1.0
    assert after[:, :, 1] - before[:, :, 1] == pytest.approx(np.full((1, 2), drag),
                                                             rel=1e-9)
    assert system.environment.current == (0.0, 1.0, 0.0)
    with pytest.raises(ValueError, match='current'):
        system.set_current([0.0, math.nan, 0.0])


@pytest.mark.parametrize('values, name', [
    ({'water_level': math.nan}, 'water_level'),
    ({'seabed_level': math.inf}, 'seabed_level'),
    ({'water_density': -1.0}, 'water_density'),
    ({'current': (0.0, 1.0)}, 'current'),
    ({'quay_normal': (0.0, 0.0, 1.0)}, 'quay_normal'),
])
def test_an_environment_names_what_is_wrong(values, name):
    with pytest.raises(ValueError, match=name):
        Environment(**values)
