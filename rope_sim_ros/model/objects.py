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
The objects of a mooring system, each owning its state, as MoorDyn has them.

- LineType: what a line is made of (per metre numbers, EA or a strain-tension curve, damping
  model, strain limit).
- Environment: gravity, air, water (level, density, a uniform current), a flat seabed and an
  optional quay block (forces/fluid.py and forces/contact.py say how they act).
- Point: where line ends meet. FIXED (never moves), DRIVEN (its position and velocity are set
  every substep from outside: a fairlead on a ship, a crane tip), FREE (a lumped body with a
  mass, a volume, a drag area and an added-mass coefficient: a payload, a shackle joining
  lines) or CARRIED (a point of a rigid Body: a fairlead on a free ship).
- Body and Fender (body.py): a rigid body in six degrees of freedom and the fenders it rests
  on.
- Winch: how one end of a line pays out or heaves in (winch.py).
- Line: a LineType, N segments with a rest length each (its winch changes them), the N+1
  particles' positions and velocities, the two points its ends sit on, its break load and,
  once it has parted (parting.py), which segment parted.
- System: any number of lines, points, bodies and fenders, stepped together by one
  integrator (stepping/step.py).

A line's end particle coincides with its point: the point sets it, and the line returns to
the point its end force (springs and dampers, plus the weight, buoyancy, drag and contact of
the half segment lumped at the end). A free point's acceleration is (its weight, buoyancy,
drag and contact + the sum of those end forces) over its mass matrix (its mass and added
mass plus the attached half segments' masses and added masses).

The System packs everything into the flat tables of layout.py, once (pack) and again when a
line's rest lengths or a point change (refresh), and hands its state and tables to the kernels
as one record, its arrays (record.SystemArrays), made anew with them. After packing, every
Line's x and v and every Point's position and velocity are views into the System's arrays:
writing them moves the state the kernels step.
"""

from dataclasses import dataclass, replace
from functools import cached_property
import math
import numbers
from typing import List, Sequence, Tuple

import numpy as np

from . import parting, winch
from .body import Body, Fender
from .forces import assembly
from .forces.body import place_points
from .layout import (ADDED_MASS, ADJUST, AXIAL, AXIAL_STIFFNESS, BEND_DAMPING, BEND_REST,
                     BEND_STIFFNESS, BENDING, BODY_COLUMNS, BODY_OMEGA, BODY_POSITION,
                     BODY_QUATERNION, BODY_VELOCITY, CARRIED, DAMPING, DIAMETER, DRAG, DRAG_AREA,
                     DRIVEN, END_A, END_B, ENV_AIR_DENSITY, ENV_COLUMNS, ENV_CURRENT, ENV_GRAVITY,
                     ENV_QUAY_DEPTH, ENV_QUAY_EDGE, ENV_QUAY_NORMAL, ENV_SEABED_DAMPING,
                     ENV_SEABED_FRICTION, ENV_SEABED_LEVEL, ENV_SEABED_STIFFNESS,
                     ENV_WATER_DENSITY, ENV_WATER_LEVEL, FENDER_COLUMNS, FIRST, FIXED, FLUID, FREE,
                     INV_MASS, KIND, LAST, LENGTH, LINE_COLUMNS, LINE_REAL_COLUMNS, MASS,
                     MAX_STRAIN, NORMAL_ADDED_MASS, NORMAL_DRAG, OWN_MASS, PARTICLE_COLUMNS,
                     POINT_BODY, POINT_COLUMNS, POINT_OFFSET, POINT_SINK, REST, SINK, SIZE,
                     STIFFNESS, TANGENTIAL_ADDED_MASS, TANGENTIAL_DRAG, TANGENTS, TENSION,
                     TENSION_BEFORE, TOTAL_MASS, VOLUME, VOLUME_AREA, VOLUME_DIAMETER)
from .layout import (BREAK_LOAD, PARTED, PARTED_STEP, PEAK_A, PEAK_B, SNAP_FLOOR, UNSTRETCHED,
                     WINCH_ACCELERATION, WINCH_BRAKE_LOAD, WINCH_COMMAND, WINCH_END,
                     WINCH_MAX_LENGTH, WINCH_MAX_SPEED, WINCH_MIN_LENGTH, WINCH_MODE,
                     WINCH_RESPONSE, WINCH_SPEED)
from .record import SystemArrays
from .ship.waves import Waves
from .ship.wind import Wind
from .tension_curve import check_curve, TensionCurve

KINDS = {'fixed': FIXED, 'driven': DRIVEN, 'free': FREE, 'carried': CARRIED}
STANDARD_GRAVITY = 9.80665  # [m/s^2]
SMALLEST_SINK = 1e-4  # [m]: the contact damping's ramp depth at least (a buoyant line's)


def _finite(name: str, value, low: float = -math.inf) -> None:
    """Raise ValueError unless value is a finite number >= low."""
    if not (isinstance(value, numbers.Real) and math.isfinite(value) and value >= low):
        allowed = 'a finite number' + (f' >= {low:g}' if low > -math.inf else '')
        raise ValueError(f'{name} {value!r} must be {allowed}')


def _vector(name: str, value) -> tuple:
    """Return value as a tuple of 3 finite floats, or raise ValueError."""
    try:
        vector = tuple(float(c) for c in value)
    except (TypeError, ValueError):
        vector = ()
    if len(vector) != 3 or not all(math.isfinite(c) for c in vector):
        raise ValueError(f'{name} {value!r} must be a list of 3 finite numbers')
    return vector


@dataclass(frozen=True)
class LineType:
    """
    What a line is made of.

    :ivar mass_per_length: [kg/m].
    :ivar axial_stiffness: EA [N]: the structural springs' stiffness where the line has no
        tension_curve; with one, the nominal EA of its bending springs only.
    :ivar axial_damping: BA [N s]: a segment's damping coefficient is BA / its rest length.
    :ivar diameter: nominal diameter d [m]: drag and contact width.
    :ivar mbl: minimum breaking load [N] (the default break load; the snap watch's scale).
    :ivar bending_stiffness_ratio: bending spring stiffness / structural spring stiffness.
    :ivar bending_damping_ratio: bending spring damping / structural spring damping.
    :ivar damping_model: 'axial' (stretch rate only) or 'seed' (K_SD (V_A - V_B)).
    :ivar air_drag_coefficient: K_A per metre [N s^2 / m^3]: f = -K_A |v| v.
    :ivar max_strain: super-elasticity threshold (strain).
    :ivar superelastic_adjustment: apply the strain-limit projection.
    :ivar volume_diameter: volume-equivalent diameter dv [m] (0: the diameter): buoyancy,
        added mass and the width of the water surface's ramp.
    :ivar normal_drag: Cd, on the nominal diameter (MoorDyn's Cd).
    :ivar tangential_drag: CdAx, on the circumference pi d (MoorDyn's CdAx).
    :ivar normal_added_mass: Ca (MoorDyn's Ca), on the volume A_v = pi dv^2 / 4 per metre.
    :ivar tangential_added_mass: CaAx (MoorDyn's CaAx).
    :ivar tension_curve: the load-extension as (strain, tension [N]) pairs, MoorDyn's table
        (tension_curve.py: linear between the points, 0 at a strain <= 0, the last slope past
        the table, where MoorDyn clamps); () for a linear line of EA. Kept starting at (0, 0).
    """

    mass_per_length: float
    axial_stiffness: float
    axial_damping: float
    diameter: float = 0.0
    mbl: float = math.inf
    bending_stiffness_ratio: float = 0.0
    bending_damping_ratio: float = 0.0
    damping_model: str = 'axial'
    air_drag_coefficient: float = 0.0
    max_strain: float = 0.25
    superelastic_adjustment: bool = True
    volume_diameter: float = 0.0
    normal_drag: float = 0.0
    tangential_drag: float = 0.0
    normal_added_mass: float = 0.0
    tangential_added_mass: float = 0.0
    tension_curve: tuple = ()

    def __post_init__(self):
        """Check the fluid's numbers (finite, >= 0) and the curve (tension_curve.py's rules)."""
        for name in ('diameter', 'volume_diameter', 'normal_drag', 'tangential_drag',
                     'normal_added_mass', 'tangential_added_mass'):
            _finite(name, getattr(self, name), 0.0)
        object.__setattr__(self, 'tension_curve', check_curve(self.tension_curve))

    @cached_property
    def curve(self):
        """Return the TensionCurve of the line, None for a linear line."""
        return TensionCurve.from_pairs(self.tension_curve) if self.tension_curve else None

    def stiffest(self, strain: float) -> float:
        """Return the largest tangent dT/dstrain [N] up to `strain`: EA on a linear line."""
        if self.curve is not None:
            return self.curve.stiffest(strain)
        return self.axial_stiffness

    @property
    def displacing_diameter(self) -> float:
        """Return dv: the volume diameter, or the diameter where it is 0 [m]."""
        return self.volume_diameter if self.volume_diameter > 0.0 else self.diameter

    @property
    def wave_speed(self) -> float:
        """Fastest axial wave up to the strain limit, c = sqrt(dT/dstrain / m) [m/s]."""
        return math.sqrt(self.stiffest(self.max_strain) / self.mass_per_length)


@dataclass(frozen=True)
class Environment:
    """
    What a mooring lives in: one per mooring, its lines, points and ship read it.

    Heights are z in the System's frame (REP-103: z up).

    :ivar gravity: gravity vector [m/s^2], (3,).
    :ivar air_density: [kg/m^3]: buoyancy, drag and added mass above the water (the seed's
        isotropic drag takes its K_A directly).
    :ivar water_level: z of the still water surface [m]; -inf: no water.
    :ivar water_density: [kg/m^3].
    :ivar current: uniform velocity of the water [m/s], (3,).
    :ivar seabed_level: z of the flat seabed [m]; -inf: no seabed.
    :ivar seabed_stiffness: MoorDyn's kBot [Pa/m].
    :ivar seabed_damping: MoorDyn's cBot [Pa s/m].
    :ivar seabed_friction: MoorDyn's FrictionCoefficient mu.
    :ivar quay_edge: a point on the top edge of the quay's face [m], (3,); its z is the deck.
    :ivar quay_normal: the face's outward normal, towards the water, (3,) (its horizontal part
        counts); all zero: no quay.
    :ivar quay_depth: how far below the deck the quay block reaches [m].
    :ivar wind: the wind over the water (ship/wind.py's Wind): it pushes the ship, not the
        lines.
    :ivar waves: the waves on the water (ship/waves.py's Waves): they load the ship (its
        hydrodynamic database's loads), not the lines.
    """

    gravity: tuple = (0.0, 0.0, -9.81)
    air_density: float = 1.225
    water_level: float = -math.inf
    water_density: float = 1025.0
    current: tuple = (0.0, 0.0, 0.0)
    seabed_level: float = -math.inf
    seabed_stiffness: float = 3.0e6
    seabed_damping: float = 3.0e5
    seabed_friction: float = 0.0
    quay_edge: tuple = (0.0, 0.0, 0.0)
    quay_normal: tuple = (0.0, 0.0, 0.0)
    quay_depth: float = 1.0e4
    wind: Wind = Wind()
    waves: Waves = Waves()

    def __post_init__(self):
        """Check every number: a one-line error naming the first that is wrong."""
        for name in ('gravity', 'current', 'quay_edge', 'quay_normal'):
            object.__setattr__(self, name, _vector(name, getattr(self, name)))
        for name in ('air_density', 'water_density', 'seabed_stiffness', 'seabed_damping',
                     'seabed_friction', 'quay_depth'):
            _finite(name, getattr(self, name), 0.0)
        if not (isinstance(self.water_level, numbers.Real) and not math.isnan(self.water_level)):
            raise ValueError(f'water_level {self.water_level!r} must be a number '
                             '(-inf: no water)')
        if not (isinstance(self.seabed_level, numbers.Real)
                and (math.isfinite(self.seabed_level) or self.seabed_level == -math.inf)):
            raise ValueError(f'seabed_level {self.seabed_level!r} must be a finite number '
                             '(-inf: no seabed)')
        nx, ny, nz = self.quay_normal
        if nz != 0.0 and nx == 0.0 and ny == 0.0:
            raise ValueError(f'quay_normal {self.quay_normal!r} must have a horizontal part '
                             '(all zero: no quay)')

    @property
    def g(self) -> float:
        """|gravity| [m/s^2]."""
        return math.hypot(*self.gravity)

    @property
    def has_water(self) -> bool:
        """Tell whether there is water (a water level above -inf)."""
        return self.water_level > -math.inf

    @property
    def depth(self) -> float:
        """Return the depth of the water, water_level - seabed_level [m]; math.inf: deep."""
        if self.water_level == -math.inf or self.seabed_level == -math.inf:
            return math.inf
        return self.water_level - self.seabed_level

    def array(self) -> np.ndarray:
        """Return the ENV array the kernels take (layout.ENV_*), quay normal made a unit."""
        env = np.zeros(ENV_COLUMNS)
        env[ENV_GRAVITY:ENV_GRAVITY + 3] = self.gravity
        env[ENV_WATER_LEVEL] = self.water_level
        env[ENV_WATER_DENSITY] = self.water_density
        env[ENV_AIR_DENSITY] = self.air_density
        env[ENV_CURRENT:ENV_CURRENT + 3] = self.current
        env[ENV_SEABED_LEVEL] = self.seabed_level
        env[ENV_SEABED_STIFFNESS] = self.seabed_stiffness
        env[ENV_SEABED_DAMPING] = self.seabed_damping
        env[ENV_SEABED_FRICTION] = self.seabed_friction
        env[ENV_QUAY_EDGE:ENV_QUAY_EDGE + 3] = self.quay_edge
        horizontal = math.hypot(self.quay_normal[0], self.quay_normal[1])
        if horizontal > 0.0:
            env[ENV_QUAY_NORMAL:ENV_QUAY_NORMAL + 2] = np.divide(self.quay_normal[:2],
                                                                 horizontal)
        env[ENV_QUAY_DEPTH] = self.quay_depth
        return env

    def fluid_density_at(self, z: float) -> float:
        """Return the density of what is at height z: water below the level, else air."""
        return self.water_density if z < self.water_level else self.air_density


@dataclass(frozen=True)
class Winch:
    """
    A winch at one end of a line (winch.py says how each mode acts).

    :ivar mode: 'none', 'speed', 'brake' or 'constant_tension'.
    :ivar end: the end it sits on: 0 (A) or 1 (B).
    :ivar command: 'speed': the commanded pay-out speed [m/s] (+ pays out);
        'constant_tension': the set tension [N].
    :ivar max_speed: [m/s].
    :ivar acceleration: [m/s^2].
    :ivar brake_load: 'brake': the load above which the brake renders [N].
    :ivar response_time: 'constant_tension': how fast it brings the tension to the set one [s].
    :ivar min_length, max_length: the unstretched lengths the winch stops at [m].
    """

    mode: str = 'none'
    end: int = 1
    command: float = 0.0
    max_speed: float = 1.0
    acceleration: float = 0.5
    brake_load: float = math.inf
    response_time: float = 1.0
    min_length: float = 0.0
    max_length: float = math.inf

    def __post_init__(self):
        """Check the mode, the end and every number."""
        if self.mode not in ('none', 'speed', 'brake', 'constant_tension'):
            raise ValueError(f'winch mode {self.mode!r} is not one of none, speed, brake, '
                             'constant_tension')
        if not (isinstance(self.response_time, numbers.Real) and self.response_time > 0.0):
            raise ValueError(f'winch response_time {self.response_time!r} must be > 0')
        if self.end not in (0, 1):
            raise ValueError(f'winch end {self.end!r} must be 0 (A) or 1 (B)')
        _finite('winch command', self.command)
        for name in ('max_speed', 'acceleration', 'min_length'):
            _finite(f'winch {name}', getattr(self, name), 0.0)
        for name in ('brake_load', 'max_length'):
            value = getattr(self, name)
            if not (isinstance(value, numbers.Real) and value >= 0.0):
                raise ValueError(f'winch {name} {value!r} must be a number >= 0 (inf: none)')


class Point:
    """
    A point line ends attach to.

    :ivar kind: 'fixed', 'driven', 'free' or 'carried'.
    :ivar mass: own mass [kg] (a free point's; 0 for the others).
    :ivar body: a carried point's body (its index in the System); offset: where it sits on
        it, from its centre of gravity in body axes [m] (its position follows from them).
    :ivar position: (3,) [m], a view into the System's state once packed.
    :ivar velocity: (3,) [m/s], likewise.
    :ivar volume: the water (or air) it displaces when wholly in it [m^3] (a free point's).
    :ivar drag_area: Cd times its frontal area [m^2]: isotropic drag 1/2 rho CdA |u| u.
    :ivar added_mass: its added-mass coefficient Ca_p: added mass Ca_p rho V, isotropic.
    """

    def __init__(self, kind: str, position, mass: float = 0.0, velocity=None,
                 volume: float = 0.0, drag_area: float = 0.0, added_mass: float = 0.0,
                 body: int = -1, offset=(0.0, 0.0, 0.0)):
        """Make a point of `kind` at `position` (a free point needs mass or a line)."""
        if kind not in KINDS:
            raise ValueError(f'point kind {kind!r} is not one of {", ".join(KINDS)}')
        if not (math.isfinite(mass) and mass >= 0.0):
            raise ValueError(f'point mass {mass!r} must be a finite number >= 0')
        for name, value in (('point volume', volume), ('point drag_area', drag_area),
                            ('point added_mass', added_mass)):
            _finite(name, value, 0.0)
        self.kind = kind
        self.mass = float(mass)
        self.volume = float(volume)
        self.drag_area = float(drag_area)
        self.added_mass = float(added_mass)
        self.position = np.array(position, dtype=float).reshape(3)
        self.velocity = (np.zeros(3) if velocity is None
                         else np.array(velocity, dtype=float).reshape(3))
        if kind == 'carried' and body < 0:
            raise ValueError('a carried point needs its body')
        self.body = int(body)
        self.offset = tuple(float(c) for c in offset)


class Line:
    """
    One line: particles joined by structural (i, i+1) and bending (i, i+2) springs.

    Particle 0 sits on point `ends[0]` (end A), particle N on `ends[1]` (end B).

    :ivar line_type: its LineType.
    :ivar rest: rest length of each segment [m], shape (N,).
    :ivar x: particle positions (N+1, 3) [m] (a view into the System's state once packed).
    :ivar v: particle velocities (N+1, 3) [m/s], likewise.
    :ivar ends: indices of the points of end A and end B in the System.
    :ivar winch: its Winch (mode 'none': no winch).
    :ivar break_load: a segment pulling harder parts [N]; inf: it never parts.
    :ivar parted: the index of the segment that parted, None while the line is whole.
    """

    def __init__(self, line_type: LineType, rest: Sequence[float], positions,
                 ends: Sequence[int], winch: Winch = Winch(), break_load: float = math.inf):
        """Place the line at rest at `positions` (N+1, 3) with segment rest lengths `rest`."""
        if not (isinstance(break_load, numbers.Real) and break_load > 0.0):
            raise ValueError(f'break_load {break_load!r} must be a number > 0 (inf: never)')
        self.winch = winch
        self.break_load = float(break_load)
        self.parted = None
        self.line_type = line_type
        self.rest = np.array(rest, dtype=float).reshape(-1)
        self.x = np.array(positions, dtype=float)
        if self.x.shape != (len(self.rest) + 1, 3):
            raise ValueError(
                f'positions must have shape ({len(self.rest) + 1}, 3), got {self.x.shape}')
        if not (self.rest > 0.0).all():
            raise ValueError('every segment rest length must be > 0')
        self.v = np.zeros_like(self.x)
        self.ends = (int(ends[0]), int(ends[1]))

    @classmethod
    def uniform(cls, line_type: LineType, length: float, segments: int, positions,
                ends: Sequence[int], **options) -> 'Line':
        """Make a line of `segments` equal segments of length / segments (options: winch...)."""
        return cls(line_type, np.full(segments, length / segments), positions, ends, **options)

    @property
    def segments(self) -> int:
        """Count the segments: N."""
        return len(self.rest)

    @property
    def length(self) -> float:
        """Unstretched length: the sum of the rest lengths [m]."""
        return float(self.rest.sum())

    def particle_masses(self) -> np.ndarray:
        """Lumped masses (N+1,) [kg]: half of each neighbouring segment."""
        half = 0.5 * self.line_type.mass_per_length * self.rest
        masses = np.zeros(self.segments + 1)
        masses[:-1] += half
        masses[1:] += half
        return masses

    def strains(self) -> np.ndarray:
        """Strain of every structural spring, shape (N,) (0 where it parted: it pulls no more)."""
        d = np.diff(self.x, axis=0)
        strains = np.sqrt(np.einsum('ij,ij->i', d, d)) / self.rest - 1.0
        if self.parted is not None:
            strains[self.parted] = 0.0
        return strains


class System:
    """
    Lines and points stepped together.

    Add points and lines, then pack(); step with improved_euler or implicit_euler.

    :ivar environment: the Environment.
    :ivar points: the Points, in index order.
    :ivar lines: the Lines.
    :ivar arrays: after pack(), the arrays the kernels step, as one record
        (record.SystemArrays); refresh() makes it anew, with the tables.
    """

    def __init__(self, environment: Environment):
        """Make an empty system in `environment`."""
        self.environment = environment
        self.points: List[Point] = []
        self.lines: List[Line] = []
        self.bodies: List[Body] = []
        self.fenders: List[Fender] = []
        self.gravity = np.asarray(environment.gravity, dtype=float)
        self.env = environment.array()  # what the kernels read (set_current writes in it)
        self._packed = False
        self.steps = 0  # steps taken: tells whether loads() must compute again

    def add_point(self, point: Point) -> int:
        """Add a point; return its index."""
        self.points.append(point)
        self._packed = False
        return len(self.points) - 1

    def add_body(self, body: Body) -> int:
        """Add a rigid body (its carried points name it by this index); return the index."""
        self.bodies.append(body)
        self._packed = False
        return len(self.bodies) - 1

    def add_fender(self, fender: Fender) -> int:
        """Add a fender that touches one of the bodies; return its index."""
        self.fenders.append(fender)
        self._packed = False
        return len(self.fenders) - 1

    def add_line(self, line: Line) -> int:
        """Add a line whose ends sit on points already added; return its index."""
        for end in line.ends:
            if not 0 <= end < len(self.points):
                raise ValueError(f'line end on point {end}: the system has '
                                 f'{len(self.points)} points')
        self.lines.append(line)
        self._packed = False
        return len(self.lines) - 1

    # -- packing ---------------------------------------------------------------------------

    def pack(self) -> None:
        """
        Stack the state into the System's arrays and build the kernels' tables.

        Every line end is put on its point. Afterwards Line.x / Line.v and Point.position /
        Point.velocity are views into x, v, point_x, point_v.
        """
        counts = [line.segments + 1 for line in self.lines]
        starts = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        self.x = np.empty((int(starts[-1]), 3))
        self.v = np.empty((int(starts[-1]), 3))
        for k, line in enumerate(self.lines):
            self.x[starts[k]:starts[k + 1]] = line.x
            self.v[starts[k]:starts[k + 1]] = line.v
            line.x = self.x[starts[k]:starts[k + 1]]
            line.v = self.v[starts[k]:starts[k + 1]]
        self.point_x = np.array([p.position for p in self.points], dtype=float).reshape(-1, 3)
        self.point_v = np.array([p.velocity for p in self.points], dtype=float).reshape(-1, 3)
        for q, point in enumerate(self.points):
            point.position = self.point_x[q]
            point.velocity = self.point_v[q]
        self._pack_bodies()
        self._starts = starts
        self._packed = True
        self.refresh()
        place_points(self.body_table, self.points_table, self.point_x, self.point_v)
        assembly.set_ends(self.x, self.v, self.lines_table, self.point_x, self.point_v)

    def _pack_bodies(self) -> None:
        """Build the BODY and FENDER tables; each Body's state becomes a view of its row."""
        for point in self.points:
            if point.kind == 'carried' and not 0 <= point.body < len(self.bodies):
                raise ValueError(f'carried point on body {point.body}: the system has '
                                 f'{len(self.bodies)} bodies')
        for fender in self.fenders:
            if not 0 <= fender.body < len(self.bodies):
                raise ValueError(f'fender on body {fender.body}: the system has '
                                 f'{len(self.bodies)} bodies')
        self.body_table = np.array([body.row() for body in self.bodies],
                                   dtype=float).reshape(-1, BODY_COLUMNS)
        for b, body in enumerate(self.bodies):
            row = self.body_table[b]
            body.position = row[BODY_POSITION:BODY_POSITION + 3]
            body.quaternion = row[BODY_QUATERNION:BODY_QUATERNION + 4]
            body.velocity = row[BODY_VELOCITY:BODY_VELOCITY + 3]
            body.omega = row[BODY_OMEGA:BODY_OMEGA + 3]
        self.fender_table = np.array([fender.row() for fender in self.fenders],
                                     dtype=float).reshape(-1, FENDER_COLUMNS)

    def refresh(self) -> None:
        """
        Rebuild the tables from the lines and the points (their types, rest lengths, winches).

        What the step keeps in the tables goes on: the winches' speeds, the held peaks, and
        the segments' tensions the adaptive integrator's snap watch compares the next step's
        with (else the step after a refresh, a line let go, went unwatched: the let go's
        recoil, taken in one implicit step, came 18 % fast).
        """
        kept = None
        if getattr(self, 'line_real', None) is not None and len(self.line_real) == len(
                self.lines) and len(self.particles) == len(self.x):
            kept = (self.line_real[:, [WINCH_SPEED, PEAK_A, PEAK_B]].copy(),
                    self.particles[:, [TENSION, TENSION_BEFORE]].copy())
        self._build_tables()
        if kept is not None:
            self.line_real[:, [WINCH_SPEED, PEAK_A, PEAK_B]] = kept[0]
            self.particles[:, [TENSION, TENSION_BEFORE]] = kept[1]
        # the accelerations of the last implicit step (P, 3), (Q, 3), and the step count at
        # which they are the state's (-1: they are not); each line's improved Euler time left
        # in the adaptive integrator [s]
        self.accel = np.zeros_like(self.x)
        self.point_accel = np.zeros_like(self.point_x)
        # what every step passes, built once: a step runs at kHz
        self.arrays = SystemArrays(self.x, self.v, self.point_x, self.point_v, self.accel,
                                   self.point_accel, self.particles, self.lines_table,
                                   self.line_real, self.points_table, self.env,
                                   self.body_table, self.fender_table)
        self._accel_at = -1
        self.fine_left = np.zeros(len(self.lines))
        # the lines the adaptive integrator may take into improved Euler through a snap: its
        # user's choice (the Mooring's: not a line let go once it has recoiled)
        self.watched = np.ones(len(self.lines), dtype=bool)
        self._forces = np.zeros((len(self.lines), 2, 3))
        self._strains = np.zeros(len(self.lines))
        self._loads_at = -1  # the step count at which _forces and _strains were computed

    def _build_tables(self) -> None:
        """Build particles, lines_table, line_real and points_table."""
        starts = self._starts
        self.particles = np.zeros((int(starts[-1]), PARTICLE_COLUMNS))
        self.particles[:, [TENSION, TENSION_BEFORE]] = np.nan  # not measured yet
        self.lines_table = np.zeros((len(self.lines), LINE_COLUMNS), dtype=np.int64)
        self.line_real = np.zeros((len(self.lines), LINE_REAL_COLUMNS))
        self.points_table = np.zeros((len(self.points), POINT_COLUMNS))
        env = self.environment
        for q, point in enumerate(self.points):
            self.points_table[q, KIND] = KINDS[point.kind]
            self.points_table[q, OWN_MASS] = point.mass
            self.points_table[q, TOTAL_MASS] = point.mass
            self.points_table[q, VOLUME] = point.volume
            self.points_table[q, DRAG_AREA] = point.drag_area
            self.points_table[q, ADDED_MASS] = point.added_mass
            size = point.volume ** (1.0 / 3.0)
            self.points_table[q, SIZE] = size
            self.points_table[q, POINT_BODY] = point.body
            self.points_table[q, POINT_OFFSET:POINT_OFFSET + 3] = point.offset
            # its static sink into the ground under its submerged weight
            sinking = (point.mass - point.volume * self._ground_density()) * env.g
            self.points_table[q, POINT_SINK] = self._ramp(sinking, size * size)
        for k, line in enumerate(self.lines):
            first, last = int(starts[k]), int(starts[k + 1]) - 1
            t = line.line_type
            rows = self.particles[first:last + 1]
            rest = line.rest
            masses = line.particle_masses()
            rows[:, MASS] = masses
            lumped = np.zeros(line.segments + 1)
            lumped[:-1] += 0.5 * rest
            lumped[1:] += 0.5 * rest
            rows[:, DRAG] = t.air_drag_coefficient * lumped
            rows[:, LENGTH] = lumped
            rows[:, SINK] = self._sink(t)
            rows[:-1, REST] = rest
            rows[:-1, STIFFNESS] = t.axial_stiffness / rest
            rows[:-1, DAMPING] = t.axial_damping / rest
            if line.segments >= 2:
                pair = rest[:-1] + rest[1:]
                mean = 0.5 * pair
                rows[:-2, BEND_REST] = pair
                rows[:-2, BEND_STIFFNESS] = t.bending_stiffness_ratio * (
                    t.axial_stiffness / mean)
                rows[:-2, BEND_DAMPING] = t.bending_damping_ratio * (t.axial_damping / mean)
            self.lines_table[k, :ADJUST + 1] = (
                first, last, line.ends[0], line.ends[1], t.damping_model == 'axial',
                line.segments >= 2 and (t.bending_stiffness_ratio > 0.0
                                        or t.bending_damping_ratio > 0.0),
                t.superelastic_adjustment)
            self.line_real[k, MAX_STRAIN] = t.max_strain
            # the adaptive integrator's tension scale at least: the line's weight (under
            # standard gravity, so that a line without gravity has one too), or a share of
            # its MBL
            self.line_real[k, SNAP_FLOOR] = max(
                parting.SNAP_FLOOR_WEIGHT * masses.sum() * STANDARD_GRAVITY,
                parting.SNAP_FLOOR_MBL * t.mbl if math.isfinite(t.mbl) else 0.0)
            self.line_real[k, AXIAL_STIFFNESS] = t.axial_stiffness
            if t.curve is not None:
                t.curve.fill(self.line_real[k])
            dv = t.displacing_diameter
            real = self.line_real[k]
            real[DIAMETER] = t.diameter
            real[VOLUME_DIAMETER] = dv
            real[VOLUME_AREA] = 0.25 * math.pi * dv * dv
            real[NORMAL_DRAG] = 0.5 * t.normal_drag * t.diameter
            real[TANGENTIAL_DRAG] = 0.5 * t.tangential_drag * math.pi * t.diameter
            real[NORMAL_ADDED_MASS] = t.normal_added_mass
            real[TANGENTIAL_ADDED_MASS] = t.tangential_added_mass
            drag = real[NORMAL_DRAG] > 0.0 or real[TANGENTIAL_DRAG] > 0.0
            # with neither water nor air every fluid term is zero: skip them (a third of an
            # implicit step's time, three quarters of an explicit one's)
            fluid = (real[VOLUME_AREA] > 0.0 or drag) and (env.has_water
                                                           or env.air_density > 0.0)
            self.lines_table[k, FLUID] = fluid
            self.lines_table[k, TANGENTS] = fluid and (drag or (
                real[VOLUME_AREA] > 0.0
                and t.normal_added_mass != t.tangential_added_mass))
            for e, row in ((0, first), (1, last)):
                self.points_table[line.ends[e], TOTAL_MASS] += masses[0 if e == 0 else -1]
            self._line_changes(k, line)
        for k, line in enumerate(self.lines):
            # inverse masses relative to the line's heaviest particle: only their ratios
            # matter, and a uniform line's inner particles get exactly 1
            first, last = self.lines_table[k, FIRST], self.lines_table[k, LAST]
            unit = self.particles[first:last + 1, MASS].max()
            self.particles[first:last + 1, INV_MASS] = unit / self.particles[first:last + 1, MASS]
            for e, row in ((0, first), (1, last)):
                q = line.ends[e]
                kind = self.points_table[q, KIND]
                self.particles[row, INV_MASS] = (
                    unit / self.points_table[q, TOTAL_MASS] if kind == FREE else 0.0)
        for q in range(len(self.points)):
            if self.points_table[q, KIND] == FREE and not self.points_table[q, TOTAL_MASS] > 0.0:
                raise ValueError(f'free point {q} has no mass and no line')
        ends = self.lines_table[:, [END_A, END_B]].reshape(-1)
        free = ends[self.points_table[ends, KIND] == FREE] if len(ends) else ends
        self.joins_lines = len(free) > len(set(free.tolist()))  # a free point of two lines

    def _line_changes(self, k: int, line: Line) -> None:
        """Fill line k's winch and parting columns; part it again if it had parted."""
        real = self.line_real[k]
        w = line.winch
        real[UNSTRETCHED] = line.length
        real[WINCH_MODE] = winch.mode_code(w.mode)
        real[WINCH_END] = w.end
        real[WINCH_COMMAND] = w.command
        real[WINCH_MAX_SPEED] = w.max_speed
        real[WINCH_ACCELERATION] = w.acceleration
        real[WINCH_BRAKE_LOAD] = w.brake_load
        real[WINCH_RESPONSE] = w.response_time
        real[WINCH_MIN_LENGTH] = w.min_length
        real[WINCH_MAX_LENGTH] = w.max_length
        real[BREAK_LOAD] = line.break_load
        real[PARTED] = -1.0 if line.parted is None else line.parted
        real[PARTED_STEP] = -1.0
        if line.parted is not None:
            first = int(self.lines_table[k, FIRST])
            parting.part(self.particles, self.lines_table, self.particles[:, REST].copy(), k,
                         first + line.parted)

    def _ground_density(self) -> float:
        """Return the density of the fluid on the seabed (water unless it is dry)."""
        env = self.environment
        return (env.water_density if env.water_level > env.seabed_level
                else env.air_density)

    def _ramp(self, weight: float, area: float) -> float:
        """Return the contact damping's ramp depth: the sink of `weight` [N] on `area` [m^2]."""
        stiffness = self.environment.seabed_stiffness * area
        if not (weight > 0.0 and stiffness > 0.0):
            return SMALLEST_SINK
        return max(weight / stiffness, SMALLEST_SINK)

    def _sink(self, t: LineType) -> float:
        """Return a line's contact ramp depth: its static sink w_sub / (k_b d) [m]."""
        dv = t.displacing_diameter
        w_sub = (t.mass_per_length - self._ground_density() * 0.25 * math.pi * dv * dv) \
            * self.environment.g
        return self._ramp(w_sub, t.diameter)

    def set_current(self, current) -> None:
        """Set the water's uniform current (3,) [m/s] now, without rebuilding anything."""
        self.set_environment(replace(self.environment, current=_vector('current', current)))

    def set_environment(self, environment: Environment) -> None:
        """
        Take the environment as a run changed it (its current, wind, waves) from now on.

        Nothing else of it changes at run time: the current alone goes into the tables.
        """
        self.environment = environment
        self.env[ENV_CURRENT:ENV_CURRENT + 3] = environment.current
        self._loads_at = -1  # the end forces' drag changes with it

    # -- what the integrators and the outputs need -----------------------------------------

    @property
    def free_points(self) -> np.ndarray:
        """Return the indices of the free points."""
        return np.flatnonzero(self.points_table[:, KIND] == FREE)

    @property
    def carried_points(self) -> np.ndarray:
        """Return the indices of the points a body carries."""
        return np.flatnonzero(self.points_table[:, KIND] == CARRIED)

    @property
    def has_bodies(self) -> bool:
        """Tell whether a rigid body moves with the lines."""
        return len(self.bodies) > 0

    def lumped_mass(self, q: int) -> float:
        """Return a point's own mass plus the half segments of the line ends on it [kg]."""
        return float(self.points_table[q, TOTAL_MASS])

    def drive_arrays(self, steps: int) -> tuple:
        """Return drive_x, drive_v (steps, Q, 3) holding every point where it is now, at rest."""
        drive_x = np.repeat(self.point_x[None], steps, axis=0)
        return drive_x, np.zeros_like(drive_x)

    def took_steps(self, history_kept: bool) -> list:
        """
        Take in a run of steps the integrators took (stepping/step.py): the Lines follow.

        :param history_kept: the accelerations the run leaves are the state's (the
            adaptive integrator's Newmark steps start from them).
        :returns: (line index, step of the run) of every line that parted in the run.
        """
        self.steps += 1
        self._accel_at = self.steps if history_kept else -1
        return self._follow_line_changes()

    @property
    def history_kept(self) -> bool:
        """Tell whether the accelerations are from the step taken last (the adaptive one)."""
        return self._accel_at == self.steps

    def save_state(self) -> tuple:
        """Return a copy of everything a step changes (load_state puts it back)."""
        return (self.x.copy(), self.v.copy(), self.point_x.copy(), self.point_v.copy(),
                self.particles.copy(), self.line_real.copy(), self.accel.copy(),
                self.point_accel.copy(), self.body_table.copy())

    def load_state(self, saved: tuple) -> None:
        """Put back what save_state copied, in place (the Lines' and Points' views see it)."""
        for mine, kept in zip(self._state(), saved):
            mine[:] = kept

    def load_line_state(self, saved: tuple, k: int) -> None:
        """Put back line k's part of what save_state copied: its particles and table rows."""
        rows = slice(self.lines_table[k, FIRST], self.lines_table[k, LAST] + 1)
        x, v, _, _, particles, line_real, accel, _, _ = saved
        self.x[rows] = x[rows]
        self.v[rows] = v[rows]
        self.accel[rows] = accel[rows]
        self.particles[rows] = particles[rows]
        self.line_real[k] = line_real[k]

    def line_view(self, k: int) -> 'LineView':
        """Return line k alone, on views of its rows (see LineView)."""
        return LineView(self, k)

    def _state(self) -> tuple:
        """Return the arrays save_state copies, in its order."""
        return (self.x, self.v, self.point_x, self.point_v, self.particles, self.line_real,
                self.accel, self.point_accel, self.body_table)

    def _follow_line_changes(self) -> list:
        """
        Bring the Lines up to what the step changed: rest lengths (winches), parted segments.

        :returns: (line index, step of the run) of every line that parted in the run.
        """
        parted = []
        for k, line in enumerate(self.lines):
            if line.winch.mode != 'none':
                real = self.line_real[k]
                first, last = self.lines_table[k, FIRST], self.lines_table[k, LAST]
                rest = self.particles[first:last, REST]
                if line.parted is None and real[PARTED] < 0.0:
                    line.rest[:] = rest
                else:  # the parted segment's own rest length: what the others leave
                    whole = np.arange(line.segments) != int(real[PARTED])
                    line.rest[whole] = rest[whole]
                    line.rest[~whole] = real[UNSTRETCHED] - rest[whole].sum()
        # one look at the partings' column: looking line by line took 1 us a line an output
        if len(self.lines) and self.line_real[:, PARTED].max() >= 0.0:
            for k in np.flatnonzero(self.line_real[:, PARTED] >= 0.0):
                line, real = self.lines[k], self.line_real[k]
                if line.parted is None:
                    line.parted = int(real[PARTED])
                    step = float(real[PARTED_STEP])
                    parted.append((int(k), int(step) if step.is_integer() else step))
        return parted

    def set_winch(self, k: int, **changes) -> None:
        """Change line k's winch (mode, command, ...) from the next step, without a rebuild."""
        line = self.lines[k]
        line.winch = replace(line.winch, **changes)
        self._line_changes(k, line)

    def take_tensions(self, forces: np.ndarray, x: np.ndarray) -> tuple:
        """
        Return each line's end tensions now and their peaks since the last call (L, 2) [N].

        Clears the held peaks (take_peaks) and takes this state's tensions into them.

        :param forces: loads()' end forces of this state (L, 2, 3) [N].
        :param x: the particles' positions (a copy of x) to sum with them.
        :returns: tensions, peaks, and the sum of x, forces and peaks (finite only if every
            one of them is).
        """
        tensions, peaks = np.empty((len(forces), 2)), np.empty((len(forces), 2))
        total = assembly.take_tensions(forces, self.line_real, x, tensions, peaks)
        return tensions, peaks, total

    def take_peaks(self, lines=slice(None)) -> np.ndarray:
        """
        Return the lines' largest end forces since the last call, (L, 2) [N]; clear them.

        :param lines: which lines (an index array or a slice; all by default): the others
            keep holding theirs.
        """
        peaks = self.line_real[lines, PEAK_A:PEAK_B + 1].copy()  # (PEAK_B is PEAK_A + 1)
        self.line_real[lines, PEAK_A:PEAK_B + 1] = 0.0
        return peaks

    def load_line(self, k: int, source: 'System', j: int = 0) -> None:
        """
        Make line k and its end points what line j of `source` and its end points are.

        Everything of the line is taken: its particles' state, its type and rest lengths, its
        winch (and the speed it ran at), break load and parting, its held peaks; and the
        positions and velocities of the points its ends sit on. The two lines must have as
        many segments, and their points be of the same kinds (a carried point takes its
        body's motion instead). The other lines and points go on untouched. This is how a
        line started at rest in a System of its own (relaxed alone) takes its place in a
        System it shares with others.
        """
        self.load_lines([(k, source, j)])

    def load_lines(self, loads: Sequence[Tuple[int, 'System', int]]) -> None:
        """Load line k from line j of each (k, source, j) as load_line does, refreshed once."""
        for k, source, j in loads:
            line, other = self.lines[k], source.lines[j]
            if line.segments != other.segments:
                raise ValueError(f'line {k} has {line.segments} segments, the source line '
                                 f'{other.segments}')
            line.x[:] = other.x
            line.v[:] = other.v
            line.line_type = other.line_type
            line.rest[:] = other.rest
            line.winch, line.break_load, line.parted = (other.winch, other.break_load,
                                                        other.parted)
            for mine, theirs in zip(line.ends, other.ends):
                self.point_x[mine] = source.point_x[theirs]
                self.point_v[mine] = source.point_v[theirs]
        self.refresh()
        for k, source, j in loads:
            self.line_real[k, [WINCH_SPEED, PEAK_A, PEAK_B]] = \
                source.line_real[j, [WINCH_SPEED, PEAK_A, PEAK_B]]
        if self.bodies:  # a carried end moves with its body, whatever the source's did
            place_points(self.body_table, self.points_table, self.point_x, self.point_v)
            assembly.set_ends(self.x, self.v, self.lines_table, self.point_x, self.point_v)

    def line_loads(self) -> np.ndarray:
        """
        Return each line's largest end force or EA times strain now, (L,) [N].

        largest_load's number, line by line (NaN or inf where the numbers overflow).
        """
        forces, strains = self.loads()
        return np.maximum(np.linalg.norm(forces, axis=2).max(axis=1),
                          self.line_real[:, AXIAL_STIFFNESS] * strains)

    def unstretched_length(self, k: int) -> float:
        """Return line k's unstretched length now [m] (its winch changes it)."""
        return float(self.line_real[k, UNSTRETCHED])

    def winch_speed(self, k: int) -> float:
        """Return the speed line k's winch paid out at in the last step [m/s] (+ pays out)."""
        return float(self.line_real[k, WINCH_SPEED])

    def end_forces(self) -> np.ndarray:
        """Force of each line on the points of its ends, (L, 2, 3) [N] (see kernels)."""
        out = np.empty((len(self.lines), 2, 3))
        assembly.end_forces(self.x, self.v, self.particles, self.lines_table, self.line_real,
                            self.env, out)
        return out

    def largest_load(self) -> tuple:
        """
        Return whether the state is finite, and its largest end force or EA strain [N].

        The end forces and strains it computes on the way are what loads() returns until the
        next step.
        """
        finite, largest = assembly.largest_load(
            self.x, self.v, self.point_x, self.point_v, self.particles, self.lines_table,
            self.line_real, self.env, self._forces, self._strains)
        self._loads_at = self.steps if finite else -1
        return finite, largest

    def loads(self) -> tuple:
        """
        Return the end forces (L, 2, 3) [N] and each line's largest strain (L,) now.

        Computed once per state: the check of a state (largest_load) and its outputs share
        them. Call refresh() after writing x or v other than by step().
        """
        if self._loads_at != self.steps:
            self.largest_load()
            if self._loads_at != self.steps:  # not finite: computed for what it is
                assembly.end_forces(self.x, self.v, self.particles, self.lines_table,
                                    self.line_real, self.env, self._forces)
                for k, line in enumerate(self.lines):
                    self._strains[k] = assembly.max_strain(line.x, line.rest)
        return self._forces.copy(), self._strains.copy()

    def energy(self) -> tuple:
        """
        Return (kinetic, potential, elastic) energy of the lines, free points and bodies [J].

        A body's: kinetic with its mass and added mass, potential of its hydrostatic
        restoring, 1/2 (k_heave dz^2 + k_roll phi^2 + k_pitch theta^2) about where it floats
        freely (forces/body.py; exact for small angles).

        Kinetic of every particle (a line end on a free point counted with the point, once),
        potential of every lumped mass in gravity less the air it displaces (0 at the
        origin), elastic of the structural springs (EA stretch^2 / (2 l), or on a curve the
        rest length times its integral up to the strain) and the bending springs. Not
        counted: the added masses' kinetic energy, and the buoyancy of water (its potential
        depends on how each segment crosses the surface).
        """
        kinetic = potential = elastic = 0.0
        g = self.gravity
        on_free = np.zeros(len(self.x), dtype=bool)
        for k, line in enumerate(self.lines):
            for e, row in ((0, self.lines_table[k, FIRST]), (1, self.lines_table[k, LAST])):
                on_free[row] = self.points_table[line.ends[e], KIND] == FREE
        moving = ~on_free
        m = self.particles[:, MASS]
        air = self.environment.air_density
        if not self.environment.has_water:
            areas = np.concatenate([np.full(line.segments + 1,
                                            self.line_real[k, VOLUME_AREA])
                                    for k, line in enumerate(self.lines)] or [np.zeros(0)])
            net = m - air * areas * self.particles[:, LENGTH]
        else:
            net = m
        kinetic += 0.5 * float(np.sum(m[moving] * np.einsum('ij,ij->i', self.v, self.v)[moving]))
        potential -= float(np.sum(net[moving] * (self.x[moving] @ g)))
        for q in self.free_points:
            total = self.points_table[q, TOTAL_MASS]
            kinetic += 0.5 * total * float(self.point_v[q] @ self.point_v[q])
            lifted = total
            if not self.environment.has_water:
                lifted -= air * self.points_table[q, VOLUME]
                for k, line in enumerate(self.lines):
                    for e, row in ((0, self.lines_table[k, FIRST]),
                                   (1, self.lines_table[k, LAST])):
                        if line.ends[e] == q:
                            lifted -= m[row] - net[row]
            potential -= lifted * float(self.point_x[q] @ g)
        for body in self.bodies:
            k_body, p_body = body.energy()
            kinetic += k_body
            potential += p_body
        for k in range(len(self.lines)):
            first, last = self.lines_table[k, FIRST], self.lines_table[k, LAST]
            rows = self.particles[first:last + 1]
            x = self.x[first:last + 1]
            length = np.linalg.norm(x[1:] - x[:-1], axis=1)
            curve = self.lines[k].line_type.curve
            if curve is not None:
                rest = rows[:-1, REST]
                elastic += float(np.sum(rest * curve.energy(length / rest - 1.0)))
            else:
                stretch = np.maximum(length - rows[:-1, REST], 0.0)
                elastic += 0.5 * float(np.sum(rows[:-1, STIFFNESS] * stretch ** 2))
            if self.lines_table[k, BENDING] and len(x) > 2:
                bend = np.linalg.norm(x[2:] - x[:-2], axis=1) - rows[:-2, BEND_REST]
                elastic += 0.5 * float(np.sum(rows[:-2, BEND_STIFFNESS] * bend ** 2))
        return kinetic, potential, elastic

    def damper_power(self) -> float:
        """
        Power the dampers and the drag take out of the motion now [W] (>= 0 without current).

        Axial: c ((v_j - v_i) . u)^2 per spring; seed: c |v_j - v_i|^2; the seed's air drag:
        kappa |v|^3 per particle; the fluid drag: c_n |v_n|^3 + c_t |v_t|^3 per particle and
        c |v|^3 per free point (relative to the water's current, whose work it leaves out).
        With every point fixed or free, in air, the energy (energy()) falls at exactly this
        rate.
        """
        power = 0.0
        sub = np.zeros(len(self.x))
        tangent = np.zeros_like(self.x)
        assembly.line_passes(self.x, self.particles, self.lines_table, self.line_real, self.env,
                             sub, tangent)
        env = self.environment
        relative = self.v - np.where(sub[:, None] > 0.0, np.asarray(env.current), 0.0)
        for k in range(len(self.lines)):
            if not self.lines_table[k, TANGENTS]:
                continue
            first, last = self.lines_table[k, FIRST], self.lines_table[k, LAST] + 1
            wet = sub[first:last]
            dry = self.particles[first:last, LENGTH] - wet
            for part, rho, u in ((wet, env.water_density, relative[first:last]),
                                 (dry, env.air_density, self.v[first:last])):
                q = tangent[first:last]
                along = np.einsum('ij,ij->i', u, q)
                normal = np.linalg.norm(u - along[:, None] * q, axis=1)
                power += float(np.sum(rho * part * (
                    self.line_real[k, NORMAL_DRAG] * normal ** 3
                    + self.line_real[k, TANGENTIAL_DRAG] * np.abs(along) ** 3)))
        for q in self.free_points:
            area = self.points_table[q, DRAG_AREA]
            if area > 0.0:
                wet = 0.0
                if env.has_water:
                    size = max(self.points_table[q, SIZE], 1e-6)
                    wet = min(max((env.water_level - self.point_x[q, 2]) / size + 0.5, 0.0),
                              1.0)
                for part, rho, u in ((wet, env.water_density,
                                      self.point_v[q] - np.asarray(env.current)),
                                     (1.0 - wet, env.air_density, self.point_v[q])):
                    power += 0.5 * rho * area * part * float(np.linalg.norm(u)) ** 3
        for k in range(len(self.lines)):
            first, last = self.lines_table[k, FIRST], self.lines_table[k, LAST]
            rows = self.particles[first:last + 1]
            x, v = self.x[first:last + 1], self.v[first:last + 1]
            axial = self.lines_table[k, AXIAL] == 1
            for stride, col in ((1, DAMPING), (2, BEND_DAMPING)):
                if stride == 2 and not self.lines_table[k, BENDING]:
                    continue
                d = x[stride:] - x[:-stride]
                u = d / np.linalg.norm(d, axis=1)[:, None]
                dv = v[stride:] - v[:-stride]
                c = rows[:-stride, col]
                if axial:
                    power += float(np.sum(c * np.einsum('ij,ij->i', dv, u) ** 2))
                else:
                    power += float(np.sum(c * np.einsum('ij,ij->i', dv, dv)))
            speed = np.linalg.norm(v, axis=1)
            power += float(np.sum(rows[:, DRAG] * speed ** 3))
        return power


class LineView:
    """
    One line of a System whose lines end on driven, fixed or carried points, as a System of it.

    Its particle rows and its line_real row are views of the System's: a kernel run of the
    view steps that line in the System, and no other. Its points are copies (ends: their
    indices in the System); put them back with store_points. A carried point is a driven one
    here: the view moves the line, not the body, whose motion comes from the step the whole
    System took (the drive arrays the caller gives). The adaptive integrator takes a snapping
    line's improved Euler steps so, at the cost of that line alone. Make it anew after
    anything rebuilds the System's tables (refresh).
    """

    def __init__(self, system: System, k: int):
        """View line k of `system`."""
        first, last = system.lines_table[k, FIRST], system.lines_table[k, LAST] + 1
        self.ends = system.lines_table[k, [END_A, END_B]].copy()
        self.x, self.v = system.x[first:last], system.v[first:last]
        self.accel = system.accel[first:last]
        self.point_x = system.point_x[self.ends]
        self.point_v = system.point_v[self.ends]
        self.point_accel = system.point_accel[self.ends]
        self.line_real = system.line_real[k:k + 1]
        self.watched = system.watched[k:k + 1]
        lines_table = system.lines_table[k:k + 1].copy()
        lines_table[0, [FIRST, LAST]] -= first
        lines_table[0, [END_A, END_B]] = (0, 1)
        points = system.points_table[self.ends]  # a copy
        points[points[:, KIND] == CARRIED, KIND] = DRIVEN
        self.arrays = SystemArrays(self.x, self.v, self.point_x, self.point_v, self.accel,
                                   self.point_accel, system.particles[first:last],
                                   lines_table, self.line_real, points, system.env,
                                   system.body_table[:0], system.fender_table[:0])

    def drive(self, drive_x: np.ndarray, drive_v: np.ndarray) -> tuple:
        """Return the view's points' rows of a System's drive arrays (n, Q, 3): (n, 2, 3) twice."""
        # contiguous, as the System's own: a strided copy would be another kernel to compile
        return (np.ascontiguousarray(drive_x[:, self.ends]),
                np.ascontiguousarray(drive_v[:, self.ends]))

    def store_points(self, system: System) -> None:
        """Put the view's points (where its run left them) back into `system`."""
        system.point_x[self.ends] = self.point_x
        system.point_v[self.ends] = self.point_v


def single_line(line_type: LineType, environment: Environment, length: float, segments: int,
                positions, end_a: Point, end_b: Point) -> System:
    """Make and pack a System of one uniform line from point end_a (0) to end_b (1)."""
    system = System(environment)
    system.add_point(end_a)
    system.add_point(end_b)
    system.add_line(Line.uniform(line_type, length, segments, positions, (0, 1)))
    system.pack()
    return system
