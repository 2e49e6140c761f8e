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
Drive a Rope through time from end trajectories.

The one simulator of the node, the offline runner and the tests.

Data flows one way: end samples -> trajectories -> fixed substeps -> rope state -> outputs.
"""

from dataclasses import dataclass
import math
import os
from pathlib import Path
import sys
from typing import List, Optional

import numpy as np

from .params import LineParams
from .physics import catenary
from .physics import kernels
from .physics.integrators import automatic_time_step, implicit_bending, improved_euler_step
from .physics.materials import MaterialLibrary, MaterialProperties
from .physics.rope import critical_axial_damping, Rope, RopeProperties
from .physics.superelastic import adjust, MAX_ITERATIONS
from .trajectory import EndBlend, EndTrajectory, TrajectoryError

CONFIG_DIR = Path(__file__).resolve().parent.parent / 'config'
# An end found further than END_TOLERANCE [m] off its trajectory (late samples changed the
# trajectory under the rope) is brought back onto it over END_BLEND_TIME [s] (an EndBlend).
END_TOLERANCE = 1e-6
END_BLEND_TIME = 1.0  # see trajectory.py for what it costs


def default_config_dir() -> Path:
    """
    Find config/: the source tree's, else the installed share/rope_sim_ros/config.

    An installed package lives in <prefix>/lib/pythonX.Y/site-packages/rope_sim_ros, so its
    own prefix is tried first: an executable started without a sourced setup file (no
    AMENT_PREFIX_PATH) still finds its materials.
    """
    if (CONFIG_DIR / 'materials.yaml').exists():
        return CONFIG_DIR
    own_prefix = Path(__file__).resolve().parents[:5][-1]
    prefixes = [own_prefix, Path(sys.prefix)]
    prefixes += [Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    for prefix in prefixes:
        candidate = prefix / 'share' / 'rope_sim_ros' / 'config'
        if (candidate / 'materials.yaml').exists():
            return candidate
    return CONFIG_DIR


def load_materials() -> MaterialLibrary:
    """Load the material presets of config/materials.yaml."""
    return MaterialLibrary.from_file(default_config_dir() / 'materials.yaml')


def rope_properties(params: LineParams, material: MaterialProperties) -> RopeProperties:
    """Resolve the parameters into the physical numbers of the line."""
    mass = params.mass_per_length or material.mass_per_length
    ea = params.axial_stiffness or material.axial_stiffness
    ba = params.axial_damping or critical_axial_damping(params.length, mass, ea)
    return RopeProperties(
        segments=params.segments, length=params.length, mass_per_length=mass,
        axial_stiffness=ea, axial_damping=ba,
        bending_stiffness_ratio=params.bending_stiffness_ratio,
        bending_damping_ratio=params.bending_damping_ratio,
        damping_model=params.damping_model,
        air_drag_coefficient=params.air_drag_coefficient,
        gravity=tuple(params.gravity), max_strain=params.max_strain,
        superelastic_adjustment=params.superelastic_adjustment)


@dataclass(frozen=True)
class Output:
    """
    What the line looks like at one instant.

    :ivar t: state time [s].
    :ivar positions: particles (N+1, 3) [m], bollard first.
    :ivar fairlead_force: force of the line on the fairlead (3,) [N].
    :ivar bollard_force: force of the line on the bollard (3,) [N].
    :ivar max_strain: largest structural spring strain.
    """

    t: float
    positions: np.ndarray
    fairlead_force: np.ndarray
    bollard_force: np.ndarray
    max_strain: float

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
    :ivar restarted: why the rope was restarted ('' when it was not).
    """

    steps: int
    lag: float
    restarted: str = ''


