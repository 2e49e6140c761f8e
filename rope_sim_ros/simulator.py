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
Drive a line through time from end trajectories.

The one simulator of the node, the offline runner and the tests: a physics System
(physics/objects.py) of one line between two points, the bollard (point 0, particle 0) and
the fairlead (point 1, particle N). The fairlead is a driven point (its samples); the bollard
is driven too (its samples, or bollard_position while it has none), or, with payload_mass > 0,
a free point: a payload of that mass hanging at the line's end.

Data flows one way: end samples -> trajectories -> fixed substeps -> system state -> outputs.
"""

from dataclasses import dataclass, replace
import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .model.forces import fluid
from .model.materials import MaterialLibrary, MaterialProperties
from .model.objects import Line, Point, System, Winch
from .model.rope import critical_axial_damping, RopeProperties, tension_bound
from .model.statics.start import start_shape
from .model.superelastic import MAX_ITERATIONS
from .params.materials import load_materials
from .params.table import LineParams, ParameterError
from .stepping.relax import relax
from .stepping.rules import (automatic_time_step, drag_rate, end_distances, implicit_bending,
                             motion_spread, stability_limit)
from .stepping.step import step
from .trajectory import EndBlend, EndTrajectory, TrajectoryError

# An end found further than END_TOLERANCE [m] off its trajectory (late samples changed the
# trajectory under the rope) is brought back onto it over END_BLEND_TIME [s] (an EndBlend).
END_TOLERANCE = 1e-6
END_BLEND_TIME = 1.0  # see trajectory.py for what it costs
# Largest motion of a particle against the bollard in one substep, as a fraction of a
# segment (see Simulator._step).
MAX_STEP_MOTION = 0.5
# ... into at most this many parts (a faster state is past any physical one: the state check
# restarts it).
MAX_DIVISIONS = 1000
# The winch's defaults (params.py): its brake holds 60 % of the MBL (OCIMF MEG4); it hauls in
# to a tenth of the line's length and pays out to four times it.
BRAKE_FRACTION = 0.6
MIN_LENGTH_FRACTION = 0.1
MAX_LENGTH_FRACTION = 4.0


def _round_down(value: float) -> float:
    """Return value rounded down to 2 significant digits (a step that is safe to quote)."""
    shown = float(f'{value:.2g}')
    if shown > value:
        exponent = math.floor(math.log10(value)) - 1
        shown = float(f'{shown - 10.0 ** exponent:.2g}')
    return shown


def rope_properties(params: LineParams, material: MaterialProperties) -> RopeProperties:
    """
    Resolve the parameters into the physical numbers of the line.

    A coefficient of -1 and a volume_diameter of 0 take the material's value; quay_normal
    is made a unit vector (all zeros stay zeros: no quay). load_extension 'curve' gives the
    line the material's strain-tension curve.

    :raises ParameterError: load_extension is 'curve' and the material has no curve.
    """
    if params.load_extension == 'curve' and not material.tension_curve:
        raise ParameterError(
            f"parameter 'load_extension' = 'curve' is not allowed with material "
            f'{material.name!r}: it has no tension_curve in the materials file; set '
            "load_extension to 'linear' or choose a material with one")
    mass = params.mass_per_length or material.mass_per_length
    ea = params.axial_stiffness or material.axial_stiffness
    ba = params.axial_damping or critical_axial_damping(params.length, mass, ea)
    normal = np.array(params.quay_normal, dtype=float)
    size = float(np.linalg.norm(normal))
    return RopeProperties(
        segments=params.segments, length=params.length, mass_per_length=mass,
        axial_stiffness=ea, axial_damping=ba,
        bending_stiffness_ratio=params.bending_stiffness_ratio,
        bending_damping_ratio=params.bending_damping_ratio,
        damping_model=params.damping_model,
        air_drag_coefficient=params.air_drag_coefficient,
        gravity=tuple(params.gravity), max_strain=params.max_strain,
        superelastic_adjustment=params.superelastic_adjustment,
        payload_mass=params.payload_mass,
        diameter=params.diameter,
        volume_diameter=params.volume_diameter or material.volume_diameter,
        mbl=material.mbl,
        normal_drag=_own(params.normal_drag_coefficient, material.normal_drag_coefficient),
        tangential_drag=_own(params.tangential_drag_coefficient,
                             material.tangential_drag_coefficient),
        normal_added_mass=_own(params.normal_added_mass_coefficient,
                               material.normal_added_mass_coefficient),
        tangential_added_mass=_own(params.tangential_added_mass_coefficient,
                                   material.tangential_added_mass_coefficient),
        air_density=params.air_density, water_level=params.water_level,
        water_density=params.water_density, current=tuple(params.current),
        seabed_level=params.seabed_level, seabed_stiffness=params.seabed_stiffness,
        seabed_damping=params.seabed_damping, seabed_friction=params.seabed_friction,
        quay_edge=tuple(params.quay_edge),
        quay_normal=tuple(normal / size if size > 0.0 else normal),
        quay_depth=params.quay_depth, payload_volume=params.payload_volume,
        payload_drag_area=params.payload_drag_area,
        payload_added_mass=params.payload_added_mass_coefficient,
        tension_curve=material.tension_curve if params.load_extension == 'curve' else ())


def _own(value: float, material_value: float) -> float:
    """Return a coefficient parameter, or the material's where it is -1 (see params.py)."""
    return material_value if value < 0.0 else value


