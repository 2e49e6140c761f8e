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
Loads a ship passing on a parallel course exerts on a moored ship: Wang's method, any depth.

Method
------
S. Wang, "Dynamic effects of ship passage on moored vessels", Journal of the Waterways,
Harbors and Coastal Engineering Division, ASCE, 101(WW3), 1975, 247-258. Both hulls are
slender bodies described by their sectional-area curves S1 (moored ship, length L1) and S2
(passing ship, length L2), x measured from each midship. With the stagger xi (passing midship
ahead of the moored midship), the lateral distance eta > 0 between the centrelines, the
passing speed U and R = x2 - x1 + xi::

    X = rho U^2 / (2 pi) ∫∫ S1'(x1) S2'(x2) R / (R^2 + eta^2)^(3/2) dx2 dx1
    Y = rho U^2 eta / pi ∫∫ S1'(x1) S2'(x2) / (R^2 + eta^2)^(3/2) dx2 dx1
    N = rho U^2 eta / pi ∫∫ (x1 S1'(x1) + S1(x1)) S2'(x2) / (R^2 + eta^2)^(3/2) dx2 dx1

x1 runs over [-L1/2, L1/2] and x2 over [-L2/2, L2/2]. X is the force along the moored ship,
Y the force across it, positive toward the passing ship, and N the moment about its midship,
positive turning its bow toward the passing ship. These are the forms the secondary literature
gives for Wang (1975) (the paper's own pages could not be consulted here); K. S. Varyani,
P. Krishnankutty and M. Vantorre, "Prediction of load on mooring ropes of a container ship due
to the forces induced by a passing bulk carrier", MARSIM 2003, Kanazawa, describe the same
construction and add a method-of-images depth term. The constants were checked by deriving
them again from the model: the passing ship and its mirror image in a rigid free surface
(no waves: low Froude number) are a line of sources of strength -U d(2 S2)/dx per length;
the moored ship feels the pressure -rho dphi/dt of that flow along its length (its
longitudinal force is the integral of p S1') and, across it, 2 rho S1 dv/dt per length (the
Froude-Krylov term plus a lateral added mass equal to the displaced mass, the slender-body
value); with d/dt = -U d/dx and S1 = 0 at the ends, integration by parts gives exactly the
three lines above. Far from the moored ship they reduce to the interaction of two dipoles of
the two displaced volumes, X ~ -rho U^2 V1 V2 K''(xi) / (2 pi) with K = R / (R^2 + eta^2)^(3/2)
(test/test_passing_ship.py checks that limit, and saved outputs of an independent
implementation of the same equations: test/data/passing_ship/README.md).

The sectional-area curve is the parabola S(x) = S_m (1 - (2x/L)^2) with S_m = 1.5 C_b B T, so
that it holds the displaced volume C_b L B T (the far-field loads are set by those volumes;
for C_b > 2/3 S_m exceeds B T, the price of keeping the volume exact).

Conventions
-----------
Everything is in the moored ship's body axes (REP-103): x forward, y to port, z up, origin at
its midship. ``separation`` is the distance between the centrelines, positive when the
passing ship is on the starboard side (at body y = -separation), negative on the port side;
eta = |separation|. ``stagger`` is the passing midship's body x. Returned are (F_x, F_y, M_z):
surge force along +x, sway force along +y (port), yaw moment about +z (bow to port). From
Wang's signs: F_x = X; F_y = -sign(separation) Y and M_z = -sign(separation) N, since Y and N
act toward the passing ship. So abeam (stagger 0) the moored ship is drawn toward the passing
ship; a ship on the other side mirrors F_y and M_z and leaves F_x. The source strength is
proportional to the passing velocity and the pressure to its square, so the loads at a given
stagger do not depend on the passing direction (the parabolic hull is symmetric fore and aft);
a passage along -x reads the same curves in reverse order of stagger.

Finite depth: the method of images
----------------------------------
A flat sea bed at depth h under the rigid free surface is a wall the flow may not cross:
mirroring the two ships' sources in the bed and the mirrors in the surface, again and again,
satisfies both, and puts an image of the passing ship at every lateral distance
eta_n = sqrt(eta^2 + (2 n h)^2), n = ..., -1, 0, 1, ... (straight below and above it, the
line between the hulls tilted by atan(2 n h / eta)). Each image acts on the moored ship as
the passing ship would at eta_n, its sway and yaw projected on the horizontal by eta / eta_n:

    X_h = sum_n X(xi, eta_n),   Y_h = eta sum_n Y(xi, eta_n) / eta_n,
    N_h = eta sum_n N(xi, eta_n) / eta_n,

i.e. rho U^2 / (2 pi) sum_n I_x(eta_n), rho U^2 eta / pi sum_n I_y(eta_n) and
rho U^2 eta / pi sum_n I_n(eta_n) with the integrals above. This is the construction of
K. S. Varyani, P. Krishnankutty and M. Vantorre (MARSIM 2003), as three legacy programs
implement it: the US Navy's DYNMOOR 6.10 (2007, subroutine PARSHIP), and a workbook and a
worksheet of 2014-2016, all with n = -10..10 (test/data/passing_ship/README.md has them; the
module reproduces their saved outputs with ``image_pairs=10``). The terms fall as n^-5 once
2 n h passes the ships' lengths, so that truncation leaves their sums 0.6 % (the worksheet's
abeam sway) to 1.2 % low abeam, and far more off abeam, where the images matter out to the
stagger's distance: at a stagger of 10 ship lengths the workbook's truncated sway is a
quarter of the converged one, and at one ship length its surge has the wrong sign.

By default (``image_pairs=0``) the sum converges: the pairs +-1..+-N are summed term by term
and the rest, n > N, by the integral over n they approach (Euler-Maclaurin's midpoint rule:
the integral from N + 1/2 on, plus f'(N + 1/2) / 24 from the terms N and N + 1), whose
kernel, the point kernel integrated over the image distance z = 2 h n, is closed form:
integral from a of (R^2 + eta^2 + z^2)^(-3/2) dz = 1 / (s (s + a)), s^2 = R^2 + eta^2 + a^2
(_tail_kernel_integrals). N starts at 8 and doubles, stagger by stagger, until doubling it
changes each of surge, sway and yaw by less than 1e-4 of its sum (a load zero by symmetry,
surge and yaw abeam, by 1e-10 of the others). For config/berth.yaml's ship and passing ship
at 16 m of water (depth / draft 1.14), 40 to 150 m apart, the result agrees with a direct
sum of 20 000 pairs to 2e-6 of each load from abeam to 13 ship lengths off, in 23
evaluations of the integrals per stagger (the direct sum needs 64 to 2048 pairs for 1e-4);
for the legacy cases abeam, to 5e-8 (test_passing_ship.py).

The depth enters nowhere else (Limits says what that leaves out).

Numerics
--------
The integral over the passing ship is done in closed form (S2' is linear), written without
the 1/eta^2 cancellation of the textbook antiderivative. What is left, over the moored ship, is
smooth but, for small eta, varies on the scale eta where an end of the passing ship is abeam,
x1 = xi -+ L2/2 (complex singularities at distance eta). The moored ship is split there and
at x1 = xi into four panels; each gets Gauss-Legendre nodes through the sinh map
x = c + eta sinh(tau) anchored at that end (P. R. Johnston and D. Elliott, "A sinh
transformation for evaluating nearly singular boundary element integrals", Int. J. Numer.
Meth. Engng 62, 2005, 564-578), which moves the singularity to Im tau = pi/2. With 16 nodes a
panel the loads agree with 64 nodes a panel, and with a brute-force double Gauss-Legendre sum,
to 1e-14 of their peak for eta / L from 0.15 to 2 and to 6e-12 down to eta / L = 0.02
(test/test_passing_ship.py). A call takes 0.07-0.08 ms for one stagger in deep water, under
1 ms at a finite depth; an array of staggers is one vectorised evaluation (under 10 us a
stagger in deep water, about 0.3 ms at a finite depth).

Limits
------
Parallel courses, constant speed, slender hulls, no waves (a rigid free surface: a depth
Froude number U / sqrt(g h) well below 1, 0.36 for 4.5 m/s in 16 m of water), no quay wall
(the moored ship is in open water), no propeller wash. At a finite depth the hulls stay
lines of sources on the surface: the draft is not in the method, so a ship drawing 14 m of
16 m gets the loads of one drawing 5 m, and the flow squeezed under a keel a few metres off
the bottom, which raises the loads, is left out. Fits to model tests grow exponentially with
the draft / depth ratio instead (D. Kriebel, "Mooring loads due to parallel passing ships",
NFESC TR-6056-OCN, 2005; DYNMOOR 6.10's fits for a ship passing across a berth, PERSHIP, go
as exp(2.3 T / h) in surge and exp(4.0 T / h) in sway). So the nearer the keel to the bed,
the more the loads here are a lower estimate: at a depth / draft below about 1.5 check them
against model tests or such a fit before relying on them.
"""

from dataclasses import dataclass
from functools import lru_cache
import math
from typing import Optional, Tuple, Union

import numpy as np

# Gauss-Legendre nodes per panel (four panels). 16 reproduces 64 to 6e-12 of the peak at
# eta / L = 0.02 and to 1e-14 from 0.15 (test_quadrature_converges); 4 are off by 1e-4..1e-3.
DEFAULT_NODES = 16

# The sum over the sea bed's images (finite depth): pairs summed one by one, then the tail's
# integral; the pairs double from FIRST_IMAGE_PAIRS until that changes each load by less than
# IMAGE_TOLERANCE of itself. With the tail, 16 pairs were enough for the berth's ships 40 to
# 300 m apart in 15 to 42 m of water, abeam to 40 ship lengths off (32 once, 300 m apart in
# 42 m); MAX_IMAGE_PAIRS is a guard.
IMAGE_TOLERANCE = 1e-4
FIRST_IMAGE_PAIRS = 8
MAX_IMAGE_PAIRS = 2 ** 12
# (stagger, image) rows integrated at once: bounds the memory a block takes (~15 MB).
CHUNK_ROWS = 4096

ArrayLike = Union[float, np.ndarray]
Loads = Tuple[ArrayLike, ArrayLike, ArrayLike]


def _number(name: str, value: float) -> float:
    """Return value as a float, or raise ValueError naming it."""
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f'{name} {value!r} must be a number') from None


def _positive(name: str, value: float, unit: str) -> float:
    """Return value as a float, or raise ValueError unless it is finite and > 0."""
    number = _number(name, value)
    if not (math.isfinite(number) and number > 0.0):
        raise ValueError(f'{name} {value!r} must be a finite number > 0 [{unit}]')
    return number


@dataclass(frozen=True)
class Hull:
    """
    A ship as Wang's method sees it: a parabolic sectional-area curve over its length.

    S(x) = S_m (1 - (2x/L)^2) for |x| <= L/2, S_m = 1.5 C_b B T, x from midship (forward
    positive), so that the curve holds the displaced volume C_b L B T.

    :ivar length: length between perpendiculars L [m].
    :ivar beam: moulded beam B [m].
    :ivar draft: draft T [m].
    :ivar block_coefficient: C_b, in (0, 1].
    """

    length: float
    beam: float
    draft: float
    block_coefficient: float

    def __post_init__(self) -> None:
        """Check the particulars (ValueError naming the one that is out of range)."""
        _positive('length', self.length, 'm')
        _positive('beam', self.beam, 'm')
        _positive('draft', self.draft, 'm')
        cb = _number('block_coefficient', self.block_coefficient)
        if not (math.isfinite(cb) and 0.0 < cb <= 1.0):
            raise ValueError(f'block_coefficient {self.block_coefficient!r} must be in (0, 1]')

    @property
    def midship_area(self) -> float:
        """S_m = 1.5 C_b B T, the peak of the sectional-area curve [m^2]."""
        return 1.5 * self.block_coefficient * self.beam * self.draft

    @property
    def volume(self) -> float:
        """Displaced volume C_b L B T, which the curve integrates to [m^3]."""
        return self.block_coefficient * self.length * self.beam * self.draft

    def sectional_area(self, x: ArrayLike) -> np.ndarray:
        """Return S(x) [m^2] at x [m] from midship; 0 beyond the ends."""
        x = np.asarray(x, dtype=float)
        inside = np.abs(x) <= 0.5 * self.length
        return np.where(inside, self.midship_area * (1.0 - (2.0 * x / self.length) ** 2), 0.0)

    def sectional_area_slope(self, x: ArrayLike) -> np.ndarray:
        """Return dS/dx [m] at x [m] from midship; 0 beyond the ends."""
        x = np.asarray(x, dtype=float)
        inside = np.abs(x) <= 0.5 * self.length
        return np.where(inside, -8.0 * self.midship_area * x / self.length ** 2, 0.0)


def passing_loads(moored: Hull, passing: Hull, speed: float, separation: float,
                  stagger: ArrayLike, depth: float = math.inf, water_density: float = 1025.0,
                  direction: int = 1, *, image_pairs: int = 0,
                  nodes: int = DEFAULT_NODES) -> Loads:
    """
    Return (surge force [N], sway force [N], yaw moment [N m]) on the moored ship.

    Wang (1975), in deep water or, at a finite depth, summed over the images of the sea bed,
    in the moored ship's body axes (x forward, y to port, z up; moment about its midship,
    positive bow to port); the module docstring has the formulas. Floats for a scalar
    stagger, arrays of its shape for an array, so a whole passage is one call.

    :param moored: the moored ship.
    :param passing: the passing ship.
    :param speed: the passing ship's speed through the water, > 0 [m/s].
    :param separation: distance between the centrelines [m], positive with the passing ship
        on the starboard side (body -y), negative on the port side; at least half the sum of
        the beams, or the hulls would overlap.
    :param stagger: the passing midship's position along the moored ship's body x, from its
        midship, positive ahead [m]; a number or an array.
    :param depth: water depth [m]: math.inf (deep water, the default) or a finite depth
        greater than both drafts.
    :param water_density: [kg/m^3].
    :param direction: +1 if the passing ship moves along body +x, -1 along -x. The loads at
        a given stagger are the same either way (the pressure goes with the square of the
        velocity); it is checked so that callers state it.
    :param image_pairs: at a finite depth, 0 (the default) sums the image pairs until the
        sum has converged (module docstring); n > 0 sums the images -n..n only (the legacy
        programs' truncation: 10). Ignored in deep water.
    :param nodes: Gauss-Legendre nodes in each of the four panels over the moored ship.
    :raises ValueError: an argument outside the ranges above.
    """
    if not isinstance(moored, Hull) or not isinstance(passing, Hull):
        raise ValueError('moored and passing must be Hull instances')
    speed = _positive('speed', speed, 'm/s')
    water_density = _positive('water_density', water_density, 'kg/m^3')
    separation = _number('separation', separation)
    min_separation = 0.5 * (moored.beam + passing.beam)
    if not (math.isfinite(separation) and abs(separation) >= min_separation):
        raise ValueError(f'separation {separation!r} must be finite with |separation| >= '
                         f'{min_separation:g} m (half the sum of the beams)')
    depth = _number('depth', depth)
    deepest_draft = max(moored.draft, passing.draft)
    if not (depth == math.inf or (math.isfinite(depth) and depth > deepest_draft)):
        raise ValueError(f'depth {depth!r} must be math.inf (deep water) or a finite number '
                         f'> {deepest_draft:g} m (the deeper draft: a keel below the sea bed)')
    if isinstance(image_pairs, bool) or not isinstance(image_pairs, (int, np.integer)) \
            or image_pairs < 0:
        raise ValueError(f'image_pairs {image_pairs!r} must be an integer >= 0 (0: until '
                         'converged)')
    if direction not in (1, -1):
        raise ValueError(f'direction {direction!r} must be 1 (along body +x) or -1')
    if isinstance(nodes, bool) or not isinstance(nodes, (int, np.integer)) or nodes < 2:
        raise ValueError(f'nodes {nodes!r} must be an integer >= 2')
    try:
        xi = np.asarray(stagger, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f'stagger {stagger!r} must be a number or an array of numbers [m]') \
            from None
    if not np.isfinite(xi).all():
        raise ValueError('stagger must be finite [m]')

    eta = abs(separation)
    i_x, i_y, i_n = _image_sum(moored, passing, xi.ravel(), eta, depth, int(image_pairs),
                               int(nodes))
    dynamic = water_density * speed * speed  # rho U^2; direction enters squared
    lateral = -math.copysign(1.0, separation)  # passing ship at body y = -separation
    surge = dynamic / (2.0 * math.pi) * i_x
    sway = lateral * dynamic * eta / math.pi * i_y
    yaw = lateral * dynamic * eta / math.pi * i_n
    if xi.ndim == 0:
        return float(surge[0]), float(sway[0]), float(yaw[0])
    return surge.reshape(xi.shape), sway.reshape(xi.shape), yaw.reshape(xi.shape)


def _image_sum(moored: Hull, passing: Hull, xi: np.ndarray, eta: float, depth: float,
               image_pairs: int, nodes: int) -> np.ndarray:
    """
    Return (I_x, I_y, I_n) summed over the sea bed's images, shape (3, len(xi)).

    Deep water: the ship itself (n = 0). At a depth h, the terms n = -N..N at
    eta_n = sqrt(eta^2 + (2 n h)^2), the pairs +-n alike: image_pairs > 0 is N, summed as
    the legacy programs do. 0 (converged) adds to the pairs 1..N the integral over n that
    their tail n > N approaches (_image_tail) and doubles N from FIRST_IMAGE_PAIRS,
    stagger by stagger, until doubling changes each of surge, sway and yaw by less than
    IMAGE_TOLERANCE of its sum (module docstring, Finite depth).
    """
    total = np.array(_wang_integrals(moored, passing, xi, np.full(xi.shape, eta), nodes))
    if depth == math.inf:
        return total
    if image_pairs:
        return total + _image_pairs(moored, passing, xi, eta, depth, 1, image_pairs, nodes)
    # surge, sway and yaw / L1 are (I_x / 2, eta I_y, eta I_n / L1) times rho U^2 / pi
    scale = np.array([[0.5], [eta], [eta / moored.length]])
    pairs = FIRST_IMAGE_PAIRS
    total += _image_pairs(moored, passing, xi, eta, depth, 1, pairs, nodes)
    tail = _image_tail(moored, passing, xi, eta, depth, pairs, nodes)
    active = np.arange(xi.size)
    while active.size and pairs < MAX_IMAGE_PAIRS:
        more = _image_pairs(moored, passing, xi[active], eta, depth, pairs + 1, 2 * pairs,
                            nodes)
        pairs *= 2
        new_tail = _image_tail(moored, passing, xi[active], eta, depth, pairs, nodes)
        change = more + new_tail - tail[:, active]
        total[:, active] += more
        tail[:, active] = new_tail
        sums = np.abs(scale * (total[:, active] + new_tail))
        # a load zero by symmetry (surge and yaw abeam) is converged at 1e-6 of the others
        floor = 1e-6 * sums.sum(axis=0)
        done = (np.abs(scale * change) <= IMAGE_TOLERANCE * np.maximum(sums, floor)).all(axis=0)
        active = active[~done]
    return total + tail


def _image_pairs(moored: Hull, passing: Hull, xi: np.ndarray, eta: float, depth: float,
                 first: int, last: int, nodes: int) -> np.ndarray:
    """Return the sum of the image pairs n = +-first..+-last, shape (3, len(xi))."""
    lateral = np.hypot(eta, 2.0 * depth * np.arange(first, last + 1, dtype=float))
    rows_xi = np.repeat(xi, lateral.size)
    rows_eta = np.tile(lateral, xi.size)
    parts = []
    for start in range(0, rows_xi.size, CHUNK_ROWS):
        chunk = slice(start, start + CHUNK_ROWS)
        parts.append(_wang_integrals(moored, passing, rows_xi[chunk], rows_eta[chunk], nodes))
    terms = np.concatenate(parts, axis=1).reshape(3, xi.size, lateral.size)
    return 2.0 * terms.sum(axis=2)


def _image_tail(moored: Hull, passing: Hull, xi: np.ndarray, eta: float, depth: float,
                pairs: int, nodes: int) -> np.ndarray:
    """
    Return the pairs n > N (N = pairs) as the integral over n they approach, (3, len(xi)).

    Euler-Maclaurin's midpoint rule: sum_{n > N} f(n) = integral of f over n from N + 1/2
    on + f'(N + 1/2) / 24 + ..., f(n) = Wang's integrals at eta_n. The integral, with the
    image distance z = 2 h n, is 1 / (2 h) times Wang's integrals of the point kernel
    (R^2 + eta^2 + z^2)^(-3/2) integrated over z from a = 2 h (N + 1/2) on (closed form:
    _tail_kernel_integrals); f'(N + 1/2) is f(N + 1) - f(N). Twice that for the pairs.
    Without the f' term the rule is off by up to 3e-4 of the loads at N = 8 to 32 where
    f still grows with n (a stagger of 4 to 13 ship lengths at the berth's depth); with it,
    by 1e-5 at most at N = 8 and 1e-7 at N = 16 (measured against a direct sum of 40 000
    pairs, 300 m to 3 km off, 70 m apart).
    """
    reach = 2.0 * depth * (pairs + 0.5)
    integral = np.array(_wang_integrals(moored, passing, xi, np.full(xi.shape, eta), nodes,
                                        reach)) / (2.0 * depth)
    nearest = np.array(_wang_integrals(moored, passing, np.repeat(xi, 2), np.tile(
        np.hypot(eta, 2.0 * depth * np.array([pairs, pairs + 1.0])), xi.size), nodes))
    slope = nearest[:, 1::2] - nearest[:, 0::2]
    return 2.0 * (integral + slope / 24.0)


@lru_cache(maxsize=8)
def _gauss_legendre(nodes: int) -> Tuple[np.ndarray, np.ndarray]:
    """Return Gauss-Legendre nodes and weights on [-1, 1] (cached: 0.3 ms to compute for 16)."""
    return np.polynomial.legendre.leggauss(int(nodes))


def _moored_nodes(xi: np.ndarray, eta: np.ndarray, half_moored: float, half_passing: float,
                  nodes: int) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return quadrature points x1 and weights over the moored ship, shape (len(xi), 4 nodes).

    Panels [-L1/2, c-], [c-, xi], [xi, c+], [c+, L1/2] (clipped to the hull), where
    c-+ = xi -+ L2/2 put an end of the passing ship abeam; each panel is mapped by
    x = c + eta sinh(tau) from the c it touches, with Gauss-Legendre nodes in tau. eta is
    each row's lateral distance (len(xi),).
    """
    t, w = _gauss_legendre(nodes)
    xi = xi[:, None]
    eta = eta[:, None]
    aft_end, fore_end = xi - half_passing, xi + half_passing
    edges = np.concatenate([np.full_like(xi, -half_moored),
                            np.clip(aft_end, -half_moored, half_moored),
                            np.clip(xi, -half_moored, half_moored),
                            np.clip(fore_end, -half_moored, half_moored),
                            np.full_like(xi, half_moored)], axis=1)
    anchors = np.concatenate([aft_end, aft_end, fore_end, fore_end], axis=1)
    tau_start = np.arcsinh((edges[:, :-1] - anchors) / eta)
    tau_end = np.arcsinh((edges[:, 1:] - anchors) / eta)
    half = 0.5 * (tau_end - tau_start)[:, :, None]
    tau = 0.5 * (tau_end + tau_start)[:, :, None] + half * t
    x1 = anchors[:, :, None] + eta[:, :, None] * np.sinh(tau)
    weights = half * w * eta[:, :, None] * np.cosh(tau)
    return x1.reshape(len(xi), -1), weights.reshape(len(xi), -1)


def _passing_integrals(x1: np.ndarray, xi: np.ndarray, eta: np.ndarray,
                       passing: Hull) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return the integrals over the passing ship, in closed form, at moored-ship points x1.

    j_x = ∫ S2'(x2) R / rho^3 dx2 and j_y = ∫ S2'(x2) / rho^3 dx2, rho = sqrt(R^2 + eta^2),
    R = x2 - x1 + xi. With S2' = -k x2 and d = x1 - xi (so x2 = R + d):
    j_x = -k [asinh(R / eta) - x2 / rho] and j_y = -k [-1 / rho + d R / (eta^2 rho)] between
    the ends. Both differences are rewritten so that nothing cancels: 1 / rho- - 1 / rho+ and,
    for R+ and R- of one sign, R+ / rho+ - R- / rho- = eta^2 (R+^2 - R-^2) / (rho+ rho-
    (R+ rho- + R- rho+)), which keeps 1/eta^2 from amplifying rounding far from abeam.
    """
    length = passing.length
    half = 0.5 * length
    k = 8.0 * passing.midship_area / length ** 2
    d = x1 - xi
    r_fore = half - d  # R at the passing ship's bow (x2 = +L2/2)
    r_aft = -half - d
    rho_fore = np.hypot(r_fore, eta)
    rho_aft = np.hypot(r_aft, eta)
    j_x = -k * (np.arcsinh(r_fore / eta) - np.arcsinh(r_aft / eta)
                - half * (1.0 / rho_fore + 1.0 / rho_aft))
    total = r_fore + r_aft  # = -2 d; r_fore - r_aft = L2
    inverse_difference = length * total / (rho_fore * rho_aft * (rho_fore + rho_aft))
    same_side = r_fore * r_aft > 0.0
    cross = np.where(same_side, r_fore * rho_aft + r_aft * rho_fore, 1.0)
    ratio_difference = np.where(
        same_side, length * total / (rho_fore * rho_aft * cross),
        (r_fore / rho_fore - r_aft / rho_aft) / (eta * eta))
    j_y = -k * (inverse_difference + d * ratio_difference)
    return j_x, j_y


def _tail_kernel_integrals(x1: np.ndarray, xi: np.ndarray, eta: np.ndarray, reach: float,
                           passing: Hull) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return the passing-ship integrals of the images beyond `reach`, at moored-ship points x1.

    The point kernel integrated over the image distance z from a = reach on:
    integral of (R^2 + eta^2 + z^2)^(-3/2) dz = G(R) = 1 / (s (s + a)), s = sqrt(R^2 + e^2),
    e^2 = eta^2 + a^2. Then j_x = integral of S2'(x2) R G dx2 and j_y = integral of
    S2'(x2) G dx2 in closed form: with S2' = -k x2 and x2 = R + d (d = x1 - xi),
    j_y = -k [ln(s + a) + d F] and j_x = -k [R - a asinh(R / e) - eta^2 F + d ln(s + a)]
    between the ends, where F = integral of G dR = (atan(R / eta) - atan(a R / (eta s))) /
    eta, written as one atan2 of their difference, (R / eta) (R^2 + eta^2) / (s (s + a)).
    """
    length = passing.length
    half = 0.5 * length
    k = 8.0 * passing.midship_area / length ** 2
    d = x1 - xi
    r_fore = half - d
    r_aft = -half - d
    e = np.hypot(eta, reach)
    s_fore = np.hypot(r_fore, e)
    s_aft = np.hypot(r_aft, e)

    def primitive(r, s):
        # F(R) (module docstring of this function), odd in R
        return np.arctan2(r * (r * r + eta * eta) / (s * (s + reach)),
                          eta * (1.0 + reach * r * r / (eta * eta * s))) / eta

    log_step = np.log1p(length * (r_fore + r_aft) / (s_fore + s_aft) / (s_aft + reach))
    f_step = primitive(r_fore, s_fore) - primitive(r_aft, s_aft)
    asinh_step = np.arcsinh(r_fore / e) - np.arcsinh(r_aft / e)
    j_y = -k * (log_step + d * f_step)
    j_x = -k * (length - reach * asinh_step - eta * eta * f_step + d * log_step)
    return j_x, j_y


def _wang_integrals(moored: Hull, passing: Hull, xi: np.ndarray, eta: np.ndarray,
                    nodes: int, reach: Optional[float] = None
                    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """
    Return Wang's double integrals (I_x, I_y, I_n) for each row (xi, eta), shape (len(xi),).

    X = rho U^2 / (2 pi) I_x, Y = rho U^2 eta / pi I_y, N = rho U^2 eta / pi I_n [m^4].
    With a reach a: the same integrals of the point kernel integrated over an image's
    distance z from a to infinity (_tail_kernel_integrals) [m^5].
    """
    if reach is None:
        x1, weights = _moored_nodes(xi, eta, 0.5 * moored.length, 0.5 * passing.length,
                                    nodes)
        j_x, j_y = _passing_integrals(x1, xi[:, None], eta[:, None], passing)
    else:
        # the tail's kernel varies on the scale sqrt(eta^2 + a^2): the nodes of that distance
        x1, weights = _moored_nodes(xi, np.hypot(eta, reach), 0.5 * moored.length,
                                    0.5 * passing.length, nodes)
        j_x, j_y = _tail_kernel_integrals(x1, xi[:, None], eta[:, None], reach, passing)
    area = moored.midship_area
    slope = -8.0 * area / moored.length ** 2 * x1  # S1'(x1)
    # x1 S1' + S1 = S_m (1 - 12 x1^2 / L1^2)
    yaw_weight = area * (1.0 - 12.0 * (x1 / moored.length) ** 2)
    i_x = np.einsum('ij,ij->i', weights * slope, j_x)
    i_y = np.einsum('ij,ij->i', weights * slope, j_y)
    i_n = np.einsum('ij,ij->i', weights * yaw_weight, j_y)
    return i_x, i_y, i_n
