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
A moored ship at rest: the static load on it at a pose, its equilibrium, its stiffness.

Quasi-static: nothing moves, and each part of the load is what the dynamic model puts on a
ship at rest at that pose.

- Each line is the elastic catenary in air between its bollard and its fairlead
  (catenary.solve_catenary: its weight less the air's buoyancy, as length_for_tension takes
  it; its strain-tension curve if it has one). It hangs free: it touches neither the water
  nor the quay nor the seabed. A line without weight is a straight elastic bar (slack: no
  force). A line whose ends are farther apart than its reach, L (1 + strain limit), pulls
  its fairlead toward its bollard with its limit tension (EA max_strain on a linear line),
  as the dynamic model holds such a line at its strain limit.
- The ship's own loads, hydrostatics and fenders, are forces/body.py's body_loads of the
  body at rest at the pose (zero velocities): the one rule of the dynamic ship. So the
  fenders push along their normals only: their friction (fender.py) opposes sliding, and a
  ship at rest does not slide.
- An external load: a constant force and moment about the body origin in world axes, plus,
  optionally, a function of the pose (wind and current turn with the ship).

Conventions (REP-103): a pose is the body origin's position (x, y, z) in the world frame
(frame_id) and the body's orientation, as a unit quaternion (x, y, z, w) or as roll, pitch,
yaw (Z-Y-X: R = Rz(yaw) Ry(pitch) Rx(roll)). Every load is a force and a moment about the
body origin, both in world axes: [F_x, F_y, F_z, M_x, M_y, M_z]. A displacement is the body
origin's translation and a small rotation about the world axes through it; the stiffness is
K = -dF/dx over those six, rows and columns x, y, z, roll, pitch, yaw (N/m, N/rad, N m/m,
N m/rad): MoorPy's body stiffness (Body.getStiffnessA) about the same reference point.

Only numpy and the model's own modules.
"""

from collections.abc import Callable
from dataclasses import dataclass
import math
from typing import Optional, Sequence, Tuple, Union

import numpy as np

from .catenary import CatenaryError, solve_catenary
from ..body import Body, Fender
from ..forces.body import body_loads
from ..forces.fender import fender_force
from ..frames import rotation_matrix
from ..layout import (BODY_CLOCK, BODY_LOAD, BODY_LOAD_RATE, BODY_OMEGA, BODY_POSITION,
                      BODY_QUATERNION, BODY_RESTORING, BODY_VELOCITY, FENDER_BODY,
                      FENDER_COLUMNS)
from ..objects import Environment
from ..rope import RopeProperties

# The central-difference steps of the stiffness: the body origin moves TRANSLATION_STEP [m],
# and turns by the angle that moves its farthest point (a fairlead or a hull corner) as far.
# The catenary is solved to 1e-12 of the line's length, so a line's force is exact to about
# EA 1e-12 (1e-4 N on a 1e8 N line): over 2 mm that is < 0.1 N/m, 1e-6 of a mooring line's
# stiffness. The truncation error is (h / l)^2 / 6 of a term, l the distance over which a
# line's stiffness changes (its stretch or its sag: centimetres at the least): < 1e-3 at
# 1 mm (measured: the stiffness of test_ship_statics.py's lines agrees with MoorPy's analytic
# one within 1.1e-5 at steps of 1e-5 to 1e-3 m, 3e-5 at 1e-2 m, 9e-2 at 0.1 m). Hydrostatics
# are linear, and the fenders' curves piecewise linear: their terms are exact but where a
# step crosses a point of a curve (or a fender's first touch): the mean of the two slopes.
TRANSLATION_STEP = 1.0e-3
# Newton stops when the force left is below TOLERANCE times the loads' scale (the sum of
# the line tensions, fender reactions and external force), the moment below it times that
# scale times the ship's size.
TOLERANCE = 1.0e-9
MAX_ITERATIONS = 100
# No point of the ship moves more than this in one Newton step [m] (MoorPy's limits are 30 m
# and 0.02 rad): a step taken on the stiffness of slack lines, or of a fender not yet
# touched, does not throw the ship far past where lines and fenders take hold.
MAX_STEP = 2.0
MAX_HALVINGS = 30


class StaticsError(ValueError):
    """No static solution: bad inputs, or an equilibrium that was not found (says why)."""


# ------------------------------------------------------------------------------ poses


def quaternion_from_rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Return the unit quaternion (x, y, z, w) of Z-Y-X roll, pitch, yaw [rad]."""
    cr, sr = math.cos(0.5 * roll), math.sin(0.5 * roll)
    cp, sp = math.cos(0.5 * pitch), math.sin(0.5 * pitch)
    cy, sy = math.cos(0.5 * yaw), math.sin(0.5 * yaw)
    return np.array([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy])


