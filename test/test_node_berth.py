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
The berth (config/berth.yaml) as a ROS user meets it.

A parameter dump loaded back, a ship driven by ship_motion as docs/ros.md says, a start
past the working load limit.

Over real DDS from the colcon install.
"""

from pathlib import Path
import re
import time

from geometry_msgs.msg import WrenchStamped
from node_harness import berth_file, Client, Executable, Keep
import numpy as np
from rclpy.parameter import parameter_value_to_python
import yaml

REPO = Path(__file__).resolve().parent.parent
BERTH = REPO / 'config' / 'berth.yaml'
START = 4000 * 1_000_000_000  # [ns] sim time of the first pose
REST = [0.0, -17.6, 0.0]  # the berth's ship at rest (config/berth.yaml)
NAMES = ['head_1', 'head_2', 'breast_fwd', 'spring_fwd', 'spring_aft', 'breast_aft',
         'stern_1', 'stern_2']


def wrenches(client: Client) -> dict:
    """Return {stamp [ns]: force (x, y, z) [N]} of the wrenches the client received."""
    return {msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec:
            np.array([msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z])
            for _, msg in client.wrenches}


def drive(client: Client, seconds: float) -> None:
    """Publish /clock and the ship at rest at 50 Hz of sim time from START."""
    client.drive(START, seconds, ship=lambda t: REST)


def dump_parameters(client: Client) -> dict:
    """Return the node's parameters as `ros2 param dump` writes them (nested at dots)."""
    names = list(client.call(client.parameters.list_parameters()).result.names)
    values = client.call(client.parameters.get_parameters(names)).values
    nested = {}
    for name, value in zip(names, values):
        *path, leaf = name.split('.')
        where = nested
        for key in path:
            where = where.setdefault(key, {})
        where[leaf] = parameter_value_to_python(value)
    return {'/mooring': {'ros__parameters': nested}}


def lengths(dump: dict) -> dict:
    values = dump['/mooring']['ros__parameters']
    return {name: values[name]['length'] for name in NAMES}


def test_a_parameter_dump_restarts_the_same_lines(colcon_install, colcon_env, tmp_path):
    # The berth's lines take their lengths from their pretensions at the first ship pose.
    # A dump of the running node then holds each line's length in use beside its
    # pretension (issue: head_1.length read 40.0 for a 44.8 m line, and the node refused its
    # own dump: "line 'head_1' has both length and pretension"). Loaded into a new node,
    # the dump starts the same lines: the same lengths, the same wrench.
    client = Client(node='mooring', poses=('ship',),
                    keep={'wrenches': Keep('ship/mooring_wrench', WrenchStamped, 1000)})
    runs, node = [], None
    try:
        for name, params in (('first', berth_file(tmp_path / 'berth.yaml')),
                             ('again', tmp_path / 'dump.yaml')):
            # the node before has left the graph: its wrench publisher matches no more
            client.wait_for(lambda: client.wrenches.subscription.get_publisher_count() == 0,
                            30.0, 'no node')
            node = Executable(colcon_install, colcon_env, tmp_path / f'{name}.log', 'mooring',
                              '--ros-args', '--params-file', str(params),
                              '-p', 'use_sim_time:=true')
            client.clear()
            client.wait_for_node(node)
            # 2 s: the node may see the test's subscription a few outputs after the test
            # sees its publisher (DDS discovery is not symmetric); the first are then unsent
            drive(client, 2.0)
            client.wait_for(lambda: len(wrenches(client)) >= 75, 20.0, 'the wrenches', node)
            dump = dump_parameters(client)
            if name == 'first':
                (tmp_path / 'dump.yaml').write_text(yaml.safe_dump(dump))
            assert node.interrupt() == 0
            runs.append((node, dump, wrenches(client)))
    finally:
        client.close()
        if node is not None and node.process.poll() is None:
            node.interrupt()
    (first, dumped, before), (again, reloaded, after) = runs
    chosen = re.search(r'lengths for their pretension: (.*)', first.text()).group(1)
    expected = {name: float(length) for name, length in re.findall(r'(\w+) ([\d.]+) m', chosen)}
    print('lengths chosen:', expected)
    assert set(expected) == set(NAMES)
    for name in NAMES:
        assert lengths(dumped)[name] == lengths(reloaded)[name]
        assert abs(lengths(dumped)[name] - expected[name]) < 5e-4, name  # logged to 1 mm
    assert abs(lengths(dumped)['head_1'] - 40.0) > 4.0  # not the default it read before
    assert dumped['/mooring']['ros__parameters']['head_1']['pretension'] == 126000.0
    assert 'lengths for their pretension' not in again.text()  # it took the lengths
    assert 'ERROR' not in again.text() and 'WARN' not in again.text(), again.text()
    common = sorted(set(before) & set(after))
    assert len(common) >= 50
    largest = max(np.abs(before[s] - after[s]).max() for s in common)
    print(f'{len(common)} wrenches compared: largest difference {largest:.3g} N')
    assert largest <= 1e-6 * np.abs(before[common[-1]]).max()


