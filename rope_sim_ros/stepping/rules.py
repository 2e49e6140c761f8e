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
The step rules: the time step of a line, the bounds a step's motion must keep, its ends driven.

The integrators themselves are kernels.improved_euler_run and kernels.implicit_euler_run,
which step a whole System (model/objects.py).

The seed's improved Euler (eq. 7) is Heun's method: an Euler predictor, then the mean of the
two accelerations for the velocity and the trapezoid of the two velocities for the position.
On an undamped oscillator its amplification is |G|^2 = 1 + (w dt)^4 / 4 > 1 for every step,
so it lives on the line's damping: the automatic step is the largest one for which every
axial mode of the chain, with its damping, is stable, times a safety factor. Ground contact
and water drag add modes of their own (contact_rates, drag_rate). On a line with a
strain-tension curve the modes stiffen as it stretches: every step rule takes the stiffest
tangent the curve reaches up to the line's strain limit (RopeProperties.
stiffest_axial_stiffness), so that no stretch the line can reach outruns the step.
"""

import math

import numba
import numpy as np

from ..model.objects import Environment
from ..model.rope import RopeProperties

SAFETY_FACTOR = 0.8


def _heun_growth(z: np.ndarray) -> np.ndarray:
    """|R(z)| of Heun's method, R(z) = 1 + z + z^2 / 2."""
    return np.abs(1.0 + z + 0.5 * z * z)


def _has_ground(environment: Environment) -> bool:
    """Tell whether a seabed or a quay can touch the line."""
    quay = getattr(environment, 'quay_normal', (0.0, 0.0, 0.0))
    return (getattr(environment, 'seabed_level', -math.inf) > -math.inf
            or bool(np.any(np.asarray(quay, dtype=float))))


def contact_rates(props: RopeProperties, environment: Environment) -> tuple:
    """
    Return the ground contact's (stiffness rate [1/s^2], damping rate [1/s]) on a particle.

    A particle in the ground (seabed or quay) of a line of nominal diameter d feels k_b d
    len_i per metre of penetration and c_b d len_i per m/s (MoorDyn's kBot, cBot), over its
    mass m len_i: k_b d / m and c_b d / m, the same for every particle. Its added mass
    would lower both; it is left out, which errs on the safe side. (0, 0) without ground.
    Heun's method is stable on the damping alone only below a step of 2 / (c_b d / m):
    1.1 ms for the 40 mm wire and 0.27 ms for the 64 mm polyester on MoorDyn's default
    c_b = 3e5 Pa s/m, where their axial modes alone allow 0.4 to 2 ms.
    """
    if not _has_ground(environment):
        return 0.0, 0.0
    d = getattr(props.line_type, 'diameter', 0.0)
    m = props.mass_per_length
    return (getattr(environment, 'seabed_stiffness', 0.0) * d / m,
            getattr(environment, 'seabed_damping', 0.0) * d / m)


def _payload_contact_rates(props: RopeProperties, environment: Environment) -> tuple:
    """
    Return the contact's (stiffness, damping) rates on a free payload, as contact_rates.

    A payload of volume V touches with width and length V^(1/3) (its contact area V^(2/3)),
    over its lumped mass (its own and half a segment). (0, 0) without ground or volume.
    """
    volume = getattr(props, 'payload_volume', 0.0)
    if props.payload_mass <= 0.0 or volume <= 0.0 or not _has_ground(environment):
        return 0.0, 0.0
    area = volume ** (2.0 / 3.0)
    return (environment.seabed_stiffness * area / props.end_mass,
            environment.seabed_damping * area / props.end_mass)


def drag_rate(props: RopeProperties, environment: Environment, speed: float) -> float:
    """
    Return how fast the drag takes a particle's velocity [1/s] at a relative speed [m/s].

    Quadratic drag c |u| u changes with the velocity at up to 2 c |u|: per unit mass, in
    water (1/2 rho_w (Cd d + CdAx pi d)) 2 |u| / m, in air the same with rho_air, and the
    seed's isotropic K_A 2 |u| / m (the larger of water and air, plus K_A). Heun's method
    is stable on it below a step of 2 / rate; the rate grows with the speed, so it cannot
    set a fixed step: the current's part (a line at rest in it) joins the automatic step,
    the motion's part is the simulator's to divide steps by.
    """
    t = props.line_type
    d = getattr(t, 'diameter', 0.0)
    per_speed = (max(getattr(t, 'normal_drag', 0.0), 0.0)
                 + math.pi * max(getattr(t, 'tangential_drag', 0.0), 0.0)) * d
    water = getattr(environment, 'water_level', -math.inf) > -math.inf
    density = max(getattr(environment, 'water_density', 0.0) if water else 0.0,
                  getattr(environment, 'air_density', 0.0))
    return (density * per_speed + 2.0 * props.air_drag_coefficient) * speed / (
        props.mass_per_length)


