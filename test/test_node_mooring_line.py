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
The mooring_line node over real DDS: started from the colcon install, as `ros2 run` would.

One node process serves the topic, parameter, reset, bad-input, skip and Ctrl-C tests (in
that order, in namespace /line); the moving-fairlead comparison gets a fresh node (its start
must be known exactly), and the other start-up tests start short-lived ones. The domain is
the test run's own (test/conftest.py), discovery is localhost only.
"""

import math
from pathlib import Path
import signal
import subprocess
import time

from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
from node_harness import Client, no_gc_pauses, NodeProcess
import numpy as np
from one_line import OneLine
import pytest
from rclpy.parameter import Parameter, parameter_value_to_python
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rope_sim_ros.model.statics import catenary
from rope_sim_ros.params.files import load_params, read_params_file
from rope_sim_ros.params.table import LineParams, SPECS
from std_srvs.srv import Trigger

FAIRLEAD = np.array([36.0, 0.0, 8.0])
CHORD = FAIRLEAD / np.linalg.norm(FAIRLEAD)
SIM_START = 1000 * 1_000_000_000  # [ns] where the tests' sim time starts
START_TIMEOUT = 60.0  # the first node of a fresh install compiles the kernels (~10 s)
PARAMS_FILE = Path(__file__).resolve().parent.parent / 'config' / 'mooring_line.yaml'
VECTORS = [name for name, spec in SPECS.items() if isinstance(spec.default, list)]


# ------------------------------------------------------------------------------ helpers


def fairlead_tension(wrench: Wrench) -> float:
    f = wrench.force
    return math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)


def wrench_numbers(wrench: Wrench) -> list:
    return [wrench.force.x, wrench.force.y, wrench.force.z,
            wrench.torque.x, wrench.torque.y, wrench.torque.z]


def particle_array(msg: PoseArray) -> np.ndarray:
    return np.array([[p.position.x, p.position.y, p.position.z] for p in msg.poses])


def all_finite(client: Client) -> bool:
    numbers = [n for _, w in client.fairlead + client.bollard for n in wrench_numbers(w)]
    for _, msg in client.particles:
        for p in msg.poses:
            numbers += [p.position.x, p.position.y, p.position.z, p.orientation.x,
                        p.orientation.y, p.orientation.z, p.orientation.w]
    return bool(np.isfinite(numbers).all())


def default_line() -> LineParams:
    return load_params(PARAMS_FILE)


def chain_at(fairlead) -> catenary.ChainEquilibrium:
    """Exact static equilibrium of the default line between the origin and `fairlead`."""
    sim = OneLine(default_line())
    p, air = sim.props, sim.environment
    return catenary.chain_equilibrium([0.0, 0.0, 0.0], fairlead, p.length, p.segments,
                                      p.weight_per_length(air), p.axial_stiffness, air.gravity)


def smooth_step(t: float, start: float, duration: float) -> float:
    """0 before start, 1 after start + duration, a half cosine in between."""
    s = min(max((t - start) / duration, 0.0), 1.0)
    return 0.5 * (1.0 - math.cos(math.pi * s))


def log_lines(node: NodeProcess, word: str) -> list:
    return [line for line in node.text().splitlines() if word in line]


# ------------------------------------------------------------------------------ fixtures


@pytest.fixture(scope='module')
def line_node(colcon_install, colcon_env, tmp_path_factory):
    # length:=40, the file's 40.0 as an integer: test_sigint_ends_the_node_cleanly
    node = NodeProcess(colcon_install, colcon_env,
                       tmp_path_factory.mktemp('node') / 'line.log', '/line', '-p', 'length:=40')
    client = Client('/line', sim_time=False)
    try:
        client.wait_for_node(node)
        yield node, client
    finally:
        client.close()
        node.interrupt()


# --------------------------------------------------------------------------------- tests


def test_params_file_sets_every_parameter_to_its_default():
    values = read_params_file(PARAMS_FILE)
    assert set(values) == set(SPECS), set(values) ^ set(SPECS)
    assert {k: v for k, v in values.items() if v != SPECS[k].default} == {}
    text = PARAMS_FILE.read_text()
    assert '/**/mooring_line:' in text  # reaches the node in any namespace


def test_static_fairlead_gives_catenary_tension(line_node):
    node, client = line_node
    # no pose yet: nothing published, and the node says what it waits for
    client.spin(0.3)
    assert client.particles == [] and client.fairlead == []
    assert len(log_lines(node, 'waiting for the first pose on /line/fairlead/pose')) == 1

    client.drive_wall(4.0, lambda t: FAIRLEAD, rate=20.0)
    line = OneLine(default_line())
    expected = catenary.solve_catenary(
        math.hypot(FAIRLEAD[0], FAIRLEAD[1]), FAIRLEAD[2], line.props.length,
        line.material.mass_per_length * 9.81, line.material.axial_stiffness)
    start = client.fairlead[0][0]
    tensions = [fairlead_tension(w) for t, w in client.fairlead if t > start + 0.5]
    assert len(tensions) > 100, f'{len(tensions)} fairlead/tension messages in 3.5 s'
    mean = float(np.mean(tensions))
    assert abs(mean - expected.tension_b) < 0.01 * expected.tension_b, \
        f'mean fairlead tension {mean:.1f} N, catenary {expected.tension_b:.1f} N'

    msg = client.particles[-1][1]
    x = particle_array(msg)
    assert x.shape == (line.props.segments + 1, 3)
    assert msg.header.frame_id == 'world'
    assert np.allclose(x[0], 0.0, atol=1e-9) and np.allclose(x[-1], FAIRLEAD, atol=1e-9)
    # orientation: x axis along the local tangent (here: the middle particle's neighbours)
    q = msg.poses[10].orientation
    x_axis = np.array([1 - 2 * (q.y ** 2 + q.z ** 2), 2 * (q.x * q.y + q.z * q.w),
                       2 * (q.x * q.z - q.y * q.w)])
    tangent = (x[11] - x[9]) / np.linalg.norm(x[11] - x[9])
    assert np.dot(x_axis, tangent) > 0.9999
    # the stamp is the state time: within a few publish periods of the wall clock
    stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
    assert abs(stamp - time.time()) < 0.5
    # torque about the pose origin: zero offset, so zero torque
    assert np.allclose(wrench_numbers(client.fairlead[-1][1])[3:], 0.0)


def test_reset_restarts_the_rope_at_rest(line_node):
    node, client = line_node
    # shake the line (0.4 m along the chord and back), then hold the fairlead still
    client.drive_wall(1.5, lambda t: FAIRLEAD + 0.4 * CHORD * (
        smooth_step(t, 0.0, 0.3) - smooth_step(t, 0.3, 0.3)))
    chain = chain_at(FAIRLEAD)
    before = np.abs(particle_array(client.particles[-1][1]) - chain.positions).max()
    assert before > 0.01, f'the shake left the rope within {before} m of equilibrium'

    future = client.reset.call_async(Trigger.Request())
    response = client.call(future)
    assert response.success, response.message
    asked = time.monotonic()
    client.clear()
    for _ in range(25):  # 0.2 s is plenty on a quiet machine
        assert client.drive_wall(0.2, lambda t: FAIRLEAD)
        after = [(t, msg) for t, msg in client.particles if t > asked]
        if after:
            break
    assert after, 'no rope/particles after the reset'
    deviation = np.abs(particle_array(after[0][1]) - chain.positions).max()
    assert deviation < 0.003, f'first state after reset is {deviation} m off the catenary'
    assert len(log_lines(node, 'rope restarted on the catenary')) >= 1


def _ringing(client: Client) -> float:
    """Reset, then pull the fairlead 0.3 m out in 0.4 s; std of the tension afterwards [N]."""
    client.drive_wall(0.1, lambda t: FAIRLEAD)  # started, whichever test ran before
    response = client.call(client.reset.call_async(Trigger.Request()))
    assert response.success
    client.clear()
    # the window from the pull's own clock: the first tension after a reset comes late by
    # whatever the restart takes, and a window from it caught less of the ringing
    start = client.drive_wall(
        2.4, lambda t: FAIRLEAD + 0.3 * CHORD * smooth_step(t, 0.5, 0.4))[0].made
    window = [fairlead_tension(w) for t, w in client.fairlead if start + 1.1 < t < start + 2.3]
    assert len(window) > 30
    client.drive_wall(0.3, lambda t: FAIRLEAD + 0.3 * CHORD * (1.0 - smooth_step(t, 0.0, 0.3)))
    return float(np.std(window))


def test_parameters(line_node):
    node, client = line_node
    names = client.call(client.parameters.list_parameters()).result.names
    assert set(SPECS) <= set(names)
    descriptors = {d.name: d for d in client.call(
        client.parameters.describe_parameters(list(SPECS))).descriptors}
    for name, spec in SPECS.items():
        assert descriptors[name].read_only == spec.read_only, name
        assert spec.unit in descriptors[name].description
    # the parameter file reached the node in its namespace: every value is the file's
    values = client.call(client.parameters.get_parameters(list(SPECS))).values
    in_file = read_params_file(PARAMS_FILE)
    for name, value in zip(SPECS, values):
        got = parameter_value_to_python(value)
        assert (list(got) if name in VECTORS else got) == in_file[name], name
    assert descriptors['max_strain'].floating_point_range[0].to_value == 10.0
    assert descriptors['segments'].integer_range[0].from_value == 2
    assert 'polyester' in descriptors['material'].additional_constraints

    def set_(name, value):
        return client.call(client.parameters.set_parameters(
            [Parameter(name, value=value)])).results[0]

    refused = set_('max_strain', -1.0)
    assert not refused.successful and 'max_strain' in refused.reason
    refused = set_('publish_rate', 0.0)  # the range allows 0, the rate must be > 0
    assert not refused.successful and '> 0' in refused.reason, refused.reason
    refused = set_('segments', 40)
    assert not refused.successful and 'read-only' in refused.reason
    refused = set_('material', 'nylon')
    assert not refused.successful

    default_ringing = _ringing(client)
    accepted = set_('axial_damping', 20000)  # an integer for a double: taken as 20000.0
    assert accepted.successful, accepted.reason
    value = client.call(client.parameters.get_parameters(['axial_damping'])).values[0]
    assert value.double_value == 20000.0
    damped_ringing = _ringing(client)
    assert set_('axial_damping', 0.0).successful
    assert damped_ringing < 0.5 * default_ringing, \
        f'tension std after the pull: {default_ringing:.1f} N at the default damping, ' \
        f'{damped_ringing:.1f} N at 20000 N s'


def test_bad_input_is_dropped_and_output_stays_finite(line_node):
    node, client = line_node
    client.drive_wall(0.3, lambda t: FAIRLEAD)
    client.clear()
    now = time.time_ns
    nan, inf = float('nan'), float('inf')
    client.pose([nan, 0.0, 8.0])
    client.spin(0.05)
    client.pose(FAIRLEAD, orientation=(0.0, inf, 0.0, 1.0))
    client.spin(0.05)
    client.pose(FAIRLEAD, orientation=(0.0, 0.0, 0.0, 0.0))
    client.spin(0.05)
    client.pose(FAIRLEAD, stamp_ns=now() - 2_000_000_000)  # older than the last
    client.spin(0.05)
    client.pose([0.0, 0.0, nan], to='bollard')
    client.spin(0.05)
    client.pose(FAIRLEAD, orientation=(0.0, 0.0, 0.0, 2.0))  # not unit: normalised
    client.spin(0.05)
    client.pose(FAIRLEAD + [0.0, 0.0, 6.0])  # a teleport: restart there
    client.spin(0.3)
    client.drive_wall(1.0, lambda t: FAIRLEAD)  # and back (another teleport)
    assert len(client.fairlead) > 40, 'the node stopped publishing'
    assert all_finite(client)
    # back on the catenary at the fairlead (mean over the restart's ringing)
    mean = np.mean([fairlead_tension(w) for _, w in client.fairlead[-40:]])
    assert abs(mean - 993.0) < 100.0, mean
    dropped = log_lines(node, 'dropped a message')
    assert len(dropped) == 5, '\n'.join(dropped)
    assert '(4 dropped on fairlead/pose so far)' in dropped[3]
    assert '(1 dropped on bollard/pose so far)' in dropped[4]
    assert len(log_lines(node, 'normalised a non-unit quaternion')) == 1
    assert len(log_lines(node, 'rope restarted on the catenary there')) >= 2


def test_a_stalled_node_skips_ahead_instead_of_spiralling(line_node):
    node, client = line_node
    client.drive_wall(0.5, lambda t: FAIRLEAD, rate=20.0)
    client.spin(0.8)  # the poses stop: the node warns and goes on with the clock
    assert log_lines(node, 'fairlead/pose: no new pose for 0.5 s: the fairlead coasts to a stop')
    skips = log_lines(node, 's behind the clock: skipped ahead')
    _frozen(node, 1.5, lambda: client.spin(1.5))  # too far behind: skip
    client.clear()
    client.drive_wall(1.0, lambda t: FAIRLEAD, rate=20.0)
    # every skip is logged (each restarts the rope), with a count
    new = log_lines(node, 's behind the clock: skipped ahead')[len(skips):]
    assert len(new) == 1, new
    assert f'(skips so far: {len(skips) + 1})' in new[0], new[0]
    lag = float(new[0].split('simulation fell ')[1].split()[0])
    assert 1.5 < lag < 2.0, new[0]
    # back to real time at once: a whole second of outputs, stamped with the wall clock
    assert len(client.particles) > 35 and all_finite(client)
    assert abs(_stamp_ns(client.particles[-1][1]) * 1e-9 - time.time()) < 0.3


def _frozen(node: NodeProcess, seconds: float, action):
    """
    Stop the node (SIGSTOP) for `seconds` while running action(); return its result.

    Another process sends the SIGCONT: publishing to a stopped node at times blocks this
    process for 1.0 s (Fast DDS; 32 of 100 freezes of 0.3 s, 0 of 220 with this waker),
    and such a block once stretched a freeze of 0.8 s to 3.1 s in CI.
    """
    node.process.send_signal(signal.SIGSTOP)
    waker = subprocess.Popen(['sh', '-c', f'sleep {seconds}; kill -CONT {node.process.pid}'])
    try:
        return action()
    finally:
        waker.wait()
        node.process.send_signal(signal.SIGCONT)


def _stamp_ns(msg: PoseArray) -> int:
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


def offline_simulator(line: LineParams) -> OneLine:
    """Return the Simulator the node runs: its step divides the publish period."""
    return OneLine(line, output_interval=1.0 / line.publish_rate, history=math.inf)


def _first_sample(sent: list, first_output_ns: int, line: LineParams) -> tuple:
    """
    Return (index, time origin) of the pose the node started the rope with.

    DDS may lose the first samples of a fresh connection even after both ends matched. The
    node starts on the first pose it gets, takes its stamp as time 0 and steps from there:
    the first output lies a whole number of steps after that pose.
    """
    dt = offline_simulator(line).time_step
    for index, ns in enumerate(pose.stamp_ns for pose in sent):
        if ns > first_output_ns:
            break
        steps = (first_output_ns - ns) * 1e-9 / dt
        if abs(steps - round(steps)) < 1e-4:
            return index, ns
    raise AssertionError('no published pose lies a whole number of steps before the first '
                         'output: the node did not start on one of them')


def test_moving_fairlead_matches_the_offline_simulator(colcon_install, colcon_env, tmp_path):
    # 0.2 m at 0.5 Hz along the chord after a 2 s ramp, 50 Hz stamped poses, 6 s (two
    # periods after the ramp); the offline Simulator gets the same stamped samples (later:
    # `rope_sim run` on them).
    # In sim time: on the wall clock a stall of this process past LIVE_INPUT (seen in CI)
    # rightly makes the node go on without poses, which the offline run cannot follow.
    def motion(t):
        return FAIRLEAD + 0.2 * math.sin(math.pi * t) * smooth_step(t, 0.0, 2.0) * CHORD

    seconds = 6.0
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'motion.log', '/motion',
                       '-p', 'use_sim_time:=true')
    client = Client('/motion')
    try:
        client.wait_for_node(node)
        client.spin(0.5)  # let discovery settle both ways: the first pose must not be lost
        sent = client.drive(SIM_START, seconds, motion)
        assert node.interrupt() == 0
        client.spin(0.3)  # everything the node published has arrived
    finally:
        client.close()
        node.interrupt()
    # the node publishes particles and both tensions once per tick: the writers' sequence
    # numbers pair them (whatever a loaded machine may have dropped)
    particles = dict(zip(client.particles.sequences, client.particles))
    pairs = [(particles[k], wrench) for k, wrench in zip(
        client.fairlead.sequences, client.fairlead) if k in particles]
    assert len(pairs) > 0.8 * 50 * seconds, f'{len(pairs)} outputs in {seconds} s at 50 Hz'
    # one output every 1 / publish_rate of simulated time (the poses' 50 Hz rate, too)
    periods = np.diff([_stamp_ns(particles) for (_, particles), _ in pairs]) / 20e6
    assert np.allclose(periods, np.round(periods), rtol=0.0, atol=1e-4), periods
    print(f'{len(pairs)} outputs; {np.mean(np.round(periods) == 1):.1%} one period apart')
    assert np.mean(np.round(periods) == 1) > 0.95, np.round(periods)
    first, epoch = _first_sample(sent, _stamp_ns(pairs[0][0][1]), default_line())

    sim = offline_simulator(default_line())
    for pose in sent[first:]:
        sim.push_fairlead((pose.stamp_ns - epoch) * 1e-9, pose.position)
    sim.start((sent[first].stamp_ns - epoch) * 1e-9)
    live, offline = [], []
    for (_, particles), (_, wrench) in pairs:
        t = (_stamp_ns(particles) - epoch) * 1e-9
        sim.advance_to(t + 0.5 * sim.time_step)
        assert abs(sim.time - t) < 1e-6
        live.append(fairlead_tension(wrench))
        offline.append(sim.output().fairlead_tension)
    live, offline = np.array(live), np.array(offline)
    assert first < 25, f'the node missed the first {first} poses'

    nrmse = np.sqrt(np.mean((live - offline) ** 2)) / np.std(offline)
    print(f'node vs offline fairlead tension: NRMSE {nrmse:.2e} over {len(live)} outputs, '
          f'tension std {np.std(offline):.0f} N; the node started on pose {first}')
    assert np.std(offline) > 50.0, 'the motion hardly changed the tension'
    differ = np.flatnonzero(np.abs(live - offline) > 1e-6 * np.abs(offline))
    assert nrmse < 0.02, (
        f'NRMSE {nrmse:.4f} between node and offline tension series; they differ from output '
        f'{differ[0]} of {len(live)} on ({live[differ[0]]:.1f} N vs {offline[differ[0]]:.1f} N)')
    assert '[WARN]' not in node.text() and '[ERROR]' not in node.text(), node.text()


def test_best_effort_poses_need_pose_reliability_best_effort(
        colcon_install, colcon_env, tmp_path):
    # A best-effort publisher (REP-2003 sensor data) cannot reach a reliable subscription:
    # the default node says so and what to set; a best_effort node takes its poses.
    reliable = NodeProcess(colcon_install, colcon_env, tmp_path / 'reliable.log', '/qos_r')
    best = NodeProcess(colcon_install, colcon_env, tmp_path / 'best.log', '/qos_b',
                       '-p', 'pose_reliability:=best_effort')
    client = Client('/qos_b', sim_time=False)
    qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
    publishers = [client.node.create_publisher(PoseStamped, f'/{ns}/fairlead/pose', qos)
                  for ns in ('qos_r', 'qos_b')]
    try:
        client.wait_for_node(best)
        client.wait_for(lambda: publishers[1].get_subscription_count() > 0
                        and log_lines(reliable, 'waiting for the first pose'), 30.0,
                        'both nodes')
        client.spin(0.5)
        with no_gc_pauses():
            for _ in range(75):
                for publisher in publishers:
                    client.pose(FAIRLEAD, to=publisher)
                client.spin(0.02)
        # the graph check runs once a second, after discovery has shown the publisher
        start = time.monotonic()
        client.wait_for(lambda: log_lines(reliable, 'a best-effort publisher cannot'), 10.0,
                        'the QoS warning of the reliable node')
        print(f'QoS warning after {time.monotonic() - start:.2f} s more')
    finally:
        client.close()
        best.interrupt()
        reliable.interrupt()
    assert len(client.fairlead) > 40, best.text()
    mean = np.mean([fairlead_tension(w) for _, w in client.fairlead[-20:]])
    assert abs(mean - 993.0) < 10.0, mean
    assert 'first fairlead pose' not in reliable.text(), reliable.text()
    warning = log_lines(reliable, '/qos_r/fairlead/pose: a best-effort publisher cannot')
    assert warning, reliable.text()  # once per 5 s while it lasts
    assert warning[0].endswith('set pose_reliability:=best_effort'), warning[0]
    assert 'bollard/pose' not in reliable.text()  # no publisher there


def test_sigint_ends_the_node_cleanly(line_node):
    # an integer for a double parameter (length) is accepted, as the offline runner does:
    # the module's node was started with length:=40. The last test of that node.
    node, client = line_node
    client.clear()
    try:
        # a live node, not just a started one (a loaded machine may take a while to answer)
        for _ in range(30):
            client.drive_wall(0.3, lambda t: FAIRLEAD)
            if client.fairlead:
                break
        assert client.fairlead
    finally:
        code = node.interrupt()
    assert code == 0, node.text()
    assert 'Traceback' not in node.text(), node.text()
    assert '40 m, 20 segments' in node.text()


@pytest.mark.parametrize('value', ['segments:=1', 'material:=kevlar', 'max_strain:=0.0'])
def test_bad_start_value_exits_with_code_2(colcon_install, colcon_env, tmp_path, value):
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'bad.log', '/bad', '-p', value)
    try:
        code = node.process.wait(START_TIMEOUT)
    except subprocess.TimeoutExpired:
        node.interrupt()
        raise AssertionError(f'node started with {value}:\n{node.text()}')
    text = node.text()
    assert code == 2, text
    assert 'Traceback' not in text, text
    errors = [line for line in text.splitlines() if '[ERROR]' in line]
    name = value.split(':=')[0]
    assert len(errors) == 1 and f"parameter '{name}'" in errors[0] and 'must be' in errors[0], \
        text


def test_use_sim_time_follows_the_clock_topic(colcon_install, colcon_env, tmp_path):
    # /clock runs at twice the wall clock from 1000 s; poses are stamped in sim time
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'sim.log', '/simtime',
                       '-p', 'use_sim_time:=true')
    client = Client('/simtime')
    try:
        client.wait_for_node(node)
        wall = time.monotonic()
        while time.monotonic() - wall < 2.0:
            now_ns = SIM_START + int(2e9 * (time.monotonic() - wall))
            client.clock(now_ns)
            client.pose(FAIRLEAD, stamp_ns=now_ns)
            client.spin(0.01)
    finally:
        client.close()
        node.interrupt()
    stamps = [_stamp_ns(msg) * 1e-9 for _, msg in client.particles]
    assert len(stamps) > 50, node.text()
    assert 1000.0 <= stamps[0] and 1003.0 < stamps[-1] <= 1004.1, (stamps[0], stamps[-1])
    assert all(b > a for a, b in zip(stamps, stamps[1:]))
