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
Write config/ship/current_coefficients_tanker_loaded.csv from DNV-ST-0111's current formulas.

Run ``python test/data/ship_coefficients/dnv_current_tanker_loaded.py > \
config/ship/current_coefficients_tanker_loaded.csv``; test/test_ship_coefficients.py checks
that the shipped file is exactly this script's output, so every number in it is traceable
to the formulas and the constants below.

Source
------
DNV-ST-0111 "Assessment of station keeping capability of dynamic positioning vessels", DNV AS,
Edition December 2021 (it supersedes DNVGL-ST-0111, March 2018), section 3, [3.6] current
loads, the prescriptive DP capability Level 1 method for ship-shaped monohulls. With
rho_water the water density, V the current speed and beta the direction the current comes
FROM, measured clockwise seen from above (0 head-on, 90 deg from starboard), in the body axes
of [2.8.2] (x forward, y to port, z up, origin at L_pp/2 on the centreline)::

    F_X = 1/2 rho_water V^2 B T (-0.07 cos(beta))
    F_Y = 1/2 rho_water V^2 A_L,current (0.6 sin(beta))
    M_Z = F_Y (x_L,current + max(min(0.4 (1 - 2 dir / pi), 0.25), -0.2) L_pp)
    dir = beta for 0 <= beta <= pi,  2 pi - beta for pi <= beta <= 2 pi

with B the breadth at the waterline, T the draft, A_L,current the longitudinal (side)
projected area below water and x_L,current the longitudinal position of its centre
(Table A-2 of the standard lists these inputs).

What was read, and what was not: the text of [3.6] itself could not be read for this work
(the public web copies of the December 2021 edition that could be reached gave only the
front matter and the table of changes). The formulas above are the ones that two
independent open implementations transcribe, identically, from the standard:

- FRyDoM (Ecole Centrale de Nantes, LHEEA, and D-ICE Engineering; GPLv3; frydom-ce.org, e.g.
  the public mirror github.com/baptistelabat/frydom), class FrCurrentStandardForce
  ("Standard current drag force from DNV standard", DNV GL station keeping 0111), file
  src/frydom/environment/ocean/current/FrCurrentStandardForce.cpp: force.x = -0.07 ak A_T
  cos(alpha), force.y = 0.6 ak A_L sin(alpha), torque.z = force.y m2 L_pp with
  m2 = max(min(0.4 (1 - 2 alpha / pi), 0.25), -0.2) and alpha folded to [0, pi], the force
  applied at x = x_center; A_T defaults to draft x breadth;
- github.com/WilliamBoland1/Prosjektoppgave_Collab, dp_capability/models/currentloads.py
  (function current_loads_level1) and dp_capability/models/Descriptions/currentloads.md, which
  cite DNV-ST-0111 Edition December 2021 [3.6] and state that the formulas were checked
  against the PDF of the standard; the same three formulas, with x_L,current.

FRyDoM's transcription predates the December 2021 edition (it names the DNV GL standard), so
the two also agree that the formulas did not change between the editions.

Why this source: it is the only public source found with all three coefficients. UFC 4-159-03
"Design: Moorings" (3 October 2005), section 4-5, gives the transverse and longitudinal
current forces (eqs. 10-23, read on pages 87-92), but its yaw moment (eqs. 24, 25, page 95)
needs the constants of Table 4-10 "Current moment eccentricity ratio variables" (page 96),
and that page could not be read in any copy reached (ufc_current_tanker_loaded.py keeps the
UFC surge and sway for comparison). DNV's formulas hold for any ship-shaped monohull: they are
not specific to a tanker, which is why they can stand for a loaded tanker or bulk carrier.
Compared with UFC's formulas for the KVLCC2 benchmark tanker in deep water (that script,
``--preview``), the beam-current coefficient agrees (UFC 0.574, DNV 0.6) but the head-current
one does not: UFC gives 0.207 on B T (form drag, skin friction and a locked propeller) against
DNV's 0.07, so the surge load of this table is uncertain by a factor of about 3.

The two ship inputs
-------------------
In coefficient form the formulas need only two ratios, and this table fixes them:

- A_L,current / (L_pp T) = 1 (AREA_RATIO): the side profile below water taken as the
  rectangle L_pp x T, a fair value for a full-bodied loaded tanker or bulk carrier, whose
  underwater profile reaches about from the aft to the forward perpendicular at even keel.
  cy and cmz are proportional to it: for another ratio r, multiply both by r.
- x_L,current / L_pp = 0 (CENTRE_RATIO): the centre of that area at midship. cmz is linear
  in it: for a centre x_L,current forward of midship, cmz + (x_L,current / L_pp) cy.

Conversion to the project's convention (rope_sim_ros.model.ship.coefficients)
-----------------------------------------------------------------------------
Both frames have x forward, y to port, z up and the origin at L_pp / 2; the project's angle
theta is also where the current comes from, but measured from the bow toward PORT
(counter-clockwise), so beta = 360 deg - theta. The areas are the project's A_T = B T (the
same as DNV's) and A_L = L_pp T, and the moment goes with A_L L_pp. Then, for 0..180 deg::

    cx  = -0.07 cos(theta)
    cy  = -0.6 sin(theta) AREA_RATIO
    cmz = (CENTRE_RATIO + max(min(0.4 (1 - 2 theta / pi), 0.25), -0.2)) cy

(dir = 360 deg - theta folds onto theta for theta <= 180 deg). A current from port (theta = 90)
gives cy = -0.6: the ship is pushed to starboard; a current on the port bow (theta = 30)
pushes the bow to starboard, cmz < 0. The ship is symmetric port to starboard, so the rows
190..350 mirror 170..10: cx(360 - t) = cx(t), cy(360 - t) = -cy(t), cmz(360 - t) = -cmz(t).