def _current_speed(environment: Environment) -> float:
    """Return the current's speed [m/s] where there is water (0 without)."""
    if getattr(environment, 'water_level', -math.inf) == -math.inf:
        return 0.0
    return float(np.linalg.norm(getattr(environment, 'current', (0.0, 0.0, 0.0))))


def _mode_eigenvalues(props: RopeProperties, environment: Environment,
                      count: int = 400) -> np.ndarray:
    """
    Eigenvalues of the chain's axial modes, from the slowest to the fastest.

    The chain's frequencies lie in (0, w_max] with w_max^2 the largest Gershgorin row sum
    of M^-1 K: 4 (k_s + k_b) / m for an inner particle, 2 (k_s + k_b) / M_e for a free end
    of lumped mass M_e (a payload and half a segment). A free end is never lighter than
    half a particle, so it never raises the bound; a lighter free point would. Each mode
    is damped in proportion to its stiffness (w^2 beta).

    The same modes slack (the structural springs idle, every damper and bending spring
    acting: s^2 + beta w^2 s + r w^2 = 0, r the bending springs' share of the stiffness).
    With ground contact each mode also appears with the contact's stiffness and damping
    added (a particle's Gershgorin row grows by them): s^2 + (beta w^2 + g_c) s + w^2 + k_c
    = 0, w^2 from 0 (the contact alone); in a current, with the drag's rate at rest in it.
    Every family counts: some particles touch, some do not.
    """
    m = props.particle_mass
    k = _stiffest_structural(props) + props.bending_stiffness
    c = props.structural_damping + props.bending_damping
    w2_max = 4.0 * k / m
    if props.payload_mass > 0.0:
        w2_max = max(w2_max, 2.0 * k / props.end_mass)
    w2 = np.concatenate([[0.0], w2_max * np.geomspace(1e-8, 1.0, count)])
    # taut, and slack: a slack segment's spring does nothing, its damper still acts, so the
    # modes of a slack line are its dampers' and bending springs' (rates up to 4 c / m; with
    # MoorDyn's critical damping per segment, BA = l sqrt(EA m), Heun's method then needs
    # half the step the taut line does: a chain let fall blew up at 0.7 of that)
    base = [(w2, (c / k) * w2), ((props.bending_stiffness / k) * w2, (c / k) * w2)]
    families = list(base)
    stiffness, damping = contact_rates(props, environment)
    drag = drag_rate(props, environment, _current_speed(environment))
    for stiff, damp in base:
        if stiffness > 0.0 or damping > 0.0:
            families.append((stiff + stiffness, damp + damping + drag))
        if drag > 0.0:
            families.append((stiff, damp + drag))
    stiffness, damping = _payload_contact_rates(props, environment)
    if stiffness > 0.0 or damping > 0.0:  # its own row: its springs only via the line end
        end = np.array([0.0, 2.0 * k / props.end_mass])
        families.append((end + stiffness, (c / k) * end + damping))
    modes = []
    for stiff, damp in families:
        # roots of s^2 + damp s + stiff = 0, both branches (overdamped modes have two)
        half = 0.5 * damp
        root = np.sqrt((half * half - stiff).astype(complex))
        modes += [-half + root, -half - root]
    return np.concatenate(modes)


def _stiffest_structural(props: RopeProperties) -> float:
    """Stiffest a structural spring gets up to the strain limit [N/m]: EA / l0 if linear."""
    return props.stiffest_axial_stiffness / props.segment_length


def stability_limit(props: RopeProperties, environment: Environment) -> float:
    """
    Largest stable improved-Euler step [s] for the line's axial and contact modes.

    Returns 0 when no step is stable (an undamped line).
    """
    if props.structural_damping + props.bending_damping <= 0.0:
        return 0.0  # |G| > 1 for every mode: rounding would hide it at tiny steps
    modes = _mode_eigenvalues(props, environment)
    modes = modes[modes != 0.0]
    lo, hi = 0.0, 4.0 / np.abs(modes).max()
    if _heun_growth(1e-9 * hi * modes).max() > 1.0:
        return 0.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _heun_growth(mid * modes).max() <= 1.0 + 1e-12:
            lo = mid
        else:
            hi = mid
    return lo


