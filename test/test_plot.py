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

"""``rope_sim plot``, ``info`` and ``recover`` on a bag written by ``rope_sim run --bag``."""

import csv
import math
import re

from matplotlib import image
import numpy as np
import pytest
from rope_sim_ros.bag import bag_info, BagWriter, cdr
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.plot import read_tensions
from rope_sim_ros.offline.sinks import STATE_COLUMN


@pytest.fixture(scope='module')
def recorded(tmp_path_factory):
    base = tmp_path_factory.mktemp('plot')
    motion = base / 'motion.csv'
    lines = ['t,fairlead_x,fairlead_y,fairlead_z']
    for k in range(201):
        t = k * 0.01
        lines.append(f'{t:.2f},{36.0 + 0.5 * (1 - math.cos(math.pi * t)):.6f},0,8')
    motion.write_text('\n'.join(lines) + '\n')
    out, bag = base / 'out.csv', base / 'run'
    assert cli.main(['run', '--motion', str(motion), '--out', str(out), '--bag', str(bag),
                     '--quiet', '--set', 'segments=10']) == 0
    with open(out, newline='') as f:
        rows = [{k: float(v) for k, v in row.items() if k != STATE_COLUMN}
                for row in csv.DictReader(f)]
    return base, bag, rows


def test_plot_writes_a_png(recorded, capsys):
    base, bag, _ = recorded
    png = base / 'tension.png'
    assert cli.main(['plot', str(bag), '-o', str(png)]) == 0
    assert capsys.readouterr().out.strip() == str(png)
    assert png.stat().st_size > 20_000
    pixels = image.imread(str(png))
    assert pixels.shape[:2] == (800, 1000)
    assert pixels.std() > 0.05  # not a blank canvas


def test_plot_with_other_params_and_bad_input(recorded, tmp_path, capsys):
    base, bag, _ = recorded
    png = tmp_path / 'wire.png'
    assert cli.main(['plot', str(bag), '-o', str(png), '--set', 'material=steel_wire',
                     '--shapes', '3']) == 0
    assert image.imread(str(png)).shape[:2] == (800, 1000)
    capsys.readouterr()
    assert cli.main(['plot', str(tmp_path / 'nothing'), '-o', str(png)]) == 2
    err = capsys.readouterr().err
    assert 'does not exist' in err and err.count('\n') == 1


def test_info_counts_duration_and_peaks(recorded, capsys):
    _, bag, rows = recorded
    assert cli.main(['info', str(bag)]) == 0
    text = capsys.readouterr().out
    counts = dict(re.findall(r'^\s+(/\S+)\s+\S+\s+(\d+)$', text, re.M))
    # the node's outputs: the peaks and the winch's length at each, parted (latched) once
    assert counts == {'/fairlead/pose': '201', '/rope/particles': '201',
                      '/fairlead/tension': '201', '/bollard/tension': '201',
                      '/fairlead/peak_tension': '201', '/bollard/peak_tension': '201',
                      '/winch/length': '201', '/rope/parted': '1'}
    assert 'duration:  2.000 s' in text and 'messages:  1408' in text
    for end in ('fairlead', 'bollard'):
        tension = np.array([r[f'{end}_tension'] for r in rows])
        k = int(np.argmax(tension))
        match = re.search(rf'peak {end} tension \S+: ([\d.]+) N at log time ([\d.]+) s', text)
        assert match, text
        assert float(match.group(1)) == pytest.approx(tension[k], abs=0.05)
        assert float(match.group(2)) == pytest.approx(rows[k]['t'], abs=5e-4)
    series = read_tensions(bag)['fairlead']
    assert series.peak()[0] == max(r['fairlead_tension'] for r in rows)


def test_recover_completes_a_cut_bag(tmp_path, capsys):
    cut = tmp_path / 'cut'
    writer = BagWriter(cut, chunk_size=2048)
    writer.add_topic('/fairlead/tension', 'geometry_msgs/msg/Wrench')
    for k in range(400):
        wrench = cdr.wrench((float(k), 0.0, 0.0), (0.0, 0.0, 0.0))
        writer.write('/fairlead/tension', wrench, k * 10_000_000)
    writer.close()
    (cut / 'metadata.yaml').unlink()
    mcap = cut / 'cut_0.mcap'
    data = mcap.read_bytes()
    mcap.write_bytes(data[:len(data) // 2])  # as a kill leaves it: no summary, cut chunk
    assert not bag_info(cut).complete
    assert cli.main(['recover', str(cut)]) == 0
    out = capsys.readouterr().out
    info = bag_info(cut)
    assert info.complete and (cut / 'metadata.yaml').exists()
    assert f'recovered: {info.message_count} messages' in out
    assert 50 < info.message_count < 400
    assert info.topics['/fairlead/tension'].message_count == info.message_count


def test_recover_an_empty_recording(tmp_path, capsys):
    with BagWriter(tmp_path / 'empty') as writer:
        writer.add_topic('/fairlead/tension', 'geometry_msgs/msg/Wrench')
    assert cli.main(['recover', str(tmp_path / 'empty'), '--out', str(tmp_path / 'copy')]) == 0
    assert 'complete already' in capsys.readouterr().out
    assert bag_info(tmp_path / 'copy').message_count == 0
