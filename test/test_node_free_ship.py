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
The mooring node with a free ship: its parameters, topics, bag, stiffness and resim.

The node runs in this process on sim time that the test sets tick by tick (no sleeping, no
spinning): the berth of config/berth.yaml made free, a ship passing on its starboard side,
a tug's push in surge from t = 2 s and a head wind from t = 3 s, each sent as the topic's
message into its callback.
"""

from pathlib import Path
from typing import Optional

from geometry_msgs.msg import Vector3Stamped, WrenchStamped
from nav_msgs.msg import Odometry
from node_harness import spin_until
import numpy as np
import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.serialization import deserialize_message
from rclpy.signals import SignalHandlerOptions
from rclpy.time import Time
from rope_sim_ros.bag import read_messages
from rope_sim_ros.bag.cdr import decode_pose_array, decode_pose_stamped, decode_wrench_stamped
from rope_sim_ros.messages import topics
from rope_sim_ros.model.frames import rotation_matrix
from rope_sim_ros.model.ship.coefficients import ocimf_loads
from rope_sim_ros.mooring.statics import ship_stiffness
from rope_sim_ros.offline.resim import resim, stored_setup
from rope_sim_ros.params.arrangement import flatten, read_arrangement_file
from rope_sim_ros.params.ship import read_coefficients
from rope_sim_ros.ros.mooring_display import Fenders, LineMarkers
from rope_sim_ros.ros.node import MooringNode
from std_msgs.msg import Float64MultiArray

BERTH = Path(__file__).resolve().parents[1] / 'config' / 'berth.yaml'
RATE = 20.0  # [Hz] outputs
EPOCH = 1_000_000_000  # [ns] the sim clock's first tick
PUSH = 2.0e6  # [N] the tug's push along the ship's body x, from PUSH_AT [s]
PUSH_AT, WIND_AT, END = 2.0, 3.0, 6.0
WIND = 15.0  # [m/s] a head wind: the air goes to -x, the ship heads +x
PASSING = {'passing_ship.speed': 4.0, 'passing_ship.separation': 70.0,
           'passing_ship.start_x': -60.0}


def overrides(bag: Optional[Path]) -> list:
    """Return config/berth.yaml's parameters, made free, recorded into bag unless it is None."""
    values = flatten(read_arrangement_file(BERTH).values())
    values.update({'ship_mode': 'free', 'publish_rate': RATE, 'stiffness_rate': 2.0,
                   **PASSING})
    if bag is not None:
        values['record_path'] = str(bag)
    return [Parameter('use_sim_time', value=True)] + [
        Parameter(name, value=value) for name, value in values.items()]


def at(node, t: float) -> None:
    """Set the node's sim clock to t [s] after EPOCH and run one tick."""
    node.get_clock().set_ros_time_override(Time(nanoseconds=EPOCH + round(t * 1e9)))
    node._on_tick()


@pytest.fixture(scope='module')
def run(tmp_path_factory):
    """Run the free berth for END s; return the node's findings and its bag."""
    bag = tmp_path_factory.mktemp('free') / 'bag'
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = MooringNode(context=context, namespace='/free_ship',
                       parameter_overrides=overrides(bag))
    found = {}
    try:
        found['parameters'] = {name: node.get_parameter(name).value for name in (
            'ship_mode', 'fenders', 'fender_2.rated_compression', 'passing_ship.speed')}
        found['read_only'] = node.describe_parameter('ship.mass').read_only
        at(node, 0.0)
        found['start_time'] = node.driver.mooring.time
        node._on_stiffness()  # (its timer's callback)
        for k in range(1, round(END * RATE) + 1):
            t = k / RATE
            if t == PUSH_AT:
                push = WrenchStamped()
                push.header.frame_id = 'base_link'  # body axes
                push.wrench.force.x = PUSH
                node._on_external_wrench(push)
            if t == WIND_AT:
                wind = Vector3Stamped()
                wind.header.frame_id = 'world'
                wind.vector.x = -WIND
                node._on_environment(topics.WIND, wind)
            at(node, t)
        found['wind'] = (node.get_parameter('wind_speed').value,
                         node.get_parameter('wind_direction').value)
        out = node.driver.mooring.output()
        found['output'] = out
        node._on_stiffness()
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)
    found['bag'] = bag
    return found


def messages(bag: Path, topic: str) -> list:
    return [m.data for m in read_messages(bag, [f'/free_ship/{topic}'])]


def test_the_node_declares_the_free_ships_parameters(run):
    params = run['parameters']
    assert params['ship_mode'] == 'free'
    assert params['fenders'] == ['fender_1', 'fender_2', 'fender_3', 'fender_4']
    assert params['fender_2.rated_compression'] == 1.2
    assert params['passing_ship.speed'] == 4.0
    assert run['read_only']


