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
What a mooring says of itself: its state at an output, what an advance did, what goes out.

Records built by keyword, the one form every part of the mooring and its users read: a
MooringOutput (every line and the ship at one instant), a MooringAdvance (what steps did),
a Published output (stamped, with its levers and the wrench on the ship) and the Driver's
Report of one call.
"""

from dataclasses import dataclass, field
import math
from typing import Dict, List, Optional, Tuple

import numpy as np

from .line import Parting
from ..model.frames import cross_rows, rotation_matrix


@dataclass(frozen=True)
class ShipState:
    """
    A free ship's motion at one instant (its body origin's).

    :ivar position: the body origin [m]; orientation: unit quaternion (x, y, z, w).
    :ivar velocity: the body origin's velocity [m/s]; omega: angular velocity [rad/s]; both
        in frame_id axes.
    """

    position: np.ndarray
    orientation: np.ndarray
    velocity: np.ndarray
    omega: np.ndarray


@dataclass(frozen=True)
class MooringOutput:
    """
    What every line looks like at one instant.

    :ivar t: state time [s].
    :ivar positions: each line's particles (N_k + 1, 3) [m], bollard first.
    :ivar fairlead_forces: force of each line on its fairlead (L, 3) [N].
    :ivar bollard_forces: force of each line on its bollard (L, 3) [N] (on its payload,
        for a payload line).
    :ivar max_strains: each line's largest structural strain (L,).
    :ivar payload_positions: a payload line's payload (3,) [m], else None, per line.
    :ivar parted: whether each line has parted (L,).
    :ivar fairlead_peaks: each line's largest fairlead tension since the previous output
        (L,) [N]: every step's, this output's included.
    :ivar fairlead_tensions: |fairlead force| of each line (L,) [N]; bollard_tensions too.
    :ivar bollard_peaks: each line's largest bollard (or payload) tension likewise (L,) [N].
    :ivar line_lengths: each line's unstretched length now (L,) [m] (its winch changes it).
    :ivar winch_speeds: the speed each line's winch paid out at in the last step (L,) [m/s].
    :ivar finite: every number of the output is finite (their sum is: an overflow is not).
    :ivar ship: the ship's motion (a driven ship's as its newest pose puts it, at rest).
    :ivar fender_compressions: each fender's compression [m] (F,) (<= 0: not touched).
    :ivar fender_forces: each fender's force on the ship (F, 3) [N], frame_id axes, at
        fender_points (F, 3) [m] (the contact points; the fender's centre when untouched).
    :ivar ship_loads: the wind's, the current's and a passing ship's load on the ship, rows
        in that order, each F_x, F_y [N], M_z [N m] in its body axes about its origin (a
        driven ship's at its pose, taken at rest: applied to a free ship only).
    :ivar wave_elevation: the waves' elevation at the ship's origin [m] (0: no waves).
    :ivar wave_loads: the waves' loads on the ship, rows first order and slow drift, each
        force [N] and moment [N m] in its body axes about its origin (zeros: no waves).
    :ivar states: each line's state: 'fast', 'free' or 'stowed' (mooring/handling.py); a
        stowed line's particles are all at its fairlead, its forces zero.
    """

    t: float
    positions: Tuple[np.ndarray, ...]
    fairlead_forces: np.ndarray
    bollard_forces: np.ndarray
    max_strains: np.ndarray
    payload_positions: Tuple[Optional[np.ndarray], ...]
    parted: np.ndarray
    fairlead_peaks: np.ndarray
    fairlead_tensions: np.ndarray
    bollard_tensions: np.ndarray
    bollard_peaks: np.ndarray
    line_lengths: np.ndarray
    winch_speeds: np.ndarray
    finite: bool = True
    ship: Optional[ShipState] = None
    fender_compressions: np.ndarray = field(default_factory=lambda: np.zeros(0))
    fender_forces: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    fender_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    ship_loads: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    wave_elevation: float = 0.0
    wave_loads: np.ndarray = field(default_factory=lambda: np.zeros((2, 6)))
    states: Tuple[str, ...] = ()

    @property
    def peaks(self) -> np.ndarray:
        """Return each line's largest tension at either end since the previous output (L,)."""
        return np.maximum(self.fairlead_peaks, self.bollard_peaks)


@dataclass
class MooringAdvance:
    """
    What one advance_to call did.

    :ivar steps: steps taken (by the group that took the most).
    :ivar lag: how far the state time is behind the requested time [s].
    :ivar restarted: {line index: why} for every line restarted at rest ('non-finite
        state', 'unphysical state', 'back within reach').
    :ivar beyond_reach: {line index: the largest distance between its ends [m]} for every
        line whose fairlead was held at its reach.
    :ivar parted: {line index: its Parting} for every line that parted in these steps.
    :ivar ship_restarted: how a free ship left the bounds of a moored ship (model.body
        out_of_bounds), restarting it at its start pose at rest and every line with it
        ('ship restarted' in restarted); '' if it did not.
    :ivar released: {line index: the bollard tension [N] past its release_load} for every
        line its quick-release hook let go at the end of these steps.
    """

    steps: int
    lag: float
    restarted: Dict[int, str] = field(default_factory=dict)
    beyond_reach: Dict[int, float] = field(default_factory=dict)
    parted: Dict[int, Parting] = field(default_factory=dict)
    ship_restarted: str = ''
    released: Dict[int, float] = field(default_factory=dict)


def mooring_wrench(fairlead_forces: np.ndarray, offsets: np.ndarray,
                   orientation) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return the total force and moment of the lines on the ship, in its body frame.

    F = R^T sum_k F_k and M = sum_k o_k x (R^T F_k): the moment about the ship's origin.

    :param fairlead_forces: force of each line on its fairlead (L, 3) [N], in frame_id.
    :param offsets: each fairlead in the ship's body frame (L, 3) [m].
    :param orientation: the ship's orientation: a unit quaternion (x, y, z, w), or its
        rotation matrix R (3, 3).
    """
    rotation = np.asarray(orientation, dtype=float)
    if rotation.shape != (3, 3):
        rotation = rotation_matrix(rotation)
    body = np.asarray(fairlead_forces, dtype=float).reshape(-1, 3) @ rotation  # R^T F
    moments = cross_rows(np.asarray(offsets, dtype=float).reshape(-1, 3), body)
    return body.sum(axis=0), moments.sum(axis=0)


class Published:
    """
    One output of the mooring; its levers and wrench are worked out when first asked for.

    :ivar stamp_ns: its stamp [ns] (epoch + simulated time).
    :ivar output: the lines' state (output.t is the simulated time [s]).
    :ivar ship_position: the ship pose's origin at the output [m] (see the module docstring).
    :ivar ship_orientation: its unit quaternion (x, y, z, w).
    :ivar bollard_levers: each bollard minus its pose's origin (L, 3) [m] (zeros: a fixed
        bollard).
    :ivar advance: the Mooring advance that reached it; None for a fresh output.
    :ivar bollard_loads: each named bollard's load (status.BollardLoad), in the order of
        the arrangement's bollards: the lines fast on each at this output.
    """

    __slots__ = ('stamp_ns', 'output', 'ship_position', 'ship_orientation', 'bollard_levers',
                 'advance', 'bollard_loads', '_offsets', '_rotation', '_wrench')

    def __init__(self, stamp_ns: int, output: MooringOutput, ship_position: np.ndarray,
                 ship_orientation: np.ndarray, offsets: np.ndarray, bollard_levers: np.ndarray,
                 advance: Optional[MooringAdvance], bollard_loads: tuple = ()):
        """Keep an output and what its levers and wrench are made from."""
        self.stamp_ns = stamp_ns
        self.output = output
        self.ship_position = ship_position
        self.ship_orientation = ship_orientation
        self.bollard_levers = bollard_levers
        self.advance = advance
        self.bollard_loads = bollard_loads
        self._offsets = offsets
        self._rotation = None
        self._wrench = None

    @property
    def rotation(self) -> np.ndarray:
        """Return the ship's orientation as a rotation matrix R (body to frame_id axes)."""
        if self._rotation is None:
            self._rotation = rotation_matrix(self.ship_orientation)
        return self._rotation

    @property
    def fairlead_levers(self) -> np.ndarray:
        """Return each fairlead minus the ship's origin in frame_id axes (L, 3) [m]."""
        return self._offsets @ self.rotation.T

    def _body_wrench(self) -> Tuple[np.ndarray, np.ndarray]:
        if self._wrench is None:
            self._wrench = mooring_wrench(self.output.fairlead_forces, self._offsets,
                                          self.rotation)
        return self._wrench

    @property
    def force(self) -> np.ndarray:
        """Return the total force of the lines on the ship, body frame (3,) [N]."""
        return self._body_wrench()[0]

    @property
    def moment(self) -> np.ndarray:
        """Return their total moment about the ship's origin, body frame (3,) [N m]."""
        return self._body_wrench()[1]

    def world_wrench(self) -> tuple:
        """Return the force and the moment about the ship's origin in frame_id axes."""
        rotation = self.rotation
        force, moment = self._body_wrench()
        return rotation @ force, rotation @ moment


@dataclass(frozen=True)
class ScheduledCommand:
    """
    A line-handling command at a time, as a commands file gives it (offline).

    :ivar t: when [s of simulated time]; line: its line ('' with let_go_all);
        command: one of handling.COMMANDS; bollard: for make_fast, the bollard to make it
        fast to ('': its own).
    """

    t: float
    line: str
    command: str
    bollard: str = ''


@dataclass(frozen=True)
class Handled:
    """
    A scheduled command as it was taken.

    :ivar t: the state time it was taken at [s]; scheduled: the command; text: what was
        done, or why it was refused; refused: whether it was.
    :ivar bollard: the bollard the line was given before the command (scheduled.bollard;
        '' if none was named or the line could not take it), whether the command was then
        refused or not.
    """

    t: float
    scheduled: ScheduledCommand
    text: str
    refused: bool
    bollard: str = ''


@dataclass
class Report:
    """
    What one call that moves the ropes on did.

    :ivar outputs: the outputs reached, in order.
    :ivar skipped: how far [s] the ropes skipped ahead (0: no skip).
    :ivar skip_to: the simulated time they skipped to.
    :ivar clock_back: how far [s] the clock was behind the ropes (0: it was not; else the
        mooring was cleared and waits for the next ship pose).
    :ivar faults: simulated times of states not output because a number was not finite
        (the ropes were restarted at rest).
    :ivar handled: the scheduled commands taken (offline), in order.
    """

    outputs: List[Published] = field(default_factory=list)
    skipped: float = 0.0
    skip_to: float = math.nan
    clock_back: float = 0.0
    faults: List[float] = field(default_factory=list)
    handled: List[Handled] = field(default_factory=list)
