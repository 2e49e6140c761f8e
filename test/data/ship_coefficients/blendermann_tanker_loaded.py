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
Write config/ship/wind_coefficients_tanker_loaded.csv from Blendermann's published formula.

Run ``python test/data/ship_coefficients/blendermann_tanker_loaded.py > \
config/ship/wind_coefficients_tanker_loaded.csv``; test/test_ship_coefficients.py checks
that the shipped file is exactly this script's output, so every number in it is traceable
to the formula and the constants below.

Source
------
W. Blendermann, "Parameter identification of wind loads on ships", Journal of Wind
Engineering and Industrial Aerodynamics 51 (1994) 339-351. His coefficients for the ship
type "Tanker, loaded" are CD_t = 0.70, CD_l,AF(0) = 0.90, CD_l,AF(180 deg) = 0.55,
delta = 0.40 (and kappa = 3.1, for roll, unused here), as tabulated in T. I. Fossen, Handbook
of Marine Craft Hydrodynamics and Motion Control, 2nd ed., Wiley 2021, section 10.1.2, and
in his open-source Marine Systems Simulator (function blendermann94, row 15 of its table).
The formula, for the relative wind angle gamma from the bow, 0 <= gamma <= 180 deg::

    CD_l = CD_l,AF(gamma) A_F / A_L      (CD_l,AF(0) for gamma <= 90, CD_l,AF(180) beyond)
    den  = 1 - delta / 2 (1 - CD_l / CD_t) sin^2(2 gamma)
    CX   = -CD_l,AF(gamma) cos(gamma) / den      (force along x, with A_F)
    CY   =  CD_t sin(gamma) / den                (force toward the lee side, with A_L)
    CN   = (s_L / L_oa - 0.18 (gamma - 90 deg)) CY     (moment, with A_L L_oa)

The two ship inputs
-------------------
The formula needs the ratio A_F / A_L of the ship's front and side windage areas (in the
denominator only) and s_L, the distance of the centroid of A_L forward of midship. Neither is
in Blendermann's table, and no public source for a complete loaded tanker's windage could be
read for this work, so:

- A_F / A_L = B / L_pp of the above-water hull, a box of the freeboard's height, with B and
  L_pp of the public KVLCC2 benchmark tanker (B = 58 m, L_pp = 320 m; SIMMAN 2008): 0.18125.
  The superstructure is left out of both areas. The ratio moves C_x and C_y only between the
  cardinal directions (at 0, 90 and 180 deg den = 1).
- s_L = 0: the table is for a lateral centroid at midship. CN is linear in s_L, so for a
  centroid s_L forward of midship the moment coefficient is cmz + (s_L / L) cy exactly.

