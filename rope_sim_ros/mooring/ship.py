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

import math
from typing import List, Tuple

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


def reports_ship_loads(setup: ArrangementParams) -> bool:
    """Tell whether the ship's wind, current and passing-ship loads are outputs of a run."""
    ship = setup.ship
    return (not setup.single and (ship.free or ship.wind_speed > 0.0 or setup.passing.present
                                  or any(setup.shared.current)))
