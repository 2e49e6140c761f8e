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
The free ship of an arrangement as model objects: its body and its fenders.

One place turns the ship.* and fender parameters into a model.body.Body and Fenders, for the
Mooring that steps them and for the statics (equilibrium, stiffness) alike.
"""

from typing import List

import numpy as np

from ..model.body import Body, Fender
from ..params.arrangement import ArrangementParams


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
