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
(equilibrium, stiffness, the berth check) alike.
"""

from typing import List

import numpy as np

from ..model.body import Body, Fender
from ..model.ship.loads import PassingShip, ShipLoads, Wind
from ..model.ship.passing import Hull
from ..model.ship.wind import GustyWind
from ..params.arrangement import ArrangementParams
from ..params.ship import read_coefficients, ShipParams


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


def ship_loads(setup: ArrangementParams) -> ShipLoads:
    """
    Return the wind, current and passing-ship loads of the arrangement's ship.

    The passing ship's track starts from the ship's start pose (ship.start_position,
    ship.start_yaw).

    :raises ParameterError: a coefficient table that cannot be read.
    """
    ship, shared, passing = setup.ship, setup.shared, setup.passing
    hull = Hull(ship.length, ship.beam, ship.draft, ship.block_coefficient)
    other = None
    if passing.present:
        other = PassingShip.beside(
            Hull(passing.length, passing.beam, passing.draft, passing.block_coefficient),
            passing.speed, passing.direction, passing.separation, passing.start_x,
            ship.start_position, ship.start_yaw)
    return ShipLoads(
        hull, read_coefficients(ship, 'wind_coefficients'),
        read_coefficients(ship, 'current_coefficients'),
        (ship.wind_area_front, ship.wind_area_side),
        (ship.current_area_front or ship.beam * ship.draft,
         ship.current_area_side or ship.length * ship.draft),
        shared.air_density, shared.water_density,
        ship_wind(ship), tuple(shared.current), other)


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
