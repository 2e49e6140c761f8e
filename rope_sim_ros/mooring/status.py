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

A bollard's load is the sum of the forces of the lines fast on it (bollard_loads), graded
against its safe working load.

No ROS here: the mooring node and the offline plots take the same bands.
"""

from dataclasses import dataclass
import math
from typing import Any, List, Sequence

import numpy as np

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


@dataclass(frozen=True)
class BollardLoad:
    """
    One bollard's load at an output.

    :ivar name: the bollard's name; position: where it stands [m] (frame_id).
    :ivar force: the sum of the forces of the lines fast on it (3,) [N], frame_id axes.
    :ivar lines: the names of those lines.
    :ivar safe_working_load: its safe working load [N] (0: no limit).
    """

    name: str
    position: tuple
    force: np.ndarray
    lines: tuple
    safe_working_load: float

    @property
    def load(self) -> float:
        """Return the magnitude of its load [N]."""
        return float(np.linalg.norm(self.force))

    @property
    def over(self) -> bool:
        """Tell whether its load is past its safe working load (never without one)."""
        return self.safe_working_load > 0.0 and self.load > self.safe_working_load


def bollard_loads(setup: ArrangementParams, states: Sequence[str],
                  bollard_forces: np.ndarray) -> List[BollardLoad]:
    """
    Return each named bollard's load: the sum of the forces of the lines fast on it.

    :param states: each line's state at the output; bollard_forces: each line's force on
        its bollard (L, 3) [N].
    """
    loads = []
    for bollard in setup.bollards:
        on = [k for k, line in enumerate(setup.lines)
              if line.bollard == bollard.name and states[k] == 'fast']
        force = np.asarray(bollard_forces, dtype=float)[on].sum(axis=0) if on else np.zeros(3)
        loads.append(BollardLoad(bollard.name, bollard.position, force,
                                 tuple(setup.lines[k].name for k in on),
                                 bollard.safe_working_load))
    return loads
