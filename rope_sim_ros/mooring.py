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
A ship's mooring lines stepped together: one physics System, one kernel call per output.

Each line keeps a Simulator (simulator.py) for the rules of one line, so that each rule
has one home: its parameters and properties, its end trajectories, the fairlead held
within the line's reach, the start at rest, a teleport, the step division, an end brought
back onto its track, its winch, its parting, its peak hold, the state check's bound. Lines
with equal steps share one System (simulator.share_system: line j between point 2 j, its
bollard, and point 2 j + 1, its fairlead), and the Mooring steps it through the
Simulators' public pieces (drive, fixed_bollard, hold_beyond_reach, reach_steps,
blend_ends, divisions_for, fine_step_for, follow_run, load_bound): the kernels step each
line whose ends are fixed or driven on its own, so a line here steps exactly as its
single-line Simulator does at that step (a test finds eight lines equal to eight
single-line runs to round-off). One exception: a step that one line's violent motion
divides is divided for every line of its group. A Simulator that starts its rope again (a
restart, a teleport, a restore) puts it in its place in the shared System itself.

The ship pose drives every fairlead: fairlead k is the pose ⊕ its fairlead_offset (body
frame), pushed to its Simulator as that line's fairlead sample, so it is interpolated as
the single-line node interpolates it. The Mooring keeps the same samples of every fairlead
in one trajectory too: while a line's own samples are those (a teleport gives it its own)
and its bollard stands still, its ends come from one sampling of all of them, the very
numbers its Simulator gives, without each line's Python. Bollards are fixed at
bollard_position or follow their own samples (ship-to-ship mooring).

The total load on the ship (mooring_wrench) is the sum of the fairlead forces and of their
moments about the ship's origin: in the ship's body frame, F = R^T sum F_k and
M = sum o_k x (R^T F_k), with o_k the fairlead offsets and R the ship's orientation.

