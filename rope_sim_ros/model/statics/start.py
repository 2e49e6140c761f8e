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
from ..forces import fluid
from ..objects import Environment, LineType
from ..rope import RopeProperties


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


def wet_fraction(z, water_level: float, width) -> np.ndarray:
    """
    How much of a body of height `width` centred at z is under water, 0..1 (elementwise).

    The physics' own smooth submergence (forces/fluid.py point_fraction, a width below 1e-6 m
    taken as 1e-6 m, as the steps take it); no water (water_level = -inf) gives 0.
    """
    z = np.asarray(z, dtype=float)
    width = np.maximum(np.broadcast_to(np.asarray(width, dtype=float), z.shape), 1e-6)
    return np.vectorize(fluid.point_fraction, otypes=[float])(z, float(water_level), width)


def hanging_shape(props: RopeProperties, environment: Environment,
                  top: np.ndarray) -> np.ndarray:
    """
    Particles (N+1, 3) of a line hanging straight down from `top` with its payload, at rest.

    Particle N is at top, particle 0 (the payload) lowest, along gravity (-z without it).
    Each segment is stretched by the tension it carries: the weight of the payload and of
    the line below it (the lumped masses below: the payload's half segment first), less
    the buoyancy of the air or water each lumped mass is in (a segment that would carry
    a net upward pull is left at its rest length). Which fluid depends on where the
    particles end up: a few passes settle it (each moves them by the stretch only).
    """
    gravity = np.asarray(environment.gravity, dtype=float)
    g = float(np.linalg.norm(gravity))
    down = gravity / g if g > 0.0 else np.array([0.0, 0.0, -1.0])
    n = props.segments
    lumped = np.full(n + 1, props.segment_length)
    lumped[[0, -1]] *= 0.5
    masses = props.mass_per_length * lumped
    masses[0] += props.payload_mass
    volumes = props.volume_area * lumped
    widths = np.full(n + 1, props.volume_diameter or props.diameter)
    volumes[0] += props.payload_volume
    widths[0] = props.payload_volume ** (1.0 / 3.0) if props.payload_volume > 0.0 else widths[0]
    shape = top + np.outer(props.segment_length * (n - np.arange(n + 1)), down)
    for _ in range(4 if math.isfinite(environment.water_level) else 1):
        wet = wet_fraction(shape[:, 2], environment.water_level, widths)
        density = environment.water_density * wet + environment.air_density * (1.0 - wet)
        below = np.cumsum(masses - density * volumes)[:-1]  # net mass under segment j
        lengths = props.segment_length * (1.0 + props.strain_at(g * np.maximum(below, 0.0)))
        shape = np.empty((n + 1, 3))
        shape[n] = top
        for j in range(n - 1, -1, -1):
            shape[j] = shape[j + 1] + lengths[j] * down
    return shape