def test_the_free_ship_starts_at_rest_at_its_start_pose_and_publishes_it(run):
    poses = [decode_pose_stamped(data) for data in messages(run['bag'], topics.SHIP_POSE)]
    assert len(poses) == round(END * RATE) + 1  # every output from t = 0
    first = poses[0]
    assert first[2] == 'world'
    np.testing.assert_allclose(first[3], [0.0, -17.6, 0.0], atol=1e-9)
    odometry = [deserialize_message(data, Odometry)
                for data in messages(run['bag'], topics.SHIP_ODOMETRY)]
    assert len(odometry) == len(poses)
    assert odometry[0].child_frame_id == 'base_link'
    # the published pose is the one the lines used: the last output's, the model's now
    np.testing.assert_allclose(poses[-1][3], run['output'].ship.position, atol=1e-12)
    last = odometry[-1].pose.pose.position
    np.testing.assert_allclose([last.x, last.y, last.z], poses[-1][3], atol=1e-12)


def test_a_push_on_external_wrench_moves_the_ship_ahead(run):
    poses = [decode_pose_stamped(data)[3] for data in messages(run['bag'], topics.SHIP_POSE)]
    before = poses[round(PUSH_AT * RATE)][0]
    surge = poses[-1][0] - before
    # 2 MN on 8.84e7 kg plus its added mass for 4 s: at most 0.18 m were the springs slack;
    # the springs hold it back, but not all of it
    assert 0.02 < surge < 0.18, surge
    assert run['output'].ship.velocity[0] > 0.0


def test_the_wind_topic_sets_the_wind_and_its_load_is_ocimfs(run):
    speed, direction = run['wind']
    assert speed == pytest.approx(WIND, rel=1e-12)
    assert direction == pytest.approx(0.0, abs=1e-12)  # it comes FROM +x
    out = run['output']
    setup = read_arrangement_file(BERTH)
    ship = setup.ship
    # the air past the ship, in its body axes (the passing ship yawed it a little)
    relative = (np.array([-WIND, 0.0, 0.0]) - out.ship.velocity) @ rotation_matrix(
        out.ship.orientation)
    expected = ocimf_loads(read_coefficients(ship, 'wind_coefficients'),
                           setup.shared.air_density, relative[:2], ship.wind_area_front,
                           ship.wind_area_side, ship.length)
    np.testing.assert_allclose(out.ship_loads[0], expected, rtol=1e-9)
    assert out.ship_loads[0][0] < -3e4  # a head wind pushes the ship astern


def test_the_passing_ship_wrench_is_published_in_body_axes(run):
    wrenches = [decode_wrench_stamped(data)
                for data in messages(run['bag'], topics.PASSING_WRENCH)]
    assert len(wrenches) == round(END * RATE) + 1
    assert {w[2] for w in wrenches} == {'base_link'}
    sway = np.array([w[3][1] for w in wrenches])
    assert np.all(np.isfinite(sway)) and np.abs(sway).max() > 1e4
    np.testing.assert_allclose(wrenches[-1][3][:2], run['output'].ship_loads[2][:2])


