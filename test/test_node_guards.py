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
Every input the mooring_line node can receive leaves it in a physical state.

Over real DDS, from the colcon install: pose stamps far from the clock, jumps of either end,
publish_rate changed at run time, bursts of poses, Ctrl-C during start-up, QoS overrides.
Time is sim time driven by the test (/clock) wherever it matters; the inputs are not the
ones the other node tests use (another fairlead, another teleport_distance, other rates).
"""

import math
import os
from pathlib import Path
import signal
import subprocess
from types import SimpleNamespace

from geometry_msgs.msg import PoseStamped
from node_harness import Client, no_gc_pauses, node_summary, NodeProcess
import numpy as np
from one_line import OneLine
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rope_sim_ros.model.statics import catenary
from rope_sim_ros.params.files import load_params
from rope_sim_ros.params.table import LineParams
from rope_sim_ros.ros import executables

START = 5000 * 1_000_000_000  # [ns] sim time of the first pose
FAIRLEAD = np.array([32.0, 12.0, 6.0])
CHORD = FAIRLEAD / np.linalg.norm(FAIRLEAD)
PARAMS_FILE = Path(__file__).resolve().parent.parent / 'config' / 'mooring_line.yaml'
SECOND = 1_000_000_000


def default_line(**values) -> LineParams:
    return load_params(PARAMS_FILE).with_values(values)


def log_lines(node: NodeProcess, word: str) -> list:
    return [line for line in node.text().splitlines() if word in line]


def equilibrium(bollard, fairlead) -> tuple:
    """Return (bollard, fairlead) tension [N] of the default line at rest between the ends."""
    sim = OneLine(default_line())
    p, air = sim.props, sim.environment
    chain = catenary.chain_equilibrium(bollard, fairlead, p.length, p.segments,
                                       p.weight_per_length(air), p.axial_stiffness, air.gravity)
    return float(np.linalg.norm(chain.force_a)), float(np.linalg.norm(chain.force_b))


def smooth_step(t: float, start: float, duration: float) -> float:
    """0 before start, 1 after start + duration, a half cosine in between."""
    s = min(max((t - start) / duration, 0.0), 1.0)
    return 0.5 * (1.0 - math.cos(math.pi * s))


@pytest.fixture
def sim_node(colcon_install, colcon_env, tmp_path):
    """Start a node with use_sim_time and extra --ros-args; yield (node, client); stop both."""
    started = []

    def start(namespace: str, *ros_args: str, **client_options):
        node = NodeProcess(colcon_install, colcon_env, tmp_path / f'{namespace[1:]}.log',
                           namespace, '-p', 'use_sim_time:=true', *ros_args)
        client = Client(namespace, **client_options)
        started.append((node, client))
        client.wait_for_node(node)
        # The node's clock: /clock for 0.5 s before START. Meanwhile the node's side of
        # discovery settles too (a pose sent at once after wait_for_node may be lost).
        client.drive(START - 500_000_000, 0.5, fairlead=None)
        return node, client

    yield start
    for node, client in started:
        client.close()
        node.interrupt()


# ------------------------------------------------------------------------ stamps


def test_poses_stamped_far_from_the_clock_are_dropped_and_the_stream_goes_on(sim_node):
    # A surge at 50 Hz for 5 s of sim time. Before the very first pose, and before the
    # samples at 1 s, 2 s and 3 s, a stray pose stamped 1 h ahead, 1 h ahead, 15 s ahead and
    # 1 h behind the clock (each froze the fairlead for that long, or held the outputs back).
    node, client = sim_node('/stamps')

    def motion(t):
        return FAIRLEAD + 0.3 * math.sin(2.0 * math.pi * 0.4 * t) * smooth_step(t, 0.0, 1.0) \
            * CHORD

    stray = {0.0: 3600.0, 1.0: 3600.0, 2.0: 15.0, 3.0: -3600.0}

    def send_stray(t):
        offset = stray.get(round(t, 6))
        if offset is not None:
            client.pose(motion(t) + [0.0, 0.0, 2.0], START + round((t + offset) * 1e9))

    client.drive(START, 5.0, motion, at=send_stray)
    # the rope stays one sample behind the stream: outputs every 20 ms from 0 to 4.98 s
    client.wait_for(lambda: len(client.outputs()) >= 250, 30.0, '250 outputs')
    assert node.interrupt() == 0
    outputs = client.outputs()
    stamps = np.array([ns for ns, _, _ in outputs])
    assert np.array_equal(stamps, START + 20_000_000 * np.arange(250)), \
        (stamps[:3], np.diff(stamps).max())
    assert node_summary(node, 'fairlead/pose') == (255, 4, 0)
    ahead = log_lines(node, 'stamp ahead of the node clock by 3600.000 s, more than 1 s')
    # sent between the /clock of 2.98 s and that of 3 s: the node may have either
    behind = log_lines(node, 'stamp behind the node clock by 3')
    assert len(ahead) == 1 and '(1 dropped on fairlead/pose so far)' in ahead[0], node.text()
    assert len(behind) == 1 and '(4 dropped on fairlead/pose so far)' in behind[0]
    assert float(behind[0].split(' by ')[1].split()[0]) in (3599.98, 3600.0), behind[0]
    assert 'more than 10 s' in behind[0]
    assert 'first fairlead pose: rope started on the catenary to (32.00, 12.00, 6.00)' \
        in node.text()

    # the node is the offline simulator fed with the good poses alone
    line = default_line()
    sim = OneLine(line, output_interval=1.0 / line.publish_rate, history=math.inf)
    for k in range(251):
        sim.push_fairlead(k / 50.0, motion(k / 50.0))
    sim.start(0.0)
    errors = []
    for ns, live, _ in outputs:
        sim.advance_to((ns - START) * 1e-9 + 0.5 * sim.time_step)
        errors.append(abs(live - sim.output().fairlead_tension))
    print(f'largest difference to the offline run: {max(errors):.2e} N')
    assert max(errors) < 0.01, max(errors)


# ------------------------------------------------------------------------ jumps


def test_a_jump_of_either_end_restarts_the_rope_at_the_new_place(sim_node):
    # teleport_distance 3 m. The first bollard pose lands 3.64 m from bollard_position, the
    # bollard drifts 1 m smoothly (followed), jumps 4 m up and back; then the fairlead
    # jumps 3.5 m. Each jump restarts the rope at rest, logged with the end and distance.
    node, client = sim_node('/jumps', '-p', 'teleport_distance:=3.0')
    b1 = np.array([1.0, -3.5, 0.0])
    b2 = b1 + [0.0, 1.0, 0.0]
    up = b2 + [0.0, 0.0, 4.0]
    f2 = FAIRLEAD + [-3.5, 0.0, 0.0]

    def bollard(t):
        if t < 1.0:
            return np.zeros(3)  # = bollard_position: no jump
        if 3.0 <= t < 4.5:
            return up
        return b1 + [0.0, smooth_step(t, 2.0, 1.0), 0.0]

    client.drive(START, 7.0, lambda t: FAIRLEAD if t < 6.0 else f2,
                 bollard=lambda t: bollard(t) if t >= 1.0 else None)
    client.wait_for(lambda: len(client.outputs()) >= 350, 30.0, '350 outputs')
    assert node.interrupt() == 0
    jumps = log_lines(node, ' jumped ')
    assert [line.split(']: ')[1] for line in jumps] == [
        'bollard jumped 3.64 m, more than teleport_distance (3 m), to (1.00, -3.50, 0.00): '
        'rope restarted on the catenary there',
        'bollard jumped 4.00 m, more than teleport_distance (3 m), to (1.00, -2.50, 4.00): '
        'rope restarted on the catenary there',
        'bollard jumped 4.00 m, more than teleport_distance (3 m), to (1.00, -2.50, 0.00): '
        'rope restarted on the catenary there',
        'fairlead jumped 3.50 m, more than teleport_distance (3 m), to (28.50, 12.00, 6.00): '
        'rope restarted on the catenary there',
    ], node.text()
    assert '[ERROR]' not in node.text() and 'skipped ahead' not in node.text()

    outputs = np.array([((ns - START) * 1e-9, f, b) for ns, f, b in client.outputs()])
    t, fairlead, bollard_tension = outputs.T
    for (start, end), ends in {(1.5, 2.0): (b1, FAIRLEAD), (3.5, 4.5): (up, FAIRLEAD),
                               (5.0, 6.0): (b2, FAIRLEAD), (6.5, 7.0): (b2, f2)}.items():
        window = (t > start) & (t < end)
        expected = equilibrium(*ends)
        got = (np.mean(bollard_tension[window]), np.mean(fairlead[window]))
        print(f'{start}-{end} s: tension {got[0]:.1f} / {got[1]:.1f} N, at rest '
              f'{expected[0]:.1f} / {expected[1]:.1f} N')
        assert got == pytest.approx(expected, rel=0.01), (start, got, expected)
    # the jumps cost no spike: the largest tension is that of the highest bollard, at rest
    assert max(fairlead.max(), bollard_tension.max()) < 1.5 * max(equilibrium(up, FAIRLEAD))


def test_the_bollard_has_the_fairleads_jump_guard_in_the_simulator():
    line = default_line(teleport_distance=2.0)
    sim = OneLine(line, output_interval=0.02, history=math.inf)
    sim.push_fairlead(0.0, FAIRLEAD)
    assert sim.push_bollard(0.0, [0.0, 0.0, 0.0]) == ''  # not started: nothing to restart
    sim.start(0.0)
    sim.advance_to(0.5)
    assert sim.push_bollard(0.5, [0.0, 1.5, 0.0]) == '' and sim.last_jump == 1.5
    sim.advance_to(1.0)
    moved = sim.output()
    assert moved.positions[0][1] == pytest.approx(1.5)  # followed, not restarted
    assert sim.push_bollard(1.0, [0.0, 1.5, -2.5]) == 'teleport'
    assert sim.last_jump == pytest.approx(2.5)
    out = sim.output()
    assert out.t == 1.0 and np.allclose(out.positions[0], [0.0, 1.5, -2.5])
    assert out.bollard_tension == pytest.approx(
        equilibrium([0.0, 1.5, -2.5], FAIRLEAD)[0], rel=1e-3)
    # the samples before the jump are gone: the bollard holds at the new place
    sim.advance_to(1.5)
    assert np.allclose(sim.output().positions[0], [0.0, 1.5, -2.5])
    assert sim.push_fairlead(1.6, FAIRLEAD + [0.0, 0.0, 2.01]) == 'teleport'
    assert sim.last_jump == pytest.approx(2.01)

    # a first bollard sample after the start jumps from bollard_position
    fresh = OneLine(default_line(teleport_distance=2.0, bollard_position=[1.0, 1.0, 0.0]))
    fresh.push_fairlead(0.0, FAIRLEAD)
    fresh.start(0.0)
    assert fresh.push_bollard(0.1, [1.0, 3.5, 0.0]) == 'teleport'
    assert fresh.last_jump == pytest.approx(2.5) and fresh.time == 0.0
    assert np.allclose(fresh.output().positions[0], [1.0, 3.5, 0.0])


# ------------------------------------------------------------------------ publish_rate


def test_publish_rate_changes_take_effect_with_the_next_output(sim_node):
    # 50 Hz poses, the fairlead still. publish_rate 50 -> 137 Hz at run time, over DDS: 137
    # Hz divides neither the pose period nor the 5 ms step. (test_pacing.py plays 50 -> 30
    # -> 1000 -> 137 Hz, the tick rate's limit with them, on a simulated clock.)
    node, client = sim_node('/rate')
    stay = (lambda t: FAIRLEAD)

    def caught_up(ns: int, rate: float):
        period = 1.0 / rate
        # the rope stays one pose (20 ms) behind: wait for its outputs up to there, so that
        # the next change lands at a known output
        due = ns - 20_000_000 - 0.5 * period * 1e9

        ahead = [40_000_000]

        def arrived():
            # Outputs that one pose lets through together go out each the same time after
            # its stamp: the node's ticks publish them, on the sim clock, which must run for
            # them once the last pose is taken. The clock then creeps on by 1 ms a look (to
            # 140 ms at most; the stream counts as silent after 0.5 s): a tick that ran
            # before the last pose was taken leaves its outputs to the next.
            outputs = client.outputs()
            if outputs and outputs[-1][0] > due - max(2 * period, 0.04) * 1e9:
                client.clock(ns + ahead[0])
                ahead[0] = min(ahead[0] + 1_000_000, 140_000_000)
            return outputs and outputs[-1][0] > due

        try:
            client.wait_for(arrived, 30.0, f'the outputs up to {(due - START) * 1e-9:.4f} s')
        except AssertionError as e:
            last = (client.outputs() or [(0,)])[-1][0]
            raise AssertionError(f'{e}; the last is at {(last - START) * 1e-9:.4f} s, '
                                 f'{len(client.outputs())} outputs') from None

    client.drive(START, 1.0, stay)
    caught_up(START + SECOND, 50.0)
    result = client.set_parameter('publish_rate', 137.0)
    assert result.successful, result.reason
    client.drive(START + SECOND + 20_000_000, 0.98, stay)
    caught_up(START + 2 * SECOND, 137.0)
    assert node.interrupt() == 0
    assert '[WARN]' not in node.text() and '[ERROR]' not in node.text(), node.text()
    outputs = client.outputs()
    stamps = np.array([ns for ns, _, _ in outputs])
    periods = np.diff(stamps) * 1e-9
    # runs of equal periods, in order: every output 1 / rate after the one before it, the
    # rate of the time it was published at (no gap, no burst at the change)
    runs = []
    for period in periods:
        if runs and abs(period - runs[-1][0]) < 5e-9:
            runs[-1][1] += 1
        else:
            runs.append([period, 1])
    print('periods [ms] x count:', [(round(p * 1e3, 4), n) for p, n in runs])
    assert [round(1.0 / p, 3) for p, _ in runs] == [50.0, 137.0], runs
    # from 0 to 0.98 s, to 1.98 s
    assert [n for _, n in runs] == [49, 137], runs
    # the step changed under a rope at rest: nothing moved
    expected = equilibrium([0.0, 0.0, 0.0], FAIRLEAD)[1]
    tensions = np.array([f for _, f, _ in outputs])
    assert np.abs(tensions - expected).max() < 0.01 * expected, \
        (tensions.min(), tensions.max(), expected)


# ------------------------------------------------------------------------ losses


def test_a_burst_of_poses_is_taken_whole_and_losses_on_the_way_are_counted(sim_node):
    # 10,000 fairlead poses from a publisher that keeps them all (depth 10000), then 10,000
    # bollard poses from one that keeps 10 (KEEP_LAST): at this rate it overwrites poses
    # DDS has not sent yet. Stamps 50 us apart within 0.5 s of the clock, which stands
    # still (sim time: a busy machine cannot age them). Before: the node took 747 of such a
    # burst, silently.
    node, client = sim_node('/burst', pose_depth=10000, bollard_depth=10)
    with no_gc_pauses():
        for k in range(10000):
            client.pose(FAIRLEAD, START + k * 50_000)
        for k in range(10000):
            client.pose([0.0, 0.0, 0.0], START + k * 50_000, 'bollard')
    # Then each end jumps 6 m and back, which the node logs. A writer's poses come in order,
    # so the second jump is logged after every pose before it was taken or counted lost
    # (DDS tells of the losses at the end of a burst only with the writer's next message).
    for end, position in {'fairlead': FAIRLEAD, 'bollard': np.zeros(3)}.items():
        client.pose(position + [0.0, 6.0, 0.0], START + 600_000_000, end)
        client.pose(position, START + 700_000_000, end)
    client.wait_for(lambda: len(log_lines(node, 'fairlead jumped 6.00 m')) == 2
                    and len(log_lines(node, 'bollard jumped 6.00 m')) == 2, 60.0,
                    'the node to take both bursts')
    assert node.interrupt() == 0
    assert node_summary(node, 'fairlead/pose') == (10002, 0, 0)
    received, dropped, lost = node_summary(node, 'bollard/pose')
    print(f'deep publisher: 10002 of 10002 taken; shallow publisher: {received} taken, '
          f'{lost} lost on the way, of 10002')
    assert dropped == 0 and lost > 0 and received + lost == 10002, (received, dropped, lost)
    warning = log_lines(node, 'bollard/pose: ')
    assert any('pose(s) lost on the way' in line for line in warning), node.text()
    assert '[ERROR]' not in node.text() and 'fairlead/pose: no new pose' not in node.text()


# ------------------------------------------------------------------------ Ctrl-C
# (Ctrl-C during start-up of the installed executables: test_startup_interrupt.py)


def test_a_ctrl_c_lost_in_a_destructor_is_sent_again(monkeypatch):
    # Python cannot raise KeyboardInterrupt out of a destructor (it prints it and goes on);
    # the entry points send the signal again, once out of it, unless main() is over.
    sent = []
    monkeypatch.setattr(executables.os, 'kill', lambda pid, signum: sent.append((pid, signum)))
    interrupted = executables._Interrupted()
    lost = SimpleNamespace(exc_type=KeyboardInterrupt)
    interrupted.unraisable(lost)
    interrupted.redelivery.join(5.0)
    assert sent == [(os.getpid(), signal.SIGINT)]
    interrupted.done = True
    interrupted.redelivery = None
    interrupted.unraisable(lost)
    assert interrupted.redelivery is None and len(sent) == 1
    interrupted(signal.SIGINT, None)  # after main(): nothing to interrupt, no exception
    assert interrupted.seen


def test_a_half_built_objects_destructor_is_quiet_only_after_a_ctrl_c(monkeypatch):
    # A Ctrl-C between two assignments of a constructor leaves an object whose destructor
    # reads a missing attribute (rclpy's Future.__del__): that follows from the Ctrl-C. The
    # same error without a Ctrl-C is a bug and goes to Python's own hook.
    reported = []
    monkeypatch.setattr(executables.sys, '__unraisablehook__', reported.append)
    interrupted = executables._Interrupted()
    half_built = SimpleNamespace(exc_type=AttributeError)
    interrupted.unraisable(half_built)
    assert reported == [half_built]
    with pytest.raises(KeyboardInterrupt):
        interrupted(signal.SIGINT, None)  # the Ctrl-C, while main() runs
    interrupted.unraisable(half_built)
    assert reported == [half_built] and interrupted.redelivery is None


def test_a_ctrl_c_as_the_handler_is_installed_exits_130(monkeypatch):
    # The Ctrl-C lands just as signal.signal returns: the new handler runs at once and raises
    # there (seen in CI at 0.02 s). That must still end as a Ctrl-C, 130 and no traceback.
    installed = []

    def install_and_fire(signum, handler):
        installed.append(handler)
        if callable(handler):
            handler(signum, None)

    monkeypatch.setattr(executables.signal, 'signal', install_and_fire)
    monkeypatch.setattr(executables.sys, 'unraisablehook', executables.sys.unraisablehook)
    assert executables._run('no_module_reached') == executables.EXIT_INTERRUPTED
    assert installed[-1] == executables.signal.SIG_IGN  # and SIGINT is left ignored


def test_a_ctrl_c_an_import_swallowed_still_ends_the_start(monkeypatch):
    # A bare except in some import takes the KeyboardInterrupt: the Ctrl-C was seen all the
    # same, so main() must not run (before, the node started and ran on, deaf to it).
    handlers = []
    started = []

    def install(signum, handler):
        handlers.append(handler)

    def import_swallowing_ctrl_c(name):
        try:
            handlers[-1](signal.SIGINT, None)
        except:  # noqa: E722 (as third-party code does)
            pass
        return SimpleNamespace(main=lambda: started.append(name) or 0)

    monkeypatch.setattr(executables.signal, 'signal', install)
    monkeypatch.setattr(executables.importlib, 'import_module', import_swallowing_ctrl_c)
    monkeypatch.setattr(executables.sys, 'unraisablehook', executables.sys.unraisablehook)
    assert executables._run('ros.node', 'main_line') == executables.EXIT_INTERRUPTED
    assert started == [] and handlers[-1] == executables.signal.SIG_IGN

# ------------------------------------------------------------------------ QoS


def test_qos_overrides_set_the_pose_subscriptions(sim_node):
    # The standard qos_overrides parameters override pose_reliability and the depth; a
    # name that is not a pose subscription's is warned about, not silently ignored.
    node, client = sim_node(
        '/qos',
        '-p', 'qos_overrides./qos/fairlead/pose.subscription.reliability:=best_effort',
        '-p', 'qos_overrides./qos/bollard/pose.subscription.depth:=7',
        '-p', 'qos_overrides.fairlead/pose.subscription.reliability:=best_effort')
    names = [f'qos_overrides./qos/{end}/pose.subscription.{policy}'
             for end in ('fairlead', 'bollard') for policy in ('reliability', 'history', 'depth')]
    future = client.parameters.get_parameters(names)
    client.wait_for(future.done, 10.0, 'the qos_overrides parameters')
    values = [v.string_value or v.integer_value for v in future.result().values]
    assert values == ['best_effort', 'keep_last', 10000, 'reliable', 'keep_last', 7], values
    for end, reliability in (('fairlead', ReliabilityPolicy.BEST_EFFORT),
                             ('bollard', ReliabilityPolicy.RELIABLE)):
        infos = [i for i in client.node.get_subscriptions_info_by_topic(f'/qos/{end}/pose')
                 if i.node_name == 'mooring_line']
        assert [i.qos_profile.reliability for i in infos] == [reliability], infos
    warning = log_lines(node, "ignoring unknown parameter 'qos_overrides.fairlead/pose.")
    assert warning and 'qos_overrides./qos/fairlead/pose.subscription.reliability' \
        in warning[0], node.text()

    # a best-effort publisher reaches the fairlead subscription now
    best_effort = client.node.create_publisher(
        PoseStamped, 'fairlead/pose',
        QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT))
    client.wait_for(lambda: best_effort.get_subscription_count() > 0, 10.0, 'the node')
    for k in range(50):
        client.clock(START + k * 20_000_000)
        client.pose(FAIRLEAD, START + k * 20_000_000, best_effort)
        client.spin_once(0.02)
    client.wait_for(lambda: len(client.outputs()) > 20, 10.0, 'outputs')
    assert node.interrupt() == 0
    assert 'cannot reach this reliable subscription' not in node.text()


def test_a_bad_qos_override_is_one_error_line(colcon_install, colcon_env, tmp_path):
    node = NodeProcess(colcon_install, colcon_env, tmp_path / 'badqos.log', '/badqos', '-p',
                       'qos_overrides./badqos/bollard/pose.subscription.reliability:=fast')
    try:
        code = node.process.wait(60.0)
    except subprocess.TimeoutExpired:
        node.interrupt()
        raise AssertionError(f'node started:\n{node.text()}')
    errors = log_lines(node, '[ERROR]')
    assert code == 2 and 'Traceback' not in node.text(), node.text()
    assert len(errors) == 1 and 'qos_overrides of /badqos/bollard/pose' in errors[0] \
        and '`fast`' in errors[0] and 'reliable or best_effort' in errors[0], errors
