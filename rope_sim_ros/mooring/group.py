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
A group of a mooring's lines: one System, one step, one kernel call, and the rules of a step.

Lines with equal steps (and bending treatment) form a group that shares one physics System
(line j of the group between point 2 j, its bollard, and point 2 j + 1, its fairlead) and is
stepped by one kernel call per output, its lines' rules held as arrays of the group
(GroupRules). The kernels step each line whose ends are fixed or driven on its own, so a line
steps exactly as it would alone; one exception: a step that one line's violent motion
divides is divided for every line of its group. A free ship's lines are one group, whose
System holds the ship's body and the fenders.

Each line's rules, for every step of its group:

- its fairlead is held at its reach while its ends are farther apart than the line can
  stretch (ends.py), and the line restarts at rest at the first step they are back within
  it (a line held at its strain limit stores 1/2 EA e^2 L, which released whips it at c e
  with MN tensions for tens of seconds: the energy of a line that could not reach, not of
  the motion);
- a step in which a particle would move more than MAX_STEP_MOTION of a segment against the
  bollard is divided until none does (a line let go at its strain limit flings its
  particles at up to c e, 630 m/s on the default line, 3 m in one 5 ms implicit step on a
  0.8 m segment: the implicit step, linearised about a shape it has left far behind, then
  stretched every spring far past the limit each step); improved Euler's steps also until
  none is longer than the line's fine step (its stable step at its length now, no longer
  than the drag takes the particles' speed in);
- a state that turns non-finite, or whose end forces or strains pass the line's load bound
  (rope.tension_bound), restarts the line at rest; a free ship out of every bound of a moored
  ship restarts at its start pose at rest, every line with it;
