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

"""A rigid body stepped with its lines: at rest, free decay, energy, fenders, a light boat."""

import math

import numpy as np
import pytest

from rope_sim_ros.model.body import Body, Fender
from rope_sim_ros.model.forces.fender import reaction
from rope_sim_ros.model.frames import rotation_matrix
from rope_sim_ros.model.objects import Environment, Line, LineType, Point, System
from rope_sim_ros.params.ship import ShipParams
from rope_sim_ros.stepping.kernels import run_kernel

SHIP = ShipParams()  # the default ship: a loaded 225 m Panamax bulk carrier
WATER = 1025.0
G = 9.81
INTEGRATORS = ('improved_euler', 'implicit_euler')


def ship(damping=(0.0,) * 6, yaw=0.3, position=(0.0, 0.0, 0.0)) -> Body:
    """Return the default ship at rest at `position`, heading `yaw` (linear damping given)."""
    zeros = [0.0] * 6
    return Body.ship(SHIP.mass, SHIP.center_of_gravity, SHIP.radii_of_gyration, SHIP.added_mass,
                     damping, zeros, SHIP.waterplane_area,
                     SHIP.metacentric_height, position, yaw,
                     (SHIP.length, SHIP.beam, SHIP.draft), WATER, G)


def run(system: System, integrator: str, dt: float, steps: int) -> None:
    """Take `steps` steps of dt (no driven points)."""
    drive = np.zeros((steps, len(system.points), 3))
    run_kernel(system, integrator, dt, drive, drive.copy(), 10, False, True)


def crossings(values: np.ndarray, dt: float) -> float:
    """Return the mean period between upward zero crossings of a sampled signal [s]."""
    up = np.flatnonzero((values[:-1] < 0.0) & (values[1:] >= 0.0))
    # linear interpolation of each crossing's time
    times = (up + values[up] / (values[up] - values[up + 1])) * dt
    return float(np.diff(times).mean())


def tilt(body: Body, axis: int, angle: float) -> None:
    """Turn the body about its own axis (0 roll, 1 pitch) by angle [rad] (in place)."""
    half = 0.5 * angle
    turn = np.zeros(4)
    turn[axis] = math.sin(half)
    turn[3] = math.cos(half)
    x, y, z, w = body.quaternion
    a, b, c, d = turn
    body.quaternion[:] = [w * a + x * d + y * c - z * b, w * b - x * c + y * d + z * a,
                          w * c + x * b - y * a + z * d, w * d - x * a - y * b - z * c]


@pytest.mark.parametrize('integrator', INTEGRATORS)
def test_a_ship_without_lines_holds_its_start_pose(integrator):
    system = System(Environment(water_level=0.0))
    system.add_body(ship())
    system.pack()
    before = system.body_table.copy()
    run(system, integrator, 0.01, 2000)
    assert np.abs(system.body_table[:, :13] - before[:, :13]).max() <= 1e-12


@pytest.mark.parametrize('mode, axis, offset', [('heave', 2, 0.5), ('roll', 0, math.radians(2)),
                                                ('pitch', 1, math.radians(0.3))])
def test_free_decay_periods_follow_mass_added_mass_and_hydrostatics(mode, axis, offset):
    """T = 2 pi sqrt((M + A) / K), K = rho g A_wp, m g GM_T, m g GM_L."""
    body = ship(yaw=0.0)
    if mode == 'heave':
        body.position[2] += offset
        inertia, stiffness = SHIP.mass + SHIP.added_mass[2], WATER * G * SHIP.waterplane_area
    else:
        tilt(body, axis, offset)
        k = SHIP.radii_of_gyration[axis]
        inertia = SHIP.mass * k * k + SHIP.added_mass[3 + axis]
        stiffness = SHIP.mass * G * SHIP.metacentric_height[axis]
    system = System(Environment(water_level=0.0))
    system.add_body(body)
    system.pack()
    dt, samples = 0.02, []
    for _ in range(2500):  # 50 s: several periods of each
        run(system, 'improved_euler', dt, 1)
        if mode == 'heave':
            samples.append(body.origin_pose()[0][2])
        else:  # the tilt about that body axis: the z of the other axis's unit vector
            turned = rotation_matrix(body.quaternion)
            samples.append(turned[2, 1] if axis == 0 else -turned[2, 0])
    expected = 2.0 * math.pi * math.sqrt(inertia / stiffness)
    assert crossings(np.array(samples), dt) == pytest.approx(expected, rel=0.005)


