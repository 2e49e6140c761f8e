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
Line handling through the installed nodes: the services, their events, the bag and resim.

One recording mooring node (three lines, two named bollards, sim time driven by the test)
is given a berthing's commands over real service calls: the stowed `spring` made fast to
bollard b1 beside `head`, `head` let go, given bollard b2 by a parameter and made fast
there, `stern` let go by its quick-release hook as the ship surges ahead, then let go all.
Each answer, event and log line is checked, each bollard's load against the sum of the
forces of the lines fast on it, and `rope_sim resim` of the bag against the node's outputs.
The poses come at half the output rate, so that the node holds outputs it has reached for
their time (mooring/pacing.py) and takes some commands ahead of them, as a live node does.
"""

import json
import math
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PoseStamped, WrenchStamped
from node_harness import bag_events, spin_until
import numpy as np
import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.signals import SignalHandlerOptions
from rope_sim_ros.bag import read_messages
from rope_sim_ros.bag.cdr import decode_pose_array, decode_wrench, decode_wrench_stamped
from rope_sim_ros.mooring.status import COLOURS
from rope_sim_ros.offline import cli
from rope_sim_ros.ros.mooring_display import FREE_COLOUR
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String
from std_srvs.srv import Trigger
from test_node_mooring import colour, MooringProcess, stamp_ns, statuses
from test_node_resim import compare, record, ship, START
from visualization_msgs.msg import Marker, MarkerArray
import yaml

SIM_START = 2000 * 1_000_000_000  # [ns]
OUTPUT_RATE = 50.0  # [Hz] publish_rate
POSE_RATE = 25.0  # poses and /clock per second of sim time: half the output rate
SURGE = 0.6  # [m] the ship moves this far ahead ...
RAMP = (1.6, 3.6)  # [s] from and to
# [s] the ends of the drives, a command or two after each: the diagnostics report each
# second of the node clock, at whole seconds (1 s: the lines as they started; 5 s: let go)
ENDS = (1.2, 1.4, 2.0, 4.0, 5.2)
NAMES = ['head', 'spring', 'stern']
LINE = dict(material='polyester', diameter=0.064, segments=10)
RELEASE_LOAD = 2.0e5  # [N] stern's hook: its tension passes it in the ramp (27 kN at rest)
SAFE_WORKING_LOAD = 1.0e5  # [N] of b2, which stern alone loads past it before its release
VALUES = {
    'lines': NAMES, 'publish_rate': OUTPUT_RATE, 'marker_rate': 10.0,
    'bollards': ['b1', 'b2'],
    'b1': {'position': [-50.0, 4.0, 0.0]},
    'b2': {'position': [-50.0, -8.0, 0.0], 'safe_working_load': SAFE_WORKING_LOAD},
    'head': dict(LINE, fairlead_offset=[-10.0, 0.0, 6.0], bollard='b1', length=42.0),
    'spring': dict(LINE, fairlead_offset=[-10.0, 5.0, 6.0], bollard='b1', length=41.0,
                   start_state='stowed'),
    'stern': dict(LINE, fairlead_offset=[-10.0, -5.0, 6.0], bollard='b2', length=40.5,
                  release_load=RELEASE_LOAD),
}
SERVICES = ['spring/make_fast', 'spring/let_go', 'head/let_go', 'head/make_fast',
            'stern/stow', 'mooring/let_go_all']


def smooth_step(t: float, start: float, end: float) -> float:
    """0 before start, 1 after end, a half cosine in between."""
    s = min(max((t - start) / (end - start), 0.0), 1.0)
    return 0.5 * (1.0 - math.cos(math.pi * s))


class Client:
    """A test node: /clock and ship poses in; services, events, loads and displays kept."""

    def __init__(self):
        self.context = rclpy.Context()
        rclpy.init(context=self.context, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node('handling_test', context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.ship_pub = self.node.create_publisher(PoseStamped, 'ship/pose', 1000)
        self.clock_pub = self.node.create_publisher(Clock, '/clock', 10)
        self.events, self.loads, self.markers, self.diagnostics = [], [], [], []
        self.subscriptions = [
            self.node.create_subscription(
                String, 'mooring/events', lambda m: self.events.append(json.loads(m.data)),
                100),
            self.node.create_subscription(WrenchStamped, 'b1/load', self.loads.append, 1000),
            self.node.create_subscription(MarkerArray, 'mooring/markers',
                                          self.markers.append, 100),
            self.node.create_subscription(DiagnosticArray, '/diagnostics',
                                          self.diagnostics.append, 100),
        ]
        self.services = {name: self.node.create_client(Trigger, name) for name in SERVICES}
        self.parameters = AsyncParameterClient(self.node, 'mooring')

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)

    def wait_for(self, condition, timeout: float, what: str) -> None:
        spin_until(self.executor, condition, timeout, what)

    def wait_for_node(self, node: MooringProcess, timeout: float = 90.0) -> None:
        def ready():
            if node.process.poll() is not None:
                raise AssertionError(f'mooring exited with {node.process.returncode}:\n'
                                     f'{node.text()}')
            return (self.parameters.services_are_ready()
                    and all(c.service_is_ready() for c in self.services.values())
                    and self.ship_pub.get_subscription_count() > 0
                    and self.clock_pub.get_subscription_count() > 0
                    and all(s.get_publisher_count() > 0 for s in self.subscriptions))
        self.wait_for(ready, timeout, 'the mooring node')

    def drive(self, start: float, end: float) -> None:
        """Publish /clock and the ship's pose from sim time start to before end, at POSE_RATE."""
        wall = time.monotonic()
        first = round(start * POSE_RATE)
        for k in range(first, round(end * POSE_RATE)):
            t = k / POSE_RATE
            while time.monotonic() - wall < t - start:
                self.executor.spin_once(timeout_sec=0.002)
            sec, nanosec = divmod(SIM_START + round(t * 1e9), 1_000_000_000)
            clock = Clock()
            clock.clock.sec, clock.clock.nanosec = sec, nanosec
            self.clock_pub.publish(clock)
            msg = PoseStamped()
            msg.header.frame_id = 'world'
            msg.header.stamp.sec, msg.header.stamp.nanosec = sec, nanosec
            msg.pose.position.x = SURGE * smooth_step(t, *RAMP)
            msg.pose.orientation.w = 1.0
            self.ship_pub.publish(msg)
        # The last pose lets the ropes reach its second-newest sample's time, and the first
        # output of the two it lets through goes out at once (mooring/pacing.py): an output
        # that recent says the node took every pose, so a command now is taken there.
        last = (round(end * POSE_RATE) - 1) / POSE_RATE
        reached = SIM_START + round((last - 1.0 / POSE_RATE - 1.0 / OUTPUT_RATE) * 1e9)
        self.wait_for(lambda: self.loads and stamp_ns(self.loads[-1]) >= reached, 10.0,
                      f'the output of {reached} ns')

    def call(self, service: str) -> Trigger.Response:
        future = self.services[service].call_async(Trigger.Request())
        self.wait_for(future.done, 10.0, service)
        return future.result()

    def set_parameter(self, name: str, value):
        future = self.parameters.set_parameters([Parameter(name, value=value)])
        self.wait_for(future.done, 10.0, f'setting {name}')
        return future.result().results[0]


