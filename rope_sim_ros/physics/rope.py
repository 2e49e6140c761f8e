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
The simulator's one line: its numbers (RopeProperties) and the bound on its end forces.

RopeProperties describes a line between two points, a bollard (particle 0) and a fairlead
(particle N), in one environment: it gives the LineType and Environment of objects.py and
the step rules of integrators.py their numbers. Forces follow the seed paper (Liang & Yin
2016): Hooke springs (eq. 2), spring damping (eq. 3), gravity (eq. 4) and quadratic air drag
(eq. 5), in forces/.
"""

from dataclasses import dataclass
import math

import numpy as np

from .objects import Environment, LineType


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
    :ivar payload_mass: mass of a free payload at the bollard end [kg]; 0: the bollard is a
        fixed or driven point.
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
    payload_mass: float = 0.0

    @property
    def line_type(self) -> LineType:
        """Return the LineType of the line."""
        return LineType(
            mass_per_length=self.mass_per_length, axial_stiffness=self.axial_stiffness,
            axial_damping=self.axial_damping,
            bending_stiffness_ratio=self.bending_stiffness_ratio,
            bending_damping_ratio=self.bending_damping_ratio, damping_model=self.damping_model,
            air_drag_coefficient=self.air_drag_coefficient, max_strain=self.max_strain,
            superelastic_adjustment=self.superelastic_adjustment)

    @property
    def environment(self) -> Environment:
        """Return the Environment of the line."""
        return Environment(gravity=tuple(float(g) for g in self.gravity))

    @property
    def end_mass(self) -> float:
        """Lumped mass of a free bollard end [kg]: the payload and half a segment."""
        return self.payload_mass + 0.5 * self.particle_mass

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

    Every term of the end force (kernels.end_forces) is bounded:

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

    With a payload of mass M at the bollard end (a free point) three terms grow:

    - its weight M |g|;
    - its fall: a payload thrown up by a snap can rise to the reach above the fairlead
      and fall to the reach below it, so the fall speed above becomes
      v_f = sqrt(4 |g| L (1 + max_strain)), and a line stretched to its limit can fling a
      light payload at up to max_strain sqrt(EA L / M_e) (its elastic energy
      EA max_strain^2 L / 2 all in M_e = M + half a segment): both join v*;
    - its snatch: a payload moving at v_s = v_f + the ends' speed away from the fairlead
      when the line snaps taut is stopped by the line's stiffness EA / L: the spring-mass
      peak v_s sqrt(EA M / L), plus the wave front's Z v_s (Z = sqrt(EA m), the line's wave
      impedance) before the line's whole stiffness acts; counted twice, like the springs
      (a reflected wave, or a line without the strain limit). With the strain limit the
      springs term already caps the pull; this keeps the bound valid without it.

    A slack-taut snap of a 1 t payload on the default 40 m polyester line under a crane tip
    heaving at 1.4 g peaks well under a tenth of this bound (test_payload.py).

    :param end_speed: the largest speed of an end [m/s].
    """
    ea, strain = props.axial_stiffness, props.max_strain
    r_s, r_d = props.bending_stiffness_ratio, props.bending_damping_ratio
    g = math.hypot(*props.gravity)
    fall = math.sqrt(2.0 * g * props.length)
    payload = props.payload_mass
    snatch = 0.0
    if payload > 0.0:
        fall = math.sqrt(4.0 * g * props.reach)
        fall += strain * math.sqrt(ea * props.length / props.end_mass)
        impedance = math.sqrt(ea * payload / props.length) + math.sqrt(
            ea * props.mass_per_length)
        snatch = 2.0 * (fall + end_speed) * impedance + payload * g
    v_star = props.wave_speed * strain + fall + end_speed
    springs = 2.0 * ea * strain * (1.0 + 2.0 * r_s) + 2.0 * r_s * ea
    dampers = 2.0 * props.axial_damping * v_star / props.segment_length * (1.0 + 2.0 * r_d)
    return springs + dampers + props.weight_per_length * props.length + snatch


def critical_axial_damping(length: float, mass_per_length: float, axial_stiffness: float,
                           ratio: float = 0.01) -> float:
    """
    BA [N s] giving `ratio` of critical damping to the line's first axial mode.

    The first axial mode of a line fixed at both ends has w1 = (pi / L) sqrt(EA / m); a
    stiffness-proportional damper BA gives it the damping ratio BA w1 / (2 EA).
    """
    return 2.0 * ratio * length * np.sqrt(axial_stiffness * mass_per_length) / np.pi
