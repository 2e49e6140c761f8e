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
The start shape of a line: the catenary in its environment, before relax brings it to rest.

A line starts at rest between its ends: in air, in water (buoyant below the surface) and on
a seabed. catenary.py solves the elastic catenary; here the line's weights in air and water
and its ground are put to it.
"""

import math

import numpy as np

from . import catenary
from ..objects import Environment, LineType


def line_weights(line_type: LineType, environment: Environment) -> tuple:
    """
    Return a line's weight per metre in air and in water [N/m] along gravity.

    (m - rho_air A_v) |g| and (m - rho_water A_v) |g|, A_v = pi dv^2 / 4 with dv the volume
    diameter (the nominal one where it is 0): the physics' weight and buoyancy of a metre
    wholly in the one or the other. The second is negative for a line lighter than water.
    """
    g = math.hypot(*environment.gravity)
    dv = getattr(line_type, 'volume_diameter', 0.0) or line_type.diameter
    area = 0.25 * math.pi * dv * dv
    m = line_type.mass_per_length
    return ((m - getattr(environment, 'air_density', 0.0) * area) * g,
            (m - getattr(environment, 'water_density', 0.0) * area) * g)


def start_shape(line_type: LineType, environment: Environment, end_a, end_b, length: float,
                segments: int) -> np.ndarray:
    """
    Return the start shape (N+1, 3) of a uniform line between two ends in its environment.

    catenary.initial_shape with the line's weight in air and in water (line_weights), its
    EA or strain-tension curve, the surface's ramp width dv, and a seabed (or none) at which
    a laid line sinks by its weight over k_b d, as it does in the physics. relax then brings
    it to the model's exact rest.

    :raises catenary.CatenaryError: an input is invalid.
    """
    w_air, w_water = line_weights(line_type, environment)
    water_level = getattr(environment, 'water_level', -math.inf)
    seabed_level = getattr(environment, 'seabed_level', -math.inf)
    dv = getattr(line_type, 'volume_diameter', 0.0) or line_type.diameter
    w_bed = w_water if seabed_level < water_level else w_air
    support = getattr(environment, 'seabed_stiffness', 0.0) * line_type.diameter
    sink = max(w_bed, 0.0) / support if support > 0.0 else 0.0
    return catenary.initial_shape(
        end_a, end_b, length, segments, max(w_air, 0.0), line_type.axial_stiffness,
        np.asarray(environment.gravity, dtype=float),
        submerged_weight_per_length=w_water if water_level > -math.inf else None,
        water_level=water_level, volume_diameter=dv, seabed_level=seabed_level,
        seabed_sink=sink, tension_curve=getattr(line_type, 'curve', None))
