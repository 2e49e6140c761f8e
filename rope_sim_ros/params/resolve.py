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
Parameters resolved into the model's numbers: a line's and the environment of a mooring.

A line's numbers take its material's where it gives none; the one environment of a mooring
(its water, ground, current, wind and waves) is its shared parameters and its ship's wind
and waves.
"""

from dataclasses import replace
from typing import Optional

import numpy as np

from .ship import ShipParams
from .table import LineParams, ParameterError
from ..model.materials import MaterialProperties
from ..model.objects import Environment
from ..model.rope import critical_axial_damping, RopeProperties
from ..model.ship.waves import Waves
from ..model.ship.wind import GustyWind, Wind


def rope_properties(params: LineParams, material: MaterialProperties) -> RopeProperties:
    """
    Resolve the parameters into the physical numbers of the line.

    Its own numbers: environment() gives what it lives in. A coefficient of -1 and a
    volume_diameter of 0 take the material's value; load_extension 'curve' gives the line
    the material's strain-tension curve.

    :raises ParameterError: load_extension is 'curve' and the material has no curve.
    """
    if params.load_extension == 'curve' and not material.tension_curve:
        raise ParameterError(
            f"parameter 'load_extension' = 'curve' is not allowed with material "
            f'{material.name!r}: it has no tension_curve in the materials file; set '
            "load_extension to 'linear' or choose a material with one")
    mass = params.mass_per_length or material.mass_per_length
    ea = params.axial_stiffness or material.axial_stiffness
    ba = params.axial_damping or critical_axial_damping(params.length, mass, ea)
    return RopeProperties(
        segments=params.segments, length=params.length, mass_per_length=mass,
        axial_stiffness=ea, axial_damping=ba,
        bending_stiffness_ratio=params.bending_stiffness_ratio,
        bending_damping_ratio=params.bending_damping_ratio,
        damping_model=params.damping_model,
        air_drag_coefficient=params.air_drag_coefficient,
        max_strain=params.max_strain,
        superelastic_adjustment=params.superelastic_adjustment,
        payload_mass=params.payload_mass,
        diameter=params.diameter,
        volume_diameter=params.volume_diameter or material.volume_diameter,
        mbl=material.mbl,
        normal_drag=_own(params.normal_drag_coefficient, material.normal_drag_coefficient),
        tangential_drag=_own(params.tangential_drag_coefficient,
                             material.tangential_drag_coefficient),
        normal_added_mass=_own(params.normal_added_mass_coefficient,
                               material.normal_added_mass_coefficient),
        tangential_added_mass=_own(params.tangential_added_mass_coefficient,
                                   material.tangential_added_mass_coefficient),
        payload_volume=params.payload_volume,
        payload_drag_area=params.payload_drag_area,
        payload_added_mass=params.payload_added_mass_coefficient,
        tension_curve=material.tension_curve if params.load_extension == 'curve' else ())


def environment(shared: LineParams, ship: Optional[ShipParams] = None) -> Environment:
    """
    Return the one environment of a mooring: its shared parameters, its ship's wind and waves.

    quay_normal is made a unit vector (all zeros stay zeros: no quay).

    :param ship: the ship's parameters (wind_*, waves.*); None: no wind and no waves (a
        line alone).
    :raises ValueError: a number the model refuses (objects.Environment's message).
    """
    normal = np.array(shared.quay_normal, dtype=float)
    size = float(np.linalg.norm(normal))
    built = Environment(
        gravity=tuple(float(c) for c in shared.gravity), air_density=float(shared.air_density),
        water_level=float(shared.water_level), water_density=float(shared.water_density),
        current=tuple(float(c) for c in shared.current),
        seabed_level=float(shared.seabed_level),
        seabed_stiffness=float(shared.seabed_stiffness),
        seabed_damping=float(shared.seabed_damping),
        seabed_friction=float(shared.seabed_friction),
        quay_edge=tuple(float(c) for c in shared.quay_edge),
        quay_normal=tuple(float(c) for c in (normal / size if size > 0.0 else normal)),
        quay_depth=float(shared.quay_depth), wind=Wind() if ship is None else wind(ship))
    if ship is None or ship.waves_spectrum == 'none':
        return built
    return replace(built, waves=Waves.make(
        ship.waves_spectrum, ship.waves_height, ship.waves_period, ship.waves_direction,
        ship.waves_peak_enhancement, ship.waves_seed, built.depth, built.g))


def wind(ship: ShipParams) -> Wind:
    """Return the wind of the ship's parameters: steady, or gusty about its mean."""
    gusts = None
    if ship.wind_spectrum != 'none' and ship.wind_speed > 0.0:
        gusts = GustyWind(ship.wind_spectrum, ship.wind_speed, ship.wind_seed)
    return Wind(ship.wind_speed, ship.wind_direction, gusts)


def _own(value: float, material_value: float) -> float:
    """Return a coefficient parameter, or the material's where it is -1 (see params.py)."""
    return material_value if value < 0.0 else value
