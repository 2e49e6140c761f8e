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
Current load coefficients of a loaded tanker from UFC 4-159-03 (INCOMPLETE: see below).

Status
------
This script does not write the shipped table. config/ship/current_coefficients_tanker_loaded.csv
comes from DNV-ST-0111 (December 2021) [3.6], the only public source found with all three
coefficients, by dnv_current_tanker_loaded.py beside this file (its docstring says why). This
script stays as the UFC counterpart for surge and sway: the surge and sway coefficients follow
from published formulas with published constants (below); the yaw moment needs the two
constants a, b of UFC 4-159-03 Table 4-10 (page 96), which could not be read for this work
(neither in the 2005 edition nor in the 2020 one, MIL-HDBK-1026/4A or NAVFAC DM-26.5/26.6).
Run::

    python test/data/ship_coefficients/ufc_current_tanker_loaded.py --preview

to print cx and cy (cmz left out), or, once a and b are read from Table 4-10 for the hull
type that fits a tanker::

    python test/data/ship_coefficients/ufc_current_tanker_loaded.py --eccentricity A B \
        > ufc_current_tanker_loaded.csv

and check the sign convention of the eccentricity (positive forward of midship is assumed
here) against the page itself. Unlike the shipped table (A_T = B T), this script makes cx
dimensionless with L T (see the conversion below): multiply its cx by L / B = 320 / 58 before
comparing or shipping. For KVLCC2 in deep water it gives cy(90) = -0.574 against DNV's -0.6,
and cx(0) = -0.0375 on L T (-0.207 on B T) against DNV's -0.07 on B T: the surge coefficient
is uncertain by a factor of about 3 between the two sources.

Source
------
Unified Facilities Criteria UFC 4-159-03, "Design: Moorings", US Department of Defense
(NAVFAC preparing activity), 3 October 2005, approved for public release, section 4-5
"Current forces and moments on ships" (pages 84-96), read as text on pages 87-92 and 95:

- transverse force (section 4-5.1), F_yc = 1/2 rho V^2 L_wL T C_yc sin(theta_c), with
  C_yc = C0 + (C1 - C0) (T/d)^K (eq. 11), C1 = 3.2, K = 2 ("wide range of ship and barge
  tests"), C0 = 0.22 sqrt(chi) (eq. 12), chi = L_wL^2 A_m / (B V) (eq. 13; V the displaced
  volume). The equation images of eqs. 10 and 12 were not legible; the form of eq. 10 and of
  eq. 11 is confirmed by reproducing Table 4-6 (FFG-7, page 87) in
  test/test_ship_coefficients.py (three rows predicted from two to their printed digits). The
  square root in eq. 12 follows from the same table: it needs C0 = 0.851, i.e. chi = 15.0 with
  the root (for any ship chi = (L/B) / C_p >= L/B, and L/B ~ 9 for a frigate of L_wL T = 546
  m^2, T = 4.39 m), while without it chi = 3.9 < L/B would need a beam over 32 m.
- longitudinal force (section 4-5.2, after NCEL TN-1634, STATMOOR), the sum of
  form drag 1/2 rho V^2 B T C_xcb cos(theta_c), C_xcb = 0.1 (eq. 16);
  skin friction 1/2 rho V^2 S C_xca cos(theta_c) (eq. 17), S = 1.7 T L_wL + D / (T gamma_w)
  (eq. 18, D / gamma_w = V), C_xca = 0.075 / (log10 R_N - 2)^2 (eq. 19),
  R_N = V L_wL cos(theta_c) / nu (eq. 20);
  propeller drag 1/2 rho V^2 A_p C_PROP cos(theta_c) (eq. 21), C_PROP = 1.0,
  A_p = A_Tpp / (1.067 - 0.229 p/d) (eq. 22, = A_Tpp / 0.838 for p/d = 1.0),
  A_Tpp = L_wL B / A_R (eq. 23), A_R = 270 for a tanker (Table 4-7, page 92).
- yaw moment (section 4-5.4), M_xyc = F_yc (e_c / L_wL) L_wL (eq. 24), e_c / L_wL = a + b
  theta_c for theta_c in 0..180 deg and a + b (360 - theta_c) for 180..360 (eqs. 25, 25a),
  a and b from Table 4-10 "Current moment eccentricity ratio variables" (page 96, NOT READ).