def wet_fraction(z, water_level: float, width) -> np.ndarray:
    """
    How much of a body of height `width` centred at z is under water, 0..1 (elementwise).

    The physics' own smooth submergence (forces/fluid.py point_fraction, a width below 1e-6 m
    taken as 1e-6 m, as the steps take it); no water (water_level = -inf) gives 0.
    """
    z = np.asarray(z, dtype=float)
    width = np.maximum(np.broadcast_to(np.asarray(width, dtype=float), z.shape), 1e-6)
    return np.vectorize(fluid.point_fraction, otypes=[float])(z, float(water_level), width)


def hanging_shape(props: RopeProperties, top: np.ndarray) -> np.ndarray:
    """
    Particles (N+1, 3) of a line hanging straight down from `top` with its payload, at rest.

    Particle N is at top, particle 0 (the payload) lowest, along gravity (-z without it).
    Each segment is stretched by the tension it carries: the weight of the payload and of
    the line below it (the lumped masses below: the payload's half segment first), less
    the buoyancy of the air or water each lumped mass is in (a segment that would carry
    a net upward pull is left at its rest length). Which fluid depends on where the
    particles end up: a few passes settle it (each moves them by the stretch only).
    """
    gravity = np.asarray(props.gravity, dtype=float)
    g = float(np.linalg.norm(gravity))
    down = gravity / g if g > 0.0 else np.array([0.0, 0.0, -1.0])
    n = props.segments
    lumped = np.full(n + 1, props.segment_length)
    lumped[[0, -1]] *= 0.5
    masses = props.mass_per_length * lumped
    masses[0] += props.payload_mass
    volumes = props.volume_area * lumped
    widths = np.full(n + 1, props.volume_diameter or props.diameter)
    volumes[0] += props.payload_volume
    widths[0] = props.payload_volume ** (1.0 / 3.0) if props.payload_volume > 0.0 else widths[0]
    shape = top + np.outer(props.segment_length * (n - np.arange(n + 1)), down)
    for _ in range(4 if props.has_water else 1):
        wet = wet_fraction(shape[:, 2], props.water_level, widths)
        density = props.water_density * wet + props.air_density * (1.0 - wet)
        below = np.cumsum(masses - density * volumes)[:-1]  # net mass under segment j
        lengths = props.segment_length * (1.0 + props.strain_at(g * np.maximum(below, 0.0)))
        shape = np.empty((n + 1, 3))
        shape[n] = top
        for j in range(n - 1, -1, -1):
            shape[j] = shape[j + 1] + lengths[j] * down
    return shape


@dataclass(frozen=True)
class Output:
    """
    What the line looks like at one instant.

    :ivar t: state time [s].
    :ivar positions: particles (N+1, 3) [m], bollard first.
    :ivar fairlead_force: force of the line on the fairlead (3,) [N].
    :ivar bollard_force: force of the line on the bollard (3,) [N].
    :ivar max_strain: largest structural spring strain.
    :ivar payload_position: the payload (particle 0) with payload_mass > 0, (3,) [m]; else
        None. bollard_force is then the force of the line on the payload.
    :ivar payload_velocity: its velocity (3,) [m/s]; else None.
    :ivar fairlead_peak: the largest fairlead tension since the previous output [N] (every
        step's, this output's included).
    :ivar bollard_peak: the same at the bollard (or the payload).
    :ivar line_length: the unstretched length now [m] (the winch changes it).
    :ivar winch_speed: the winch's pay-out speed in the last step [m/s] (+ pays out).
    :ivar parted: the line has parted (its two pieces are the particles either side of the
        parted segment).
    """

    t: float
    positions: np.ndarray
    fairlead_force: np.ndarray
    bollard_force: np.ndarray
    max_strain: float
    payload_position: Optional[np.ndarray] = None
    payload_velocity: Optional[np.ndarray] = None
    fairlead_peak: float = 0.0
    bollard_peak: float = 0.0
    line_length: float = math.nan
    winch_speed: float = 0.0
    parted: bool = False

    @property
    def fairlead_tension(self) -> float:
        """|fairlead_force| [N]."""
        return float(np.linalg.norm(self.fairlead_force))

    @property
    def bollard_tension(self) -> float:
        """|bollard_force| [N]."""
        return float(np.linalg.norm(self.bollard_force))


@dataclass(frozen=True)
class Advance:
    """
    What one advance_to call did.

    :ivar steps: substeps taken.
    :ivar lag: how far the state time is behind the requested time [s].
    :ivar restarted: why the rope was restarted at rest ('' when it was not): a fault,
        'non-finite state' or 'unphysical state' (a force or strain past tension_bound, see
        rope.py); or 'back within reach' (the ends came back within the line's reach after
        the fairlead was held at it).
    :ivar beyond_reach: the largest distance between the ends [m] while it exceeded the
        line's reach (Simulator.reach), else 0: the rope held the fairlead at the reach
        on the line from the bollard to it.
    """

    steps: int
    lag: float
    restarted: str = ''
    beyond_reach: float = 0.0
    parted: Optional['Parting'] = None


@dataclass(frozen=True)
class Parting:
    """
    The moment a line parted.

    :ivar t: the end of the step in which it parted [s].
    :ivar segment: the segment that parted (0 at the bollard).
    :ivar break_load: the load it exceeded [N].
    """

    t: float
    segment: int
    break_load: float