def recorded_outputs(bag) -> dict:
    """Return {topic: [(stamp [ns], force + torque)]} of each line's tensions, loads in a bag."""
    wrenches = [f'/{name}/{end}/tension' for name in NAMES for end in ('fairlead', 'bollard')]
    loads = ['/b1/load', '/b2/load']
    rows = {topic: [] for topic in ['/head/rope/particles', *wrenches, *loads]}
    stamp = None
    for m in read_messages(bag, list(rows)):
        if m.topic == '/head/rope/particles':
            sec, nanosec = decode_pose_array(m.data)[:2]
            stamp = sec * 1_000_000_000 + nanosec
            rows[m.topic].append((stamp, None))
        elif m.topic in loads:
            sec, nanosec, frame, force, torque = decode_wrench_stamped(m.data)
            assert frame == 'world' and sec * 1_000_000_000 + nanosec == stamp
            rows[m.topic].append((stamp, np.concatenate([force, torque])))
        else:
            rows[m.topic].append((stamp, np.concatenate(decode_wrench(m.data))))
    return rows


# ------------------------------------------------------------------------------ fixtures


@pytest.fixture(scope='module')
def berthing(colcon_install, colcon_env, tmp_path_factory):
    """Run the commands through the recording node; return what it answered and did."""
    folder = tmp_path_factory.mktemp('handling')
    bag = folder / 'bag'
    params_file = folder / 'handling.yaml'
    params_file.write_text(yaml.safe_dump({'mooring': {'ros__parameters': dict(
        VALUES, record_path=str(bag))}}))
    node = MooringProcess(colcon_install, colcon_env, folder / 'mooring.log', params_file,
                          '-p', 'use_sim_time:=true')
    client = Client()
    answers, markers_stowed = {}, None
    try:
        client.wait_for_node(node)
        client.drive(0.0, ENDS[0])  # past the first diagnostics report, at 1 s
        markers_stowed = client.markers[-1]
        for key, service in (('let go stowed', 'spring/let_go'),
                             ('make fast stowed', 'spring/make_fast'),
                             ('make fast fast', 'spring/make_fast')):
            answers[key] = client.call(service)
        client.drive(ENDS[0], ENDS[1])
        answers['let go head'] = client.call('head/let_go')
        answers['set head'] = client.set_parameter('head.bollard', 'b2')
        answers['set spring'] = client.set_parameter('spring.bollard', 'b2')
        client.drive(ENDS[1], ENDS[2])
        answers['make fast head'] = client.call('head/make_fast')
        answers['stow fast'] = client.call('stern/stow')
        client.drive(ENDS[2], ENDS[3])
        answers['let go all'] = client.call('mooring/let_go_all')
        client.drive(ENDS[3], ENDS[4])
    finally:
        client.close()
        code = node.interrupt()  # the bag closed
    assert code == 0, node.text()
    return dict(node=node, client=client, bag=bag, answers=answers,
                markers_stowed=markers_stowed)


