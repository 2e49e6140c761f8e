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

"""A free ship moored by its lines, run: at rest where MoorPy puts it, its periods M, K's."""

import math

import numpy as np
import pytest

from rope_sim_ros.model import frames
from rope_sim_ros.model.forces import assembly
from rope_sim_ros.model.forces.body import place_points
from rope_sim_ros.model.layout import BODY_ADDED, BODY_LINEAR_DAMPING
from rope_sim_ros.model.statics.ship import Pose
from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.mooring.statics import mooring_statics
from rope_sim_ros.params import arrangement
from rope_sim_ros.params.ship import ShipParams
from test_ship_statics import moorpy_system

WATER, G = 1025.0, 9.81
START = (0.0, -17.6, 0.0)
# (mass [kg/m], EA [N], diameter [m]), fairlead (body frame), bollard, fairlead tension at
# the start [N]: a ship held off a quay without fenders by lines both ways
LINES = {
    'head': ((2.78, 1.77e7, 0.064), (106.0, 13.0, 10.0), (150.0, 3.0, 3.5), 1.2e5),
    'breast_fwd': ((2.40, 4.2e6, 0.064), (82.0, 15.0, 12.0), (88.0, 12.0, 3.5), 8.0e4),
    'spring_fwd': ((1.14, 7.5e7, 0.048), (62.0, 15.5, 10.0), (12.0, 3.0, 3.5), 1.4e5),
    'spring_aft': ((1.14, 7.5e7, 0.048), (-62.0, 15.5, 6.0), (-12.0, 3.0, 3.5), 1.4e5),
    'breast_aft': ((2.40, 4.2e6, 0.064), (-82.0, 15.0, 10.0), (-88.0, 12.0, 3.5), 8.0e4),
    'stern': ((2.78, 1.77e7, 0.064), (-104.0, 13.0, 12.0), (-150.0, 3.0, 3.5), 1.0e5),
    # two lines to buoys off the ship's starboard side, holding it from the quay
    'off_fwd': ((2.78, 1.77e7, 0.064), (80.0, -15.0, 8.0), (100.0, -80.0, 0.5), 1.0e5),
    'off_aft': ((2.78, 1.77e7, 0.064), (-80.0, -15.0, 8.0), (-100.0, -80.0, 0.5), 1.0e5),
}
LOAD = (2.0e5, -3.0e5, 0.0, 0.0, 0.0, -6.0e6)  # ahead, off the quay, yawing
# about critical damping, 2 sqrt(K M) of each diagonal term (the stiffness at the start: 3.8
# and 1.0 MN/m in surge and sway, 6.6e9 N m/rad in yaw), so that SETTLE s settle it (to
# 1e-7 m/s): more would leave it creeping, its dampers holding part of the load
SETTLE_DAMPING = [3.0e7, 2.0e7, 1.5e8, 1.2e10, 7.0e10, 8.0e10]
SETTLE = 480.0


def setup(damping):
    """Return the arrangement: the default ship, free, in air for its lines (MoorPy's)."""
    values = {'lines': list(LINES), 'ship_mode': 'free', 'ship.start_position': list(START),
              'ship.metacentric_height': [3.0, 3.0], 'ship.linear_damping': list(damping),
              'ship.added_mass': [0.0] * 6, 'air_density': 0.0, 'segments': 10}
    for name, ((mass, ea, diameter), fairlead, bollard, tension) in LINES.items():
        values[name] = {'mass_per_length': mass, 'axial_stiffness': ea, 'diameter': diameter,
                        'fairlead_offset': list(fairlead), 'bollard_position': list(bollard),
                        'pretension': tension, 'material': 'polyester'}
    return arrangement.from_values(values)


def pose_vector(mooring: Mooring) -> np.ndarray:
    """Return the ship origin's x, y, z and its small rotation vector from level (6,)."""
    position, orientation = mooring.ship_pose(mooring.time)
    x, y, z, w = orientation
    angle = 2.0 * math.atan2(math.sqrt(x * x + y * y + z * z), w)
    axis = np.array([x, y, z]) / max(math.sqrt(x * x + y * y + z * z), 1e-300)
    return np.concatenate([position, angle * axis])


