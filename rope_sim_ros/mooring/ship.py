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
The one ship of a mooring: a body with a mode, its fenders and the loads on it.

One place turns the ship.*, fender, wind, waves.* and passing_ship.* parameters into a
model.body.Body, Fenders and ShipLoads, for the Mooring that steps them and for the statics
(equilibrium, stiffness, the berth check) alike; and the Ship the Mooring holds. Its body is
driven or free, as MoorDyn's bodies are coupled or free: a driven ship's body is where its
host's newest pose puts it, at rest (its fairleads follow the pose's samples); a free ship's
body is integrated with its lines in their System (its fairleads are points it carries).
Its fenders, its loads, its published state and its stiffness read the same body either way.
The loads are those at the depth of the water, water_level - seabed_level (no sea bed, or
no water: deep): the passing ship's are summed over the sea bed's images, the current's
table is the one for the ratio of that depth to the ship's draft. The waves' loads come
from the ship's hydrodynamic database (hydrodynamics): waves without one are refused.
"""

from collections import deque
import math
from typing import Deque, List, Optional, Tuple

import numpy as np

from .records import ShipState
from .trajectory import TrajectoryError
from ..model.body import Body, clear_memory, Fender, out_of_bounds
from ..model.forces.body import place_points
from ..model.forces.fender import contact, fender_force
from ..model.frames import cross, rotation_matrix
from ..model.layout import (BODY_CLOCK, BODY_LOAD, BODY_LOAD_RATE, BODY_ORIGIN, BODY_POSITION,
                            FENDER_COLUMNS)
from ..model.objects import Environment, System
from ..model.ship.coefficients import table_at_ratio
from ..model.ship.hydro import HydroDatabase
from ..model.ship.loads import PassingShip, ShipLoads, world_load, world_wrench
from ..model.ship.passing import Hull
from ..model.ship.waves import ShipWaves, Waves
from ..params.arrangement import ArrangementParams
from ..params.resolve import environment
from ..params.ship import (PASSING_SHIP, read_coefficients, read_current_tables, SHIP_SPECS,
                           WAVES)
from ..params.table import LineParams, ParameterError


def ship_body(setup: ArrangementParams, database: Optional[HydroDatabase] = None) -> Body:
    """
    Return the arrangement's ship as a Body floating at rest at its start pose.

    :param database: its hydrodynamic database (hydrodynamics(setup)): its full added mass
        and radiation memory; None: the constant ship.added_mass and damping alone.
    :raises ParameterError: a database whose memory no modes fit.
    """
    ship = setup.ship
    shared = setup.shared
    g = float(np.linalg.norm(shared.gravity))
    try:
        return Body.ship(ship.mass, ship.center_of_gravity, ship.radii_of_gyration,
                         ship.added_mass, ship.linear_damping, ship.quadratic_damping,
                         ship.waterplane_area, ship.metacentric_height, ship.start_position,
                         ship.start_yaw, (ship.length, ship.beam, ship.draft),
                         shared.water_density, g, hydrodynamics=database)
    except ValueError as e:
        if database is None:
            raise
        raise ParameterError(f'parameter ship.hydrodynamics {ship.hydrodynamics!r}: '
                             f'{e}') from None


def fenders(setup: ArrangementParams, body: int = 0) -> List[Fender]:
    """Return the arrangement's fenders, each touching the hull of body `body`."""
    return [Fender(fender.position, fender.normal, fender.curve, fender.friction, body)
            for fender in setup.fenders]


def fender_gaps(setup: ArrangementParams, position, orientation) -> np.ndarray:
    """
    Return how far the hull is off each fender's face with its origin at this pose [m].

    < 0: it compresses the fender that much (as the fenders push, model/forces/fender.py);
    0 for a fender facing no side of the hull.

    :param position: the body origin in frame_id; orientation: (x, y, z, w).
    """
    body = ship_body(setup)
    rotation = rotation_matrix(orientation)
    body.quaternion = np.array(orientation, dtype=float)
    body.position = np.asarray(position, dtype=float) - rotation @ np.asarray(body.origin)
    row = body.row()
    point = np.zeros(3)
    return np.array([-contact(fender.row(), row, rotation, point)
                     for fender in fenders(setup)])