A parted line goes on as its two pieces; its fairlead force, and so its part of the total
wrench, is the pull of the piece still on the ship (nothing once that piece hangs free).
Each line's winch takes its own commands (command_winch).
"""

from collections import deque
from dataclasses import dataclass, field
import math
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .model.frames import cross_rows, pose_points, rotation_matrix, unit_quaternion
from .model.objects import System
from .model.rope import RopeProperties
from .model.statics.catenary import CatenaryError, solve_catenary
from .model.superelastic import MAX_ITERATIONS
from .params.arrangement import ArrangementParams, LineSetup
from .params.materials import load_materials
from .params.table import ParameterError
from .simulator import divide_run, Parting, share_system, Simulator, take_peaks
from .stepping.rules import drive_lines, implicit_bending, lines_motion_spreads
from .stepping.step import step
from .trajectory import EndTrajectory, TrajectoryError

# Bisection steps of length_for_tension (2^-60 of the bracket: far below a micrometre).
LENGTH_BISECTIONS = 60


def length_for_tension(props: RopeProperties, bollard, fairlead, tension: float) -> float:
    """
    Return the unstretched length whose elastic catenary pulls the fairlead with `tension`.

    The catenary in air (the line's weight less the air's buoyancy, props.weight_per_length)
    between the bollard and the fairlead; a weightless line is a straight elastic bar. The
    fairlead tension falls as the line grows, down to the least it can have hanging between
    its ends; bisection between the line at its reach and that.

    :raises ParameterError: the tension is more than the line pulls at its reach (EA times
        max_strain) or less than the least it can have between these ends.
    """
    up = -np.asarray(props.gravity, dtype=float)
    g = float(np.linalg.norm(up))
    up = up / g if g > 0.0 else np.array([0.0, 0.0, 1.0])
    chord = np.asarray(fairlead, dtype=float) - np.asarray(bollard, dtype=float)
    distance = float(np.linalg.norm(chord))
    rise = float(chord @ up)
    span = math.sqrt(max(distance * distance - rise * rise, 0.0))
    ea, w = props.axial_stiffness, props.weight_per_length
    strongest = ea * props.max_strain
    if not distance > 0.0:
        raise ParameterError('pretension needs the fairlead away from the bollard: they are '
                             'at one place at the first ship pose')
    if tension >= strongest:
        raise ParameterError(f'pretension {tension:.0f} N is not below what the line pulls at '
                             f'its reach (EA x max_strain = {strongest:.0f} N)')
    if not w > 0.0:
        return distance / (1.0 + tension / ea)

    def fairlead_tension(length: float) -> float:
        return solve_catenary(span, rise, length, w, ea).tension_b

    low, high = distance / (1.0 + props.max_strain), distance
    try:
        least = fairlead_tension(high)
        while least > tension:  # longer lines until one pulls less, or the tension grows
            longer = fairlead_tension(high * 1.25)
            if longer >= least:
                raise ParameterError(
                    f'pretension {tension:.0f} N is below the least fairlead tension the '
                    f'line can have between its ends ({least:.0f} N, hanging under its '
                    'weight)')
            low, high, least = high, high * 1.25, longer
        for _ in range(LENGTH_BISECTIONS):
            middle = 0.5 * (low + high)
            if fairlead_tension(middle) > tension:
                low = middle
            else:
                high = middle
    except CatenaryError as e:
        raise ParameterError(f'pretension {tension:.0f} N: no catenary between the ends: '
                             f'{e}') from None
    return 0.5 * (low + high)


def mooring_wrench(fairlead_forces: np.ndarray, offsets: np.ndarray,
                   orientation: Sequence[float]) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return the total force and moment of the lines on the ship, in its body frame.

    F = R^T sum_k F_k and M = sum_k o_k x (R^T F_k): the moment about the ship's origin.

    :param fairlead_forces: force of each line on its fairlead (L, 3) [N], in frame_id.
    :param offsets: each fairlead in the ship's body frame (L, 3) [m].
    :param orientation: the ship's orientation (x, y, z, w), a unit quaternion.
    """
    body = np.asarray(fairlead_forces, dtype=float).reshape(-1, 3) @ rotation_matrix(
        orientation)  # R^T F, row by row
    moments = cross_rows(np.asarray(offsets, dtype=float).reshape(-1, 3), body)
    return body.sum(axis=0), moments.sum(axis=0)


