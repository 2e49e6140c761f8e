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
Waves through the installed rope_sim, as a user runs it (`ros2 run rope_sim_ros rope_sim`).

`rope_sim hydro` solves a small box's database and writes it; `rope_sim run` moves the
berth's free ship with the shipped database of its hull in a regular wave, OUT.csv holding
the waves' columns.
"""

import csv
import math
import subprocess

from rope_sim_ros.params.hydro_file import read_hydro_database
from test_hydro_database import BERTH, BOX, REPO_ROOT

PACKAGE = 'rope_sim_ros'
DATABASE = REPO_ROOT / 'test' / 'data' / 'hydro' / 'berth_ship.nc'


def rope_sim(colcon_install, colcon_env, cwd, *args):
    return subprocess.run([str(colcon_install / 'lib' / PACKAGE / 'rope_sim'), *args],
                          env=colcon_env, cwd=str(cwd), stdin=subprocess.DEVNULL,
                          capture_output=True, text=True, timeout=300)


def test_hydro_writes_a_database_the_nodes_read(colcon_install, colcon_env, tmp_path):
    sets = []
    for key, value in BOX.items():
        sets += ['--set', f'{key}={value}'.replace('-inf', '-.inf')]
    out = tmp_path / 'box.nc'
    result = rope_sim(colcon_install, colcon_env, tmp_path, 'hydro', BERTH, '--out', str(out),
                      *sets, '--omega', '0.5', '1.0', '2', '--heading-step', '90',
                      '--panel-size', '2')
    assert result.returncode == 0, result.stderr[-3000:]
    record = read_hydro_database(out)
    assert record.omega.tolist() == [0.5, 1.0]
    assert record.headings.size == 5  # -180, -90, 0, 90, 180
    # the box's heave added mass is of the order of its displaced mass (2 m draft, 20 m x 4 m)
    assert 0.2 < record.added_mass[0, 2, 2] / BOX['ship.mass'] < 5.0


def test_run_moves_the_free_ship_in_a_regular_wave(colcon_install, colcon_env, tmp_path):
    out = tmp_path / 'out.csv'
    result = rope_sim(colcon_install, colcon_env, tmp_path, 'run', '--params', BERTH,
                      '--set', 'ship_mode=free', '--set', f'ship.hydrodynamics={DATABASE}',
                      '--set', 'waves.spectrum=regular', '--set', 'waves.height=1.0',
                      '--set', 'waves.period=8.0', '--set', 'waves.direction=-1.5708',
                      '--duration', '4', '--rate', '10', '--out', str(out), '--quiet')
    assert result.returncode == 0, result.stderr[-3000:]
    # the database beside ship.linear_damping's defaults (the waves' damping twice): said once
    assert result.stderr.count('ship.linear_damping is at its defaults') == 1, result.stderr
    with open(out, newline='') as stream:
        rows = list(csv.DictReader(stream))
    assert len(rows) == 41
    elevation = [float(row['wave_elevation']) for row in rows]
    # a 1 m wave at the ship's origin: within its amplitude, and it swings across it
    assert max(abs(e) for e in elevation) <= 0.5 + 1e-9
    assert max(elevation) - min(elevation) > 0.5
    heave = [float(row['wave_force_z']) for row in rows]
    assert all(math.isfinite(f) for f in heave) and max(heave) - min(heave) > 1e6