class Simulator:
    """One mooring line between a bollard (particle 0) and a fairlead (particle N)."""

    def __init__(self, params: LineParams, materials: Optional[MaterialLibrary] = None,
                 output_interval: float = 0.0, compiled: bool = True,
                 history: float = 5.0):
        """
        Build the line; the rope is placed by start().

        :param params: validated parameters.
        :param materials: presets (default: config/materials.yaml).
        :param output_interval: if > 0, the automatic step is shortened to divide it, so that
            outputs fall on step times.
        :param compiled: step with the numba kernels (False: the numpy reference path).
        :param history: seconds of end samples kept behind the newest (math.inf offline, where
            a whole motion is pushed before the first step).

        :raises ParameterError / MaterialError / ValueError: the line cannot be built; the
            message says why.
        """
        self.params = params
        self.material = (materials or load_materials()).properties(
            params.material, params.diameter)
        self.props = rope_properties(params, self.material)
        self._coefficients = kernels.coefficients(self.props)
        self._output_interval = output_interval
        self.time_step = self._choose_time_step()
        self.compiled = compiled
        self.fairlead = EndTrajectory(keep=history, method=params.end_interpolation)
        self.bollard = EndTrajectory(keep=history, method=params.end_interpolation)
        self.rope: Optional[Rope] = None
        self.time = math.nan
        self._blends: List[Optional[EndBlend]] = [None, None]  # bollard, fairlead
        self._off_track = False  # a sample or a skip may have moved an end's track under it
        self._inv_mass = np.ones(params.segments + 1)
        self._inv_mass[[0, -1]] = 0.0

    def _choose_time_step(self) -> float:
        dt = self.params.time_step or automatic_time_step(self.props, self.params.integrator)
        if self._output_interval > 0.0:
            dt = self._output_interval / math.ceil(self._output_interval / dt - 1e-9)
        return dt

    @property
    def started(self) -> bool:
        """Tell whether the rope has been placed."""
        return self.rope is not None

    def update(self, values: dict) -> None:
        """Apply run-time parameter changes (damping, drag, max_strain, ...) at once."""
        self.params = self.params.with_values(values)
        self.props = rope_properties(self.params, self.material)
        self._coefficients = kernels.coefficients(self.props)
        if self.rope is not None:
            self.rope.props = self.props
        self.time_step = self._choose_time_step()

    # -- inputs -------------------------------------------------------------------------

    def push_fairlead(self, t: float, position) -> str:
        """
        Add a fairlead sample; return 'teleport' if it restarted the rope, else ''.

        :raises TrajectoryError: non-finite or not newer than the last sample (state unchanged).
        """
        last, settled = self.fairlead.last_position, self.fairlead.settled_until
        self.fairlead.push(t, position)
        self._off_track |= self.started and self.time > settled
        if self.started and math.dist(position, last) > self.params.teleport_distance:
            self.fairlead.clear()
            self.fairlead.push(t, position)
            self.restart(max(t, self.time))
            return 'teleport'
        return ''

    def push_bollard(self, t: float, position) -> None:
        """Add a bollard sample (see push_fairlead)."""
        settled = self.bollard.settled_until
        self.bollard.push(t, position)
        self._off_track |= self.started and self.time > settled

    def ends_at(self, times: np.ndarray) -> tuple:
        """End positions and velocities at `times`: arrays (n, 2, 3), bollard first."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        ends = np.empty((len(times), 2, 3))
        velocities = np.zeros((len(times), 2, 3))
        ends[:, 1], velocities[:, 1] = self.fairlead.sample(times)
        if len(self.bollard):
            ends[:, 0], velocities[:, 0] = self.bollard.sample(times)
        else:
            ends[:, 0] = self.params.bollard_position
        return ends, velocities

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
            self.rope = Rope(self.props, shape)

    def restart(self, t: Optional[float] = None) -> None:
        """Put the rope back on the catenary between the ends (at its current time)."""
        t = self.time if t is None else t
        ends, _ = self.ends_at([t])
        p = self.props
        shape = catenary.initial_shape(
            ends[0, 0], ends[0, 1], p.length, p.segments, p.weight_per_length,
            p.axial_stiffness, np.asarray(p.gravity))
        self.rope = Rope(p, shape)
        self.time = t

    def advance_to(self, t: float, max_steps: Optional[int] = None) -> Advance:
        """
        Advance the rope in fixed substeps up to t (at most max_steps of them).

        A state that turns non-finite is never kept: the rope restarts on the catenary.
        """
        dt = self.time_step
        steps = max(0, int(math.floor((t - self.time) / dt + 1e-9)))
        if max_steps is not None:
            steps = min(steps, max_steps)
        if steps == 0:
            return Advance(0, t - self.time)
        times = self.time + dt * np.arange(1, steps + 1)
        ends, velocities = self.ends_at(times)
        self._blend_ends(times, ends, velocities)
        self._run(dt, ends, velocities)
        self.time = float(times[-1])
        finite = kernels.all_finite(self.rope.x, self.rope.v) if self.compiled else \
            self.rope.is_finite()
        if not finite:
            self.restart()
            return Advance(steps, t - self.time, 'non-finite state')
        return Advance(steps, t - self.time)

    def _blend_ends(self, times: np.ndarray, ends: np.ndarray, velocities: np.ndarray) -> None:
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
        rope, props = self.rope, self.props
        args = (rope.x, rope.v, ends, velocities, dt, self._coefficients, self._inv_mass,
                props.max_strain, props.superelastic_adjustment, MAX_ITERATIONS)
        if self.params.integrator == 'implicit_euler':
            run = kernels.implicit_euler_run
            if not self.compiled:
                run = run.py_func  # the same code, interpreted: for tests
            run(*args, implicit_bending(props, dt))
            return
        if self.compiled:
            kernels.improved_euler_run(*args)
            return
        for k in range(len(ends)):
            improved_euler_step(rope, dt, ends[k], velocities[k])
            if props.superelastic_adjustment:
                adjust(rope.x, rope.v, self._inv_mass, props.segment_length, props.max_strain,
                       MAX_ITERATIONS)

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
        """Return the current state: particles, end forces and the largest strain."""
        rope = self.rope
        if self.compiled:
            forces = np.empty((2, 3))
            kernels.end_forces(rope.x, rope.v, self._coefficients, forces)
            bollard, fairlead = forces
            strain = kernels.max_strain(rope.x, self.props.segment_length)
        else:
            bollard, fairlead = rope.end_forces()
            strain = float(rope.strains().max())
        return Output(self.time, rope.x.copy(), fairlead, bollard, strain)
