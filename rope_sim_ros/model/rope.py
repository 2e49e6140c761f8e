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
(eq. 5); and MoorDyn in the fluids: buoyancy, Morison drag and added mass in water and air,
and seabed and quay contact, in forces/.
"""

from dataclasses import dataclass
from functools import cached_property
import math

import numpy as np

from .objects import Environment, LineType
from .superelastic import curve_strain_limit
from .tension_curve import check_curve, TensionCurve


@dataclass(frozen=True)
class RopeProperties:
    """
    The physical numbers of one line, all resolved (no 'take from material' values).

    The line's own numbers only: what it lives in (gravity, the fluids, the ground) is the
    mooring's one objects.Environment, which the functions that need it take beside these.

    :ivar segments: number of segments N.
    :ivar length: unstretched length L [m].
    :ivar mass_per_length: [kg/m].
    :ivar axial_stiffness: EA [N]; on a line with a tension_curve its nominal EA: the bending
        springs' and the default damping's, not the structural springs'.
    :ivar axial_damping: BA [N s]: a segment's damping coefficient is BA / segment length.
    :ivar bending_stiffness_ratio: bending spring stiffness / structural spring stiffness.
    :ivar bending_damping_ratio: bending spring damping / structural spring damping.
    :ivar damping_model: 'axial' (stretch rate only) or 'seed' (K_SD (V_A - V_B)).
    :ivar air_drag_coefficient: K_A per metre [N s^2 / m^3].
    :ivar max_strain: super-elasticity threshold (strain); a curve may raise it (strain_limit).
    :ivar superelastic_adjustment: apply the position/velocity adjustment.
    :ivar payload_mass: mass of a free payload at the bollard end [kg]; 0: the bollard is a
        fixed or driven point.
    :ivar diameter: nominal diameter d [m] (drag, contact width); 0: no fluid drag, no
        buoyancy, no contact (a line of numbers only, as in the kernel tests).
    :ivar volume_diameter: volume-equivalent diameter dv [m] (buoyancy, added mass).
    :ivar mbl: minimum breaking load [N].
    :ivar normal_drag, tangential_drag: MoorDyn's Cd (on d) and CdAx (on pi d).
    :ivar normal_added_mass, tangential_added_mass: MoorDyn's Ca and CaAx.
    :ivar payload_volume: [m^3]; payload_drag_area: CdA [m^2]; payload_added_mass: Ca.
    :ivar tension_curve: the load-extension as (strain, tension [N]) pairs (LineType's);
        () for a linear line of EA.
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
    max_strain: float = 0.25
    superelastic_adjustment: bool = True
    payload_mass: float = 0.0
    diameter: float = 0.0
    volume_diameter: float = 0.0
    mbl: float = math.inf
    normal_drag: float = 0.0
    tangential_drag: float = 0.0
    normal_added_mass: float = 0.0
    tangential_added_mass: float = 0.0
    payload_volume: float = 0.0
    payload_drag_area: float = 0.0
    payload_added_mass: float = 0.0
    tension_curve: tuple = ()

    def __post_init__(self):
        """Check the curve (tension_curve.py's rules) and keep it starting at (0, 0)."""
        object.__setattr__(self, 'tension_curve', check_curve(self.tension_curve))

    @cached_property
    def curve(self):
        """Return the line's TensionCurve, None for a linear line."""
        return TensionCurve.from_pairs(self.tension_curve) if self.tension_curve else None

    @cached_property
    def strain_limit(self) -> float:
        """Return the strain no segment is left beyond: max_strain, on a curve its 2 MBL's."""
        return curve_strain_limit(self.max_strain, self.curve, self.mbl)

    @property
    def stiffest_axial_stiffness(self) -> float:
        """Largest tangent dT/dstrain [N] the line meets up to its strain limit: EA if linear."""
        if self.curve is None:
            return self.axial_stiffness
        return self.curve.stiffest(self.strain_limit)

    @property
    def limit_tension(self) -> float:
        """Elastic tension of a segment at the strain limit [N]."""
        if self.curve is None:
            return self.axial_stiffness * self.strain_limit
        return float(self.curve.tension(self.strain_limit))

    @property
    def limit_energy(self) -> float:
        """Elastic energy per metre of rest length at the strain limit [J/m]."""
        if self.curve is None:
            return 0.5 * self.axial_stiffness * self.strain_limit ** 2
        return float(self.curve.energy(self.strain_limit))

    def strain_at(self, tension):
        """Return the strain at elastic tension(s) [N] (the curve's inverse, or T / EA)."""
        if self.curve is None:
            return np.asarray(tension, dtype=float) / self.axial_stiffness
        return self.curve.strain_at(tension)

    @property
    def line_type(self) -> LineType:
        """Return the LineType of the line."""
        return LineType(
            mass_per_length=self.mass_per_length, axial_stiffness=self.axial_stiffness,
            axial_damping=self.axial_damping, diameter=self.diameter, mbl=self.mbl,
            bending_stiffness_ratio=self.bending_stiffness_ratio,
            bending_damping_ratio=self.bending_damping_ratio, damping_model=self.damping_model,
            air_drag_coefficient=self.air_drag_coefficient, max_strain=self.strain_limit,
            superelastic_adjustment=self.superelastic_adjustment,
            volume_diameter=self.volume_diameter, normal_drag=self.normal_drag,
            tangential_drag=self.tangential_drag, normal_added_mass=self.normal_added_mass,
            tangential_added_mass=self.tangential_added_mass, tension_curve=self.tension_curve)

    @property
    def volume_area(self) -> float:
        """Displaced area per metre, pi dv^2 / 4 [m^2] (dv = 0: the nominal diameter)."""
        dv = self.volume_diameter or self.diameter
        return 0.25 * math.pi * dv * dv

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
        """Structural spring stiffness k = EA / l0 [N/m] (nominal EA on a curve)."""
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

    def weight_per_length(self, environment: Environment) -> float:
        """Weight per length in air, less the air's buoyancy: (m - rho_a A_v) |g| [N/m]."""
        return self.fluid_weight_per_length(environment.air_density, environment)

    def submerged_weight_per_length(self, environment: Environment) -> float:
        """Weight per length in water, (m - rho_w A_v) |g| [N/m] (< 0: the line floats)."""
        return self.fluid_weight_per_length(environment.water_density, environment)

    def fluid_weight_per_length(self, density: float, environment: Environment) -> float:
        """Weight per length less the buoyancy of a fluid of `density`, [N/m]."""
        g = float(np.linalg.norm(environment.gravity))
        return (self.mass_per_length - density * self.volume_area) * g

    @property
    def reach(self) -> float:
        """Farthest the ends can be apart, every segment at its limit: L (1 + limit) [m]."""
        return self.length * (1.0 + self.strain_limit)

    @property
    def wave_speed(self) -> float:
        """Fastest axial wave up to the strain limit, c = sqrt(dT/dstrain / m) [m/s]."""
        return math.sqrt(self.stiffest_axial_stiffness / self.mass_per_length)


def tension_bound(props: RopeProperties, environment: Environment,
                  end_speed: float = 0.0) -> float:
    """
    Largest force [N] the line can put on an end; a state past it is a numerical artefact.

    Every term of the end force (kernels.end_forces) is bounded:

    - springs: a structural spring is never longer than l0 (1 + e) (the superelastic
      adjustment at the strain limit e, with the ends held within reach), so it pulls at
      most T(e) (EA e, or the curve's); a bending spring (i, i+2) then pulls at most
      2 r_s EA e and, folded flat, pushes 2 r_s EA (r_s = bending_stiffness_ratio, EA the
      nominal one on a curve, as the bending springs have it);
    - a wave reflected at the end doubles the strain: the spring terms count twice, which
      also covers a line without the adjustment overshooting its limit (1.5 to 2 times);
    - dampers: neighbouring particles part at most at 2 v*, twice the fastest a particle
      moves against its neighbours: v* = c e (an axial wave at the strain limit, c =
      sqrt(EA / m), on a curve its stiffest tangent's: the release of a strain e moves a
      particle at int c(e) de <= c_max e) + sqrt(2 |g| L) (a fall of the whole length) + the
      ends' speed.
      A segment's damper then pulls at most 2 BA v* / l0, its bending damper
      4 r_d BA v* / l0 (r_d = bending_damping_ratio);
    - the weight of the whole line and the buoyancy of it all, (m + rho A_v) |g| L
      (rho: the densest fluid present);
    - the fluid drag of the half segment lumped at the end, moving at the end's speed
      plus the current (and, on a payload's end, the fall speed below) through the densest
      fluid: 1/2 rho (Cd d + CdAx pi d) l0 / 2 (|U| + speed)^2. Quadratic in the end speed
      where the rest is linear: the state check extrapolates linearly from speeds 0 and 1,
      which falls short of it by 1/2 rho (Cd + pi CdAx) d l0 / 2 (s^2 - s) at a speed s:
      4.7 kN at 10 m/s on the default line in water, far inside the springs' 28 MN.

    The reference polyester line (EA 50 MN, max_strain 0.25) at rest gives 28 MN, where its
    converged peak under a 3 m jerk in 0.5 s is 0.12 MN and an unstable step overflows to
    1e153 N. A line-parting model (tension past the breaking load) acts far below this
    bound and would take its place.

    With a payload of mass M at the bollard end (a free point) three terms grow:

    - its weight M |g|;
    - its fall: a payload thrown up by a snap can rise to the reach above the fairlead
      and fall to the reach below it, so the fall speed above becomes
      v_f = sqrt(4 |g| L (1 + e)), and a line stretched to its limit can fling a light
      payload at up to sqrt(2 W L / M_e) (its elastic energy W L all in M_e = M + half a
      segment; W = EA e^2 / 2 per metre, or the curve's integral): both join v*;
    - its snatch: a payload moving at v_s = v_f + the ends' speed away from the fairlead
      when the line snaps taut is stopped by the line's stiffness EA / L (on a curve its
      stiffest tangent's, as everywhere the wave speed enters): the spring-mass
      peak v_s sqrt(EA M / L), plus the wave front's Z v_s (Z = sqrt(EA m), the line's wave
      impedance) before the line's whole stiffness acts; counted twice, like the springs
      (a reflected wave, or a line without the strain limit). With the strain limit the
      springs term already caps the pull; this keeps the bound valid without it.

    A slack-taut snap of a 1 t payload on the default 40 m polyester line under a crane tip
    heaving at 1.4 g peaks well under a tenth of this bound (test_payload.py).

    :param environment: what the line lives in (gravity, the fluids, the current).
    :param end_speed: the largest speed of an end [m/s].
    """
    ea, strain = props.axial_stiffness, props.strain_limit
    stiffest = props.stiffest_axial_stiffness
    r_s, r_d = props.bending_stiffness_ratio, props.bending_damping_ratio
    g = math.hypot(*environment.gravity)
    fall = math.sqrt(2.0 * g * props.length)
    payload = props.payload_mass
    snatch = 0.0
    if payload > 0.0:
        fall = math.sqrt(4.0 * g * props.reach)
        fall += math.sqrt(2.0 * props.limit_energy * props.length / props.end_mass)
        impedance = math.sqrt(stiffest * payload / props.length) + math.sqrt(
            stiffest * props.mass_per_length)
        snatch = 2.0 * (fall + end_speed) * impedance + payload * g
    v_star = props.wave_speed * strain + fall + end_speed
    springs = 2.0 * props.limit_tension + 2.0 * r_s * ea * (2.0 * strain + 1.0)
    dampers = 2.0 * props.axial_damping * v_star / props.segment_length * (1.0 + 2.0 * r_d)
    water = math.isfinite(environment.water_level)
    rho = max(environment.air_density, environment.water_density if water else 0.0)
    weight = (props.mass_per_length + rho * props.volume_area) * g * props.length
    speed = math.hypot(*environment.current) * water + end_speed
    if payload > 0.0:
        speed += fall
    drag = (0.25 * rho * (props.normal_drag + math.pi * props.tangential_drag)
            * props.diameter * props.segment_length * speed * speed)
    return springs + dampers + weight + drag + snatch


def critical_axial_damping(length: float, mass_per_length: float, axial_stiffness: float,
                           ratio: float = 0.01) -> float:
    """
    BA [N s] giving `ratio` of critical damping to the line's first axial mode.

    The first axial mode of a line fixed at both ends has w1 = (pi / L) sqrt(EA / m); a
    stiffness-proportional damper BA gives it the damping ratio BA w1 / (2 EA).
    """
    return 2.0 * ratio * length * np.sqrt(axial_stiffness * mass_per_length) / np.pi
