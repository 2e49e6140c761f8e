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
Waves on a moored free ship: their parameters, OUT.csv columns, topics and run-time changes.

The ship's hydrodynamic database is test_waves.py's synthetic one, given to the ship where
it takes its database (mooring.ship.hydrodynamics).
"""

import csv
import math

import numpy as np
import pytest
from rope_sim_ros.bag import cdr
from rope_sim_ros.messages import topics
from rope_sim_ros.messages.encode import encoder_for
from rope_sim_ros.model.frames import rotation_matrix
from rope_sim_ros.model.ship.waves import ShipWaves, Waves
from rope_sim_ros.mooring import ship as mooring_ship
from rope_sim_ros.mooring.driver import Driver
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.sinks import LOAD_COLUMNS, WAVE_COLUMNS
from rope_sim_ros.params.arrangement import from_values, read_setup
from rope_sim_ros.params.table import ParameterError
from test_cli_free import FREE_BERTH
from test_waves import database

REGULAR = '    waves: {spectrum: regular, height: 2.0, period: 8.0, direction: 1.2}\n'


@pytest.fixture
def hull(monkeypatch):
    """Give the ship the synthetic database."""
    monkeypatch.setattr(mooring_ship, 'hydrodynamics', lambda setup: database())


def run(tmp_path, text, name='out.csv', duration='4'):
    params = tmp_path / f'{name}.yaml'
    params.write_text(text)
    out = tmp_path / name
    code = cli.main(['run', '--params', str(params), '--duration', duration, '--rate', '10',
                     '--out', str(out), '--quiet'])
    return code, out


def table(out):
    with open(out, newline='') as stream:
        rows = list(csv.reader(stream))
    header = rows[0]
    numbers = [[float(v) if not v.isalpha() else math.nan for v in row] for row in rows[1:]]
    return header, np.array(numbers)


def test_out_csv_has_the_waves_at_the_ships_pose(hull, tmp_path):
    code, out = run(tmp_path, FREE_BERTH + REGULAR)
    assert code == 0
    header, data = table(out)
    assert header[-len(WAVE_COLUMNS):] == list(WAVE_COLUMNS)
    assert header[-len(WAVE_COLUMNS) - len(LOAD_COLUMNS):-len(WAVE_COLUMNS)] == \
        list(LOAD_COLUMNS)
    column = {name: i for i, name in enumerate(header)}
    setup = read_setup(tmp_path / 'out.csv.yaml')
    depth = mooring_ship.water_depth(setup.shared)
    waves = Waves.make('regular', 2.0, 8.0, 1.2, 3.3, 0, depth, 9.81)
    loads = ShipWaves(database())
    for row in data[::7]:
        t, x, y = row[0], row[column['x']], row[column['y']]
        rotation = rotation_matrix(row[[column[c] for c in ('qx', 'qy', 'qz', 'qw')]])
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        elevation, expected = loads.at(t, waves, [x, y, 0.0], yaw)
        assert row[column['wave_elevation']] == pytest.approx(elevation, abs=1e-12)
        got = row[[column[c] for c in WAVE_COLUMNS[1:]]]
        np.testing.assert_allclose(got, [*expected[0], *expected[1, [0, 1, 5]]],
                                   rtol=1e-9, atol=1e-6)
    # a 2 m wave of 8 s: over 4 s its elevation at the ship spans half a period
    assert np.ptp(data[:, column['wave_elevation']]) > 1.4
    # and the ship moves under them (no other load moves it: it starts at rest)
    assert np.abs(data[:, column['y']] - data[0, column['y']]).max() > 1e-4


def test_waves_none_change_nothing_to_the_bit(hull, tmp_path):
    code, plain = run(tmp_path, FREE_BERTH, 'plain.csv', '3')
    assert code == 0
    calm = '    waves: {spectrum: none, height: 2.0, period: 6.0, direction: 1.0, seed: 4}\n'
    code, none = run(tmp_path, FREE_BERTH + calm, 'none.csv', '3')
    assert code == 0
    assert none.read_bytes() == plain.read_bytes()
    assert 'wave_elevation' not in plain.read_text().splitlines()[0]


def test_waves_without_a_database_are_refused(tmp_path, capsys):
    code, out = run(tmp_path, FREE_BERTH + REGULAR)
    assert code == 2
    error = capsys.readouterr().err.strip()
    assert error == ('rope_sim run: error: waves need ship.hydrodynamics: waves.spectrum is '
                     "'regular' but the ship has no hydrodynamic database (the file `rope_sim "
                     'hydro` writes); set it, or waves.spectrum: none')
    assert not out.exists()


def test_a_sea_the_database_does_not_cover_is_refused(hull, tmp_path, capsys):
    short = REGULAR.replace('period: 8.0', 'period: 1.5')  # 4.2 rad/s, the table ends at 3
    code, _ = run(tmp_path, FREE_BERTH + short)
    assert code == 2
    assert ("waves: 100% of the sea's energy lies outside the frequencies of the "
            'hydrodynamic database (0.2 to 3 rad/s)') in capsys.readouterr().err


@pytest.mark.parametrize('name, value, message', [
    ('waves.spectrum', 'storm', "parameter 'waves.spectrum' = 'storm' is not allowed"),
    ('waves.height', -1.0, "parameter 'waves.height' = -1.0 is not allowed"),
    ('waves.period', 0.5, "parameter 'waves.period' = 0.5 is not allowed"),
    ('waves.peak_enhancement', 0.5, "parameter 'waves.peak_enhancement' = 0.5 is not allowed"),
    ('waves.heigth', 1.0, "unknown parameter 'waves.heigth'; waves takes: waves.spectrum, "
                          'waves.height, waves.period, waves.direction, '
                          'waves.peak_enhancement, waves.seed'),
])
def test_bad_wave_parameters_are_refused(name, value, message):
    values = {'lines': ['head'], 'head': {'fairlead_offset': [1.0, 0.0, 0.0],
                                          'bollard_position': [30.0, 0.0, 0.0],
                                          'length': 30.0}, name: value}
    with pytest.raises(ParameterError, match='^' + message.replace('(', r'\(')):
        from_values(values)


def test_waves_change_at_run_time_like_the_wind(hull, repo_root):
    setup = read_setup(repo_root / 'config' / 'berth.yaml',
                       {'ship_mode': 'free', 'segments': 8, 'waves.spectrum': 'jonswap',
                        'waves.seed': 3})
    driver = Driver(setup)
    driver.start_free(0)
    mooring = driver.mooring
    assert mooring.environment.waves.sea is None  # height 0: calm
    assert not driver.advance(0.0).outputs[-1].output.wave_loads.any()
    driver.update(None, {'waves.height': 2.5, 'waves.period': 9.0, 'waves.direction': 0.5})
    waves = mooring.environment.waves
    assert (waves.height, waves.period, waves.direction, waves.seed) == (2.5, 9.0, 0.5, 3)
    assert driver.arrangement.ship.waves_height == 2.5
    assert all(group.system.environment is mooring.environment for group in mooring.groups)
    mooring.advance_to(0.5)
    output = mooring.output()
    assert np.abs(output.wave_loads[0]).max() > 1e3 and output.wave_elevation != 0.0
    with pytest.raises(ParameterError, match='outside the frequencies'):
        driver.update(None, {'waves.period': 1.2})
    assert mooring.environment.waves.period == 9.0  # nothing changed


def test_the_wave_topics_are_outputs_only_with_waves(hull, repo_root):
    calm = read_setup(repo_root / 'config' / 'berth.yaml', {'ship_mode': 'free'})
    assert topics.WAVE_WRENCH not in encoder_for(calm).types
    setup = read_setup(repo_root / 'config' / 'berth.yaml',
                       {'ship_mode': 'free', 'segments': 8, 'waves.spectrum': 'regular',
                        'waves.height': 2.0})
    encoder = encoder_for(setup)
    assert encoder.types[topics.WAVE_WRENCH] == topics.WRENCH_STAMPED
    assert encoder.types[topics.WAVE_ELEVATION] == topics.FLOAT64
    assert encoder.has_header(topics.WAVE_WRENCH)
    assert not encoder.has_header(topics.WAVE_ELEVATION)
    driver = Driver(setup)
    driver.start_free(0)
    driver.mooring.advance_to(1.0)
    published = driver.advance(1.1).outputs[-1]
    out = published.output
    built = dict(encoder.messages(published, [topics.WAVE_WRENCH, topics.WAVE_ELEVATION]))
    total = out.wave_loads.sum(axis=0)  # first order and drift together
    sec, nanosec = divmod(published.stamp_ns, 10 ** 9)
    assert built[topics.WAVE_WRENCH] == cdr.wrench_stamped(
        sec, nanosec, setup.ship_frame_id, total[:3], total[3:])
    assert built[topics.WAVE_ELEVATION] == cdr.float64(out.wave_elevation)
    assert out.wave_loads[1, 0] != 0.0 and out.wave_loads[1, 2:5].tolist() == [0.0] * 3


def test_the_default_damping_beside_a_database_is_warned_of(repo_root, tmp_path, capsys):
    # The defaults stand for the whole damping of a ship without a database; with one its
    # radiation memory counts the waves' part a second time: said once, at the start.
    database = repo_root / 'test' / 'data' / 'hydro' / 'berth_ship.nc'
    berth = repo_root / 'config' / 'berth.yaml'
    start = ['run', '--params', str(berth), '--set', 'ship_mode=free', '--duration', '0.2',
             '--rate', '10', '--quiet']
    viscous = '[0.0, 0.0, 0.0, 6.0e8, 0.0, 0.0]'  # the roll's viscous damping alone
    cases = ((['--set', f'ship.hydrodynamics={database}'], 1),
             (['--set', f'ship.hydrodynamics={database}', '--set',
               f'ship.linear_damping={viscous}'], 0),
             ([], 0))
    for k, (extra, warnings) in enumerate(cases):
        assert cli.main([*start, *extra, '--out', str(tmp_path / f'{k}.csv')]) == 0
        said = capsys.readouterr().err
        assert said.count('ship.linear_damping is at its defaults') == warnings, said
    setup = read_setup(berth, {'ship_mode': 'free', 'ship.hydrodynamics': str(database)})
    assert 'give ship.linear_damping the viscous part alone' in \
        mooring_ship.damping_advice(setup)
