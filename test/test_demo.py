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
`make demo`: the free ship at its berth and a ship passing it.

The berth demo's table (pure functions), the demo's setup and bad input, the event plot of
a free ship's bag recorded offline as the node records it, then the live demo end to end.
"""

import math
import os
import re
import subprocess
import sys

from geometry_msgs.msg import PoseStamped, Wrench, WrenchStamped
from matplotlib import image
import numpy as np
import pytest
import rclpy
from rope_sim_ros.messages import topics
from rope_sim_ros.messages.encode import OutputEncoder
from rope_sim_ros.offline import cli, demo
from rope_sim_ros.offline.plot import (_passing_outline, abeam_time, line_kinds, plot_event,
                                       read_record, ship_offsets, stagger)
from rope_sim_ros.offline.run import simulate_free
from rope_sim_ros.offline.sinks import BagSink
from rope_sim_ros.params.arrangement import stored
from rope_sim_ros.params.table import ParameterError
from rope_sim_ros.ros import berth_demo_node as table

BERTH_LINES = ['head_1', 'head_2', 'breast_fwd', 'spring_fwd', 'spring_aft', 'breast_aft',
               'stern_1', 'stern_2']
# A ship passing close and soon: abeam at t = 20 s (5 m/s from 100 m astern), 60 m off.
CLOSE = """/**/mooring:
  ros__parameters:
    ship_mode: free
    publish_rate: 10.0
    passing_ship: {speed: 5.0, length: 200.0, beam: 32.0, draft: 12.0,
                   block_coefficient: 0.8, separation: 60.0, start_x: -100.0, direction: 1}