class Simulator:
    """
    One mooring line between a bollard (particle 0) and a fairlead (particle N).

    Alone, it steps its own System (advance_to). Sharing one with other lines
    (share_system), it keeps every rule of its line and its owner steps them all at once,
    through the same public pieces advance_to is made of: drive (the ends it follows),
    reach_steps and held (the fairlead held at the reach), blend_ends, divisions,
    follow_run (what a step did to the line) and load_bound (the state check).

    :ivar system: the physics System (None before start): alone, point 0 the bollard
        (driven, or free with a payload), point 1 the fairlead (driven), line 0 the rope;
        shared, line `index` between points 2 index and 2 index + 1.
    :ivar index: the rope's line index in system (0 alone).
    :ivar rope: the line (system.lines[index]; None before start): its x and v (N+1, 3)
        are the state the integrators step.
    :ivar held: the fairlead was held at the reach at the last step taken.
    """

    # How far [m] the newest end sample lies from that end's place before it (see _push).
    last_jump = 0.0

    def __init__(self, params: LineParams, materials: Optional[MaterialLibrary] = None,
                 output_interval: float = 0.0, compiled: bool = True,
                 history: float = 5.0):
        """
        Build the line; the rope is placed by start().

        :param params: validated parameters.
        :param materials: presets (default: config/materials.yaml).
        :param output_interval: if > 0, the automatic step is shortened to divide it, so that
            outputs fall on step times.
        :param compiled: step with the numba kernels (False: their Python code, interpreted:
            the reference the tests compare with).
        :param history: seconds of end samples kept behind the newest (math.inf offline, where
            a whole motion is pushed before the first step).

        :raises ParameterError / MaterialError / ValueError: the line cannot be built; the
            message says why.
        """
        self.params = params
        self.material = (materials or load_materials()).properties(
            params.material, params.diameter)
        self.props = rope_properties(params, self.material)
        self._output_interval = output_interval
        self.time_step = self._choose_time_step(params, self.props)
        self.compiled = compiled
        self.fairlead = EndTrajectory(keep=history, method=params.end_interpolation)
        self.bollard = EndTrajectory(keep=history, method=params.end_interpolation)
        self.system: Optional[System] = None
        self.index = 0
        self._shared = False  # the System holds other lines too: its owner steps it
        self.time = math.nan
        self._blends: List[Optional[EndBlend]] = [None, None]  # bollard, fairlead
        self._off_track = False  # a sample or a skip may have moved an end's track under it
        self.held = False
        # tension_bound of props at rest, and its growth per m/s of the ends (it is linear)
        self._bound = (None, math.nan, math.nan)
        # drag_rate of props at 1 m/s (see divisions)
        self._drag = (None, math.nan, math.nan)
        self.length = params.length  # the unstretched length now: the winch changes it
        self.parting: Optional[Parting] = None  # set when the line parts, until restore()
        self._winch_command = 0.0  # the speed last commanded on winch/command [m/s]
        self._held_tension = math.nan  # constant_tension with winch_tension 0: the one held

    @property
    def rope(self) -> Optional[Line]:
        """Return the line (x, v, strains()), None before start."""
        return None if self.system is None else self.system.lines[self.index]

    @property
    def payload(self) -> bool:
        """Tell whether the bollard end is a free payload: payload_mass > 0."""
        return self.params.has_payload

    def _choose_time_step(self, params: LineParams, props: RopeProperties) -> float:
        """
        Return the substep for these parameters: the one rule of time_step.

        0: automatic. improved_euler: time_step itself, refused above the step its line can
        take stably (stability_limit: at 1.9 times it, 0.5 ms, a 2.5 m jerk of the reference
        polyester line peaked at 14.5 MN for 53 kN converged, and at 2 ms overflowed).
        implicit_euler, stable at any step: an upper bound, divided into the fewest equal
        substeps no longer than the automatic step (at 10 ms the same jerk of the reference
        wire line peaked at 120 MN for 0.11 MN converged; the automatic step stays within
        0.49 to 1.13 times the converged peak on 10 jerks of the two lines).

        :raises ParameterError: improved_euler's time_step is above its stability limit.
        """
        if params.time_step == 0.0:
            dt = automatic_time_step(props, params.integrator)
        elif params.integrator == 'improved_euler':
            limit = stability_limit(props)
            if params.time_step > limit:
                largest = _round_down(limit)
                raise ParameterError(
                    f"time_step {params.time_step:g} s is above improved_euler's stability "
                    f'limit for this line (largest stable step {largest:g} s): set time_step '
                    f'<= {largest:g} or 0 (automatic)')
            dt = params.time_step
        else:
            automatic = automatic_time_step(props, params.integrator)
            dt = params.time_step / math.ceil(params.time_step / automatic - 1e-9)
        if self._output_interval > 0.0:
            dt = self._output_interval / math.ceil(self._output_interval / dt - 1e-9)
        return dt

    @property
    def started(self) -> bool:
        """Tell whether the rope has been placed."""
        return self.system is not None

    @property
    def reach(self) -> float:
        """
        Farthest the ends can be apart [m], L (1 + strain limit) at L now; inf once parted.

        The strain limit is max_strain, or on a curve line the strain of twice its MBL
        (RopeProperties.strain_limit): the strain limit the kernels hold the segments to.
        """
        if self.parting is not None:
            return math.inf
        return self.length * (1.0 + self.props.strain_limit)

    @property
    def line_props(self) -> RopeProperties:
        """Return props at the length the winch has given the line now."""
        if self.props.length == self.length:
            return self.props
        if getattr(self, '_line_props', (None, None))[0] is not self.props or \
                self._line_props[1].length != self.length:
            self._line_props = (self.props, replace(self.props, length=self.length))
        return self._line_props[1]

    # -- the winch and parting ------------------------------------------------------------

    def winch(self) -> Winch:
        """Return the fairlead's winch as the parameters and the last command set it."""
        p = self.params
        command = self._winch_command
        if p.winch_mode == 'constant_tension':
            command = p.winch_tension or self._held_tension
            if not math.isfinite(command):
                command = 0.0
        return Winch(mode=p.winch_mode, end=1, command=command, max_speed=p.winch_max_speed,
                     acceleration=p.winch_acceleration,
                     brake_load=p.winch_brake_load or BRAKE_FRACTION * self.props.mbl,
                     min_length=p.winch_min_length or MIN_LENGTH_FRACTION * p.length,
                     max_length=p.winch_max_length or MAX_LENGTH_FRACTION * p.length)

    @property
    def break_load(self) -> float:
        """Return the load a segment parts at [N]: break_load or the MBL; inf if parting is off."""
        if not self.params.parting:
            return math.inf
        return self.params.break_load or self.props.mbl

    def command_winch(self, speed: float) -> None:
        """
        Command the winch's speed [m/s] (+ pays out): a speed winch runs at it from the next step.

        Within winch_max_speed; a winch in another mode keeps it for when it is set to speed.

        :raises ParameterError: speed is not a finite number.
        """
        if not (isinstance(speed, (int, float)) and math.isfinite(speed)):
            raise ParameterError(f'winch speed {speed!r} is not allowed: must be a finite '
                                 'number [m/s] (+ pays out)')
        self._winch_command = float(speed)
        if self.system is not None:
            self.system.set_winch(self.index, command=self.winch().command)

    def _apply_winch(self) -> None:
        """Give the line the winch and break load the parameters ask for now."""
        p = self.params
        if p.winch_mode == 'constant_tension' and not p.winch_tension and \
                not math.isfinite(self._held_tension):
            self._held_tension = float(np.linalg.norm(self.system.loads()[0][self.index, 1]))
        line = self.rope
        line.break_load = self.break_load
        line.winch = self.winch()
        self.system.refresh()

    def restore(self) -> None:
        """Give the line back its length and, if it parted, its whole rope; restart it."""
        self.length = self.params.length
        self.parting = None
        self._held_tension = math.nan
        if self.started:
            self.restart()

    def check_update(self, values: dict) -> None:
        """
        Refuse run-time parameter changes that update() could not apply; change nothing.

        :raises ParameterError: a bad value, or one that makes the fixed time_step unstable
            (e.g. axial_damping lowered under improved_euler); the message says why.
        """
        self._updated(values)

    def _updated(self, values: dict) -> tuple:
        params = self.params.with_values(values)
        props = rope_properties(params, self.material)
        try:
            time_step = self._choose_time_step(params, props)
        except ParameterError as e:
            changes = ', '.join(f'{k} = {v}' for k, v in values.items())
            raise ParameterError(f'with {changes}, {e}') from None
        return params, props, time_step

    def update(self, values: dict) -> None:
        """
        Apply run-time parameter changes (damping, drag, max_strain, current, ...) at once.

        The rope goes on from where it is (no restart): a new current acts from the next
        step (System.set_current).

        :raises ParameterError: as check_update (nothing is changed then).
        """
        before = self.params
        self.params, self.props, self.time_step = self._updated(values)
        winch = (self.params.winch_mode, self.params.winch_tension)
        if winch != (before.winch_mode, before.winch_tension):
            self._held_tension = math.nan  # constant_tension takes the tension of now
        if self.system is not None:
            self.rope.line_type = self.props.line_type
            self._apply_winch()  # also refreshes the tables
            if tuple(self.system.environment.current) != self.props.current:
                self.system.set_current(self.props.current)

    # -- inputs -------------------------------------------------------------------------

    def push_fairlead(self, t: float, position) -> str:
        """
        Add a fairlead sample; return 'teleport' if it restarted the rope, else ''.

        A sample farther than teleport_distance from the newest one is a jump no rope can
        follow (its ends would be dragged through the step): the end's samples so far are
        forgotten and the rope restarts at rest on the catenary to the new place, at the
        state time (outputs stay on their grid). last_jump is the distance [m].

        :raises TrajectoryError: non-finite or not newer than the last sample (state unchanged).
        """
        return self._push(self.fairlead, t, position, None)

    def push_bollard(self, t: float, position) -> str:
        """
        Add a bollard sample; return 'teleport' if it restarted the rope (see push_fairlead).

        Before the first bollard sample the bollard is at bollard_position: a first sample
        farther than teleport_distance from there is a jump too. With a payload the bollard
        end is free: its samples are kept but move nothing, and restart nothing.
        """
        return self._push(self.bollard, t, position, self.params.bollard_position)

    def _push(self, end: EndTrajectory, t: float, position, rest) -> str:
        """Push a sample to one end's trajectory; restart the rope after a jump (see above)."""
        last = end.last_position if len(end) else rest
        settled = end.settled_until
        end.push(t, position)
        started = self.started
        self._off_track |= started and self.time > settled
        self.last_jump = 0.0 if last is None else math.dist(position, last)
        if end is self.bollard and self.payload:
            return ''
        if started and self.last_jump > self.params.teleport_distance:
            end.clear()
            end.push(t, position)
            self.restart()  # the end rests at its only sample until then
            return 'teleport'
        return ''

    def set_output_interval(self, interval: float) -> None:
        """Choose the substep again so that it divides a new output interval [s] (0: any)."""
        self._output_interval = interval
        self.time_step = self._choose_time_step(self.params, self.props)

    def ends_at(self, times: np.ndarray) -> tuple:
        """
        End positions and velocities the rope follows at `times`: arrays (n, 2, 3), bollard first.

        A fairlead farther from the bollard than the line's reach is held at the reach. With
        a payload the rope follows the fairlead only: the bollard's columns repeat it.
        """
        return self.drive(times)[:2]

    def free_ends(self, times: np.ndarray) -> tuple:
        """
        Return the ends where their samples put them at `times`, not held: (n, 2, 3) twice.

        The bollard is at bollard_position before its first sample; with a payload the
        bollard's columns repeat the fairlead (a free end follows no track).
        """
        times = np.atleast_1d(np.asarray(times, dtype=float))
        ends = np.empty((len(times), 2, 3))
        velocities = np.zeros((len(times), 2, 3))
        ends[:, 1], velocities[:, 1] = self.fairlead.sample(times)
        fixed = self.fixed_bollard
        if self.payload:
            ends[:, 0], velocities[:, 0] = ends[:, 1], velocities[:, 1]
        elif fixed is None:
            ends[:, 0], velocities[:, 0] = self.bollard.sample(times)
        else:
            ends[:, 0] = fixed
        return ends, velocities

    @property
    def fixed_bollard(self) -> Optional[Sequence[float]]:
        """Return where the bollard stands while it has no samples (and no payload), or None."""
        if self.payload or len(self.bollard):
            return None
        return self.params.bollard_position

    def drive(self, times: np.ndarray) -> tuple:
        """
        Return what drives the rope's ends at `times`: ends_at(times) and the distances.

        :returns: ends, velocities (n, 2, 3), bollard first, the fairlead held within reach;
            and the end distances [m] before holding, (n,) (zeros with a payload: nothing
            to hold).
        """
        ends, velocities = self.free_ends(times)
        if self.payload:  # a free end: nothing to hold
            return ends, velocities, np.zeros(len(ends))
        return ends, velocities, self._hold_within_reach(ends, velocities)

    def reach_steps(self, distances: np.ndarray) -> tuple:
        """
        Return, over coming steps, where the fairlead is beyond reach and where it is back.

        :param distances: the end distances [m] at the steps (drive's), (n,).
        :returns: beyond (n,): the ends are farther apart than the reach (the fairlead is
            held at it); back (n,): they are within it again after a held step (held before
            the first): the rope restarts at rest at the first such step (see advance_to).
        """
        beyond = distances > self.reach
        return beyond, ~beyond & np.append(self.held, beyond[:-1])

    def _hold_within_reach(self, ends: np.ndarray, velocities: np.ndarray) -> np.ndarray:
        """
        Hold a fairlead beyond the line's reach at the reach (in place); return the distances.

        No rope state joins ends farther apart than L (1 + max_strain): the strain limit
        cannot be met, every spring stays past it, and the tension grows with the distance
        (a fairlead three lengths away published 95 MN, one at x = 1e9 m 3.7e15 N). Held on
        the line from the bollard, the rope becomes a straight line at its limit, pulling
        along that line with EA max_strain. The held end keeps the sideways part of the
        relative velocity, scaled to the reach: it is the velocity of the held point.
        advance_to restarts the rope at rest once the ends are back within reach.

        :returns: the distance [m] between the ends of each sample before holding.
        """
        distance = end_distances(ends)
        self.hold_beyond_reach(ends, velocities, distance)
        return distance

    def hold_beyond_reach(self, ends: np.ndarray, velocities: np.ndarray,
                          distance: np.ndarray) -> None:
        """Hold the fairlead at the reach where `distance` (the ends' apart) is beyond it."""
        reach = self.reach
        if distance.max() > reach:
            beyond = distance > reach
            chord = ends[:, 1] - ends[:, 0]
            scale = reach / distance[beyond]
            u = chord[beyond] / distance[beyond, None]
            relative = velocities[beyond, 1] - velocities[beyond, 0]
            sideways = relative - np.einsum('ij,ij->i', relative, u)[:, None] * u
            ends[beyond, 1] = ends[beyond, 0] + reach * u
            velocities[beyond, 1] = velocities[beyond, 0] + scale[:, None] * sideways

    # -- time ---------------------------------------------------------------------------

    def start(self, t: float, shape: Optional[np.ndarray] = None) -> None:
        """
        Place the rope at rest at time t: in equilibrium between the ends, or at `shape`.

        :raises TrajectoryError: no fairlead sample yet.
        """
        if not len(self.fairlead):
            raise TrajectoryError('cannot start the rope before the first fairlead sample')
        self.restart(t)
        if shape is not None:
            self._place(self._build(np.asarray(shape, dtype=float)))

    def restart(self, t: Optional[float] = None) -> None:
        """
        Put the rope back at rest between the ends (at its current time).

        The catenary in its environment (integrators.start_shape: submerged weight below
        the surface, laid on the seabed where it reaches it), brought to rest under the
        bending springs, the fluids and the ground too (integrators.relax); the start shape
        itself wherever that fails, and with the fairlead held at the reach. With a
        payload: hanging straight down from the fairlead (hanging_shape), likewise brought
        to rest.
        """
        t = self.time if t is None else t
        ends, _, distances = self.drive([t])
        self.held = bool(distances[0] > self.reach)
        p = self.line_props
        if self.payload:
            shape = hanging_shape(p, ends[0, 1])
        else:
            shape = start_shape(p.line_type, p.environment, ends[0, 0], ends[0, 1], p.length,
                                p.segments)
        alone = self._build(shape)
        if not self.held and (not relax(p, alone) or self._unphysical(system=alone)):
            alone = self._build(shape)
        self._place(alone)
        self._apply_winch()
        self.time = t

    def _place(self, alone: System) -> None:
        """Make the line of `alone` (a System of it only) the rope: its System, or its share."""
        if self._shared:
            self.system.load_line(self.index, alone)
        else:
            self.system, self.index = alone, 0

    def _build(self, shape: np.ndarray) -> System:
        """
        Make the System of the line at rest at `shape` (N+1, 3), its ends on the points.

        At the winch's length now, parted where it parted; its winch and break load are
        _apply_winch's to give (a line being brought to rest has neither).
        """
        p = self.line_props
        if shape.shape != (p.segments + 1, 3):
            raise ValueError(
                f'shape must have shape ({p.segments + 1}, 3), got {shape.shape}')
        system = System(p.environment)
        if self.payload:
            system.add_point(Point('free', shape[0], mass=p.payload_mass,
                                   volume=p.payload_volume, drag_area=p.payload_drag_area,
                                   added_mass=p.payload_added_mass))
        else:
            system.add_point(Point('driven', shape[0]))
        system.add_point(Point('driven', shape[-1]))
        line = Line.uniform(p.line_type, p.length, p.segments, shape, (0, 1))
        if self.parting is not None:
            line.parted = self.parting.segment
        system.add_line(line)
        system.pack()
        return system

    def advance_to(self, t: float, max_steps: Optional[int] = None) -> Advance:
        """
        Advance the rope in fixed substeps up to t (at most max_steps of them).

        A state that turns non-finite, or whose end forces or strains go past the line's
        tension_bound, is never kept: the rope restarts at rest on the catenary. So it does
        at the first step at which the ends are back within reach after the fairlead was
        held at the reach: a line held at its strain limit stores 1/2 EA max_strain^2 L
        (22 MJ on the default line), which released would whip it at up to c max_strain
        (630 m/s) with segments snapping to the limit and MN tensions for tens of seconds:
        the energy of a line that in truth could not reach, not of the motion.

        A Simulator sharing its System (share_system) is stepped by the System's owner.
        """
        if self._shared:
            raise RuntimeError('a line sharing its System is stepped by its owner')
        dt = self.time_step
        steps = max(0, int(math.floor((t - self.time) / dt + 1e-9)))
        if max_steps is not None:
            steps = min(steps, max_steps)
        if steps == 0:
            return Advance(0, t - self.time)
        times = self.time + dt * np.arange(1, steps + 1)
        ends, velocities, distances = self.drive(times)
        beyond_reach = 0.0
        if self.held or distances.max() > self.reach:
            beyond, back = self.reach_steps(distances)
            beyond_reach = float(distances[beyond].max()) if beyond.any() else 0.0
            back = np.flatnonzero(back)
            if back.size:
                k = int(back[0])
                if k:
                    self._step(times[:k], ends[:k], velocities[:k])
                self.restart(float(times[k]))
                rest = self.advance_to(t, None if max_steps is None else max_steps - k - 1)
                return Advance(steps, rest.lag, rest.restarted or 'back within reach',
                               max(beyond_reach, rest.beyond_reach))
            self.held = bool(beyond[-1])
        parting = self.parting
        self._step(times, ends, velocities)
        restarted = self._unphysical(motion_spread(self.rope.v, velocities)[1])
        if restarted:
            self.restart()
        return Advance(steps, t - self.time, restarted, beyond_reach,
                       self.parting if self.parting is not parting else None)

    def _step(self, times: np.ndarray, ends: np.ndarray, velocities: np.ndarray) -> None:
        """
        Take the substeps to `times` with the ends there (blended onto their tracks).

        A step in which a particle would move more than MAX_STEP_MOTION of a segment
        against the bollard is divided until none does (the step the user chose stays the
        largest). A line let go at its strain limit flings its particles at up to
        c max_strain (630 m/s on the default line, 3 m in one 5 ms implicit step on a
        0.8 m segment): the implicit step, linearised about a shape it has left far
        behind, then stretched every spring far past the limit each step and kept the
        line whipping at the limit with MN tensions for as long as it ran; divided, the
        same release rings down as with the explicit step.
        """
        self.blend_ends(times, ends, velocities)
        parts, violent = self.divisions(velocities)
        if parts == 1:
            self._run(self.time_step, ends, velocities)
        elif not violent:  # only the explicit step's bounds: divide the whole run alike
            self._run_divided(divide_run(self.time, times, parts))
        else:
            for t in times:  # a violent stretch: look again before every step
                self._run_divided(divide_run(self.time, [t], self.divisions(velocities)[0]))
                self.time = float(t)
        self.time = float(times[-1])

    def _run_divided(self, fine: np.ndarray) -> None:
        """Take the steps to the divided times `fine`, the ends driven there."""
        ends, velocities, _ = self.drive(fine)
        self.blend_ends(fine, ends, velocities)
        self._run((fine[-1] - self.time) / len(fine), ends, velocities)

    def divisions(self, velocities: np.ndarray) -> Tuple[int, bool]:
        """
        Return into how many parts a step must be divided (see _step), and whether to look again.

        :param velocities: the ends' velocities over the coming steps (n, 2, 3) (drive's).
        :returns: the parts, and True when a violent stretch asks for them (a particle
            moving more than MAX_STEP_MOTION of a segment in a step): that changes from step
            to step, so the caller divides each step by what the line does then.

        Also, for improved_euler, until drag takes no more than the particle's speed in
        one part: its rate 2 K |u| / m (u: the speed through the fluid) is no part of the
        stability limit (it grows with the speed), and past 2 / step the explicit step blows
        up (K_A = 1e4 on the default line turned the state non-finite within 0.05 s of a 3 m
        jerk). K: the seed's K_A plus the fluid drag's 1/2 rho (Cd + pi CdAx) d in the
        densest fluid present (integrators.drag_rate). And until no part is longer than the
        automatic step of the line at its length now: a winch that hauls the line in
        shortens and stiffens its segments, and the step chosen for 40 m blew up at 26 m.
        These two bounds hold for a whole run of steps (one output interval): the ends'
        speeds are their largest over the run, and a winch changes the length by a small
        fraction of a segment in it (0.5 m/s over 20 ms: 1 cm of a 0.8 m segment).
        """
        spread, _, speed = motion_spread(self.rope.v, velocities)
        return self.divisions_for(spread, speed)

    def divisions_for(self, spread: float, speed: float) -> Tuple[int, bool]:
        """Return divisions() from the step's motion_spread: its spread and its speed bound."""
        p = self.line_props
        motion = spread * self.time_step / (MAX_STEP_MOTION * p.segment_length)
        parts = motion
        if self.params.integrator == 'improved_euler':
            parts = max(parts, self.time_step / self.fine_step_for(speed))
        if not parts > 1.0:  # also NaN: the state check restarts a non-finite rope
            return 1, False
        return math.ceil(min(parts, MAX_DIVISIONS)), motion > 1.0

    def fine_step(self, velocities: np.ndarray) -> float:
        """
        Return the largest improved Euler step [s] the line can take now (see divisions).

        The adaptive integrator's step through a snap: the automatic improved Euler step of
        the line at its length now, no longer than the drag takes the particles' speed in.

        :param velocities: the ends' velocities over the coming steps (n, 2, 3).
        """
        return self.fine_step_for(motion_spread(self.rope.v, velocities)[2])

    def fine_step_for(self, speed: float) -> float:
        """Return improved Euler's step at the line's length now and the particles' speed."""
        p = self.line_props
        if self._drag[0] is not p:  # once per props: drag_rate is linear in the speed
            own = p is self.props and self.params.integrator == 'improved_euler'
            stable = self.time_step if own else automatic_time_step(p)
            self._drag = (p, drag_rate(p, 1.0), stable)
        relative = speed + (math.hypot(*p.current) if p.has_water else 0.0)
        rate = self._drag[1] * relative
        return self._drag[2] if not rate * self._drag[2] > 1.0 else 1.0 / rate

    def _unphysical(self, end_speed: float = 0.0, system: Optional[System] = None) -> str:
        """
        Say what is wrong with the state ('' when nothing is): the one check of every output.

        Parting (a segment past break_load, the MBL by default) acts far below this bound.

        :param end_speed: the ends' largest speed over the steps just taken [m/s].
        :param system: the System to check (default: the rope's, of this line alone).
        """
        finite, largest = (system or self.system).largest_load()
        if not finite:
            return 'non-finite state'
        if not largest <= self.load_bound(end_speed):  # also NaN (an overflow)
            return 'unphysical state'
        return ''

    def load_bound(self, end_speed: float = 0.0) -> float:
        """
        Return the largest end force or EA strain [N] a physical state of the line can have.

        rope.tension_bound of the line at its length now, with its ends moving at up to
        end_speed [m/s]; a state past it is restarted (see advance_to).
        """
        props = self.line_props
        if self._bound[0] is not props:
            at_rest = tension_bound(props)
            self._bound = (props, at_rest, tension_bound(props, 1.0) - at_rest)
        _, at_rest, per_speed = self._bound
        return at_rest + per_speed * end_speed

    def blend_ends(self, times: np.ndarray, ends: np.ndarray, velocities: np.ndarray) -> None:
        """
        Bring an end that is off its trajectory back onto it (in place), never by a jump.

        Only a live node meets this: a pose stream that fell silent held the end, and its
        late samples then moved the trajectory away from where the rope has the end.
        The offline runner's ends are always on their trajectories: its numbers never
        change here.
        """
        if not self._off_track and self._blends[0] is None and self._blends[1] is None:
            return  # the common case, and the offline runner's only one: nothing to check
        self._off_track = False
        here, here_velocities = self.ends_at([self.time])
        for k, particle in ((0, 0), (1, -1)):
            if k == 0 and self.payload:  # a free end follows no track
                continue
            offset = self.rope.x[particle] - here[0, k]
            blend = self._blends[k]
            if np.abs(offset).max() <= END_TOLERANCE:
                self._blends[k] = None
                continue
            if blend is None or np.abs(blend.at([self.time])[0][0] - offset).max() > END_TOLERANCE:
                # a new departure from the trajectory: fade it out from the rope's own motion
                rate = self.rope.v[particle] - here_velocities[0, k]
                blend = self._blends[k] = EndBlend(self.time, END_BLEND_TIME, offset, rate)
            offsets, rates = blend.at(times)
            ends[:, k] += offsets
            velocities[:, k] += rates

    def _run(self, dt: float, ends: np.ndarray, velocities: np.ndarray) -> None:
        """Take len(ends) substeps of dt: ends, velocities (n, 2, 3) drive points 0 and 1."""
        fine = self.fine_step(velocities) if self.params.integrator == 'adaptive' else 0.0
        parted = step(self.system, self.params.integrator, dt, ends, velocities, MAX_ITERATIONS,
                      implicit_bending(self.props, dt), self.compiled, fine)
        self.follow_run(dt, parted)

    def follow_run(self, dt: float, parted: list) -> None:
        """
        Take in what a run of steps of dt from the state time did to the line.

        Its length (the winch's) and its parting. Call it before moving the state time on.

        :param parted: System.step's (line index, step of the run) of the lines that parted.
        """
        self.length = self.system.unstretched_length(self.index)
        for k, at in parted:
            if k == self.index:
                self.parting = Parting(self.time + (at + 1) * dt, self.rope.parted,
                                       self.break_load)

    def skip_to(self, t: float) -> None:
        """
        Move the state time to t without simulating.

        The particles stay where they are, so after more than rounding the ends are brought
        back onto their tracks over END_BLEND_TIME: follow a long skip with restart().
        """
        if abs(t - self.time) > 1e-6 * self.time_step:  # more than pinning an output time
            self._off_track = True
        self.time = t

    def output(self) -> Output:
        """
        Return the current state: particles, end forces, the largest strain, the winch.

        The peaks are those since the previous output (this call clears them).
        """
        bollard, fairlead, strain = self._forces()
        position = velocity = None
        if self.payload:
            bollard_point = self.rope.ends[0]
            position = self.system.point_x[bollard_point].copy()
            velocity = self.system.point_v[bollard_point].copy()
        peaks = take_peaks(self.system, [self.index])[0]
        return Output(self.time, self.rope.x.copy(), fairlead, bollard, strain, position,
                      velocity, peaks[1], peaks[0], self.length,
                      self.system.winch_speed(self.index), self.parting is not None)

    def _forces(self) -> tuple:
        """Return the forces on the bollard and the fairlead and the largest strain."""
        forces, strains = self.system.loads()
        return forces[self.index, 0], forces[self.index, 1], float(strains[self.index])


