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
Static shapes of a mooring line: Irvine's elastic catenary and the lumped-mass chain.

Planar convention (test/data/README.md): end A at (0, 0), end B at (span, rise), x
horizontal from A to B, z up. The line pulls A with (+H, V_A) and B with (-H, -V_B), so
V_B - V_A = w L. The tension at unstretched arc length s from A is (H, V_A + w s), and a
segment of unstretched length ds stretches to ds (1 + T / EA), or on a line with a
strain-tension curve (tension_curve.py) to ds (1 + e(T)), e the curve's inverse. The curve's
inverse is piecewise linear in T, e = a_k + b_k T, so the continuous solution
x = int (1 + e(T)) H / T ds, z = int (1 + e(T)) V / T ds has a closed form on every piece
(V_k = +-sqrt(T_k^2 - H^2) bound them): a_k H asinh(V / H) + b_k H V and a_k T + b_k V^2 / 2
(over w) on top of the inextensible catenary; the functions take it as tension_curve=.

The 3-D functions take world points and a gravity vector: 'up' is -gravity / |gravity| and the
horizontal direction is the chord projected onto the plane normal to gravity. There,
weight_per_length is the weight per unstretched metre at that gravity (mass_per_length *
|gravity|), and a zero gravity vector or a zero weight means a weightless, straight line.