"""


@pytest.fixture
def config(repo_root):
    return repo_root / 'config'


@pytest.fixture(scope='module')
def close_scenario(tmp_path_factory):
    path = tmp_path_factory.mktemp('scenario') / 'close.yaml'
    path.write_text(CLOSE)
    return path


# -- the table ----------------------------------------------------------------------------

def test_the_table_reads_both_files_the_later_on_top(config):
    setup = table.read_setup([str(config / 'berth.yaml'), str(config / 'berth_demo.yaml')])
    assert setup.names == BERTH_LINES and len(setup.fenders) == 4
    assert setup.ship.free and setup.ship.start_position == [0.0, -17.6, 0.0]
    assert (setup.passing.speed, setup.passing.separation, setup.passing.start_x) == (
        2.5, 100.0, -350.0)


def test_the_passing_ship_is_where_its_parameters_put_it(config):
    setup = table.read_setup([str(config / 'berth.yaml'), str(config / 'berth_demo.yaml')])
    passer = table.passing_ship(setup)
    rest = setup.ship.start_position
    assert table.where_passing(passer, 0.0, rest, 0.0) == pytest.approx((-350.0, 100.0))
    assert table.where_passing(passer, 140.0, rest, 0.0) == pytest.approx((0.0, 100.0))
    # drawn 0.5 m off the quay towards it, then turned 0.01 rad bow to port
    assert table.where_passing(passer, 140.0, [0.0, -18.1, 0.0], 0.0) == pytest.approx(
        (0.0, 99.5))
    dx, dy = -350.0, -100.0
    c, s = math.cos(0.01), math.sin(0.01)
    assert table.where_passing(passer, 0.0, rest, 0.01) == pytest.approx(
        (c * dx + s * dy, s * dx - c * dy))
    assert table.passing_ship(table.read_setup([str(config / 'berth.yaml')])) is None
    # in a current along its track it moves over the ground faster, as the node moves it
    drifting = table.read_setup([str(config / 'berth.yaml'), str(config / 'berth_demo.yaml')])
    drifting = table.arrangement.from_values({**table.arrangement.flatten(drifting.values()),
                                              'current': [0.5, -0.2, 0.0]})
    passer = table.passing_ship(drifting)
    assert table.where_passing(passer, 100.0, rest, 0.0) == pytest.approx((-50.0, 100.0))


def test_offsets_are_in_the_start_pose_axes():
    assert table.offsets([0.0, -17.6, 0.0], 0.0, [0.1, -18.1, 0.0], 0.01) == pytest.approx(
        (0.1, -0.5, math.degrees(0.01)))
    # heading along world +y: a move along world +y is surge, along world -x is sway to port
    assert table.offsets([5.0, 5.0, 0.0], math.pi / 2, [4.0, 7.0, 0.0],
                         math.pi / 2 - 0.02) == pytest.approx((2.0, 1.0, -math.degrees(0.02)))
    # across +-pi: the short way round
    assert table.offsets([0.0, 0.0, 0.0], math.pi - 0.01, [0.0, 0.0, 0.0],
                         -math.pi + 0.01)[2] == pytest.approx(math.degrees(0.02))
    assert table.yaw_of((0.0, 0.0, math.sin(0.3), math.cos(0.3))) == pytest.approx(0.6)


def test_the_rows_line_up_under_the_header():
    names = table.HEADER.splitlines()[1]
    row = table.format_row(100.0, (-12.25, 70.31), (0.0512, -0.6443, -0.5504), (-12e3, -471.9e3),
                           ('breast_fwd', 365.04e3, 0.402))
    assert row.split() == ['100.0', '-12.2', '70.3', '+0.051', '-0.644', '-0.550', '-12.0',
                           '-471.9', 'breast_fwd', '365.0', '40.2']
    # every number ends where its column's name ends (the line's name starts with its name)
    for name, number in [('t [s]', '100.0'), ('stagger [m]', '-12.2'), ('separ. [m]', '70.3'),
                         ('surge [m]', '+0.051'), ('sway [m]', '-0.644'),
                         ('yaw [deg]', '-0.550'), ('Fx [kN]', '-12.0'), ('Fy [kN]', '-471.9'),
                         ('T [kN]', '365.0'), ('% MBL', '40.2')]:
        assert names.index(name) + len(name) == row.index(number) + len(number), name
    assert names.index('name') == row.index('breast_fwd')
    empty = table.format_row(3.0, None, None, None, None)
    assert empty.split() == ['3.0'] + ['-'] * 8
    assert len(table.HEADER.splitlines()[0]) <= len(names)


def _stamped(cls, t: float):
    msg = cls()
    stamp = round((1000.0 + t) * 1e9)
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp, 1_000_000_000)
    return msg


def test_a_row_a_second_of_each_output_whole_whatever_the_order(config):
    setup = table.read_setup([str(config / 'berth.yaml'), str(config / 'berth_demo.yaml')])
    context = rclpy.Context()
    context.init()
    rows = []
    node = table.BerthDemo(setup, duration=2.0, say=rows.append, context=context)
    try:
        def pose(t, sway):
            msg = _stamped(PoseStamped, t)
            msg.pose.position.x, msg.pose.position.y = 0.0, -17.6 + sway
            msg.pose.orientation.w = 1.0
            return msg

        def load(t, fy):
            msg = _stamped(WrenchStamped, t)
            msg.wrench.force.x, msg.wrench.force.y = 1000.0, fy
            return msg

        tension = Wrench()
        tension.force.x = 140.8e3  # 10 % of the spring's MBL
        node._keeper('spring_fwd')(tension)
        node._on_pose(pose(0.0, 0.0))
        node._on_passing(load(0.0, 2e3))  # the load after the pose
        node._on_pose(pose(0.5, -0.1))
        node._on_passing(load(0.5, 3e3))  # within the second: no row
        node._on_passing(load(1.0, 4e3))  # the load first, then two poses at once
        node._on_pose(pose(1.0, -0.2))
        node._on_pose(pose(1.5, -0.3))
        node._on_pose(pose(2.0, -0.4))  # its load comes late, after the next output's
        node._on_pose(pose(2.5, -0.5))
        node._on_passing(load(2.5, 6e3))  # past the duration: no row
        node._on_passing(load(2.0, 5e3))
    finally:
        node.destroy_node()
        context.try_shutdown()
    assert [row.split()[:8] for row in rows] == [
        ['0.0', '-350.0', '100.0', '+0.000', '+0.000', '+0.000', '+1.0', '+2.0'],
        ['1.0', '-347.5', '99.8', '+0.000', '-0.200', '+0.000', '+1.0', '+4.0'],
        ['2.0', '-345.0', '99.6', '+0.000', '-0.400', '+0.000', '+1.0', '+5.0']]
    assert rows[0].split()[8:] == ['spring_fwd', '140.8', '10.0']


# -- the demo's setup and bad input ---------------------------------------------------------

def test_the_demo_setup_puts_the_passing_ship_abeam_in_the_middle(config, close_scenario):
    setup = demo.demo_setup(config / 'berth.yaml', config / 'berth_demo.yaml')
    assert demo.default_duration(setup) == pytest.approx(280.0)
    assert demo.story(setup) == (
        'A 200 m ship passes 100 m off the starboard side at 2.5 m/s (4.9 kn) in 16 m of '
        'water, abeam at t = 140 s: it moves the free ship, the lines hold it')
    close = demo.demo_setup(config / 'berth.yaml', close_scenario)
    assert demo.default_duration(close) == pytest.approx(40.0)
    with pytest.raises(ParameterError, match="ship_mode is 'driven'"):
        demo.demo_setup(config / 'berth.yaml', None)  # the berth's own ship is driven


def test_a_passing_ship_that_never_comes_abeam_gives_a_quiet_run(config, tmp_path):
    away = tmp_path / 'away.yaml'
    away.write_text(CLOSE.replace('start_x: -100.0', 'start_x: 100.0'))
    setup = demo.demo_setup(config / 'berth.yaml', away)
    assert abeam_time(setup.passing) is None
    assert demo.default_duration(setup) == demo.QUIET_DURATION


@pytest.fixture
def fake_install(tmp_path):
    """Return an install base whose executables exist (the demo stops before it starts them)."""
    executables = tmp_path / 'install' / 'rope_sim_ros' / 'lib' / 'rope_sim_ros'
    executables.mkdir(parents=True)
    for name in ('mooring', 'rope_sim'):
        (executables / name).write_text('')
    return tmp_path / 'install'


@pytest.mark.parametrize('arguments, message', [
    (['--speed', '0'], 'demo: --speed 0.0 is not allowed: must be a number > 0'),
    (['--duration', 'nan'], 'demo: --duration nan is not allowed: must be a number > 0'),
    (['--scenario', '{config}/mooring_line.yaml'],
     'demo: parameter file {config}/mooring_line.yaml has no "mooring: ros__parameters:" '
     'section'),
    (['--scenario', '{config}/berth.yaml'],
     "demo: ship_mode is 'driven': the demo's ship moves by itself: set ship_mode: free"),
    (['--params', '{config}/mooring_line.yaml'],
     'demo: {config}/mooring_line.yaml holds no mooring node parameters (mooring: '
     'ros__parameters: lines: ...)'),
])
def test_bad_input_is_one_line_before_anything_starts(arguments, message, config, fake_install,
                                                      tmp_path, capsys):
    arguments = [a.format(config=config) for a in arguments]
    assert demo.main(arguments + ['--install', str(fake_install),
                                  '--out', str(tmp_path / 'out')]) == 2
    err = capsys.readouterr().err
    assert err == message.format(config=config) + '\n'
    assert not (tmp_path / 'out').exists()


def test_no_install_says_make_build(tmp_path, capsys):
    assert demo.main(['--install', str(tmp_path)]) == 2
    assert 'run `make build` first' in capsys.readouterr().err


# -- the plots, from a free ship's bag recorded offline as the node records it -------------

@pytest.fixture(scope='module')
def free_bag(tmp_path_factory, repo_root, close_scenario):
    """40 s of the berth's free ship, a ship passing abeam at 20 s: the bag and the outputs."""
    setup = demo.demo_setup(repo_root / 'config' / 'berth.yaml', close_scenario)
    encoder = OutputEncoder(topics.MOORING_NODE, setup.names, [False] * len(setup.names),
                            setup.shared.frame_id, setup.ship_frame_id, True,
                            [fender.name for fender in setup.fenders], True)
    path = tmp_path_factory.mktemp('free') / 'bag'
    sink = BagSink(path, encoder, '', [], {}, stored(setup))
    outputs = []
    try:
        simulate_free(setup, 40.0, rate=10.0, sinks=[sink, outputs.append])
    finally:
        sink.close()
    return setup, path, outputs


