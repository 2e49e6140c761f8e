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
A rigid body the lines hang from (a free ship) and the fenders it rests on: the objects.

A System (objects.py) packs them into its BODY and FENDER tables (layout.py), as it packs its
lines and points; forces/body.py and forces/fender.py say how they act. Here: what they are,
checked, and the ship's numbers turned into a body's (its inertia from its radii of gyration,
its hydrostatic stiffness from its waterplane and metacentric heights).
"""

from dataclasses import dataclass, field
import math
from typing import Optional, Sequence, Tuple

import numpy as np

from .frames import rotation_matrix
from .layout import (BODY_ADDED, BODY_ADDED_MATRIX, BODY_COLUMNS, BODY_FULL_ADDED, BODY_HULL,
                     BODY_INERTIA, BODY_LINEAR_DAMPING, BODY_MASS, BODY_MODE, BODY_MODES,
                     BODY_OMEGA, BODY_ORIGIN, BODY_POSITION, BODY_QUADRATIC_DAMPING,
                     BODY_QUATERNION, BODY_REST_Z, BODY_RESTORING, BODY_VELOCITY, FENDER_BODY,
                     FENDER_CAPACITY, FENDER_COLUMNS, FENDER_CURVE_COMPRESSION,
                     FENDER_CURVE_REACTION, FENDER_FRICTION, FENDER_NORMAL, FENDER_POINTS,
                     FENDER_POSITION, MODE_CAPACITY, MODE_COLUMNS, MODE_INPUT, MODE_OUTPUT,
                     MODE_POLE, MODE_STATE, MODE_WEIGHT)
from .ship.hydro import HydroDatabase
from .ship.radiation import consistent_added_mass, database_modes, RadiationModes


# A free ship past any of these bounds has left every state a moored ship can be in (a load
# past what the model holds, numbers running away): it restarts at its start pose at rest.
MAX_TILT = math.radians(60.0)  # [rad] of its deck from level: capsized (GM is linear anyway)
MIN_HEAVE_BOUND = 10.0  # [m] up or down from where it floats; its draft if that is more
MAX_DRIFT = 5000.0  # [m] from where it floats, horizontally
MAX_SPEED = 25.0  # [m/s] (49 kn) past any ship's
MAX_TURN_RATE = 1.0  # [rad/s] a turn in 6 s


def _numbers(name: str, value, size: int, low: float = -math.inf) -> Tuple[float, ...]:
    """Return value as `size` finite floats >= low, or raise ValueError naming it."""
    try:
        numbers = tuple(float(c) for c in value)
    except (TypeError, ValueError):
        numbers = ()
    if len(numbers) != size or not all(math.isfinite(c) and c >= low for c in numbers):
        bound = f' >= {low:g}' if low > -math.inf else ''
        raise ValueError(f'{name} {value!r} must be {size} finite numbers{bound}')
    return numbers


@dataclass
class Body:
    """
    A rigid body in six degrees of freedom; its reference point is its centre of gravity.

    :ivar mass: [kg].
    :ivar inertia: principal moments of inertia about the centre of gravity, roll, pitch,
        yaw (body axes) [kg m^2].
    :ivar added: added mass in surge, sway, heave [kg] and roll, pitch, yaw [kg m^2].
    :ivar linear_damping, quadratic_damping: per degree of freedom, body axes.
    :ivar restoring: hydrostatic heave [N/m], roll and pitch [N m/rad] stiffness.
    :ivar rest_z: z of the body origin where it floats freely [m].
    :ivar hull: the hull box the fenders touch: length, beam, draft [m].
    :ivar origin: the body origin from the centre of gravity, body axes [m].
    :ivar position: the centre of gravity [m]; quaternion: (x, y, z, w), body to world;
        velocity [m/s]; omega: angular velocity, world axes [rad/s]. Views of the System's
        BODY table once packed.
    :ivar added_matrix: None, or a hydrodynamic database's added mass at infinite frequency,
        6x6 about the centre of gravity in body axes (its symmetric part), which replaces
        `added` in its motion.
    :ivar radiation: None, or its radiation memory's modes (model/ship/radiation.py).
    """

    mass: float
    inertia: Tuple[float, float, float]
    added: Tuple[float, ...] = (0.0,) * 6
    linear_damping: Tuple[float, ...] = (0.0,) * 6
    quadratic_damping: Tuple[float, ...] = (0.0,) * 6
    restoring: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    rest_z: float = 0.0
    hull: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    origin: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))
    quaternion: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 0.0, 1.0]))
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    omega: np.ndarray = field(default_factory=lambda: np.zeros(3))
    added_matrix: Optional[np.ndarray] = None
    radiation: Optional[RadiationModes] = None

    def __post_init__(self):
        """Check every number (ValueError naming the first that is wrong)."""
        if not (math.isfinite(self.mass) and self.mass > 0.0):
            raise ValueError(f'body mass {self.mass!r} must be a finite number > 0')
        self.inertia = _numbers('body inertia', self.inertia, 3, 0.0)
        for name in ('added', 'linear_damping', 'quadratic_damping'):
            setattr(self, name, _numbers(f'body {name}', getattr(self, name), 6, 0.0))
        self.restoring = _numbers('body restoring', self.restoring, 3, 0.0)
        self.hull = _numbers('body hull', self.hull, 3, 0.0)
        self.origin = _numbers('body origin', self.origin, 3)
        self.position = np.array(_numbers('body position', self.position, 3))
        self.quaternion = np.array(_numbers('body quaternion', self.quaternion, 4))
        norm = float(np.linalg.norm(self.quaternion))
        if norm < 1e-9:
            raise ValueError('body quaternion must not be zero')
        self.quaternion /= norm
        self.velocity = np.array(_numbers('body velocity', self.velocity, 3))
        self.omega = np.array(_numbers('body omega', self.omega, 3))
        if self.added_matrix is not None:
            added = np.asarray(self.added_matrix, dtype=float)
            if added.shape != (6, 6) or not np.isfinite(added).all():
                raise ValueError('body added_matrix must be 6x6 finite numbers')
            # its symmetric part: a solver's A_inf is symmetric but for its numerics, and the
            # step's Cholesky solve takes a symmetric mass matrix
            added = 0.5 * (added + added.T)
            if np.linalg.eigvalsh(self._rigid_mass() + added).min() <= 0.0:
                raise ValueError('body added_matrix: its mass and inertia with the added mass '
                                 'must be positive definite')
            self.added_matrix = added
        if self.radiation is not None and self.radiation.poles.size > MODE_CAPACITY:
            raise ValueError(f'body radiation: {self.radiation.poles.size} modes, at most '
                             f'{MODE_CAPACITY}')

    def _rigid_mass(self) -> np.ndarray:
        """Return its rigid mass and inertia about the centre of gravity, body axes (6, 6)."""
        return np.diag([self.mass] * 3 + list(self.inertia))

    def mass_matrix(self) -> np.ndarray:
        """Return its mass and inertia with the added ones, body axes (6, 6)."""
        if self.added_matrix is not None:
            return self._rigid_mass() + self.added_matrix
        return self._rigid_mass() + np.diag(self.added)

    @classmethod
    def ship(cls, mass: float, center_of_gravity: Sequence[float],
             radii_of_gyration: Sequence[float], added_mass: Sequence[float],
             linear_damping: Sequence[float], quadratic_damping: Sequence[float],
             waterplane_area: float, metacentric_height: Sequence[float],
             start_position: Sequence[float], start_yaw: float, hull: Sequence[float],
             water_density: float, g: float,
             hydrodynamics: Optional[HydroDatabase] = None) -> 'Body':
        """
        Return a ship floating at rest at its start pose (the ship.* parameters' meanings).

        Its inertia is m k^2 per radius of gyration k; its heave stiffness rho g A_wp, its
        roll and pitch stiffnesses m g GM_T and m g GM_L. With a hydrodynamic database its
        added mass is the database's at infinite frequency (`added` its diagonal) and it
        carries the radiation memory of the database's damping.
        """
        cog = np.array(_numbers('center_of_gravity', center_of_gravity, 3))
        half = 0.5 * start_yaw
        quaternion = np.array([0.0, 0.0, math.sin(half), math.cos(half)])
        origin = np.array(_numbers('start_position', start_position, 3))
        position = origin + rotation_matrix(quaternion) @ cog
        radii = _numbers('radii_of_gyration', radii_of_gyration, 3, 0.0)
        gm = _numbers('metacentric_height', metacentric_height, 2)
        added_matrix = radiation = None
        if hydrodynamics is not None:
            radiation = database_modes(hydrodynamics)
            added_matrix = consistent_added_mass(hydrodynamics, radiation)
            added_mass = tuple(max(float(a), 0.0) for a in np.diagonal(added_matrix))
        return cls(mass, tuple(mass * k * k for k in radii), added_mass, linear_damping,
                   quadratic_damping,
                   (water_density * g * waterplane_area, mass * g * gm[0], mass * g * gm[1]),
                   float(origin[2]), hull, tuple(-cog), position, quaternion,
                   added_matrix=added_matrix, radiation=radiation)

    def origin_pose(self) -> Tuple[np.ndarray, np.ndarray]:
        """Return the body origin's position [m] and the orientation (x, y, z, w) now."""
        rotation = rotation_matrix(self.quaternion)
        return self.position + rotation @ np.asarray(self.origin), self.quaternion.copy()

    def energy(self) -> Tuple[float, float]:
        """
        Return its kinetic energy and the potential of its hydrostatic restoring now [J].

        Kinetic with the added masses (a database's full one at infinite frequency); the
        radiation memory's waves are not counted; the potential
        1/2 (k_heave dz^2 + k_roll phi^2 + k_pitch theta^2), dz the body origin's rise
        above where it floats freely, phi and theta its roll and pitch.
        """
        rotation = rotation_matrix(self.quaternion)
        velocity = rotation.T @ self.velocity
        omega = rotation.T @ self.omega
        if self.added_matrix is not None:
            u = np.concatenate((velocity, omega))
            kinetic = 0.5 * float(u @ self.mass_matrix() @ u)
        else:
            linear = self.mass + np.asarray(self.added[:3])
            angular = np.asarray(self.inertia) + np.asarray(self.added[3:])
            kinetic = 0.5 * float(linear @ velocity ** 2 + angular @ omega ** 2)
        heave = float((self.position + rotation @ np.asarray(self.origin))[2]) - self.rest_z
        x, y, z, w = self.quaternion
        roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
        pitch = math.asin(min(max(2.0 * (w * y - z * x), -1.0), 1.0))
        k_heave, k_roll, k_pitch = self.restoring
        return kinetic, 0.5 * (k_heave * heave ** 2 + k_roll * roll ** 2 + k_pitch * pitch ** 2)

    def row(self) -> np.ndarray:
        """Return the body's row of the BODY table (layout.py)."""
        row = np.zeros(BODY_COLUMNS)
        row[BODY_POSITION:BODY_POSITION + 3] = self.position
        row[BODY_QUATERNION:BODY_QUATERNION + 4] = self.quaternion
        row[BODY_VELOCITY:BODY_VELOCITY + 3] = self.velocity
        row[BODY_OMEGA:BODY_OMEGA + 3] = self.omega
        row[BODY_MASS] = self.mass
        row[BODY_INERTIA:BODY_INERTIA + 3] = self.inertia
        row[BODY_ADDED:BODY_ADDED + 6] = self.added
        row[BODY_LINEAR_DAMPING:BODY_LINEAR_DAMPING + 6] = self.linear_damping
        row[BODY_QUADRATIC_DAMPING:BODY_QUADRATIC_DAMPING + 6] = self.quadratic_damping
        row[BODY_RESTORING:BODY_RESTORING + 3] = self.restoring
        row[BODY_REST_Z] = self.rest_z
        row[BODY_HULL:BODY_HULL + 3] = self.hull
        row[BODY_ORIGIN:BODY_ORIGIN + 3] = self.origin
        if self.added_matrix is not None:
            row[BODY_FULL_ADDED] = 1.0
            row[BODY_ADDED_MATRIX:BODY_ADDED_MATRIX + 36] = self.added_matrix.ravel()
        if self.radiation is not None:
            modes = self.radiation
            row[BODY_MODES] = modes.poles.size
            for i in range(modes.poles.size):
                m = BODY_MODE + i * MODE_COLUMNS
                row[m + MODE_POLE:m + MODE_POLE + 2] = modes.poles[i].real, modes.poles[i].imag
                row[m + MODE_WEIGHT] = modes.weights[i]
                row[m + MODE_INPUT:m + MODE_INPUT + 6] = modes.inputs[i].real
                row[m + MODE_INPUT + 6:m + MODE_INPUT + 12] = modes.inputs[i].imag
                row[m + MODE_OUTPUT:m + MODE_OUTPUT + 6] = modes.outputs[i].real
                row[m + MODE_OUTPUT + 6:m + MODE_OUTPUT + 12] = modes.outputs[i].imag
        return row


@dataclass(frozen=True)
class Fender:
    """
    A fender on the quay (forces/fender.py says how it pushes).

    :ivar position: the centre of its face, uncompressed [m].
    :ivar normal: out of the quay toward the ship (normalised here).
    :ivar curve: (compression [m], reaction [N]) pairs from (0, 0), compressions rising.
    :ivar friction: friction coefficient of its face against the hull.
    :ivar body: the index of the body whose hull it touches.
    """

    position: Tuple[float, float, float]
    normal: Tuple[float, float, float]
    curve: Tuple[Tuple[float, float], ...]
    friction: float = 0.0
    body: int = 0

    def __post_init__(self):
        """Check the numbers and the curve (ValueError naming what is wrong)."""
        object.__setattr__(self, 'position', _numbers('fender position', self.position, 3))
        normal = np.array(_numbers('fender normal', self.normal, 3))
        length = float(np.linalg.norm(normal))
        if length < 1e-9:
            raise ValueError('fender normal must not be zero')
        object.__setattr__(self, 'normal', tuple(normal / length))
        pairs = tuple(_numbers('fender curve point', pair, 2, 0.0) for pair in self.curve)
        if len(pairs) < 2 or pairs[0] != (0.0, 0.0) or len(pairs) > FENDER_CAPACITY or \
                any(b[0] <= a[0] or b[1] < a[1] for a, b in zip(pairs, pairs[1:])):
            raise ValueError(f'fender curve {self.curve!r} must start at (0, 0), hold at most '
                             f'{FENDER_CAPACITY} points, its compressions rising and its '
                             'reactions never falling')
        object.__setattr__(self, 'curve', pairs)
        if not (math.isfinite(self.friction) and self.friction >= 0.0):
            raise ValueError(f'fender friction {self.friction!r} must be a finite number >= 0')

    def row(self) -> np.ndarray:
        """Return the fender's row of the FENDER table (layout.py)."""
        row = np.zeros(FENDER_COLUMNS)
        row[FENDER_POSITION:FENDER_POSITION + 3] = self.position
        row[FENDER_NORMAL:FENDER_NORMAL + 3] = self.normal
        row[FENDER_FRICTION] = self.friction
        row[FENDER_BODY] = self.body
        row[FENDER_POINTS] = len(self.curve)
        for i, (compression, push) in enumerate(self.curve):
            row[FENDER_CURVE_COMPRESSION + i] = compression
            row[FENDER_CURVE_REACTION + i] = push
        return row


def clear_memory(row: np.ndarray) -> None:
    """Clear a body's radiation memory in its BODY row (in place): no past motion."""
    for i in range(int(row[BODY_MODES])):
        m = BODY_MODE + i * MODE_COLUMNS
        row[m + MODE_STATE:m + MODE_STATE + 2] = 0.0


def out_of_bounds(row: np.ndarray, start: np.ndarray) -> str:
    """
    Say how a body has left the bounds of a moored ship ('' if it has not).

    :param row: its BODY row now; start: its row where it floats at rest (layout.py).
    :returns: e.g. 'sunk 2412.0 m', 'tilted 85 deg', 'moving at 3000.0 m/s'; 'not finite'.
    """
    state = row[:BODY_OMEGA + 3]
    if not np.isfinite(state).all():
        return 'not finite'
    rotation = rotation_matrix(row[BODY_QUATERNION:BODY_QUATERNION + 4])
    origin = row[BODY_POSITION:BODY_POSITION + 3] + rotation @ row[BODY_ORIGIN:BODY_ORIGIN + 3]
    start_rotation = rotation_matrix(start[BODY_QUATERNION:BODY_QUATERNION + 4])
    rest = start[BODY_POSITION:BODY_POSITION + 3] + start_rotation @ start[
        BODY_ORIGIN:BODY_ORIGIN + 3]
    heave = float(origin[2] - row[BODY_REST_Z])
    tilt = math.acos(min(max(float(rotation[2, 2]), -1.0), 1.0))
    drift = float(np.hypot(*(origin[:2] - rest[:2])))
    speed = float(np.linalg.norm(row[BODY_VELOCITY:BODY_VELOCITY + 3]))
    turn = float(np.linalg.norm(row[BODY_OMEGA:BODY_OMEGA + 3]))
    if abs(heave) > max(row[BODY_HULL + 2], MIN_HEAVE_BOUND):
        return f'{"sunk" if heave < 0.0 else "risen"} {abs(heave):.1f} m'
    if tilt > MAX_TILT:
        return f'tilted {math.degrees(tilt):.0f} deg'
    if drift > MAX_DRIFT:
        return f'{drift:.0f} m off its start'
    if speed > MAX_SPEED:
        return f'moving at {speed:.1f} m/s'
    if turn > MAX_TURN_RATE:
        return f'turning at {turn:.2f} rad/s'
    return ''
