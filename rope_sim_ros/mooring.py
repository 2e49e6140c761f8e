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
back onto its track. The Mooring steps the particles of every line in one System (line k
between point 2k, its bollard, and point 2k + 1, its fairlead) with the smallest of the
lines' steps: the kernels step each line whose ends are fixed or driven on its own, so a
line here steps exactly as its single-line Simulator does at that step (a test finds eight
lines equal to eight single-line runs to round-off). Each Simulator's rope is a view of
its line in the shared System; when a Simulator starts its rope again (a restart, a
teleport) the new rope is copied in and viewed again (_load_line).

The ship pose drives every fairlead: fairlead k is the pose ⊕ its fairlead_offset (body
frame), pushed to its Simulator as that line's fairlead sample, so it is interpolated as
the single-line node interpolates it. Bollards are fixed at bollard_position or follow
their own samples (ship-to-ship mooring).

The total load on the ship (mooring_wrench) is the sum of the fairlead forces and of their
moments about the ship's origin: in the ship's body frame, F = R^T sum F_k and
M = sum o_k x (R^T F_k), with o_k the fairlead offsets and R the ship's orientation.

Extension points for the single-line features to come (parting, winches, a per-step peak
hold): MooringOutput.parted and .fairlead_peaks are per-line outputs that follow the
Simulators once they carry them; until then no line parts and the peak is the tension
at the output.
"""

from collections import deque
from dataclasses import dataclass, field
import math
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .arrangement import ArrangementParams, LineSetup
from .frames import pose_point, rotate, unit_quaternion
from .params import ParameterError
from .physics.catenary import CatenaryError, solve_catenary
from .physics.integrators import implicit_bending
from .physics.objects import Line, Point, System
from .physics.rope import RopeProperties, tension_bound
from .physics.superelastic import MAX_ITERATIONS
from .simulator import load_materials, Simulator
from .trajectory import TrajectoryError

ROOT3 = math.sqrt(3.0)
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
    q = np.asarray(orientation, dtype=float)
    inverse = np.array([-q[0], -q[1], -q[2], q[3]])
    body = rotate(inverse, np.asarray(fairlead_forces, dtype=float).reshape(-1, 3))
    moments = np.cross(np.asarray(offsets, dtype=float).reshape(-1, 3), body)
    return body.sum(axis=0), moments.sum(axis=0)


def to_world(orientation: Sequence[float], force: np.ndarray,
             moment: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Return a body-frame force and moment in frame_id axes (moment about the same origin)."""
    q = np.asarray(orientation, dtype=float)
    return rotate(q, force), rotate(q, moment)


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
    :ivar parted: whether each line has parted (L,) (extension point: none parts yet).
    :ivar fairlead_peaks: each line's largest fairlead tension since the previous output
        (L,) [N] (extension point: the tension at the output until a per-step peak hold).
    """

    t: float
    positions: Tuple[np.ndarray, ...]
    fairlead_forces: np.ndarray
    bollard_forces: np.ndarray
    max_strains: np.ndarray
    payload_positions: Tuple[Optional[np.ndarray], ...]
    parted: np.ndarray
    fairlead_peaks: np.ndarray

    @property
    def fairlead_tensions(self) -> np.ndarray:
        """Return |fairlead force| of each line (L,) [N]."""
        return np.linalg.norm(self.fairlead_forces, axis=1)

    @property
    def bollard_tensions(self) -> np.ndarray:
        """Return |bollard force| of each line (L,) [N]."""
        return np.linalg.norm(self.bollard_forces, axis=1)


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
    """

    steps: int
    lag: float
    restarted: Dict[int, str] = field(default_factory=dict)
    beyond_reach: Dict[int, float] = field(default_factory=dict)