def wave_time_step(props: RopeProperties) -> float:
    """Time the fastest axial wave takes to cross one segment: (L/N) sqrt(m / EA) [s]."""
    stiffness = props.stiffest_axial_stiffness
    return props.segment_length * np.sqrt(props.mass_per_length / stiffness)


IMPLICIT_STEPS_PER_AXIAL_PERIOD = 4.0
IMPLICIT_MAX_STEP = 0.005
# Bending springs go into the implicit matrix once an explicit treatment would need a step
# below this fraction of their own stability limit (h^2 k_b / m > this).
IMPLICIT_BENDING_THRESHOLD = 0.1


def first_axial_period(props: RopeProperties) -> float:
    """Shortest period of the first axial mode with both ends held, 2 L sqrt(m / EA) [s]."""
    stiffness = props.stiffest_axial_stiffness
    return 2.0 * props.length * np.sqrt(props.mass_per_length / stiffness)


def automatic_time_step(props: RopeProperties, environment: Environment,
                        integrator: str = 'improved_euler') -> float:
    """
    Choose the step used when the user sets time_step 0 [s].

    improved_euler: the stability limit times a safety factor. implicit_euler (stable for any
    step) and adaptive (implicit Euler steps but in a snap): a step that still sees the first
    axial mode, at most IMPLICIT_MAX_STEP.

    :raises ValueError: the line has no damping, so the improved Euler step is never stable.
    """
    if integrator in ('implicit_euler', 'adaptive'):
        return min(IMPLICIT_MAX_STEP, first_axial_period(props) / IMPLICIT_STEPS_PER_AXIAL_PERIOD)
    limit = min(stability_limit(props, environment), wave_time_step(props))
    if limit <= 0.0:
        raise ValueError(
            'improved_euler is unstable on an undamped line: set axial_damping > 0')
    return SAFETY_FACTOR * limit


def implicit_bending(props: RopeProperties, dt: float) -> bool:
    """Whether the implicit step must include the bending springs in its matrix."""
    return dt * dt * props.bending_stiffness / props.particle_mass > IMPLICIT_BENDING_THRESHOLD


@numba.njit(cache=True)
def motion_spread(v, end_velocities):
    """
    Bound the speeds of a step (for the simulator's step division and state check).

    :param v: particle velocities (N+1, 3) [m/s].
    :param end_velocities: velocities of the ends over the step (n, 2, 3) [m/s].
    :returns: sqrt(3) times the largest component of (the particles' and the ends'
        velocities against the bollard's first one; the ends' velocities; the particles' and
        the ends' velocities): bounds on the speeds.
    """
    reference = end_velocities[0, 0]
    spread = 0.0
    ends = 0.0
    for i in range(v.shape[0]):
        for p in range(3):
            spread = max(spread, abs(v[i, p] - reference[p]))
            ends = max(ends, abs(v[i, p]))  # the particles' own, for now
    particles = ends
    ends = 0.0
    for k in range(end_velocities.shape[0]):
        for e in range(2):
            for p in range(3):
                spread = max(spread, abs(end_velocities[k, e, p] - reference[p]))
                ends = max(ends, abs(end_velocities[k, e, p]))
    root3 = np.sqrt(3.0)
    return root3 * spread, root3 * ends, root3 * max(particles, ends)


@numba.njit(cache=True)
def lines_motion_spreads(v, starts, end_velocities):
    """
    Return motion_spread of every line of a System at once, (L, 3).

    :param v: the System's particle velocities; line j's are rows starts[j] to starts[j + 1].
    :param end_velocities: the velocities of the driven points (n, 2 L, 3): line j's ends
        are points 2 j and 2 j + 1.
    """
    out = np.empty((len(starts) - 1, 3))
    for j in range(len(starts) - 1):
        out[j, 0], out[j, 1], out[j, 2] = motion_spread(
            v[starts[j]:starts[j + 1]], end_velocities[:, 2 * j:2 * j + 2])
    return out


