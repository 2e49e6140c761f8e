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
rope_sim run --commands COMMANDS.csv: lines let go, made fast and stowed at their times.

A ship standing still for 10 s, two lines: head fast to bollard_1 at 50 kN, stern stowed.
The commands: head let go at 2 s, stern made fast to bollard_3 at 4 s, stern stowed at 5 s
(refused: it is fast), let go all at 8 s, head made fast at 20 s (after the run's end). The
outputs (each line's tension and state), the printed lines, the bag's events, resim of the
bag, the plot's marks; then every bad commands file, a single line, a quick-release hook,
and the commands of a node's bag read back. (A free ship's: test_cli_free.py.)
"""

import csv
import io
import sys

import matplotlib
import numpy as np
import pytest
from rope_sim_ros.bag import BagWriter, cdr, read_messages
from rope_sim_ros.bag.cdr import decode_string
from rope_sim_ros.model.statics.catenary import solve_catenary
from rope_sim_ros.mooring.driver import Driver
from rope_sim_ros.mooring.events import decode_event, encode_event
from rope_sim_ros.mooring.records import ScheduledCommand
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.line_events import recorded_commands
from rope_sim_ros.offline.plot import draw_marks, read_record, read_tensions
from rope_sim_ros.params.arrangement import read_setup

matplotlib.use('Agg')

RATE = 10.0
SECONDS = 10.0
PRETENSION = 5.0e4
BERTH = """/**/mooring:
  ros__parameters:
    lines: [head, stern]
    bollards: [bollard_1, bollard_2, bollard_3]
    bollard_1: {position: [40.0, 30.0, 3.0]}
    bollard_2: {position: [-40.0, 30.0, 3.0]}
    bollard_3: {position: [-30.0, 30.0, 3.0]}
    segments: 10
    head: {fairlead_offset: [30.0, 5.0, 5.0], bollard: bollard_1, pretension: 50000.0}
    stern: {fairlead_offset: [-30.0, 5.0, 5.0], bollard: bollard_2, length: 40.0,
            winch_mode: speed, start_state: stowed}
"""
COMMANDS = """t,line,command,bollard
2.0,head,let_go,
4.0,stern,make_fast,bollard_3
5.0,stern,stow,
8.0,,let_go_all,
20.0,head,make_fast,
"""
STERN_FAIRLEAD = np.array([-30.0, 5.0, 5.0])  # the ship stands at the origin, level
BOLLARD_3 = np.array([-30.0, 30.0, 3.0])


def write_ship(path, seconds: float = SECONDS) -> None:
    """Write SHIP.csv: the ship standing at the origin, level, a row every 0.25 s."""
    with open(path, 'w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(['t', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw'])
        for i in range(int(seconds * 4) + 1):
            writer.writerow([i * 0.25, 0, 0, 0, 0, 0, 0, 1])


def read_rows(path):
    """Return OUT.csv's rows as dicts of text."""
    with open(path, newline='') as stream:
        return list(csv.DictReader(stream))


def column(rows, name, kind=float):
    """Return one column of OUT.csv's rows."""
    return np.array([kind(row[name]) for row in rows])


def bag_events(bag, topic='/mooring/events'):
    """Return a bag's events, decoded, with their stamps [s]."""
    return [(m.publish_time_ns / 1e9, decode_event(decode_string(m.data)))
            for m in read_messages(bag, [topic])]


@pytest.fixture(scope='module')
def berth(tmp_path_factory):
    """Write the berth, its ship's motion and the commands; return their folder."""
    folder = tmp_path_factory.mktemp('commands')
    (folder / 'berth.yaml').write_text(BERTH)
    write_ship(folder / 'ship.csv')
    (folder / 'commands.csv').write_text(COMMANDS)
    return folder


@pytest.fixture(scope='module')
def handled(berth):
    """Run the berth with its commands into OUT.csv and a bag; return what it printed too."""
    capture = pytest.MonkeyPatch()  # capsys is a test's, not a module's
    out, err = io.StringIO(), io.StringIO()
    capture.setattr(sys, 'stdout', out)
    capture.setattr(sys, 'stderr', err)
    try:
        code = cli.main(['run', '--params', str(berth / 'berth.yaml'), '--motion',
                         str(berth / 'ship.csv'), '--commands', str(berth / 'commands.csv'),
                         '--out', str(berth / 'out.csv'), '--bag', str(berth / 'bag'),
                         '--rate', str(RATE)])
    finally:
        capture.undo()
    return code, out.getvalue(), err.getvalue(), read_rows(berth / 'out.csv')


def test_a_line_let_go_drops_its_pull_and_is_free_from_the_next_row(handled):
    code, _, _, rows = handled
    assert code == 0
    t = column(rows, 't')
    assert len(rows) == SECONDS * RATE + 1
    state = column(rows, 'head_state', str)
    tension = column(rows, 'head_tension')
    before, after = t <= 2.0 + 1e-9, t > 2.0 + 1e-9
    # taken between the 2.0 s output and the next steps: the 2.1 s row is the first to show it
    assert set(state[before]) == {'fast'} and set(state[after]) == {'free'}
    assert tension[before] == pytest.approx(PRETENSION, rel=1e-3)  # measured +0.03 %
    # the pull is gone in the next row: 1.0 kN, 2.0 % (the line's weight is 0.73 kN)
    assert tension[after][0] < 0.025 * PRETENSION
    # then it swings from its fairlead, jerking now and then (at most 4.5 kN, 9 %): its
    # median 0.22 kN
    assert np.median(tension[after]) < 0.01 * PRETENSION
    assert tension[after].min() > 0.0
    # the ship feels it: its pull towards the quay (+y), 46.3 kN, is gone with it (median
    # 0.11 kN until stern is made fast)
    force_y = column(rows, 'force_y')
    assert force_y[before] == pytest.approx(force_y[0], rel=1e-9)
    assert force_y[0] > 0.9 * PRETENSION
    assert np.median(np.abs(force_y[after & (t < 4.0)])) < 0.01 * force_y[0]


def test_a_stowed_line_made_fast_lies_on_the_catenary_of_its_length(handled, berth):
    _, _, _, rows = handled
    t = column(rows, 't')
    state = column(rows, 'stern_state', str)
    tension = column(rows, 'stern_tension')
    length = column(rows, 'stern_line_length')
    stowed, fast = t <= 4.0 + 1e-9, (t > 4.0 + 1e-9) & (t <= 8.0 + 1e-9)
    assert set(state[stowed]) == {'stowed'} and set(state[fast]) == {'fast'}
    assert (tension[stowed] == 0.0).all() and (column(rows, 'stern_bollard_tension')[stowed]
                                               == 0.0).all()
    # out to bollard_3 (named in the file, not its own bollard_2), 5 % longer than the gap
    distance = np.linalg.norm(BOLLARD_3 - STERN_FAIRLEAD)
    assert length[fast] == pytest.approx(1.05 * distance, rel=1e-12)
    mooring = Driver(read_setup(berth / 'berth.yaml'), rate=RATE).mooring
    props, environment = mooring.lines[1].line_props, mooring.environment
    weight = (props.mass_per_length - environment.air_density * props.volume_area) * 9.81
    span = np.hypot(*(BOLLARD_3 - STERN_FAIRLEAD)[:2])
    catenary = solve_catenary(span, STERN_FAIRLEAD[2] - BOLLARD_3[2], 1.05 * distance,
                              weight, props.axial_stiffness)
    # at rest on it from the make fast on: measured -0.34 % (10 segments)
    assert tension[fast] == pytest.approx(catenary.tension_b, rel=0.005)
    assert np.ptp(tension[fast]) < 1e-6 * catenary.tension_b


def test_a_refused_command_is_said_and_the_run_goes_on(handled):
    _, out, err, rows = handled
    assert ('rope_sim: warning: t = 5.000 s: stow refused: line stern is fast on its '
            'bollard: only a line let go and heaved in can be stowed\n') in err
    assert column(rows, 'stern_state', str)[column(rows, 't') == 6.0] == ['fast']
    # the commands taken, on stdout as the run goes
    said = [line for line in out.splitlines() if line.startswith('rope_sim: t = ')]
    assert said == [
        'rope_sim: t = 2.000 s: line head let go from bollard_1 at 50.0 kN',
        'rope_sim: t = 4.000 s: line stern made fast to bollard_3: 26.3 m out, 25.1 m from '
        'the fairlead',
        said[2]]
    assert said[2].startswith('rope_sim: t = 8.000 s: ') and 'stern' in said[2]
    # the one after the run's end is said once, not taken
    assert ('rope_sim: warning: 1 command from t = 20 s on was not taken: the run ended at '
            '10.000 s\n') in err


def test_let_go_all_lets_every_fast_line_go(handled):
    _, _, _, rows = handled
    t = column(rows, 't')
    assert set(column(rows, 'stern_state', str)[t > 8.0 + 1e-9]) == {'free'}
    assert set(column(rows, 'head_state', str)[t > 8.0 + 1e-9]) == {'free'}


def test_the_bag_records_every_command_and_its_answer(handled, berth):
    events = bag_events(berth / 'bag')
    assert [(stamp, event['event'], event.get('line'), event.get('command'))
            for stamp, event in events] == [
        (2.0, 'command', 'head', 'let_go'),
        (4.0, 'set', 'stern', None),
        (4.0, 'command', 'stern', 'make_fast'),
        (5.0, 'command', 'stern', 'stow'),
        (8.0, 'command', '', 'let_go_all')]  # the mooring's: line '', as the node's
    for stamp, event in events:
        if event['event'] == 'command':
            assert event['t'] == pytest.approx(stamp, abs=1e-9)
            assert event['text']
    assert events[1][1]['values'] == {'bollard': 'bollard_3'}
    assert events[0][1]['text'] == 'line head let go from bollard_1 at 50.0 kN'
    assert events[3][1]['refused'] is True and 'refused' not in events[0][1]
    assert events[3][1]['text'].startswith('line stern is fast on its bollard')


def test_resim_of_the_bag_takes_the_commands_again_to_round_off(handled, berth):
    assert cli.main(['resim', str(berth / 'bag'), '--out', str(berth / 'again'),
                     '--quiet']) == 0
    assert bag_events(berth / 'again') == bag_events(berth / 'bag')
    for line in ('head', 'stern'):
        recorded = read_tensions(berth / 'bag', f'/{line}')['fairlead']
        again = read_tensions(berth / 'again', f'/{line}')['fairlead']
        assert len(again.tension) == len(recorded.tension) == SECONDS * RATE + 1
        np.testing.assert_allclose(again.tension, recorded.tension, rtol=1e-9, atol=1e-6)


def test_the_plot_marks_every_command_on_the_time_axis(handled, berth, tmp_path):
    record = read_record(berth / 'bag')
    assert [(pytest.approx(t, abs=1e-9), label) for t, label in record.marks] == [
        (2.0, 'head let go'), (4.0, 'stern make fast'), (5.0, 'stern stow (refused)'),
        (8.0, 'let go all')]
    assert cli.main(['plot', str(berth / 'bag'), '-o', str(tmp_path / 'plot.png')]) == 0
    assert (tmp_path / 'plot.png').stat().st_size > 10000
    from matplotlib.figure import Figure
    figure = Figure()
    axes = [figure.add_subplot(2, 1, 1), figure.add_subplot(2, 1, 2)]
    draw_marks(record.marks, axes, axes[0])
    for axis in axes:  # one dotted vertical line per mark, at its time
        assert [line.get_xdata()[0] for line in axis.get_lines()] == [
            t for t, _ in record.marks]
        assert {line.get_linestyle() for line in axis.get_lines()} == {':'}
    assert [text.get_text() for text in axes[0].texts] == [label for _, label in record.marks]
    assert len(axes[1].texts) == 0


@pytest.mark.parametrize('rows, message', [
    ('1.0,haed,let_go,\n', "data row 1 (file line 2), column 'line': 'haed' is not a line: "
     "one of head, stern; did you mean 'head'?"),
    ('1.0,head,let_goo,\n', "data row 1 (file line 2), column 'command': 'let_goo' is not a "
     "command: one of make_fast, let_go, stow, let_go_all; did you mean 'let_go'?"),
    ('1.0,head,,\n', "column 'command': an empty cell is not a command"),
    ('2.0,head,let_go,\n1.0,stern,make_fast,\n', "data row 2 (file line 3), column 't': 1.0 "
     "is before the previous row's 2; the commands are taken in time order: sort the rows"),
    ('1.0,head,let_go,\nnan,stern,make_fast,\n',
     "data row 2 (file line 3), column 't': 'nan' is not a finite number"),
    ('inf,head,let_go,\n', "data row 1 (file line 2), column 't': 'inf' is not a finite"),
    ('soon,head,let_go,\n', "data row 1 (file line 2), column 't': 'soon' is not a number"),
    ('-1.0,head,let_go,\n', "column 't': -1.0 is before the run's start"),
    ('1.0,stern,make_fast,bolard_3\n', "column 'bollard': 'bolard_3' is not a bollard: one "
     "of bollard_1, bollard_2, bollard_3; did you mean 'bollard_3'?"),
    ('1.0,head,let_go,bollard_1\n', "column 'bollard': 'bollard_1' with let_go: a bollard "
     'is named for make_fast only'),
    ('1.0,head,let_go_all,\n', "column 'line': 'head' with let_go_all"),
    ('1.0,,make_fast,\n', "column 'line': an empty cell is not a line: one of head, stern"),
    ('1.0,head,let_go\n', 'data row 1 (file line 2): 3 cells, but the header has 4 columns'),
])
def test_a_bad_commands_file_is_one_line_and_exit_2(berth, tmp_path, capsys, rows, message):
    commands = tmp_path / 'commands.csv'
    commands.write_text('t,line,command,bollard\n' + rows)
    out = tmp_path / 'out.csv'
    assert cli.main(['run', '--params', str(berth / 'berth.yaml'), '--motion',
                     str(berth / 'ship.csv'), '--commands', str(commands), '--out', str(out),
                     '--quiet']) == 2
    err = capsys.readouterr().err
    assert err.startswith(f'rope_sim run: error: {commands}: ') and err.count('\n') == 1, err
    assert message in err
    assert not out.exists()  # refused before anything ran


@pytest.mark.parametrize('text, message', [
    ('t,line,bollard\n1.0,head,\n', 'file line 1 (header): missing column(s) command; the '
     'header must name t, line, command and optionally bollard (found: t, line, bollard)'),
    ('t,line,command\n', 'the header has no data rows after it'),
])
def test_a_commands_file_without_its_columns_or_rows_is_refused(berth, tmp_path, capsys,
                                                                text, message):
    commands = tmp_path / 'commands.csv'
    commands.write_text(text)
    assert cli.main(['run', '--params', str(berth / 'berth.yaml'), '--motion',
                     str(berth / 'ship.csv'), '--commands', str(commands), '--out',
                     str(tmp_path / 'out.csv')]) == 2
    err = capsys.readouterr().err
    assert err == f'rope_sim run: error: {commands}: {message}\n'


def test_a_missing_commands_file_is_one_line(berth, tmp_path, capsys):
    missing = tmp_path / 'nowhere.csv'
    assert cli.main(['run', '--params', str(berth / 'berth.yaml'), '--motion',
                     str(berth / 'ship.csv'), '--commands', str(missing), '--out',
                     str(tmp_path / 'out.csv')]) == 2
    assert capsys.readouterr().err == (f'rope_sim run: error: cannot read commands file '
                                       f'{missing}: No such file or directory\n')


def test_a_single_line_let_go_and_made_fast_again(tmp_path, capsys):
    # the default line (40 m polyester from a bollard at the origin), its fairlead held
    # 39 m off; the single line has no name: the line cells are empty
    motion = tmp_path / 'motion.csv'
    motion.write_text('t,fairlead_x,fairlead_y,fairlead_z\n0,39,0,0\n4,39,0,0\n')
    commands = tmp_path / 'commands.csv'
    commands.write_text('t,line,command\n1.0,,let_go\n2.0,,make_fast\n')
    out = tmp_path / 'out.csv'
    assert cli.main(['run', '--motion', str(motion), '--commands', str(commands), '--out',
                     str(out), '--rate', '10', '--quiet', '--set', 'segments=8']) == 0
    rows = read_rows(out)
    t, state = column(rows, 't'), column(rows, 'state', str)
    tension = column(rows, 'fairlead_tension')
    assert list(state[(t > 0.95) & (t < 2.25)]) == ['fast'] + ['free'] * 10 + ['fast'] * 2
    hanging = tension[t == 1.0][0]
    assert hanging == pytest.approx(1454.16, rel=1e-5)  # its sag's pull, fast
    # free, its eye end pulls 61 .. 147 N: no bollard holds it
    assert column(rows, 'bollard_tension')[(t > 1.05) & (t < 2.05)].max() < 0.15 * hanging
    # made fast again with the 40 m it has out, at rest: the same catenary as before
    assert column(rows, 'line_length')[t > 2.05] == pytest.approx(40.0, abs=1e-12)
    assert tension[t > 2.05] == pytest.approx(hanging, rel=1e-6)  # measured 2e-10
    capsys.readouterr()
    # a single line's command names no line
    commands.write_text('t,line,command\n1.0,head,let_go\n')
    assert cli.main(['run', '--motion', str(motion), '--commands', str(commands), '--out',
                     str(out), '--quiet']) == 2
    assert ("column 'line': 'head', but the single line has no name: leave the line empty"
            in capsys.readouterr().err)


def test_a_quick_release_hook_lets_go_by_itself_and_is_recorded(berth, tmp_path, capsys):
    # the ship drawn off the quay (-y) 1 cm/s: head's tension passes its release_load
    ship = tmp_path / 'ship.csv'
    with open(ship, 'w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(['t', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw'])
        for i in range(21):
            writer.writerow([i * 0.25, 0, -0.0025 * i, 0, 0, 0, 0, 1])
    out, bag = tmp_path / 'out.csv', tmp_path / 'bag'
    assert cli.main(['run', '--params', str(berth / 'berth.yaml'), '--motion', str(ship),
                     '--out', str(out), '--bag', str(bag), '--rate', str(RATE), '--quiet',
                     '--set', 'head.release_load=60000']) == 0
    rows = read_rows(out)
    t, state = column(rows, 't'), column(rows, 'head_state', str)
    [(stamp, released)] = bag_events(bag)
    assert released['event'] == 'released' and released['line'] == 'head'
    assert released['t'] == pytest.approx(stamp, abs=1e-9)
    assert released['tension'] > 60000.0
    assert set(state[t < stamp - 1e-9]) == {'fast'} and set(state[t > stamp - 1e-9]) == {'free'}
    # the row the hook let go in has about the tension it let go at as its peak
    [peak] = column(rows, 'head_bollard_peak_tension')[np.abs(t - stamp) < 1e-9]
    assert released['tension'] <= peak < released['tension'] * (1.0 + 1e-6)  # 4e-8
    assert column(rows, 'head_bollard_tension')[t < stamp - 1e-9].max() < 60000.0
    err = capsys.readouterr().err
    assert (f'rope_sim: warning: t = {stamp:.3f} s: line head let go by its quick-release '
            f'hook at {released["tension"] / 1e3:.1f} kN (release_load 60 kN)\n') in err
    assert read_record(bag).marks == ((pytest.approx(stamp, abs=1e-9), 'head released'),)