Conversion to the project's convention (rope_sim_ros.model.ship.coefficients)
-----------------------------------------------------------------------------
Fossen writes the body y axis to starboard and z down, and gamma = -atan2(v_rw, u_rw) with
(u_rw, v_rw) the ship's velocity relative to the air; the project has y to port, z up and
theta = atan2(-u_y, -u_x) with u the air's velocity relative to the ship. Both are the angle
the wind comes from, measured from the bow toward port, so theta = gamma (a wind from port,
theta = 90, gives CY = CD_t > 0: a force toward starboard in Fossen's axes). Then::

    cx = CX,  cy = -CY,  cmz = -CN

(the y and z axes are reversed). Blendermann gives 0..180 deg; the tanker is symmetric port
to starboard, so for theta in 190..350 the rows are mirrored: cx(360 - t) = cx(t),
cy(360 - t) = -cy(t), cmz(360 - t) = -cmz(t).
"""

import math
import sys
from typing import List, Tuple

CD_T = 0.70  # Blendermann (1994), tanker loaded: transverse drag coefficient
CD_L_AF_BOW = 0.90  # longitudinal drag coefficient with A_F, wind from ahead
CD_L_AF_STERN = 0.55  # longitudinal drag coefficient with A_F, wind from astern
DELTA = 0.40  # cross-force parameter
AREA_RATIO = 58.0 / 320.0  # A_F / A_L = B / L_pp of KVLCC2 (see the module docstring)
CENTROID_RATIO = 0.0  # s_L / L_oa: the table is for a lateral centroid at midship
STEP_DEG = 10
DIGITS = 6

HEADER = """\
# Wind load coefficients, tanker, loaded condition, OCIMF form (rope_sim_ros convention).
# F_x = 1/2 rho V^2 A_T cx, F_y = 1/2 rho V^2 A_L cy, M_z = 1/2 rho V^2 A_L L cmz
# A_T, A_L: front and side windage areas; L: length (Blendermann uses L_oa).
# angle_deg: direction the wind comes FROM, from the bow (0) toward port (90), body axes
# x forward, y to port, z up, moment about midship; V, angle: wind relative to the ship.
# Signs: head wind cx < 0; wind from port (90) cy < 0 (pushes the ship to starboard).
# Source: W. Blendermann, "Parameter identification of wind loads on ships", Journal of
# Wind Engineering and Industrial Aerodynamics 51 (1994) 339-351, coefficients for
# "Tanker, loaded": CD_t 0.70, CD_l,AF(0) 0.90, CD_l,AF(180) 0.55, delta 0.40, as tabulated
# in T. I. Fossen, Handbook of Marine Craft Hydrodynamics and Motion Control, 2nd ed.,
# Wiley 2021, section 10.1.2 (and his Marine Systems Simulator, blendermann94, row 15).
# Obtained: computed (not digitised) from Blendermann's formula
#   CX = -CD_l,AF cos(g)/den, CY = CD_t sin(g)/den, CN = (s_L/L - 0.18 (g - pi/2)) CY,
#   den = 1 - delta/2 (1 - CD_l/CD_t) sin^2(2 g), CD_l = CD_l,AF A_F/A_L,
# by test/data/ship_coefficients/blendermann_tanker_loaded.py, for 0..180 deg, with
#   A_F/A_L = 0.18125 (B/L_pp of the KVLCC2 benchmark tanker, hull above water only: an
#   assumption of this table, not Blendermann's) and s_L = 0 (lateral centroid at midship;
#   for a centroid s_L forward of midship use cmz + (s_L/L) cy, exact for this formula).
# Converted from Fossen's axes (y starboard, z down, gamma = angle the wind comes from,
# from the bow toward port) as angle_deg = gamma, cx = CX, cy = -CY, cmz = -CN; rows
# 190..350 mirror 170..10 (cx even, cy and cmz odd: port/starboard symmetric ship).
"""


def coefficients(gamma_deg: float) -> Tuple[float, float, float]:
    """Return Blendermann's (CX, CY, CN) in Fossen's axes at gamma in [0, 180] deg."""
    gamma = math.radians(gamma_deg)
    cd_l_af = CD_L_AF_BOW if gamma_deg <= 90.0 else CD_L_AF_STERN
    cd_l = cd_l_af * AREA_RATIO
    den = 1.0 - 0.5 * DELTA * (1.0 - cd_l / CD_T) * math.sin(2.0 * gamma) ** 2
    cx = -cd_l_af * math.cos(gamma) / den
    cy = CD_T * math.sin(gamma) / den
    cn = (CENTROID_RATIO - 0.18 * (gamma - 0.5 * math.pi)) * cy
    return cx, cy, cn


def rows() -> List[Tuple[int, float, float, float]]:
    """Return (angle_deg, cx, cy, cmz) rows, 0..350 deg, in the project's convention."""
    half = {}
    for angle in range(0, 181, STEP_DEG):
        cx, cy, cn = coefficients(float(angle))
        half[angle] = (cx, -cy, -cn)
    table = []
    for angle in range(0, 360, STEP_DEG):
        if angle <= 180:
            cx, cy, cmz = half[angle]
        else:
            cx, cy, cmz = half[360 - angle]
            cy, cmz = -cy, -cmz
        table.append((angle, cx, cy, cmz))
    return table


def _number(value: float) -> str:
    """Format a coefficient with DIGITS decimals, without a negative zero."""
    text = f'{value:.{DIGITS}f}'
    return text[1:] if text == '-' + f'{0.0:.{DIGITS}f}' else text


def csv_text() -> str:
    """Return the whole CSV file: comment header, column header, rows."""
    lines = [HEADER.rstrip('\n'), 'angle_deg,cx,cy,cmz']
    for angle, cx, cy, cmz in rows():
        lines.append(f'{angle},{_number(cx)},{_number(cy)},{_number(cmz)}')
    return '\n'.join(lines) + '\n'


if __name__ == '__main__':
    sys.stdout.write(csv_text())
