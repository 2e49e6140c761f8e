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
`rope_sim study` through the installed rope_sim, as a user runs it.

The installed rope_sim is what `ros2 run rope_sim_ros rope_sim study ...` runs. Dask starts a
study's local workers as new interpreters that import the parent's main file first: there the
launcher (bin/launcher), which must not run the command line again.
"""

import csv
import subprocess

from test_study import write_study

PACKAGE = 'rope_sim_ros'
MATERIALS = ('hmpe', 'polyester')
FACTORS = f'  factors:\n    spring_fwd.material: [{", ".join(MATERIALS)}]\n'


def test_a_study_runs_from_the_installed_rope_sim(colcon_install, colcon_env, tmp_path):
    study = write_study(tmp_path, FACTORS)
    out = tmp_path / 'out'
    result = subprocess.run(
        [str(colcon_install / 'lib' / PACKAGE / 'rope_sim'), 'study', str(study), '--out',
         str(out), '--workers', '2'],
        env=colcon_env, cwd=str(tmp_path), stdin=subprocess.DEVNULL, capture_output=True,
        text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr[-3000:]
    lines = result.stdout.splitlines()
    first = f'{study}: 2 cases (2 factorial), 4 s each; 2 to run -> {out}'
    assert lines.count(first) == 1, result.stdout  # said once: no worker ran it again
    assert lines[1].startswith('workers: a local cluster of 2 processes, 1 thread each'), \
        result.stdout
    assert '2 of 2 cases done (2 now, 0 before): 2 ok' in result.stdout, result.stdout
    with open(out / 'results.csv', newline='') as stream:
        rows = list(csv.DictReader(stream))
    assert [row['spring_fwd.material'] for row in rows] == list(MATERIALS)
    assert [row['status'] for row in rows] == ['ok', 'ok']
    assert all(0.0 < float(row['spring_fwd_max_tension']) < 2.0e6 for row in rows), rows