- a line parts where a segment passes its break load, and its winch runs, in the steps.
"""

import math
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from .handling import recoiling
from .line import MooringLine, Parting
from .records import MooringAdvance
from ..model.objects import Environment, Line, Point, System
from ..model.superelastic import MAX_ITERATIONS
from ..stepping.rules import (fine_steps, implicit_bending, lines_motion_spreads,
                              lowest_bound, step_divisions)
from ..stepping.step import step


def divide_run(start: float, times: Sequence[float], parts: int) -> np.ndarray:
    """Return the times of the steps from start to times' last, each of times' cut in parts."""
    count = len(times) * parts
    return start + (times[-1] - start) * np.arange(1, count + 1) / count


def group_lines(lines: Sequence[MooringLine], free: bool) -> List['Group']:
    """
    Return the lines out (not stowed) with equal steps and bending treatment in one group each.

    A free ship's lines are one group (one System holds the body): at the smallest of their
    steps, with the bending springs in the implicit step if any line needs them. With every
    line stowed there is still one group, of no line, that keeps the time (and a free
    ship's body).
    """
    out = [k for k, line in enumerate(lines) if line.stepped]
    if free or not out:
        dt = min(lines[k].time_step for k in out or range(len(lines)))
        bending = any(implicit_bending(lines[k].props, dt) for k in out)
        return [Group(out, dt, bending)]
    keys: Dict[tuple, List[int]] = {}
    for k in out:
        line = lines[k]
        key = (line.time_step, implicit_bending(line.props, line.time_step))
        keys.setdefault(key, []).append(k)
    return [Group(members, dt, bending) for (dt, bending), members in sorted(keys.items())]


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

    def __init__(self, lines: Sequence[MooringLine], environment: Environment):
        """Take the lines' rules now, in the environment."""
        count = len(lines)
        self.reach = np.empty(count)
        self.segment_length = np.empty(count)
        self.stable = np.empty(count)
        self.rate = np.empty(count)
        self.current = np.empty(count)
        self.bound_at_rest = np.empty(count)
        self.bound_per_speed = np.empty(count)
        self._of = [None] * count  # the line's rules each row was taken from
        self.refresh(lines, environment)

    def refresh(self, lines: Sequence[MooringLine], environment: Environment) -> None:
        """Take again the rules of the lines whose numbers (or environment) changed since."""
        for j, line in enumerate(lines):
            rules = line.rules(environment)
            if self._of[j] is rules:
                continue
            self._of[j] = rules
            (self.reach[j], self.segment_length[j], self.stable[j], self.rate[j],
             self.current[j], self.bound_at_rest[j], self.bound_per_speed[j]) = rules


class Group:
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
        self.plan = (None, None)  # how its ends are driven (Ends._plan)
        self.index = np.array(members, dtype=np.int64)  # members, to index arrays with
        self.winches = (None, [])  # (j, k) of its lines with a winch, and of when

    @property
    def key(self) -> tuple:
        """Return what makes it the group it is: its lines, its step, its bending."""
        return tuple(self.members), self.step, self.bending

    def refresh(self, lines: Sequence[MooringLine], environment: Environment) -> None:
        """Take again the rules of its lines (of the mooring's `lines`) that changed."""
        self.rules.refresh([lines[k] for k in self.members], environment)

    def build(self, sources: Dict[int, System], indices: Dict[int, int], mooring) -> None:
        """
        Put the group's lines in one new System, each line as it is in `sources`.

        A free ship's System holds its body and the fenders, and each fairlead is a point
        the body carries.

        :param sources: line k's System now (its own at rest, or an old group's).
        :param indices: line k's index in it.
        :param mooring: the Mooring: its lines, its ship and their ends.
        """
        members = [(sources[k], indices[k]) for k in self.members]
        system = System(mooring.environment)
        free = mooring.ship.free
        if free:
            system.add_body(mooring.ship.body)
            for fender in mooring.ship.fenders:
                system.add_fender(fender)
        for j, (source, i) in enumerate(members):
            rope = source.lines[i]
            for e, q in enumerate(rope.ends):
                point = source.points[q]
                if e == 1 and free:  # the fairlead: on the ship
                    system.add_point(Point('carried', point.position.copy(), body=0,
                                           offset=mooring.ends.from_gravity(self.members[j])))
                    continue
                system.add_point(Point(point.kind, point.position.copy(), point.mass,
                                       point.velocity.copy(), point.volume, point.drag_area,
                                       point.added_mass))
            system.add_line(Line(rope.line_type, rope.rest.copy(), rope.x.copy(),
                                 (2 * j, 2 * j + 1)))
        system.pack()
        system.load_lines([(j, source, i) for j, (source, i) in enumerate(members)])
        self.system = system
        self.starts = np.array([0] + [len(line.x) for line in system.lines]).cumsum()
        self.rules = GroupRules([mooring.lines[k] for k in self.members], mooring.environment)
        self.fine = np.empty(len(self.members))

    # -- its steps ------------------------------------------------------------------------

    def advance(self, mooring, times: np.ndarray, done: MooringAdvance) -> None:
        """
        Take the group's steps to `times`: held at the reach, back within it (Mooring's).

        :param mooring: the Mooring the group is of: its lines, ends, ship and restarts.
        """
        ends = mooring.ends
        if mooring.ship.free:
            self._check_ship(mooring, done)
            mooring.ship.set_body_loads(self.system, self.time, float(times[-1]),
                                        mooring.environment)
        elif not self.members:  # every line stowed: time passes, nothing moves
            self.time = float(times[-1])
            return
        drive_x, drive_v, distances, far = ends.drive_group(self, times)
        if not (far or ends.held.any()):  # the common case
            self._step(mooring, times, drive_x, drive_v, done)
            return
        held = ends.held[self.index]
        beyond = distances > self.rules.reach
        back = ~beyond & np.vstack([held, beyond[:-1]])
        for j in np.flatnonzero(beyond.any(axis=0)):
            k = self.members[j]
            done.beyond_reach[k] = max(done.beyond_reach.get(k, 0.0),
                                       float(distances[beyond[:, j], j].max()))
        if back.any():
            # a line back within reach restarts at rest at that step (its state there is the
            # restart's, whatever the step did): step the group to it, then go on
            i = int(np.flatnonzero(back.any(axis=1))[0])
            self._step(mooring, times[:i + 1], drive_x[:i + 1], drive_v[:i + 1], done)
            for j in np.flatnonzero(back[i]):
                mooring.restart_line(self.members[j], float(times[i]))
                done.restarted[self.members[j]] = 'back within reach'
            for j in np.flatnonzero(~back[i]):
                ends.held[self.members[j]] = bool(beyond[i, j])
            if i + 1 < len(times):
                self.advance(mooring, times[i + 1:], done)
            return
        ends.held[self.index] = beyond[-1]
        self._step(mooring, times, drive_x, drive_v, done)

    def _step(self, mooring, times: np.ndarray, drive_x: np.ndarray, drive_v: np.ndarray,
              done: MooringAdvance) -> None:
        """Take the steps to `times`, divided as the rules ask, then check the lines."""
        mooring.ends.blend(self, times, drive_x, drive_v)
        spreads = lines_motion_spreads(self.system.v, self.starts, drive_v)
        parts, violent = self._divisions(mooring, spreads)
        if parts == 1:
            self._run(mooring, self.step, drive_x, drive_v, done, spreads[:, 2])
        elif not violent:  # only explicit steps' bounds: divide the whole run alike
            self._run_divided(mooring, divide_run(self.time, times, parts), done)
        else:
            for t in times:  # a violent stretch somewhere: look again before every step
                parts, _ = self._divisions(
                    mooring, lines_motion_spreads(self.system.v, self.starts, drive_v))
                self._run_divided(mooring, divide_run(self.time, [t], parts), done)
                self.time = float(t)
        self.time = float(times[-1])
        self._check(mooring, spreads[:, 1], done)  # the ends' speeds

    def _divisions(self, mooring, spreads: np.ndarray) -> Tuple[int, bool]:
        """Return the parts every step is divided in, and whether to look again."""
        rules = self.rules
        explicit = mooring.integrator == 'improved_euler'
        return step_divisions(spreads, self.step, rules.segment_length, explicit,
                              rules.stable, rules.rate, rules.current)

    def _run_divided(self, mooring, fine: np.ndarray, done: MooringAdvance) -> None:
        """Take the steps to the divided times `fine`, the ends driven there."""
        fine_x, fine_v = mooring.ends.drive_group(self, fine)[:2]
        mooring.ends.blend(self, fine, fine_x, fine_v)
        self._run(mooring, (fine[-1] - self.time) / len(fine), fine_x, fine_v, done)

    def _run(self, mooring, dt: float, drive_x: np.ndarray, drive_v: np.ndarray,
             done: MooringAdvance, speeds: Optional[np.ndarray] = None) -> None:
        """
        Take len(drive_x) substeps of dt of the lines: one kernel call.

        :param speeds: the lines' speed bounds for these steps (lines_motion_spreads' last
            column), if the caller has them.
        """
        integrator = mooring.integrator
        fine = 0.0
        if integrator == 'adaptive':  # each line's own improved Euler step
            if mooring.has_free_lines:
                self.system.watched[:] = [recoiling(mooring.lines[k], self.time)
                                          for k in self.members]
            if speeds is None:
                speeds = lines_motion_spreads(self.system.v, self.starts, drive_v)[:, 2]
            rules = self.rules
            fine_steps(rules.stable, rules.rate, rules.current, speeds, self.fine)
            fine = self.fine
        parted = step(self.system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS,
                      self.bending, mooring.compiled, fine)
        self._follow_run(mooring, dt, parted, done)

    def _follow_run(self, mooring, dt: float, parted: list, done: MooringAdvance) -> None:
        """Take in what a run of steps of dt from the group's time did: lengths, partings."""
        changed = False
        lines = mooring.lines
        version = mooring.ends.version
        if self.winches[0] != version:  # (parameters changed: a winch mode)
            self.winches = (version, [(j, k) for j, k in enumerate(self.members)
                                      if lines[k].params.winch_mode != 'none'])
        for j, k in self.winches[1]:
            line = lines[k]
            length = self.system.unstretched_length(j)
            changed |= length != line.length
            line.length = length
        for j, at in parted:
            k = self.members[j]
            line = lines[k]
            line.parting = Parting(self.time + (at + 1) * dt, self.system.lines[j].parted,
                                   line.break_load)
            mooring.ends.held[k] = False  # its pieces reach anywhere: no 'back within reach'
            done.parted[k] = line.parting
            changed = True
        if changed:
            self.refresh(lines, mooring.environment)

    # -- its checks -----------------------------------------------------------------------

    def _check(self, mooring, end_speeds: np.ndarray, done: MooringAdvance) -> None:
        """
        Restart every line whose state is not finite or past its load bound.

        A free ship out of a moored ship's bounds (sunk, capsized, far off, its numbers not
        finite) restarts at its start pose at rest, and every line with it.

        :param end_speeds: each line's largest end speed over the steps just taken [m/s].
        """
        system = self.system
        restarted = done.restarted
        if mooring.ship.free:
            self._check_ship(mooring, done)
        finite, largest = system.largest_load()
        rules = self.rules
        if finite and largest <= lowest_bound(rules.bound_at_rest, rules.bound_per_speed,
                                              end_speeds):
            return  # the common case: no line near its bound
        bounds = rules.bound_at_rest + rules.bound_per_speed * end_speeds
        if not finite:  # which lines? (the kernel stops at the first)
            rows = np.isfinite(system.x).all(axis=1) & np.isfinite(system.v).all(axis=1)
            finite = np.logical_and.reduceat(rows, self.starts[:-1])
            finite &= (np.isfinite(system.point_x).all(axis=1)
                       & np.isfinite(system.point_v).all(axis=1)).reshape(-1, 2).all(axis=1)
            for j in np.flatnonzero(~finite):  # first, so that the others' loads count
                restarted[self.members[j]] = 'non-finite state'
                mooring.restart_line(self.members[j])
        largest = system.line_loads()  # from the loads largest_load computed, once per state
        for j in np.flatnonzero(~(largest <= bounds)):  # also NaN
            restarted[self.members[j]] = 'unphysical state'
            mooring.restart_line(self.members[j])

    def _check_ship(self, mooring, done: MooringAdvance) -> None:
        """
        Restart a free ship out of a moored ship's bounds at its start pose, at rest.

        Every line restarts with it (done.restarted: 'ship restarted'). Before the steps
        too: the loads on the ship are worked out from its state.
        """
        why = mooring.ship.out_of_bounds(self.system)
        if why:
            mooring.ship.reset(self.system)
            done.ship_restarted = why
            for k in self.members:
                done.restarted[k] = 'ship restarted'
                mooring.restart_line(k)
