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
A mooring's state at an output: every line's particles, end forces and peaks, and the ship.

One MooringOutput from every group's System: its lines' loads and tensions taken once (the
peaks since the previous output cleared), their lengths, partings and states, and the
ship's state, fenders and loads (the waves' too), read from its one body whatever its
mode. A stowed line, in no group, is all at its fairlead and pulls nothing. Whether every
number is finite is worked out from one sum of them: an overflow anywhere makes it so.
"""

import math
from typing import List, Optional

import numpy as np

from .records import MooringOutput
from ..model.layout import WINCH_SPEED


def mooring_output(mooring) -> MooringOutput:
    """Return the Mooring's state now (its peaks are cleared: they count from here)."""
    count = len(mooring.lines)
    groups = mooring.groups
    single = len(groups) == 1 and len(groups[0].members) == count
    positions: List[Optional[np.ndarray]] = [None] * count
    payloads: List[Optional[np.ndarray]] = [None] * count
    if not single:  # (a stowed line's stay zero)
        forces, strains = np.zeros((count, 2, 3)), np.zeros(count)
        tensions, peaks = np.zeros((count, 2)), np.zeros((count, 2))
        winch_speeds = np.zeros(count)
    total = 0.0
    for group in groups:
        system = group.system
        members = group.members
        group_forces, group_strains = system.loads()
        x = system.x.copy()  # one copy; each line's particles are a view of it
        group_tensions, group_peaks, group_total = system.take_tensions(group_forces, x)
        total += group_total
        if single:
            forces, strains, tensions, peaks = (group_forces, group_strains, group_tensions,
                                                group_peaks)
            winch_speeds = system.line_real[:, WINCH_SPEED].copy()
        else:
            forces[members], strains[members] = group_forces, group_strains
            tensions[members], peaks[members] = group_tensions, group_peaks
            winch_speeds[members] = system.line_real[:, WINCH_SPEED]
        starts = group.starts
        for j, k in enumerate(members):
            positions[k] = x[starts[j]:starts[j + 1]]
            if mooring.lines[k].payload:
                payloads[k] = system.point_x[system.lines[j].ends[0]].copy()
                total += float(payloads[k].sum())
    for k, line in enumerate(mooring.lines):
        if not line.stepped:  # aboard, coiled at its fairlead
            fairlead = mooring.free_ends(k, [mooring.time])[0][0, 1]
            positions[k] = np.repeat(fairlead[None], line.params.segments + 1, axis=0)
    parted = np.array([line.parting is not None for line in mooring.lines])
    lengths = np.array([line.length for line in mooring.lines])
    total += float(lengths.sum())
    ship = mooring.ship
    ship.follow(mooring.time)
    state = ship.state()
    compressions, fender_forces, points = ship.fender_states()
    elevation, waves = ship.waves_at(mooring.time, state, mooring.environment)
    return MooringOutput(
        t=mooring.time, positions=tuple(positions), fairlead_forces=forces[:, 1],
        bollard_forces=forces[:, 0], max_strains=strains, payload_positions=tuple(payloads),
        parted=parted, fairlead_peaks=peaks[:, 1], fairlead_tensions=tensions[:, 1],
        bollard_tensions=tensions[:, 0], bollard_peaks=peaks[:, 0], line_lengths=lengths,
        winch_speeds=winch_speeds, finite=math.isfinite(total), ship=state,
        fender_compressions=compressions, fender_forces=fender_forces, fender_points=points,
        ship_loads=ship.loads_at(mooring.time, state, mooring.arrangement,
                                 mooring.environment),
        wave_elevation=elevation, wave_loads=waves,
        states=tuple(line.state for line in mooring.lines))