Only numpy: the simulator seeds its particles from here, and the tests check the rope model
against these equilibria.
"""

from collections.abc import Callable
from dataclasses import dataclass
import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike

from ..forces import fluid
from ..tension_curve import TensionCurve

# Residual of the closure equations relative to the line's length at which Newton stops.
_TOLERANCE = 1e-12
# Where rounding keeps Newton from reaching _TOLERANCE, a residual this small is still exact
# for any practical purpose; a larger one is a failure.
_ROUNDING_TOLERANCE = 1e-10
# Newton needs at most ~50 residual evaluations wherever an equilibrium exists (a sweep of
# slack to taut, soft to stiff, vertical to level lines); where none does (a chain folded at
# a vertical hang) it would crawl for thousands. The budget keeps a failure cheap for
# initial_shape's fallbacks.
_MAX_EVALUATIONS = 100
_MAX_HALVINGS = 40
# Below this fraction of L the span is treated as this fraction: H = 0 makes the catenary
# equations singular (asinh(V / H)), while H from a tiny span is well defined and harmless.
_MIN_SPAN_FRACTION = 1e-9
# Newton may shrink H by at most this factor per step, keeping it positive.
_MAX_H_SHRINK = 0.1


class CatenaryError(ValueError):
    """Invalid inputs to, or no convergence of, a catenary or chain solve."""


@dataclass(frozen=True)
class CatenarySolution:
    """
    End forces of an elastic catenary, in the planar convention of the module docstring.

    :ivar horizontal_tension: H [N], the horizontal force on A (and, reversed, on B); H >= 0.
    :ivar vertical_a: V_A [N], the vertical force of the line on end A (+ up).
    :ivar vertical_b: V_B [N]; the line pulls B with (-H, -V_B).
    :ivar tension_a: |force on A| = hypot(H, V_A) [N].
    :ivar tension_b: |force on B| = hypot(H, V_B) [N].
    """

    horizontal_tension: float
    vertical_a: float
    vertical_b: float
    tension_a: float
    tension_b: float


# eq=False: comparing numpy arrays field by field has no single truth value.
@dataclass(frozen=True, eq=False)
class ChainEquilibrium:
    """
    Static equilibrium of the N-segment lumped-mass chain between two fixed ends.

    :ivar positions: (N + 1, 3) node positions [m], first = end A, last = end B.
    :ivar force_a: (3,) total force of the line on end A [N]: the first segment's tension
        (pointing into the line) plus the weight of the half segment lumped at A.
    :ivar force_b: (3,) the same at end B.
    :ivar segment_tension: (N,) tension of each segment [N], from A to B.
    :ivar horizontal_tension: H [N], the horizontal component of every segment's tension
        (of a weightless chain, where nothing is horizontal: its tension).
    """

    positions: np.ndarray
    force_a: np.ndarray
    force_b: np.ndarray
    segment_tension: np.ndarray
    horizontal_tension: float


# ----------------------------------------------------------------------------- validation


def _check_finite(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value):
        raise CatenaryError(f'{name} must be finite, got {value}')
    return value


def _check_positive(name: str, value: float) -> float:
    value = _check_finite(name, value)
    if value <= 0.0:
        raise CatenaryError(f'{name} must be > 0, got {value}')
    return value


def _check_non_negative(name: str, value: float) -> float:
    value = _check_finite(name, value)
    if value < 0.0:
        raise CatenaryError(f'{name} must be >= 0, got {value}')
    return value


def _check_point(name: str, value: ArrayLike) -> np.ndarray:
    point = np.asarray(value, dtype=float)
    if point.shape != (3,):
        raise CatenaryError(f'{name} must have shape (3,), got {point.shape}')
    if not np.all(np.isfinite(point)):
        raise CatenaryError(f'{name} must be finite, got {point}')
    return point


def _check_segments(segments: int) -> int:
    if isinstance(segments, bool) or int(segments) != segments or segments < 1:
        raise CatenaryError(f'segments must be an integer >= 1, got {segments}')
    return int(segments)


# ---------------------------------------------------------------------- catenary equations


def _asinh_difference(v: ArrayLike, v_a: float, dv: ArrayLike, t: ArrayLike, t_a: float,
                      h: float) -> np.ndarray:
    """
    Return asinh(v / h) - asinh(v_a / h) without cancellation.

    Where v and v_a share a sign the two terms nearly cancel on a taut or vertical line, so
    use sinh(a - b) = (v - v_a)(v + v_a) / (v t_a + v_a t), which needs no h at all.

    :param v: vertical tension component(s) at the far point [N].
    :param v_a: vertical component at the near point [N].
    :param dv: v - v_a, known exactly by the caller (w s) [N].
    :param t: hypot(h, v) [N].
    :param t_a: hypot(h, v_a) [N].
    :param h: horizontal tension, > 0 unless v and v_a share a sign [N].

    :returns: The difference, shaped like v.
    """
    v = np.asarray(v, dtype=float)
    same_sign = v * v_a > 0.0
    with np.errstate(divide='ignore', invalid='ignore', over='ignore'):
        stable = np.arcsinh(dv * (v + v_a) / (v * t_a + v_a * t))
        direct = np.arcsinh(v / h) - np.arcsinh(v_a / h)
    return np.where(same_sign, stable, direct)


def _catenary_residual(x: np.ndarray, span: float, rise: float, length: float, w: float,
                       ea: float) -> tuple[np.ndarray, np.ndarray]:
    """Closure of the elastic catenary at B, and its Jacobian, for unknowns x = (H, V_B)."""
    h, v_b = float(x[0]), float(x[1])
    wl = w * length
    v_a = v_b - wl
    t_a = math.hypot(h, v_a)
    t_b = math.hypot(h, v_b)
    d_asinh = float(_asinh_difference(v_b, v_a, wl, t_b, t_a, h))
    # T_B - T_A = (V_B - V_A)(V_B + V_A) / (T_B + T_A): no cancellation on a taut line.
    f = np.array([
        h * length / ea + h / w * d_asinh - span,
        length * (v_a + v_b) * (0.5 / ea + 1.0 / (t_a + t_b)) - rise,
    ])
    # Symmetric: it is the compliance matrix of the line's end.
    off = h / w * (1.0 / t_b - 1.0 / t_a)
    jac = np.array([
        [length / ea + (d_asinh - v_b / t_b + v_a / t_a) / w, off],
        [off, length / ea + (v_b / t_b - v_a / t_a) / w],
    ])
    return f, jac


def _asinh_between(p: float, q: float, h: float) -> float:
    """Return asinh(q / h) - asinh(p / h) for p, q of one sign (or 0), without cancellation."""
    tp, tq = math.hypot(h, p), math.hypot(h, q)
    return math.asinh((q - p) * (q + p) / (q * tp + p * tq)) if q != p else 0.0


def _curve_integrals(h: float, v_a: float, v: float, w: float,
                     curve: TensionCurve) -> tuple:
    """
    Return the elastic parts of x, z and dx/dH from vertical force v_a to v (> v_a).

    int e(T) H / T dV / w, int e(T) V / T dV / w and int d/dH (e(T) H / T) dV / w, e = a + b T
    on each piece, over [v_a, v] split at V = 0 and where T crosses a piece's first tension.
    """
    starts, a, b = curve.inverse_pieces()
    cuts = [v_a, v, 0.0]
    for t_k in starts[1:]:
        if t_k > h:
            side = math.sqrt((t_k - h) * (t_k + h))
            cuts += [side, -side]
    cuts = sorted(c for c in set(cuts) if v_a <= c <= v)
    x = z = dh = 0.0
    for p, q in zip(cuts, cuts[1:]):
        tp, tq = math.hypot(h, p), math.hypot(h, q)
        k = int(np.clip(np.searchsorted(starts, math.hypot(h, 0.5 * (p + q))) - 1, 0,
                        len(starts) - 1))
        z += a[k] * (q - p) * (q + p) / (tq + tp) + 0.5 * b[k] * (q - p) * (q + p)
        if h > 0.0:  # a vertical hang (H = 0) has no horizontal extent
            asinh = _asinh_between(p, q, h)
            x += a[k] * h * asinh + b[k] * h * (q - p)
            dh += a[k] * (asinh - (q / tq - p / tp)) + b[k] * (q - p)
    return x / w, z / w, dh / w


def _curve_catenary_residual(x: np.ndarray, span: float, rise: float, length: float, w: float,
                             curve: TensionCurve) -> tuple[np.ndarray, np.ndarray]:
    """Closure at B of the catenary of a line with a curve, and its Jacobian; x = (H, V_B)."""
    h, v_b = float(x[0]), float(x[1])
    wl = w * length
    v_a = v_b - wl
    t_a = math.hypot(h, v_a)
    t_b = math.hypot(h, v_b)
    d_asinh = float(_asinh_difference(v_b, v_a, wl, t_b, t_a, h))
    x_el, z_el, dh_el = _curve_integrals(h, v_a, v_b, w, curve)
    e_a, e_b = (float(e) for e in curve.strain_at([t_a, t_b]))
    f = np.array([
        h / w * d_asinh + x_el - span,
        length * (v_a + v_b) / (t_a + t_b) + z_el - rise,
    ])
    # Symmetric, as the linear one: the compliance matrix of the line's end.
    off = h / w * ((1.0 + e_b) / t_b - (1.0 + e_a) / t_a)
    jac = np.array([
        [(d_asinh - v_b / t_b + v_a / t_a) / w + dh_el, off],
        [off, ((1.0 + e_b) * v_b / t_b - (1.0 + e_a) * v_a / t_a) / w],
    ])
    return f, jac


def _equivalent_ea(curve: Optional[TensionCurve], ea: float, span: float, rise: float,
                   length: float) -> float:
    """Return a linear EA to start a curve's Newton from: its secant at the chord's strain."""
    if curve is None:
        return ea
    strain = math.hypot(span, rise) / length - 1.0
    if strain <= 0.0:
        return float(curve.slopes[0])
    return float(curve.tension(strain)) / strain


def _catenary_guess(span: float, rise: float, length: float, w: float,
                    ea: float) -> np.ndarray:
    """Start (H, V_B) from MoorPy's lambda guess, raised to a taut chord's elastic stretch."""
    chord = math.hypot(span, rise)
    if span <= _MIN_SPAN_FRACTION * length:  # vertical: V_B = w (rise + L) / 2, H ~ 0
        lam = 1e6
    elif chord >= length:
        lam = 0.2
    else:
        lam = math.sqrt(3.0 * ((length * length - rise * rise) / (span * span) - 1.0))
        lam = max(lam, 1e-6)
    h = max(abs(0.5 * w * span / lam), 1e-300)
    v_b = 0.5 * w * (rise / math.tanh(lam) + length)
    # A chord longer than L pulls at least the straight stretch tension: start above it.
    stretch_tension = ea * (chord / length - 1.0)
    if stretch_tension * span / chord > h:
        h = stretch_tension * span / chord
        v_b = stretch_tension * rise / chord + 0.5 * w * length
    return np.array([h, v_b])


# -------------------------------------------------------------------------------- Newton


def _positive_fraction(h: float, dh: float) -> float:
    """Largest step fraction <= 1 that shrinks H by no more than _MAX_H_SHRINK."""
    floor = _MAX_H_SHRINK * h
    if h + dh >= floor:
        return 1.0
    return (floor - h) / dh


def _newton_step(f: np.ndarray, jac: np.ndarray) -> np.ndarray:
    det = jac[0, 0] * jac[1, 1] - jac[0, 1] * jac[1, 0]
    if det == 0.0 or not math.isfinite(det):
        raise CatenaryError('singular Jacobian: the line has no unique equilibrium here')
    return np.array([
        (-f[0] * jac[1, 1] + f[1] * jac[0, 1]) / det,
        (-f[1] * jac[0, 0] + f[0] * jac[1, 0]) / det,
    ])


def _newton(residual: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
            start: np.ndarray, scale: float, what: str) -> np.ndarray:
    """
    Solve residual(x) = 0 for x = (H, V) with H > 0 by Newton with backtracking.

    :param residual: returns (f (2,), Jacobian (2, 2)) at x; f in metres.
    :param start: initial (H, V), H > 0.
    :param scale: length the residual is measured against (the line's length) [m].
    :param what: name of the problem, for the error message.

    :returns: The converged (H, V).

    :raises CatenaryError: the residual did not fall below _ROUNDING_TOLERANCE * scale (Newton
        aims at _TOLERANCE * scale and stops there).
    """
    x = np.array(start, dtype=float)
    f, jac = residual(x)
    norm = math.hypot(f[0], f[1])
    evaluations = 1
    while norm > _TOLERANCE * scale and evaluations < _MAX_EVALUATIONS:
        step = _newton_step(f, jac)
        alpha = _positive_fraction(x[0], step[0])
        for _ in range(_MAX_HALVINGS):
            trial = x + alpha * step
            f_trial, jac_trial = residual(trial)
            evaluations += 1
            norm_trial = math.hypot(f_trial[0], f_trial[1])
            if norm_trial <= (1.0 - 1e-4 * alpha) * norm:  # Armijo: a real decrease
                break
            alpha *= 0.5
        else:
            break  # no descent left: rounding, or no solution
        x, f, jac, norm = trial, f_trial, jac_trial, norm_trial
    if norm <= _ROUNDING_TOLERANCE * scale:
        return x
    raise CatenaryError(
        f'{what} did not converge: closure residual {norm:.3g} m for a {scale:.6g} m line')


# ---------------------------------------------------------------------- planar catenary


def solve_catenary(span: float, rise: float, length: float, weight_per_length: float,
                   axial_stiffness: float,
                   tension_curve: Optional[TensionCurve] = None) -> CatenarySolution:
    """
    Solve Irvine's elastic catenary between A = (0, 0) and B = (span, rise).

    Handles slack, U-shaped, nearly taut and stretched (chord > L) lines, very soft lines,
    B below A, and a vertical hang (a span below 1e-9 L is solved as 1e-9 L).

    :param span: horizontal distance from A to B [m], >= 0.
    :param rise: height of B above A [m], any sign.
    :param length: unstretched length L [m], > 0.
    :param weight_per_length: weight w per unstretched metre [N/m], > 0.
    :param axial_stiffness: EA [N], > 0.
    :param tension_curve: the line's strain-tension curve; EA then only starts Newton.

    :returns: The end forces.

    :raises CatenaryError: an input is invalid, or Newton did not converge.
    """
    span = _check_non_negative('span', span)
    rise = _check_finite('rise', rise)
    length = _check_positive('length', length)
    w = _check_positive('weight_per_length', weight_per_length)
    ea = _check_positive('axial_stiffness', axial_stiffness)
    span = max(span, _MIN_SPAN_FRACTION * length)
    if rise > 0.0:
        # Solve from B, so that the unknown is the lower end's V: it can be tiny (a line
        # hanging almost straight up from A), and V_B - w L would lose it to rounding.
        h, v_a, v_b = _solve_lower_end(span, -rise, length, w, ea, tension_curve)
        v_a, v_b = -v_b, -v_a
    else:
        h, v_a, v_b = _solve_lower_end(span, rise, length, w, ea, tension_curve)
    return CatenarySolution(h, v_a, v_b, math.hypot(h, v_a), math.hypot(h, v_b))


def _solve_lower_end(span: float, rise: float, length: float, w: float, ea: float,
                     curve: Optional[TensionCurve] = None) -> tuple[float, float, float]:
    """Return (H, V_A, V_B) of a catenary whose end B is not above A (rise <= 0)."""
    if curve is None:
        def residual(x):
            return _catenary_residual(x, span, rise, length, w, ea)
    else:
        def residual(x):
            return _curve_catenary_residual(x, span, rise, length, w, curve)
    starts = (
        _catenary_guess(span, rise, length, w, _equivalent_ea(curve, ea, span, rise, length)),
        # Nearly vertical lines whose lower end is almost unloaded defeat the first start
        # (V changes sign within H of the solution): begin from the vertical hang there.
        np.array([0.5 * w * span * 1e-6, 0.5 * w * (rise + length)]),
    )
    for start in starts:
        try:
            h, v_b = _newton(residual, start, length, 'elastic catenary')
        except CatenaryError as error:
            failure = error
            continue
        return float(h), float(v_b - w * length), float(v_b)
    raise failure


def catenary_profile(solution: CatenarySolution, length: float, weight_per_length: float,
                     axial_stiffness: float, s: ArrayLike,
                     tension_curve: Optional[TensionCurve] = None
                     ) -> tuple[np.ndarray, np.ndarray]:
    """
    Return the planar shape of a solved catenary.

    :param solution: from solve_catenary with the same line properties.
    :param length: unstretched length L [m], > 0.
    :param weight_per_length: w [N/m], > 0.
    :param axial_stiffness: EA [N], > 0.
    :param s: unstretched arc lengths from A [m] (any shape).
    :param tension_curve: the line's strain-tension curve (EA then unused).

    :returns: (x, z): horizontal and vertical positions relative to A [m], shaped like s.

    :raises CatenaryError: an input is invalid.
    """
    _check_positive('length', length)
    w = _check_positive('weight_per_length', weight_per_length)
    ea = _check_positive('axial_stiffness', axial_stiffness)
    s = np.asarray(s, dtype=float)
    h = solution.horizontal_tension
    v_a = solution.vertical_a
    v = v_a + w * s
    t = np.hypot(h, v)
    t_a = math.hypot(h, v_a)
    if h > 0.0:
        x = h / w * _asinh_difference(v, v_a, w * s, t, t_a, h)
    else:  # a vertical hang: no horizontal force, no horizontal extent
        x = np.zeros_like(s)
    # z = (V^2 - V_A^2) / (2 w EA) + (T - T_A) / w, written without cancellation; the
    # denominator is 0 only at a zero-tension point, where z is 0 too.
    denominator = np.asarray(t + t_a)
    inverse = np.divide(1.0, denominator, out=np.zeros_like(denominator),
                        where=denominator > 0.0)
    if tension_curve is None:
        if h > 0.0:
            x = h * s / ea + x
        return x, s * (v + v_a) * (0.5 / ea + inverse)
    # the inextensible catenary plus the curve's stretch, piece by piece, at every s
    x, z = x.copy(), s * (v + v_a) * inverse
    flat_x, flat_z = x.reshape(-1), z.reshape(-1)
    for i, v_i in enumerate(v.reshape(-1)):
        if v_i > v_a:
            dx, dz, _ = _curve_integrals(h, v_a, float(v_i), w, tension_curve)
            flat_x[i] += dx
            flat_z[i] += dz
    return x, z


# ---------------------------------------------------------------------------- 3-D helpers


def _is_weightless(weight_per_length: float, gravity: np.ndarray) -> bool:
    return weight_per_length == 0.0 or not np.any(gravity)


def _vertical_frame(end_a: np.ndarray, end_b: np.ndarray,
                    gravity: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, float]:
    """Return (up, horizontal unit vector, span, rise) of the chord A -> B under gravity."""
    up = -gravity / np.linalg.norm(gravity)
    chord = end_b - end_a
    rise = float(chord @ up)
    horizontal = chord - rise * up
    span = float(np.linalg.norm(horizontal))
    if span > 1e-12 * float(np.linalg.norm(chord)):
        return up, horizontal / span, span, rise
    # Vertical chord: any horizontal direction will do; take the world axis least along up.
    axis = np.zeros(3)
    axis[int(np.argmin(np.abs(up)))] = 1.0
    horizontal = axis - (axis @ up) * up
    return up, horizontal / np.linalg.norm(horizontal), 0.0, rise


def _close_on_end(points: np.ndarray, fraction: np.ndarray, end_b: np.ndarray,
                  reached_b: np.ndarray) -> np.ndarray:
    """Spread the closure error (<= 1e-12 L, or the tiny span of a vertical hang) along s."""
    return points + np.outer(fraction, end_b - reached_b)


def _straight_line(end_a: np.ndarray, end_b: np.ndarray, segments: int) -> np.ndarray:
    fraction = np.linspace(0.0, 1.0, segments + 1)
    return end_a + np.outer(fraction, end_b - end_a)


def _check_line(end_a, end_b, gravity, length, weight_per_length, axial_stiffness) -> tuple:
    """Return the 3-D functions' line inputs checked (CatenaryError names a bad one)."""
    return (_check_point('end_a', end_a), _check_point('end_b', end_b),
            _check_point('gravity', gravity), _check_positive('length', length),
            _check_non_negative('weight_per_length', weight_per_length),
            _check_positive('axial_stiffness', axial_stiffness))


def catenary_points(end_a: ArrayLike, end_b: ArrayLike, length: float,
                    weight_per_length: float, axial_stiffness: float, gravity: ArrayLike,
                    s: ArrayLike, tension_curve: Optional[TensionCurve] = None) -> np.ndarray:
    """
    Return world points of the elastic catenary between two ends.

    :param end_a: (3,) end A [m].
    :param end_b: (3,) end B [m].
    :param length: unstretched length L [m], > 0.
    :param weight_per_length: weight per unstretched metre at this gravity [N/m], >= 0.
    :param axial_stiffness: EA [N], > 0.
    :param gravity: (3,) gravity vector [m/s^2], any direction; zero means weightless.
    :param s: (M,) unstretched arc lengths from A [m].
    :param tension_curve: the line's strain-tension curve, if it has one.

    :returns: (M, 3) points; s = 0 gives end A and s = L gives end B.

    :raises CatenaryError: an input is invalid, or the catenary did not converge.
    """
    end_a, end_b, gravity, length, w, ea = _check_line(
        end_a, end_b, gravity, length, weight_per_length, axial_stiffness)
    s = np.asarray(s, dtype=float).reshape(-1)
    fraction = s / length
    if _is_weightless(w, gravity):
        # Straight; stretched evenly if the chord is longer than L, else spread evenly.
        return end_a + np.outer(fraction, end_b - end_a)
    up, horizontal, span, rise = _vertical_frame(end_a, end_b, gravity)
    solution = solve_catenary(span, rise, length, w, ea, tension_curve)
    x, z = catenary_profile(solution, length, w, ea, np.append(s, length), tension_curve)
    points = end_a + np.outer(x, horizontal) + np.outer(z, up)
    return _close_on_end(points[:-1], fraction, end_b, points[-1])


# ------------------------------------------------------------------- lumped-mass chain


def _chain_residual(x: np.ndarray, span: float, rise: float, l0: float,
                    offsets: np.ndarray, ea: float) -> tuple[np.ndarray, np.ndarray]:
    """
    Closure of the chain at B, and its Jacobian, for x = (H, V of the first segment).

    offsets (N,): what the interior nodes before each segment add to its vertical tension
    component (their weights summed from A; 0 for the first segment).
    """
    h, v0 = float(x[0]), float(x[1])
    segments = len(offsets)
    v = v0 + offsets
    t = np.hypot(h, v)
    inv_t = 1.0 / t
    inv_t3 = inv_t ** 3
    f = np.array([
        l0 * (h * np.sum(inv_t) + segments * h / ea) - span,
        l0 * (np.sum(v * inv_t) + np.sum(v) / ea) - rise,
    ])
    off = -l0 * h * np.sum(v * inv_t3)
    jac = np.array([
        [l0 * (np.sum(v * v * inv_t3) + segments / ea), off],
        [off, l0 * (h * h * np.sum(inv_t3) + segments / ea)],
    ])
    return f, jac


def _curve_chain_residual(x: np.ndarray, span: float, rise: float, l0: float,
                          offsets: np.ndarray,
                          curve: TensionCurve) -> tuple[np.ndarray, np.ndarray]:
    """
    Closure of the chain of a line with a curve, and its Jacobian (as _chain_residual).

    A segment of tension t is l0 (1 + e(t)) long, e the curve's inverse, de/dt its
    compliance c: d/dH of l0 (1 + e) H / t is l0 ((1 + e) V^2 / t^3 + c H^2 / t^2), and so on.
    """
    h, v0 = float(x[0]), float(x[1])
    v = v0 + offsets
    t = np.hypot(h, v)
    stretch = 1.0 + curve.strain_at(t)
    compliance = curve.compliance(t)
    inv_t = 1.0 / t
    inv_t2 = inv_t * inv_t
    inv_t3 = inv_t2 * inv_t
    f = np.array([
        l0 * h * np.sum(stretch * inv_t) - span,
        l0 * np.sum(stretch * v * inv_t) - rise,
    ])
    off = l0 * h * np.sum(v * (compliance * inv_t2 - stretch * inv_t3))
    jac = np.array([
        [l0 * np.sum(stretch * v * v * inv_t3 + compliance * h * h * inv_t2), off],
        [off, l0 * np.sum(stretch * h * h * inv_t3 + compliance * v * v * inv_t2)],
    ])
    return f, jac


def _chain_verticals(span: float, rise: float, length: float, loads: np.ndarray,
                     ea: float, curve: Optional[TensionCurve] = None
                     ) -> tuple[float, np.ndarray]:
    """
    Return H and the vertical components (N,) of the segments' tensions, from A to B.

    loads (N - 1,): the weights of the interior nodes [N], any sign (a buoyant node pulls
    up); their sum must not be 0 unless every one is (the caller's weightless case).
    """
    if loads.sum() < 0.0:
        # A buoyant chain is a heavy one upside down: flip the vertical.
        h, v = _chain_verticals(span, -rise, length, -loads, ea, curve)
        return h, -v
    if rise < 0.0:
        # Solve from B so that the unknown is the lower end's V (see solve_catenary).
        h, v = _chain_verticals(span, -rise, length, loads[::-1], ea, curve)
        return h, -v[::-1]
    segments = len(loads) + 1
    l0 = length / segments
    offsets = np.concatenate([[0.0], np.cumsum(loads)])
    # Seed from the catenary of the mean weight (of a uniform chain: its own), whose V at the
    # middle of the first segment is the chain's first segment's V.
    w = max(loads.sum(), 1e-3 * np.abs(loads).sum()) / (length - l0) if segments > 1 else 0.0
    if w > 0.0:
        seed = solve_catenary(span, rise, length, w, ea, curve)
        start = np.array([seed.horizontal_tension, seed.vertical_a + 0.5 * w * l0])
    else:  # one segment: a straight spring
        chord = math.hypot(span, rise)
        tension = _tension(max(chord / length - 1.0, 1e-9), ea, curve)
        start = np.array([tension * span / chord, tension * rise / chord])
    span = max(span, _MIN_SPAN_FRACTION * length)
    if curve is None:
        def residual(x):
            return _chain_residual(x, span, rise, l0, offsets, ea)
    else:
        def residual(x):
            return _curve_chain_residual(x, span, rise, l0, offsets, curve)
    h, v0 = _newton(residual, start, length, 'lumped-mass chain')
    return float(h), v0 + offsets


def _tension(strain: float, ea: float, curve: Optional[TensionCurve]) -> float:
    """Return the tension at a strain >= 0 [N]: EA strain, or the curve's."""
    return ea * strain if curve is None else float(curve.tension(strain))


def _strain(tension: np.ndarray, ea: float, curve: Optional[TensionCurve]) -> np.ndarray:
    """Return the strain at tensions >= 0: T / EA, or the curve's inverse."""
    return tension / ea if curve is None else curve.strain_at(tension)


def _weightless_chain(end_a: np.ndarray, end_b: np.ndarray, length: float, segments: int,
                      ea: float, curve: Optional[TensionCurve] = None) -> ChainEquilibrium:
    chord = end_b - end_a
    chord_length = float(np.linalg.norm(chord))
    # A chain shorter than its chord stretches evenly; a longer one rests unloaded (any
    # shape is an equilibrium; the chord is the obvious one).
    tension = _tension(max(chord_length / length - 1.0, 0.0), ea, curve)
    direction = chord / chord_length if chord_length > 0.0 else np.zeros(3)
    return ChainEquilibrium(
        positions=_straight_line(end_a, end_b, segments),
        force_a=tension * direction,
        force_b=-tension * direction,
        segment_tension=np.full(segments, tension),
        horizontal_tension=tension,
    )


def chain_equilibrium(end_a: ArrayLike, end_b: ArrayLike, length: float, segments: int,
                      weight_per_length: float, axial_stiffness: float,
                      gravity: ArrayLike,
                      tension_curve: Optional[TensionCurve] = None) -> ChainEquilibrium:
    """
    Return the exact static equilibrium of the N-segment lumped-mass chain.

    N equal linear springs of unstretched length l0 = L / N (length l0 (1 + T / EA)); the
    interior nodes carry the weight w l0, the two fixed end nodes w l0 / 2 each. Newton on
    the two closure equations, seeded by the elastic catenary. This is what a converged
    simulation with the same lumping settles to (moordyn_static.csv's disc_* values).

    :param end_a: (3,) end A [m].
    :param end_b: (3,) end B [m].
    :param length: unstretched length L [m], > 0.
    :param segments: N >= 1.
    :param weight_per_length: weight per unstretched metre at this gravity [N/m], >= 0.
    :param axial_stiffness: EA [N], > 0.
    :param gravity: (3,) gravity vector [m/s^2]; zero means weightless (a straight chain).
    :param tension_curve: the line's strain-tension curve: a segment of tension T is then
        l0 (1 + e(T)) long (EA only starts Newton).

    :returns: Positions, end forces and segment tensions.

    :raises CatenaryError: an input is invalid, or there is no equilibrium Newton can reach
        (for example a chain folded at a vertical hang, or too few segments to sag).
    """
    end_a, end_b, gravity, length, w, ea = _check_line(
        end_a, end_b, gravity, length, weight_per_length, axial_stiffness)
    segments = _check_segments(segments)
    if _is_weightless(w, gravity):
        return _weightless_chain(end_a, end_b, length, segments, ea, tension_curve)
    weights = np.full(segments + 1, w * length / segments)
    weights[[0, -1]] *= 0.5
    return _loaded_chain(end_a, end_b, length, weights, ea, gravity, tension_curve)


def loaded_chain_equilibrium(end_a: ArrayLike, end_b: ArrayLike, length: float,
                             node_weights: ArrayLike, axial_stiffness: float,
                             gravity: ArrayLike,
                             tension_curve: Optional[TensionCurve] = None
                             ) -> ChainEquilibrium:
    """
    Return the static equilibrium of a lumped-mass chain whose nodes weigh node_weights.

    As chain_equilibrium, N = len(node_weights) - 1 equal segments, but every node has its
    own weight along gravity, of either sign: a node in water weighs its submerged weight,
    which is negative on a line lighter than water (node_weights from node_weights()).

    :param end_a: (3,) end A [m].
    :param end_b: (3,) end B [m].
    :param length: unstretched length L [m], > 0.
    :param node_weights: (N + 1,) weight of each node [N] (the ends' go into the end
        forces), finite.
    :param axial_stiffness: EA [N], > 0.
    :param gravity: (3,) gravity vector [m/s^2]; it gives the direction 'down'.
    :param tension_curve: the line's strain-tension curve, if it has one.

    :returns: Positions, end forces and segment tensions.

    :raises CatenaryError: an input is invalid, or Newton did not converge.
    """
    end_a, end_b, gravity, length, _, ea = _check_line(
        end_a, end_b, gravity, length, 0.0, axial_stiffness)
    weights = np.asarray(node_weights, dtype=float).reshape(-1)
    _check_segments(len(weights) - 1)
    if not np.all(np.isfinite(weights)):
        raise CatenaryError('node_weights must be finite')
    if not np.any(gravity) or not np.any(weights[1:-1]):
        chain = _weightless_chain(end_a, end_b, length, len(weights) - 1, ea, tension_curve)
        if np.any(gravity):
            down = gravity / np.linalg.norm(gravity)
            chain = ChainEquilibrium(chain.positions, chain.force_a + weights[0] * down,
                                     chain.force_b + weights[-1] * down,
                                     chain.segment_tension, chain.horizontal_tension)
        return chain
    if weights[1:-1].sum() == 0.0:
        raise CatenaryError('node_weights of the interior sum to 0 with mixed signs: no '
                            'unique equilibrium to seed')
    return _loaded_chain(end_a, end_b, length, weights, ea, gravity, tension_curve)


def _loaded_chain(end_a: np.ndarray, end_b: np.ndarray, length: float, weights: np.ndarray,
                  ea: float, gravity: np.ndarray,
                  curve: Optional[TensionCurve] = None) -> ChainEquilibrium:
    """Solve the chain whose nodes weigh `weights` (N + 1,), checked inputs."""
    segments = len(weights) - 1
    up, horizontal, span, rise = _vertical_frame(end_a, end_b, gravity)
    l0 = length / segments
    h, v = _chain_verticals(span, rise, length, weights[1:-1], ea, curve)
    t = np.hypot(h, v)
    stretched = l0 * (1.0 + _strain(t, ea, curve))
    steps = np.outer(stretched * h / t, horizontal) + np.outer(stretched * v / t, up)
    positions = end_a + np.vstack([np.zeros(3), np.cumsum(steps, axis=0)])
    fraction = np.linspace(0.0, 1.0, segments + 1)
    positions = _close_on_end(positions, fraction, end_b, positions[-1])
    return ChainEquilibrium(
        positions=positions,
        force_a=h * horizontal + v[0] * up - weights[0] * up,
        force_b=-h * horizontal - v[-1] * up - weights[-1] * up,
        segment_tension=t,
        horizontal_tension=float(h),
    )


# ------------------------------------------------------------------- water and seabed


def wetted_fraction(z_a: ArrayLike, z_b: ArrayLike, water_level: float,
                    volume_diameter: float) -> np.ndarray:
    """
    Return the wetted fraction of segments with ends at heights z_a, z_b [m].

    The mean over the segment of r(z) = clip((water_level - z) / dv + 0.5, 0, 1), z linear
    between its ends: the physics' smooth submergence, a ramp one volume diameter dv wide
    centred on the surface. With t(z) the ramp's argument and P(t) the integral of the
    clipped ramp from 0 to t, the mean is (P(t_b) - P(t_a)) / (t_b - t_a), r(z_mid) when
    the ends are level within 1e-9 m. No water (water_level -inf): 0.

    :param z_a: heights of the segments' first ends [m].
    :param z_b: heights of their second ends [m].
    :param water_level: height of the still surface [m]; -inf: no water.
    :param volume_diameter: dv [m]; a dv below 1e-6 m is taken as 1e-6 m (a sharp surface).

    :returns: Fractions in [0, 1], shaped like z_a.
    """
    # the physics' own ramp (forces/fluid.py), elementwise: the start sees what the steps do
    dv = max(float(volume_diameter), 1e-6)
    return np.vectorize(fluid.wetted_fraction, otypes=[float])(
        np.asarray(z_a, dtype=float), np.asarray(z_b, dtype=float), float(water_level), dv)


def node_weights(positions: ArrayLike, rest: ArrayLike, weight_per_length: float,
                 submerged_weight_per_length: float, water_level: float,
                 volume_diameter: float) -> np.ndarray:
    """
    Return each node's weight [N] (along gravity; negative: it floats) where it is now.

    The physics' lumping: node i carries half of each adjacent segment; a segment weighs
    weight_per_length (in air) over its dry part and submerged_weight_per_length over its
    wetted fraction (wetted_fraction) of its rest length.

    :param positions: (N + 1, 3) node positions [m] (z up: the surface is a level of z).
    :param rest: (N,) rest lengths of the segments [m].
    :param weight_per_length: w in air [N/m] ((m - rho_air A_v) g).
    :param submerged_weight_per_length: w in water [N/m] ((m - rho_water A_v) g).
    :param water_level: height of the still surface [m]; -inf: no water.
    :param volume_diameter: dv [m] (see wetted_fraction).

    :returns: (N + 1,) weights [N].
    """
    x = np.asarray(positions, dtype=float)
    rest = np.asarray(rest, dtype=float)
    wet = wetted_fraction(x[:-1, 2], x[1:, 2], water_level, volume_diameter)
    segment = rest * (weight_per_length + wet * (submerged_weight_per_length
                                                 - weight_per_length))
    weights = np.zeros(len(x))
    weights[:-1] += 0.5 * segment
    weights[1:] += 0.5 * segment
    return weights


@dataclass(frozen=True)
class SeabedCatenary:
    """
    An elastic catenary lying partly on a flat, frictionless seabed (planar convention).

    From A: a suspended part down to the touchdown point, a straight part lying on the
    seabed, a suspended part up to B; the tension is horizontal (H) where the line meets the
    seabed and H throughout the laid part. An end on the seabed has no suspended part.

    :ivar horizontal_tension: H [N].
    :ivar suspended_a: unstretched length of the suspended part at A [m].
    :ivar laid_length: unstretched length lying on the seabed [m] (> 0).
    :ivar suspended_b: the same at B [m].
    :ivar height_a: height of A above the seabed [m] (>= 0).
    :ivar height_b: the same of B [m].
    :ivar tension_a: tension at A [N], hypot(H, w suspended_a).
    :ivar tension_b: tension at B [N].
    """

    horizontal_tension: float
    suspended_a: float
    laid_length: float
    suspended_b: float
    height_a: float
    height_b: float
    tension_a: float
    tension_b: float


def _hanging(h: float, w: float, ea: float, sigma: ArrayLike) -> tuple:
    """
    Return (x, z) of a suspended part at unstretched arc length sigma from its touchdown.

    The tension there is horizontal (H = h); at sigma it is (H, w sigma).
    """
    sigma = np.asarray(sigma, dtype=float)
    u = w * sigma / h
    x = h / w * np.arcsinh(u) + h * sigma / ea
    z = h / w * (u * u / (np.sqrt(1.0 + u * u) + 1.0)) + 0.5 * w * sigma * sigma / ea
    return x, z


def _hanging_length(height: float, h: float, w: float, ea: float) -> float:
    """Return the unstretched length of a suspended part that rises `height` at tension H."""
    if height <= 0.0:
        return 0.0
    a = h / w
    # Newton on z(u) = a (sqrt(1 + u^2) - 1) + a^2 w u^2 / (2 EA) = height (u = w s / H): z
    # is convex and increasing, so Newton from the inextensible root (above) comes down
    # monotonically.
    u = math.sqrt((1.0 + height / a) ** 2 - 1.0)
    for _ in range(100):
        root = math.sqrt(1.0 + u * u)
        z = a * u * u / (root + 1.0) + 0.5 * a * a * w * u * u / ea
        slope = a * u / root + a * a * w * u / ea
        step = (z - height) / slope
        u -= step
        if abs(step) <= 1e-15 * u:
            break
    return a * u


def solve_seabed_catenary(span: float, rise: float, bed: float, length: float,
                          weight_per_length: float,
                          axial_stiffness: float) -> Optional[SeabedCatenary]:
    """
    Solve the elastic catenary between A = (0, 0) and B = (span, rise) over a seabed.

    The frictionless case of MoorPy's catenary with seabed contact (its profile types 2,
    4 and 5: an end on the seabed or both above it, the laid part straight at tension H),
    for the seabed at height `bed` relative to A. An end below the seabed is taken as on
    it. Solves the one closure in H, x_A(H) + (L - s_A - s_B)(1 + H / EA) + x_B(H) = span,
    by bisection (it grows with H).

    :param span: horizontal distance from A to B [m], >= 0.
    :param rise: height of B above A [m].
    :param bed: height of the seabed above A [m].
    :param length: unstretched length L [m], > 0.
    :param weight_per_length: w [N/m], > 0.
    :param axial_stiffness: EA [N], > 0.

    :returns: The solution; None when the line does not reach the seabed (it hangs free:
        solve_catenary), or lies slack on it (no tension can lay it: H would be 0).

    :raises CatenaryError: an input is invalid.
    """
    span = _check_non_negative('span', span)
    rise = _check_finite('rise', rise)
    bed = _check_finite('bed', bed)
    length = _check_positive('length', length)
    w = _check_positive('weight_per_length', weight_per_length)
    ea = _check_positive('axial_stiffness', axial_stiffness)
    height_a, height_b = max(-bed, 0.0), max(rise - bed, 0.0)

    def closure(h):
        s_a = _hanging_length(height_a, h, w, ea)
        s_b = _hanging_length(height_b, h, w, ea)
        laid = length - s_a - s_b
        x_a = float(_hanging(h, w, ea, s_a)[0])
        x_b = float(_hanging(h, w, ea, s_b)[0])
        return x_a + x_b + laid * (1.0 + h / ea) - span, s_a, s_b, laid

    # The largest H that still lays some line: the suspended parts then take all of L.
    low, high = 1e-12 * w * length, w * length
    while closure(high)[3] > 0.0:
        high *= 4.0
        if high > 1e6 * ea:
            return None
    for _ in range(200):
        middle = math.sqrt(low * high)
        if closure(middle)[3] > 0.0:
            low = middle
        else:
            high = middle
        if high - low <= 1e-14 * high:
            break
    top = low
    if closure(top)[0] < 0.0:
        return None  # even just touching, the line is too long for the span: it hangs free
    low = 1e-12 * w * length
    if closure(low)[0] >= 0.0:
        return None  # slack on the seabed
    high = top
    for _ in range(400):
        middle = 0.5 * (low + high) if high < 4.0 * low else math.sqrt(low * high)
        if closure(middle)[0] < 0.0:
            low = middle
        else:
            high = middle
        if high - low <= 4e-16 * high:
            break
    h = 0.5 * (low + high)
    _, s_a, s_b, laid = closure(h)
    return SeabedCatenary(h, s_a, laid, s_b, height_a, height_b,
                          math.hypot(h, w * s_a), math.hypot(h, w * s_b))


def seabed_profile(solution: SeabedCatenary, weight_per_length: float,
                   axial_stiffness: float, s: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """
    Return the planar shape of a solved seabed catenary.

    :param solution: from solve_seabed_catenary with the same line properties.
    :param weight_per_length: w [N/m], > 0.
    :param axial_stiffness: EA [N], > 0.
    :param s: unstretched arc lengths from A [m] (any shape).

    :returns: (x, z): positions relative to A [m], shaped like s.
    """
    w = _check_positive('weight_per_length', weight_per_length)
    ea = _check_positive('axial_stiffness', axial_stiffness)
    s = np.asarray(s, dtype=float)
    h = solution.horizontal_tension
    s_a, laid = solution.suspended_a, solution.laid_length
    x_a, _ = _hanging(h, w, ea, s_a)
    bed = -solution.height_a
    hanging_a = _hanging(h, w, ea, np.clip(s_a - s, 0.0, None))
    on_bed = x_a + (np.clip(s, s_a, s_a + laid) - s_a) * (1.0 + h / ea)
    hanging_b = _hanging(h, w, ea, np.clip(s - s_a - laid, 0.0, None))
    x = np.where(s < s_a, x_a - hanging_a[0], on_bed + hanging_b[0])
    z = bed + np.where(s < s_a, hanging_a[1], hanging_b[1])
    return x, z


def _seabed_points(end_a: np.ndarray, end_b: np.ndarray, length: float, segments: int,
                   w: float, ea: float, bed: float) -> Optional[np.ndarray]:
    """Return the nodes of the seabed catenary (z up, seabed at z = bed), or None."""
    chord = end_b - end_a
    span = float(np.hypot(chord[0], chord[1]))
    if span > 1e-12 * length:
        horizontal = np.array([chord[0], chord[1], 0.0]) / span
    else:
        horizontal = np.array([1.0, 0.0, 0.0])
    solution = solve_seabed_catenary(span, float(chord[2]), bed - float(end_a[2]), length, w,
                                     ea)
    if solution is None:
        return None
    s = np.linspace(0.0, length, segments + 1)
    x, z = seabed_profile(solution, w, ea, s)
    # the profile starts at A, or where A is below the seabed, on the seabed above it
    points = end_a * np.array([1.0, 1.0, 0.0]) + np.outer(x, horizontal)
    points[:, 2] = z + max(float(end_a[2]), bed)
    return _close_on_end(points, s / length, end_b, points[-1]) + np.outer(
        1.0 - s / length, end_a - points[0])


# Fixed-point passes of a line crossing the surface: the node weights follow the shape, the
# shape the weights. A hanging line settles in a few; one floating on the surface may
# cycle, and the best pass is only a start for relax.
_WEIGHT_PASSES = 30
_WEIGHT_TOLERANCE = 1e-10


def _uniform_shape(end_a, end_b, length, segments, w, ea, gravity,
                   curve=None) -> Optional[np.ndarray]:
    """Return the chain's equilibrium, else the catenary, of one weight w (any sign), or None."""
    if w < 0.0:  # a buoyant line hangs upwards
        w, gravity = -w, -gravity
    shapes = (
        lambda: chain_equilibrium(end_a, end_b, length, segments, w, ea, gravity,
                                  curve).positions,
        lambda: catenary_points(end_a, end_b, length, w, ea, gravity,
                                np.linspace(0.0, length, segments + 1), curve),
    )
    for shape in shapes:
        try:
            positions = shape()
        except CatenaryError:
            continue
        if np.all(np.isfinite(positions)):
            return positions
    return None


def _water_shape(end_a, end_b, length, segments, w_air, w_water, water_level, dv, ea,
                 gravity, curve=None) -> Optional[np.ndarray]:
    """Return the chain's equilibrium with each node's weight where it lies, or a guess."""
    mid = 0.5 * (end_a[2] + end_b[2])
    positions = _uniform_shape(end_a, end_b, length, segments,
                               w_water if mid < water_level else w_air, ea, gravity, curve)
    if positions is None:
        return None
    rest = np.full(segments, length / segments)
    weights = node_weights(positions, rest, w_air, w_water, water_level, dv)
    scale = max(abs(w_air), abs(w_water)) * length / segments
    best, best_change = positions, math.inf
    for k in range(_WEIGHT_PASSES):
        try:
            positions = loaded_chain_equilibrium(end_a, end_b, length, weights, ea,
                                                 gravity, curve).positions
        except CatenaryError:
            break
        if not np.all(np.isfinite(positions)):
            break
        new = node_weights(positions, rest, w_air, w_water, water_level, dv)
        change = float(np.abs(new - weights).max())
        if change < best_change:
            best, best_change = positions, change
        if change <= _WEIGHT_TOLERANCE * scale:
            return positions
        # a line floating on the surface flips between sinking and floating: damp it
        weights = new if k < 5 else 0.5 * (weights + new)
    return best


def initial_shape(end_a: ArrayLike, end_b: ArrayLike, length: float, segments: int,
                  weight_per_length: float, axial_stiffness: float,
                  gravity: ArrayLike, *, submerged_weight_per_length: Optional[float] = None,
                  water_level: float = -math.inf, volume_diameter: float = 0.0,
                  seabed_level: float = -math.inf, seabed_sink: float = 0.0,
                  tension_curve: Optional[TensionCurve] = None) -> np.ndarray:
    """
    Return node positions to start a simulation at rest.

    Without water and seabed: the chain's exact equilibrium if Newton reaches it, else the
    elastic catenary sampled at s = linspace(0, L, N + 1), else the straight line between
    the ends. Never non-finite.

    With water (a finite water_level and submerged_weight_per_length): each node weighs
    what node_weights() gives where it lies, and the shape is the chain's equilibrium with
    those weights (a few fixed-point passes: exact for a line that hangs through the
    surface or lies below it; for one floating on the surface only a start). With a seabed
    that the line would pass through: the seabed catenary (solve_seabed_catenary) with the
    weight at the seabed, laid at seabed_level - seabed_sink (where a soft seabed holds a
    laid line), else the shape with its nodes lifted out of the seabed. Water and seabed are
    levels of z (REP-103: z up); the seabed catenary needs gravity along -z (else the nodes
    are only lifted). With a strain-tension curve every segment stretches by the curve,
    but in a seabed catenary, which stretches by T / EA (a start the caller's relaxation
    settles).

    :param end_a: (3,) end A [m].
    :param end_b: (3,) end B [m].
    :param length: unstretched length L [m], > 0.
    :param segments: N >= 1.
    :param weight_per_length: weight per unstretched metre at this gravity [N/m], >= 0 (in
        air: (m - rho_air A_v) |g|).
    :param axial_stiffness: EA [N], > 0.
    :param gravity: (3,) gravity vector [m/s^2].
    :param submerged_weight_per_length: weight per unstretched metre in water [N/m], (m -
        rho_water A_v) |g|, any sign (negative: the line floats); None: no water.
    :param water_level: z of the still surface [m]; -inf: no water.
    :param volume_diameter: dv [m], the width of the surface's ramp (wetted_fraction).
    :param seabed_level: z of the seabed [m]; -inf: none.
    :param seabed_sink: how far a laid line sinks into the seabed [m], >= 0: w / (k_b d).
    :param tension_curve: the line's strain-tension curve, if it has one.

    :returns: (N + 1, 3) positions, first = end A, last = end B.

    :raises CatenaryError: an input is invalid (solver failures fall back instead).
    """
    end_a, end_b, gravity, length, w, ea = _check_line(
        end_a, end_b, gravity, length, weight_per_length, axial_stiffness)
    segments = _check_segments(segments)
    water_level = _check_level('water_level', water_level)
    seabed_level = _check_level('seabed_level', seabed_level)
    seabed_sink = _check_non_negative('seabed_sink', seabed_sink)
    volume_diameter = _check_non_negative('volume_diameter', volume_diameter)
    water = water_level > -math.inf and submerged_weight_per_length is not None
    w_water = (_check_finite('submerged_weight_per_length', submerged_weight_per_length)
               if water else w)
    if water:
        positions = _water_shape(end_a, end_b, length, segments, w, w_water, water_level,
                                 volume_diameter, ea, gravity, tension_curve)
    else:
        positions = _uniform_shape(end_a, end_b, length, segments, w, ea, gravity,
                                   tension_curve)
    if positions is None:
        positions = _straight_line(end_a, end_b, segments)
    bed = seabed_level - seabed_sink
    if seabed_level == -math.inf or positions[:, 2].min() >= bed:
        return positions
    w_bed = w_water if water and seabed_level < water_level else w
    g = float(np.linalg.norm(gravity))
    if w_bed > 0.0 and g > 0.0 and np.allclose(gravity / g, [0.0, 0.0, -1.0], atol=1e-9):
        laid = _seabed_points(end_a, end_b, length, segments, w_bed, ea, bed)
        if laid is not None and np.all(np.isfinite(laid)):
            return laid
    lifted = positions.copy()
    lifted[1:-1, 2] = np.maximum(lifted[1:-1, 2], bed)
    return lifted


def _check_level(name: str, value: float) -> float:
    value = float(value)
    if math.isnan(value) or value == math.inf:
        raise CatenaryError(f'{name} must be finite or -inf (none), got {value}')
    return value
