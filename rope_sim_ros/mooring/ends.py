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
Where a mooring's line ends are: the fairleads on the ship, the bollards, their trajectories.

The ship pose drives every fairlead: fairlead k is the pose ⊕ its fairlead_offset (body
frame). Every fairlead's samples are kept in one trajectory, sampled for a whole group in
one call; a line whose fairlead jumped past its teleport_distance restarts at rest at the
new place and follows its own samples from there (its trajectory holds only those), until a
jump of the whole ship starts everything over. A free ship carries its fairleads (the Ship
says where). Bollards stand at bollard_position or follow their own samples (ship-to-ship
mooring); a line with a free end (a payload's, a line let go) has a free point there, which
follows no track.

Two rules of every step live here:

- a fairlead is held at its line's reach while its ends are farther apart than the line can
  stretch (L (1 + strain limit)): hold_beyond_reach;
- an end found off its trajectory (late samples moved the trajectory under the rope, or the
  state time was moved) is brought back onto it over END_BLEND_TIME (an EndBlend), never by
  a jump.
"""

import math
from typing import List, Optional, Sequence

import numpy as np

from .line import MooringLine
from .ship import Ship
from .trajectory import EndBlend, EndTrajectory
from ..model.frames import distances_beyond, unit_pose_points
from ..stepping.rules import drive_lines, end_distances

# An end found further than END_TOLERANCE [m] off its trajectory (late samples changed the
# trajectory under the rope) is brought back onto it over END_BLEND_TIME [s] (an EndBlend).
END_TOLERANCE = 1e-6
END_BLEND_TIME = 1.0  # see trajectory.py for what it costs
# A state time past the settled part of an end's track (what a new sample cannot change) by
# no more than this [s] is on it: step times and sample stamps differ by rounding alone, and
# counting that as a moved track sent a fifth to half of a steady stream's outputs through
# the end check (a drive of the line, 25 us) to find the ends where they were.
SETTLED_TOLERANCE = 1e-9


class Ends:
    """
    Every line's two ends and their samples (see the module docstring).

    :ivar held: whether each line's fairlead was held at its reach (L,).
    :ivar last_jumps: how far each line's newest end sample jumped [m] (L,).
    :ivar version: counts the changes of how the ends are driven (plans and arrays follow).
    """

    def __init__(self, lines: List[MooringLine], ship: Ship, history: float, method: str):
        """
        Keep the ends of these lines (the Mooring's list: a line replaced there is seen here).

        :param history: seconds of samples each end keeps behind the newest.
        :param method: the trajectories' interpolation (end_interpolation).
        """
        self.lines = lines
        self.ship = ship
        self._history = history
        self._method = method
        count = len(lines)
        self._fairleads = self._trajectory(count)  # every fairlead, in one trajectory
        self._own_fairlead: List[Optional[EndTrajectory]] = [None] * count
        self._bollards: List[Optional[EndTrajectory]] = [None] * count
        self._blends: List[List[Optional[EndBlend]]] = [[None, None] for _ in range(count)]
        # an end may be off its trajectory, or is being blended back onto it
        self._off_track = np.zeros(count, dtype=bool)
        self.held = np.zeros(count, dtype=bool)
        self.last_jumps = np.zeros(count)
        self.version = 0
        self._last_fairleads: Optional[np.ndarray] = None  # every fairlead's newest point
        self._arrays: tuple = (None,)

    def _trajectory(self, width: Optional[int] = None) -> EndTrajectory:
        return EndTrajectory(keep=self._history, method=self._method, width=width)

    def changed(self) -> None:
        """Note a change of how an end is driven: a parameter, a length, a new track."""
        self.version += 1

    def _line_arrays(self) -> tuple:
        """Return every line's fairlead_offset (L, 3) [m] and teleport_distance (L,) [m]."""
        if self._arrays[0] != self.version:  # (parameters changed)
            self._arrays = (self.version, np.array([line.params.fairlead_offset
                                                    for line in self.lines], dtype=float),
                            np.array([line.params.teleport_distance for line in self.lines]))
        return self._arrays[1:]

    @property
    def offsets(self) -> np.ndarray:
        """Return every fairlead in the ship's body frame (L, 3) [m]."""
        return self._line_arrays()[0]

    def from_gravity(self, k: int) -> np.ndarray:
        """Return line k's fairlead from the ship's centre of gravity, body axes [m]."""
        return np.asarray(self.offsets[k]) - self.ship.center_of_gravity

    # -- samples --------------------------------------------------------------------------

    def push_ship(self, t: float, position, orientation, time: float) -> List[int]:
        """
        Take a ship pose at t: every fairlead gets its sample, pose ⊕ fairlead_offset.

        A sample farther than a line's teleport_distance from its fairlead's newest one is
        a jump no rope can follow: those lines' tracks start over at it (the Mooring
        restarts them), a jump of every line starts every track over. last_jumps says how
        far each jumped.

        :param time: the state time (NaN before the lines start).
        :returns: the lines that jumped.
        :raises PoseError: non-finite pose or zero quaternion (nothing changed).
        :raises TrajectoryError: not after the newest ship pose, or the ship is free (nothing
            changed).
        """
        self.ship.check_pose(t)
        q, points = unit_pose_points(position, orientation, self.offsets)
        self.ship.take_pose(t, position, q)
        shared = self._fairleads
        started = not math.isnan(time)
        settled = shared.settled_until if started else math.inf
        before = self._last_fairleads
        shared.push(t, points)
        owns = [k for k, own in enumerate(self._own_fairlead) if own is not None]
        if owns:  # a line that teleported: its own samples (its last point is theirs)
            before = before.copy()
            for k in owns:
                own = self._own_fairlead[k]
                before[k] = own.last_position
                self._off_track[k] |= started and _past(time, own.settled_until)
                own.push(t, points[k])
        if before is None:
            self.last_jumps[:] = 0.0
            farther = 0
        else:
            farther = distances_beyond(points, before, self._line_arrays()[1], self.last_jumps)
        self._last_fairleads = points
        if started and _past(time, settled):  # the samples may have moved the shared track
            shared_lines = np.ones(len(self.lines), dtype=bool)
            shared_lines[owns] = False
            self._off_track |= shared_lines
        jumped = np.flatnonzero(self.last_jumps > self._line_arrays()[1]).tolist() \
            if started and farther else []
        if jumped:
            self.version += 1
        if jumped and len(jumped) == len(self.lines):  # the whole ship: start over
            shared.clear()
            shared.push(t, points)
            self._own_fairlead = [None] * len(self.lines)
        else:
            for k in jumped:
                own = self._own_fairlead[k] = self._trajectory()
                own.push(t, points[k])
        return jumped

    def push_bollard(self, k: int, t: float, point, time: float) -> bool:
        """
        Take a bollard sample of line k; return whether it jumped past teleport_distance.

        Before the first sample the bollard is at bollard_position: a first sample farther
        than teleport_distance from there is a jump too. A line whose bollard end is free (a
        payload, a line let go): its samples are kept but move nothing, and jump nothing. A
        jump starts the bollard's track over at it (the Mooring restarts the line).

        :param time: the state time (NaN before the lines start).
        :raises TrajectoryError: non-finite, or not after that bollard's newest sample.
        """
        line = self.lines[k]
        track = self._bollards[k]
        if track is None or not len(track):  # from now on it moves: its own samples drive it
            track = track or self._trajectory()
            self.version += 1
        last = track.last_position if len(track) else line.params.bollard_position
        settled = track.settled_until
        track.push(t, point)
        self._bollards[k] = track
        started = not math.isnan(time)
        self._off_track[k] |= started and _past(time, settled)
        self.last_jumps[k] = math.dist(point, last)
        if line.free_end or not (started and self.last_jumps[k] > line.params.teleport_distance):
            return False
        track.clear()
        track.push(t, point)
        self.version += 1
        return True

    def has_bollard_samples(self, k: int) -> bool:
        """Tell whether line k's bollard has samples of its own (it moves)."""
        return self._bollards[k] is not None and len(self._bollards[k]) > 0

    def skipped(self, members: Sequence[int]) -> None:
        """Note that the state time of these lines moved without them: check their ends."""
        self._off_track[list(members)] = True

    # -- where they are -------------------------------------------------------------------

    def fixed_bollard(self, k: int) -> Optional[Sequence[float]]:
        """Return where line k's bollard stands while it has no samples and the line is on it."""
        line = self.lines[k]
        if line.free_end or self.has_bollard_samples(k):
            return None
        return line.params.bollard_position

    def bollard(self, k: int, t: float) -> np.ndarray:
        """Return where line k's bollard is at t [m], whether the line is on it or not."""
        if self.has_bollard_samples(k):
            return self._bollards[k].sample(np.array([t]))[0][0]
        return np.array(self.lines[k].params.bollard_position, dtype=float)

    def free_ends(self, k: int, times: np.ndarray) -> tuple:
        """
        Return line k's ends where their samples put them at `times`: (n, 2, 3) twice.

        The bollard is at bollard_position before its first sample; with a free end (a
        payload, a line let go) the bollard's columns repeat the fairlead (a free end follows
        no track); a free ship's fairlead is where the ship carries it now.
        """
        times = np.atleast_1d(np.asarray(times, dtype=float))
        ends = np.empty((len(times), 2, 3))
        velocities = np.zeros((len(times), 2, 3))
        own = self._own_fairlead[k]
        if self.ship.free:
            ends[:, 1], velocities[:, 1] = self.ship.carried(self.from_gravity(k))
        elif own is not None:
            ends[:, 1], velocities[:, 1] = own.sample(times)
        else:
            shared_x, shared_v = self._fairleads.sample(times)
            ends[:, 1], velocities[:, 1] = shared_x[:, k], shared_v[:, k]
        fixed = self.fixed_bollard(k)
        if self.lines[k].free_end:
            ends[:, 0], velocities[:, 0] = ends[:, 1], velocities[:, 1]
        elif fixed is None:
            ends[:, 0], velocities[:, 0] = self._bollards[k].sample(times)
        else:
            ends[:, 0] = fixed
        return ends, velocities

    def drive(self, k: int, times: np.ndarray) -> tuple:
        """
        Return what drives line k's ends at `times`.

        :returns: ends, velocities (n, 2, 3), bollard first, the fairlead held within reach;
            and the end distances [m] before holding, (n,) (zeros with a free end or on a
            free ship: nothing to hold, a ship is not held).
        """
        ends, velocities = self.free_ends(k, times)
        if self.lines[k].free_end or self.ship.free:
            return ends, velocities, np.zeros(len(ends))
        distances = end_distances(ends)
        hold_beyond_reach(ends, velocities, distances, self.lines[k].reach)
        return ends, velocities, distances

    def drive_group(self, group, times: np.ndarray) -> tuple:
        """
        Return a group's driven points, its lines' end distances, and whether one is too far.

        The points at `times` (n, Q, 3) twice, the distances (n, L), and whether a line's ends
        are farther apart than its reach at one of them.

        drive() of each line. The lines whose bollards stand still and whose fairleads
        follow the shared trajectory get the same numbers from one sampling of every
        fairlead (drive_lines).
        """
        n, count = len(times), len(group.members)
        drive_x = np.empty((n, 2 * count, 3))
        drive_v = np.empty((n, 2 * count, 3))
        distances = np.empty((n, count))
        reach = group.rules.reach
        shared, bollards, others = self._plan(group)
        far = False
        for j in others:
            ends, velocities, distances[:, j] = self.drive(group.members[j], times)
            drive_x[:, 2 * j:2 * j + 2] = ends
            drive_v[:, 2 * j:2 * j + 2] = velocities
            far |= bool(distances[:, j].max() > reach[j])
        if len(shared):
            beyond = np.empty(len(shared), dtype=bool)
            if drive_lines(drive_x, drive_v, distances, *self._fairleads.sample(times), shared,
                           bollards, reach, beyond):
                far = True
                for j, _ in shared[beyond]:
                    hold_beyond_reach(drive_x[:, 2 * j:2 * j + 2],
                                      drive_v[:, 2 * j:2 * j + 2], distances[:, j], reach[j])
        return drive_x, drive_v, distances, far

    def _plan(self, group) -> tuple:
        """
        Return how a group's ends are driven: together (drive_lines) or line by line (drive).

        (j, k) (S, 2) and bollards (S, 3) of the lines driven together, the indices j of the
        others. Kept until an end changes how it is driven (version).
        """
        if group.plan[0] != self.version:
            shared, bollards, others = [], [], []
            for j, k in enumerate(group.members):
                fixed = self.fixed_bollard(k)
                if fixed is not None and self._own_fairlead[k] is None and not self.ship.free:
                    shared.append((j, k))
                    bollards.append(fixed)
                else:
                    others.append(j)
            plan = (np.array(shared, dtype=np.int64).reshape(-1, 2),
                    np.array(bollards, dtype=float).reshape(-1, 3), others)
            group.plan = (self.version, plan)
        return group.plan[1]

    def blend(self, group, times: np.ndarray, drive_x: np.ndarray,
              drive_v: np.ndarray) -> None:
        """
        Bring every end of a group that is off its trajectory back onto it (in place).

        Only a live node meets this: a pose stream that fell silent held the end, and its
        late samples then moved the trajectory under the rope. The offline runner's ends are
        always on their trajectories: its numbers never change here.
        """
        if not self._off_track.any() or not self._off_track[group.index].any():
            return  # the common case, and the offline runner's only one
        for j, k in enumerate(group.members):
            if not self._off_track[k]:
                continue
            blends = self._blends[k]
            ends, velocities = drive_x[:, 2 * j:2 * j + 2], drive_v[:, 2 * j:2 * j + 2]
            here, here_velocities = self.drive(k, [group.time])[:2]
            rope = group.system.lines[j]
            for e, particle in ((0, 0), (1, -1)):
                if e == 0 and self.lines[k].free_end:  # a free end follows no track
                    continue
                offset = rope.x[particle] - here[0, e]
                blend = blends[e]
                if np.abs(offset).max() <= END_TOLERANCE:
                    blends[e] = None
                    continue
                if blend is None or np.abs(blend.at([group.time])[0][0] - offset).max() > \
                        END_TOLERANCE:
                    # a new departure from the trajectory: fade it out from the rope's motion
                    rate = rope.v[particle] - here_velocities[0, e]
                    blend = blends[e] = EndBlend(group.time, END_BLEND_TIME, offset, rate)
                offsets, rates = blend.at(times)
                ends[:, e] += offsets
                velocities[:, e] += rates
            # looked at again next time while a blend is under way
            self._off_track[k] = blends[0] is not None or blends[1] is not None


def _past(time: float, settled: float) -> bool:
    """Tell whether the state time is past a track's settled part (SETTLED_TOLERANCE)."""
    return time > settled + SETTLED_TOLERANCE


def hold_beyond_reach(ends: np.ndarray, velocities: np.ndarray, distance: np.ndarray,
                      reach: float) -> None:
    """
    Hold a fairlead beyond the line's reach at the reach (in place).

    No rope state joins ends farther apart than L (1 + max_strain): the strain limit cannot
    be met, every spring stays past it, and the tension grows with the distance (a fairlead
    three lengths away published 95 MN, one at x = 1e9 m 3.7e15 N). Held on the line from the
    bollard, the rope becomes a straight line at its limit, pulling along that line with
    EA max_strain. The held end keeps the sideways part of the relative velocity, scaled to
    the reach: it is the velocity of the held point. The Mooring restarts the rope at rest
    once the ends are back within reach.

    :param ends, velocities: a line's ends over some steps (n, 2, 3), bollard first.
    :param distance: the distance between the ends at each step [m] (n,).
    """
    if distance.max() > reach:
        beyond = distance > reach
        chord = ends[:, 1] - ends[:, 0]
        scale = reach / distance[beyond]
        u = chord[beyond] / distance[beyond, None]
        relative = velocities[beyond, 1] - velocities[beyond, 0]
        sideways = relative - np.einsum('ij,ij->i', relative, u)[:, None] * u
        ends[beyond, 1] = ends[beyond, 0] + reach * u
        velocities[beyond, 1] = velocities[beyond, 0] + scale[:, None] * sideways
