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
The free ship in regular waves responds as the frequency domain of its own database says.

The default ship of config/berth.yaml with its shipped database (test/data/hydro/
berth_ship.nc) alone in the water, held in surge, sway and yaw by soft springs and dampers
(natural periods of about 100 s, a third of critical), in a regular wave: stepped in the
time domain (its full added mass at infinite frequency, the radiation memory's modes, the
first-order wave load of model/ship/waves.py, the hydrostatics) until steady, its complex
amplitudes fitted, against the RAO that Capytaine's own post-processing
(capytaine.post_pro.rao) computes from the same database, the same mass, hydrostatics,
springs and dampers. The slow drift is left out: in a regular wave it is a constant force,
which would only shift where the springs hold the ship (and turn it a little, so that the
wave meets it at another heading than the database's).
"""

import math
from pathlib import Path

import capytaine as cpt
import numpy as np
import pytest
from rope_sim_ros.model.body import Body
from rope_sim_ros.model.frames import rotation_matrix
from rope_sim_ros.model.layout import BODY_CLOCK, BODY_LOAD, BODY_LOAD_RATE
from rope_sim_ros.model.objects import Environment, System
from rope_sim_ros.model.ship.waves import WaveLoads, Waves
from rope_sim_ros.params.hydro_file import read_hydro_database
from rope_sim_ros.params.ship import SHIP_SPECS
from rope_sim_ros.stepping.adaptive import NEWMARK
from rope_sim_ros.stepping.kernels import run_kernel
import xarray as xr

FILE = Path(__file__).parent / 'data' / 'hydro' / 'berth_ship.nc'
DATABASE = read_hydro_database(FILE)
G, WATER = 9.81, 1025.0


def default(name):
    """Return the default of ship.NAME: the ship the database was solved for."""
    return SHIP_SPECS[f'ship.{name}'].default


MASS = default('mass')
INERTIA = [MASS * k * k for k in default('radii_of_gyration')]
# springs: about 100 s in surge, sway and yaw; dampers a third of critical there, the
# ship's own viscous damping in heave, roll and pitch
SPRINGS = np.diag([3.7e5, 4.0e5, 0.0, 0.0, 0.0, 2.0e9])
DAMPING = np.diag([4.0e6, 4.5e6] + list(default('linear_damping')[2:5]) + [2.0e10])


def ship() -> Body:
    """Return the ship at rest, its origin at (0, 0, 0), heading along x."""
    return Body.ship(MASS, default('center_of_gravity'), default('radii_of_gyration'),
                     (0.0,) * 6, np.diagonal(DAMPING), (0.0,) * 6, default('waterplane_area'),
                     default('metacentric_height'), (0.0, 0.0, 0.0), 0.0,
                     (default('length'), default('beam'), default('draft')), WATER, G,
                     hydrodynamics=DATABASE)


def motions(body: Body, start: np.ndarray) -> np.ndarray:
    """Return its six motions: the centre of gravity's from start [m], roll, pitch, yaw."""
    x, y, z, w = body.quaternion
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(min(max(2.0 * (w * y - z * x), -1.0), 1.0))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return np.concatenate((body.position - start, [roll, pitch, yaw]))


def time_domain(integrator: str, omega: float, travel: float, dt: float = 0.01) -> np.ndarray:
    """
    Return the ship's steady complex amplitudes (6,) per metre of a regular wave's amplitude.

    The wave (0.5 m amplitude, travelling toward `travel` [rad] in frame_id) loads it as a
    run's free ship is loaded: its first-order force at each 0.05 s interval's ends, linear
    between, turned into frame_id axes with the ship then; the springs likewise from its
    state at the interval's start, with their rate over the interval (the dampers are its
    own linear damping). The wave is
    eased in over its first 30 s; from 200 s on, four periods are fitted with a constant, a
    drift and cos, sin.
    """
    body = ship()
    system = System(Environment(water_level=0.0))
    system.add_body(body)
    system.pack()
    table = system.body_table
    start = body.position.copy()
    amplitude = 0.5
    sea = Waves.make('regular', 2.0 * amplitude, 2.0 * math.pi / omega, travel - math.pi,
                     3.3, 0, DATABASE.water_depth, G).sea
    loads = WaveLoads(DATABASE, sea)
    interval, per = 0.05, int(round(0.05 / dt))
    settle, ease = 200.0, 30.0
    samples, times = [], []
    for k in range(int(round((settle + 4 * 2.0 * math.pi / omega) / interval))):
        t0, t1 = k * interval, (k + 1) * interval
        rotation = rotation_matrix(body.quaternion)
        turn = np.kron(np.eye(2), rotation)
        origin, _ = body.origin_pose()
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        wave = [loads.at(t, origin[0], origin[1], yaw)[0] * min(t / ease, 1.0) for t in (t0, t1)]
        state = motions(body, start)
        velocity = np.concatenate((body.velocity, body.omega))
        held = -SPRINGS @ state  # the dampers are the body's own linear damping
        rate = -SPRINGS @ velocity
        f0 = turn @ wave[0] + held
        f1 = turn @ wave[1] + held + rate * interval
        table[0, BODY_LOAD:BODY_LOAD + 6] = f0
        table[0, BODY_LOAD_RATE:BODY_LOAD_RATE + 6] = (f1 - f0) / interval
        table[0, BODY_CLOCK] = 0.0
        drive = np.zeros((per, 0, 3))
        if integrator == 'implicit':
            run_kernel(system, 'implicit_euler', dt, drive, drive.copy(), 10, False, True,
                       NEWMARK)
        else:
            run_kernel(system, integrator, dt, drive, drive.copy(), 10, False, True)
        if t1 >= settle:
            samples.append(motions(body, start))
            times.append(t1)
    t = np.array(times)
    basis = np.column_stack((np.ones_like(t), t - t.mean(), np.cos(omega * t),
                             np.sin(omega * t)))
    fit = np.linalg.lstsq(basis, np.array(samples), rcond=None)[0]
    return (fit[2] + 1j * fit[3]) / amplitude


def frequency_domain(omega: float, travel: float) -> np.ndarray:
    """Return Capytaine's RAO (6,) of the same database, mass, hydrostatics and springs."""
    dataset = cpt.io.xarray.merge_complex_values(xr.open_dataset(FILE))
    dofs = dataset.inertia_matrix.dims
    gm = default('metacentric_height')

    def matrix(values):
        return xr.DataArray(values, dims=dofs, coords={d: dataset[d] for d in dofs})

    dataset['inertia_matrix'] = matrix(np.diag([MASS] * 3 + INERTIA))
    dataset['hydrostatic_stiffness'] = matrix(np.diag(
        [0.0, 0.0, WATER * G * default('waterplane_area'), MASS * G * gm[0], MASS * G * gm[1],
         0.0]))
    response = cpt.post_pro.rao(dataset, dissipation=matrix(DAMPING), stiffness=matrix(SPRINGS))
    return response.sel(omega=omega, wave_direction=travel % (2.0 * math.pi),
                        method='nearest').values


@pytest.mark.parametrize('omega, travel, integrator', [
    (0.5, 0.5 * math.pi, 'implicit'),  # beam seas near the heave resonance (0.59 rad/s)
    (0.7, 0.75 * math.pi, 'implicit'),  # bow quartering: every motion
    (0.9, 0.5 * math.pi, 'improved_euler')])
def test_the_steady_response_is_capytaines_rao(omega, travel, integrator):
    """
    Every motion's amplitude within 2 % and its phase within 2 % of a period.

    Motions under a tenth of the largest of their kind (translations, rotations) within
    2 % of that largest, as complex amplitudes (their phase means little).
    """
    simulated = time_domain(integrator, omega, travel)
    expected = frequency_domain(omega, travel)
    for group in (slice(0, 3), slice(3, 6)):  # translations [m/m], rotations [rad/m]
        scale = np.abs(expected[group]).max()
        for got, want in zip(simulated[group], expected[group]):
            if abs(want) >= 0.1 * scale:
                assert abs(got) == pytest.approx(abs(want), rel=0.02), (simulated, expected)
                turn = abs(np.angle(got / want))
                assert turn <= 0.02 * 2.0 * math.pi, (simulated, expected)
            else:
                assert abs(got - want) <= 0.02 * scale, (simulated, expected)