# --------------------------------------------------------------------------------- tests


def test_the_services_answer_what_was_done_or_why_not(berthing):
    answers = berthing['answers']
    refused = answers['let go stowed']
    assert not refused.success
    assert refused.message == ('line spring is not fast (stowed aboard): there is nothing to '
                               'let go')
    done = answers['make fast stowed']
    assert done.success
    assert done.message.startswith('line spring made fast to b1: ')
    # the length out is the distance times 1.05 (make_fast_slack)
    out, distance = (float(word) for word in
                     done.message.split(': ')[1].replace(' m from the fairlead', '')
                     .split(' m out, '))
    assert distance == pytest.approx(math.dist([-10.0, 5.0, 6.0], [-50.0, 4.0, 0.0]), abs=0.05)
    assert out == pytest.approx(1.05 * distance, abs=0.1)
    again = answers['make fast fast']
    assert not again.success and again.message == 'line spring is already fast to b1'
    let_go = answers['let go head']
    assert let_go.success and let_go.message.startswith('line head let go from b1 at ')
    assert let_go.message.endswith(' kN')
    made_fast = answers['make fast head']
    assert made_fast.success, made_fast.message
    assert made_fast.message.startswith('line head made fast to b2: 42.0 m out, ')
    stow = answers['stow fast']
    assert not stow.success
    assert stow.message == ('line stern is fast on its bollard: only a line let go and heaved '
                            'in can be stowed')
    assert answers['let go all'].success
    assert answers['let go all'].message == 'let go all: head, spring (2 lines)'


def test_a_bollard_is_set_by_parameter_while_the_line_is_not_fast(berthing):
    answers = berthing['answers']
    assert answers['set head'].successful, answers['set head'].reason
    assert not answers['set spring'].successful
    assert answers['set spring'].reason == (
        "parameter 'spring.bollard' cannot change while line spring is fast: let it go first "
        '(its bollard changes while it is stowed or free)')


def test_each_command_taken_is_an_event_and_a_log_line(berthing):
    client, node, answers = berthing['client'], berthing['node'], berthing['answers']
    commands = [e for e in client.events if e['event'] == 'command']
    assert [(e['line'], e['command']) for e in commands] == [
        ('spring', 'make_fast'), ('head', 'let_go'), ('head', 'make_fast'),
        ('', 'let_go_all')]
    texts = [answers[key].message for key in ('make fast stowed', 'let go head',
                                              'make fast head', 'let go all')]
    assert [e['text'] for e in commands] == texts
    # at the state time: on the output grid, in order, within the drive that preceded each
    times = [e['t'] for e in commands]
    assert times == sorted(times)
    assert all(abs(t * 50.0 - round(t * 50.0)) < 1e-6 for t in times), times
    # each after the drive before it: the ropes at the second-newest pose's time, or one
    # output short of it (the newest output the test saw, see Client.drive)
    for t, end in zip(times, ENDS):
        reached = end - 2.0 / POSE_RATE
        assert reached - 1.0 / OUTPUT_RATE - 1e-9 <= t <= reached + 1e-9, (t, end)
    log = node.text()
    for text in texts:  # logged once, at INFO
        assert sum(text in line and '[INFO]' in line for line in log.splitlines()) == 1, text
    for key in ('let go stowed', 'make fast fast', 'stow fast'):  # refused: once, at WARN
        text = answers[key].message
        assert sum(text in line and '[WARN]' in line for line in log.splitlines()) == 1, text
    assert 'Traceback' not in log


