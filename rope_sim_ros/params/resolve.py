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

"""A line's parameters resolved into the model's numbers: its material's where it gives none."""

import numpy as np

from .table import LineParams, ParameterError
from ..model.materials import MaterialProperties
from ..model.rope import critical_axial_damping, RopeProperties


def rope_properties(params: LineParams, material: MaterialProperties) -> RopeProperties:
    """
    Resolve the parameters into the physical numbers of the line.

    A coefficient of -1 and a volume_diameter of 0 take the material's value; quay_normal
    is made a unit vector (all zeros stay zeros: no quay). load_extension 'curve' gives the
    line the material's strain-tension curve.

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
    normal = np.array(params.quay_normal, dtype=float)
    size = float(np.linalg.norm(normal))
    return RopeProperties(
        segments=params.segments, length=params.length, mass_per_length=mass,
        axial_stiffness=ea, axial_damping=ba,
        bending_stiffness_ratio=params.bending_stiffness_ratio,
        bending_damping_ratio=params.bending_damping_ratio,
        damping_model=params.damping_model,
        air_drag_coefficient=params.air_drag_coefficient,
        gravity=tuple(params.gravity), max_strain=params.max_strain,
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
        air_density=params.air_density, water_level=params.water_level,
        water_density=params.water_density, current=tuple(params.current),
        seabed_level=params.seabed_level, seabed_stiffness=params.seabed_stiffness,
        seabed_damping=params.seabed_damping, seabed_friction=params.seabed_friction,
        quay_edge=tuple(params.quay_edge),
        quay_normal=tuple(normal / size if size > 0.0 else normal),
        quay_depth=params.quay_depth, payload_volume=params.payload_volume,
        payload_drag_area=params.payload_drag_area,
        payload_added_mass=params.payload_added_mass_coefficient,
        tension_curve=material.tension_curve if params.load_extension == 'curve' else ())


def _own(value: float, material_value: float) -> float:
    """Return a coefficient parameter, or the material's where it is -1 (see params.py)."""
    return material_value if value < 0.0 else value