def quay_normal(setup: ArrangementParams) -> np.ndarray:
    """
    Return the horizontal unit vector out of the quay towards the ship: its fenders' normal.

    :raises ParameterError: no fenders, or their normals have no common horizontal direction.
    """
    normals = np.array([fender.normal for fender in setup.fenders], dtype=float).reshape(-1, 3)
    normal = normals.sum(axis=0) * [1.0, 1.0, 0.0]
    size = float(np.linalg.norm(normal))
    if size < 1e-6:
        raise ParameterError('the berth needs fenders on its quay (fenders: [...], each with '
                             'a horizontal normal out of the quay): they say where the quay is')
    return normal / size


def start_pose(setup: ArrangementParams) -> tuple:
    """Return the ship's start pose: its body origin [m] and orientation (x, y, z, w)."""
    half = 0.5 * setup.ship.start_yaw
    return (np.array(setup.ship.start_position, dtype=float),
            np.array([0.0, 0.0, np.sin(half), np.cos(half)]))


def water_depth(shared: LineParams) -> float:
    """Return the depth of the water, water_level - seabed_level [m]; math.inf: deep."""
    return environment(shared).depth


def passing_ship(setup: ArrangementParams) -> Optional[PassingShip]:
    """
    Return the ship passing the arrangement's, its track from the ship's start pose, or None.

    (ship.start_position, ship.start_yaw), moving in the arrangement's current from its
    start (ShipLoads follows a current changed at run time from then on).

    :raises ParameterError: a depth of water its keel or the moored ship's would not float
        in.
    """
    ship, passing = setup.ship, setup.passing
    if not passing.present:
        return None
    depth = water_depth(setup.shared)
    if depth <= max(ship.draft, passing.draft):
        raise ParameterError(
            f'the water is {depth:g} m deep (water_level - seabed_level): a ship passing '
            f'({PASSING_SHIP}.speed > 0) needs it deeper than both drafts (ship.draft '
            f'{ship.draft:g} m, {PASSING_SHIP}.draft {passing.draft:g} m)')
    track = PassingShip.beside(
        Hull(passing.length, passing.beam, passing.draft, passing.block_coefficient),
        passing.speed, passing.direction, passing.separation, passing.start_x,
        ship.start_position, ship.start_yaw)
    return track.in_current(track.start_time, setup.shared.current)


# How far a database's water depth may be from the mooring's: its added mass, damping and
# drift change with the depth under the keel (a fraction of the mooring's depth).
DEPTH_TOLERANCE = 0.01


def hydrodynamics(setup: ArrangementParams) -> Optional[HydroDatabase]:
    """
    Return the ship's hydrodynamic database (ship.hydrodynamics), or None: it has none.

    :raises ParameterError: a file that cannot be read (HydroFileError), or one solved at
        another water depth than the mooring's (water_level - seabed_level).
    """
    path = setup.ship.hydrodynamics
    if not path:
        return None
    # imported here: a run without a database loads no NetCDF reader
    from ..params.hydro_file import read_hydro_database
    database = read_hydro_database(path)
    depth = water_depth(setup.shared)
    same = (math.isinf(depth) and math.isinf(database.water_depth)) or (
        abs(database.water_depth - depth) <= DEPTH_TOLERANCE * depth)
    if not same:
        raise ParameterError(
            f'parameter ship.hydrodynamics {path!r}: solved in {database.water_depth:g} m of '
            f'water, the mooring is in {depth:g} m (water_level - seabed_level): solve it '
            'again at this depth (rope_sim hydro)')
    return database


# The largest share of a sea's variance at frequencies its ship's hydrodynamic database
# leaves out (they take no load): past it the database is refused for that sea.
OUTSIDE_SHARE = 0.05


