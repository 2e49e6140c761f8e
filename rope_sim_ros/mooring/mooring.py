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
A mooring: one to many lines from a ship to their bollards, stepped together.

The one model of the nodes, the offline commands and the tests: a single line is a mooring
of one line. Each line's own numbers and rules are its MooringLine's (line.py); lines with
equal steps (and bending treatment) form a group that shares one physics System (line j of
the group between point 2 j, its bollard, and point 2 j + 1, its fairlead) and is stepped by
one kernel call per output, its lines' rules held as arrays of the group (GroupRules). The
kernels step each line whose ends are fixed or driven on its own, so a line steps exactly as
it would alone; one exception: a step that one line's violent motion divides is divided for
every line of its group.

The ship pose drives every fairlead: fairlead k is the pose ⊕ its fairlead_offset (body
frame). Every fairlead's samples are kept in one trajectory, sampled for a whole group in
one call; a line whose fairlead jumped past its teleport_distance restarts at rest at the
new place and follows its own samples from there (its trajectory holds only those), until
a jump of the whole ship starts everything over. Bollards stand at bollard_position or
follow their own samples (ship-to-ship mooring); a payload line's bollard end is a free
point, a payload hanging from the fairlead.

Each line's rules, for every step (Simulator.advance_to of earlier releases, line by line):

- its fairlead is held at its reach while its ends are farther apart than the line can
  stretch (L (1 + strain limit)), and the line restarts at rest at the first step they are
  back within it (a line held at its strain limit stores 1/2 EA e^2 L, which released whips
  it at c e with MN tensions for tens of seconds: the energy of a line that could not
  reach, not of the motion);
- a step in which a particle would move more than MAX_STEP_MOTION of a segment against the
  bollard is divided until none does (a line let go at its strain limit flings its
  particles at up to c e, 630 m/s on the default line, 3 m in one 5 ms implicit step on a
  0.8 m segment: the implicit step, linearised about a shape it has left far behind, then
  stretched every spring far past the limit each step); improved Euler's steps also until
  none is longer than the line's fine step (its stable step at its length now, no longer
  than the drag takes the particles' speed in);
- a state that turns non-finite, or whose end forces or strains pass the line's load bound
  (rope.tension_bound), restarts the line at rest;
- an end found off its trajectory (late samples moved the trajectory under the rope, or
  the state time was moved) is brought back onto it over END_BLEND_TIME (an EndBlend),
  never by a jump;
- a line parts where a segment passes its break load, and its winch runs, in the steps.

The total load on the ship (mooring_wrench) is the sum of the fairlead forces and of their
moments about the ship's origin: in the ship's body frame, F = R^T sum F_k and
M = sum o_k x (R^T F_k), with o_k the fairlead offsets and R the ship's orientation.

A free ship (ship_mode free) is a rigid body in the lines' System instead of a pose: every
line is in one group, whose System holds the body (mooring/ship.py builds it from the ship.*
parameters) and the fenders, each fairlead a point the body carries; the kernels step them
together. Its pose is then an output (ship_pose), and the loads on it besides its lines and
fenders (an external wrench, a schedule of them) are set per advance: their value at its
start and their rate to its end, about the centre of gravity in world axes.
"""

from collections import deque
from dataclasses import dataclass, field, replace
import math
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .line import MooringLine, Parting
from .ship import (check_external_load, external_load_limits, fenders, reports_ship_loads,
                   ship_body, ship_loads, ship_wind)
from .trajectory import EndBlend, EndTrajectory, TrajectoryError
from ..model.body import out_of_bounds
from ..model.forces.body import place_points
from ..model.forces.fender import fender_force
from ..model.frames import cross_rows, distances_beyond, rotation_matrix, unit_pose_points
from ..model.layout import (BODY_CLOCK, BODY_LOAD, BODY_LOAD_RATE, BODY_OMEGA, BODY_ORIGIN,
                            BODY_POSITION, BODY_QUATERNION, BODY_VELOCITY,
                            FENDER_COLUMNS, WINCH_SPEED)
from ..model.objects import Line, Point, System
from ..model.ship.loads import world_load
from ..model.statics.pretension import length_for_tension, PretensionError
from ..model.superelastic import MAX_ITERATIONS
from ..params.arrangement import ArrangementParams
from ..params.materials import load_materials
from ..params.table import ParameterError
from ..stepping.rules import (drive_lines, end_distances, fine_steps, implicit_bending,
                              lines_motion_spreads, lowest_bound, step_divisions)
from ..stepping.step import step

# An end found further than END_TOLERANCE [m] off its trajectory (late samples changed the
# trajectory under the rope) is brought back onto it over END_BLEND_TIME [s] (an EndBlend).
END_TOLERANCE = 1e-6
END_BLEND_TIME = 1.0  # see trajectory.py for what it costs
# A state time past the settled part of an end's track (what a new sample cannot change) by
# no more than this [s] is on it: step times and sample stamps differ by rounding alone, and
# counting that as a moved track sent a fifth to half of a steady stream's outputs through
# the end check (a drive of the line, 25 us) to find the ends where they were.
SETTLED_TOLERANCE = 1e-9


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


def to_world(orientation: Sequence[float], force: np.ndarray,
             moment: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Return a body-frame force and moment in frame_id axes (moment about the same origin)."""
    rotation = rotation_matrix(orientation)
    return rotation @ np.asarray(force, dtype=float), rotation @ np.asarray(moment, dtype=float)


