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

"""Bring a line's start shape to rest under its own forces: pseudo-steps of the integrators."""

import numpy as np

from .rules import automatic_time_step, implicit_bending
from .step import step
from ..model.objects import Environment, System
from ..model.rope import RopeProperties
from ..model.superelastic import MAX_ITERATIONS

# Bringing a start shape to rest (relax): pseudo-steps until no particle moves more than
# RELAX_TOLERANCE * L in one, first Newton-like ones of NEWTON_STEP from rest (at most
# NEWTON_STEPS), then, where a fold is left, steps of the line's own motion, of its
# automatic implicit step, over at most FOLD_TIME and FOLD_WORK particle steps (about 0.5 s
# of computing). Kinetic damping took up to 35 s at N = 1001 (7e6 particle steps, 0.34 s);
# steps of 20 ms or more cycled without settling.
RELAX_TOLERANCE = 1e-9
NEWTON_STEP = 1.0
NEWTON_STEPS = 200
FOLD_TIME = 60.0
FOLD_WORK = 1.0e7
# A bending spring shorter than this fraction of its rest length 2 l0 marks a fold (an angle
# sharper than 128 degrees between its segments); the default line hanging between ends 20 m
# apart stays above 0.977.
FOLD_LENGTH = 0.9
# The fold is nudged sideways by this fraction of a segment: the Newton-like steps stop on a
# balanced fold (an unstable rest), which only a nudge shows to be one.
FOLD_NUDGE = 1e-3


def relax(props: RopeProperties, system: System) -> bool:
    """
    Bring the system (in place) to rest under its own forces, fixed and driven points held.

    Free points (a payload) settle with the lines. The fold checks look at the first line,
    the one props describes.

    The catenary is the rest shape of a chain without bending springs. With them it is
    nearly so wherever the line is smooth (they move the settled tension of the reference
    line by 0.05 %), but not where it folds: ends at one point hang the two halves of the
    chain on top of each other, and the bending spring across the fold, pushed from its
    rest length 2 l0 to nothing, kicks it open with 2 r_s EA (3.5 kN on the default line,
    whose weight is 1.1 kN) and a stored 7 kJ that axial damping never takes out of the
    swinging halves: the end tension rang between 2 N and 4.4 kN for 14 s.

    Newton-like pseudo-steps (an implicit Euler step of NEWTON_STEP from rest) settle a
    smooth line in about 7 and that fold in 37. They also stop on a fold held in balance,
    as with an odd N, where the two middle particles meet (the bending springs then push
    along the line): that rest is unstable, and the line rang between 318 N and 981 N.
    A fold left after them, or a line they could not settle, is nudged and settled by the
    line's own motion, stopped at every peak of its kinetic energy (kinetic damping), which
    only ends in a stable rest. (A line with its ends at its reach has no rest: straight at
    its strain limit, it cannot carry its weight. Do not relax it: 200 pseudo-steps of N =
    2000 then cost 0.7 s, and the line's own motion 40 s.)

    :returns: whether the system came to rest (else it is where the steps left it); either
        way, every velocity is zero.
    """
    try:
        settled = _settle(props, system, NEWTON_STEP, NEWTON_STEPS, True)
        x = system.lines[0].x
        if settled and not _folded(props, x):
            return True
        x += FOLD_NUDGE * props.segment_length * _sideways(props, system.environment, x)
        system.v[:] = 0.0
        system.point_v[:] = 0.0
        pseudo_step = automatic_time_step(props, system.environment, 'implicit_euler')
        steps = int(min(np.ceil(FOLD_TIME / pseudo_step), FOLD_WORK / len(system.x)))
        return _settle(props, system, pseudo_step, steps, False)
    finally:
        system.v[:] = 0.0
        system.point_v[:] = 0.0


def _settle(props, system, pseudo_step, steps, from_rest) -> bool:
    """Take pseudo-steps until nothing moves; return whether it stopped."""
    drive_x, drive_v = system.drive_arrays(1)  # fixed and driven points held still
    system.point_v[:] = 0.0
    bending = implicit_bending(props, pseudo_step)
    tolerance = RELAX_TOLERANCE * props.length
    peak = 0.0
    x, v = system.x, system.v
    for _ in range(steps):
        before = x.copy()
        before_points = system.point_x.copy()
        if from_rest:
            v[:] = 0.0
            system.point_v[:] = 0.0
        step(system, 'implicit_euler', pseudo_step, drive_x, drive_v, MAX_ITERATIONS,
             bending)
        kinetic = float(np.einsum('ij,ij->', v, v)
                        + np.einsum('ij,ij->', system.point_v, system.point_v))
        if not np.isfinite(kinetic):
            return False
        if kinetic < peak:  # past a peak of kinetic energy: stop there
            v[:] = 0.0
            system.point_v[:] = 0.0
            kinetic = 0.0
        peak = kinetic
        if max(np.abs(x - before).max(), np.abs(system.point_x - before_points).max(
                initial=0.0)) <= tolerance:
            return True
    return False


def _folded(props: RopeProperties, x: np.ndarray) -> bool:
    """Tell whether a bending spring is folded shorter than FOLD_LENGTH of its rest length."""
    if props.bending_stiffness <= 0.0 or len(x) < 3:
        return False
    d = x[2:] - x[:-2]
    return bool(np.einsum('ij,ij->i', d, d).min()
                < (FOLD_LENGTH * 2.0 * props.segment_length) ** 2)


def _sideways(props: RopeProperties, environment: Environment, x: np.ndarray) -> np.ndarray:
    """Return a smooth, lopsided sideways displacement of size 1 (0 at the ends), (N+1, 3)."""
    gravity = np.asarray(environment.gravity, dtype=float)
    up = -gravity / np.linalg.norm(gravity) if np.any(gravity) else np.array([0.0, 0.0, 1.0])
    chord = x[-1] - x[0]
    side = chord - (chord @ up) * up
    if np.linalg.norm(side) < 1e-9 * props.length:  # a vertical chord: any level direction
        side = np.zeros(3)
        side[int(np.argmin(np.abs(up)))] = 1.0
        side -= (side @ up) * up
    s = np.linspace(0.0, np.pi, len(x))
    return np.outer(np.sin(s) * (1.0 + 0.5 * np.cos(s)), side / np.linalg.norm(side))