def damping_advice(setup: ArrangementParams) -> Optional[str]:
    """
    Return a warning for a free ship with a hydrodynamic database and the default damping.

    ship.linear_damping's defaults stand for the whole damping of a ship without a database,
    the waves it makes in heave and pitch too; with a database its radiation memory is that
    part, and the defaults count it a second time (the motions come out too small).
    """
    ship = setup.ship
    if not (ship.free and ship.hydrodynamics):
        return None
    if list(ship.linear_damping) != list(SHIP_SPECS['ship.linear_damping'].default):
        return None
    return ("ship.linear_damping is at its defaults, a ship's whole damping without a "
            "hydrodynamic database: with ship.hydrodynamics the database's radiation damping "
            'counts the wave part (heave and pitch most) a second time; give '
            'ship.linear_damping the viscous part alone (docs/waves.md)')


def check_waves(waves: Waves, database: Optional[HydroDatabase]) -> None:
    """
    Refuse waves the ship's hydrodynamic database cannot load it with.

    :raises ParameterError: waves (a spectrum other than none) without a database, or a
        sea with more than OUTSIDE_SHARE of its variance outside the database's frequencies.
    """
    if not waves.configured:
        return
    if database is None:
        raise ParameterError(
            f'waves need ship.hydrodynamics: {WAVES}.spectrum is {waves.spectrum!r} but the '
            'ship has no hydrodynamic database (the file `rope_sim hydro` writes); set it, '
            f'or {WAVES}.spectrum: none')
    if waves.sea is None:
        return
    low, high = float(database.omega[0]), float(database.omega[-1])
    share = waves.sea.outside_share(low, high)
    if share > OUTSIDE_SHARE:
        sea = waves.sea.omega
        raise ParameterError(
            f"{WAVES}: {share:.0%} of the sea's energy lies outside the frequencies of the "
            f'hydrodynamic database ({low:.3g} to {high:.3g} rad/s); at most '
            f'{OUTSIDE_SHARE:.0%} may: make it cover {sea.min():.3g} to {sea.max():.3g} rad/s '
            f'or change {WAVES}.period')


def ship_loads(setup: ArrangementParams,
               database: Optional[HydroDatabase] = None) -> ShipLoads:
    """
    Return the wind, current, passing-ship and wave loads of the arrangement's ship.

    At the depth of the water (module docstring); the passing ship as passing_ship gives it;
    the waves' from `database`, the ship's hydrodynamic database (None: none).

    :raises ParameterError: a coefficient table that cannot be read; a passing ship in water
        too shallow for it.
    """
    ship, shared = setup.ship, setup.shared
    hull = Hull(ship.length, ship.beam, ship.draft, ship.block_coefficient)
    depth = water_depth(shared)
    return ShipLoads(
        hull, read_coefficients(ship, 'wind_coefficients'),
        table_at_ratio(read_current_tables(ship), depth / ship.draft),
        (ship.wind_area_front, ship.wind_area_side),
        (ship.current_area_front or ship.beam * ship.draft,
         ship.current_area_side or ship.length * ship.draft),
        passing_ship(setup), depth, setup.passing.image_pairs, ShipWaves(database))


# The largest external load a free ship takes (ship/external_wrench, LOADS.csv): a force of a
# tenth of its weight, 8.7e7 N on the default 88,400 t ship, some ninety of the largest
# harbour tugs (about 1 MN of bollard pull each), and that force at the ship's length for the
# moment. A load past it is no tug's or thruster's (one of 1e12 N, 11 km/s^2 on that ship,
# sent it 2.4 km deep) and is refused.
EXTERNAL_FORCE_SHARE = 0.1
STANDARD_GRAVITY = 9.80665  # [m/s^2] the weight of the limit, whatever the gravity setting


def external_load_limits(setup: ArrangementParams) -> Tuple[float, float]:
    """Return the largest external force [N] and moment [N m] the ship may take."""
    force = EXTERNAL_FORCE_SHARE * setup.ship.mass * STANDARD_GRAVITY
    return force, force * setup.ship.length


def check_external_load(load, limits: Tuple[float, float]) -> None:
    """
    Refuse an external load (force [N], moment [N m]: 6 numbers) past the limits.

    :raises ValueError: a number not finite, or a force or moment past its limit; the
        message says which and what is allowed.
    """
    load = np.asarray(load, dtype=float).reshape(6)
    if not np.isfinite(load).all():
        raise ValueError(f'external load {load.tolist()} must be finite numbers')
    for name, size, limit, unit in (('force', math.hypot(*load[:3]), limits[0], 'N'),
                                    ('moment', math.hypot(*load[3:]), limits[1], 'N m')):
        if size > limit:
            raise ValueError(
                f'an external {name} of {size:.3g} {unit} is more than any tug or thruster '
                f'gives this ship: at most {limit:.3g} {unit} (a force of a tenth of its '
                'weight, at its length for a moment)')


