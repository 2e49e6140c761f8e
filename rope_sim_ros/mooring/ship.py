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
The ship of an arrangement as model objects: its body, its fenders and the loads on it.

One place turns the ship.*, fender, wind and passing_ship.* parameters into a
model.body.Body, Fenders and ShipLoads, for the Mooring that steps them and for the statics
(equilibrium, stiffness, the berth check) alike. The loads are those at the depth of the
water, water_level - seabed_level (no sea bed, or no water: deep): the passing ship's are
summed over the sea bed's images, the current's table is the one for the ratio of that depth
to the ship's draft.
"""

import math
from typing import List, Optional

import numpy as np

from ..model.body import Body, Fender
from ..model.ship.coefficients import table_at_ratio
from ..model.ship.loads import PassingShip, ShipLoads, Wind
from ..model.ship.passing import Hull
from ..model.ship.wind import GustyWind
from ..params.arrangement import ArrangementParams
from ..params.ship import PASSING_SHIP, read_coefficients, read_current_tables, ShipParams
from ..params.table import LineParams, ParameterError


def ship_body(setup: ArrangementParams) -> Body:
    """Return the arrangement's ship as a Body floating at rest at its start pose."""
    ship = setup.ship
    shared = setup.shared
    g = float(np.linalg.norm(shared.gravity))
    return Body.ship(ship.mass, ship.center_of_gravity, ship.radii_of_gyration,
                     ship.added_mass, ship.linear_damping, ship.quadratic_damping,
                     ship.waterplane_area, ship.metacentric_height, ship.start_position,
                     ship.start_yaw, (ship.length, ship.beam, ship.draft),
                     shared.water_density, g)


def fenders(setup: ArrangementParams, body: int = 0) -> List[Fender]:
    """Return the arrangement's fenders, each touching the hull of body `body`."""
    return [Fender(fender.position, fender.normal, fender.curve, fender.friction, body)
            for fender in setup.fenders]


def start_pose(setup: ArrangementParams) -> tuple:
    """Return the ship's start pose: its body origin [m] and orientation (x, y, z, w)."""
    half = 0.5 * setup.ship.start_yaw
    return (np.array(setup.ship.start_position, dtype=float),
            np.array([0.0, 0.0, np.sin(half), np.cos(half)]))


def water_depth(shared: LineParams) -> float:
    """Return the depth of the water, water_level - seabed_level [m]; math.inf: deep."""
    if shared.water_level == -math.inf or shared.seabed_level == -math.inf:
        return math.inf
    return shared.water_level - shared.seabed_level


def passing_ship(setup: ArrangementParams) -> Optional[PassingShip]:
    """
    Return the ship passing the arrangement's, its track from the ship's start pose, or None.

    (ship.start_position, ship.start_yaw; ShipLoads sets it moving in the current.)

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
    return PassingShip.beside(
        Hull(passing.length, passing.beam, passing.draft, passing.block_coefficient),
        passing.speed, passing.direction, passing.separation, passing.start_x,
        ship.start_position, ship.start_yaw)


def ship_loads(setup: ArrangementParams) -> ShipLoads:
    """
    Return the wind, current and passing-ship loads of the arrangement's ship.

    At the depth of the water (module docstring); the passing ship as passing_ship gives it.

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
        shared.air_density, shared.water_density,
        ship_wind(ship), tuple(shared.current), passing_ship(setup), depth,
        setup.passing.image_pairs)


def ship_wind(ship: ShipParams) -> Wind:
    """Return the wind of the ship's parameters: steady, or gusty about its mean."""
    gusts = None
    if ship.wind_spectrum != 'none' and ship.wind_speed > 0.0:
        gusts = GustyWind(ship.wind_spectrum, ship.wind_speed, ship.wind_seed)
    return Wind(ship.wind_speed, ship.wind_direction, gusts)


def reports_ship_loads(setup: ArrangementParams) -> bool:
    """Tell whether the ship's wind, current and passing-ship loads are outputs of a run."""
    ship = setup.ship
    return (not setup.single and (ship.free or ship.wind_speed > 0.0 or setup.passing.present
                                  or any(setup.shared.current)))
