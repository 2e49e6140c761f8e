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
The mooring node with a free ship in waves: their topics, their bag, a height set at run time.

The node runs in this process on sim time the test sets tick by tick (no sleeping, no
spinning), as test_node_free_ship.py's: the berth of config/berth.yaml made free, with the
shipped hydrodynamic database of its ship, in a regular wave from the open water; at 2 s
`waves.height` is set from 1 m to 2 m as `ros2 param set` would.
"""

import math
from pathlib import Path

import numpy as np
import pytest
import rclpy
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions
from rope_sim_ros.bag import read_messages
from rope_sim_ros.bag.cdr import decode_float64, decode_pose_stamped, decode_wrench_stamped
from rope_sim_ros.messages import topics
from rope_sim_ros.params.arrangement import flatten, read_arrangement_file
from rope_sim_ros.ros.node import MooringNode
from test_node_free_ship import at, BERTH

DATABASE = Path(__file__).resolve().parent / 'data' / 'hydro' / 'berth_ship.nc'
RATE, END, RAISE_AT = 20.0, 4.0, 2.0
PERIOD, DIRECTION = 8.0, -0.5 * math.pi  # from -y, the open water off the ship's starboard


@pytest.fixture(scope='module')
def run(tmp_path_factory):
    """Run the free berth in waves for END s; return its bag and the node's last output."""
    bag = tmp_path_factory.mktemp('waves') / 'bag'
    values = flatten(read_arrangement_file(BERTH).values())
    values.update({'ship_mode': 'free', 'publish_rate': RATE, 'record_path': str(bag),
                   'ship.hydrodynamics': str(DATABASE), 'waves.spectrum': 'regular',
                   'waves.height': 1.0, 'waves.period': PERIOD,
                   'waves.direction': DIRECTION})
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = MooringNode(context=context, namespace='/swell', parameter_overrides=[
        Parameter('use_sim_time', value=True)] + [
        Parameter(name, value=value) for name, value in values.items()])
    found = {'bag': bag}
    try:
        at(node, 0.0)
        for k in range(1, round(END * RATE) + 1):
            t = k / RATE
            if t == RAISE_AT:
                found['set'] = node.set_parameters([Parameter('waves.height', value=2.0)])[0]
            at(node, t)
        found['height'] = node.get_parameter('waves.height').value
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)
    return found


def series(bag, topic, decode):
    return [decode(m.data) for m in read_messages(bag, [f'/swell/{topic}'])]


def test_the_elevation_is_the_regular_wave_at_the_ships_origin(run):
    assert run['set'].successful and run['height'] == 2.0
    elevations = series(run['bag'], topics.WAVE_ELEVATION, decode_float64)
    poses = series(run['bag'], topics.SHIP_POSE, decode_pose_stamped)
    assert len(elevations) == len(poses) == round(END * RATE) + 1
    omega = 2.0 * math.pi / PERIOD
    # 16 m of water (config/berth.yaml): omega^2 = g k tanh(k h)
    k = omega ** 2 / 9.81
    for _ in range(50):
        k = omega ** 2 / (9.81 * math.tanh(k * 16.0))
    travel = DIRECTION + math.pi
    for i, (elevation, pose) in enumerate(zip(elevations, poses)):
        t = i / RATE
        x, y = pose[3][0], pose[3][1]
        amplitude = 0.5 if t < RAISE_AT else 1.0
        expected = amplitude * math.cos(k * (x * math.cos(travel) + y * math.sin(travel))
                                        - omega * t)
        assert elevation == pytest.approx(expected, abs=1e-6), t


def test_the_wave_wrench_is_published_in_body_axes_and_doubles_with_the_height(run):
    wrenches = series(run['bag'], topics.WAVE_WRENCH, decode_wrench_stamped)
    assert len(wrenches) == round(END * RATE) + 1
    assert {w[2] for w in wrenches} == {'base_link'}
    forces = np.array([w[3] for w in wrenches])
    assert np.isfinite(forces).all()
    # beam seas from starboard: the sway and heave forces swing through the wave's period
    before = forces[:round(RAISE_AT * RATE)]
    assert np.ptp(before[:, 1]) > 1e6 and np.ptp(before[:, 2]) > 1e6
    # the heave force (first order alone) at the wave's frequency: its amplitude in each
    # part, fitted with cos and sin, doubles with the height (0.492 seen: the ship sways
    # and yaws in the wave, which meets it a little later and at another heading)
    omega = 2.0 * math.pi / PERIOD
    t = np.arange(len(forces)) / RATE

    def amplitude(part):
        basis = np.column_stack((np.cos(omega * t[part]), np.sin(omega * t[part])))
        fit, residual = np.linalg.lstsq(basis, forces[part, 2], rcond=None)[:2]
        assert math.sqrt(residual[0] / len(basis)) < 0.01 * np.hypot(*fit)  # a sinusoid
        return np.hypot(*fit)

    split = round(RAISE_AT * RATE)
    ratio = amplitude(slice(0, split)) / amplitude(slice(split, None))
    assert ratio == pytest.approx(0.5, rel=0.03)
