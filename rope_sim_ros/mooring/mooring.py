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
of one line. A Mooring is made of parts, each a module of its own:

- its lines (line.py: each line's numbers and rules, a MooringLine);
- its ship (ship.py: one body with a mode, driven or free, its fenders and loads);
- their ends (ends.py: the fairleads on the ship, the bollards, their trajectories);
- its groups (group.py: lines with equal steps in one System, stepped by one kernel call,
  with the rules of every step);
- its outputs (outputs.py) and their records (records.py);
- its run-time changes: parameters and the environment (changes.py), and the lines made
  fast, let go and stowed (handling.py).

This module holds them together: it builds the groups, starts and restarts the lines at
rest, advances every group to a time and applies run-time changes. The Driver (driver.py)
is the one door to it from outside mooring/.
"""

import math
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from . import changes, handling
from .ends import Ends
from .group import Group, group_lines
from .line import MooringLine
from .outputs import mooring_output
from .records import MooringAdvance, MooringOutput
from .ship import Ship
from .trajectory import TrajectoryError
from ..model.objects import Line, System
from ..model.statics.pretension import length_for_tension, PretensionError
from ..params.arrangement import ArrangementParams
from ..params.materials import load_materials
from ..params.resolve import environment
from ..params.table import ParameterError


class Mooring:
    """
    Every line of an arrangement, stepped together (see the module docstring).

    :ivar lines: one MooringLine per line, in the arrangement's order.
    :ivar ship: the ship; ends: every line's ends; groups: the lines' groups.
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
        self.compiled = compiled
        self.integrator = arrangement.shared.integrator  # every line's: one kernel call
        # the one environment of the mooring: its lines, their Systems and the ship read it
        self.environment = environment(arrangement.shared, arrangement.ship)
        self.lines = [self._line(setup.name, setup.params) for setup in arrangement.lines]
        self.time = math.nan
        self.ship = Ship(arrangement)
        self.ends = Ends(self.lines, self.ship, history, arrangement.shared.end_interpolation)
        self.make_groups()

    def _line(self, name: str, params) -> MooringLine:
        try:
            return MooringLine(name, params, self._materials, self.environment,
                               self._output_interval)
        except ValueError as e:  # ParameterError, MaterialError, an unstable line
            if not name:  # the single line of a line node: its own parameters
                raise
            raise type(e)(f'line {name!r}: {e}') from None

    # -- what it is -----------------------------------------------------------------------

    @property
    def names(self) -> List[str]:
        """Return the line names, in order."""
        return self.arrangement.names

    @property
    def free(self) -> bool:
        """Tell whether the ship is free, moved by its lines and loads (ship_mode free)."""
        return self.ship.free

    @property
    def body(self):
        """Return the ship's body, where the ship is now."""
        return self.ship.placed_body()

    @property
    def started(self) -> bool:
        """Tell whether the ropes have been placed (by the first ship pose)."""
        return self.groups[0].system is not None

    @property
    def has_free_lines(self) -> bool:
        """Tell whether a line has been let go (is free)."""
        return any(line.state == 'free' for line in self.lines)

    @property
    def time_step(self) -> float:
        """Return the smallest of the lines' steps [s]."""
        return min(group.step for group in self.groups)

    @property
    def kernel_calls(self) -> int:
        """Return how many kernel calls step every line once: one per step group."""
        return len(self.groups)

    @property
    def offsets(self) -> np.ndarray:
        """Return every fairlead in the ship's body frame (L, 3) [m]."""
        return self.ends.offsets

    @property
    def held(self) -> np.ndarray:
        """Return whether each line's fairlead was held at its reach (L,)."""
        return self.ends.held

    @property
    def last_jumps(self) -> np.ndarray:
        """Return how far each line's newest end sample jumped [m] (L,)."""
        return self.ends.last_jumps

    def where(self, k: int) -> Tuple[Group, int]:
        """Return line k's group and its index there (a line out: not stowed)."""
        group = self._group_of[k]
        return group, group.members.index(k)

    def rope(self, k: int) -> Line:
        """Return line k's Line in its group's System (its x and v are the state)."""
        group, j = self.where(k)
        return group.system.lines[j]

    # -- groups ---------------------------------------------------------------------------

    def make_groups(self) -> None:
        """Put the lines with equal steps and bending treatment in one group each."""
        self.groups = group_lines(self.lines, self.free)
        self._group_of = {k: group for group in self.groups for k in group.members}

    def regroup(self, placed: Optional[Dict[int, System]] = None) -> None:
        """
        Group the lines again after a step or a state changed; rebuild the Systems if started.

        :param placed: {line index: a System of that line alone} for lines put in anew (a
            line made fast); the others carry on as they are.
        """
        started = self.started
        placed = placed or {}
        systems = {k: self.where(k) for k in self._group_of} if started else {}
        before = {group.key: group for group in self.groups}
        self.make_groups()
        if not started:
            return
        # a group that is what it was goes on as it is (a line made fast into one group
        # left the others' Systems alone: 16 lines in two groups, 4 ms less)
        kept = [before.get(group.key) for group in self.groups]
        self.groups = [old if old is not None and not set(old.members) & set(placed) else new
                       for old, new in zip(kept, self.groups)]
        self._group_of = {k: group for group in self.groups for k in group.members}
        sources = {k: group.system for k, (group, _) in systems.items()}
        indices = {k: j for k, (_, j) in systems.items()}
        for k, alone in placed.items():
            sources[k], indices[k] = alone, 0
        for group in self.groups:  # new groups carry on from the state time
            if group.system is None:
                group.build(sources, indices, self)
        self._set_time(self.time)

    def _build(self, sources: Dict[int, System], indices: Dict[int, int]) -> None:
        """Put each group's lines in one new System, each as it is in `sources` (Group.build)."""
        for group in self.groups:
            group.build(sources, indices, self)

    # -- inputs ---------------------------------------------------------------------------

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
        jumped = self.ends.push_ship(t, position, orientation, self.time)
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
        if not self.ends.push_bollard(k, t, point, self.time):
            return ''
        self.restart_line(k)
        return 'teleport'

    def ship_pose(self, t: float) -> Tuple[np.ndarray, np.ndarray]:
        """
        Return (position, unit quaternion) of the newest ship pose at or before t.

        A free ship's: its body origin's pose now (t is the state time at an output).
        """
        return self.ship.pose(t)

    def forget_ship(self) -> None:
        """Drop ship poses no output can use: outputs come at or after the state time."""
        self.ship.forget(self.time)

    def has_bollard_samples(self, k: int) -> bool:
        """Tell whether line k's bollard has samples of its own (it moves)."""
        return self.ends.has_bollard_samples(k)

    def free_ends(self, k: int, times: np.ndarray) -> tuple:
        """Return line k's ends where their samples put them at `times` (Ends.free_ends)."""
        return self.ends.free_ends(k, times)

    def drive(self, k: int, times: np.ndarray) -> tuple:
        """Return what drives line k's ends at `times` (Ends.drive)."""
        return self.ends.drive(k, times)

    def set_external_load(self, force, moment, body_axes: bool) -> None:
        """Hold an external load on the free ship from now on (Ship.set_external_load)."""
        self.ship.set_external_load(force, moment, body_axes)

    def set_load_schedule(self, times: np.ndarray, loads: np.ndarray) -> None:
        """Take a schedule of external loads on the free ship (Ship.set_load_schedule)."""
        self.ship.set_load_schedule(times, loads)

    # -- start and restarts ---------------------------------------------------------------

    def start(self, t: float) -> Dict[int, float]:
        """
        Place every rope at rest at time t (a ship pose must have come).

        A line given a pretension gets its length first, from where its ends are now.

        :returns: {line index: the length chosen [m]} of the pretensioned lines.
        :raises ParameterError: a pretension no length gives (named with its line).
        """
        if not self.ship.has_pose:
            raise TrajectoryError('cannot start the lines before the first ship pose')
        lengths = self.resolve_pretensions(t)
        alone = {}
        for k in self._group_of:  # the lines out; a stowed line waits aboard
            alone[k] = self.at_rest_or_parted(k, t)
        self._build(alone, {k: 0 for k in alone})
        for group in self.groups:  # what bringing them to rest pulled is no load of theirs
            group.system.take_peaks()
        self._set_time(t)
        for k in range(len(self.lines)):
            self.apply_winch(k)
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
            if setup.pretension <= 0.0 or self.lines[k].state != 'fast':
                continue
            line = self.lines[k]
            try:
                ends = self.free_ends(k, [t])[0][0]
                length = length_for_tension(line.props, self.environment, ends[0], ends[1],
                                            setup.pretension)
                params = setup.params.with_values({'length': length})
            except (ParameterError, PretensionError) as e:
                raise ParameterError(f'line {setup.name!r}: {e}') from None
            self.lines[k] = self._line(setup.name, params)
            self.arrangement = self.arrangement.with_line(setup.name, params)
            lengths[k] = length
            self.ends.changed()
        if lengths:
            self.make_groups()  # a new length can give a line another step
        return lengths

    def at_rest_or_parted(self, k: int, t: float) -> System:
        """
        Return line k alone at rest between its ends at t (MooringLine.at_rest).

        Parted at once if that state passes its break load (MooringLine.parted_if_overloaded).
        """
        line = self.lines[k]
        ends, _, distances = self.drive(k, [t])
        self.held[k] = bool(distances[0] > line.reach)
        alone = line.parted_if_overloaded(
            t, line.at_rest(ends[0], bool(self.held[k]), self.environment))
        if line.parting is not None:
            self.held[k] = False  # in pieces: nothing to hold at a reach
        return alone

    def place_line(self, k: int, shape: np.ndarray) -> None:
        """Put line k at rest at `shape` (N+1, 3) [m], its ends on its points (after start)."""
        group, j = self.where(k)
        group.system.load_line(j, self.lines[k].build(np.asarray(shape, dtype=float),
                                                      self.environment))
        self.apply_winch(k)

    def place_out(self, k: int, alone: System) -> None:
        """Put line k in its group as it is in `alone` (a System of it at rest), made fast."""
        self._give_winch(k, alone, 0)  # carried into the group with the rest of it
        alone.take_peaks()  # what bringing it to rest pulled is no load of its
        self.regroup({k: alone})

    def restart_line(self, k: int, t: Optional[float] = None) -> None:
        """Put line k back at rest between its ends, at its group's state time (or t)."""
        if not self.started or not self.lines[k].stepped:
            return
        group, j = self.where(k)
        t = group.time if t is None else t
        group.system.load_line(j, self.at_rest_or_parted(k, t))
        self.apply_winch(k)
        group.system.take_peaks(j)  # nor before the restart: the peaks start from its rest
        group.refresh(self.lines, self.environment)

    def apply_winch(self, k: int) -> None:
        """Give line k the winch and break load its parameters ask for now."""
        if not self.lines[k].stepped:  # aboard: its winch is given when it is made fast
            return
        group, j = self.where(k)
        self._give_winch(k, group.system, j)
        group.system.refresh()

    def _give_winch(self, k: int, system: System, j: int) -> None:
        """Give line k, line j of `system`, its winch and break load (tables not refreshed)."""
        line = self.lines[k]
        p = line.params
        if p.winch_mode == 'constant_tension' and not p.winch_tension and \
                not math.isfinite(line.held_tension):
            line.held_tension = float(np.linalg.norm(system.loads()[0][j, 1]))
        rope = system.lines[j]
        rope.break_load = line.break_load
        rope.winch = line.winch()

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
            self.ship.reset(self.groups[0].system)
        if self.started:
            self.restart()

    def command_winch(self, k: int, speed: float) -> None:
        """
        Command line k's winch speed [m/s] (+ pays out) from its next step.

        :raises ParameterError: speed is not a finite number.
        """
        line = self.lines[k]
        line.command_winch(speed)
        if self.started and line.stepped:
            group, j = self.where(k)
            group.system.set_winch(j, command=line.winch().command)

    # -- time -----------------------------------------------------------------------------

    def advance_to(self, t: float) -> MooringAdvance:
        """
        Advance every rope in its own fixed steps up to t (group.py's rules).

        Every group ends within a step of t; the state time is the earliest group's.
        """
        done = MooringAdvance(steps=0, lag=0.0)  # what the groups' steps did, gathered
        for group in self.groups:
            count = int(math.floor((t - group.time) / group.step + 1e-9))
            if count > 0:
                done.steps = max(done.steps, count)
                group.advance(self, group.time + group.step * np.arange(1, count + 1), done)
        groups = self.groups
        self.time = groups[0].time if len(groups) == 1 else min(g.time for g in groups)
        done.lag = t - self.time
        done.released = handling.release_hooks(self)
        self.forget_ship()  # (else a run fed every pose first searches them all at each output)
        return done

    def _set_time(self, t: float) -> None:
        self.time = t
        for group in self.groups:
            group.time = t

    def skip_to(self, t: float) -> None:
        """
        Move the state time to t without simulating.

        The particles stay where they are, so after more than rounding the ends are brought
        back onto their tracks over ends.py's END_BLEND_TIME: follow a long skip with restart().
        """
        for group in self.groups:
            if abs(t - group.time) > 1e-6 * group.step:  # more than pinning an output time
                self.ends.skipped(group.members)
        self._set_time(t)

    # -- parameters -----------------------------------------------------------------------

    def check_update(self, k: Optional[int], values: dict) -> None:
        """Refuse run-time changes update() could not apply (k None: every line's)."""
        changes.check_update(self, k, values)

    def update(self, k: Optional[int], values: dict) -> None:
        """Apply run-time changes of line k's parameters, or every line's (changes.py)."""
        changes.update(self, k, values)

    def set_output_interval(self, interval: float) -> None:
        """Choose the steps again so that each divides a new output interval [s]."""
        self._output_interval = interval
        for line in self.lines:
            line.set_output_interval(interval, self.environment)
        self.regroup()

    # -- line handling --------------------------------------------------------------------

    def command(self, k: int, name: str) -> str:
        """
        Take a line-handling command on line k now (handling.py); return what was done.

        :raises CommandError: an unknown command, or one that does not fit (says why).
        """
        return handling.command(self, k, name)

    def set_bollard(self, k: int, bollard: str) -> None:
        """
        Name the bollard line k will be made fast to ('': where it is now).

        :raises ParameterError: no bollard of that name, or the line is fast.
        """
        changes.set_bollard(self, k, bollard)

    # -- outputs --------------------------------------------------------------------------

    def output(self) -> MooringOutput:
        """
        Return the current state of every line: particles, end forces, strains, peaks.

        The peaks are those since the previous output (this call clears them).
        """
        return mooring_output(self)