The angle theta_c is where the current goes TO: the UFC's example on page 92 calls
theta_c = 180 deg a bow-on current, "in a negative X direction", giving negative forces.

Ship and water (assumptions of this table, not the UFC's)
--------------------------------------------------------
- KVLCC2 benchmark tanker, full scale, loaded: L_pp = 320 m, B = 58 m, d = 20.8 m,
  V = 312 600 m^3 (H. Yasukawa and Y. Yoshimura, "Introduction of MMG standard method for
  ship maneuvering predictions", J. Marine Science and Technology 20 (2015) 37-52, Table 1).
  L_wL is taken equal to L_pp.
- A_m = B T (midship section coefficient 1: no published value of KVLCC2's was read; C0 goes
  with its square root, so C_M = 0.99 would lower C0 by 0.5 %).
- Deep water: T/d = 0 (C_yc = C0). For a berth, pass --draft-over-depth.
- Salt water at 20 deg C, nu = 1.054e-6 m^2/s (E. C. Tupper, Introduction to Naval
  Architecture, Table 5.1, salinity 3.5 %); rho cancels in the coefficients.
- The friction term depends on the current speed through R_N: the table is for a reference
  speed of 1.0 m/s (--speed). R_N uses |cos(theta_c)| (eq. 20 as printed would take the log of
  a negative number for a current from ahead); eq. 17 multiplies by cos(theta_c) once, as
  printed, not by cos |cos|.

Conversion to the project's convention (rope_sim_ros.model.ship.coefficients)
-----------------------------------------------------------------------------
Coefficients are made dimensionless with L T for both forces and L T L for the moment (the
OCIMF form: area_front = area_side = L T). The project's angle is where the current comes
FROM, theta = theta_c + 180 deg, so cos(theta_c) = -cos(theta), sin(theta_c) = -sin(theta)::

    cx  = -(0.1 B T + S C_xca + A_p C_PROP) / (L T) cos(theta)
    cy  = -C_yc sin(theta)
    cmz = (e_c / L)(theta_c) cy

(a current from port, theta = 90, gives cy = -C_yc: pushed to starboard; a head current gives
cx < 0). The moment line holds whichever way the UFC's y and z axes point, as long as e_c is
measured positive forward of midship: a transverse force F_y at x = e_c turns the ship by
e_c F_y about +z in the project's axes.
"""

import argparse
import math
import sys
from typing import List, Optional, Tuple

# UFC 4-159-03 (2005) constants, section 4-5
C1 = 3.2  # shallow-water transverse drag coefficient at T/d = 1 (eq. 11)
K_EXPONENT = 2.0  # exponent of T/d (eq. 11, "wide range of ship and barge tests")
C0_FACTOR = 0.22  # C0 = 0.22 sqrt(chi) (eq. 12)
CXCB = 0.1  # longitudinal form drag coefficient (eq. 16)
SURFACE_FACTOR = 1.7  # S = 1.7 T L_wL + V / T (eq. 18)
CPROP = 1.0  # propeller drag coefficient (eq. 21)
PITCH_RATIO = 1.0  # p/d assumed by the UFC (eq. 22)
AREA_RATIO_TANKER = 270.0  # A_R for a tanker (Table 4-7)

# Ship and water (module docstring)
LENGTH = 320.0  # L_wL = L_pp of KVLCC2 [m]
BEAM = 58.0  # [m]
DRAFT = 20.8  # [m]
VOLUME = 312600.0  # displaced volume [m^3]
MIDSHIP_AREA = BEAM * DRAFT  # A_m with C_M = 1 (assumption)
NU = 1.054e-6  # kinematic viscosity, salt water 20 deg C [m^2/s]

STEP_DEG = 10
DIGITS = 6


def transverse_coefficient(draft_over_depth: float) -> float:
    """Return C_yc of eqs. 11-13 for the ship above."""
    chi = LENGTH ** 2 * MIDSHIP_AREA / (BEAM * VOLUME)
    c0 = C0_FACTOR * math.sqrt(chi)
    return c0 + (C1 - c0) * draft_over_depth ** K_EXPONENT


def longitudinal_area(theta_c_deg: float, speed: float) -> float:
    """Return B T C_xcb + S C_xca + A_p C_PROP [m^2] at the UFC angle theta_c."""
    cos_c = abs(math.cos(math.radians(theta_c_deg)))
    wetted = SURFACE_FACTOR * DRAFT * LENGTH + VOLUME / DRAFT
    reynolds = speed * LENGTH * cos_c / NU
    # eq. 19 is singular at R_N = 100; below that (only where cos = 0 here) the term is nil
    friction = 0.0 if reynolds <= 100.0 else 0.075 / (math.log10(reynolds) - 2.0) ** 2
    propeller = LENGTH * BEAM / AREA_RATIO_TANKER / (1.067 - 0.229 * PITCH_RATIO)
    return BEAM * DRAFT * CXCB + wetted * friction + propeller * CPROP


def eccentricity(theta_c_deg: float, a: float, b: float) -> float:
    """Return e_c / L_wL of eqs. 25, 25a."""
    theta_c = theta_c_deg % 360.0
    return a + b * (theta_c if theta_c <= 180.0 else 360.0 - theta_c)


def rows(speed: float, draft_over_depth: float,
         ecc: Optional[Tuple[float, float]]) -> List[Tuple[int, float, float, Optional[float]]]:
    """Return (angle_deg, cx, cy, cmz or None) in the project's convention, 0..350 deg."""
    c_yc = transverse_coefficient(draft_over_depth)
    table = []
    for angle in range(0, 360, STEP_DEG):
        theta = math.radians(angle)
        theta_c = (angle + 180) % 360
        cx = -longitudinal_area(theta_c, speed) / (LENGTH * DRAFT) * math.cos(theta)
        cy = -c_yc * math.sin(theta)
        cmz = None if ecc is None else eccentricity(theta_c, *ecc) * cy
        table.append((angle, cx, cy, cmz))
    return table


def _number(value: float) -> str:
    """Format a coefficient with DIGITS decimals, without a negative zero."""
    text = f'{value:.{DIGITS}f}'
    return text[1:] if text == '-' + f'{0.0:.{DIGITS}f}' else text


def csv_text(speed: float, draft_over_depth: float, a: float, b: float) -> str:
    """Return the CSV file (comment header left to the caller to complete from Table 4-10)."""
    lines = [
        '# Current load coefficients, tanker (KVLCC2), loaded, OCIMF form with A = L T,',
        '# from UFC 4-159-03 (2005) section 4-5 by',
        '# test/data/ship_coefficients/ufc_current_tanker_loaded.py (see its docstring);',
        f'# reference speed {speed} m/s, T/d = {draft_over_depth}, Table 4-10 a = {a}, b = {b}.',
        'angle_deg,cx,cy,cmz',
    ]
    for angle, cx, cy, cmz in rows(speed, draft_over_depth, (a, b)):
        lines.append(f'{angle},{_number(cx)},{_number(cy)},{_number(cmz)}')
    return '\n'.join(lines) + '\n'


def main(argv: Optional[List[str]] = None) -> int:
    """Print the preview (cx, cy) or, given Table 4-10's a and b, the whole CSV."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--speed', type=float, default=1.0, help='reference current [m/s]')
    parser.add_argument('--draft-over-depth', type=float, default=0.0, help='T/d (0: deep)')
    parser.add_argument('--eccentricity', type=float, nargs=2, metavar=('A', 'B'),
                        help='a and b of UFC 4-159-03 Table 4-10 (e_c/L = a + b theta_c)')
    parser.add_argument('--preview', action='store_true', help='print cx and cy only')
    args = parser.parse_args(argv)
    if args.preview:
        print('angle_deg,cx,cy')
        for angle, cx, cy, _ in rows(args.speed, args.draft_over_depth, None):
            print(f'{angle},{_number(cx)},{_number(cy)}')
        return 0
    if args.eccentricity is None:
        sys.stderr.write('the yaw moment needs a and b of UFC 4-159-03 Table 4-10 '
                         '(--eccentricity A B); use --preview for cx and cy\n')
        return 2
    sys.stdout.write(csv_text(args.speed, args.draft_over_depth, *args.eccentricity))
    return 0


if __name__ == '__main__':
    sys.exit(main())