@numba.njit(cache=True)
def end_distances(ends):
    """Return the distance between the two ends of each sample, ends (n, 2, 3) -> (n,) [m]."""
    out = np.empty(ends.shape[0])
    for k in range(ends.shape[0]):
        out[k] = np.sqrt((ends[k, 1, 0] - ends[k, 0, 0]) ** 2
                         + (ends[k, 1, 1] - ends[k, 0, 1]) ** 2
                         + (ends[k, 1, 2] - ends[k, 0, 2]) ** 2)
    return out


@numba.njit(cache=True)
def drive_lines(drive_x, drive_v, distances, fairlead_x, fairlead_v, shared, bollards, reach,
                beyond):
    """
    Drive lines whose bollards stand still and whose fairleads were sampled together.

    Writes what Simulator.drive gives (before holding within reach) into a System's drive
    arrays drive_x, drive_v (n, 2 L, 3) and end distances (n, L).

    :param shared: (j, k) of each such line: its line in the System (points 2 j, 2 j + 1),
        its column of fairlead_x, fairlead_v (n, K, 3); its bollard (3,) is in bollards.
    :param reach: the reach [m] of every line of the System (L,), by j.
    :param beyond: (S,) bool, written: which of them are beyond their reach at some step
        (to be held there).
    :returns: how many are.
    """
    count = 0
    for i in range(len(shared)):
        j, k = shared[i, 0], shared[i, 1]
        for n in range(drive_x.shape[0]):
            drive_x[n, 2 * j] = bollards[i]
            drive_v[n, 2 * j] = 0.0
            drive_x[n, 2 * j + 1] = fairlead_x[n, k]
            drive_v[n, 2 * j + 1] = fairlead_v[n, k]
        apart = end_distances(drive_x[:, 2 * j:2 * j + 2])
        distances[:, j] = apart
        beyond[i] = apart.max() > reach[j]
        count += beyond[i]
    return count


@numba.njit(cache=True)
def lowest_bound(at_rest, per_speed, speeds):
    """Return the lowest of the lines' load bounds at_rest + per_speed * speeds (L,) [N]."""
    lowest = np.inf
    for j in range(len(speeds)):
        bound = at_rest[j] + per_speed[j] * speeds[j]
        if np.isnan(bound):
            return np.nan  # (no load is within it)
        lowest = min(lowest, bound)
    return lowest


# A step in which a particle would move more than MAX_STEP_MOTION of a segment against the
# bollard is divided until none does (Mooring._step says why) ...
MAX_STEP_MOTION = 0.5
# ... into at most this many parts (a faster state is past any physical one: the state check
# restarts it).
MAX_DIVISIONS = 1000


@numba.njit(cache=True)
def fine_steps(stable, rate, current, speeds, out):
    """
    Write each line's improved Euler step now into out (L,) [s]: its stable step, or less.

    No longer than the drag takes a particle's speed in: its rate grows with the speed
    through the fluid (drag_rate: rate per m/s, times the particles' speed bound plus the
    current), and past 2 / step the explicit step blows up.
    """
    for j in range(len(out)):
        r = rate[j] * (speeds[j] + current[j])
        out[j] = stable[j] if not r * stable[j] > 1.0 else 1.0 / r


@numba.njit(cache=True)
def step_divisions(spreads, dt, segment_length, explicit, stable, rate, current):
    """
    Return into how many parts a group's steps are divided, and whether to look again.

    :param spreads: each line's motion_spread (L, 3): its particles' speeds against its
        bollard, its ends' speeds, its particles' speeds.
    :param dt: the group's step [s].
    :param segment_length: each line's segment length now (L,) [m].
    :param explicit: the steps are improved Euler's: also divide until no part is longer
        than a line's fine step (fine_steps; stable, rate, current (L,) as there).
    :returns: the parts (the most any line needs) and whether a violent stretch asks for
        them (a particle moving more than MAX_STEP_MOTION of a segment in a step): that
        changes from step to step, so the caller divides each step by what the lines do
        then. A NaN motion asks for nothing: the state check restarts a non-finite line.
    """
    parts = 1
    violent = False
    for j in range(len(segment_length)):
        motion = spreads[j, 0] * dt / (MAX_STEP_MOTION * segment_length[j])
        needed = motion
        if explicit:
            r = rate[j] * (spreads[j, 2] + current[j])
            fine = stable[j] if not r * stable[j] > 1.0 else 1.0 / r
            needed = max(needed, dt / fine)
        if needed > 1.0:
            parts = max(parts, int(np.ceil(min(needed, MAX_DIVISIONS))))
            violent |= motion > 1.0
    return parts, violent
