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
rope_sim run, resim, plot and info of an arrangement (config/berth.yaml, a ship motion).

The first 20 s of the demo's passing ship (it starts at 8 s) through the eight lines of
the berth, at 20 Hz.
"""

import csv
import math
import re

import numpy as np
import pytest
from rope_sim_ros.bag import read_messages
from rope_sim_ros.bag.cdr import decode_float64
from rope_sim_ros.mooring import scenario
from rope_sim_ros.mooring.driver import Driver
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.motion import MotionError, read_ship_motion
from rope_sim_ros.offline.plot import read_tensions
from rope_sim_ros.params import arrangement

RATE = 20.0
SECONDS = 20.0


def decode_tensions(path, line: str) -> np.ndarray:
    """Return one line's recorded fairlead tensions in order."""
    return read_tensions(path, f'/{line}')['fairlead'].tension


@pytest.fixture(scope='module')
def berth_run(tmp_path_factory, repo_root):
    """Run the berth through 20 s of the passing ship: OUT.csv and a bag."""
    folder = tmp_path_factory.mktemp('berth')
    ship = folder / 'ship.csv'
    with open(ship, 'w', newline='') as f:
        writer = csv.writer(f)
        writer.writerow(['t', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw'])
        for row in scenario.motion_rows(SECONDS, RATE):
            writer.writerow([repr(v) for v in row])
    params = repo_root / 'config' / 'berth.yaml'
    code = cli.main(['run', '--params', str(params), '--motion', str(ship), '--out',
                     str(folder / 'out.csv'), '--bag', str(folder / 'bag'), '--rate',
                     str(RATE), '--quiet'])
    assert code == 0
    with open(folder / 'out.csv', newline='') as f:
        rows = list(csv.DictReader(f))
    return folder, params, ship, rows


def test_run_writes_every_line_and_the_wrench(berth_run):
    _, params, ship, rows = berth_run
    setup = arrangement.read_arrangement_file(params)
    assert len(rows) == SECONDS * RATE + 1
    first, last = rows[0], rows[-1]
    for name in setup.names:
        # pretension: 10 % of the MBL at the start, within the 30 segments' discretisation
        assert float(first[f'{name}_utilisation']) == pytest.approx(0.10, abs=2e-3), name
    springs = [float(row['spring_fwd_utilisation']) for row in rows]
    assert 0.3 < max(springs) < 0.5  # the passer pushes the ship ahead: the spring takes it
    # the same numbers as the driver gives, row by row
    driver = Driver(setup, rate=RATE)
    motion = read_ship_motion(ship)
    outputs = []
    for i in range(len(motion)):
        driver.push_ship(int(motion.t_ns[i]), motion.position[i], motion.orientation[i])
        outputs += driver.advance(math.inf, max_lag=math.inf).outputs
    k = setup.names.index('spring_fwd')
    length = driver.arrangement.lines[k].params.length  # chosen for its pretension
    for row, published in zip(rows, outputs):
        out = published.output
        assert float(row['t']) == pytest.approx(out.t, abs=1e-6)
        assert float(row['spring_fwd_tension']) == pytest.approx(
            out.fairlead_tensions[k], rel=1e-5)
        assert float(row['force_x']) == pytest.approx(published.force[0], rel=1e-5, abs=1.0)
        # as the single-line OUT.csv: the peaks since the previous row, the length, parted
        peak = float(row['spring_fwd_fairlead_peak_tension'])
        assert peak == pytest.approx(out.fairlead_peaks[k], rel=1e-5)
        assert peak >= float(row['spring_fwd_tension'])
        assert float(row['spring_fwd_bollard_peak_tension']) == pytest.approx(
            out.bollard_peaks[k], rel=1e-5)
        assert float(row['spring_fwd_line_length']) == pytest.approx(length, rel=1e-5)
        assert row['spring_fwd_parted'] == '0.0'  # written as every number: repr(float)
    assert float(last['moment_z']) != 0.0


def test_the_bag_holds_the_peaks_lengths_and_parted(berth_run):
    folder, params, _, rows = berth_run
    setup = arrangement.read_arrangement_file(params)
    for name in setup.names:
        messages = {topic: list(read_messages(folder / 'bag', [f'/{name}/{topic}']))
                    for topic in ('fairlead/peak_tension', 'winch/length', 'rope/parted')}
        peaks = [decode_float64(m.data) for m in messages['fairlead/peak_tension']]
        assert peaks == pytest.approx(
            [float(row[f'{name}_fairlead_peak_tension']) for row in rows], rel=1e-5)
        assert len(messages['winch/length']) == len(rows)
        assert [m.data[-1] for m in messages['rope/parted']] == [0]  # once: not parted


def test_info_lists_every_lines_peak(berth_run, capsys):
    folder, params, _, rows = berth_run
    assert cli.main(['info', str(folder / 'bag')]) == 0
    text = capsys.readouterr().out
    setup = arrangement.read_arrangement_file(params)
    for name in setup.names:
        line = next(t for t in text.splitlines() if t.strip().startswith(name + ' '))
        peak = max(float(row[f'{name}_tension']) for row in rows)
        assert f'{peak / 1e3:9.1f} kN' in line, line
        assert 'below the WLL' in line
    assert 'peak horizontal force on the ship' in text


def test_resim_of_the_bag_gives_the_same_tensions(berth_run, tmp_path):
    folder, params, _, _ = berth_run
    assert cli.main(['resim', str(folder / 'bag'), '--out', str(tmp_path / 'again'),
                     '--quiet']) == 0
    setup = arrangement.read_arrangement_file(params)
    for name in setup.names:
        before = decode_tensions(folder / 'bag', name)
        after = decode_tensions(tmp_path / 'again', name)
        assert len(before) == len(after) == SECONDS * RATE + 1
        assert np.array_equal(before, after), name


def test_plot_draws_the_tensions_and_the_berth(berth_run, tmp_path, capsys):
    folder, _, _, _ = berth_run
    assert cli.main(['plot', str(folder / 'bag'), '-o', str(tmp_path / 'berth.png')]) == 0
    for name in ('berth.png', 'berth_plan.png'):
        assert (tmp_path / name).stat().st_size > 20_000


def test_set_overrides_a_line_setting(berth_run, tmp_path):
    _, params, ship, _ = berth_run
    assert cli.main(['run', '--params', str(params), '--motion', str(ship), '--out',
                     str(tmp_path / 'out.csv'), '--rate', str(RATE), '--quiet',
                     '--set', 'spring_fwd.pretension=282000', '--set',
                     'spring_aft.segments=10']) == 0
    with open(tmp_path / 'out.csv', newline='') as f:
        first = next(csv.DictReader(f))
    assert float(first['spring_fwd_utilisation']) == pytest.approx(0.20, abs=2e-3)


def test_ship_motion_with_a_yaw_column(tmp_path):
    path = tmp_path / 'yaw.csv'
    path.write_text('t,x,y,z,yaw\n0,0,-17.6,0,0\n0.1,0.01,-17.6,0,0.5\n')
    motion = read_ship_motion(path)
    assert motion.orientation[1] == pytest.approx([0, 0, math.sin(0.25), math.cos(0.25)])
    assert motion.t_ns.tolist() == [0, 100_000_000]


@pytest.mark.parametrize('text, message', [
    ('t,x,y\n0,0,0\n', 'missing column(s) z'),
    ('t,x,y,z\n0,0,0,0\n1,0,nan,0\n', "data row 2 (file line 3), column 'y'"),
    ('t,x,y,z\n0,0,0,0\n0,1,0,0\n', "data row 2 (file line 3), column 't': 0 is not after"),
    ('t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,0\n', 'zero quaternion'),
])
def test_bad_ship_motion_is_one_line(tmp_path, capsys, repo_root, text, message):
    path = tmp_path / 'bad.csv'
    path.write_text(text)
    with pytest.raises(MotionError, match=re.escape(message)):
        read_ship_motion(path)
    code = cli.main(['run', '--params', str(repo_root / 'config' / 'berth.yaml'), '--motion',
                     str(path), '--out', str(tmp_path / 'out.csv')])
    err = capsys.readouterr().err.strip()
    assert code == 2 and '\n' not in err and message in err, err


def test_a_single_line_file_for_every_node_is_not_an_arrangement(tmp_path, repo_root):
    from rope_sim_ros.params.arrangement import is_arrangement_file
    single = tmp_path / 'any_node.yaml'
    single.write_text('/**:\n  ros__parameters:\n    length: 40.0\n')
    assert not is_arrangement_file(single)
    assert not is_arrangement_file(repo_root / 'config' / 'mooring_line.yaml')
    assert is_arrangement_file(repo_root / 'config' / 'berth.yaml')
