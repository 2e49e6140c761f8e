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
The rope: particles joined by structural (i, i+1) and bending (i, i+2) springs.

Particle 0 is the bollard end and particle N the fairlead end; both are kinematic (moved by
the inputs), the N-1 others are free. Forces follow the seed paper (Liang & Yin 2016):
Hooke springs (eq. 2), spring damping (eq. 3), gravity (eq. 4) and quadratic air drag (eq. 5).
"""

from dataclasses import dataclass
import math

import numpy as np


@dataclass(frozen=True)
class RopeProperties:
    """
    The physical numbers of one line, all resolved (no 'take from material' zeros).

    :ivar segments: number of segments N.
    :ivar length: unstretched length L [m].
    :ivar mass_per_length: [kg/m].
    :ivar axial_stiffness: EA [N].
    :ivar axial_damping: BA [N s]: a segment's damping coefficient is BA / segment length.
    :ivar bending_stiffness_ratio: bending spring stiffness / structural spring stiffness.
    :ivar bending_damping_ratio: bending spring damping / structural spring damping.
    :ivar damping_model: 'axial' (stretch rate only) or 'seed' (K_SD (V_A - V_B)).
    :ivar air_drag_coefficient: K_A per metre [N s^2 / m^3].
    :ivar gravity: gravity vector [m/s^2], shape (3,).
    :ivar max_strain: super-elasticity threshold (strain).
    :ivar superelastic_adjustment: apply the position/velocity adjustment.
    """

    segments: int
    length: float
    mass_per_length: float
    axial_stiffness: float
    axial_damping: float
    bending_stiffness_ratio: float = 0.0
    bending_damping_ratio: float = 0.0
    damping_model: str = 'axial'
    air_drag_coefficient: float = 0.0
    gravity: tuple = (0.0, 0.0, -9.81)
    max_strain: float = 0.25
    superelastic_adjustment: bool = True

    @property
    def segment_length(self) -> float:
        """Unstretched structural spring length l0 = L / N [m]."""
        return self.length / self.segments

    @property
    def particle_mass(self) -> float:
        """Mass of a free particle [kg]; each end carries half of it."""
        return self.mass_per_length * self.segment_length

    @property
    def structural_stiffness(self) -> float:
        """Structural spring stiffness k = EA / l0 [N/m]."""
        return self.axial_stiffness / self.segment_length

    @property
    def structural_damping(self) -> float:
        """Structural spring damping c = BA / l0 [N s/m]."""
        return self.axial_damping / self.segment_length

    @property
    def bending_stiffness(self) -> float:
        """Bending spring stiffness [N/m]."""
        return self.bending_stiffness_ratio * self.structural_stiffness

    @property
    def bending_damping(self) -> float:
        """Bending spring damping [N s/m]."""
        return self.bending_damping_ratio * self.structural_damping

    @property
    def weight_per_length(self) -> float:
        """Weight per length w = mass per length * |g| [N/m]."""
        return self.mass_per_length * float(np.linalg.norm(self.gravity))

    @property
    def reach(self) -> float:
        """Farthest the ends can be apart, every segment at its limit: L (1 + max_strain) [m]."""
        return self.length * (1.0 + self.max_strain)

    @property
    def wave_speed(self) -> float:
        """Speed of an axial wave, c = sqrt(EA / m) [m/s]."""
        return math.sqrt(self.axial_stiffness / self.mass_per_length)


def tension_bound(props: RopeProperties, end_speed: float = 0.0) -> float:
    """
    Largest force [N] the line can put on an end; a state past it is a numerical artefact.

    Every term of the end force (Rope.end_forces) is bounded:

    - springs: a structural spring is never longer than l0 (1 + max_strain) (the
      superelastic adjustment, with the ends held within reach), so it pulls at most
      EA max_strain; a bending spring (i, i+2) then pulls at most 2 r_s EA max_strain and,
      folded flat, pushes 2 r_s EA (r_s = bending_stiffness_ratio);
    - a wave reflected at the end doubles the strain: the spring terms count twice, which
      also covers a line without the adjustment overshooting its limit (1.5 to 2 times);
    - dampers: neighbouring particles part at most at 2 v*, twice the fastest a particle
      moves against its neighbours: v* = c max_strain (an axial wave at the strain limit,
      c = sqrt(EA / m)) + sqrt(2 |g| L) (a fall of the whole length) + the ends' speed.
      A segment's damper then pulls at most 2 BA v* / l0, its bending damper
      4 r_d BA v* / l0 (r_d = bending_damping_ratio);
    - the weight of the whole line, w L.

    The reference polyester line (EA 50 MN, max_strain 0.25) at rest gives 28 MN, where its
    converged peak under a 3 m jerk in 0.5 s is 0.12 MN and an unstable step overflows to
    1e153 N. A line-parting model (tension past the breaking load) acts far below this
    bound and would take its place.

    :param end_speed: the largest speed of an end [m/s].
    """
    ea, strain = props.axial_stiffness, props.max_strain
    r_s, r_d = props.bending_stiffness_ratio, props.bending_damping_ratio
    fall = math.sqrt(2.0 * math.hypot(*props.gravity) * props.length)
    v_star = props.wave_speed * strain + fall + end_speed
    springs = 2.0 * ea * strain * (1.0 + 2.0 * r_s) + 2.0 * r_s * ea
    dampers = 2.0 * props.axial_damping * v_star / props.segment_length * (1.0 + 2.0 * r_d)
    return springs + dampers + props.weight_per_length * props.length


def critical_axial_damping(length: float, mass_per_length: float, axial_stiffness: float,
                           ratio: float = 0.01) -> float:
    """
    BA [N s] giving `ratio` of critical damping to the line's first axial mode.

    The first axial mode of a line fixed at both ends has w1 = (pi / L) sqrt(EA / m); a
    stiffness-proportional damper BA gives it the damping ratio BA w1 / (2 EA).
    """
    return 2.0 * ratio * length * np.sqrt(axial_stiffness * mass_per_length) / np.pi


def _spring_forces(x, v, stride, rest, stiffness, damping, axial, tension_only, out):
    """
    Add the forces of springs (i, i + stride) to `out`; return their axial force.

    The axial force is positive in tension. A structural spring is a rope segment and carries
    no compression; a bending spring pushes back when the rope folds (the seed's purpose).
    """
    d = x[stride:] - x[:-stride]
    length = np.sqrt(np.einsum('ij,ij->i', d, d))
    u = d / np.maximum(length, 1e-12)[:, None]
    stretch = length - rest
    if tension_only:
        stretch = np.maximum(stretch, 0.0)
    dv = v[stride:] - v[:-stride]
    if axial:
        tension = stiffness * stretch + damping * np.einsum('ij,ij->i', dv, u)
        f = tension[:, None] * u
    else:
        tension = stiffness * stretch
        f = tension[:, None] * u + damping * dv
    out[:-stride] += f
    out[stride:] -= f
    return tension


class Rope:
    """
    State and forces of one line.

    :ivar props: the line's RopeProperties.
    :ivar x: particle positions, shape (N+1, 3) [m].
    :ivar v: particle velocities, shape (N+1, 3) [m/s].
    """

    def __init__(self, props: RopeProperties, positions: np.ndarray):
        """Place the rope at rest at `positions`, shape (N+1, 3)."""
        self.props = props
        self.x = np.array(positions, dtype=float)
        if self.x.shape != (props.segments + 1, 3):
            raise ValueError(
                f'positions must have shape ({props.segments + 1}, 3), got {self.x.shape}')
        self.v = np.zeros_like(self.x)
        self._gravity = np.asarray(props.gravity, dtype=float)

    @property
    def count(self) -> int:
        """Count the particles: N + 1."""
        return self.props.segments + 1

    def line_forces(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Spring and damper forces of the line on every particle, shape (N+1, 3)."""
        p = self.props
        axial = p.damping_model == 'axial'
        f = np.zeros_like(x)
        _spring_forces(x, v, 1, p.segment_length, p.structural_stiffness,
                       p.structural_damping, axial, True, f)
        if p.bending_stiffness > 0.0 or p.bending_damping > 0.0:
            _spring_forces(x, v, 2, 2.0 * p.segment_length, p.bending_stiffness,
                           p.bending_damping, axial, False, f)
        return f

    def accelerations(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Accelerations of all particles (the two ends' rows are meaningless)."""
        p = self.props
        f = self.line_forces(x, v)
        if p.air_drag_coefficient > 0.0:
            speed = np.sqrt(np.einsum('ij,ij->i', v, v))
            f -= (p.air_drag_coefficient * p.segment_length) * speed[:, None] * v
        return f / p.particle_mass + self._gravity

    def end_forces(self) -> tuple:
        """
        Force of the line on the bollard (particle 0) and on the fairlead (particle N).

        The attached springs and dampers plus the weight of the half segment lumped at the
        end, as MoorDyn reports for a coupled point: it converges to the catenary's end
        tension at second order in N.
        """
        f = self.line_forces(self.x, self.v)
        half_weight = 0.5 * self.props.particle_mass * self._gravity
        return f[0] + half_weight, f[-1] + half_weight

    def strains(self) -> np.ndarray:
        """Strain of every structural spring, shape (N,)."""
        d = np.diff(self.x, axis=0)
        return np.sqrt(np.einsum('ij,ij->i', d, d)) / self.props.segment_length - 1.0

    def is_finite(self) -> bool:
        """Tell whether every position and velocity is a finite number."""
        return bool(np.isfinite(self.x).all() and np.isfinite(self.v).all())
