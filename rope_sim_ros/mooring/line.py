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
One line of a mooring: its parameters as the model's numbers, and the rules of that line.

A MooringLine knows what its line is (its RopeProperties, its material's MBL and WLL), the
step it takes (the one rule of time_step), how far its ends can be apart (its reach), what
a physical state of it can pull (its load bound), its winch and its parting, and how it
starts at rest between two ends: in a System of its own, which the Mooring then puts in the
System its group shares. It steps nothing itself: the Mooring steps every line of a group
at once, with these rules as arrays of the group (GroupRules). What it lives in is the
mooring's one Environment, which the rules that depend on it (the step, the load bound, the
shape at rest) are given.
"""

from dataclasses import dataclass, replace
import math
from typing import Optional

import numpy as np

from ..model.materials import MaterialLibrary
from ..model.objects import Environment, Line, Point, System, Winch
from ..model.rope import RopeProperties, tension_bound
from ..model.statics.start import hanging_shape, start_shape
from ..params.resolve import rope_properties
from ..params.table import LineParams, ParameterError
from ..stepping.relax import relax
from ..stepping.rules import automatic_time_step, drag_rate, stability_limit

# The shortest improved Euler step a line may need [s]: the adaptive integrator's step in a
# snap, improved_euler's automatic step. One core takes 57,000 improved Euler steps of a
# 30-segment line a second (benchmarks: a 2-core machine, loaded): a line that needs steps
# under this cannot keep up with the clock while it takes them. Damping sets it: the berth's
# head line takes 2.5 ns at axial_damping 1e9 N s, whose first snap then stalled the mooring
# node (two million steps per 5 ms step), 25 us at 1e5.
MIN_EXPLICIT_STEP = 1.0e-5

# The winch's defaults (params/table.py): its brake holds 60 % of the MBL (OCIMF MEG4); it
# hauls in to a tenth of the line's length and pays out to four times it.
BRAKE_FRACTION = 0.6
MIN_LENGTH_FRACTION = 0.1
MAX_LENGTH_FRACTION = 4.0


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


def _round_down(value: float) -> float:
    """Return value rounded down to 2 significant digits (a step that is safe to quote)."""
    shown = float(f'{value:.2g}')
    if shown > value:
        exponent = math.floor(math.log10(value)) - 1
        shown = float(f'{shown - 10.0 ** exponent:.2g}')
    return shown


def choose_time_step(params: LineParams, props: RopeProperties, environment: Environment,
                     output_interval: float = 0.0) -> float:
    """
    Return the step of a line with these parameters: the one rule of time_step.

    0: automatic. improved_euler: time_step itself, refused above the step its line can
    take stably (stability_limit: at 1.9 times it, 0.5 ms, a 2.5 m jerk of the reference
    polyester line peaked at 14.5 MN for 53 kN converged, and at 2 ms overflowed).
    implicit_euler and adaptive, stable at any step: an upper bound, divided into the fewest
    equal substeps no longer than the automatic step (at 10 ms the same jerk of the
    reference wire line peaked at 120 MN for 0.11 MN converged; the automatic step stays
    within 0.49 to 1.13 times the converged peak on 10 jerks of the two lines). With an
    output interval, the step is shortened to divide it, so that outputs fall on steps.

    :raises ParameterError: improved_euler's time_step is above its stability limit.
    """
    if params.time_step == 0.0:
        dt = automatic_time_step(props, environment, params.integrator)
    elif params.integrator == 'improved_euler':
        limit = stability_limit(props, environment)
        if params.time_step > limit:
            largest = _round_down(limit)
            raise ParameterError(
                f"time_step {params.time_step:g} s is above improved_euler's stability "
                f'limit for this line (largest stable step {largest:g} s): set time_step '
                f'<= {largest:g} or 0 (automatic)')
        dt = params.time_step
    else:
        automatic = automatic_time_step(props, environment, params.integrator)
        dt = params.time_step / math.ceil(params.time_step / automatic - 1e-9)
    if output_interval > 0.0:
        dt = output_interval / math.ceil(output_interval / dt - 1e-9)
    return dt


def _explicit_step(params: LineParams, props: RopeProperties,
                   environment: Environment) -> float:
    """Return the improved Euler step a line takes (inf: it takes none)."""
    if params.integrator == 'adaptive' or (params.integrator == 'improved_euler'
                                           and params.time_step == 0.0):
        return automatic_time_step(props, environment)
    return math.inf


def check_pace(params: LineParams, props: RopeProperties, material,
               environment: Environment) -> None:
    """
    Refuse an axial_damping that makes the line's improved Euler step shorter than it can run.

    See MIN_EXPLICIT_STEP. The message names the largest axial_damping the line takes (found
    by bisection: the step shrinks as the damping grows). A line whose step is that short
    without the damping (thousands of segments) is left alone: its steps are its size's.

    :raises ParameterError: the damping makes the step shorter than MIN_EXPLICIT_STEP.
    """
    step = _explicit_step(params, props, environment)
    if step >= MIN_EXPLICIT_STEP or params.axial_damping <= 0.0:
        return

    def step_at(damping: float) -> float:
        return _explicit_step(params, rope_properties(
            params.with_values({'axial_damping': damping}), material), environment)

    if step_at(0.0) < MIN_EXPLICIT_STEP:
        return
    low, high = 0.0, params.axial_damping  # the step is long enough at low, too short at high
    for _ in range(40):
        middle = 0.5 * (low + high)
        if step_at(middle) >= MIN_EXPLICIT_STEP:
            low = middle
        else:
            high = middle
    largest = _round_down(low) if low > 0.0 else 0.0
    raise ParameterError(
        f'axial_damping {params.axial_damping:g} N s is not allowed on this line: it makes '
        f"{params.integrator}'s improved Euler step {step:.2g} s, under the "
        f'{MIN_EXPLICIT_STEP:g} s that runs at live pace; allowed: up to {largest:g} N s (or '
        'integrator implicit_euler)')


class MooringLine:
    """
    One line's numbers and rules (see the module docstring).

    :ivar name: the line's name (its parameter prefix and topic namespace in a mooring).
    :ivar params: its parameters in force.
    :ivar material: its material's properties at its diameter (MBL, WLL, ...).
    :ivar props: its RopeProperties at its parameters' length.
    :ivar time_step: its step [s].
    :ivar length: its unstretched length now [m] (the winch changes it).
    :ivar parting: how it parted, None while whole (until restore()).
    :ivar state: 'fast' (its eye on its bollard), 'free' (let go: its bollard end a free
        end) or 'stowed' (aboard: no force, not stepped): handling.py changes it.
    """

    def __init__(self, name: str, params: LineParams, materials: MaterialLibrary,
                 environment: Environment, output_interval: float = 0.0):
        """
        Resolve the line's parameters, for a line in this environment (its step's).

        :raises ParameterError / MaterialError / ValueError: it cannot be built; the
            message says why.
        """
        self.name = name
        self.params = params
        self.material = materials.properties(params.material, params.diameter)
        self.props = rope_properties(params, self.material)
        self.output_interval = output_interval
        self.time_step = choose_time_step(params, self.props, environment, output_interval)
        check_pace(params, self.props, self.material, environment)
        self.length = params.length
        self.parting: Optional[Parting] = None
        if params.start_state == 'stowed' and params.has_payload:
            raise ParameterError('start_state stowed is not allowed for a line with a '
                                 'payload: a payload hangs from the fairlead from the start')
        self.state = params.start_state
        self.let_go_at = math.nan  # when it was last let go [s]
        self.winch_command = 0.0  # the speed last commanded [m/s]
        self.held_tension = math.nan  # constant_tension with winch_tension 0: the one held
        self._line_props = (None, None)  # (props, props at the length now)
        self._rules = (None, ())  # (what they were worked out from, rules())

    # -- what the line is now -------------------------------------------------------------

    @property
    def payload(self) -> bool:
        """Tell whether the bollard end is a free payload: payload_mass > 0."""
        return self.params.has_payload

    @property
    def free_end(self) -> bool:
        """Tell whether the bollard end is a free end: a payload's, or a line let go."""
        return self.state == 'free' or self.params.has_payload

    @property
    def stepped(self) -> bool:
        """Tell whether the line is out (fast or free), stepped in a group; not stowed."""
        return self.state != 'stowed'

    @property
    def line_props(self) -> RopeProperties:
        """Return props at the length the winch has given the line now."""
        if self.props.length == self.length:
            return self.props
        if self._line_props[0] is not self.props or self._line_props[1].length != self.length:
            self._line_props = (self.props, replace(self.props, length=self.length))
        return self._line_props[1]

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
    def break_load(self) -> float:
        """Return the load a segment parts at [N]: break_load or the MBL; inf if parting is off."""
        if not self.params.parting:
            return math.inf
        return self.params.break_load or self.props.mbl

    def load_bound(self, environment: Environment) -> tuple:
        """
        Return the largest end force or EA strain [N] a physical state can have, as two terms.

        rope.tension_bound of the line at its length now, at rest and its growth per m/s of
        the ends (it is linear in their speed): a state past at_rest + per_speed * speed is
        restarted.
        """
        props = self.line_props
        at_rest = tension_bound(props, environment)
        return at_rest, tension_bound(props, environment, 1.0) - at_rest

    def fine_step(self, environment: Environment) -> tuple:
        """
        Return improved Euler's step at the line's length now: its stable step and drag rate.

        The adaptive integrator's step through a snap (and improved_euler's bound on drag):
        the automatic improved Euler step of the line at its length now (its own step, for
        improved_euler at its parameters' length), no longer than the drag takes the
        particles' speed in: 1 / (rate (speed + current)), rate the drag's per m/s
        (stepping/rules.py's drag_rate). Returns (stable step [s], drag rate per m/s [1/s
        per m/s], current speed [m/s] where there is water).
        """
        props = self.line_props
        own = props is self.props and self.params.integrator == 'improved_euler'
        stable = self.time_step if own else automatic_time_step(props, environment)
        water = math.isfinite(environment.water_level)
        current = math.hypot(*environment.current) if water else 0.0
        return stable, drag_rate(props, environment, 1.0), current

    def rules(self, environment: Environment) -> tuple:
        """
        Return the rules of its every step in the environment, kept while its numbers hold.

        (reach, segment length now, fine_step's three numbers, load_bound's two): what a
        group holds as arrays (group.py's GroupRules); worked out again only when the
        line's properties, length, parting, step or environment change.
        """
        key = (self.props, self.length, self.parting, self.time_step, environment)
        if self._rules[0] != key:
            self._rules = (key, (self.reach, self.line_props.segment_length,
                                 *self.fine_step(environment), *self.load_bound(environment)))
        return self._rules[1]

    def winch(self) -> Winch:
        """Return the fairlead's winch as the parameters and the last command set it."""
        p = self.params
        command = self.winch_command
        if p.winch_mode == 'constant_tension':
            command = p.winch_tension or self.held_tension
            if not math.isfinite(command):
                command = 0.0
        return Winch(mode=p.winch_mode, end=1, command=command, max_speed=p.winch_max_speed,
                     acceleration=p.winch_acceleration,
                     brake_load=p.winch_brake_load or BRAKE_FRACTION * self.props.mbl,
                     min_length=p.winch_min_length or MIN_LENGTH_FRACTION * p.length,
                     max_length=p.winch_max_length or MAX_LENGTH_FRACTION * p.length)

    # -- at rest -----------------------------------------------------------------------------

    def at_rest(self, ends: np.ndarray, held: bool, environment: Environment) -> System:
        """
        Return a System of this line alone at rest between its ends (2, 3) [m].

        The catenary in the environment (start_shape: submerged weight below the surface,
        laid on the seabed where it reaches it), brought to rest under the bending springs,
        the fluids and the ground too (relax); the start shape itself wherever that fails
        or the ends are held at the reach. With a free end (a payload, a line let go):
        hanging straight down from the fairlead (hanging_shape), likewise brought to rest.
        """
        p = self.line_props
        if self.free_end:
            shape = hanging_shape(p, environment, ends[1])
        else:
            shape = start_shape(p.line_type, environment, ends[0], ends[1], p.length,
                                p.segments)
        alone = self.build(shape, environment)
        if not held and (not relax(p, alone) or not self._physical(alone, environment)):
            alone = self.build(shape, environment)
        return alone

    def parted_if_overloaded(self, t: float, alone: System) -> System:
        """
        Return its rest state at a (re)start at t, parted if that state passes its break load.

        A line (re)started where its ends are too far apart for it to hold its break load
        (a teleport past its reach, a skip or a reset there) has no whole rest state: it
        parts at once, at its most stretched segment, its two pieces laid unstretched along
        the line from their ends. Held whole at its reach it would pull EA x max_strain (up
        to 20 MN on the berth's springs) at the restart and in the step it parted in.

        :param alone: the line alone at rest (at_rest).
        """
        if self.parting is not None or self.free_end or not self.params.parting:
            return alone
        finite, largest = alone.largest_load()
        if finite and largest <= self.break_load:
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
        self.parting = Parting(t, segment, self.break_load)
        return self.build(shape, alone.environment)

    def _physical(self, system: System, environment: Environment) -> bool:
        """Tell whether a System of this line alone is finite and within its load bound."""
        finite, largest = system.largest_load()
        return finite and largest <= self.load_bound(environment)[0]

    def build(self, shape: np.ndarray, environment: Environment) -> System:
        """
        Make the System of the line at rest at `shape` (N+1, 3), its ends on the points.

        At the winch's length now, parted where it parted; its winch and break load are
        the Mooring's to give (a line being brought to rest has neither).
        """
        p = self.line_props
        if shape.shape != (p.segments + 1, 3):
            raise ValueError(f'shape must have shape ({p.segments + 1}, 3), got {shape.shape}')
        system = System(environment)
        if self.free_end:  # a line let go has no payload: its end is its own last particle
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

    # -- changes -------------------------------------------------------------------------

    def command_winch(self, speed: float) -> None:
        """
        Take a winch speed command [m/s] (+ pays out): a speed winch runs at it.

        :raises ParameterError: speed is not a finite number.
        """
        if not (isinstance(speed, (int, float)) and math.isfinite(speed)):
            raise ParameterError(f'winch speed {speed!r} is not allowed: must be a finite '
                                 'number [m/s] (+ pays out)')
        self.winch_command = float(speed)

    def restore(self) -> None:
        """Give the line back its length and, if it parted, its whole rope (in its state)."""
        self.length = self.params.length
        self.parting = None
        self.held_tension = math.nan

    def updated(self, values: dict, environment: Environment) -> tuple:
        """
        Return (params, props, time_step) with run-time changes applied; change nothing.

        :param environment: the environment the line is in then (its step's).

        :raises ParameterError: a bad value, or one that makes the fixed time_step unstable
            (e.g. axial_damping lowered under improved_euler); the message says why.
        """
        params = self.params.with_values(values)
        props = rope_properties(params, self.material)
        try:
            time_step = choose_time_step(params, props, environment, self.output_interval)
            check_pace(params, props, self.material, environment)
        except ParameterError as e:
            changes = ', '.join(f'{k} = {v}' for k, v in values.items())
            raise ParameterError(f'with {changes}, {e}') from None
        return params, props, time_step

    def update(self, values: dict, environment: Environment) -> None:
        """
        Apply run-time parameter changes (damping, drag, max_strain, a winch's, ...).

        Also for a new environment (values {}, or the shared ones it is made of): the step
        is the line's in it.

        :raises ParameterError: as updated() (nothing is changed then).
        """
        before = (self.params.winch_mode, self.params.winch_tension)
        self.params, self.props, self.time_step = self.updated(values, environment)
        if (self.params.winch_mode, self.params.winch_tension) != before:
            self.held_tension = math.nan  # constant_tension takes the tension of now

    def set_output_interval(self, interval: float, environment: Environment) -> None:
        """Choose the step again so that it divides a new output interval [s] (0: any)."""
        self.output_interval = interval
        self.time_step = choose_time_step(self.params, self.props, environment, interval)