class Mooring:
    """
    Every line of an arrangement, stepped together (see the module docstring).

    :ivar sims: one Simulator per line, in the arrangement's order: each line's rules.
    :ivar system: the shared System (None before start).
    :ivar time: the state time [s] (NaN before start).
    """

    def __init__(self, arrangement: ArrangementParams, materials: Any = None,
                 output_interval: float = 0.0, history: float = 5.0):
        """
        Build every line (see Simulator); the ropes are placed by start().

        :param arrangement: validated parameters.
        :param materials: material presets (default: config/materials.yaml).
        :param output_interval: if > 0, the step divides it (outputs fall on step times).
        :param history: seconds of samples each line keeps behind the newest.
        :raises ParameterError / MaterialError / ValueError: a line cannot be built; the
            message names it.
        """
        self.arrangement = arrangement
        self._materials = materials or load_materials()
        self._output_interval = output_interval
        self._history = history
        self.sims = [self._simulator(line, line.params) for line in arrangement.lines]
        # each line's own step, before _choose_time_step gives them all the smallest
        self._own_steps = [sim.time_step for sim in self.sims]
        self.system: Optional[System] = None
        self.time = math.nan
        # ship samples (t, position, unit quaternion): the newest at or before an output
        # gives its orientation (as LineDriver.lever does for the levers)
        self._ship: deque = deque()
        self._bounds: List[tuple] = [(None, math.nan, math.nan)] * len(self.sims)
        self._choose_time_step()

    # -- lines ----------------------------------------------------------------------------

    @property
    def names(self) -> List[str]:
        """Return the line names, in order."""
        return self.arrangement.names

    @property
    def started(self) -> bool:
        """Tell whether the ropes have been placed (by the first ship pose)."""
        return self.system is not None

    def _simulator(self, line: LineSetup, params) -> Simulator:
        try:
            return Simulator(params, self._materials, output_interval=self._output_interval,
                             history=self._history)
        except ValueError as e:  # ParameterError, MaterialError, an unstable line
            raise type(e)(f'line {line.name!r}: {e}') from None

    def _choose_time_step(self) -> None:
        """Take the smallest of the lines' steps (each divides the output interval) for all."""
        self.time_step = min(self._own_steps)
        for sim in self.sims:  # its step division then judges the step it takes
            sim.time_step = self.time_step
        self._implicit_bending = any(implicit_bending(sim.props, self.time_step)
                                     for sim in self.sims)

    @property
    def offsets(self) -> np.ndarray:
        """Return every fairlead in the ship's body frame (L, 3) [m]."""
        return np.array([sim.params.fairlead_offset for sim in self.sims], dtype=float)

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
        points = [pose_point(position, q, sim.params.fairlead_offset).point
                  for sim in self.sims]
        if self._ship and t <= self._ship[-1][0]:
            raise TrajectoryError(f'ship pose at t={t:.6f} s is not after the newest one '
                                  f'({self._ship[-1][0]:.6f} s)')
        self._ship.append((t, np.array(position, dtype=float), q))
        self.forget_ship()
        teleported = []
        for k, (sim, point) in enumerate(zip(self.sims, points)):
            if sim.push_fairlead(t, point) == 'teleport' and self.started:
                self._load_line(k)
                teleported.append(k)
        return teleported

    def push_bollard(self, k: int, t: float, point) -> str:
        """
        Take a bollard sample of line k; return 'teleport' if it restarted the line.

        :raises TrajectoryError: non-finite, or not after that bollard's newest sample.
        """
        event = self.sims[k].push_bollard(t, point)
        if event == 'teleport' and self.started:
            self._load_line(k)
        return event

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
        self.time = t
        return lengths

    def _resolve_pretensions(self, t: float) -> Dict[int, float]:
        """Give every pretensioned line the length that starts it at its pretension."""
        lengths = {}
        for k, line in enumerate(self.arrangement.lines):
            if line.pretension <= 0.0:
                continue
            sim = self.sims[k]
            try:
                length = length_for_tension(sim.props, *self._free_ends(sim, t),
                                            line.pretension)
                params = line.params.with_values({'length': length})
            except ParameterError as e:
                raise ParameterError(f'line {line.name!r}: {e}') from None
            new = self._simulator(line, params)
            new.fairlead, new.bollard = sim.fairlead, sim.bollard  # the samples so far
            self.sims[k] = new
            self._own_steps[k] = new.time_step
            self.arrangement = self.arrangement.with_line(line.name, params)
            lengths[k] = length
        if lengths:
            self._choose_time_step()
        return lengths

    @staticmethod
    def _free_ends(sim: Simulator, t: float) -> tuple:
        """Return a line's bollard and fairlead at t as their samples put them (not held)."""
        times = np.array([t])
        fairlead = sim.fairlead.sample(times)[0][0]
        if len(sim.bollard):
            return sim.bollard.sample(times)[0][0], fairlead
        return np.asarray(sim.params.bollard_position, dtype=float), fairlead

    def _build(self) -> None:
        """Make the shared System from every Simulator's rope, then view each rope in it."""
        system = System(self.sims[0].props.environment)
        for k, sim in enumerate(self.sims):
            for point in sim.system.points:
                system.add_point(Point(point.kind, point.position.copy(), point.mass,
                                       point.velocity.copy(), point.volume, point.drag_area,
                                       point.added_mass))
            rope = sim.rope
            system.add_line(Line(rope.line_type, rope.rest.copy(), rope.x.copy(),
                                 (2 * k, 2 * k + 1)))
            system.lines[k].v[:] = rope.v
        system.pack()
        self.system = system
        self._starts = np.array([0] + [len(line.x) for line in system.lines]).cumsum()
        for k, sim in enumerate(self.sims):
            sim.rope.x, sim.rope.v = system.lines[k].x, system.lines[k].v

    def _load_line(self, k: int) -> None:
        """Copy line k's Simulator's new rope (a restart) into the shared System; view it."""
        sim, system = self.sims[k], self.system
        line = system.lines[k]
        line.x[:] = sim.rope.x
        line.v[:] = sim.rope.v
        system.point_x[2 * k:2 * k + 2] = sim.system.point_x
        system.point_v[2 * k:2 * k + 2] = sim.system.point_v
        line.line_type = sim.rope.line_type
        system.refresh()  # the state changed other than by a step
        sim.rope.x, sim.rope.v = line.x, line.v

    def restart(self, t: Optional[float] = None) -> None:
        """Put every rope back at rest between its ends (at the state time, or t)."""
        t = self.time if t is None else t
        for k in range(len(self.sims)):
            self._restart_line(k, t)
        self.time = t

    def _restart_line(self, k: int, t: float) -> None:
        self.sims[k].restart(t)
        self._load_line(k)

    # -- time -----------------------------------------------------------------------------

    def advance_to(self, t: float, max_steps: Optional[int] = None) -> MooringAdvance:
        """
        Advance every rope in fixed substeps up to t (at most max_steps of them).

        Each line follows Simulator.advance_to's rules: held at its reach while its ends are
        farther apart, restarted at rest once they are back within it, and restarted when
        its state turns non-finite or past its tension_bound.
        """
        dt = self.time_step
        steps = max(0, int(math.floor((t - self.time) / dt + 1e-9)))
        if max_steps is not None:
            steps = min(steps, max_steps)
        if steps == 0:
            return MooringAdvance(0, t - self.time)
        times = self.time + dt * np.arange(1, steps + 1)
        drive_x, drive_v, distances = self._drive(times)
        reach = np.array([sim.reach for sim in self.sims])
        beyond = distances > reach
        beyond_reach = {k: float(distances[beyond[:, k], k].max())
                        for k in np.flatnonzero(beyond.any(axis=0))}
        held = np.array([sim._held for sim in self.sims])
        back = ~beyond & np.vstack([held, beyond[:-1]])
        if back.any():
            # a line back within reach restarts at rest at that step (its state there is the
            # restart's, whatever the step did): step every line to it, then go on
            j = int(np.flatnonzero(back.any(axis=1))[0])
            restarted = self._step(times[:j + 1], drive_x[:j + 1], drive_v[:j + 1])
            for k in np.flatnonzero(back[j]):
                self._restart_line(int(k), float(times[j]))
                restarted[int(k)] = 'back within reach'
            for k in np.flatnonzero(~back[j]):
                self.sims[k]._held = bool(beyond[j, k])
            rest = self.advance_to(t, None if max_steps is None else max_steps - j - 1)
            for k, distance in rest.beyond_reach.items():
                beyond_reach[k] = max(beyond_reach.get(k, 0.0), distance)
            return MooringAdvance(steps, rest.lag, {**restarted, **rest.restarted},
                                  beyond_reach)
        for k, sim in enumerate(self.sims):
            sim._held = bool(beyond[-1, k])
        restarted = self._step(times, drive_x, drive_v)
        return MooringAdvance(steps, t - self.time, restarted, beyond_reach)

    def _drive(self, times: np.ndarray) -> tuple:
        """Return the driven points at `times` (n, Q, 3) twice and the end distances (n, L)."""
        n, count = len(times), len(self.sims)
        drive_x = np.empty((n, 2 * count, 3))
        drive_v = np.empty((n, 2 * count, 3))
        distances = np.empty((n, count))
        for k, sim in enumerate(self.sims):
            ends, velocities, distances[:, k] = sim._ends(times)
            drive_x[:, 2 * k:2 * k + 2] = ends
            drive_v[:, 2 * k:2 * k + 2] = velocities
        return drive_x, drive_v, distances

    def _step(self, times: np.ndarray, drive_x: np.ndarray,
              drive_v: np.ndarray) -> Dict[int, str]:
        """
        Take the steps to `times` (as Simulator._step), then check every line's state.

        :returns: {line index: why} of the lines restarted by the check.
        """
        for k, sim in enumerate(self.sims):  # ends brought back onto their tracks (views)
            sim._blend_ends(times, drive_x[:, 2 * k:2 * k + 2], drive_v[:, 2 * k:2 * k + 2])
        parts = max(sim._divisions(drive_v[:, 2 * k:2 * k + 2])
                    for k, sim in enumerate(self.sims))
        if parts == 1:
            self._run(self.time_step, drive_x, drive_v)
            self._set_time(float(times[-1]))
        else:
            for t in times:  # a violent stretch somewhere: look again before every step
                start = self.time
                parts = max(sim._divisions(drive_v[:, 2 * k:2 * k + 2])
                            for k, sim in enumerate(self.sims))
                fine = start + (t - start) * np.arange(1, parts + 1) / parts
                fine_x, fine_v, _ = self._drive(fine)
                for k, sim in enumerate(self.sims):
                    sim._blend_ends(fine, fine_x[:, 2 * k:2 * k + 2], fine_v[:, 2 * k:2 * k + 2])
                self._run((t - start) / len(fine), fine_x, fine_v)
                self._set_time(float(t))
        speeds = ROOT3 * np.abs(drive_v).max(axis=(0, 2)).reshape(-1, 2).max(axis=1)
        return self._check(speeds)

    def _run(self, dt: float, drive_x: np.ndarray, drive_v: np.ndarray) -> None:
        """Take len(drive_x) substeps of dt of every line: one kernel call."""
        self.system.step(self.sims[0].params.integrator, dt, drive_x, drive_v,
                         MAX_ITERATIONS, self._implicit_bending)

    def _set_time(self, t: float) -> None:
        self.time = t
        for sim in self.sims:
            sim.time = t

    def _check(self, end_speeds: np.ndarray) -> Dict[int, str]:
        """
        Restart every line whose state is not finite or past its tension_bound.

        Simulator._unphysical's rule, for all lines from one computation of the loads.

        :param end_speeds: each line's largest end speed over the steps just taken [m/s].
        :returns: {line index: why} of the lines restarted.
        """
        system = self.system
        rows = np.isfinite(system.x).all(axis=1) & np.isfinite(system.v).all(axis=1)
        finite = np.logical_and.reduceat(rows, self._starts[:-1])
        finite &= (np.isfinite(system.point_x).all(axis=1)
                   & np.isfinite(system.point_v).all(axis=1)).reshape(-1, 2).all(axis=1)
        faults = {int(k): 'non-finite state' for k in np.flatnonzero(~finite)}
        for k in faults:  # first, so that the loads of the others can be computed
            self._restart_line(k, self.time)
        forces, strains = system.loads()
        ea = np.array([sim.props.axial_stiffness for sim in self.sims])
        largest = np.maximum(np.linalg.norm(forces, axis=2).max(axis=1), ea * strains)
        for k in np.flatnonzero(~(largest <= self._bound(end_speeds))):  # also NaN
            faults[int(k)] = 'unphysical state'
            self._restart_line(int(k), self.time)
        return faults

    def _bound(self, end_speeds: np.ndarray) -> np.ndarray:
        """Return each line's tension_bound at its end speed (it is linear in the speed)."""
        bounds = np.empty(len(self.sims))
        for k, sim in enumerate(self.sims):
            props, at_rest, per_speed = self._bounds[k]
            if props is not sim.props:
                at_rest = tension_bound(sim.props)
                per_speed = tension_bound(sim.props, 1.0) - at_rest
                self._bounds[k] = (sim.props, at_rest, per_speed)
            bounds[k] = at_rest + per_speed * end_speeds[k]
        return bounds

    def skip_to(self, t: float) -> None:
        """Move the state time to t without simulating (see Simulator.skip_to)."""
        for sim in self.sims:
            sim.skip_to(t)
        self.time = t

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
        sim.update(values)
        self._own_steps[k] = sim.time_step
        self.arrangement = self.arrangement.with_line(self.names[k], sim.params)
        if self.started:
            self.system.lines[k].line_type = sim.props.line_type
            self.system.refresh()
            if tuple(self.system.environment.current) != sim.props.current:
                self.system.set_current(sim.props.current)
        self._choose_time_step()

    def set_output_interval(self, interval: float) -> None:
        """Choose the step again so that it divides a new output interval [s]."""
        self._output_interval = interval
        for k, sim in enumerate(self.sims):
            sim.set_output_interval(interval)
            self._own_steps[k] = sim.time_step
        self._choose_time_step()

    # -- outputs --------------------------------------------------------------------------

    def output(self) -> MooringOutput:
        """Return the current state of every line: particles, end forces, strains."""
        forces, strains = self.system.loads()
        payloads = tuple(self.system.point_x[2 * k].copy() if sim.payload else None
                         for k, sim in enumerate(self.sims))
        return MooringOutput(
            self.time, tuple(line.x.copy() for line in self.system.lines), forces[:, 1],
            forces[:, 0], strains, payloads, np.zeros(len(self.sims), dtype=bool),
            np.linalg.norm(forces[:, 1], axis=1))