def test_the_hook_lets_go_past_its_release_load(berthing):
    client, node = berthing['client'], berthing['node']
    released = [e for e in client.events if e['event'] == 'released']
    assert len(released) == 1, client.events
    event = released[0]
    assert event['line'] == 'stern'
    # within an output interval of passing it: by less than an interval's rise
    assert RELEASE_LOAD < event['tension'] < 1.1 * RELEASE_LOAD
    assert RAMP[0] < event['t'] < RAMP[1]
    assert sum('stern: its quick-release hook let go' in line and '[WARN]' in line
               for line in node.text().splitlines()) == 1


def test_the_bag_holds_the_events_and_resim_gives_the_node_outputs(berthing, tmp_path):
    client = berthing['client']
    events = bag_events(berthing['bag'])
    assert [e for e in events if e['event'] in ('command', 'released')] == [
        e for e in client.events if e['event'] in ('command', 'released')]
    assert [e for e in events if e['event'] == 'set'] == [
        {'event': 'set', 'line': 'head', 'values': {'bollard': 'b2'}}]
    again = tmp_path / 'resim'
    assert cli.main(['resim', str(berthing['bag']), '--out', str(again), '--quiet']) == 0
    live, offline = recorded_outputs(berthing['bag']), recorded_outputs(again)
    assert len(live['/head/rope/particles']) > 250  # 5.2 s at 50 Hz, less the start
    worst = 0.0
    for topic, rows in live.items():
        assert [stamp for stamp, _ in rows] == [stamp for stamp, _ in offline[topic]], topic
        if rows[0][1] is None:
            continue
        numbers = np.array([row for _, row in rows])
        difference = np.abs(numbers - np.array([row for _, row in offline[topic]])).max()
        worst = max(worst, difference / np.abs(numbers[:, :3]).max())
    print(f'node vs resim: largest difference {worst:.2e} of the largest force')
    assert worst < 1e-9


def test_a_bollard_load_is_the_sum_of_the_lines_fast_on_it(berthing):
    rows = recorded_outputs(berthing['bag'])
    events = bag_events(berthing['bag'])
    commands = {(e['line'], e['command']): e['t'] for e in events
                if e['event'] == 'command'}
    hook = next(e['t'] for e in events if e['event'] == 'released')

    epoch = rows['/head/rope/particles'][0][0]  # simulated time 0: the first output's

    def on(bollard: str, line: str, stamp: int) -> bool:
        # an output at a command's time was reached before it; a hook lets go in the
        # advance that reaches its output
        t = (stamp - epoch) / 1e9
        done = commands[('', 'let_go_all')]
        if line == 'spring':
            return bollard == 'b1' and commands[('spring', 'make_fast')] < t <= done
        if line == 'head':
            if bollard == 'b1':
                return t <= commands[('head', 'let_go')]
            return commands[('head', 'make_fast')] < t <= done
        return bollard == 'b2' and t < hook

    counted = {('b1', 2): 0, ('b1', 1): 0, ('b1', 0): 0, ('b2', 2): 0, ('b2', 1): 0,
               ('b2', 0): 0}
    for bollard in ('b1', 'b2'):
        for n, (stamp, load) in enumerate(rows[f'/{bollard}/load']):
            lines = [line for line in NAMES if on(bollard, line, stamp)]
            forces = [rows[f'/{line}/bollard/tension'][n][1][:3] for line in lines]
            assert np.allclose(load[:3], np.sum(forces, axis=0) if forces else np.zeros(3),
                               rtol=1e-12, atol=1e-9), (bollard, stamp, lines)
            assert not load[3:].any()
            counted[(bollard, len(lines))] += 1
    assert all(counted.values()), counted  # two, one and no line on each, over the run
    # and over DDS: the received loads are the recorded ones
    received = {stamp_ns(msg): [msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z]
                for msg in berthing['client'].loads}
    recorded = dict(rows['/b1/load'])
    assert len(received) > 100
    assert all(np.array_equal(force, recorded[stamp][:3]) for stamp, force in received.items())


