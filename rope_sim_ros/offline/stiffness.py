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
``rope_sim stiffness``: the 6x6 stiffness of an arrangement's lines and fenders.

At the ship's start pose (ship.start_position, ship.start_yaw), about the ship's origin in
frame_id axes, rows and columns x, y, z, roll, pitch, yaw (N/m, N/rad, N m/m, N m/rad):
mooring/statics.py's ship_stiffness. A few lines say what it is; the matrix is the last six
lines, six numbers each, for a ship simulator (or a script) to read.
"""

from typing import Any, List

import numpy as np

from ..model.statics.ship import StaticsError
from ..mooring.statics import ship_statics
from ..params.arrangement import ArrangementParams
from ..params.table import ParameterError

AXES = ('x', 'y', 'z', 'roll', 'pitch', 'yaw')


def stiffness_report(setup: ArrangementParams, materials: Any = None,
                     hydrostatics: bool = False) -> List[str]:
    """
    Return the lines rope_sim stiffness prints: what the matrix is, then its six rows.

    :param hydrostatics: add the heave, roll and pitch restoring of the ship.
    :raises ParameterError / MaterialError: the arrangement cannot be built (a pretension
        no length gives, ...) or a line has no catenary at the start pose.
    """
    try:
        statics = ship_statics(setup, materials)
        loads = statics.loads(hydrostatics=False, external=False)
        matrix = statics.stiffness(hydrostatics=hydrostatics)
    except StaticsError as e:
        raise ParameterError(str(e)) from None
    ship = setup.ship
    x, y, z = ship.start_position
    what = 'lines, fenders and hydrostatics' if hydrostatics else 'lines and fenders'
    frame = setup.shared.frame_id
    report = [f'stiffness of the {what} about the ship origin at its start pose '
              f'({x:g}, {y:g}, {z:g}) m, yaw {ship.start_yaw:g} rad, in {frame} axes',
              f'rows and columns {", ".join(AXES)} [N/m, N/rad, N m/m, N m/rad]']
    tensions = ', '.join(f'{line.name or "the line"} {t / 1e3:.1f} kN'
                         for line, t in zip(statics.lines, loads.fairlead_tensions))
    report.append(f'fairlead tensions: {tensions}')
    compressed = [f'{fender.name} {r / 1e3:.1f} kN' for fender, r in
                  zip(setup.fenders, loads.fender_reactions) if r > 0.0]
    if setup.fenders:
        report.append('fenders compressed: ' + (', '.join(compressed) or 'none'))
    if not np.all(np.isfinite(matrix)):
        raise ParameterError('the stiffness is not finite at the start pose: a line or a '
                             'fender meets the hull where it has no slope')
    report += [' '.join(f'{value + 0.0: .9e}' for value in row) for row in matrix]  # no -0
    return report
