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

"""Systems of several lines sharing points: a bridle, a shared anchor, both integrators."""

import numpy as np
import pytest

from rope_sim_ros.model.objects import Environment, Line, LineType, Point, System
from rope_sim_ros.model.record import FIELDS, SystemArrays
from rope_sim_ros.model.rope import RopeProperties
from rope_sim_ros.model.superelastic import MAX_ITERATIONS
from rope_sim_ros.stepping.kernels import run_kernel
from rope_sim_ros.stepping.rules import automatic_time_step
from rope_sim_ros.stepping.step import step

G = 9.81
WIRE = LineType(mass_per_length=6.5, axial_stiffness=1.0e8, axial_damping=8000.0)
ENVIRONMENT = Environment(gravity=(0.0, 0.0, -G))


def _straight(a, b, segments):
    return np.linspace(a, b, segments + 1)


def _step_of(line_type, length, segments, integrator):
    props = RopeProperties(segments, length, line_type.mass_per_length,
                           line_type.axial_stiffness, line_type.axial_damping)
    return automatic_time_step(props, ENVIRONMENT, integrator)


def _run(system, integrator, dt, duration):
    steps = int(round(duration / dt))
    drive_x, drive_v = system.drive_arrays(100)
    for _ in range(steps // 100):
        step(system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS)


def _settle(system):
    """Newton-like pseudo-steps: implicit steps of 1 s from rest (as integrators.relax)."""
    drive_x, drive_v = system.drive_arrays(1)
    for _ in range(60):
        system.v[:] = 0.0
        system.point_v[:] = 0.0
        step(system, 'implicit_euler', 1.0, drive_x, drive_v, MAX_ITERATIONS)
    system.v[:] = 0.0
    system.point_v[:] = 0.0


def _bridle(mass=2000.0, segments=10):
    """Two 20 m wires from anchors 24 m apart to one free point (a hanging mass)."""
    system = System(ENVIRONMENT)
    left = system.add_point(Point('fixed', [-12.0, 0.0, 30.0]))
    right = system.add_point(Point('fixed', [12.0, 0.0, 30.0]))
    knot = system.add_point(Point('free', [0.0, 0.0, 14.0], mass=mass))
    for anchor in (left, right):
        start = system.points[anchor].position
        system.add_line(Line.uniform(WIRE, 20.0, segments,
                                     _straight(start, [0.0, 0.0, 14.0], segments),
                                     (anchor, knot)))
    system.pack()
    return system, knot


@pytest.mark.parametrize('integrator', ['improved_euler', 'implicit_euler'])
def test_a_bridle_holds_its_mass_as_the_force_balance_says(integrator):
    system, knot = _bridle()
    _settle(system)
    dt = _step_of(WIRE, 20.0, 10, integrator)
    _run(system, integrator, dt, 2.0)  # and it stays there
    assert np.abs(system.point_v[knot]).max() < 1e-6
    forces = system.end_forces()
    # the anchors hold everything: the mass, both lines
    total = (2000.0 + 2 * 6.5 * 20.0) * G
    lift = -(forces[0, 0, 2] + forces[1, 0, 2])
    assert lift == pytest.approx(total, rel=1e-6)
    # on the free point: the lines' pulls (their half segments' weights in) and its own
    # weight balance
    on_knot = forces[0, 1] + forces[1, 1] + [0.0, 0.0, -2000.0 * G]
    assert np.abs(on_knot).max() < 1e-6 * total
    # symmetric, and each line's tension along its chord as statics says: the pull at the
    # knot has the line's direction there, with H equal on both sides
    assert forces[0, 1, 0] == pytest.approx(-forces[1, 1, 0], rel=1e-6)
    assert system.point_x[knot, 0] == pytest.approx(0.0, abs=1e-6)
    # the knot sits where the two stretched lines (catenaries, nearly straight) meet:
    # 20 m each, 24 m apart, so 16 m below the anchors, lowered by the stretch
    drop = 30.0 - system.point_x[knot, 2]
    stretch = np.linalg.norm(forces[0, 1]) * 20.0 / WIRE.axial_stiffness
    assert drop == pytest.approx(np.sqrt((20.0 + stretch) ** 2 - 12.0 ** 2), rel=2e-3)


def test_two_lines_share_a_fixed_point():
    """Two lines from one anchor, to two fixed points: each as if alone."""
    system = System(ENVIRONMENT)
    anchor = system.add_point(Point('fixed', [0.0, 0.0, 0.0]))
    a = system.add_point(Point('fixed', [18.0, 0.0, 4.0]))
    b = system.add_point(Point('fixed', [0.0, -15.0, 8.0]))
    alone = []
    for end, segments in ((a, 10), (b, 14)):
        shape = _straight([0.0, 0.0, 0.0], system.points[end].position, segments)
        system.add_line(Line.uniform(WIRE, 20.0, segments, shape, (anchor, end)))
        single = System(ENVIRONMENT)
        single.add_point(Point('fixed', [0.0, 0.0, 0.0]))
        single.add_point(Point('fixed', system.points[end].position))
        single.add_line(Line.uniform(WIRE, 20.0, segments, shape, (0, 1)))
        single.pack()
        alone.append(single)
    system.pack()
    dt = _step_of(WIRE, 20.0, 14, 'implicit_euler')
    _settle(system)
    _run(system, 'implicit_euler', dt, 2.0)
    forces = system.end_forces()
    for k, single in enumerate(alone):
        _settle(single)
        _run(single, 'implicit_euler', dt, 2.0)
        assert system.lines[k].x == pytest.approx(single.lines[0].x, abs=1e-12)
        assert forces[k] == pytest.approx(single.end_forces()[0], rel=1e-12, abs=1e-9)
    # the anchor carries both lines' pulls; each line's weight splits between its ends
    weight = 6.5 * 20.0 * G
    for k in range(2):
        assert -(forces[k, 0, 2] + forces[k, 1, 2]) == pytest.approx(weight, rel=1e-6)


def test_explicit_and_implicit_agree_on_a_swinging_bridle():
    """The bridle's mass pushed sideways: 4 s of swing, the knot's path in both steps."""
    paths = {}
    for integrator in ('improved_euler', 'implicit_euler'):
        system, knot = _bridle(mass=500.0)
        _settle(system)
        system.point_v[knot] = [0.0, 1.0, 0.0]
        dt = _step_of(WIRE, 20.0, 10, integrator)
        dt = 0.01 / np.ceil(0.01 / dt)
        path = []
        for _ in range(400):
            drive_x, drive_v = system.drive_arrays(int(round(0.01 / dt)))
            step(system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS)
            path.append(system.point_x[knot].copy())
        paths[integrator] = np.array(path)
    swing = np.abs(paths['improved_euler'][:, 1]).max()
    assert swing > 0.3
    # 0.3 % of the swing measured
    assert np.abs(paths['implicit_euler'] - paths['improved_euler']).max() < 0.02 * swing


@pytest.mark.parametrize('integrator', ['improved_euler', 'implicit_euler'])
def test_a_bridle_under_water_holds_its_mass_less_what_everything_displaces(integrator):
    """The bridle sunk in still water: the anchors hold the submerged weights only."""
    wet_wire = LineType(mass_per_length=6.5, axial_stiffness=1.0e8, axial_damping=8000.0,
                        diameter=0.04, normal_drag=1.2, tangential_drag=0.008,
                        normal_added_mass=1.0)
    system = System(Environment(gravity=(0.0, 0.0, -G), water_level=100.0,
                                current=(0.0, 0.2, 0.0)))
    left = system.add_point(Point('fixed', [-12.0, 0.0, 30.0]))
    right = system.add_point(Point('fixed', [12.0, 0.0, 30.0]))
    knot = system.add_point(Point('free', [0.0, 0.0, 14.0], mass=2000.0, volume=0.5,
                                  drag_area=1.0, added_mass=0.5))
    for anchor in (left, right):
        start = system.points[anchor].position
        system.add_line(Line.uniform(wet_wire, 20.0, 10,
                                     _straight(start, [0.0, 0.0, 14.0], 10),
                                     (anchor, knot)))
    system.pack()
    _settle(system)
    dt = _step_of(WIRE, 20.0, 10, integrator)
    _run(system, integrator, dt, 1.0)  # and it stays there
    assert np.abs(system.point_v[knot]).max() < 1e-6
    forces = system.end_forces()
    area = np.pi * 0.04 ** 2 / 4.0
    submerged = (2000.0 - 1025.0 * 0.5 + 2 * (6.5 - 1025.0 * area) * 20.0) * G
    # (the drag of the lines turned a little by the current has a vertical part: 4e-6)
    assert -(forces[0, 0, 2] + forces[1, 0, 2]) == pytest.approx(submerged, rel=1e-5)
    # the current pushes it all downstream: the anchors hold the whole drag, the knot's
    # 1/2 rho CdA U^2 and the lines'
    drag = forces[0, 0, 1] + forces[1, 0, 1]
    knot_drag = 0.5 * 1025.0 * 1.0 * 0.2 ** 2
    lines_drag = 0.5 * 1025.0 * 1.2 * 0.04 * 0.2 ** 2 * 40.0
    assert drag == pytest.approx(knot_drag + lines_drag, rel=0.01)
    assert system.point_x[knot, 1] > 0.0


def _two_hanging_wires():
    """Two wires, each from a fixed point to a driven one, sagging; the second one jerked."""
    system = System(ENVIRONMENT)
    for k, y in enumerate((0.0, 10.0)):
        a = system.add_point(Point('fixed', [0.0, y, 0.0]))
        b = system.add_point(Point('driven', [19.0, y, 0.0]))
        shape = _straight([0.0, y, 0.0], [19.0, y, 0.0], 10)
        shape[1:-1, 2] -= 0.5 * np.sin(np.pi * np.arange(1, 10) / 10)
        system.add_line(Line.uniform(WIRE, 20.0, 10, shape, (a, b)))
    system.pack()
    return system


def test_a_line_view_steps_its_line_in_the_system_and_no_other():
    # the adaptive integrator's improved Euler steps of one snapping line in a berth
    whole, alone = _two_hanging_wires(), _two_hanging_wires()
    steps, dt = 200, 1e-4
    drive_x, drive_v = whole.drive_arrays(steps)
    drive_v[:, 3, 0] = 2.0  # the second line's driven end pulled away at 2 m/s
    drive_x[:, 3, 0] += 2.0 * dt * np.arange(1, steps + 1)
    step(whole, 'improved_euler', dt, drive_x, drive_v, MAX_ITERATIONS)
    view = alone.line_view(1)
    run_kernel(view, 'improved_euler', dt, *view.drive(drive_x, drive_v), MAX_ITERATIONS,
               False, True)
    view.store_points(alone)
    rows = slice(11, 22)
    assert np.abs(whole.end_forces()[1]).max() > 2.0 * np.abs(alone.end_forces()[0]).max()
    np.testing.assert_array_equal(alone.x[rows], whole.x[rows])
    np.testing.assert_array_equal(alone.v[rows], whole.v[rows])
    np.testing.assert_array_equal(alone.point_x, whole.point_x)
    np.testing.assert_array_equal(alone.line_real[1], whole.line_real[1])
    # the first line was not stepped: where it was packed, at rest
    np.testing.assert_array_equal(alone.x[:11], _two_hanging_wires().x[:11])
    np.testing.assert_array_equal(alone.v[:11], 0.0)


def test_the_kernels_record_holds_the_systems_own_arrays_and_is_made_anew_with_its_tables():
    system = _two_hanging_wires()
    arrays = system.arrays
    own = (system.x, system.v, system.point_x, system.point_v, system.accel,
           system.point_accel, system.particles, system.lines_table, system.line_real,
           system.points_table, system.env, system.body_table, system.fender_table)
    assert all(getattr(arrays, name) is array for name, array in zip(FIELDS, own))
    # a compiled step writes the System's state through the record
    before = system.x.copy()
    drive_x, drive_v = system.drive_arrays(10)
    drive_x[:, 3, 0] += 0.01 * np.arange(1, 11)
    step(system, 'implicit_euler', 1e-3, drive_x, drive_v, MAX_ITERATIONS)
    assert system.x[11:22, 0].max() - before[11:22, 0].max() == pytest.approx(0.1)
    assert np.abs(system.accel[12:21]).max() > 0.0
    system.refresh()  # new tables, a new record of them
    assert system.arrays is not arrays
    assert system.arrays.particles is system.particles and system.arrays.x is system.x
    with pytest.raises(TypeError, match=r'a SystemArrays takes 13 arrays \(x, v, point_x'):
        SystemArrays(system.x, system.v)
