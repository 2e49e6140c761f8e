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
Write the shipped current tables at several water depths from the deep one and UFC 4-159-03.

Run ``python test/data/ship_coefficients/ufc_depth_current_tanker_loaded.py --write config/ship``
to write config/ship/current_coefficients_tanker_loaded_depth_<r>T.csv for each ratio r of
RATIOS (``--ratio R`` prints one); test/test_ship_coefficients.py checks that each shipped
file is exactly this script's output, so every number in it is traceable to the deep table
(dnv_current_tanker_loaded.py, DNV-ST-0111 [3.6]) and the factor below.

Source
------
Unified Facilities Criteria UFC 4-159-03, "Design: Moorings", US Department of Defense
(NAVFAC), 3 October 2005, approved for public release, section 4-5.1, eq. 11: the transverse
current force coefficient of a ship at a draft T in water of depth d,

    C_yc = C0 + (C1 - C0) (T / d)^K,

with C0 the deep-water coefficient, C1 = 3.2 the coefficient with the keel on the bottom
(T / d = 1; "for currents of 1.5 m/s (2.9 knots) or less") and K = 2 ("wide range of ship and
barge tests; most all of the physical model data available can be fit with this
coefficient"). test/test_ship_coefficients.py checks the form and the constants against the
UFC's own Table 4-6 (an FFG-7 at five depths, three rows predicted from two to their printed
digits).

How the tables are made
-----------------------
Each table is the deep-water table (config/ship/current_coefficients_tanker_loaded.csv, DNV's
C_y = 0.6) with cy and cmz multiplied by C_yc(T/d) / C0, taking C0 = 0.6, the deep table's
own beam coefficient (UFC's eq. 12, C0 = 0.22 sqrt(L^2 A_m / (B V)), gives 0.63 for the
default 225 m bulk carrier and 0.57 for the KVLCC2 tanker): a factor of
1 + (3.2 / 0.6 - 1) (T / d)^2, 4.58 at a depth of 1.1 T, 1.17 at 5 T. cx is left as it is:
the UFC's longitudinal current force (section 4-5.2) has no depth term. cmz goes with cy:
the UFC's current moment (section 4-5.4, eqs. 24-25) is F_yc times an eccentricity that
does not depend on the depth.

What this is not: OCIMF's measured current coefficients at several depths (the form the
tables take, OCIMF's "Prediction of Wind and Current Loads on VLCCs" and its Mooring
Equipment Guidelines) are not public, and no public, citable set of OCIMF-form tables at
several depth / draft ratios was found; this set is UFC's depth factor on the deep table,
and it changes only the magnitude of the lateral coefficient, not the shape of the curves
over the angle, which OCIMF's tables show changing too in shallow water.

The set: RATIOS below and, from DEEP_RATIO on, the deep table itself (UFC's factor is 1.04
there and falls to 1 as the depth grows). Interpolated linearly in the ratio between these
(rope_sim_ros.model.ship.coefficients.table_at_ratio), the set stays within MAX_SET_ERROR
(5.3 %, between 2 T and 3 T; -4.2 % at 10 T) of UFC's factor at every depth from 1.1 T on;
test/test_ship_coefficients.py measures it.
"""

import argparse
import importlib.util
from pathlib import Path
import sys
from typing import List, Optional, Tuple

C1 = 3.2  # UFC 4-159-03 eq. 11: the transverse coefficient at T / d = 1
K_EXPONENT = 2.0  # eq. 11: the exponent of T / d
RATIOS = (1.1, 1.2, 1.3, 1.5, 2.0, 3.0, 5.0)  # water depth / draft of the shallow tables
DEEP_RATIO = 10.0  # from here on the set takes the deep table
MAX_SET_ERROR = 0.053  # bound on |set / UFC's factor - 1|, module docstring
DEEP_SCRIPT = Path(__file__).resolve().parent / 'dnv_current_tanker_loaded.py'


def deep_script():
    """Import dnv_current_tanker_loaded.py beside this file (the deep table's script)."""
    spec = importlib.util.spec_from_file_location(DEEP_SCRIPT.stem, DEEP_SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def factor(ratio: float) -> float:
    """Return C_yc(T/d) / C0 of UFC 4-159-03 eq. 11 at a water depth / draft ratio."""
    c0 = deep_script().SWAY
    return (c0 + (C1 - c0) * (1.0 / ratio) ** K_EXPONENT) / c0


def file_name(ratio: float) -> str:
    """Return the shipped file's name of a ratio (config/ship/)."""
    return f'current_coefficients_tanker_loaded_depth_{ratio:g}T.csv'


def rows(ratio: float) -> List[Tuple[int, float, float, float]]:
    """Return (angle_deg, cx, cy, cmz): the deep table's rows, cy and cmz times the factor."""
    scale = factor(ratio)
    return [(angle, cx, scale * cy, scale * cmz) for angle, cx, cy, cmz in deep_script().rows()]


def header(ratio: float) -> str:
    """Return the comment header of the table at a ratio."""
    return f"""\
# Current load coefficients, loaded tanker or bulk carrier, OCIMF form (rope_sim_ros
# convention), in water {ratio:g} times as deep as the draft (T / d = {1.0 / ratio:.6f}).
# F_x = 1/2 rho V^2 A_T cx, F_y = 1/2 rho V^2 A_L cy, M_z = 1/2 rho V^2 A_L L cmz with
# A_T = B T, A_L = L T, L = L_pp; angle_deg: direction the current comes FROM, from the bow
# (0) toward port (90), body axes x forward, y to port, z up, moment about midship.
# The deep-water table (current_coefficients_tanker_loaded.csv, DNV-ST-0111 December 2021
# [3.6]) with cy and cmz times UFC 4-159-03 (US DoD, 3 October 2005) section 4-5.1 eq. 11's
# depth factor C_yc(T/d) / C0, C_yc = C0 + (C1 - C0) (T/d)^K, C1 = 3.2, K = 2, C0 = 0.6 (the
# deep table's beam coefficient): factor {factor(ratio):.6f}. cx unchanged (the UFC's
# longitudinal current force has no depth term); cmz scaled as cy (the UFC's moment is F_yc
# times a lever that does not depend on the depth). Not OCIMF's measured shallow-water
# coefficients (not public): UFC's factor on the magnitude only, not on the shape.
# Computed (not digitised) by test/data/ship_coefficients/ufc_depth_current_tanker_loaded.py.
"""


def csv_text(ratio: float) -> str:
    """Return the whole CSV file of the table at a ratio."""
    number = deep_script()._number
    lines = [header(ratio).rstrip('\n'), 'angle_deg,cx,cy,cmz']
    for angle, cx, cy, cmz in rows(ratio):
        lines.append(f'{angle},{number(cx)},{number(cy)},{number(cmz)}')
    return '\n'.join(lines) + '\n'


def main(argv: Optional[List[str]] = None) -> int:
    """Print the table at --ratio, or write every table of RATIOS into --write DIR."""
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument('--ratio', type=float, help='water depth / draft (one of RATIOS)')
    group.add_argument('--write', type=Path, metavar='DIR', help='write all into DIR')
    args = parser.parse_args(argv)
    if args.ratio is not None:
        sys.stdout.write(csv_text(args.ratio))
        return 0
    for ratio in RATIOS:
        (args.write / file_name(ratio)).write_text(csv_text(ratio))
    return 0


if __name__ == '__main__':
    sys.exit(main())