def test_the_odometry_twist_is_the_ships_velocity_in_its_body_axes(run):
    odometry = [deserialize_message(data, Odometry)
                for data in messages(run['bag'], topics.SHIP_ODOMETRY)]
    positions = np.array([[o.pose.pose.position.x, o.pose.pose.position.y,
                           o.pose.pose.position.z] for o in odometry])
    assert np.abs(positions[-1] - positions[0]).max() > 0.02  # the ship moved
    means = np.diff(positions, axis=0) * RATE  # mean velocity of each output interval
    misses, speeds = [], []
    for i in range(2, len(odometry) - 2):
        # the velocity at output i from the two intervals before it, and from the two after
        # (each linear through their means): one of them is whole where the push starts at
        # an output and the acceleration jumps; in the ship's axes (R^T v)
        q = odometry[i].pose.pose.orientation
        rotation = rotation_matrix([q.x, q.y, q.z, q.w])
        before = (1.5 * means[i - 1] - 0.5 * means[i - 2]) @ rotation
        after = (1.5 * means[i] - 0.5 * means[i + 1]) @ rotation
        t = odometry[i].twist.twist.linear
        twist = np.array([t.x, t.y, t.z])
        misses.append(min(np.abs(twist - before).max(), np.abs(twist - after).max()))
        speeds.append(np.abs(twist).max())
    assert max(speeds) > 0.02  # [m/s] (measured 0.068: the passing ship)
    assert max(misses) < 2e-5  # [m/s] (measured 2.2e-6; in world axes 3.6e-5)
    out = run['output']
    last = odometry[-1].twist.twist
    rotation = rotation_matrix(out.ship.orientation)
    np.testing.assert_allclose([last.linear.x, last.linear.y, last.linear.z],
                               out.ship.velocity @ rotation, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose([last.angular.x, last.angular.y, last.angular.z],
                               out.ship.omega @ rotation, rtol=1e-12, atol=1e-15)


def test_each_fender_publishes_its_reaction_on_the_hull(run):
    setup = read_arrangement_file(BERTH)
    out = run['output']
    pushed = 0.0
    for f, fender in enumerate(setup.fenders):
        sent = [decode_wrench_stamped(data) for data in
                messages(run['bag'], f'{fender.name}/{topics.FENDER_REACTION}')]
        assert len(sent) == round(END * RATE) + 1
        assert {w[2] for w in sent} == {'world'}
        np.testing.assert_allclose(sent[-1][3], out.fender_forces[f], rtol=1e-12)
        normal = np.asarray(fender.normal, dtype=float) / np.linalg.norm(fender.normal)
        for w in sent:
            force, torque = w[3], w[4]
            assert not torque.any()  # at its contact point
            along = float(force @ normal)
            assert along >= 0.0  # a fender pushes, never pulls
            # the rest is the hull's friction on it, at most friction x the push
            assert np.linalg.norm(force - along * normal) <= fender.friction * along + 1e-6
            pushed = max(pushed, along)
    assert pushed > 1e4  # [N]: the lines hold the ship against its fenders


def test_ship_stiffness_is_the_statics_stiffness_where_the_ship_is(run):
    assert run['start_time'] == 0.0
    sent = [deserialize_message(data, Float64MultiArray)
            for data in messages(run['bag'], topics.STIFFNESS)]
    assert len(sent) == 2
    layout = sent[0].layout
    dims = [(d.label, d.size, d.stride) for d in layout.dim]
    assert dims == [('rows', 6, 36), ('cols', 6, 6)]
    matrix = np.array(sent[0].data).reshape(6, 6)
    # at the start pose: the stiffness `rope_sim stiffness` prints for the same file
    expected = ship_stiffness(read_arrangement_file(BERTH))
    np.testing.assert_allclose(matrix, expected, rtol=1e-9, atol=1e-6 * np.abs(expected).max())
    end = np.array(sent[1].data).reshape(6, 6)
    assert end[0, 0] > 0.0 and end[1, 1] > 0.0 and end[5, 5] > 0.0
    assert not np.array_equal(end, matrix)  # where the ship is now, not where it started


def test_resim_replays_the_free_ships_bag(run, tmp_path):
    resim(run['bag'], tmp_path / 'again', stored_setup(run['bag']))
    for topic in (topics.SHIP_POSE, 'spring_fwd/' + topics.PARTICLES):
        node = messages(run['bag'], topic)
        again = [m.data for m in read_messages(tmp_path / 'again', [f'/free_ship/{topic}'])]
        assert len(again) == len(node)
        decode = decode_pose_array if topic.endswith(topics.PARTICLES) else decode_pose_stamped
        np.testing.assert_allclose(decode(again[-1])[3], decode(node[-1])[3], atol=1e-9)


def test_a_fender_past_its_rated_compression_warns():
    fenders = Fenders(['f1', 'f2'], [[0, -1, 0], [0, -1, 0]], [1.2, 1.2],
                      [[0, -1.5, 0], [10, -1.5, 0]], [0.3, 1.3], [[0, -4e5, 0], [0, -2e6, 0]])
    statuses = fenders.statuses('mooring')
    assert [s.level for s in statuses] == [b'\x00', b'\x01']  # OK, WARN
    assert statuses[1].name == 'mooring: f2'
    assert 'past its rating' in statuses[1].message
    assert dict((v.key, v.value) for v in statuses[0].values)['reaction [N]'] == '400000.0'


def test_the_fenders_are_drawn_at_their_contact_points():
    fenders = Fenders(['f1', 'f2'], [[0, -1, 0], [0, -1, 0]], [1.2, 1.2],
                      [[0, -1.5, 0], [10, -1.5, 0]], [0.3, 1.3], [[0, -4e5, 0], [0, -2e6, 0]])
    markers = LineMarkers()('world', 1_000_000_000, [], [], [], [], [], np.zeros((0, 3)),
                            np.zeros((0, 3)), fenders).markers
    bodies = [m for m in markers if m.ns == 'fenders']
    labels = [m.text for m in markers if m.ns == 'fender_labels']
    assert [(m.pose.position.x, m.pose.position.y) for m in bodies] == [(0.0, -1.5),
                                                                        (10.0, -1.5)]
    assert labels == ['f1 400 kN', 'f2 2000 kN']
    # the cylinder's axis (its z) along the normal, -y: a quarter turn about +x
    q = bodies[0].pose.orientation
    assert [q.x, q.y, q.z, q.w] == pytest.approx([np.sqrt(0.5), 0.0, 0.0, np.sqrt(0.5)])
    assert bodies[0].color.g > bodies[0].color.r  # green: within its rating
    assert bodies[1].color.r > bodies[1].color.g  # amber: past it


def test_ship_stiffness_is_worked_out_only_for_a_subscriber(monkeypatch):
    # unrecorded, unsubscribed: no statics at all (it cost 10 % of a 16-line node's CPU)
    from rope_sim_ros.mooring import driver as driver_module
    from rope_sim_ros.ros import node as node_module
    worked = []
    real = driver_module.stiffness_now
    monkeypatch.setattr(driver_module, 'stiffness_now',
                        lambda *args: worked.append(1) or real(*args))
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = node_module.MooringNode(context=context, namespace='/stiffness_taken',
                                   parameter_overrides=overrides(None))
    probe = rclpy.create_node('stiffness_probe', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    executor.add_node(probe)
    try:
        at(node, 0.0)
        at(node, 1.0 / RATE)
        node._on_stiffness()
        assert worked == []
        got = []
        probe.create_subscription(Float64MultiArray, f'/stiffness_taken/{topics.STIFFNESS}',
                                  got.append, 10)
        spin_until(executor, lambda: node._taken.subscribed(topics.STIFFNESS), 10.0,
                   'the subscriber')
        node._on_stiffness()  # (its timer may fire in the spin too)
        spin_until(executor, lambda: got, 10.0, 'ship/stiffness')
        assert len(worked) >= 1
        assert np.array(got[0].data).reshape(6, 6)[1, 1] > 0.0
    finally:
        executor.shutdown()
        probe.destroy_node()
        node.destroy_node()
        rclpy.try_shutdown(context=context)


def wrench(frame: str, force_x: float) -> WrenchStamped:
    msg = WrenchStamped()
    msg.header.frame_id = frame
    msg.wrench.force.x = force_x
    return msg


def test_a_load_no_tug_gives_or_in_an_unknown_frame_is_refused_each_in_one_line(capfd):
    # (issue: 1e12 N, 11 km/s^2 on this ship, was taken without a word; a load in `map` was
    # taken as world axes; a second, different refusal on the topic within 5 s was not said)
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = MooringNode(context=context, namespace='/refusals',
                       parameter_overrides=overrides(None))
    try:
        at(node, 0.0)
        capfd.readouterr()
        node._on_external_wrench(wrench('base_link', 1e12))
        node._on_external_wrench(wrench('base_link', 2e12))  # the same refusal: throttled
        node._on_external_wrench(wrench('map', 1e5))
        node._on_external_wrench(wrench('map', 2e5))
        assert not node.driver.mooring.ship.body_load.any()
        assert not node.driver.mooring.ship.external_load.any()
        node._on_external_wrench(wrench('world', 1e5))  # frame_id: taken, world axes
        assert node.driver.mooring.ship.external_load[0] == 1e5
        at(node, 1.0 / RATE)
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)
    lines = [line for line in capfd.readouterr().err.splitlines()
             if 'ship/external_wrench: ignored' in line]
    assert len(lines) == 2, lines
    assert ('/refusals/ship/external_wrench: ignored: an external force of 1e+12 N is more '
            'than any tug or thruster gives this ship: at most 8.67e+07 N') in lines[0]
    assert "header.frame_id 'map' is neither 'world' nor 'base_link'" in lines[1]


def test_a_free_ship_waiting_for_its_first_clock_says_so(capfd):
    # (issue: under use_sim_time with no /clock it said nothing for as long as none came)
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = MooringNode(context=context, namespace='/no_clock',
                       parameter_overrides=overrides(None))
    try:
        capfd.readouterr()
        node._on_tick()  # (its timer, had the clock run) at clock 0: nothing starts
        node._check_clock()  # (its steady timer's callback)
        assert not node.driver.started
        assert ('use_sim_time is true but no /clock message has come: the free ship starts '
                'at rest at its start pose at the first one') in capfd.readouterr().err
        at(node, 0.0)
        assert node.driver.started
        node._check_clock()
        assert 'no /clock' not in capfd.readouterr().err
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)
