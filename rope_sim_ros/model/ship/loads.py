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
The wind, the current and a passing ship on a moored ship, at one instant: one place for all.

- Wind and current: OCIMF-form coefficient tables (coefficients.py) on the velocity of the
  air or water RELATIVE to the ship's origin, in its body axes (a surging ship feels its
  own motion: the current's load on a ship moving in still water is its drag). The wind
  is steady, or gusty about its mean (wind.py), along a direction it comes FROM.
- A passing ship (passing.py, Wang's slender-body loads, in deep water or at the depth of
  the water, summed over the sea bed's images): its midship starts at start_x along the
  moored ship's body x at its start pose and moves along that start heading, separation
  off the centreline, at its speed through the water plus the current's component along
  its track (it holds its track: the current across it it steers against); at each instant
  its stagger and separation are measured in the moored ship's body axes where it is then,
  and the loads take its speed through the water. A current changed at run time changes
  its speed over the ground from the next instant the loads are asked for.

- Waves (waves.py): the first-order and slow-drift loads of the environment's sea state,
  from the ship's hydrodynamic database, at the ship's origin and heading; none without a
  sea state.

Every load is in the ship's body axes about its origin (F_x, F_y, M_z; the waves' in six
degrees of freedom); world_load turns their sum into the frame_id axes a free ship's body
takes.
"""

from dataclasses import dataclass, field, replace
import math
from typing import Optional, Sequence, Tuple

import numpy as np

from .coefficients import CoefficientTable, ocimf_loads
from .passing import Hull, passing_loads
from .waves import ShipWaves


@dataclass(frozen=True)
class PassingShip:
    """
    A ship passing on a parallel course (see the module docstring).

    :ivar hull: its hull; speed: through the water [m/s] > 0; direction +1 / -1 along the
        start heading.
    :ivar start: where its midship is at start_time [s], frame_id (3,); heading: the unit
        vector it moves along (times direction), frame_id (3,).
    :ivar drift: the current's component along heading [m/s]: over the ground it moves at
        direction * speed + drift along heading.
    """

    hull: Hull
    speed: float
    direction: int
    start: np.ndarray
    heading: np.ndarray
    drift: float = 0.0
    start_time: float = 0.0

    @classmethod
    def beside(cls, hull: Hull, speed: float, direction: int, separation: float,
               start_x: float, position: Sequence[float], yaw: float) -> 'PassingShip':
        """Return the ship passing one at `position`, heading `yaw`, from start_x off it."""
        along = np.array([math.cos(yaw), math.sin(yaw), 0.0])
        port = np.array([-math.sin(yaw), math.cos(yaw), 0.0])
        start = np.asarray(position, dtype=float) + start_x * along - separation * port
        return cls(hull, float(speed), int(direction), start, along)

    def midship(self, t: float) -> np.ndarray:
        """Return its midship at time t, frame_id (3,)."""
        return self.start + (self.direction * self.speed + self.drift) * \
            (t - self.start_time) * self.heading

    def in_current(self, t: float, current) -> 'PassingShip':
        """Return it from time t on in a current (frame_id (3,), where the water goes)."""
        drift = float(np.dot(np.asarray(current, dtype=float), self.heading))
        return replace(self, start=self.midship(t), start_time=float(t), drift=drift)


@dataclass
class ShipLoads:
    """
    What acts on the moored ship besides its lines and fenders (module docstring).

    The wind, the current and the fluids' densities are the environment's, read at each call:
    the mooring's one environment, which topics and parameters change.

    :ivar hull: the moored ship's hull (its length and block coefficient count).
    :ivar wind_table, current_table: its coefficients.
    :ivar wind_areas, current_areas: (A_T, A_L) of each table [m^2].
    :ivar passing: a passing ship, or None; it moves in the current (module docstring).
    :ivar depth: the depth of the water [m] (math.inf: deep water), for the passing ship's
        loads (the current's table is the caller's, for this depth).
    :ivar image_pairs: passing.passing_loads's: 0 sums the images until converged.
    :ivar waves: the waves' loads on it (its hydrodynamic database, or none).
    """

    hull: Hull
    wind_table: CoefficientTable
    current_table: CoefficientTable
    wind_areas: Tuple[float, float]
    current_areas: Tuple[float, float]
    passing: Optional[PassingShip] = None
    depth: float = math.inf
    image_pairs: int = 0
    waves: ShipWaves = field(default_factory=ShipWaves)
    # the current the passing ship's track was set for (at run time the current may change)
    _track_current: Optional[tuple] = field(default=None, init=False, repr=False)

    def _follow_current(self, t: Optional[float], current) -> None:
        """Give the passing ship the current's drift from time t on (None: its start)."""
        current = tuple(float(c) for c in current)
        if self.passing is not None and current != self._track_current:
            when = self.passing.start_time if t is None else t
            self.passing = self.passing.in_current(when, current)
        self._track_current = current

    def acts(self, environment) -> bool:
        """Tell whether anything pushes a ship at rest: wind, a current, a passing ship, waves."""
        wind = environment.wind
        return (wind.speed > 0.0 or wind.gusts is not None or any(environment.current)
                or self.passing is not None or environment.waves.sea is not None)

    def at(self, t: float, environment, position, rotation: np.ndarray,
           velocity) -> np.ndarray:
        """
        Return the wind's, the current's and the passing ship's loads at time t, (3, 3).

        Rows: wind, current, passing ship; columns F_x [N], F_y [N], M_z [N m], body axes,
        about the ship's origin.

        :param environment: the objects.Environment: wind, current, air and water densities.
        :param position, rotation, velocity: the ship's origin [m], its orientation matrix
            (body to frame_id) and the origin's velocity [m/s] (frame_id).
        """
        loads = np.zeros((3, 3))
        ship = np.asarray(velocity, dtype=float)
        wind = environment.wind
        if environment.air_density > 0.0 and (wind.speed > 0.0 or wind.gusts is not None):
            air = (wind.velocity(t) - ship) @ rotation
            loads[0] = ocimf_loads(self.wind_table, environment.air_density, air[:2],
                                   *self.wind_areas, self.hull.length)
        water = (np.asarray(environment.current, dtype=float) - ship) @ rotation
        if water[:2].any():
            loads[1] = ocimf_loads(self.current_table, environment.water_density, water[:2],
                                   *self.current_areas, self.hull.length)
        if self.passing is not None:
            self._follow_current(self.passing.start_time if self._track_current is None
                                 else t, environment.current)
            apart = (self.passing.midship(t) - np.asarray(position, dtype=float)) @ rotation
            separation = -apart[1]
            if abs(separation) >= 0.5 * (self.hull.beam + self.passing.hull.beam):
                loads[2] = passing_loads(self.hull, self.passing.hull, self.passing.speed,
                                         separation, apart[0], self.depth,
                                         environment.water_density, self.passing.direction,
                                         image_pairs=self.image_pairs)
        return loads

    def waves_at(self, t: float, environment, position, rotation: np.ndarray) -> tuple:
        """
        Return the wave elevation at the ship's origin [m] and the waves' loads on it (2, 6).

        Rows: first order, slow drift; force [N], moment [N m], body axes about its origin;
        zeros in a calm sea.

        :param position, rotation: the ship's origin [m] and orientation matrix (body to
            frame_id): its heading is the yaw of its body x.
        """
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        return self.waves.at(t, environment.waves, position, yaw)


def world_wrench(wrench: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """Return body-axes wrenches (n, 6: force, moment) summed, in frame_id axes (6,)."""
    total = np.asarray(wrench, dtype=float).reshape(-1, 6).sum(axis=0)
    return np.concatenate([rotation @ total[:3], rotation @ total[3:]])


def world_load(loads: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """Return the sum of body-axes loads (n, 3: F_x, F_y, M_z) in frame_id axes (6,)."""
    total = loads.sum(axis=0)
    force = rotation @ np.array([total[0], total[1], 0.0])
    moment = rotation @ np.array([0.0, 0.0, total[2]])
    return np.concatenate([force, moment])