def moored_boat(mass=2.0e5, ea=2.0e7, damping=0.0, segments=10, speed=0.0, length=24.9):
    """
    Return a System: a 30 m boat on one taut line ahead of it, in air (no dampers).

    The boat surges at `speed` [m/s] (+: toward the bollard, slackening the line).
    """
    boat = Body(mass, (mass * 3.0 ** 2, mass * 8.0 ** 2, mass * 8.0 ** 2),
                restoring=(1025 * G * 200.0, mass * G * 1.5, mass * G * 30.0),
                hull=(30.0, 8.0, 2.0), linear_damping=(damping,) * 6,
                velocity=(speed, 0.0, 0.0))
    system = System(Environment(air_density=0.0))
    system.add_body(boat)
    line_type = LineType(mass_per_length=2.0, axial_stiffness=ea, axial_damping=0.0)
    bollard = np.array([40.0, 0.0, 2.0])
    fairlead = np.array([15.0, 0.0, 2.0])
    system.add_point(Point('fixed', bollard))
    system.add_point(Point('carried', fairlead, body=0, offset=fairlead))
    chord = np.linspace(bollard, fairlead, segments + 1)
    system.add_line(Line.uniform(line_type, length, segments, chord, (0, 1)))
    system.pack()
    return system, boat


def test_energy_is_kept_to_the_integrators_order():
    """
    With every damper off, improved Euler's energy error falls with its step, as its order.

    The boat surges away from the bollard; the line stops it and pulls it back. (Improved
    Euler amplifies an undamped oscillation by about (w h)^4 / 8 a step: its error in energy
    is third order in the step over a fixed time.)
    """
    drifts = []
    for dt in (4e-4, 2e-4):
        system, _ = moored_boat(ea=2.0e6, segments=5, speed=-0.3)
        start = sum(system.energy())
        run(system, 'improved_euler', dt, int(round(4.0 / dt)))
        drifts.append(abs(sum(system.energy()) - start) / start)
    assert drifts[0] < 1e-5
    assert drifts[0] / drifts[1] > 3.5  # at least second order


def test_a_fender_pressed_by_a_constant_load_compresses_to_its_curve():
    # sway damped near critically on the fenders (2 sqrt(k m)), so that 200 s settle it
    damping = list(SHIP.linear_damping)
    damping[1] = 4.0e7
    body = ship(damping=damping, yaw=0.0, position=(0.0, -17.6, 0.0))
    curve = ((0.0, 0.0), (0.25, 2.0e5), (0.5, 5.0e5), (1.0, 1.2e6), (1.5, 1.6e6))
    system = System(Environment(water_level=0.0))
    system.add_body(body)
    # two fenders on the quay face (y = 0), their faces 1.5 m out: just touching the port side
    for x in (-40.0, 40.0):
        system.add_fender(Fender((x, -1.5, 0.0), (0.0, -1.0, 0.0), curve, 0.2))
    system.pack()
    push = 1.6e6  # toward the quay: each fender takes half, 0.8 MN
    system.body_table[0, 52:58] = [0.0, push, 0.0, 0.0, 0.0, 0.0]
    run(system, 'implicit_euler', 0.05, 4000)  # 200 s: the sway settles
    # the port side's y past the fenders' faces (y = -1.5)
    compression = body.origin_pose()[0][1] + 0.5 * SHIP.beam + 1.5
    fender = Fender((0.0, 0.0, 0.0), (0.0, -1.0, 0.0), curve).row()
    expected = 0.5 + 0.5 * (0.8e6 - 5.0e5) / (1.2e6 - 5.0e5)  # 0.714 m on the curve
    assert reaction(fender, expected)[0] == pytest.approx(0.8e6)
    assert compression == pytest.approx(expected, abs=1e-3)
    assert abs(system.body_table[0, 8]) < 1e-4  # at rest


def test_a_stiff_line_on_a_light_boat_steps_stably_in_the_implicit_step():
    """
    A 2 t boat on 25 m of steel wire (EA 1e9: about 200 Hz on the boat), drifting off.

    The implicit step at a hundred times the explicit one's stable step follows improved
    Euler's run at that stable step: the body is in the implicit step, not a load from the
    step before (which at this step would ring the boat up without end).
    """
    places = []
    for integrator, dt in (('improved_euler', 2e-5), ('implicit_euler', 2e-3)):
        system, boat = moored_boat(mass=2.0e3, ea=1.0e9, damping=1.0e3, speed=-0.2,
                                   length=25.0)
        run(system, integrator, dt, int(round(2.0 / dt)))
        assert np.isfinite(system.body_table[:, :13]).all()
        assert np.linalg.norm(system.end_forces()[0, 1]) < 2.0e4  # its weight's pull, not MN
        places.append(boat.position.copy())
    assert np.abs(places[1] - places[0]).max() < 0.05