def ship_motion_drives_mooring(colcon_install, colcon_env, folder: Path, berth: Path,
                               *ship_args, seconds: float = 3.0) -> str:
    """
    Start mooring (berth) and ship_motion remapped to ship/pose; return mooring's log.

    Both stop `seconds` after the lines started.
    """
    mooring = Executable(colcon_install, colcon_env, folder / 'mooring.log', 'mooring',
                         '--ros-args', '--params-file', str(berth))
    ship = Executable(colcon_install, colcon_env, folder / 'ship.log', 'ship_motion',
                      '--ros-args', '-r', 'fairlead/pose:=ship/pose', *ship_args)
    try:
        end = time.monotonic() + 90.0
        while 'first ship pose' not in mooring.text():
            assert time.monotonic() < end and mooring.process.poll() is None, mooring.text()
            time.sleep(0.2)  # the wall clock is the nodes' clock here: nothing to drive
        started = time.monotonic()
        while time.monotonic() < started + seconds:
            assert mooring.process.poll() is None, mooring.text()
            time.sleep(0.2)
        assert ship.interrupt() == 0 and mooring.interrupt() == 0
    finally:
        for process in (ship, mooring):
            if process.process.poll() is None:
                process.interrupt()
    return mooring.text()


def test_ship_motion_drives_the_berth_as_the_docs_say(colcon_install, colcon_env, tmp_path):
    # docs/ros.md: ship_motion remapped to ship/pose, with the installed
    # config/berth_motion.yaml (its mean_position the berth's rest pose). The lines start at
    # their pretensions, below their working load limits.
    motion = colcon_install / 'share' / 'rope_sim_ros' / 'config' / 'berth_motion.yaml'
    text = ship_motion_drives_mooring(colcon_install, colcon_env, tmp_path,
                                      berth_file(tmp_path / 'berth.yaml'),
                                      '--params-file', str(motion))
    assert 'working load limit' not in text and '[ERROR]' not in text, text
    # the ship at its berth (it began to move as the mooring node subscribed)
    head = float(re.search(r'lengths for their pretension: head_1 ([\d.]+) m', text).group(1))
    assert abs(head - 44.8) < 0.5, head
    received = int(re.search(r'ship/pose: (\d+) received', text).group(1))
    assert received > 100, text


def test_a_minute_of_berth_motion_keeps_every_line_below_its_wll():
    # What the node test above cannot wait for: config/berth_motion.yaml's motion past its
    # ramp, through the mooring node's driver (the node's rules, without DDS). ship_motion's
    # own defaults took both springs to their break load (parted at 11.3 and 27.0 s).
    from rope_sim_ros.mooring.driver import Driver
    from rope_sim_ros.mooring.status import ratings
    from rope_sim_ros.params.arrangement import read_arrangement_file
    from rope_sim_ros.params.files import read_params_file
    from rope_sim_ros.ros import ship_motion_node
    values = {name: spec[0] for name, spec in ship_motion_node.PARAMETERS.items()}
    values.update(read_params_file(REPO / 'config' / 'berth_motion.yaml', 'ship_motion'))
    assert values['mean_position'] == REST
    setup = read_arrangement_file(BERTH)
    driver = Driver(setup)
    peaks = np.zeros(len(NAMES))
    for k in range(60 * 50 + 1):  # 50 Hz poses, as ship_motion publishes them
        t = k / 50.0
        driver.push_ship(START + k * 20_000_000, *ship_motion_node.ship_pose(t, values))
        for published in driver.advance(t).outputs:
            out = published.output
            assert not out.parted.any(), t
            peaks = np.maximum(peaks, out.peaks)
    shares = peaks / [rating.wll for rating in ratings(setup)]
    assert shares.max() < 0.9, shares  # (measured: the springs at 0.77 and 0.79 of it)
    assert shares.min() > 0.2  # every line works


def test_a_start_past_the_working_load_limit_says_so(colcon_install, colcon_env, tmp_path):
    # The berth's lines at their lengths (as a dump of a running node gives them) and the
    # remap alone (issue: ship_motion's default mean_position put the ship's centreline on
    # the quay face, 8 m up; one line reached 88.6 % of its MBL and nothing warned): one
    # warning a line past its WLL, naming the line, its tension and its WLL; a line past
    # its break load parts as it starts, with an error.
    rest = {'head_1': 44.803, 'head_2': 38.836, 'breast_fwd': 16.736, 'spring_fwd': 50.588,
            'spring_aft': 50.588, 'breast_aft': 16.736, 'stern_1': 46.741, 'stern_2': 40.768}
    text = ship_motion_drives_mooring(colcon_install, colcon_env, tmp_path,
                                      berth_file(tmp_path / 'berth.yaml', rest),
                                      '-p', 'mean_position:=[0.0, 0.0, 8.0]',
                                      seconds=1.0)  # (what it checks is said at the start)
    warned = re.findall(r'\]: (\w+) starts at (\d+) kN, past its working load limit of (\d+) '
                        r'kN \(([\d.]+) % of its MBL\)', text)
    print('\n'.join(' '.join(w) for w in warned))
    parted = re.findall(r'\]: (\w+) parted at t = 0.000 s as it \(re\)started', text)
    print('parted as they started:', parted)
    assert warned, text
    assert len({w[0] for w in warned}) == len(warned)  # one line each
    assert all(w[0] in NAMES and int(w[1]) > int(w[2]) for w in warned), warned
    assert all(50.0 < float(w[3]) < 100.0 for w in warned)  # the WLL is half the MBL
    assert not set(parted) & {w[0] for w in warned}
