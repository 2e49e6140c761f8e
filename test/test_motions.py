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

"""A moored ship's motions over a run, and PIANC's limits for working cargo."""

import math

import numpy as np
import pytest
from rope_sim_ros.model.frames import rotation_matrix
from rope_sim_ros.model.ship.motions import (against_limits, MOTION_CRITERIA, motion_ranges,
                                             motion_series, MOTIONS)
from rope_sim_ros.offline.plot import describe_motions
from rope_sim_ros.params.arrangement import from_values
from rope_sim_ros.params.table import ParameterError


def from_angles(roll, pitch, yaw):
    """Return the unit quaternion (x, y, z, w) of these z-y-x angles."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return np.array([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy])


def product(a, b):
    """Return the quaternion product a b (x, y, z, w)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz])


def test_motions_are_in_the_first_poses_body_axes_and_angles():
    # a ship heading 120 deg at (50, -20, 0.3): then moved 0.4 m ahead, 0.25 m to port and
    # 0.1 m up in its own axes, and turned by roll 2, pitch -1, yaw 3 deg (z-y-x) from there
    start = from_angles(0.0, 0.0, math.radians(120.0))
    origin = np.array([50.0, -20.0, 0.3])
    turn = from_angles(math.radians(2.0), math.radians(-1.0), math.radians(3.0))
    moved = origin + rotation_matrix(start) @ np.array([0.4, 0.25, 0.1])
    series = motion_series(np.array([origin, moved]), np.array([start, product(start, turn)]))
    expected = {'surge': 0.4, 'sway': 0.25, 'heave': 0.1, 'roll': math.radians(2.0),
                'pitch': math.radians(-1.0), 'yaw': math.radians(3.0)}
    for name in MOTIONS:
        assert series[name][0] == pytest.approx(0.0, abs=1e-12)
        assert series[name][1] == pytest.approx(expected[name], abs=1e-12), name


def test_peak_to_peak_and_sway_from_its_mean():
    t = np.arange(2000) * 0.05  # four sway periods, every peak sampled
    series = {name: np.zeros_like(t) for name in MOTIONS}
    series['surge'] = 0.3 + 0.8 * np.sin(2 * np.pi * t / 50.0)  # 1.6 m peak to peak
    series['sway'] = 0.2 + 0.5 * np.cos(2 * np.pi * t / 25.0)  # 0.5 m from its mean
    series['roll'] = np.radians(1.5) * np.sin(2 * np.pi * t / 10.0)
    ranges = motion_ranges(series)
    assert ranges['surge'] == pytest.approx(1.6, rel=1e-9)
    assert ranges['sway'] == pytest.approx(0.5, rel=1e-9)
    assert ranges['roll'] == pytest.approx(np.radians(3.0), rel=1e-9)
    assert ranges['heave'] == ranges['pitch'] == ranges['yaw'] == 0.0
    shares, largest = against_limits(ranges, MOTION_CRITERIA['container_full'])
    # a container ship at full efficiency: surge 1.0, sway 0.6 m, roll 3 deg
    assert shares['surge'] == pytest.approx(1.6) and largest == pytest.approx(1.6)
    assert shares['sway'] == pytest.approx(0.5 / 0.6, rel=1e-6)
    assert shares['roll'] == pytest.approx(1.0, rel=1e-6)
    # an oil tanker's loading arms limit surge and sway only
    shares, largest = against_limits(ranges, MOTION_CRITERIA['oil_tanker'])
    assert shares['roll'] is None and largest == pytest.approx(1.6 / 3.0)


def test_every_row_of_the_table_limits_in_si_units():
    for key, row in MOTION_CRITERIA.items():
        assert set(row.limits) == set(MOTIONS), key
        assert all(v is None or 0.0 < v < 10.0 for v in row.limits.values()), key
    bulk = MOTION_CRITERIA['bulk_cranes'].limits
    assert (bulk['surge'], bulk['sway'], bulk['heave']) == (2.0, 1.0, 1.0)
    assert [math.degrees(bulk[n]) for n in ('yaw', 'pitch', 'roll')] == pytest.approx([2, 2, 6])


def test_info_says_whether_cargo_can_be_worked():
    t = np.linspace(0.0, 60.0, 601)
    level = np.tile([0.0, 0.0, 0.0, 1.0], (len(t), 1))
    positions = np.column_stack([0.9 * np.sin(t / 5.0), np.zeros_like(t), np.zeros_like(t)])
    rows = describe_motions(positions, level, MOTION_CRITERIA['bulk_cranes'])
    assert rows[0].startswith('ship motions against PIANC (1995) for a dry bulk carrier')
    surge = next(r for r in rows if r.strip().startswith('surge'))
    assert '1.80 m   peak to peak' in surge and '90.0 %' in surge
    assert rows[-1] == ('cargo handling can go on: every motion within its limit (the largest '
                        'share 90 %, surge)')
    rows = describe_motions(positions * 3.0, level, MOTION_CRITERIA['bulk_cranes'])
    assert rows[-1] == 'cargo handling stops: surge at 270 % of its limit'


def test_the_criteria_are_a_parameter_refused_when_unknown():
    line = {'fairlead_offset': [0.0, 0.0, 0.0], 'bollard_position': [0.0, 20.0, 0.0],
            'length': 25.0}
    setup = from_values({'lines': ['a'], 'a': line, 'ship': {'motion_criteria': 'container_full'}})
    assert setup.ship.motion_limits is MOTION_CRITERIA['container_full']
    with pytest.raises(ParameterError, match='ship.motion_criteria.*bulk_cranes'):
        from_values({'lines': ['a'], 'a': line, 'ship': {'motion_criteria': 'bulk_crane'}})