@pytest.fixture(scope='module')
def settled():
    """Return the Mooring of the ship settled under LOAD (its damping still on)."""
    mooring = Mooring(setup(SETTLE_DAMPING), output_interval=0.1)
    mooring.start(0.0)
    mooring.set_external_load(LOAD[:3], LOAD[3:], body_axes=False)
    for i in range(1, int(SETTLE * 10) + 1):
        mooring.advance_to(0.1 * i)
    return mooring


def moorpy_equilibrium(mooring: Mooring):
    """Return MoorPy's pose (6,) and fairlead tensions of the same ship, lines and load."""
    ship = mooring_statics(mooring, LOAD)
    system, vessel = moorpy_system(ship, Pose.of([*START, 0.0, 0.0, 0.0]))
    assert system.solveEquilibrium(tol=1e-7, maxIter=1000)
    return vessel.r6.copy(), np.array([line.TB for line in system.lineList])


def test_a_ship_under_a_steady_load_settles_where_moorpy_puts_it(settled):
    ours = pose_vector(settled)
    assert np.abs(settled.body.velocity).max() < 1e-7  # at rest
    assert np.abs(settled.body.omega).max() < 1e-9
    theirs, tensions = moorpy_equilibrium(settled)
    offset_ours, offset_theirs = ours - [*START, 0, 0, 0], theirs - [*START, 0, 0, 0]
    # centimetres of surge (the springs are HMPE), decimetres of sway, a twentieth of a degree
    # of yaw
    assert abs(offset_theirs[0]) > 0.03 and abs(offset_theirs[1]) > 0.3, theirs
    assert abs(offset_theirs[5]) > 8e-4, theirs
    for k in (0, 1, 5):  # surge, sway, yaw within 1 % (measured 0.01, 0.08, 0.2 %)
        assert offset_ours[k] == pytest.approx(offset_theirs[k], rel=1e-2)
    out = settled.output()
    assert out.fairlead_tensions == pytest.approx(tensions, rel=1e-2)


def test_small_oscillations_at_the_periods_of_the_mass_and_stiffness(settled):
    """Each of the three slowest modes of M^-1 K, started alone, swings at its period."""
    statics = mooring_statics(settled, LOAD)
    here = pose_vector(settled)
    pose = statics.start  # (the statics' start: the ship's pose now)
    stiffness = statics.stiffness(pose, hydrostatics=True)
    # the default ship's added mass from here on (it moves no equilibrium: the ship is still)
    added = np.array(ShipParams().added_mass)
    system = settled.groups[0].system
    system.body_table[0, BODY_ADDED:BODY_ADDED + 6] = added
    mass = origin_mass_matrix(settled, added)
    values, vectors = np.linalg.eig(np.linalg.solve(mass, stiffness))
    order = np.argsort(values.real)[:3]  # surge, sway and yaw: the slow ones
    system.body_table[0, BODY_LINEAR_DAMPING:BODY_LINEAR_DAMPING + 6] = 0.0
    for mode in order:
        expected = 2.0 * math.pi / math.sqrt(values[mode].real)
        shape = vectors[:, mode].real
        shape /= np.abs(shape).max()
        start = settled.time
        start_velocity(settled, 0.02 * shape * 2.0 * math.pi / expected)
        samples, dt = [], 0.5
        for i in range(1, int(2.2 * expected / dt) + 1):
            settled.advance_to(start + dt * i)
            samples.append(np.linalg.lstsq(vectors.real, pose_vector(settled) - here,
                                           rcond=None)[0][mode])
        samples = np.array(samples)
        up = np.flatnonzero((samples[:-1] > 0.0) & (samples[1:] <= 0.0))
        times = (up + samples[up] / (samples[up] - samples[up + 1])) * dt
        assert len(times) >= 2, (mode, expected)
        # (measured: 119.9, 87.0 and 64.7 s against 120.1, 86.5 and 64.7 s)
        assert float(np.diff(times).mean()) == pytest.approx(expected, rel=0.015)
        start_velocity(settled, np.zeros(6))  # still again for the next mode


