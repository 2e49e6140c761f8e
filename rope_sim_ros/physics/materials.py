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

"""Rope material presets: mass per length, axial stiffness EA and MBL per nominal diameter."""

from dataclasses import dataclass
from typing import Mapping

import yaml


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
    """

    name: str
    mass_per_length: float
    axial_stiffness: float
    mbl: float
    working_load_limit: float


def _polynomial(terms, diameter: float) -> float:
    return float(sum(c * diameter ** p for c, p in terms))


class MaterialLibrary:
    """The presets of a materials.yaml file."""

    def __init__(self, entries: Mapping[str, Mapping]):
        """Keep the parsed `materials:` map of a materials file."""
        self._entries = dict(entries)

    @classmethod
    def from_file(cls, path) -> 'MaterialLibrary':
        """
        Read a materials.yaml file.

        :raises MaterialError: the file is missing or has no `materials:` map.
        """
        try:
            with open(path, encoding='utf-8') as f:
                data = yaml.safe_load(f)
        except OSError as e:
            raise MaterialError(f'cannot read materials file {path}: {e.strerror}') from None
        if not isinstance(data, dict) or not isinstance(data.get('materials'), dict):
            raise MaterialError(f'{path} has no "materials:" map')
        return cls(data['materials'])

    @property
    def names(self) -> tuple:
        """Preset names, sorted."""
        return tuple(sorted(self._entries))

    def properties(self, name: str, diameter: float) -> MaterialProperties:
        """
        Evaluate a preset at a nominal diameter [m].

        :raises MaterialError: unknown preset name.
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
        return MaterialProperties(
            name=name,
            mass_per_length=_polynomial(entry['mass_per_length'], diameter),
            axial_stiffness=ea,
            mbl=mbl,
            working_load_limit=float(entry['working_load_fraction']) * mbl)