def to_world(orientation: Sequence[float], force: np.ndarray,
             moment: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Return a body-frame force and moment in frame_id axes (moment about the same origin)."""
    rotation = rotation_matrix(orientation)
    return rotation @ np.asarray(force, dtype=float), rotation @ np.asarray(moment, dtype=float)


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
        (L,) [N]: every step's, this output's included (Output.fairlead_peak).
    :ivar fairlead_tensions: |fairlead force| of each line (L,) [N]; bollard_tensions too.
    :ivar bollard_peaks: each line's largest bollard (or payload) tension likewise (L,) [N].
    :ivar line_lengths: each line's unstretched length now (L,) [m] (its winch changes it).
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

    @property
    def peaks(self) -> np.ndarray:
        """Return each line's largest tension at either end since the previous output (L,)."""
        return np.maximum(self.fairlead_peaks, self.bollard_peaks)


@dataclass(frozen=True)
class MooringAdvance:
    """
    What one advance_to call did.

    :ivar steps: steps taken.
    :ivar lag: how far the state time is behind the requested time [s].
    :ivar restarted: {line index: why} for every line restarted at rest ('non-finite
        state', 'unphysical state', 'back within reach'), see Simulator.advance_to.
    :ivar beyond_reach: {line index: the largest distance between its ends [m]} for every
        line whose fairlead was held at its reach.
    :ivar parted: {line index: its Parting} for every line that parted in these steps.
    """

    steps: int
    lag: float
    restarted: Dict[int, str] = field(default_factory=dict)
    beyond_reach: Dict[int, float] = field(default_factory=dict)
    parted: Dict[int, Parting] = field(default_factory=dict)


class _Group:
    """
    Lines that step together: one System, one step, one kernel call per output.

    :ivar members: the lines' indices in the arrangement; line members[j] is the System's
        line j, between its points 2 j (bollard) and 2 j + 1 (fairlead).
    :ivar step: their step [s]; bending: whether the implicit step solves the bending
        springs too (integrators.implicit_bending, the same for every member).
    :ivar system: their System (None before start); time: its state time [s].
    """

    def __init__(self, members: List[int], step: float, bending: bool):
        self.members = members
        self.step = step
        self.bending = bending
        self.system: Optional[System] = None
        self.starts = np.zeros(1, dtype=np.int64)
        self.time = math.nan


class Mooring:
    """
    Every line of an arrangement, stepped together (see the module docstring).

    Lines whose own steps (and bending treatment) are equal share a System: each line steps
    exactly as its Simulator would alone, and an arrangement of one kind of line takes one
    kernel call per output (a stiffer line, e.g. HMPE, with its shorter step, a second).

    :ivar sims: one Simulator per line, in the arrangement's order: each line's rules.
    :ivar time: the state time [s] (NaN before start).
    """

    def __init__(self, arrangement: ArrangementParams, materials: Any = None,
                 output_interval: float = 0.0, history: float = 5.0):
        """
        Build every line (see Simulator); the ropes are placed by start().

        :param arrangement: validated parameters.
        :param materials: material presets (default: config/materials.yaml).
        :param output_interval: if > 0, every step divides it (outputs fall on step times).
        :param history: seconds of samples each line keeps behind the newest.
        :raises ParameterError / MaterialError / ValueError: a line cannot be built; the
            message names it.
        """
        self.arrangement = arrangement
        self._materials = materials or load_materials()
        self._output_interval = output_interval
        self._history = history
        self.sims = [self._simulator(line, line.params) for line in arrangement.lines]
        self.time = math.nan
        # ship samples (t, position, unit quaternion): the newest at or before an output
        # gives its orientation (as LineDriver.lever does for the levers)
        self._ship: deque = deque()
        # every fairlead in one trajectory, sampled for a whole group in one call; line k's
        # own trajectory holds the same samples while _mirrored[k] is (it, its version)
        first = self.sims[0].fairlead
        self._fairleads = EndTrajectory(first.coast_time, first.keep, first.method,
                                        width=len(self.sims))
        self._mirrored = [self._mirror(sim) for sim in self.sims]
        self._group()

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

    def _mirror(self, sim: Simulator) -> Optional[tuple]:
        """Return what _mirrored keeps of a line whose fairlead samples equal _fairleads'."""
        mine, shared = sim.fairlead, self._fairleads
        settings = (mine.coast_time, mine.keep, mine.method)
        if settings != (shared.coast_time, shared.keep, shared.method):
            return None
        return mine, mine.version

    def _mirrors(self, k: int) -> bool:
        """Tell whether line k's fairlead samples are _fairleads' (none changed since)."""
        fairlead = self.sims[k].fairlead
        return self._mirrored[k] == (fairlead, fairlead.version)

    def _simulator(self, line: LineSetup, params) -> Simulator:
        try:
            return Simulator(params, self._materials, output_interval=self._output_interval,
                             history=self._history)
        except ValueError as e:  # ParameterError, MaterialError, an unstable line
            raise type(e)(f'line {line.name!r}: {e}') from None

    def _group(self) -> None:
        """Put the lines with equal steps and bending treatment in one group each."""
        keys: Dict[tuple, List[int]] = {}
        for k, sim in enumerate(self.sims):
            key = (sim.time_step, implicit_bending(sim.props, sim.time_step))
            keys.setdefault(key, []).append(k)
        self.groups = [_Group(members, step, bending)
                       for (step, bending), members in sorted(keys.items())]

    def _regroup(self) -> None:
        """Group the lines again after a step changed; rebuild the Systems if started."""
        started = self.started
        self._group()
        if started:  # new groups carry on from the state time (a new group has none)
            self._build()
            self._set_time(self.time)

    @property
    def offsets(self) -> np.ndarray:
        """Return every fairlead in the ship's body frame (L, 3) [m]."""
        params = [id(sim.params) for sim in self.sims]  # new parameters: new objects
        if getattr(self, '_offsets', (None,))[0] != params:
            self._offsets = (params, np.array([sim.params.fairlead_offset for sim in self.sims],
                                              dtype=float))
        return self._offsets[1]

    # -- inputs ---------------------------------------------------------------------------

    def push_ship(self, t: float, position, orientation) -> List[int]:
        """
        Take a ship pose: every fairlead gets its sample, pose ⊕ fairlead_offset.

        :returns: the lines a jump past teleport_distance restarted (see
            Simulator.push_fairlead).
        :raises PoseError: non-finite pose or zero quaternion (nothing changed).
        :raises TrajectoryError: not after the newest ship pose (nothing changed).
        """
        q, _ = unit_quaternion(orientation)
        points = pose_points(position, orientation, self.offsets)
        if self._ship and t <= self._ship[-1][0]:
            raise TrajectoryError(f'ship pose at t={t:.6f} s is not after the newest one '
                                  f'({self._ship[-1][0]:.6f} s)')
        self._fairleads.push(t, points)
        self._ship.append((t, np.array(position, dtype=float), q))
        self.forget_ship()
        teleported = []
        for k, (sim, point) in enumerate(zip(self.sims, points.tolist())):
            version = sim.fairlead.version
            mirrored = self._mirrors(k)
            if sim.push_fairlead(t, point) == 'teleport' and self.started:
                teleported.append(k)  # restarted in its place in the shared System
            # still the same samples if this push was the trajectory's only change
            mirrored = mirrored and sim.fairlead.version == version + 1
            self._mirrored[k] = (sim.fairlead, sim.fairlead.version) if mirrored else None
        if len(teleported) == len(self.sims):  # every line holds this sample alone
            self._fairleads.clear()
            self._fairleads.push(t, points)
            self._mirrored = [self._mirror(sim) for sim in self.sims]
        return teleported

    def push_bollard(self, k: int, t: float, point) -> str:
        """
        Take a bollard sample of line k; return 'teleport' if it restarted the line.

        :raises TrajectoryError: non-finite, or not after that bollard's newest sample.
        """
        return self.sims[k].push_bollard(t, point)

    def ship_pose(self, t: float) -> Tuple[np.ndarray, np.ndarray]:
        """Return (position, unit quaternion) of the newest ship pose at or before t."""
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

    # -- start ----------------------------------------------------------------------------

    def start(self, t: float) -> Dict[int, float]:
        """
        Place every rope at rest at time t (a ship pose must have come).

        A line given a pretension gets its length first, from where its ends are now.

        :returns: {line index: the length chosen [m]} of the pretensioned lines.
        :raises ParameterError: a pretension no length gives (named with its line).
        """
        if not self._ship:
            raise TrajectoryError('cannot start the lines before the first ship pose')
        lengths = self._resolve_pretensions(t)
        for sim in self.sims:
            sim.start(t)
        self._build()
        self._set_time(t)
        return lengths

    def _resolve_pretensions(self, t: float) -> Dict[int, float]:
        """Give every pretensioned line the length that starts it at its pretension."""
        lengths = {}
        for k, line in enumerate(self.arrangement.lines):
            if line.pretension <= 0.0:
                continue
            sim = self.sims[k]
            try:
                ends = sim.free_ends([t])[0][0]
                length = length_for_tension(sim.props, ends[0], ends[1], line.pretension)
                params = line.params.with_values({'length': length})
            except ParameterError as e:
                raise ParameterError(f'line {line.name!r}: {e}') from None
            new = self._simulator(line, params)
            new.fairlead, new.bollard = sim.fairlead, sim.bollard  # the samples so far
            self.sims[k] = new
            self.arrangement = self.arrangement.with_line(line.name, params)
            lengths[k] = length
        if lengths:
            self._group()  # a new length can give a line another step
        return lengths

    def _build(self) -> None:
        """Put each group's lines in one System (simulator.share_system)."""
        for group in self.groups:
            group.system = share_system([self.sims[k] for k in group.members])
            group.starts = np.array([0] + [len(line.x) for line in group.system.lines]).cumsum()

    def restart(self, t: Optional[float] = None) -> None:
        """Put every rope back at rest between its ends (at the state time, or t)."""
        t = self.time if t is None else t
        for sim in self.sims:
            sim.restart(t)
        self._set_time(t)

    def restore(self) -> None:
        """Give every line back its length and its whole rope, at rest at the state time."""
        self._set_time(self.time)
        for sim in self.sims:
            sim.restore()

    def command_winch(self, k: int, speed: float) -> None:
        """
        Command line k's winch speed [m/s] (+ pays out) from its next step.

        :raises ParameterError: speed is not a finite number (Simulator.command_winch).
        """
        self.sims[k].command_winch(speed)

    # -- time -----------------------------------------------------------------------------

    def advance_to(self, t: float) -> MooringAdvance:
        """
        Advance every rope in its own fixed steps up to t.

        Each line follows Simulator.advance_to's rules: held at its reach while its ends are
        farther apart, restarted at rest once they are back within it, and restarted when
        its state turns non-finite or past its load_bound; it parts, and its winch runs, in
        the steps. Every group ends within a step of t; the state time is the earliest
        group's.
        """
        start = self.time
        done = MooringAdvance(0, 0.0)  # what the groups' steps did, gathered
        steps = 0
        for group in self.groups:
            count = max(0, int(math.floor((t - group.time) / group.step + 1e-9)))
            if count:
                steps = max(steps, count)
                self._advance_group(group, group.time + group.step * np.arange(1, count + 1),
                                    done)
        self.time = min(group.time for group in self.groups)
        if not steps:
            return MooringAdvance(0, t - start)
        return MooringAdvance(steps, t - self.time, done.restarted, done.beyond_reach,
                              done.parted)

    def _advance_group(self, group: _Group, times: np.ndarray, done: MooringAdvance) -> None:
        """Take the steps of one group to `times` (Simulator.advance_to's rules)."""
        drive_x, drive_v, distances, reach = self._drive(group, times)
        sims = [self.sims[k] for k in group.members]
        beyond = distances > reach
        if not (beyond.any() or any(sim.held for sim in sims)):  # the common case
            self._step(group, times, drive_x, drive_v, done)
            return
        back = np.empty_like(beyond)
        for j, sim in enumerate(sims):
            beyond[:, j], back[:, j] = sim.reach_steps(distances[:, j])
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
                sims[j].restart(float(times[i]))
                done.restarted[group.members[j]] = 'back within reach'
            for j in np.flatnonzero(~back[i]):
                sims[j].held = bool(beyond[i, j])
            if i + 1 < len(times):
                self._advance_group(group, times[i + 1:], done)
            return
        for j, sim in enumerate(sims):
            sim.held = bool(beyond[-1, j])
        self._step(group, times, drive_x, drive_v, done)

    def _drive(self, group: _Group, times: np.ndarray) -> tuple:
        """
        Return a group's driven points at `times` (n, Q, 3) twice, distances (n, L), reach (L,).

        Simulator.drive of each line, and its reach (Simulator.reach). A line whose bollard
        stands still and whose fairlead samples are _fairleads' gets the same numbers from one
        sampling of every fairlead.
        """
        n, count = len(times), len(group.members)
        drive_x = np.empty((n, 2 * count, 3))
        drive_v = np.empty((n, 2 * count, 3))
        distances = np.empty((n, count))
        reach = np.array([self.sims[k].reach for k in group.members])
        shared, bollards = [], []  # (j, k) of those lines, their bollards
        for j, k in enumerate(group.members):
            sim = self.sims[k]
            fixed = sim.fixed_bollard
            if fixed is not None and self._mirrors(k):
                shared.append((j, k))
                bollards.append(fixed)
                continue
            ends, velocities, distances[:, j] = sim.drive(times)
            drive_x[:, 2 * j:2 * j + 2] = ends
            drive_v[:, 2 * j:2 * j + 2] = velocities
        if shared:
            shared = np.array(shared)
            beyond = drive_lines(drive_x, drive_v, distances, *self._fairleads.sample(times),
                                 shared, np.array(bollards, dtype=float), reach[shared[:, 0]])
            for j, k in shared[beyond]:
                self.sims[k].hold_beyond_reach(drive_x[:, 2 * j:2 * j + 2],
                                               drive_v[:, 2 * j:2 * j + 2], distances[:, j])
        return drive_x, drive_v, distances, reach

    def _step(self, group: _Group, times: np.ndarray, drive_x: np.ndarray,
              drive_v: np.ndarray, done: MooringAdvance) -> None:
        """Take a group's steps to `times` (as Simulator._step), then check its lines."""
        sims = [self.sims[k] for k in group.members]
        for j, sim in enumerate(sims):  # ends brought back onto their tracks (views)
            sim.blend_ends(times, drive_x[:, 2 * j:2 * j + 2], drive_v[:, 2 * j:2 * j + 2])
        parts, violent, spreads = self._divisions(group, sims, drive_v)
        if parts == 1:
            self._run(group, group.step, drive_x, drive_v, done, spreads[:, 2])
        elif not violent:  # only explicit steps' bounds: divide the whole run alike
            self._run_divided(group, sims, divide_run(group.time, times, parts), done)
        else:
            for t in times:  # a violent stretch somewhere: look again before every step
                parts = self._divisions(group, sims, drive_v)[0]
                self._run_divided(group, sims, divide_run(group.time, [t], parts), done)
                self._set_group_time(group, float(t))
        self._set_group_time(group, float(times[-1]))
        self._check(group, spreads[:, 1], done.restarted)  # the ends' speeds

    @staticmethod
    def _divisions(group: _Group, sims: List[Simulator],
                   drive_v: np.ndarray) -> Tuple[int, bool, np.ndarray]:
        """
        Return the parts every step of a group is divided in, whether to look again, spreads.

        spreads: the lines' integrators.lines_motion_spreads (L, 3) for these steps.
        """
        spreads = lines_motion_spreads(group.system.v, group.starts, drive_v)
        each = [sim.divisions_for(spread, speed)
                for sim, (spread, _, speed) in zip(sims, spreads.tolist())]
        return max(parts for parts, _ in each), any(violent for _, violent in each), spreads

    def _run_divided(self, group: _Group, sims: List[Simulator], fine: np.ndarray,
                     done: MooringAdvance) -> None:
        """Take a group's steps to the divided times `fine`, its ends driven there."""
        fine_x, fine_v, _, _ = self._drive(group, fine)
        for j, sim in enumerate(sims):
            sim.blend_ends(fine, fine_x[:, 2 * j:2 * j + 2], fine_v[:, 2 * j:2 * j + 2])
        self._run(group, (fine[-1] - group.time) / len(fine), fine_x, fine_v, done)

    def _run(self, group: _Group, dt: float, drive_x: np.ndarray, drive_v: np.ndarray,
             done: MooringAdvance, speeds: Optional[np.ndarray] = None) -> None:
        """
        Take len(drive_x) substeps of dt of a group's lines: one kernel call.

        :param speeds: the lines' speed bounds for these steps (lines_motion_spreads' last
            column), if the caller has them.
        """
        integrator = self.sims[group.members[0]].params.integrator
        fine = 0.0
        if integrator == 'adaptive':  # each line's own improved Euler step
            if speeds is None:
                speeds = lines_motion_spreads(group.system.v, group.starts, drive_v)[:, 2]
            fine = [self.sims[k].fine_step_for(speed)
                    for k, speed in zip(group.members, speeds.tolist())]
        parted = step(group.system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS,
                      group.bending, fine_step=fine)
        for k in group.members:
            self.sims[k].follow_run(dt, parted)
        for j, _ in parted:
            k = group.members[j]
            done.parted[k] = self.sims[k].parting

    def _set_group_time(self, group: _Group, t: float) -> None:
        group.time = t
        for k in group.members:
            self.sims[k].time = t

    def _set_time(self, t: float) -> None:
        self.time = t
        for group in self.groups:
            self._set_group_time(group, t)

    def _check(self, group: _Group, end_speeds: np.ndarray, restarted: Dict[int, str]) -> None:
        """
        Restart every line of a group whose state is not finite or past its load_bound.

        Simulator._unphysical's rule, for all its lines from one computation of the loads.

        :param end_speeds: each line's largest end speed over the steps just taken [m/s].
        """
        system = group.system
        finite, largest = system.largest_load()
        bounds = np.array([self.sims[k].load_bound(end_speeds[j])
                           for j, k in enumerate(group.members)])
        if finite and largest <= bounds.min():  # the common case: no line near its bound
            return
        if not finite:  # which lines? (the kernel stops at the first)
            rows = np.isfinite(system.x).all(axis=1) & np.isfinite(system.v).all(axis=1)
            finite = np.logical_and.reduceat(rows, group.starts[:-1])
            finite &= (np.isfinite(system.point_x).all(axis=1)
                       & np.isfinite(system.point_v).all(axis=1)).reshape(-1, 2).all(axis=1)
            for j in np.flatnonzero(~finite):  # first, so that the others' loads count
                restarted[group.members[j]] = 'non-finite state'
                self.sims[group.members[j]].restart(group.time)
        largest = system.line_loads()  # from the loads largest_load computed, once per state
        for j in np.flatnonzero(~(largest <= bounds)):  # also NaN
            restarted[group.members[j]] = 'unphysical state'
            self.sims[group.members[j]].restart(group.time)

    def skip_to(self, t: float) -> None:
        """Move the state time to t without simulating (see Simulator.skip_to)."""
        for sim in self.sims:
            sim.skip_to(t)
        self.time = t
        for group in self.groups:
            group.time = t

    # -- parameters -----------------------------------------------------------------------

    def check_update(self, k: int, values: dict) -> None:
        """Refuse run-time changes of line k's parameters update() could not apply."""
        try:
            self.sims[k].check_update(values)
        except ParameterError as e:
            raise ParameterError(f'line {self.names[k]!r}: {e}') from None

    def update(self, k: int, values: dict) -> None:
        """
        Apply run-time changes of line k's parameters (a shared one: call it for every line).

        :raises ParameterError: as Simulator.update (nothing changed then).
        """
        self.check_update(k, values)
        sim = self.sims[k]
        step = sim.time_step
        sim.update(values)  # on its line in the shared System too
        self.arrangement = self.arrangement.with_line(self.names[k], sim.params)
        if sim.time_step != step:
            self._regroup()

    def set_output_interval(self, interval: float) -> None:
        """Choose the steps again so that each divides a new output interval [s]."""
        self._output_interval = interval
        for sim in self.sims:
            sim.set_output_interval(interval)
        self._regroup()

    # -- outputs --------------------------------------------------------------------------

    def output(self) -> MooringOutput:
        """
        Return the current state of every line: particles, end forces, strains, peaks.

        The peaks are those since the previous output (this call clears them).
        """
        count = len(self.sims)
        forces, strains = np.empty((count, 2, 3)), np.empty(count)
        peaks = np.empty((count, 2))
        positions: List[Optional[np.ndarray]] = [None] * count
        payloads: List[Optional[np.ndarray]] = [None] * count
        for group in self.groups:
            system = group.system
            forces[group.members], strains[group.members] = system.loads()
            peaks[group.members] = take_peaks(system)
            x = system.x.copy()  # one copy; each line's particles are a view of it
            for j, k in enumerate(group.members):
                positions[k] = x[group.starts[j]:group.starts[j + 1]]
                if self.sims[k].payload:
                    payloads[k] = system.point_x[system.lines[j].ends[0]].copy()
        tensions = np.linalg.norm(forces, axis=2)
        parted = np.array([sim.parting is not None for sim in self.sims])
        lengths = np.array([sim.length for sim in self.sims])
        return MooringOutput(
            self.time, tuple(positions), forces[:, 1], forces[:, 0], strains, tuple(payloads),
            parted, peaks[:, 1], tensions[:, 1], tensions[:, 0], peaks[:, 0], lengths)