def origin_mass_matrix(mooring: Mooring, added: np.ndarray) -> np.ndarray:
    """
    Return the ship's 6x6 mass matrix about its origin, frame_id axes.

    :param added: its added mass (6,) about the centre of gravity, body axes.
    """
    body = mooring.body
    rotation = frames.rotation_matrix(body.quaternion)
    lever = body.position - body.origin_pose()[0]  # origin to centre of gravity
    cross = np.array([[0.0, -lever[2], lever[1]], [lever[2], 0.0, -lever[0]],
                      [-lever[1], lever[0], 0.0]])
    at_cg = np.zeros((6, 6))  # about the centre of gravity
    at_cg[:3, :3] = rotation @ np.diag(body.mass + added[:3]) @ rotation.T
    at_cg[3:, 3:] = rotation @ np.diag(np.asarray(body.inertia) + added[3:]) @ rotation.T
    shift = np.eye(6)  # the origin's velocities to the centre of gravity's
    shift[:3, 3:] = -cross
    return shift.T @ at_cg @ shift


def start_velocity(mooring: Mooring, twist: np.ndarray) -> None:
    """Give the ship the origin's velocity and angular velocity `twist` (its lines follow)."""
    body = mooring.body
    lever = body.position - body.origin_pose()[0]
    body.omega[:] = twist[3:]
    body.velocity[:] = twist[:3] + np.cross(twist[3:], lever)
    system = mooring.groups[0].system
    place_points(system.body_table, system.points_table, system.point_x, system.point_v)
    assembly.set_ends(system.x, system.v, system.lines_table, system.point_x, system.point_v)


def test_a_load_no_tug_or_thruster_gives_is_refused_and_nothing_changes():
    mooring = Mooring(setup(SETTLE_DAMPING), output_interval=0.1)
    mooring.start(0.0)
    weight = 8.84e7 * 9.80665  # the default ship's
    mooring.set_external_load([0.1 * weight, 0.0, 0.0], [0.0, 0.0, 0.1 * weight * 225.0],
                              body_axes=True)  # at the limits: taken
    with pytest.raises(ValueError, match=r'an external force of 1e\+12 N is more than any '
                       r'tug or thruster gives this ship: at most 8\.67e\+07 N'):
        mooring.set_external_load([1e12, 0.0, 0.0], [0.0] * 3, body_axes=False)
    with pytest.raises(ValueError, match=r'an external moment of 2e\+10 N m .* at most '
                       r'1\.95e\+10 N m'):
        mooring.set_external_load([0.0] * 3, [0.0, 0.0, 2e10], body_axes=False)
    assert mooring.ship.body_load[0] == pytest.approx(0.1 * weight)  # the one taken holds
    assert not mooring.ship.external_load.any()


@pytest.mark.parametrize('change, why', [
    (lambda row: row.__setitem__(9, -3000.0), 'moving at 3000.0 m/s'),
    (lambda row: row.__setitem__(2, row[2] - 2400.0), 'sunk 2400.0 m'),
    (lambda row: row.__setitem__(slice(3, 7), [math.sin(0.75), 0.0, 0.0, math.cos(0.75)]),
     'tilted 86 deg'),
    (lambda row: row.__setitem__(0, row[0] + 6000.0), '6000 m off its start'),
    (lambda row: row.__setitem__(12, 7.0), 'turning at 7.00 rad/s'),
    (lambda row: row.__setitem__(1, math.nan), 'not finite'),
])
def test_a_ship_out_of_every_bound_restarts_at_its_start_pose_at_rest(change, why):
    # (the issue: after a load of 1e12 N the ship went on sinking and rolling, 2.4 km deep
    # at 3 km/s and 7 rad/s, until ~/reset)
    mooring = Mooring(setup(SETTLE_DAMPING), output_interval=0.1)
    mooring.start(0.0)
    mooring.advance_to(0.5)
    system = mooring.groups[0].system
    change(system.body_table[0])
    place_points(system.body_table, system.points_table, system.point_x, system.point_v)
    advance = mooring.advance_to(0.6)
    assert advance.ship_restarted == why
    assert advance.restarted == {k: 'ship restarted' for k in range(len(LINES))}
    out = mooring.output()
    assert out.finite
    position, orientation = mooring.ship_pose(mooring.time)
    assert np.allclose(position, START, atol=1e-3) and np.allclose(orientation, [0, 0, 0, 1],
                                                                   atol=1e-5)
    assert np.abs(out.ship.velocity).max() < 1e-3 and np.abs(out.ship.omega).max() < 1e-4
    assert mooring.advance_to(0.7).ship_restarted == ''  # and it stays
