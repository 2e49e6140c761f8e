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
Rope material presets per nominal diameter: mass per length, EA, MBL and hydrodynamics.

The hydrodynamic coefficients have MoorDyn's meanings: Cd on the nominal diameter d, CdAx on
the circumference pi d, Ca and CaAx of the volume displaced by the volume-equivalent
diameter dv (config/materials.yaml says where each value comes from). A preset may also
give a load-extension curve, as strains and tensions in fractions of its MBL: scaled by the
MBL at the diameter, it is the line's strain-tension curve (tension_curve.py) when the
parameters ask for it (load_extension: curve).
"""

from dataclasses import dataclass
import math
from typing import Any, Mapping

from .tension_curve import check_curve


class MaterialError(ValueError):
    """A material name or a materials file entry is not usable."""


@dataclass(frozen=True)
class MaterialProperties:
    """
    What a preset gives for one diameter.

    :ivar name: preset name, e.g. 'polyester'.
    :ivar mass_per_length: mass per unit length [kg/m].
    :ivar axial_stiffness: static EA [N].
    :ivar mbl: minimum breaking load [N].
    :ivar working_load_limit: OCIMF MEG4 working load limit [N].
    :ivar volume_diameter_ratio: volume-equivalent diameter / nominal diameter, dv / d.
    :ivar normal_drag_coefficient: MoorDyn's Cd, on the nominal diameter.
    :ivar tangential_drag_coefficient: MoorDyn's CdAx, on the circumference pi d.
    :ivar normal_added_mass_coefficient: MoorDyn's Ca, of the displaced volume.
    :ivar tangential_added_mass_coefficient: MoorDyn's CaAx, of the displaced volume.
    :ivar diameter: the nominal diameter d they were evaluated at [m].
    :ivar tension_curve: the load-extension as (strain, tension [N]) pairs at this diameter,
        from (0, 0); () where the preset has none.
    """

    name: str
    mass_per_length: float
    axial_stiffness: float
    mbl: float
    working_load_limit: float
    volume_diameter_ratio: float = 1.0
    normal_drag_coefficient: float = 0.0
    tangential_drag_coefficient: float = 0.0
    normal_added_mass_coefficient: float = 0.0
    tangential_added_mass_coefficient: float = 0.0
    diameter: float = 0.0
    tension_curve: tuple = ()

    @property
    def volume_diameter(self) -> float:
        """Volume-equivalent diameter dv = ratio * d [m]."""
        return self.volume_diameter_ratio * self.diameter


def _polynomial(terms, diameter: float) -> float:
    return float(sum(c * diameter ** p for c, p in terms))


def _raw(name: str, entry: Mapping, key: str) -> Any:
    """Return entry[key], or say which preset lacks it."""
    if key not in entry:
        raise MaterialError(f'material {name!r} in the materials file has no {key!r}')
    return entry[key]


def _finite(name: str, key: str, value: Any) -> float:
    """Return value as a float if it is a finite number >= 0, else say what is wrong."""
    if (isinstance(value, bool) or not isinstance(value, (int, float))
            or not (math.isfinite(value) and value >= 0.0)):
        raise MaterialError(f'material {name!r}: {key} = {value!r} is not a number >= 0')
    return float(value)


class MaterialLibrary:
    """The presets of a materials file (params/materials.py reads it)."""

    def __init__(self, entries: Mapping[str, Mapping]):
        """Keep the parsed `materials:` map of a materials file."""
        self._entries = dict(entries)

    @property
    def names(self) -> tuple:
        """Preset names, sorted."""
        return tuple(sorted(self._entries))

    def properties(self, name: str, diameter: float) -> MaterialProperties:
        """
        Evaluate a preset at a nominal diameter [m].

        :raises MaterialError: unknown preset name, or an entry lacking a value or with one
            that is not allowed (named).
        """
        if name not in self._entries:
            raise MaterialError(
                f'unknown material {name!r}; allowed: {", ".join(self.names)}')
        entry = self._entries[name]
        mbl = _polynomial(entry['mbl'], diameter)
        stiffness = entry['axial_stiffness']
        if isinstance(stiffness, dict):
            ea = float(stiffness['mbl_multiple']) * mbl
        else:
            ea = _polynomial(stiffness, diameter)
        mass = _polynomial(entry['mass_per_length'], diameter)
        ratio = _raw(name, entry, 'volume_diameter_ratio')
        if isinstance(ratio, dict):
            # from the fibre's density: the line displaces its mass / density per metre
            ratio = math.sqrt(4.0 * mass / (math.pi * _form(name, ratio, 'density'))) / diameter
        else:
            ratio = _finite(name, 'volume_diameter_ratio', ratio)
        drag = _raw(name, entry, 'normal_drag_coefficient')
        if isinstance(drag, dict):
            # MoorPy's Cd is on dv: the same force per metre on d needs Cd dv / d
            drag = _form(name, drag, 'on_volume_diameter') * ratio
        else:
            drag = _finite(name, 'normal_drag_coefficient', drag)
        other = {key: _finite(name, key, _raw(name, entry, key)) for key in (
            'tangential_drag_coefficient', 'normal_added_mass_coefficient',
            'tangential_added_mass_coefficient')}
        curve = _tension_curve(name, entry.get('tension_curve'), mbl)
        return MaterialProperties(
            name=name,
            mass_per_length=mass,
            axial_stiffness=ea,
            mbl=mbl,
            working_load_limit=float(entry['working_load_fraction']) * mbl,
            volume_diameter_ratio=ratio,
            normal_drag_coefficient=drag,
            diameter=diameter,
            tension_curve=curve,
            **other)


def _form(name: str, value: Mapping, key: str) -> float:
    """Return the number of a one-entry map {key: number}, refusing any other key."""
    number = value.get(key)
    if (isinstance(number, bool) or not isinstance(number, (int, float))
            or not (math.isfinite(number) and number > 0.0)):
        raise MaterialError(
            f'material {name!r}: {value!r} is not allowed here; expected {{{key}: number > 0}}')
    return float(number)


def _tension_curve(name: str, value: Any, mbl: float) -> tuple:
    """
    Return a preset's curve as (strain, tension [N]) pairs at its MBL; () where it has none.

    The file gives {mbl_fraction: [[strain, tension / MBL], ...]}: one curve for every
    diameter, as the sources give it.
    """
    if value is None:
        return ()
    pairs = value.get('mbl_fraction') if isinstance(value, dict) and len(value) == 1 else None
    if not isinstance(pairs, list):
        raise MaterialError(f'material {name!r}: tension_curve = {value!r} is not allowed; '
                            'expected {mbl_fraction: [[strain, tension / MBL], ...]}')
    try:
        return check_curve([(pair[0], pair[1] * mbl) for pair in pairs])
    except (TypeError, IndexError, ValueError) as e:
        raise MaterialError(f'material {name!r}: {e}') from None
