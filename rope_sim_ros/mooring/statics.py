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
An arrangement's ship at rest: its stiffness and its equilibrium (model/statics/ship.py).

The lines are the Mooring's: each MooringLine's properties (its parameters resolved with its
material) and a pretensioned line's length chosen at the ship's start pose by the Mooring's
own rule (length_for_tension on the elastic catenary in air), as a run starts them; the
ship and its fenders are mooring/ship.py's. The start pose is ship.start_position and
ship.start_yaw, driven or free: a driven ship's pretensions are then those of a run whose
first ship pose is the start pose.
"""

from typing import Any, Optional, Sequence

import numpy as np

from .mooring import Mooring
from .ship import start_pose
from ..model.statics.ship import Equilibrium, LoadFunction, Pose, ShipStatics, StaticLine
from ..params.arrangement import ArrangementParams
from ..params.table import ParameterError


def mooring_statics(mooring: Mooring, load: Optional[Sequence[float]] = None,
                    load_function: Optional[LoadFunction] = None) -> ShipStatics:
    """
    Return a Mooring's ship, lines and fenders at rest (ShipStatics), its lines as they are.

    Each line at its length now (the winch's), its bollard where it stands (where its
    samples put it at the state time, if it has samples); a line that parted, was let go or
    is stowed holds the ship to nothing and is left out (the statics' lines keep their
    names). The ship is the Mooring's body: a free ship's pose now is the statics' start
    pose (a driven ship's body stands at its last output's pose).

    :param load: external force [N] and moment [N m] about the ship's origin, frame_id axes.
    :param load_function: a load that changes with the pose (model/statics/ship.py's
        LoadFunction), added to it.
    :raises ParameterError: a payload line (it has no bollard to hang from).
    """
    lines = []
    for k, line in enumerate(mooring.lines):
        if line.payload:
            who = f'line {line.name!r}' if line.name else 'the line'
            raise ParameterError(f'{who} has a payload (payload_mass > 0): the statics take '
                                 'lines between a bollard and a fairlead only')
        if line.parting is not None or line.state != 'fast':  # it pulls on no bollard
            continue
        bollard = np.array(line.params.bollard_position, dtype=float)
        if mooring.started and mooring.has_bollard_samples(k):
            bollard = mooring.free_ends(k, [mooring.time])[0][0, 0]
        lines.append(StaticLine(line.line_props, mooring.environment, bollard,
                                np.array(line.params.fairlead_offset, dtype=float), line.name))
    fenders = [fender.row() for fender in mooring.ship.fenders]
    return ShipStatics(lines, mooring.body, fenders, load, load_function)


def stiffness_now(mooring: Mooring, position, orientation) -> np.ndarray:
    """
    Return the 6x6 stiffness of a running Mooring's lines and fenders where the ship is.

    As ship_stiffness, about the ship's origin in frame_id axes, at this pose (position
    [m], unit quaternion x, y, z, w), the lines as they are now (mooring_statics).

    :raises ParameterError: a payload line; StaticsError: a catenary not found there.
    """
    pose = Pose(np.asarray(position, dtype=float), np.asarray(orientation, dtype=float))
    return mooring_statics(mooring).stiffness(pose)


def ship_statics(setup: ArrangementParams, materials: Any = None,
                 load: Optional[Sequence[float]] = None,
                 load_function: Optional[LoadFunction] = None) -> ShipStatics:
    """
    Return the arrangement's ship, lines and fenders at rest at the start pose (ShipStatics).

    The Mooring of the arrangement, its pretensioned lines given their lengths at the start
    pose by the Mooring's own rule (as a run starts them; a driven ship's first pose is
    then the start pose).

    :param materials: material presets (default: config/materials.yaml).
    :param load, load_function: as mooring_statics.
    :raises ParameterError / MaterialError: a line cannot be built, a pretension no length
        gives (named with its line), a payload line.
    """
    mooring = Mooring(setup, materials)
    if not mooring.free:  # a driven ship's lines start at its first pose: the start pose
        mooring.push_ship(0.0, *start_pose(setup))
    mooring.resolve_pretensions(0.0)
    return mooring_statics(mooring, load, load_function)


def ship_stiffness(setup: ArrangementParams, materials: Any = None, pose=None,
                   hydrostatics: bool = False) -> np.ndarray:
    """
    Return the 6x6 stiffness of the lines and fenders about the ship's origin.

    Rows and columns x, y, z, roll, pitch, yaw in frame_id axes (N/m, N/rad, N m/m,
    N m/rad), at the start pose (or `pose`: a Pose, or x, y, z, roll, pitch, yaw); with
    hydrostatics, the heave, roll and pitch restoring too (ShipStatics.stiffness).

    :raises ParameterError / MaterialError: as ship_statics.
    :raises StaticsError: a line's catenary not found at that pose.
    """
    return ship_statics(setup, materials).stiffness(pose, hydrostatics=hydrostatics)


def ship_equilibrium(setup: ArrangementParams, load: Optional[Sequence[float]] = None,
                     materials: Any = None, pose=None,
                     load_function: Optional[LoadFunction] = None) -> Equilibrium:
    """
    Return the ship's equilibrium under a load (ShipStatics.equilibrium).

    :param load: external force [N] and moment [N m] about the ship's origin, frame_id axes
        (none by default).
    :param pose: where to start looking (the start pose by default).
    :raises ParameterError / MaterialError: as ship_statics.
    :raises StaticsError: no equilibrium found (the message says what is left and where).
    """
    return ship_statics(setup, materials, load, load_function).equilibrium(pose)