def test_the_record_holds_the_passing_ship_and_the_motion(free_bag):
    setup, path, outputs = free_bag
    record = read_record(path)
    times = np.array([p.output.t for p in outputs])
    assert len(times) == 401
    assert record.passing_times == pytest.approx(times - times[0])
    loads = np.array([p.output.ship_loads[2] for p in outputs])  # Fx, Fy, Mz
    assert record.passing_force[:, :2] == pytest.approx(loads[:, :2])
    assert record.passing_moment[:, 2] == pytest.approx(loads[:, 2])
    assert not record.passing_force[:, 2].any() and not record.passing_moment[:, :2].any()
    # its pull across is strongest abeam, and its push along changes sign there
    when = abeam_time(setup.passing)
    assert when == pytest.approx(20.0) and stagger(setup.passing, when) == pytest.approx(0.0)
    i = int(np.argmin(record.passing_force[:, 1]))
    assert abs(record.passing_times[i] - when) <= 1.0
    assert record.passing_force[i, 1] < -2.0e5  # towards it, off the quay
    fx = np.interp([when - 4.0, when + 4.0], record.passing_times, record.passing_force[:, 0])
    assert fx[0] < -2.0e4 and fx[1] > 2.0e4

    surge, sway, yaw = ship_offsets(record)
    position = np.array([p.output.ship.position for p in outputs])
    q = np.array([p.output.ship.orientation for p in outputs])
    assert surge == pytest.approx(position[:, 0] - position[0, 0], abs=1e-9)
    assert sway == pytest.approx(position[:, 1] - position[0, 1], abs=1e-9)
    heading = np.arctan2(2 * (q[:, 3] * q[:, 2] + q[:, 0] * q[:, 1]),
                         1 - 2 * (q[:, 1] ** 2 + q[:, 2] ** 2))
    assert yaw == pytest.approx(np.degrees(heading - heading[0]), abs=1e-9)
    assert sway.min() < -0.1  # the free ship was drawn off the quay


