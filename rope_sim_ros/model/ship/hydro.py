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
A ship's hydrodynamic database: what a boundary-element solve of its hull gives, as numbers.

The numbers only (the model reads no file): a frequency-domain solve of the floating hull
(`rope_sim hydro`) fills it and the file it is kept in; radiation.py turns it into the
radiation memory of the Cummins equation and waves.py into wave loads.

Conventions (those of the solver that makes it, Capytaine):

- Degrees of freedom: surge, sway, heave [m], roll, pitch, yaw [rad], in the ship's body axes
  (x forward, y to port, z up) about its reference point, the centre of gravity, which lies
  at `reference_point` from the ship's body origin (body axes).
- Time goes as exp(-i omega t): a wave whose elevation at the body origin (x = y = 0) is
  Re(a exp(-i omega t)) gives the first-order force Re(a X exp(-i omega t)), X the
  excitation at that frequency and heading.
- A heading is the direction the waves travel TOWARD, in body axes, counter-clockwise from
  body x [rad] (0: from astern, pi / 2: from starboard, travelling to port).
"""

from dataclasses import dataclass
import math

import numpy as np

DOF = 6
DOF_NAMES = ('surge', 'sway', 'heave', 'roll', 'pitch', 'yaw')


@dataclass(frozen=True)
class HydroDatabase:
    """
    The frequency-domain hydrodynamics of one hull at one water depth (module docstring).

    :ivar omega: wave frequencies [rad/s], (n,), > 0 and rising.
    :ivar added_mass: A(omega), (n, 6, 6) [kg, kg m, kg m^2].
    :ivar radiation_damping: B(omega), (n, 6, 6) [N s/m, N s, N m s].
    :ivar added_mass_infinite: A at infinite frequency, (6, 6).
    :ivar headings: wave headings [rad], (m,), rising, within [-pi, pi].
    :ivar excitation: X, Froude-Krylov and diffraction force per metre of wave amplitude,
        complex, (m, n, 6) [N/m, N m/m].
    :ivar drift: mean drift load per square metre of wave amplitude in surge, sway [N/m^2]
        and yaw [N m/m^2], (m, n, 3).
    :ivar reference_point: the centre of gravity from the body origin, body axes [m], (3,).
    :ivar water_depth: [m], inf for deep water.
    :ivar water_density: [kg/m^3]; g: [m/s^2].
    """

    omega: np.ndarray
    added_mass: np.ndarray
    radiation_damping: np.ndarray
    added_mass_infinite: np.ndarray
    headings: np.ndarray
    excitation: np.ndarray
    drift: np.ndarray
    reference_point: np.ndarray
    water_depth: float
    water_density: float
    g: float

    def __post_init__(self):
        """Check every array's shape and numbers (ValueError naming the first wrong)."""
        omega = np.asarray(self.omega, dtype=float)
        headings = np.asarray(self.headings, dtype=float)
        n, m = omega.size, headings.size
        shapes = {'omega': (n,), 'added_mass': (n, DOF, DOF),
                  'radiation_damping': (n, DOF, DOF), 'added_mass_infinite': (DOF, DOF),
                  'headings': (m,), 'excitation': (m, n, DOF), 'drift': (m, n, 3),
                  'reference_point': (3,)}
        for name, shape in shapes.items():
            dtype = complex if name == 'excitation' else float
            value = np.asarray(getattr(self, name), dtype=dtype)
            if value.shape != shape or not np.isfinite(value).all():
                raise ValueError(f'hydrodynamic database: {name} must be {shape} finite '
                                 f'numbers, not {value.shape}')
            object.__setattr__(self, name, value)
        if n < 2 or omega[0] <= 0.0 or (np.diff(omega) <= 0.0).any():
            raise ValueError('hydrodynamic database: omega must hold at least 2 frequencies '
                             '> 0, rising')
        if m < 1 or (np.diff(headings) <= 0.0).any() or np.abs(headings).max() > math.pi + 1e-9:
            raise ValueError('hydrodynamic database: headings must hold at least 1 heading '
                             'within [-pi, pi], rising')
        if not (self.water_depth > 0.0):
            raise ValueError(f'hydrodynamic database: water_depth {self.water_depth!r} must be '
                             '> 0 (inf for deep water)')
        for name in ('water_density', 'g'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'hydrodynamic database: {name} {value!r} must be a finite '
                                 'number > 0')