def rpy_from_quaternion(q: Sequence[float]) -> np.ndarray:
    """Return roll, pitch, yaw [rad] (Z-Y-X) of a unit quaternion (x, y, z, w)."""
    x, y, z, w = (float(c) for c in q)
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(min(max(2.0 * (w * y - z * x), -1.0), 1.0))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return np.array([roll, pitch, yaw])


def turned(q: Sequence[float], rotation: Sequence[float]) -> np.ndarray:
    """Return q turned by a rotation vector (world axes) [rad]: exp(rotation) * q."""
    r = np.asarray(rotation, dtype=float)
    angle = float(np.linalg.norm(r))
    if angle == 0.0:
        return np.array(q, dtype=float)
    a = np.append(math.sin(0.5 * angle) / angle * r, math.cos(0.5 * angle))
    b = np.asarray(q, dtype=float)
    c = np.array([a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
                  a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
                  a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
                  a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]])
    return c / np.linalg.norm(c)


@dataclass(frozen=True, eq=False)
class Pose:
    """
    Where the ship is: its body origin and its orientation.

    :ivar position: the body origin in the world frame [m], (3,).
    :ivar quaternion: unit quaternion (x, y, z, w), body to world, (4,).
    """

    position: np.ndarray
    quaternion: np.ndarray

    @classmethod
    def of(cls, pose: Union['Pose', Sequence[float]]) -> 'Pose':
        """
        Return a Pose from a Pose or x, y, z, roll, pitch, yaw [m, rad].

        :raises StaticsError: not six finite numbers.
        """
        if isinstance(pose, Pose):
            return pose
        try:
            values = np.array(pose, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            values = np.array([])
        if values.shape != (6,) or not np.all(np.isfinite(values)):
            raise StaticsError(f'pose {pose!r} must be x, y, z [m], roll, pitch, yaw [rad]: '
                               'six finite numbers')
        return cls(values[:3].copy(), quaternion_from_rpy(*values[3:]))

    @property
    def rotation(self) -> np.ndarray:
        """Return the rotation matrix, body to world (3, 3)."""
        return rotation_matrix(self.quaternion)

    @property
    def vector(self) -> np.ndarray:
        """Return x, y, z [m], roll, pitch, yaw [rad] (6,)."""
        return np.concatenate([self.position, rpy_from_quaternion(self.quaternion)])

    def moved(self, displacement: Sequence[float]) -> 'Pose':
        """Return the pose moved by a displacement (translation, rotation vector in world axes)."""
        d = np.asarray(displacement, dtype=float)
        return Pose(self.position + d[:3], turned(self.quaternion, d[3:]))

    def offset_from(self, other: 'Pose') -> np.ndarray:
        """Return x, y, z, roll, pitch, yaw of this pose less another's (angles in (-pi, pi])."""
        d = self.vector - other.vector
        d[3:] = (d[3:] + math.pi) % (2.0 * math.pi) - math.pi
        return d


# ------------------------------------------------------------------------------ the lines


@dataclass(frozen=True, eq=False)
class StaticLine:
    """
    One line as the statics see it.

    :ivar props: its properties at the unstretched length it has (props.length).
    :ivar environment: what it hangs in (gravity, the air's buoyancy).
    :ivar bollard: its bollard in the world frame [m], (3,).
    :ivar fairlead: its fairlead in the ship's body frame, from the body origin [m], (3,).
    :ivar name: its name (for messages).
    """

    props: RopeProperties
    environment: Environment
    bollard: np.ndarray
    fairlead: np.ndarray
    name: str = ''

    def __post_init__(self):
        """Check the points (StaticsError naming the line)."""
        for name in ('bollard', 'fairlead'):
            value = np.array(getattr(self, name), dtype=float).reshape(-1)
            if value.shape != (3,) or not np.all(np.isfinite(value)):
                raise StaticsError(f'line {self.name!r}: {name} {getattr(self, name)!r} must '
                                   'be three finite numbers [m]')
            object.__setattr__(self, name, value)

    def force(self, fairlead: np.ndarray) -> Tuple[np.ndarray, float, float, bool]:
        """
        Return the line's pull on its fairlead at a world point (see the module docstring).

        :returns: (force on the fairlead, world axes [N] (3,), fairlead tension [N], bollard
            tension [N], whether the ends are beyond the line's reach).
        :raises StaticsError: the catenary did not converge (names the line).
        """
        props = self.props
        chord = fairlead - self.bollard
        distance = float(np.linalg.norm(chord))
        if distance > props.reach:
            tension = props.limit_tension
            return -tension * chord / distance, tension, tension, True
        gravity = np.asarray(self.environment.gravity, dtype=float)
        g = float(np.linalg.norm(gravity))
        w = props.weight_per_length(self.environment)
        if not (w > 0.0 and g > 0.0):  # a straight elastic bar
            strain = distance / props.length - 1.0
            if strain <= 0.0 or distance == 0.0:
                return np.zeros(3), 0.0, 0.0, False
            tension = (props.axial_stiffness * strain if props.curve is None
                       else float(props.curve.tension(strain)))
            return -tension * chord / distance, tension, tension, False
        up = -gravity / g
        rise = float(chord @ up)
        horizontal = chord - rise * up
        span = float(np.linalg.norm(horizontal))
        direction = horizontal / span if span > 0.0 else np.zeros(3)
        try:
            solution = solve_catenary(span, rise, props.length, w, props.axial_stiffness,
                                      props.curve)
        except CatenaryError as e:
            raise StaticsError(f'line {self.name!r}: no catenary between its bollard and its '
                               f'fairlead {fairlead.round(3).tolist()}: {e}') from None
        force = -solution.horizontal_tension * direction - solution.vertical_b * up
        return force, solution.tension_b, solution.tension_a, False


# ------------------------------------------------------------------------------ the loads


@dataclass(frozen=True, eq=False)
class StaticLoads:
    """
    The static load on the ship at a pose: force and moment about the body origin, world axes.

    :ivar pose: where.
    :ivar total: every load below summed (6,) [N, N m].
    :ivar lines: the lines' (6,).
    :ivar body: the body's own, body_loads': hydrostatics (if counted) and fenders (6,).
    :ivar external: the external load (6,).
    :ivar fairlead_forces: each line's force on its fairlead, world axes (L, 3) [N].
    :ivar fairlead_tensions, bollard_tensions: each line's tension at its ends (L,) [N].
    :ivar beyond_reach: each line's ends farther apart than its reach (L,).
    :ivar fender_compressions: each fender's compression (F,) [m] (0: no contact).
    :ivar fender_reactions: each fender's reaction along its normal (F,) [N].
    :ivar fender_points: each fender's contact point in the world (F, 3) [m] (NaN: none).
    """

    pose: Pose
    total: np.ndarray
    lines: np.ndarray
    body: np.ndarray
    external: np.ndarray
    fairlead_forces: np.ndarray
    fairlead_tensions: np.ndarray
    bollard_tensions: np.ndarray
    beyond_reach: np.ndarray
    fender_compressions: np.ndarray
    fender_reactions: np.ndarray
    fender_points: np.ndarray


@dataclass(frozen=True, eq=False)
class Equilibrium:
    """
    The ship at rest under its loads.

    :ivar pose: where the loads balance.
    :ivar offset: that pose less the start's: x, y, z [m], roll, pitch, yaw [rad] (6,).
    :ivar loads: the loads there (tensions, fender compressions and reactions; total is the
        residual).
    :ivar iterations: Newton steps taken.
    """

    pose: Pose
    offset: np.ndarray
    loads: StaticLoads
    iterations: int


# A load that depends on the pose: f(position (3,), rotation (3, 3) body to world) -> (6,),
# force and moment about the body origin in world axes. A load given in body axes, F_b and
# M_b, is [R F_b, R M_b] in world axes.
LoadFunction = Callable[[np.ndarray, np.ndarray], Sequence[float]]


def _fender_rows(fenders) -> np.ndarray:
    """Return fenders (rows (F, FENDER_COLUMNS) or Fender objects) as rows touching body 0."""
    if fenders is None:
        return np.zeros((0, FENDER_COLUMNS))
    if not isinstance(fenders, np.ndarray):
        fenders = [f.row() if isinstance(f, Fender) else np.asarray(f, dtype=float)
                   for f in fenders]
    rows = np.array(fenders, dtype=float).reshape(-1, FENDER_COLUMNS)
    rows[:, FENDER_BODY] = 0.0  # every fender given touches this ship
    return rows


class ShipStatics:
    """
    A ship held by its lines and fenders, under an external load: loads, equilibrium, stiffness.

    :ivar lines: the StaticLines.
    :ivar body: the Body (its numbers; its pose is the start pose of equilibrium()).
    :ivar fenders: the fenders' rows of the FENDER table (F, FENDER_COLUMNS).
    :ivar external_load: force and moment about the body origin, world axes (6,).
    :ivar load_function: a load that depends on the pose (LoadFunction), or None.
    """

    def __init__(self, lines: Sequence[StaticLine], body: Body, fenders=None,
                 external_load: Optional[Sequence[float]] = None,
                 load_function: Optional[LoadFunction] = None):
        """
        Take the parts.

        :param fenders: rows of the FENDER table (F, FENDER_COLUMNS) or Fender objects; each
            touches this ship whatever its FENDER_BODY.
        :raises StaticsError: an external load that is not six finite numbers.
        """
        self.lines = list(lines)
        self.body = body
        self.fenders = _fender_rows(fenders)
        load = np.zeros(6) if external_load is None else np.array(external_load, dtype=float)
        if load.shape != (6,) or not np.all(np.isfinite(load)):
            raise StaticsError(f'external load {external_load!r} must be six finite numbers: '
                               'force [N] and moment [N m] about the body origin, world axes')
        self.external_load = load
        self.load_function = load_function
        self._row = body.row()
        self._row[BODY_VELOCITY:BODY_VELOCITY + 3] = 0.0
        self._row[BODY_OMEGA:BODY_OMEGA + 3] = 0.0
        self._row[BODY_LOAD:BODY_LOAD + 6] = 0.0
        self._row[BODY_LOAD_RATE:BODY_LOAD_RATE + 6] = 0.0
        self._row[BODY_CLOCK] = 0.0
        self._dry_row = self._row.copy()
        self._dry_row[BODY_RESTORING:BODY_RESTORING + 3] = 0.0
        # the body origin to the centre of gravity, body axes
        self._gravity_centre = -np.asarray(body.origin, dtype=float)
        # the farthest a point of the ship (fairlead, hull corner) lies from its origin [m]
        half = 0.5 * np.asarray(body.hull, dtype=float)
        levers = [float(np.linalg.norm(line.fairlead)) for line in self.lines]
        self.size = max(levers + [float(np.linalg.norm(half)), 1.0])

    @property
    def start(self) -> Pose:
        """Return the body's own pose (its origin's): where equilibrium() starts."""
        position, quaternion = self.body.origin_pose()
        return Pose(position, quaternion)

    # -- the load at a pose ------------------------------------------------------------------

    def loads(self, pose=None, hydrostatics: bool = True, external: bool = True,
              fenders: bool = True) -> StaticLoads:
        """
        Return the static load on the ship at a pose (the start pose by default).

        :param pose: a Pose, or x, y, z, roll, pitch, yaw [m, rad].
        :param hydrostatics, external, fenders: count those loads.
        :raises StaticsError: a bad pose, a line's catenary not found, a non-finite load.
        """
        pose = self.start if pose is None else Pose.of(pose)
        rotation = pose.rotation
        count = len(self.lines)
        forces = np.zeros((count, 3))
        tensions = np.zeros((count, 2))
        beyond = np.zeros(count, dtype=bool)
        lines = np.zeros(6)
        for k, line in enumerate(self.lines):
            lever = rotation @ line.fairlead
            force, t_fairlead, t_bollard, beyond[k] = line.force(pose.position + lever)
            forces[k] = force
            tensions[k] = t_fairlead, t_bollard
            lines[:3] += force
            lines[3:] += np.cross(lever, force)
        body, compressions, reactions, points = self._body_loads(pose, rotation, hydrostatics,
                                                                 fenders)
        outside = np.zeros(6)
        if external:
            outside += self.external_load
            if self.load_function is not None:
                outside += np.asarray(self.load_function(pose.position.copy(), rotation),
                                      dtype=float).reshape(6)
        total = lines + body + outside
        if not np.all(np.isfinite(total)):
            raise StaticsError(f'the load on the ship at pose {pose.vector.round(6).tolist()} '
                               f'is not finite: lines {lines.tolist()}, body {body.tolist()}, '
                               f'external {outside.tolist()}')
        return StaticLoads(pose, total, lines, body, outside, forces, tensions[:, 0],
                           tensions[:, 1], beyond, compressions, reactions, points)

    def _body_loads(self, pose: Pose, rotation: np.ndarray, hydrostatics: bool,
                    fenders: bool) -> tuple:
        """Return body_loads at rest about the origin (6,), and each fender's state."""
        row = (self._row if hydrostatics else self._dry_row).copy()
        centre = rotation @ self._gravity_centre
        row[BODY_POSITION:BODY_POSITION + 3] = pose.position + centre
        row[BODY_QUATERNION:BODY_QUATERNION + 4] = pose.quaternion
        table = self.fenders if fenders else self.fenders[:0]
        load = np.zeros(6)
        unused = np.zeros((6, 6))
        body_loads(row, 0, table, rotation, 0.0, 0.0, load, False, unused, unused.copy())
        load[3:] += np.cross(centre, load[:3])  # about the origin, not the centre of gravity
        count = len(table)
        compressions = np.zeros(count)
        reactions = np.zeros(count)
        points = np.full((count, 3), np.nan)
        rest = np.zeros(3)
        force = np.zeros(3)
        for f in range(count):
            point = np.zeros(3)
            compression, push, _, _ = fender_force(table[f], row, rotation, rest, rest, force,
                                                   point)
            if compression > 0.0:
                compressions[f], reactions[f], points[f] = compression, push, point
        return load, compressions, reactions, points

    # -- stiffness --------------------------------------------------------------------------

    def stiffness(self, pose=None, hydrostatics: bool = False, external: bool = False,
                  fenders: bool = True) -> np.ndarray:
        """
        Return the 6x6 stiffness K = -dF/dx about the body origin, world axes, at a pose.

        Rows and columns x, y, z, roll, pitch, yaw: F the force and moment about the body
        origin, x its translation and a small rotation about the world axes through it
        (N/m, N/rad, N m/m, N m/rad). Central differences (TRANSLATION_STEP says why they
        are exact to better than 1e-3 of a term; within 1.1e-5 of MoorPy's analytic
        getStiffnessA on the lines of test_ship_statics.py).

        What is in it: the lines (each catenary's stiffness and the turning of its pull's
        lever: the geometric terms MoorPy's getStiffnessA has) and the fenders in contact
        (their curves' slopes at the contact points); with hydrostatics, the heave, roll and
        pitch restoring too (rho g A_wp, m g GM_T, m g GM_L); with external, the change of
        load_function with the pose. Not in it: the lines' and fenders' damping, and the
        fenders' friction (a ship at rest does not slide).

        The lines' part is symmetric but for the turning of their moment M about the origin:
        K - K^T = [M]x in the rotation block (a pull f at lever r gives -[f]x [r]x there), so
        it is symmetric where M is zero; hydrostatics and fenders add a symmetric part but at
        large angles or where a fender's contact slides along the hull.

        :param pose: a Pose, or x, y, z, roll, pitch, yaw (the start pose by default).
        """
        pose = self.start if pose is None else Pose.of(pose)
        return self._jacobian(pose, hydrostatics, external, fenders)

    def _jacobian(self, pose: Pose, hydrostatics: bool = True, external: bool = True,
                  fenders: bool = True) -> np.ndarray:
        """Return -dF/dx by central differences (see stiffness)."""
        steps = np.array([TRANSLATION_STEP] * 3 + [TRANSLATION_STEP / self.size] * 3)
        matrix = np.empty((6, 6))
        for j in range(6):
            d = np.zeros(6)
            d[j] = steps[j]
            ahead = self.loads(pose.moved(d), hydrostatics, external, fenders).total
            behind = self.loads(pose.moved(-d), hydrostatics, external, fenders).total
            matrix[:, j] = -(ahead - behind) / (2.0 * steps[j])
        return matrix

    # -- equilibrium ------------------------------------------------------------------------

    def _scales(self, loads: StaticLoads) -> Tuple[float, float]:
        """Return the force [N] and moment [N m] the residual is measured against."""
        force = (float(np.abs(loads.fairlead_tensions).sum() + loads.fender_reactions.sum())
                 + float(np.linalg.norm(loads.external[:3])))
        force = max(force, float(np.linalg.norm(loads.external[3:])) / self.size, 1.0)
        return force, force * self.size

    def _merit(self, loads: StaticLoads, scales: Tuple[float, float]) -> float:
        """Return the residual's size: force and moment, each over its scale."""
        return math.hypot(float(np.linalg.norm(loads.total[:3])) / scales[0],
                          float(np.linalg.norm(loads.total[3:])) / scales[1])

    def equilibrium(self, pose=None, tolerance: float = TOLERANCE,
                    max_iterations: int = MAX_ITERATIONS) -> Equilibrium:
        """
        Return the pose where every load on the ship balances (heave, roll, pitch included).

        Newton's method on the six displacements, its Jacobian stiffness()'s central
        differences of the whole load (hydrostatics, the external load's change with the
        pose), damped: no point of the ship moves more than MAX_STEP per step, and a step is
        halved until the residual falls.

        :param pose: where to start (the body's start pose by default).
        :param tolerance: stop where the force left is below tolerance times the loads'
            scale (the sum of the tensions, fender reactions and external force), and the
            moment below it times that scale times the ship's size.
        :raises StaticsError: no equilibrium found: the residual could not be brought down
            (the lines and fenders do not hold the ship against the load in some direction)
            or not within max_iterations; the message gives the residual and the pose.
        """
        start = self.start
        pose = start if pose is None else Pose.of(pose)
        loads = self.loads(pose)
        for iteration in range(max_iterations + 1):
            scales = self._scales(loads)
            merit = self._merit(loads, scales)
            if merit <= tolerance:
                return Equilibrium(pose, pose.offset_from(start), loads, iteration)
            if iteration == max_iterations:
                break
            # Newton's step; where it fails (nothing holds the ship yet in some direction:
            # a fender it has not reached, lines still slack), a step along the load
            found = None
            for step in (self._newton_step(pose, loads.total), self._load_step(loads.total)):
                found = self._search(pose, step, merit, scales)
                if found is not None:
                    break
            if found is None:
                raise StaticsError(self._failure(pose, loads, 'no step along the stiffness '
                                                 'or the load brings it down', iteration))
            pose, loads = found
        raise StaticsError(self._failure(pose, loads, f'{max_iterations} Newton steps did not '
                                         'bring it down', max_iterations))

    def _search(self, pose: Pose, step: np.ndarray, merit: float,
                scales: Tuple[float, float]) -> Optional[Tuple[Pose, StaticLoads]]:
        """Return the first of step, step / 2, ... (within MAX_STEP) that lowers the merit."""
        largest = max(float(np.linalg.norm(step[:3])),
                      float(np.linalg.norm(step[3:])) * self.size)
        if not (largest > 0.0 and math.isfinite(largest)):
            return None
        step = step * min(1.0, MAX_STEP / largest)
        for _ in range(MAX_HALVINGS):
            trial = pose.moved(step)
            try:
                loads = self.loads(trial)
            except StaticsError:  # a line with no catenary there: a shorter step
                loads = None
            if loads is not None and self._merit(loads, scales) < merit:
                return trial, loads
            step = 0.5 * step
        return None

    def _load_step(self, residual: np.ndarray) -> np.ndarray:
        """Return a displacement along the load: MAX_STEP along the force, turning as M."""
        return np.concatenate([residual[:3], residual[3:] / self.size ** 2]) * (
            MAX_STEP / max(math.hypot(float(np.linalg.norm(residual[:3])),
                                      float(np.linalg.norm(residual[3:])) / self.size),
                           1e-300))

    def _newton_step(self, pose: Pose, residual: np.ndarray) -> np.ndarray:
        """Return the displacement that K takes the residual to zero with (least squares)."""
        matrix = self._jacobian(pose)
        # in metres and newtons alike: rotations times the size, moments over it
        scale = np.array([1.0] * 3 + [self.size] * 3)
        scaled = matrix / scale[:, None] / scale[None, :]
        if not np.all(np.isfinite(scaled)):
            raise StaticsError('the stiffness of the ship is not finite at pose '
                               f'{pose.vector.round(6).tolist()}')
        solution = np.linalg.lstsq(scaled, residual / scale, rcond=1e-12)[0]
        return solution / scale

    def _failure(self, pose: Pose, loads: StaticLoads, why: str, iterations: int) -> str:
        force = float(np.linalg.norm(loads.total[:3]))
        moment = float(np.linalg.norm(loads.total[3:]))
        return (f'no equilibrium of the ship found after {iterations} Newton steps: a force '
                f'of {force:.4g} N and a moment of {moment:.4g} N m are left at pose '
                f'{pose.vector.round(4).tolist()} and {why}; do the lines and fenders hold '
                'the ship against this load in every direction?')