def test_line_kinds_from_their_leads(free_bag):
    record = read_record(free_bag[1])
    assert line_kinds(record) == ['end', 'end', 'breast', 'spring', 'spring', 'breast', 'end',
                                  'end']


def test_the_passing_ship_on_the_plan(free_bag):
    record = read_record(free_bag[1])
    outline, track, ahead = _passing_outline(record, 20.0)
    assert ahead == pytest.approx(0.0)
    assert track[:, 1] == pytest.approx([-77.6, -77.6])  # 60 m off the ship's centreline
    assert (outline[:, 0].min(), outline[:, 0].max()) == pytest.approx((-100.0, 100.0))
    assert (outline[:, 1].min(), outline[:, 1].max()) == pytest.approx((-93.6, -61.6))
    assert outline[np.argmax(outline[:, 0]), 1] == pytest.approx(-77.6)  # bow ahead


def test_plot_event_draws_force_motion_tension_and_the_plan(free_bag, tmp_path):
    paths = plot_event(free_bag[1], tmp_path, 'a ship passing')
    assert [p.rsplit('/', 1)[1] for p in paths] == ['event.png', 'plan.png']
    event = image.imread(paths[0])
    assert event.shape[:2] == (1100, 1200)
    assert event[..., :3].std() > 0.05  # drawn, not blank
    plan = image.imread(paths[1])
    assert plan.shape[0] > 300 and plan.shape[1] > 1000


# -- the live demo ----------------------------------------------------------------------------

def test_make_demo_runs_the_event_and_leaves_its_table_bag_and_plots(
        colcon_install, colcon_env, close_scenario, tmp_path):
    # abeam at 20 s: the default 40 s at 2x
    result = subprocess.run(
        [sys.executable, '-m', 'rope_sim_ros.offline.demo', '--speed', '2', '--scenario',
         str(close_scenario), '--install', str(colcon_install.parent), '--out', str(tmp_path)],
        env=colcon_env, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=300)
    output = result.stdout + result.stderr
    assert result.returncode == 0, output
    assert 'Traceback' not in output, output
    # the clock waits for a node that falls behind (a busy machine) rather than have it skip
    assert 'skipped ahead' not in output, output
    rows = [line.split() for line in result.stdout.splitlines()
            if re.match(r'\s+\d+\.\d\s+-?\d', line)]
    numbers = np.array([[float(v) for v in row[:8]] for row in rows])
    names = {row[8] for row in rows}
    # a row a simulated second of the ship's outputs, from its start to the end
    t = numbers[:, 0]
    assert t == pytest.approx(np.arange(41.0)), output
    # the passing ship where its parameters put it, in the moored ship's axes
    assert np.abs(numbers[:, 1] - (-100.0 + 5.0 * t)).max() < 1.5, output
    assert np.abs(numbers[:, 2] - 60.0).max() < 2.5, output
    # it starts at rest, then the passing ship draws it off the quay (- to port)
    assert numbers[0, 3:6] == pytest.approx([0.0, 0.0, 0.0], abs=0.002), output
    assert numbers[:, 4].min() < -0.1 and numbers[:, 7].min() < -200.0, output
    assert names <= set(BERTH_LINES), output
    assert 'lines (peak fairlead tension' in result.stdout
    assert 'stopped mooring, berth_demo' in result.stdout
    run = next(tmp_path.glob('demo_*'))
    record = read_record(run / 'bag')
    assert len(record.passing_times) > 300 and len(record.ship_times) > 300
    # the node's passing ship pulls hardest where the table's is abeam
    i = int(np.argmin(record.passing_force[:, 1]))
    assert abs(-100.0 + 5.0 * record.passing_times[i]) < 10.0
    for name in ('event.png', 'plan.png'):
        assert (run / name).stat().st_size > 20_000, name


def test_rope_sim_plot_of_a_passing_ships_bag_draws_its_load_too(free_bag, tmp_path, capsys):
    # (issue: the tensions and the plan only: not the cause of what they show)
    assert cli.main(['plot', str(free_bag[1]), '-o', str(tmp_path / 'passing.png')]) == 0
    printed = capsys.readouterr().out.split()
    assert [os.path.basename(p) for p in printed] == ['passing.png', 'passing_plan.png',
                                                      'passing_event.png']
    assert all(os.path.getsize(p) > 20_000 for p in printed)
