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
A free ship with a hydrodynamic database: the Cummins equation in the step.

Its decay and its forced motion against the frequency-domain solution of the same A(omega),
B(omega), mass and stiffness (test/hydro_cases.py's barge), with both integrators; a ship
without a database as before, to the bit.
"""

import math
from pathlib import Path

from hydro_cases import (database, heave_poles, MASS, METACENTRIC, RADII, rigid_mass,
                         stiffness, transfer, WATER, WATERPLANE)
import numpy as np
import pytest

from rope_sim_ros.model.body import Body, clear_memory, Fender
from rope_sim_ros.model.frames import rotation_matrix
from rope_sim_ros.model.layout import (BODY_CLOCK, BODY_LOAD, BODY_LOAD_RATE, BODY_MODE,
                                       BODY_MODES, MODE_COLUMNS, MODE_STATE)
from rope_sim_ros.model.objects import Environment, System
from rope_sim_ros.model.ship.radiation import consistent_added_mass
from rope_sim_ros.stepping.adaptive import NEWMARK
from rope_sim_ros.stepping.kernels import run_kernel

G = 9.81
# improved Euler, and the implicit step as the adaptive integrator takes it (Newmark's gamma a
# little past 1/2: implicit Euler's own damping, omega h / 2 of critical, 0.6 % at 0.01 s,
# would be a seventh of the barge's heave damping)
INTEGRATORS = ('improved_euler', 'implicit')
DATABASE = database()
DATA = Path(__file__).parent / 'data'
# [N s/m, N m s] viscous damping, added to the memory's: holds surge, sway and yaw (no
# restoring), damps roll some 10 % and pitch 5 % of critical; heave has the memory's alone
VISCOUS = (2.0e5, 2.0e5, 0.0, 1.7e7, 2.2e8, 5.0e8)


def barge(hydrodynamics=DATABASE, damping=VISCOUS) -> Body:
    """Return the barge at rest, its centre of gravity at its origin on the waterline."""
    return Body.ship(MASS, (0.0, 0.0, 0.0), RADII, (0.0,) * 6, damping, (0.0,) * 6,
                     WATERPLANE, METACENTRIC, (0.0, 0.0, 0.0), 0.0, (60.0, 15.0, 4.0), WATER,
                     G, hydrodynamics=hydrodynamics)


def system_of(body: Body) -> System:
    """Return a System of the body alone in water."""
    system = System(Environment(water_level=0.0))
    system.add_body(body)
    system.pack()
    return system


def steps(system: System, integrator: str, dt: float, n: int) -> None:
    """Take n steps of dt (INTEGRATORS: 'implicit' is Newmark's step of the adaptive one)."""
    drive = np.zeros((n, len(system.points), 3))
    if integrator == 'implicit':
        run_kernel(system, 'implicit_euler', dt, drive, drive.copy(), 10, False, True, NEWMARK)
    else:
        run_kernel(system, integrator, dt, drive, drive.copy(), 10, False, True)


def motions(body: Body) -> np.ndarray:
    """Return its six motions: the centre of gravity [m], roll, pitch, yaw (Z-Y-X) [rad]."""
    x, y, z, w = body.quaternion
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(min(max(2.0 * (w * y - z * x), -1.0), 1.0))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return np.concatenate((body.position, [roll, pitch, yaw]))


def heave_frequency() -> float:
    """Return the natural frequency of heave: k - omega^2 (m + A33(omega)) = 0 [rad/s]."""
    k = WATER * G * WATERPLANE
    omega = math.sqrt(k / (MASS + DATABASE.added_mass_infinite[2, 2]))
    for _ in range(100):  # fixed point, A33 smooth
        added = DATABASE.added_mass_infinite[2, 2] + transfer([omega])[0, 2, 2].imag / omega
        omega = math.sqrt(k / (MASS + added))
    return omega


@pytest.mark.parametrize('integrator', INTEGRATORS)
def test_heave_decay_has_the_frequency_domain_period_and_damping(integrator):
    """
    Released 0.3 m high, the barge heaves as the frequency domain says.

    At T = 2 pi / omega_n, k = omega_n^2 (m + A(omega_n)), its amplitude decaying by
    zeta = B(omega_n) / (2 omega_n (m + A(omega_n))).
    """
    body = barge()
    body.position[2] += 0.3
    system = system_of(body)
    dt = 0.01
    heave = []
    for _ in range(4000):  # 40 s: seven periods
        steps(system, integrator, dt, 1)
        heave.append(body.position[2])
    heave = np.array(heave)
    omega = heave_frequency()
    h = transfer([omega])[0, 2, 2]
    added = DATABASE.added_mass_infinite[2, 2] + h.imag / omega
    zeta = h.real / (2.0 * omega * (MASS + added))
    # the periods between upward zero crossings past the first one (the memory's own start)
    up = np.flatnonzero((heave[:-1] < 0.0) & (heave[1:] >= 0.0))
    times = (up + heave[up] / (heave[up] - heave[up + 1])) * dt
    period = float(np.diff(times[1:]).mean())
    # the decrement of successive crests past the first
    crests = [heave[a:b].max() for a, b in zip(up[1:-1], up[2:])]
    decrement = float(np.mean(np.log(np.array(crests[:-1]) / np.array(crests[1:]))))
    measured = decrement / math.sqrt(4.0 * math.pi ** 2 + decrement ** 2)
    print(f'period {period:.4f} s, frequency domain {2.0 * math.pi / omega:.4f} s; '
          f'zeta {measured:.4f}, frequency domain {zeta:.4f}')
    assert period == pytest.approx(2.0 * math.pi / omega, rel=0.01)
    assert measured == pytest.approx(zeta, rel=0.05)
    assert 0.03 < zeta < 0.3  # a damping the test can tell from no memory or a wrong one
    # and the exact pole of (m + A_inf) s^2 + s Khat(s) + k = 0, of which the above is the
    # light-damping estimate
    pole = heave_poles()[0]
    assert period == pytest.approx(2.0 * math.pi / abs(pole.imag), rel=0.005)
    assert measured == pytest.approx(-pole.real / abs(pole), rel=0.03)


def forced_response(integrator: str, omega: float, load: np.ndarray, dt: float = 0.01):
    """
    Return the barge's steady complex amplitudes (6,) under the load Re(load exp(-i omega t)).

    The load (body axes) is held linear over 0.05 s intervals, as a run's external load
    (world axes, turned with the body at each interval's start), and eased in
    over its first 30 s (1 - cos) / 2 so as to start little of the free motions; the
    motions from 100 s on, four periods, are fitted with a constant, a drift and cos, sin.
    """
    body = barge()
    system = system_of(body)
    table = system.body_table
    interval = 0.05
    per = int(round(interval / dt))
    settle, ease = 100.0, 30.0
    total = settle + 4 * 2.0 * math.pi / omega
    samples, times = [], []
    for k in range(int(round(total / interval))):
        t0, t1 = k * interval, (k + 1) * interval
        # in body axes, as a wave's load: turned into world axes at each interval's start
        # (in world axes the 2e7 N m pitch moment would leak into roll by the yaw the
        # transients leave, 0.01 rad giving as much as the roll moment itself)
        turn = np.kron(np.eye(2), rotation_matrix(body.quaternion))
        f0 = turn @ (load * np.exp(-1j * omega * t0)).real * _eased(t0, ease)
        f1 = turn @ (load * np.exp(-1j * omega * t1)).real * _eased(t1, ease)
        table[0, BODY_LOAD:BODY_LOAD + 6] = f0
        table[0, BODY_LOAD_RATE:BODY_LOAD_RATE + 6] = (f1 - f0) / interval
        table[0, BODY_CLOCK] = 0.0
        steps(system, integrator, dt, per)
        if t1 >= settle:
            samples.append(motions(body))
            times.append(t1)
    t = np.array(times)
    basis = np.column_stack((np.ones_like(t), t - t.mean(), np.cos(omega * t),
                             np.sin(omega * t)))
    fit = np.linalg.lstsq(basis, np.array(samples), rcond=None)[0]
    return fit[2] + 1j * fit[3]


def _eased(t: float, ease: float) -> float:
    """Return the share of the load at t: (1 - cos(pi t / ease)) / 2, then 1."""
    return 0.5 * (1.0 - math.cos(math.pi * t / ease)) if t < ease else 1.0


def frequency_domain(omega: float, load: np.ndarray) -> np.ndarray:
    """Return (-omega^2 (M + A) - i omega (B + B_visc) + C)^-1 load (6,)."""
    h = transfer([omega])[0]
    added = DATABASE.added_mass_infinite + h.imag / omega
    matrix = (-omega ** 2 * (rigid_mass() + added) - 1j * omega * (h.real + np.diag(VISCOUS))
              + stiffness())
    return np.linalg.solve(matrix, load)


@pytest.mark.parametrize('integrator', INTEGRATORS)
@pytest.mark.parametrize('omega', [0.5, 0.9, 1.3])
def test_forced_motion_has_the_frequency_domain_amplitude_and_phase(integrator, omega):
    """Every motion's complex amplitude within 2 % of the largest of its kind's."""
    load = np.array([2.0e4, 1.0e5, 3.0e5, 2.0e5, 2.0e7, 3.0e6], dtype=complex)
    load[3] *= np.exp(0.5j)  # roll a little out of phase
    simulated = forced_response(integrator, omega, load)
    expected = frequency_domain(omega, load)
    for group in (slice(0, 3), slice(3, 6)):  # translations [m], rotations [rad]
        scale = np.abs(expected[group]).max()
        assert np.abs(simulated[group] - expected[group]).max() <= 0.02 * scale, (
            simulated, expected)


def test_a_database_gives_the_full_added_mass_and_memory_modes():
    row = barge().row()
    assert row[BODY_MODES] == barge().radiation.poles.size > 0
    body = barge()
    added = consistent_added_mass(DATABASE, body.radiation)
    np.testing.assert_array_equal(body.mass_matrix(), rigid_mass() + added)
    # the analytic database is consistent: the A_inf its A(omega) and memory make is its own
    scale = np.sqrt(np.outer(np.diagonal(rigid_mass() + added), np.diagonal(rigid_mass() + added)))
    assert np.abs(added - DATABASE.added_mass_infinite).max() / scale.max() < 1e-3
    assert (np.abs(added - DATABASE.added_mass_infinite) / scale).max() < 2e-3


def test_restart_clears_the_memory():
    body = barge()
    body.velocity[2] = 0.5
    system = system_of(body)
    steps(system, 'implicit', 0.01, 50)
    row = system.body_table[0]
    states = [row[BODY_MODE + i * MODE_COLUMNS + MODE_STATE] for i in range(int(row[BODY_MODES]))]
    assert np.abs(states).max() > 0.0
    clear_memory(row)
    states = [row[BODY_MODE + i * MODE_COLUMNS + MODE_STATE:BODY_MODE + i * MODE_COLUMNS
                  + MODE_STATE + 2] for i in range(int(row[BODY_MODES]))]
    assert np.abs(states).max() == 0.0


def plain_run(integrator: str) -> np.ndarray:
    """Return the BODY row's first 19 numbers after 300 steps of a ship without a database."""
    body = Body.ship(3.69e6, (1.0, 0.0, -1.0), (5.0, 17.0, 17.0),
                     (1e5, 2e6, 3e6, 1e7, 4e9, 5e8), (2e5, 2e5, 1e6, 1.7e7, 2.2e8, 5e8),
                     (1e3,) * 6, 900.0, (2.0, 80.0), (0.0, 0.0, 0.0), 0.2, (60.0, 15.0, 4.0),
                     1025.0, 9.81)
    body.position[2] += 0.2
    body.velocity[:] = (0.1, -0.3, 0.0)
    body.omega[:] = (0.01, 0.0, 0.002)
    system = System(Environment(water_level=0.0))
    system.add_body(body)
    system.add_fender(Fender((0.0, -9.0, 0.0), (0.0, 1.0, 0.0), ((0.0, 0.0), (1.0, 1e6)), 0.2))
    system.pack()
    system.body_table[0, BODY_LOAD:BODY_LOAD + 6] = (1e4, -2e5, 0.0, 1e5, 0.0, 3e5)
    drive = np.zeros((300, 0, 3))
    run_kernel(system, integrator, 0.01, drive, drive.copy(), 10, False, True)
    return system.body_table[0, :19].copy()


@pytest.mark.parametrize('integrator', ('improved_euler', 'implicit_euler'))
def test_a_ship_without_a_database_steps_as_before_to_the_bit(integrator):
    """The numbers the code before ship.hydrodynamics computed (test/data/README.md)."""
    before = {}
    for line in (DATA / 'free_ship_without_database.txt').read_text().splitlines():
        if line and not line.startswith('#'):
            name, *numbers = line.split()
            before[name] = np.array([float.fromhex(n) for n in numbers])
    now = plain_run(integrator)
    assert now[2] != 0.0  # it moved
    np.testing.assert_array_equal(now, before[integrator])