def divide_run(start: float, times: Sequence[float], parts: int) -> np.ndarray:
    """Return the times of the steps from start to times' last, each of times' cut in parts."""
    count = len(times) * parts
    return start + (times[-1] - start) * np.arange(1, count + 1) / count


def take_peaks(system: System, lines=slice(None)) -> np.ndarray:
    """
    Return the lines' peak end tensions since the previous output, (L, 2) [N]; clear them.

    Every step's largest (System.take_peaks), and the tension now: an output's peak is never
    below its own tension.

    :param lines: which of the System's lines (an index list or a slice).
    """
    forces = system.loads()[0][lines]
    return np.maximum(system.take_peaks(lines), np.sqrt((forces * forces).sum(axis=2)))


def share_system(sims: Sequence[Simulator]) -> System:
    """
    Put the started lines of `sims` in one new System; make it each Simulator's from now on.

    Line j of the System is sims[j]'s rope, between points 2 j (its bollard) and 2 j + 1
    (its fairlead), with all it had: its state, winch, parting and held peaks. One step of
    the System steps every line exactly as its Simulator would alone at that step (the
    kernels step each line whose ends are fixed or driven on its own). The caller steps it
    (see the Simulator's docstring); each Simulator keeps its rules, and its restarts,
    teleports, winch commands and parameter changes act on its line in the System.

    :param sims: started Simulators with one environment and integrator.
    """
    system = System(sims[0].props.environment)
    for j, sim in enumerate(sims):
        rope = sim.rope
        for q in rope.ends:
            point = sim.system.points[q]
            system.add_point(Point(point.kind, point.position.copy(), point.mass,
                                   point.velocity.copy(), point.volume, point.drag_area,
                                   point.added_mass))
        system.add_line(Line(rope.line_type, rope.rest.copy(), rope.x.copy(),
                             (2 * j, 2 * j + 1)))
    system.pack()
    for j, sim in enumerate(sims):
        system.load_line(j, sim.system, sim.index)
        sim.system, sim.index, sim._shared = system, j, True
    return system