def test_markers_and_diagnostics_say_each_line_state_and_bollard_load(berthing):
    client = berthing['client']
    stowed = {(m.ns, m.id): m for m in berthing['markers_stowed'].markers}
    assert stowed[('lines', 1)].action == Marker.DELETE  # spring, aboard: not drawn
    assert stowed[('labels', 1)].action == Marker.DELETE
    assert stowed[('lines', 0)].action == Marker.ADD
    bollards = [[p.x, p.y, p.z] for p in stowed[('bollards', 0)].points]
    assert np.allclose(bollards, [[-50.0, 4.0, 0.0], [-50.0, -8.0, 0.0]])  # head's, stern's
    assert stowed[('quay_bollards', 1)].type == Marker.CYLINDER
    assert stowed[('quay_bollard_labels', 0)].text.startswith('b1 ')
    final = {(m.ns, m.id): m for m in client.markers[-1].markers}
    for k, name in enumerate(NAMES):  # every line let go
        assert final[('lines', k)].action == Marker.ADD
        assert colour(final[('lines', k)]) == tuple(round(c, 3) for c in FREE_COLOUR)
        assert final[('labels', k)].text == f'{name} let go'
    assert final[('quay_bollard_labels', 1)].text == 'b2 0 kN'
    assert colour(final[('quay_bollards', 1)]) == tuple(round(c, 3) for c in COLOURS['ok'])
    reports = [statuses(array) for array in client.diagnostics]
    # b2 past its safe working load while stern pulled on it, before its hook let go
    warned = [r['b2'] for r in reports if 'b2' in r and r['b2'][0] == DiagnosticStatus.WARN]
    assert warned and warned[0][1].startswith('past its safe working load: peak ')
    assert float(warned[0][2]['peak since last report [N]']) > SAFE_WORKING_LOAD
    last = reports[-1]
    for name in NAMES:
        assert last[name][1].startswith('let go: ') and last[name][2]['state'] == 'free'
    assert last['b1'][:2] == (DiagnosticStatus.OK, 'no line fast on it')
    assert last['b2'][2]['safe working load [N]'] == f'{SAFE_WORKING_LOAD:.0f}'
    first = next(r for r in reports if 'b1' in r)  # (before the first output: lines only)
    assert first['spring'][:2] == (DiagnosticStatus.OK, 'stowed')
    assert first['spring'][2]['state'] == 'stowed'
    assert first['b1'][2]['lines'] == 'head'


def test_the_line_node_has_the_same_services(colcon_install, colcon_env, tmp_path):
    # A single line is a mooring of one: make_fast, let_go, stow at the root of its
    # namespace, its events' line '', replayed by resim to round-off.
    answers = {}
    bollard_tensions = {}

    def drive(client, node):
        services = {name: client.node.create_client(Trigger, name)
                    for name in ('make_fast', 'let_go', 'stow')}
        client.wait_for(lambda: all(c.service_is_ready() for c in services.values()), 30.0,
                        'the services')

        def call(name):
            future = services[name].call_async(Trigger.Request())
            client.wait_for(future.done, 10.0, name)
            return future.result()

        start = START
        client.drive(start, 0.5, ship)
        bollard_tensions['stowed'] = [b for _, _, b in client.outputs()]
        answers['let_go stowed'] = call('let_go')
        answers['make_fast'] = call('make_fast')
        client.drive(start + 520_000_000, 0.5, lambda t: ship(0.52 + t))
        answers['stow fast'] = call('stow')
        answers['let_go'] = call('let_go')
        client.drive(start + 1_040_000_000, 0.5, lambda t: ship(1.04 + t))
        client.wait_for(lambda: client.outputs()[-1:] and (
            client.outputs()[-1][0] >= start + 1_520_000_000), 30.0,
                        'the last outputs')
        bollard_tensions['all'] = [b for _, _, b in client.outputs()]

    bag, node = record(colcon_install, colcon_env, tmp_path, '/handling_line', drive,
                       '-p', 'start_state:=stowed')
    assert not answers['let_go stowed'].success
    assert answers['let_go stowed'].message == ('the line is not fast (stowed aboard): there '
                                                'is nothing to let go')
    assert answers['make_fast'].success
    assert answers['make_fast'].message.startswith('the line made fast to its bollard at (')
    assert not answers['stow fast'].success
    assert answers['let_go'].success
    assert answers['let_go'].message.startswith('the line let go from its bollard at (')
    assert bollard_tensions['stowed'] and not any(bollard_tensions['stowed'])  # aboard: none
    assert max(bollard_tensions['all']) > 1000.0  # made fast, it held its weight
    events = [e for e in bag_events(bag) if e['event'] == 'command']
    assert [e['command'] for e in events] == ['make_fast', 'let_go']
    assert all(e['line'] == '' for e in events)  # named always, '' for the single line
    assert [e['text'] for e in events] == [answers['make_fast'].message,
                                           answers['let_go'].message]
    _, _, force, torque = compare(bag, tmp_path, '/handling_line')
    assert force < 1e-9 and torque < 1e-9, (force, torque)
