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

"""rope_sim run of a free ship: --loads LOADS.csv --duration T, its motion in OUT.csv."""

import csv
import math

import pytest

from rope_sim_ros.offline import cli
from rope_sim_ros.offline.sinks import FENDER_COLUMNS, LOAD_COLUMNS, SHIP_COLUMNS, STATE_COLUMN

FREE_BERTH = """/**/mooring:
  ros__parameters:
    lines: [head, stern]
    ship_mode: free
    ship:
      start_position: [0.0, -17.6, 0.0]
    fenders: [fender_a]
    fender_a: {position: [0.0, -1.5, 0.0], normal: [0.0, -1.0, 0.0],
               curve: [0.5, 5.0e5, 1.0, 1.2e6]}
    segments: 8
    head: {material: polyester, fairlead_offset: [106.0, 13.0, 10.0],
           bollard_position: [150.0, 3.0, 3.5], pretension: 126000.0}
    stern: {material: polyester, fairlead_offset: [-104.0, 13.0, 10.0],
            bollard_position: [-150.0, 3.0, 3.5], pretension: 126000.0}
"""
# a push ahead ramped in over 2 s, then held
LOADS = """t,force_x,force_y,force_z,moment_x,moment_y,moment_z
0,0,0,0,0,0,0
2,200000,0,0,0,0,0
"""


@pytest.fixture
def files(tmp_path):
    params = tmp_path / 'free.yaml'
    params.write_text(FREE_BERTH)
    loads = tmp_path / 'loads.csv'
    loads.write_text(LOADS)
    return params, loads, tmp_path / 'out.csv'


def test_a_free_ship_runs_under_its_loads_into_out_csv(files):
    params, loads, out = files
    assert cli.main(['run', '--params', str(params), '--loads', str(loads), '--duration', '6',
                     '--rate', '10', '--out', str(out), '--quiet']) == 0
    with open(out, newline='') as stream:
        rows = list(csv.reader(stream))
    header = rows[0]
    states = [i for i, name in enumerate(header) if name.endswith(f'_{STATE_COLUMN}')]
    assert [header[i] for i in states] == [f'{line}_{STATE_COLUMN}' for line in ('head', 'stern')]
    assert {row[i] for row in rows[1:] for i in states} == {'fast'}
    data = [[math.nan if i in states else float(v) for i, v in enumerate(row)]
            for row in rows[1:]]
    ship = header.index('x')
    assert header[ship:ship + len(SHIP_COLUMNS)] == list(SHIP_COLUMNS)
    fender = ship + len(SHIP_COLUMNS)
    assert header[fender:fender + 2] == [f'fender_a_{column}' for column in FENDER_COLUMNS]
    assert header[fender + 2:] == list(LOAD_COLUMNS)
    assert len(data) == 61 and data[0][0] == 0.0 and data[-1][0] == 6.0
    column = {name: i for i, name in enumerate(header)}
    first, last = data[0], data[-1]
    assert (first[column['x']], first[column['y']]) == (0.0, -17.6)  # at rest at its start
    assert first[column['qw']] == 1.0
    assert last[column['x']] > 1e-3  # pushed ahead
    assert last[column['vx']] > 0.0
    # the stern line, which the push stretches, pulls harder than at the start
    assert last[column['stern_tension']] > first[column['stern_tension']] + 1e3
    # the current's load on a ship moving in still water: its drag, against the motion
    assert last[column['current_force_x']] < 0.0
    assert last[column['wind_force_x']] == 0.0 and last[column['passing_force_y']] == 0.0


@pytest.mark.parametrize('arguments, message', [
    (['--duration', '5'], None),
    (['--motion', 'SHIP.csv', '--duration', '5'], 'takes no --motion'),
    ([], 'needs --duration S'),
])
def test_a_free_run_refuses_a_motion_or_no_duration(files, capsys, arguments, message):
    params, _, out = files
    code = cli.main(['run', '--params', str(params), '--out', str(out), '--quiet', *arguments])
    if message is None:  # no loads: the ship rests against its fender, lines pulling
        assert code == 0
        return
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count('\n') == 1, err


def test_a_driven_ship_refuses_loads(files, tmp_path, capsys):
    params, loads, out = files
    params.write_text(FREE_BERTH.replace('ship_mode: free', 'ship_mode: driven'))
    code = cli.main(['run', '--params', str(params), '--loads', str(loads), '--out', str(out),
                     '--motion', str(loads), '--quiet'])
    err = capsys.readouterr().err
    assert code == 2 and '--loads and --duration are for a free ship' in err, err


def test_a_load_no_tug_gives_is_refused_naming_its_row(files, capsys):
    params, loads, out = files
    loads.write_text(LOADS + '4,1e12,0,0,0,0,0\n')  # 11 km/s^2 on this ship
    code = cli.main(['run', '--params', str(params), '--loads', str(loads), '--duration', '6',
                     '--out', str(out), '--quiet'])
    err = capsys.readouterr().err
    assert code == 2 and err.count('\n') == 1, err
    assert 'row 3 (t = 4 s): an external force of 1e+12 N is more than any tug or thruster ' \
        'gives this ship: at most 8.67e+07 N' in err, err
    assert not out.exists()


def test_a_free_ship_takes_its_commands_at_their_times(files, tmp_path, capsys):
    params, loads, out = files
    commands = tmp_path / 'commands.csv'
    commands.write_text('t,line,command\n1.0,head,let_go\n2.0,stern,stow\n')
    assert cli.main(['run', '--params', str(params), '--loads', str(loads), '--duration', '3',
                     '--rate', '10', '--out', str(out), '--commands', str(commands),
                     '--quiet']) == 0
    with open(out, newline='') as stream:
        rows = list(csv.DictReader(stream))
    t = [float(row['t']) for row in rows]
    head = [(row['head_state'], float(row['head_tension'])) for row in rows]
    assert {state for state, _ in head[:t.index(1.0) + 1]} == {'fast'}
    assert {state for state, _ in head[t.index(1.0) + 1:]} == {'free'}
    assert head[t.index(1.0)][1] == pytest.approx(126000.0, rel=0.01)  # its pretension
    # its pull gone: it hangs from the fairlead, at most 2.7 kN, 2.2 % of its pretension
    assert max(tension for _, tension in head[t.index(1.0) + 1:]) < 0.05 * 126000.0
    assert {row['stern_state'] for row in rows} == {'fast'}
    assert capsys.readouterr().err == (
        'rope_sim: warning: t = 2.000 s: stow refused: line stern is fast on its bollard: '
        'only a line let go and heaved in can be stowed\n')
