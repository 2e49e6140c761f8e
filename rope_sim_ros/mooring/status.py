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
How close a line is to breaking: its utilisation and the band it is in, for every display.

Utilisation is the line's tension over its minimum breaking load (MBL): the larger of its
two end tensions, the fairlead's on a line hanging between a bollard and a ship. The bands,
which the markers colour and the diagnostics grade:

- OK: below the working load limit (WLL: OCIMF MEG4, 50 % of the MBL for synthetic lines,
  55 % for steel wire; config/materials.yaml);
- ABOVE_WLL: at or past the WLL;
- NEAR_BREAK: at or past NEAR_BREAK of the MBL;
- PARTED: the line has parted (whatever its tension).

No ROS here: the mooring node and the offline plots take the same bands.
"""

from dataclasses import dataclass
import math
from typing import Any, List

from ..params.arrangement import ArrangementParams
from ..params.materials import load_materials

OK = 'ok'
ABOVE_WLL = 'above_wll'
NEAR_BREAK = 'near_break'
PARTED = 'parted'
NEAR_BREAK_FRACTION = 0.9
# Colours (r, g, b) of the bands: green, amber, red; a parted line grey.
COLOURS = {
    OK: (0.10, 0.75, 0.20),
    ABOVE_WLL: (1.00, 0.60, 0.00),
    NEAR_BREAK: (0.90, 0.05, 0.05),
    PARTED: (0.55, 0.55, 0.55),
}
WORDS = {
    OK: 'below the WLL',
    ABOVE_WLL: 'past the WLL',
    NEAR_BREAK: f'past {100 * NEAR_BREAK_FRACTION:g} % of the MBL',
    PARTED: 'parted',
}


@dataclass(frozen=True)
class Rating:
    """
    What a line can carry.

    :ivar mbl: minimum breaking load [N].
    :ivar wll: working load limit [N].
    """

    mbl: float
    wll: float

    @classmethod
    def of(cls, material) -> 'Rating':
        """Return the rating of a material's properties (model/materials.py)."""
        return cls(material.mbl, material.working_load_limit)

    def utilisation(self, tension: float) -> float:
        """Return tension / MBL (0 for a line without a finite MBL)."""
        return tension / self.mbl if math.isfinite(self.mbl) and self.mbl > 0.0 else 0.0

    def band(self, tension: float, parted: bool = False) -> str:
        """Return the band of a tension [N]: OK, ABOVE_WLL, NEAR_BREAK or PARTED."""
        if parted:
            return PARTED
        if tension >= NEAR_BREAK_FRACTION * self.mbl:
            return NEAR_BREAK
        if tension >= self.wll:
            return ABOVE_WLL
        return OK


def ratings(setup: ArrangementParams, materials: Any = None) -> List[Rating]:
    """
    Return each line's MBL and WLL, from its material at its diameter.

    :param materials: the material presets (default: config/materials.yaml).
    """
    library = materials or load_materials()
    return [Rating.of(library.properties(line.params.material, line.params.diameter))
            for line in setup.lines]
