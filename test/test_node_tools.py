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

"""ship_motion, line_monitor and the scripted passing ship: pure functions."""

import math

from geometry_msgs.msg import PoseArray
import numpy as np
import pytest
from rope_sim_ros.ros import conversions
from rope_sim_ros.ros.line_monitor_node import max_strain
from rope_sim_ros.ros.ship_motion_node import PARAMETERS, ship_pose

SHIP = {name: spec[0] for name, spec in PARAMETERS.items()}


def test_ship_rests_at_the_mean_position_at_the_start():
    position, q = ship_pose(0.0, SHIP)
    assert position == pytest.approx([36.0, 0.0, 8.0])
    assert q == pytest.approx((0.0, 0.0, 0.0, 1.0))


def test_ship_motion_fades_in_smoothly():
    # velocity is continuous: the ramp starts with zero slope
    early = np.array(ship_pose(0.01, SHIP)[0]) - [36.0, 0.0, 8.0]
    assert np.linalg.norm(early) < 1e-4
    # after the ramp the motion is the plain sines
    t = 23.0
    position, _ = ship_pose(t, SHIP)
    expected = [36.0 + 0.8 * math.sin(2 * math.pi * t / 10.0),
                0.4 * math.sin(2 * math.pi * t / 14.0),
                8.0 + 0.5 * math.sin(2 * math.pi * t / 8.0)]
    assert position == pytest.approx(expected)


def test_demo_fairlead_moves_one_to_two_metres():
    points = np.array([ship_pose(t, SHIP)[0] for t in np.arange(0.0, 300.0, 0.05)])
    extent = np.ptp(points, axis=0)
    assert 1.0 <= np.linalg.norm(extent) <= 3.0, extent
    assert np.linalg.norm(points.mean(axis=0) - [36.0, 0.0, 8.0]) < 0.1


def test_ship_heading_turns_surge_and_roll():
    ship = dict(SHIP, heading=math.pi / 2, ramp_duration=0.0, sway_amplitude=0.0,
                heave_amplitude=0.0, surge_period=4.0, roll_period=4.0, roll_amplitude=0.1)
    position, q = ship_pose(1.0, ship)  # a quarter period: surge and roll at their maxima
    assert position == pytest.approx([36.0, 0.8, 8.0])
    q = np.array(q)
    assert np.linalg.norm(q) == pytest.approx(1.0)
    # the ship's x axis points along +y; its y axis (port) rolls up by 0.1 rad
    assert conversions.rotate(q, [1, 0, 0]) == pytest.approx([0.0, 1.0, 0.0], abs=1e-12)
    assert conversions.rotate(q, [0, 1, 0]) == pytest.approx(
        [-math.cos(0.1), 0.0, math.sin(0.1)], abs=1e-12)


def test_monitor_max_strain():
    positions = np.array([[0.0, 0, 0], [2.0, 0, 0], [4.02, 0, 0]])
    msg = conversions.pose_array(positions, 'world', 0)
    assert max_strain(msg, 4.0) == pytest.approx(0.01)
    assert math.isnan(max_strain(PoseArray(), 4.0))


def test_passing_ship_moves_the_ship_and_leaves_it_where_it_was():
    from rope_sim_ros.mooring import scenario as passing_ship
    times = np.arange(0.0, passing_ship.END + 10.0, 0.05)
    poses = [passing_ship.ship_pose(t) for t in times]
    positions = np.array([p for p, _ in poses])
    rest = np.array(passing_ship.REST)
    before = times < passing_ship.START
    after = times > passing_ship.END
    assert np.abs(positions[before | after] - rest).max() < 1e-12
    surge, sway = positions[:, 0] - rest[0], positions[:, 1] - rest[1]
    # ahead first, then astern, and off the quay (-y) in between
    assert times[np.argmax(surge)] < times[np.argmin(surge)]
    assert 0.25 < surge.max() < passing_ship.SURGE and -passing_ship.SURGE < surge.min() < -0.25
    assert sway.min() == pytest.approx(-passing_ship.SWAY, rel=1e-3) and sway.max() <= 0.0
    # smooth: no step in the velocity (the samples are 0.05 s apart)
    assert np.abs(np.diff(positions, 2, axis=0)).max() < 1e-4
    assert np.allclose([np.linalg.norm(q) for _, q in poses], 1.0)