Left out: the dynamic factor 1.25 that Level 1 applies to the sum of the wind, current and
wave loads ([3.2.2] as cited by the implementations above; not a property of the current),
and any effect of the water depth (the formulas have none; UFC 4-159-03 eq. 11 shows that
the transverse force can grow several times as the keel clearance closes).

Rows are every 10 deg. The moment arm has kinks at 33.75 deg and 135 deg, which fall between
rows, so the table's linear interpolation departs from the formula there by up to
MAX_INTERPOLATION_ERROR in cmz (0.0055, at 135 deg) and by less elsewhere;
test/test_ship_coefficients.py measures it.
"""

import math
import sys
from typing import List, Tuple

SURGE = 0.07  # DNV-ST-0111 [3.6]: F_X coefficient, with B T
SWAY = 0.6  # F_Y coefficient, with A_L,current
ARM_SLOPE = 0.4  # lever 0.4 (1 - 2 dir / pi) L_pp ...
ARM_MAX = 0.25  # ... at most 0.25 L_pp forward of x_L,current ...
ARM_MIN = -0.2  # ... and at most 0.2 L_pp aft of it
AREA_RATIO = 1.0  # A_L,current / (L_pp T): an assumption of this table (module docstring)
CENTRE_RATIO = 0.0  # x_L,current / L_pp: an assumption of this table (module docstring)
STEP_DEG = 10
DIGITS = 6
MAX_INTERPOLATION_ERROR = 0.0055  # bound on |cmz(table) - cmz(formula)|, module docstring

HEADER = """\
# Current load coefficients, loaded tanker or bulk carrier, OCIMF form (rope_sim_ros
# convention). F_x = 1/2 rho V^2 A_T cx, F_y = 1/2 rho V^2 A_L cy, M_z = 1/2 rho V^2 A_L L cmz
# with A_T = B T (beam x draft), A_L = L T (length between perpendiculars x draft), L = L_pp.
# angle_deg: direction the current comes FROM, from the bow (0) toward port (90), body axes
# x forward, y to port, z up, moment about midship; V, angle: water relative to the ship.
# Signs: head current cx < 0; current from port (90) cy < 0 (pushes the ship to starboard).
# Source: DNV-ST-0111 "Assessment of station keeping capability of dynamic positioning
# vessels", DNV AS, Edition December 2021, [3.6] current loads (DP capability Level 1):
#   F_X = 1/2 rho V^2 B T (-0.07 cos b), F_Y = 1/2 rho V^2 A_L,current (0.6 sin b),
#   M_Z = F_Y (x_L,current + max(min(0.4 (1 - 2 dir/pi), 0.25), -0.2) L_pp),
#   b = direction the current comes from, clockwise (from starboard = 90 deg),
#   dir = b for b <= pi, 2 pi - b beyond; axes x forward, y to port, z up ([2.8.2]).
# The text of [3.6] could not be read for this table: these are the formulas that two
# independent open implementations transcribe identically from the standard: FRyDoM
# (frydom-ce.org), src/frydom/environment/ocean/current/FrCurrentStandardForce.cpp, and
# github.com/WilliamBoland1/Prosjektoppgave_Collab, dp_capability/models/currentloads.py.
# Why this source: the only complete public one found. UFC 4-159-03 (2005) section 4-5 gives
# surge and sway, but its yaw moment needs Table 4-10 (page 96), which could not be read.
# Assumptions of this table, not DNV's: A_L,current = L_pp T and x_L,current = 0 (side
# profile below water centred at midship). For a ratio r = A_L,current/(L_pp T) multiply cy
# and cmz by r; for a centre x_L,current forward of midship use cmz + (x_L,current/L_pp) cy.
# Converted from DNV's clockwise angle as angle_deg = 360 - b: cx = -0.07 cos(angle),
# cy = -0.6 sin(angle), cmz = max(min(0.4 (1 - 2 angle/pi), 0.25), -0.2) cy for 0..180 deg;
# rows 190..350 mirror 170..10 (cx even, cy and cmz odd: port/starboard symmetric ship).
# Left out: Level 1's dynamic factor 1.25, any water-depth effect. Interpolating between the
# 10 deg rows misses the lever's kinks at 33.75 and 135 deg by up to 0.0055 in cmz.
# Computed (not digitised) by test/data/ship_coefficients/dnv_current_tanker_loaded.py.
"""


def lever(theta_deg: float) -> float:
    """Return DNV's moment arm / L_pp, max(min(0.4 (1 - 2 dir / pi), 0.25), -0.2)."""
    folded = theta_deg % 360.0
    folded = folded if folded <= 180.0 else 360.0 - folded
    return max(min(ARM_SLOPE * (1.0 - folded / 90.0), ARM_MAX), ARM_MIN)


def coefficients(theta_deg: float) -> Tuple[float, float, float]:
    """Return (cx, cy, cmz) in the project's convention at theta [deg], from the formulas."""
    theta = math.radians(theta_deg)
    cx = -SURGE * math.cos(theta)
    cy = -SWAY * math.sin(theta) * AREA_RATIO
    cmz = (CENTRE_RATIO + lever(theta_deg)) * cy
    return cx, cy, cmz


def rows() -> List[Tuple[int, float, float, float]]:
    """Return (angle_deg, cx, cy, cmz) rows, 0..350 deg, mirrored from 0..180 deg."""
    half = {angle: coefficients(float(angle)) for angle in range(0, 181, STEP_DEG)}
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