def divide_run(start: float, times: Sequence[float], parts: int) -> np.ndarray:
    """Return the times of the steps from start to times' last, each of times' cut in parts."""
    count = len(times) * parts
    return start + (times[-1] - start) * np.arange(1, count + 1) / count


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
    :ivar ship: a free ship's motion; None for a driven ship.
    :ivar fender_compressions: each fender's compression [m] (F,) (<= 0: not touched).
    :ivar fender_forces: each fender's force on the ship (F, 3) [N], frame_id axes, at
        fender_points (F, 3) [m] (the contact points; the fender's centre when untouched).
    :ivar ship_loads: the wind's, the current's and a passing ship's load on the ship, rows
        in that order, each F_x, F_y [N], M_z [N m] in its body axes about its origin (a
        driven ship's at its pose, taken at rest: applied to a free ship only).
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
    """

    steps: int
    lag: float
    restarted: Dict[int, str] = field(default_factory=dict)
    beyond_reach: Dict[int, float] = field(default_factory=dict)
    parted: Dict[int, Parting] = field(default_factory=dict)
    ship_restarted: str = ''


class GroupRules:
    """
    The rules of a group's lines as arrays (L,), kept current with the lines.

    :ivar reach: how far each line's ends can be apart [m] (inf once parted).
    :ivar segment_length: each line's segment length now [m] (the step division's scale).
    :ivar stable, rate, current: each line's improved Euler step [s], its drag rate per m/s
        and the current's speed [m/s] (MooringLine.fine_step).
    :ivar bound_at_rest, bound_per_speed: each line's load bound at rest and its growth per
        m/s of its ends [N] (MooringLine.load_bound).
    """

    def __init__(self, lines: Sequence[MooringLine]):
        """Take the lines' rules now."""
        count = len(lines)
        self.reach = np.empty(count)
        self.segment_length = np.empty(count)
        self.stable = np.empty(count)
        self.rate = np.empty(count)
        self.current = np.empty(count)
        self.bound_at_rest = np.empty(count)
        self.bound_per_speed = np.empty(count)
        self._of = [None] * count  # what each row was taken from: (props, length, parted)
        self.refresh(lines)

    def refresh(self, lines: Sequence[MooringLine]) -> None:
        """Take again the rules of the lines whose numbers changed since."""
        for j, line in enumerate(lines):
            key = (line.props, line.length, line.parting, line.time_step)
            if self._of[j] == key:
                continue
            self._of[j] = key
            self.reach[j] = line.reach
            self.segment_length[j] = line.line_props.segment_length
            self.stable[j], self.rate[j], self.current[j] = line.fine_step()
            self.bound_at_rest[j], self.bound_per_speed[j] = line.load_bound()


class _Group:
    """
    Lines that step together: one System, one step, one kernel call per output.

    :ivar members: the lines' indices in the mooring; line members[j] is the System's
        line j, between its points 2 j (bollard) and 2 j + 1 (fairlead).
    :ivar step: their step [s]; bending: whether the implicit step solves the bending
        springs too (stepping/rules.py implicit_bending, the same for every member).
    :ivar system: their System (None before start); time: its state time [s].
    :ivar starts: line j's particles are system rows starts[j] to starts[j + 1].
    """

    def __init__(self, members: List[int], step: float, bending: bool):
        self.members = members
        self.step = step
        self.bending = bending
        self.system: Optional[System] = None
        self.starts = np.zeros(1, dtype=np.int64)
        self.time = math.nan
        self.rules: Optional[GroupRules] = None
        self.fine = np.empty(len(members))  # scratch: each line's fine step
        self.plan = (None, None)  # how its ends are driven (Mooring._drive_plan)
        self.index = np.array(members, dtype=np.int64)  # members, to index arrays with
        self.winches = (None, [])  # (j, k) of its lines with a winch, and of when


class Mooring:
    """
    Every line of an arrangement, stepped together (see the module docstring).

    :ivar lines: one MooringLine per line, in the arrangement's order.
    :ivar time: the state time [s] (NaN before start).
    """

    def __init__(self, arrangement: ArrangementParams, materials: Any = None,
                 output_interval: float = 0.0, history: float = 5.0, compiled: bool = True):
        """
        Build every line; the ropes are placed by start().

        :param arrangement: validated parameters.
        :param materials: material presets (default: config/materials.yaml).
        :param output_interval: if > 0, every step divides it (outputs fall on step times).
        :param history: seconds of samples each end keeps behind the newest (math.inf
            offline, where a whole motion is pushed before the first step).
        :param compiled: step with the numba kernels (False: their Python code, interpreted:
            the reference the tests compare them with).
        :raises ParameterError / MaterialError / ValueError: a line cannot be built; the
            message names it.
        """
        self.arrangement = arrangement
        self._materials = materials or load_materials()
        self._output_interval = output_interval
        self._history = history
        self.compiled = compiled
        self.lines = [self._line(setup.name, setup.params) for setup in arrangement.lines]
        self._payloads = [line.payload for line in self.lines]
        self.time = math.nan
        # ship poses (t, position, unit quaternion): the newest at or before an output
        # gives its orientation (the fairleads' levers and the wrench's rotation)
        self._ship: deque = deque()
        count = len(self.lines)
        # every fairlead in one trajectory; a line that teleported follows its own
        self._fairleads = self._trajectory(count)
        self._own_fairlead: List[Optional[EndTrajectory]] = [None] * count
        self._bollards: List[Optional[EndTrajectory]] = [None] * count
        self._blends: List[List[Optional[EndBlend]]] = [[None, None] for _ in range(count)]
        # an end may be off its trajectory, or is being blended back onto it
        self._off_track = np.zeros(count, dtype=bool)
        self.held = np.zeros(count, dtype=bool)  # the fairlead was held at the reach
        self.last_jumps = np.zeros(count)  # how far each line's newest end sample jumped [m]
        self._ends_version = 0  # counts the changes of how the ends are driven
        self._last_fairleads: Optional[np.ndarray] = None  # every fairlead's newest point
        # a free ship: the body the lines' System steps, its fenders, the loads on it
        self.free = arrangement.ship.free
        # a free ship's body, which the lines' System steps; a driven ship's stands in for it
        # where the fenders meet the hull, placed at each output's ship pose
        self.body = ship_body(arrangement)
        self._start_row = self.body.row()
        self.fenders = fenders(arrangement)
        self.ship_loads = ship_loads(arrangement)  # wind, current, a passing ship
        self._fender_rows = np.array([fender.row() for fender in self.fenders]).reshape(
            len(self.fenders), FENDER_COLUMNS)
        # force, moment about the ship's origin, held until set again: in world axes, and in
        # the ship's body axes (turning with it)
        self.external_load = np.zeros(6)
        self.body_load = np.zeros(6)
        # offline: (times (n,), loads (n, 6)) as external_load, linear between the times
        self.load_schedule: Optional[Tuple[np.ndarray, np.ndarray]] = None
        self._group()

    def _line(self, name: str, params) -> MooringLine:
        try:
            return MooringLine(name, params, self._materials, self._output_interval)
        except ValueError as e:  # ParameterError, MaterialError, an unstable line
            if not name:  # the single line of a line node: its own parameters
                raise
            raise type(e)(f'line {name!r}: {e}') from None

    def _trajectory(self, width: Optional[int] = None) -> EndTrajectory:
        return EndTrajectory(keep=self._history, method=self.arrangement.shared.end_interpolation,
                             width=width)

    # -- lines ----------------------------------------------------------------------------

    @property
    def names(self) -> List[str]:
        """Return the line names, in order."""
        return self.arrangement.names

    @property
    def started(self) -> bool:
        """Tell whether the ropes have been placed (by the first ship pose)."""
        return self.groups[0].system is not None

    @property
    def time_step(self) -> float:
        """Return the smallest of the lines' steps [s]."""
        return min(group.step for group in self.groups)

    @property
    def kernel_calls(self) -> int:
        """Return how many kernel calls step every line once: one per step group."""
        return len(self.groups)

    def _line_arrays(self) -> tuple:
        """Return every line's fairlead_offset (L, 3) [m] and teleport_distance (L,) [m]."""
        if getattr(self, '_arrays', (None,))[0] != self._ends_version:  # (parameters changed)
            self._arrays = (self._ends_version, np.array([line.params.fairlead_offset
                                                          for line in self.lines], dtype=float),
                            np.array([line.params.teleport_distance for line in self.lines]))
        return self._arrays[1:]

    @property
    def offsets(self) -> np.ndarray:
        """Return every fairlead in the ship's body frame (L, 3) [m]."""
        return self._line_arrays()[0]

    def where(self, k: int) -> Tuple[_Group, int]:
        """Return line k's group and its index there."""
        group = self._group_of[k]
        return group, group.members.index(k)

    def rope(self, k: int) -> Line:
        """Return line k's Line in its group's System (its x and v are the state)."""
        group, j = self.where(k)
        return group.system.lines[j]

    def _group(self) -> None:
        """
        Put the lines with equal steps and bending treatment in one group each.

        A free ship's lines are one group (one System holds the body): at the smallest of
        their steps, with the bending springs in the implicit step if any line needs them.
        """
        if self.free:
            dt = min(line.time_step for line in self.lines)
            bending = any(implicit_bending(line.props, dt) for line in self.lines)
            self.groups = [_Group(list(range(len(self.lines))), dt, bending)]
            self._group_of = {k: self.groups[0] for k in range(len(self.lines))}
            return
        keys: Dict[tuple, List[int]] = {}
        for k, line in enumerate(self.lines):
            key = (line.time_step, implicit_bending(line.props, line.time_step))
            keys.setdefault(key, []).append(k)
        self.groups = [_Group(members, dt, bending)
                       for (dt, bending), members in sorted(keys.items())]
        self._group_of = {k: group for group in self.groups for k in group.members}

    def _regroup(self) -> None:
        """Group the lines again after a step changed; rebuild the Systems if started."""
        started = self.started
        systems = {k: self.where(k) for k in range(len(self.lines))} if started else {}
        self._group()
        if started:  # new groups carry on from the state time (a new group has none)
            self._build({k: group.system for k, (group, _) in systems.items()},
                        {k: j for k, (_, j) in systems.items()})
            self._set_time(self.time)

    def _build(self, sources: Dict[int, System], indices: Dict[int, int]) -> None:
        """
        Put each group's lines in one new System, each line as it is in `sources`.

        :param sources: line k's System now (its own at rest, or an old group's).
        :param indices: line k's index in it.
        """
        for group in self.groups:
            members = [(sources[k], indices[k]) for k in group.members]
            system = System(members[0][0].environment)
            if self.free:
                system.add_body(self.body)
                for fender in self.fenders:
                    system.add_fender(fender)
            for j, (source, i) in enumerate(members):
                rope = source.lines[i]
                for e, q in enumerate(rope.ends):
                    point = source.points[q]
                    if e == 1 and self.free:  # the fairlead: on the ship
                        system.add_point(Point('carried', point.position.copy(), body=0,
                                               offset=self._from_gravity(group.members[j])))
                        continue
                    system.add_point(Point(point.kind, point.position.copy(), point.mass,
                                           point.velocity.copy(), point.volume,
                                           point.drag_area, point.added_mass))
                system.add_line(Line(rope.line_type, rope.rest.copy(), rope.x.copy(),
                                     (2 * j, 2 * j + 1)))
            system.pack()
            for j, (source, i) in enumerate(members):
                system.load_line(j, source, i)
            group.system = system
            group.starts = np.array([0] + [len(line.x) for line in system.lines]).cumsum()
            group.rules = GroupRules([self.lines[k] for k in group.members])
            group.fine = np.empty(len(group.members))

    # -- inputs ---------------------------------------------------------------------------

    def _from_gravity(self, k: int) -> np.ndarray:
        """Return line k's fairlead from the free ship's centre of gravity, body axes [m]."""
        return np.asarray(self.offsets[k]) - np.asarray(self.arrangement.ship.center_of_gravity)

    def push_ship(self, t: float, position, orientation) -> List[int]:
        """
        Take a ship pose: every fairlead gets its sample, pose ⊕ fairlead_offset.

        A sample farther than a line's teleport_distance from its fairlead's newest one is
        a jump no rope can follow (its ends would be dragged through the step): that line
        restarts at rest at the new place, at the state time (outputs stay on their grid),
        and follows its own samples from this one on. last_jumps says how far each jumped.

        :returns: the lines a jump restarted.
        :raises PoseError: non-finite pose or zero quaternion (nothing changed).
        :raises TrajectoryError: not after the newest ship pose, or the ship is free (nothing
            changed).
        """
        if self.free:
            raise TrajectoryError('the ship is free (ship_mode free): its pose is an output '
                                  'of the mooring, not an input')
        q, points = unit_pose_points(position, orientation, self.offsets)
        if self._ship and t <= self._ship[-1][0]:
            raise TrajectoryError(f'ship pose at t={t:.6f} s is not after the newest one '
                                  f'({self._ship[-1][0]:.6f} s)')
        shared = self._fairleads
        started = self.started
        settled = shared.settled_until if started else math.inf
        before = self._last_fairleads
        shared.push(t, points)
        self._ship.append((t, np.array(position, dtype=float), q))  # (advance_to forgets)
        owns = [k for k, own in enumerate(self._own_fairlead) if own is not None]
        if owns:  # a line that teleported: its own samples (its last point is theirs)
            before = before.copy()
            for k in owns:
                own = self._own_fairlead[k]
                before[k] = own.last_position
                self._off_track[k] |= started and self._past(own.settled_until)
                own.push(t, points[k])
        if before is None:
            self.last_jumps[:] = 0.0
            farther = 0
        else:
            farther = distances_beyond(points, before, self._line_arrays()[1], self.last_jumps)
        self._last_fairleads = points
        if started and self._past(settled):  # the samples may have moved the shared track
            shared_lines = np.ones(len(self.lines), dtype=bool)
            shared_lines[owns] = False
            self._off_track |= shared_lines
        jumped = np.flatnonzero(self.last_jumps > self._line_arrays()[1]).tolist() \
            if started and farther else []
        if jumped:
            self._ends_version += 1
        if jumped and len(jumped) == len(self.lines):  # the whole ship: start over
            shared.clear()
            shared.push(t, points)
            self._own_fairlead = [None] * len(self.lines)
        else:
            for k in jumped:
                own = self._own_fairlead[k] = self._trajectory()
                own.push(t, points[k])
        for k in jumped:
            self.restart_line(k)  # the end rests at its only sample until then
        return jumped

    def push_bollard(self, k: int, t: float, point) -> str:
        """
        Take a bollard sample of line k; return 'teleport' if it restarted the line.

        Before the first sample the bollard is at bollard_position: a first sample farther
        than teleport_distance from there is a jump too. A payload line's bollard end is
        free: its samples are kept but move nothing, and restart nothing.

        :raises TrajectoryError: non-finite, or not after that bollard's newest sample.
        """
        line = self.lines[k]
        track = self._bollards[k]
        if track is None or not len(track):  # from now on it moves: its own samples drive it
            track = track or self._trajectory()
            self._ends_version += 1
        last = track.last_position if len(track) else line.params.bollard_position
        settled = track.settled_until
        track.push(t, point)
        self._bollards[k] = track
        started = self.started
        self._off_track[k] |= started and self._past(settled)
        self.last_jumps[k] = math.dist(point, last)
        if line.payload:
            return ''
        if started and self.last_jumps[k] > line.params.teleport_distance:
            track.clear()
            track.push(t, point)
            self._ends_version += 1
            self.restart_line(k)
            return 'teleport'
        return ''

    def _past(self, settled: float) -> bool:
        """Tell whether the state time is past a track's settled part (SETTLED_TOLERANCE)."""
        return self.time > settled + SETTLED_TOLERANCE

    def ship_pose(self, t: float) -> Tuple[np.ndarray, np.ndarray]:
        """
        Return (position, unit quaternion) of the newest ship pose at or before t.

        A free ship's: its body origin's pose now (t is the state time at an output).
        """
        if self.free:
            return self.body.origin_pose()
        chosen = self._ship[0]
        for sample in self._ship:
            if sample[0] > t:
                break
            chosen = sample
        return chosen[1], chosen[2]

    def forget_ship(self) -> None:
        """Drop ship poses no output can use: outputs come at or after the state time."""
        now = self.time if self.started else -math.inf
        while len(self._ship) > 1 and self._ship[1][0] <= now:
            self._ship.popleft()

    def has_bollard_samples(self, k: int) -> bool:
        """Tell whether line k's bollard has samples of its own (it moves)."""
        return self._bollards[k] is not None and len(self._bollards[k]) > 0

    # -- the ends -------------------------------------------------------------------------

    def _fixed_bollard(self, k: int) -> Optional[Sequence[float]]:
        """Return where line k's bollard stands while it has no samples (no payload), or None."""
        line = self.lines[k]
        if line.payload or self.has_bollard_samples(k):
            return None
        return line.params.bollard_position

    def free_ends(self, k: int, times: np.ndarray) -> tuple:
        """
        Return line k's ends where their samples put them at `times`: (n, 2, 3) twice.

        The bollard is at bollard_position before its first sample; with a payload the
        bollard's columns repeat the fairlead (a free end follows no track).
        """
        times = np.atleast_1d(np.asarray(times, dtype=float))
        ends = np.empty((len(times), 2, 3))
        velocities = np.zeros((len(times), 2, 3))
        own = self._own_fairlead[k]
        if self.free:  # where the ship carries it now
            ends[:, 1], velocities[:, 1] = self._carried_fairlead(k)
        elif own is not None:
            ends[:, 1], velocities[:, 1] = own.sample(times)
        else:
            shared_x, shared_v = self._fairleads.sample(times)
            ends[:, 1], velocities[:, 1] = shared_x[:, k], shared_v[:, k]
        fixed = self._fixed_bollard(k)
        if self.lines[k].payload:
            ends[:, 0], velocities[:, 0] = ends[:, 1], velocities[:, 1]
        elif fixed is None:
            ends[:, 0], velocities[:, 0] = self._bollards[k].sample(times)
        else:
            ends[:, 0] = fixed
        return ends, velocities

    def _carried_fairlead(self, k: int) -> Tuple[np.ndarray, np.ndarray]:
        """Return line k's fairlead on the free ship now: position [m], velocity [m/s]."""
        body = self.body
        lever = rotation_matrix(body.quaternion) @ self._from_gravity(k)
        return body.position + lever, body.velocity + np.cross(body.omega, lever)

    def drive(self, k: int, times: np.ndarray) -> tuple:
        """
        Return what drives line k's ends at `times`.

        :returns: ends, velocities (n, 2, 3), bollard first, the fairlead held within reach;
            and the end distances [m] before holding, (n,) (zeros with a payload: nothing
            to hold).
        """
        ends, velocities = self.free_ends(k, times)
        if self.lines[k].payload or self.free:  # nothing to hold (a ship is not held)
            return ends, velocities, np.zeros(len(ends))
        distances = end_distances(ends)
        hold_beyond_reach(ends, velocities, distances, self.lines[k].reach)
        return ends, velocities, distances

    def _drive_group(self, group: _Group, times: np.ndarray) -> tuple:
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
        shared, bollards, others = self._drive_plan(group)
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

    def _drive_plan(self, group: _Group) -> tuple:
        """
        Return how a group's ends are driven: together (drive_lines) or line by line (drive).

        (j, k) (S, 2) and bollards (S, 3) of the lines driven together, the indices j of the
        others.

        Kept until an end changes how it is driven (_ends_changed: its own samples begin).
        """
        if group.plan[0] != self._ends_version:
            shared, bollards, others = [], [], []
            for j, k in enumerate(group.members):
                fixed = self._fixed_bollard(k)
                if fixed is not None and self._own_fairlead[k] is None and not self.free:
                    shared.append((j, k))
                    bollards.append(fixed)
                else:
                    others.append(j)
            plan = (np.array(shared, dtype=np.int64).reshape(-1, 2),
                    np.array(bollards, dtype=float).reshape(-1, 3), others)
            group.plan = (self._ends_version, plan)
        return group.plan[1]

    def _blend_ends(self, group: _Group, times: np.ndarray, drive_x: np.ndarray,
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
                if e == 0 and self.lines[k].payload:  # a free end follows no track
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

    # -- start and restarts ---------------------------------------------------------------

    def start(self, t: float) -> Dict[int, float]:
        """
        Place every rope at rest at time t (a ship pose must have come).

        A line given a pretension gets its length first, from where its ends are now.

        :returns: {line index: the length chosen [m]} of the pretensioned lines.
        :raises ParameterError: a pretension no length gives (named with its line).
        """
        if not self._ship and not self.free:
            raise TrajectoryError('cannot start the lines before the first ship pose')
        lengths = self.resolve_pretensions(t)
        alone = {}
        for k in range(len(self.lines)):
            alone[k] = self._parted_if_overloaded(k, t, self._at_rest(k, t))
        self._build(alone, {k: 0 for k in alone})
        for group in self.groups:  # what bringing them to rest pulled is no load of theirs
            group.system.take_peaks()
        self._set_time(t)
        for k in range(len(self.lines)):
            self._apply_winch(k)
        return lengths

    def resolve_pretensions(self, t: float) -> Dict[int, float]:
        """
        Give every pretensioned line the length that starts it at its pretension at t.

        start() does it; the statics (statics.py) too, for the same lengths.

        :returns: {line index: the length chosen [m]}.
        :raises ParameterError: a pretension no length gives (named with its line).
        """
        lengths = {}
        for k, setup in enumerate(self.arrangement.lines):
            if setup.pretension <= 0.0:
                continue
            line = self.lines[k]
            try:
                ends = self.free_ends(k, [t])[0][0]
                length = length_for_tension(line.props, ends[0], ends[1], setup.pretension)
                params = setup.params.with_values({'length': length})
            except (ParameterError, PretensionError) as e:
                raise ParameterError(f'line {setup.name!r}: {e}') from None
            self.lines[k] = self._line(setup.name, params)
            self.arrangement = self.arrangement.with_line(setup.name, params)
            lengths[k] = length
            self._ends_version += 1
        if lengths:
            self._group()  # a new length can give a line another step
        return lengths

    def _at_rest(self, k: int, t: float) -> System:
        """Return line k alone at rest between its ends at t (MooringLine.at_rest)."""
        ends, _, distances = self.drive(k, [t])
        self.held[k] = bool(distances[0] > self.lines[k].reach)
        return self.lines[k].at_rest(ends[0], bool(self.held[k]))

    def place_line(self, k: int, shape: np.ndarray) -> None:
        """Put line k at rest at `shape` (N+1, 3) [m], its ends on its points (after start)."""
        group, j = self.where(k)
        group.system.load_line(j, self.lines[k].build(np.asarray(shape, dtype=float)))
        self._apply_winch(k)

    def restart_line(self, k: int, t: Optional[float] = None) -> None:
        """Put line k back at rest between its ends, at its group's state time (or t)."""
        if not self.started:
            return
        group, j = self.where(k)
        t = group.time if t is None else t
        alone = self._parted_if_overloaded(k, t, self._at_rest(k, t))
        group.system.load_line(j, alone)
        self._apply_winch(k)
        group.system.take_peaks(j)  # nor before the restart: the peaks start from its rest
        group.rules.refresh([self.lines[m] for m in group.members])

    def _parted_if_overloaded(self, k: int, t: float, alone: System) -> System:
        """
        Return line k's rest state at a (re)start, parted if that state passes its break load.

        A line (re)started where its ends are too far apart for it to hold its break load
        (a teleport past its reach, a skip or a reset there) has no whole rest state: it
        parts at once, at its most stretched segment, its two pieces laid unstretched along
        the line from their ends. Held whole at its reach it would pull EA x max_strain (up
        to 20 MN on the berth's springs) at the restart and in the step it parted in.
        """
        line = self.lines[k]
        if line.parting is not None or line.payload or not line.params.parting:
            return alone
        finite, largest = alone.largest_load()
        if finite and largest <= line.break_load:
            return alone
        rope = alone.lines[0]
        x = rope.x
        lengths = np.sqrt(((x[1:] - x[:-1]) ** 2).sum(axis=1))
        segment = int(np.argmax(lengths / rope.rest))
        chord = x[-1] - x[0]
        u = chord / max(float(np.linalg.norm(chord)), 1e-12)
        along = np.concatenate([[0.0], np.cumsum(rope.rest)])
        shape = x[0] + along[:, None] * u  # the bollard's piece from the bollard, the
        shape[segment + 1:] = x[-1] - (along[-1] - along[segment + 1:])[:, None] * u  # other
        line.parting = Parting(t, segment, line.break_load)
        self.held[k] = False  # in two pieces: nothing to hold at a reach
        return line.build(shape)

    def _apply_winch(self, k: int) -> None:
        """Give line k the winch and break load its parameters ask for now."""
        line = self.lines[k]
        group, j = self.where(k)
        system = group.system
        p = line.params
        if p.winch_mode == 'constant_tension' and not p.winch_tension and \
                not math.isfinite(line.held_tension):
            line.held_tension = float(np.linalg.norm(system.loads()[0][j, 1]))
        rope = system.lines[j]
        rope.break_load = line.break_load
        rope.winch = line.winch()
        system.refresh()

    def restart(self, t: Optional[float] = None) -> None:
        """Put every rope back at rest between its ends (at the state time, or t)."""
        t = self.time if t is None else t
        self._set_time(t)
        for k in range(len(self.lines)):
            self.restart_line(k, t)

    def restore(self) -> None:
        """
        Give every line back its length and its whole rope, at rest at the state time.

        A free ship goes back to its start pose, at rest, first.
        """
        for line in self.lines:
            line.restore()
        if self.started and self.free:
            self._reset_ship(self.groups[0].system)
        if self.started:
            self.restart()

    def _reset_ship(self, system: System) -> None:
        """Put the free ship back at its start pose, at rest (no acceleration kept)."""
        system.body_table[0, :BODY_CLOCK] = self._start_row[:BODY_CLOCK]
        place_points(system.body_table, system.points_table, system.point_x, system.point_v)

    def command_winch(self, k: int, speed: float) -> None:
        """
        Command line k's winch speed [m/s] (+ pays out) from its next step.

        :raises ParameterError: speed is not a finite number.
        """
        line = self.lines[k]
        line.command_winch(speed)
        if self.started:
            group, j = self.where(k)
            group.system.set_winch(j, command=line.winch().command)

    # -- time -----------------------------------------------------------------------------

    def advance_to(self, t: float) -> MooringAdvance:
        """
        Advance every rope in its own fixed steps up to t (the module docstring's rules).

        Every group ends within a step of t; the state time is the earliest group's.
        """
        done = MooringAdvance(0, 0.0)  # what the groups' steps did, gathered
        for group in self.groups:
            count = int(math.floor((t - group.time) / group.step + 1e-9))
            if count > 0:
                done.steps = max(done.steps, count)
                self._advance_group(group, group.time + group.step * np.arange(1, count + 1),
                                    done)
        groups = self.groups
        self.time = groups[0].time if len(groups) == 1 else min(g.time for g in groups)
        done.lag = t - self.time
        self.forget_ship()  # (else a run fed every pose first searches them all at each output)
        return done

    def _advance_group(self, group: _Group, times: np.ndarray, done: MooringAdvance) -> None:
        """Take the steps of one group to `times`: held at the reach, back within it."""
        if self.free:
            self._check_ship(group, done)
            self._set_body_loads(group.system, group.time, float(times[-1]))
        drive_x, drive_v, distances, far = self._drive_group(group, times)
        if not (far or self.held.any()):  # the common case
            self._step(group, times, drive_x, drive_v, done)
            return
        held = self.held[group.index]
        beyond = distances > group.rules.reach
        back = ~beyond & np.vstack([held, beyond[:-1]])
        for j in np.flatnonzero(beyond.any(axis=0)):
            k = group.members[j]
            done.beyond_reach[k] = max(done.beyond_reach.get(k, 0.0),
                                       float(distances[beyond[:, j], j].max()))
        if back.any():
            # a line back within reach restarts at rest at that step (its state there is the
            # restart's, whatever the step did): step the group to it, then go on
            i = int(np.flatnonzero(back.any(axis=1))[0])
            self._step(group, times[:i + 1], drive_x[:i + 1], drive_v[:i + 1], done)
            for j in np.flatnonzero(back[i]):
                self.restart_line(group.members[j], float(times[i]))
                done.restarted[group.members[j]] = 'back within reach'
            for j in np.flatnonzero(~back[i]):
                self.held[group.members[j]] = bool(beyond[i, j])
            if i + 1 < len(times):
                self._advance_group(group, times[i + 1:], done)
            return
        self.held[group.index] = beyond[-1]
        self._step(group, times, drive_x, drive_v, done)

    def _step(self, group: _Group, times: np.ndarray, drive_x: np.ndarray,
              drive_v: np.ndarray, done: MooringAdvance) -> None:
        """Take a group's steps to `times`, divided as the rules ask, then check its lines."""
        self._blend_ends(group, times, drive_x, drive_v)
        spreads = lines_motion_spreads(group.system.v, group.starts, drive_v)
        parts, violent = self._divisions(group, spreads)
        if parts == 1:
            self._run(group, group.step, drive_x, drive_v, done, spreads[:, 2])
        elif not violent:  # only explicit steps' bounds: divide the whole run alike
            self._run_divided(group, divide_run(group.time, times, parts), done)
        else:
            for t in times:  # a violent stretch somewhere: look again before every step
                parts, _ = self._divisions(
                    group, lines_motion_spreads(group.system.v, group.starts, drive_v))
                self._run_divided(group, divide_run(group.time, [t], parts), done)
                self._set_group_time(group, float(t))
        self._set_group_time(group, float(times[-1]))
        self._check(group, spreads[:, 1], done)  # the ends' speeds

    def _divisions(self, group: _Group, spreads: np.ndarray) -> Tuple[int, bool]:
        """Return the parts every step of a group is divided in, and whether to look again."""
        rules = group.rules
        explicit = self.lines[group.members[0]].params.integrator == 'improved_euler'
        return step_divisions(spreads, group.step, rules.segment_length, explicit,
                              rules.stable, rules.rate, rules.current)

    def _run_divided(self, group: _Group, fine: np.ndarray, done: MooringAdvance) -> None:
        """Take a group's steps to the divided times `fine`, its ends driven there."""
        fine_x, fine_v = self._drive_group(group, fine)[:2]
        self._blend_ends(group, fine, fine_x, fine_v)
        self._run(group, (fine[-1] - group.time) / len(fine), fine_x, fine_v, done)

    def _run(self, group: _Group, dt: float, drive_x: np.ndarray, drive_v: np.ndarray,
             done: MooringAdvance, speeds: Optional[np.ndarray] = None) -> None:
        """
        Take len(drive_x) substeps of dt of a group's lines: one kernel call.

        :param speeds: the lines' speed bounds for these steps (lines_motion_spreads' last
            column), if the caller has them.
        """
        integrator = self.lines[group.members[0]].params.integrator
        fine = 0.0
        if integrator == 'adaptive':  # each line's own improved Euler step
            if speeds is None:
                speeds = lines_motion_spreads(group.system.v, group.starts, drive_v)[:, 2]
            rules = group.rules
            fine_steps(rules.stable, rules.rate, rules.current, speeds, group.fine)
            fine = group.fine
        parted = step(group.system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS,
                      group.bending, self.compiled, fine)
        self._follow_run(group, dt, parted, done)

    def _follow_run(self, group: _Group, dt: float, parted: list,
                    done: MooringAdvance) -> None:
        """Take in what a run of steps of dt from the group's time did: lengths, partings."""
        changed = False
        if group.winches[0] != self._ends_version:  # (parameters changed: a winch mode)
            group.winches = (self._ends_version, [
                (j, k) for j, k in enumerate(group.members)
                if self.lines[k].params.winch_mode != 'none'])
        for j, k in group.winches[1]:
            line = self.lines[k]
            length = group.system.unstretched_length(j)
            changed |= length != line.length
            line.length = length
        for j, at in parted:
            k = group.members[j]
            line = self.lines[k]
            line.parting = Parting(group.time + (at + 1) * dt, group.system.lines[j].parted,
                                   line.break_load)
            self.held[k] = False  # its pieces reach anywhere: no restart 'back within reach'
            done.parted[k] = line.parting
            changed = True
        if changed:
            group.rules.refresh([self.lines[k] for k in group.members])

    def load_at(self, t: float) -> np.ndarray:
        """
        Return the load on the free ship at t besides its lines and fenders (6,).

        The external wrench (external_load, body_load turned with the ship) plus the
        schedule's (load_schedule) at t: force [N] and moment about the ship's origin [N m],
        world axes.
        """
        load = self.external_load.copy()
        if self.body_load.any():
            rotation = rotation_matrix(self.body.quaternion)
            load[:3] += rotation @ self.body_load[:3]
            load[3:] += rotation @ self.body_load[3:]
        if self.load_schedule is not None:
            times, loads = self.load_schedule
            load += [np.interp(t, times, loads[:, c]) for c in range(6)]
        return load

    def set_external_load(self, force, moment, body_axes: bool) -> None:
        """
        Hold an external load on the free ship from now on (it replaces the one before).

        :param force, moment: [N], [N m] about the ship's origin; in its body axes (they
            turn with it) or in frame_id axes.
        :raises ValueError: a number that is not finite, or a load past what any tug or
            thruster gives (ship.external_load_limits).
        """
        load = np.concatenate([np.asarray(force, dtype=float).reshape(3),
                               np.asarray(moment, dtype=float).reshape(3)])
        check_external_load(load, external_load_limits(self.arrangement))
        self.external_load = np.zeros(6) if body_axes else load
        self.body_load = load if body_axes else np.zeros(6)

    def set_load_schedule(self, times: np.ndarray, loads: np.ndarray) -> None:
        """
        Take a schedule of external loads on the free ship (offline: LOADS.csv).

        :param times: [s] (n,), increasing; loads: force [N] and moment about the ship's
            origin [N m] in world axes at each (n, 6), linear between them.
        :raises ValueError: a load past what any tug or thruster gives, naming its row.
        """
        limits = external_load_limits(self.arrangement)
        for row, load in enumerate(np.asarray(loads, dtype=float).reshape(-1, 6)):
            try:
                check_external_load(load, limits)
            except ValueError as e:
                raise ValueError(f'row {row + 1} (t = {times[row]:g} s): {e}') from None
        self.load_schedule = (np.asarray(times, dtype=float), np.asarray(loads, dtype=float))

    def _set_body_loads(self, system: System, start: float, end: float) -> None:
        """
        Give the body its loads from start to end [s]: their value at start, their rate to end.

        Taken about the centre of gravity where the ship is at start, with its velocity there
        (the wind and current on it): over one output interval it turns and speeds up far
        too little for that to matter.
        """
        origin, orientation = self.body.origin_pose()
        lever = self.body.position - origin  # from the origin to the CG
        rotation = rotation_matrix(orientation)
        velocity = self.body.velocity - np.cross(self.body.omega, lever)
        row = system.body_table[0]
        values = []
        for t in (start, end):
            load = self.load_at(t)
            load += world_load(self.ship_loads.at(t, origin, rotation, velocity), rotation)
            load[3:] -= np.cross(lever, load[:3])  # the moment about the CG
            values.append(load)
        row[BODY_LOAD:BODY_LOAD + 6] = values[0]
        row[BODY_LOAD_RATE:BODY_LOAD_RATE + 6] = (
            (values[1] - values[0]) / (end - start) if end > start else 0.0)
        row[BODY_CLOCK] = 0.0

    def _set_group_time(self, group: _Group, t: float) -> None:
        group.time = t

    def _set_time(self, t: float) -> None:
        self.time = t
        for group in self.groups:
            group.time = t

    def _check(self, group: _Group, end_speeds: np.ndarray, done: MooringAdvance) -> None:
        """
        Restart every line of a group whose state is not finite or past its load bound.

        A free ship out of a moored ship's bounds (sunk, capsized, far off, its numbers not
        finite) restarts at its start pose at rest, and every line with it.

        :param end_speeds: each line's largest end speed over the steps just taken [m/s].
        """
        system = group.system
        restarted = done.restarted
        if self.free:
            self._check_ship(group, done)
        finite, largest = system.largest_load()
        rules = group.rules
        if finite and largest <= lowest_bound(rules.bound_at_rest, rules.bound_per_speed,
                                              end_speeds):
            return  # the common case: no line near its bound
        bounds = rules.bound_at_rest + rules.bound_per_speed * end_speeds
        if not finite:  # which lines? (the kernel stops at the first)
            rows = np.isfinite(system.x).all(axis=1) & np.isfinite(system.v).all(axis=1)
            finite = np.logical_and.reduceat(rows, group.starts[:-1])
            finite &= (np.isfinite(system.point_x).all(axis=1)
                       & np.isfinite(system.point_v).all(axis=1)).reshape(-1, 2).all(axis=1)
            for j in np.flatnonzero(~finite):  # first, so that the others' loads count
                restarted[group.members[j]] = 'non-finite state'
                self.restart_line(group.members[j])
        largest = system.line_loads()  # from the loads largest_load computed, once per state
        for j in np.flatnonzero(~(largest <= bounds)):  # also NaN
            restarted[group.members[j]] = 'unphysical state'
            self.restart_line(group.members[j])

    def _check_ship(self, group: _Group, done: MooringAdvance) -> None:
        """
        Restart a free ship out of a moored ship's bounds at its start pose, at rest.

        Every line restarts with it (done.restarted: 'ship restarted'). Before a group's
        steps too: the loads on the ship are worked out from its state.
        """
        system = group.system
        why = out_of_bounds(system.body_table[0], self._start_row)
        if why:
            self._reset_ship(system)
            done.ship_restarted = why
            for k in group.members:
                done.restarted[k] = 'ship restarted'
                self.restart_line(k)

    def skip_to(self, t: float) -> None:
        """
        Move the state time to t without simulating.

        The particles stay where they are, so after more than rounding the ends are brought
        back onto their tracks over END_BLEND_TIME: follow a long skip with restart().
        """
        for group in self.groups:
            if abs(t - group.time) > 1e-6 * group.step:  # more than pinning an output time
                self._off_track[group.members] = True
        self._set_time(t)

    # -- parameters -----------------------------------------------------------------------

    def check_update(self, k: int, values: dict) -> None:
        """Refuse run-time changes of line k's parameters update() could not apply."""
        try:
            self.lines[k].updated(values)
        except ParameterError as e:
            if not self.names[k]:  # the single line of a line node: its own parameters
                raise
            raise ParameterError(f'line {self.names[k]!r}: {e}') from None

    def update(self, k: int, values: dict) -> None:
        """
        Apply run-time changes of line k's parameters (a shared one: call it for every line).

        The rope goes on from where it is (no restart): a new current acts from the next step.

        :raises ParameterError: as MooringLine.updated (nothing changed then).
        """
        self.check_update(k, values)
        line = self.lines[k]
        dt = line.time_step
        line.update(values)
        self._ends_version += 1  # (a payload's, a bollard's place are its parameters)
        self.arrangement = self.arrangement.with_line(self.names[k], line.params)
        self.ship_loads.current = line.props.current  # (the same for every line)
        if not self.started:
            if line.time_step != dt:
                self._group()
            return
        group, j = self.where(k)
        system = group.system
        system.lines[j].line_type = line.props.line_type
        self._apply_winch(k)  # also refreshes the tables
        if tuple(system.environment.current) != line.props.current:
            system.set_current(line.props.current)
        if line.time_step != dt:
            self._regroup()
        else:
            group.rules.refresh([self.lines[m] for m in group.members])

    def set_wind(self, speed: float, direction: float) -> None:
        """
        Blow the wind at this mean speed [m/s] from this direction [rad] from now on.

        Gusty wind (wind_spectrum) keeps its spectrum and seed about the new mean.
        """
        ship = replace(self.arrangement.ship, wind_speed=float(speed),
                       wind_direction=float(direction))
        self.arrangement = replace(self.arrangement, ship=ship)
        self.ship_loads.wind = ship_wind(ship)

    def set_output_interval(self, interval: float) -> None:
        """Choose the steps again so that each divides a new output interval [s]."""
        self._output_interval = interval
        for line in self.lines:
            line.set_output_interval(interval)
        self._regroup()

    # -- outputs --------------------------------------------------------------------------

    def output(self) -> MooringOutput:
        """
        Return the current state of every line: particles, end forces, strains, peaks.

        The peaks are those since the previous output (this call clears them).
        """
        count = len(self.lines)
        single = len(self.groups) == 1
        positions: List[Optional[np.ndarray]] = [None] * count
        payloads: List[Optional[np.ndarray]] = [None] * count
        if not single:
            forces, strains = np.empty((count, 2, 3)), np.empty(count)
            tensions, peaks = np.empty((count, 2)), np.empty((count, 2))
            winch_speeds = np.empty(count)
        total = 0.0
        for group in self.groups:
            system = group.system
            members = group.members
            group_forces, group_strains = system.loads()
            x = system.x.copy()  # one copy; each line's particles are a view of it
            group_tensions, group_peaks, group_total = system.take_tensions(group_forces, x)
            total += group_total
            if single:
                forces, strains, tensions, peaks = (group_forces, group_strains,
                                                    group_tensions, group_peaks)
                winch_speeds = system.line_real[:, WINCH_SPEED].copy()
            else:
                forces[members], strains[members] = group_forces, group_strains
                tensions[members], peaks[members] = group_tensions, group_peaks
                winch_speeds[members] = system.line_real[:, WINCH_SPEED]
            starts = group.starts
            for j, k in enumerate(members):
                positions[k] = x[starts[j]:starts[j + 1]]
                if self._payloads[k]:
                    payloads[k] = system.point_x[system.lines[j].ends[0]].copy()
                    total += float(payloads[k].sum())
        parted = np.array([line.parting is not None for line in self.lines])
        lengths = np.array([line.length for line in self.lines])
        total += float(lengths.sum())
        ship = self._ship_state() if self.free else None
        compressions, fender_forces, points = self._fender_states()
        loads = np.zeros((3, 3))
        if ship is not None:
            loads = self.ship_loads.at(self.time, ship.position,
                                       rotation_matrix(ship.orientation), ship.velocity)
        elif self.ship_loads.acts and reports_ship_loads(self.arrangement):
            # a driven ship's, worked out only where they are outputs: a single line's
            # current acts on the line alone
            position, orientation = self.ship_pose(self.time)
            loads = self.ship_loads.at(self.time, position, rotation_matrix(orientation),
                                       np.zeros(3))
        return MooringOutput(
            self.time, tuple(positions), forces[:, 1], forces[:, 0], strains, tuple(payloads),
            parted, peaks[:, 1], tensions[:, 1], tensions[:, 0], peaks[:, 0], lengths,
            winch_speeds, math.isfinite(total), ship, compressions, fender_forces, points,
            loads)

    def _ship_state(self) -> ShipState:
        """Return the free ship's motion now (its body origin's)."""
        body = self.body
        position, orientation = body.origin_pose()
        velocity = body.velocity + np.cross(body.omega, position - body.position)
        return ShipState(position, orientation, velocity, body.omega.copy())

    def _fender_states(self) -> tuple:
        """
        Return each fender's compression (F,), force on the ship (F, 3) and point (F, 3).

        A driven ship's hull is placed at the newest ship pose, at rest (no friction).
        """
        count = len(self.fenders)
        compressions, forces = np.zeros(count), np.zeros((count, 3))
        points = self._fender_rows[:, :3].copy() if count else np.zeros((0, 3))
        if not count or not self.started:
            return compressions, forces, points
        row = self.groups[0].system.body_table[0] if self.free else self._driven_hull()
        rotation = rotation_matrix(row[BODY_QUATERNION:BODY_QUATERNION + 4])
        velocity = row[BODY_VELOCITY:BODY_VELOCITY + 3]
        omega = row[BODY_OMEGA:BODY_OMEGA + 3]
        for f in range(count):
            compressions[f] = fender_force(self._fender_rows[f], row, rotation, velocity,
                                           omega, forces[f], points[f])[0]
        return compressions, forces, points

    def _driven_hull(self) -> np.ndarray:
        """Return a BODY row of the driven ship at its newest pose, at rest."""
        position, orientation = self.ship_pose(self.time)
        row = self._start_row.copy()
        row[BODY_QUATERNION:BODY_QUATERNION + 4] = orientation
        row[BODY_POSITION:BODY_POSITION + 3] = position - rotation_matrix(orientation) @ \
            row[BODY_ORIGIN:BODY_ORIGIN + 3]
        row[BODY_VELOCITY:BODY_OMEGA + 3] = 0.0
        return row


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