def reports_waves(setup: ArrangementParams) -> bool:
    """Tell whether the waves (their elevation, their loads on the ship) are outputs of a run."""
    return not setup.single and setup.ship.waves_spectrum != 'none'


def reports_ship_loads(setup: ArrangementParams) -> bool:
    """Tell whether the ship's wind, current and passing-ship loads are outputs of a run."""
    ship = setup.ship
    return (not setup.single and (ship.free or ship.wind_speed > 0.0 or setup.passing.present
                                  or any(setup.shared.current)))


class Ship:
    """
    The mooring's ship (module docstring): driven (its pose an input) or free (integrated).

    :ivar free: whether it is free (ship_mode free).
    :ivar body: its Body: a free ship's state is its System's; a driven ship's follows its
        newest pose at or before the state time (follow), at rest.
    :ivar fenders: the fenders on the quay it rests against.
    :ivar loads: the wind's, the current's, a passing ship's and the waves' load on it.
    :ivar external_load: force [N], moment about its origin [N m] held in frame_id axes;
        body_load: the same in its body axes (they turn with it); held until set again.
    :ivar load_schedule: offline, (times (n,), loads (n, 6)) as external_load, linear
        between the times; None: none.
    """

    def __init__(self, setup: ArrangementParams):
        """Build the ship of an arrangement, at rest at its start pose."""
        self.free = setup.ship.free
        self.center_of_gravity = np.array(setup.ship.center_of_gravity, dtype=float)
        database = hydrodynamics(setup)
        self.body = ship_body(setup, database)
        self.start_row = self.body.row()
        self.fenders = fenders(setup)
        self.fender_rows = np.array([fender.row() for fender in self.fenders]).reshape(
            len(self.fenders), FENDER_COLUMNS)
        self.loads = ship_loads(setup, database)
        self.check_waves(environment(setup.shared, setup.ship).waves)
        self.limits = external_load_limits(setup)
        self.external_load = np.zeros(6)
        self.body_load = np.zeros(6)
        self.load_schedule: Optional[Tuple[np.ndarray, np.ndarray]] = None
        # a driven ship's poses (t, position, unit quaternion): the newest at or before an
        # output gives its orientation (the fairleads' levers, the wrench's rotation)
        self._poses: Deque[tuple] = deque()
        self._origin = start_pose(setup)  # a driven ship's origin pose followed (follow)
        self._placed = True  # its body is there

    # -- its pose -------------------------------------------------------------------------

    def check_pose(self, t: float) -> None:
        """
        Refuse a pose at t of a free ship, or not after the newest pose.

        :raises TrajectoryError: the ship is free, or t is not after the newest pose.
        """
        if self.free:
            raise TrajectoryError('the ship is free (ship_mode free): its pose is an output '
                                  'of the mooring, not an input')
        if self._poses and t <= self._poses[-1][0]:
            raise TrajectoryError(f'ship pose at t={t:.6f} s is not after the newest one '
                                  f'({self._poses[-1][0]:.6f} s)')

    def take_pose(self, t: float, position, quaternion: np.ndarray) -> None:
        """Keep a driven ship's pose at t (check_pose'd; [m], unit quaternion x, y, z, w)."""
        self._poses.append((t, np.array(position, dtype=float), quaternion))

    @property
    def has_pose(self) -> bool:
        """Tell whether the ship has a pose to start its lines at: free, or one taken."""
        return self.free or bool(self._poses)

    def pose(self, t: float) -> Tuple[np.ndarray, np.ndarray]:
        """
        Return (position, unit quaternion) of its origin at t.

        A driven ship's newest pose at or before t; a free ship's now (t is the state time
        at an output).
        """
        if self.free:
            return self.body.origin_pose()
        chosen = self._poses[0]
        for sample in self._poses:
            if sample[0] > t:
                break
            chosen = sample
        return chosen[1], chosen[2]

    def forget(self, now: float) -> None:
        """Drop a driven ship's poses no output can use: outputs come at or after now."""
        while len(self._poses) > 1 and self._poses[1][0] <= now:
            self._poses.popleft()

    def clear(self) -> None:
        """Forget a driven ship's poses (its lines start over at the next one)."""
        self._poses.clear()

    def follow(self, t: float) -> None:
        """Put a driven ship where its newest pose at or before t puts it, at rest."""
        if not self.free:
            self._origin = self.pose(t)
            self._placed = False

    def placed_body(self) -> Body:
        """Return its body where the ship is: a driven ship's placed at the pose it follows."""
        if not (self.free or self._placed):
            position, quaternion = self._origin
            self.body.quaternion = np.array(quaternion, dtype=float)
            self.body.position = position - rotation_matrix(quaternion) @ np.asarray(
                self.start_row[BODY_ORIGIN:BODY_ORIGIN + 3])
            self.body.velocity = np.zeros(3)
            self.body.omega = np.zeros(3)
            self._placed = True
        return self.body

    def carried(self, offset_from_gravity: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """Return a point the body carries (body axes, from its CG): position, velocity."""
        body = self.body
        lever = rotation_matrix(body.quaternion) @ offset_from_gravity
        return body.position + lever, body.velocity + cross(body.omega, lever)

    def state(self) -> ShipState:
        """Return its motion now (its body origin's): a driven ship's pose followed, at rest."""
        if not self.free:
            return ShipState(self._origin[0], self._origin[1], np.zeros(3), np.zeros(3))
        body = self.body
        position, orientation = body.origin_pose()
        velocity = body.velocity + cross(body.omega, position - body.position)
        return ShipState(position, orientation, velocity, body.omega.copy())

    # -- a free ship in its System --------------------------------------------------------

    def reset(self, system: System) -> None:
        """Put a free ship back at its start pose, at rest (no acceleration, no memory kept)."""
        system.body_table[0, :BODY_CLOCK] = self.start_row[:BODY_CLOCK]
        clear_memory(system.body_table[0])
        place_points(system.body_table, system.points_table, system.point_x, system.point_v)

    def out_of_bounds(self, system: System) -> str:
        """Say how a free ship left the bounds of a moored ship ('' if it has not)."""
        return out_of_bounds(system.body_table[0], self.start_row)

    # -- the loads on it ------------------------------------------------------------------

    def check_waves(self, waves: Waves) -> None:
        """Refuse waves its hydrodynamic database cannot load it with (check_waves)."""
        check_waves(waves, self.loads.waves.database)

    def set_external_load(self, force, moment, body_axes: bool) -> None:
        """
        Hold an external load on the free ship from now on (it replaces the one before).

        :param force, moment: [N], [N m] about the ship's origin; in its body axes (they
            turn with it) or in frame_id axes.
        :raises ValueError: a number that is not finite, or a load past what any tug or
            thruster gives (external_load_limits).
        """
        load = np.concatenate([np.asarray(force, dtype=float).reshape(3),
                               np.asarray(moment, dtype=float).reshape(3)])
        check_external_load(load, self.limits)
        self.external_load = np.zeros(6) if body_axes else load
        self.body_load = load if body_axes else np.zeros(6)

    def set_load_schedule(self, times: np.ndarray, loads: np.ndarray) -> None:
        """
        Take a schedule of external loads on the free ship (offline: LOADS.csv).

        :param times: [s] (n,), increasing; loads: force [N] and moment about the ship's
            origin [N m] in world axes at each (n, 6), linear between them.
        :raises ValueError: a load past what any tug or thruster gives, naming its row.
        """
        for row, load in enumerate(np.asarray(loads, dtype=float).reshape(-1, 6)):
            try:
                check_external_load(load, self.limits)
            except ValueError as e:
                raise ValueError(f'row {row + 1} (t = {times[row]:g} s): {e}') from None
        self.load_schedule = (np.asarray(times, dtype=float), np.asarray(loads, dtype=float))

    def load_at(self, t: float) -> np.ndarray:
        """
        Return the load on the free ship at t besides its lines and fenders (6,).

        The external wrench (external_load, body_load turned with the ship) plus the
        schedule's (load_schedule) at t: force [N] and moment about the ship's origin [N m],
        world axes.
        """
        load = self.external_load.copy()
        if self.body_load.any():
            rotation = rotation_matrix(self.body.quaternion)
            load[:3] += rotation @ self.body_load[:3]
            load[3:] += rotation @ self.body_load[3:]
        if self.load_schedule is not None:
            times, loads = self.load_schedule
            load += [np.interp(t, times, loads[:, c]) for c in range(6)]
        return load

    def set_body_loads(self, system: System, start: float, end: float,
                       environment: Environment) -> None:
        """
        Give the free body its loads from start to end [s]: their value at start, their rate.

        Taken about the centre of gravity where the ship is at start, with its velocity there
        (the wind and current on it) and its heading there (the waves): over one output
        interval it turns and speeds up far too little for that to matter. The waves' loads
        are linear between the interval's ends too: at the default 50 Hz a 4 s wave is
        sampled 200 times a period, and the largest error of that line against the wave is
        (omega dt)^2 / 8 = 1.2e-4 of its amplitude.
        """
        origin, orientation = self.body.origin_pose()
        lever = self.body.position - origin  # from the origin to the CG
        rotation = rotation_matrix(orientation)
        velocity = self.body.velocity - cross(self.body.omega, lever)
        row = system.body_table[0]
        values = []
        for t in (start, end):
            load = self.load_at(t)
            load += world_load(self.loads.at(t, environment, origin, rotation, velocity),
                               rotation)
            if environment.waves.sea is not None:
                load += world_wrench(self.loads.waves_at(t, environment, origin, rotation)[1],
                                     rotation)
            load[3:] -= cross(lever, load[:3])  # the moment about the CG
            values.append(load)
        row[BODY_LOAD:BODY_LOAD + 6] = values[0]
        row[BODY_LOAD_RATE:BODY_LOAD_RATE + 6] = (
            (values[1] - values[0]) / (end - start) if end > start else 0.0)
        row[BODY_CLOCK] = 0.0

    def loads_at(self, t: float, state: ShipState, setup: ArrangementParams,
                 environment: Environment) -> np.ndarray:
        """
        Return the wind's, current's and passing ship's loads on it at t (3, 3), body axes.

        Worked out where they are outputs (a free ship, which they move, or a run that
        reports them: reports_ship_loads), else zeros: a single line's current acts on the
        line alone.

        :param setup: the arrangement in force; environment: the mooring's now.
        """
        if not (self.free or (self.loads.acts(environment) and reports_ship_loads(setup))):
            return np.zeros((3, 3))
        return self.loads.at(t, environment, state.position,
                             rotation_matrix(state.orientation), state.velocity)

    def waves_at(self, t: float, state: ShipState,
                 environment: Environment) -> Tuple[float, np.ndarray]:
        """
        Return the wave elevation at its origin [m] and the waves' loads on it (2, 6) at t.

        Rows: first order, slow drift (ShipLoads.waves_at): body axes, about its origin.
        """
        return self.loads.waves_at(t, environment, state.position,
                                   rotation_matrix(state.orientation))

    # -- its fenders ----------------------------------------------------------------------

    def fender_states(self) -> tuple:
        """Return each fender's compression (F,), force on the ship (F, 3), point (F, 3)."""
        count = len(self.fenders)
        compressions, forces = np.zeros(count), np.zeros((count, 3))
        points = self.fender_rows[:, :3].copy() if count else np.zeros((0, 3))
        if not count:
            return compressions, forces, points
        body = self.placed_body()
        # the fenders read the hull's geometry and where it is: the start row's geometry
        # with the body's position now (a whole row() writes the memory's modes, 80 us)
        row = self.start_row.copy()
        row[BODY_POSITION:BODY_POSITION + 3] = body.position
        rotation = rotation_matrix(body.quaternion)
        velocity = body.velocity
        omega = body.omega
        for f in range(count):
            compressions[f] = fender_force(self.fender_rows[f], row, rotation, velocity,
                                           omega, forces[f], points[f])[0]
        return compressions, forces, points