def test_the_commands_a_node_recorded_are_read_back_as_it_took_them(tmp_path):
    # a mooring node's events, as it records them: let_go_all's line '', a bollard set
    # before a make fast; the other events are not commands
    events = [encode_event('winch', line='head', speed=-0.5, t=1.0),
              encode_event('set', line='stern', values={'bollard': 'bollard_3'}),
              encode_event('set', line='head', values={'winch_tension': 5.0e4}),
              encode_event('command', line='stern', command='make_fast', t=4.0, text='...'),
              encode_event('command', line='head', command='stow', t=5.0, text='...',
                           refused=True),
              encode_event('released', line='head', tension=7.0e4, t=6.0),
              encode_event('command', line='', command='let_go_all', t=8.0, text='...')]
    with BagWriter(tmp_path / 'node') as writer:
        writer.add_topic('/mooring/events', 'std_msgs/msg/String')
        for k, text in enumerate(events):
            writer.write('/mooring/events', cdr.string(text), k * 1_000_000_000)
    assert recorded_commands(tmp_path / 'node', '/mooring/events') == [
        ScheduledCommand(4.0, 'stern', 'make_fast', 'bollard_3'),
        ScheduledCommand(5.0, 'head', 'stow', ''),
        ScheduledCommand(8.0, '', 'let_go_all', '')]
