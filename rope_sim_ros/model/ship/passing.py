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
Loads a ship passing on a parallel course exerts on a moored ship: Wang's method, deep water.

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
(test/test_passing_ship.py). A call takes 0.07-0.08 ms for one stagger; an array of staggers
is one vectorised evaluation (under 10 us a stagger).

Limits
------
Parallel courses, constant speed, slender hulls, no waves, deep water; Varyani et al. (2003)
add the effect of the sea bed once the depth is below about twice the draft. No finite-depth
correction is implemented: neither the image sum of Varyani et al. (2003) nor the empirical
factors of D. Kriebel, "Mooring loads due to parallel passing ships", NFESC TR-6056-OCN
(2005), could be checked here against the examples they were published with, so ``depth``
accepts math.inf only.
"""

from dataclasses import dataclass
from functools import lru_cache
import math
from typing import Tuple, Union

import numpy as np

# Gauss-Legendre nodes per panel (four panels). 16 reproduces 64 to 6e-12 of the peak at
# eta / L = 0.02 and to 1e-14 from 0.15 (test_quadrature_converges); 4 are off by 1e-4..1e-3.
DEFAULT_NODES = 16

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
                  direction: int = 1, *, nodes: int = DEFAULT_NODES) -> Loads:
    """
    Return (surge force [N], sway force [N], yaw moment [N m]) on the moored ship.

    Wang (1975) in deep water, in the moored ship's body axes (x forward, y to port, z up;
    moment about its midship, positive bow to port); the module docstring has the formulas.
    Floats for a scalar stagger, arrays of its shape for an array, so a whole passage is
    one call.

    :param moored: the moored ship.
    :param passing: the passing ship.
    :param speed: the passing ship's speed through the water, > 0 [m/s].
    :param separation: distance between the centrelines [m], positive with the passing ship
        on the starboard side (body -y), negative on the port side; at least half the sum of
        the beams, or the hulls would overlap.
    :param stagger: the passing midship's position along the moored ship's body x, from its
        midship, positive ahead [m]; a number or an array.
    :param depth: water depth [m]; only math.inf (deep water) is accepted, see the module
        docstring.
    :param water_density: [kg/m^3].
    :param direction: +1 if the passing ship moves along body +x, -1 along -x. The loads at
        a given stagger are the same either way (the pressure goes with the square of the
        velocity); it is checked so that callers state it.
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
    if _number('depth', depth) != math.inf:
        raise ValueError(f'depth {depth!r} must be math.inf: only deep water is implemented '
                         '(no finite-depth correction could be verified)')
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
    i_x, i_y, i_n = _wang_integrals(moored, passing, xi.ravel(), eta, nodes)
    dynamic = water_density * speed * speed  # rho U^2; direction enters squared
    lateral = -math.copysign(1.0, separation)  # passing ship at body y = -separation
    surge = dynamic / (2.0 * math.pi) * i_x
    sway = lateral * dynamic * eta / math.pi * i_y
    yaw = lateral * dynamic * eta / math.pi * i_n
    if xi.ndim == 0:
        return float(surge[0]), float(sway[0]), float(yaw[0])
    return surge.reshape(xi.shape), sway.reshape(xi.shape), yaw.reshape(xi.shape)


@lru_cache(maxsize=8)
def _gauss_legendre(nodes: int) -> Tuple[np.ndarray, np.ndarray]:
    """Return Gauss-Legendre nodes and weights on [-1, 1] (cached: 0.3 ms to compute for 16)."""
    return np.polynomial.legendre.leggauss(int(nodes))


def _moored_nodes(xi: np.ndarray, eta: float, half_moored: float, half_passing: float,
                  nodes: int) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return quadrature points x1 and weights over the moored ship, shape (len(xi), 4 nodes).

    Panels [-L1/2, c-], [c-, xi], [xi, c+], [c+, L1/2] (clipped to the hull), where
    c-+ = xi -+ L2/2 put an end of the passing ship abeam; each panel is mapped by
    x = c + eta sinh(tau) from the c it touches, with Gauss-Legendre nodes in tau.
    """
    t, w = _gauss_legendre(nodes)
    xi = xi[:, None]
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
    x1 = anchors[:, :, None] + eta * np.sinh(tau)
    weights = half * w * eta * np.cosh(tau)
    return x1.reshape(len(xi), -1), weights.reshape(len(xi), -1)


def _passing_integrals(x1: np.ndarray, xi: np.ndarray, eta: float,
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


def _wang_integrals(moored: Hull, passing: Hull, xi: np.ndarray, eta: float,
                    nodes: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """
    Return Wang's double integrals (I_x, I_y, I_n) for each stagger in xi, shape (len(xi),).

    X = rho U^2 / (2 pi) I_x, Y = rho U^2 eta / pi I_y, N = rho U^2 eta / pi I_n [m^4].
    """
    x1, weights = _moored_nodes(xi, eta, 0.5 * moored.length, 0.5 * passing.length, nodes)
    j_x, j_y = _passing_integrals(x1, xi[:, None], eta, passing)
    area = moored.midship_area
    slope = -8.0 * area / moored.length ** 2 * x1  # S1'(x1)
    # x1 S1' + S1 = S_m (1 - 12 x1^2 / L1^2)
    yaw_weight = area * (1.0 - 12.0 * (x1 / moored.length) ** 2)
    i_x = np.einsum('ij,ij->i', weights * slope, j_x)
    i_y = np.einsum('ij,ij->i', weights * slope, j_y)
    i_n = np.einsum('ij,ij->i', weights * yaw_weight, j_y)
    return i_x, i_y, i_n
