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
``rope_sim resim``: a bag's inputs through a fresh line, deterministic, and what-ifs.

A bag recorded by ``rope_sim run --bag`` is re-simulated twice (byte-identical payloads,
and identical to the run's own outputs, since the bag stores the run's parameters) and
once with another material (a different, finite tension series).
"""

import math

import numpy as np
import pytest
from rope_sim_ros.bag import bag_info, read_messages
from rope_sim_ros.bag.cdr import decode_pose_array, decode_wrench
from rope_sim_ros.offline import cli

# what the node records: the peaks, the winch's length and the latched parted flag too
OUTPUTS = ('/rope/particles', '/fairlead/tension', '/bollard/tension',
           '/fairlead/peak_tension', '/bollard/peak_tension', '/winch/length', '/rope/parted')


def write_motion(path, seconds: float = 4.0):
    lines = ['t,fairlead_x,fairlead_y,fairlead_z']
    for k in range(int(seconds * 100) + 1):
        t = k * 0.01
        surge = 1.0 * (1.0 - math.cos(2.0 * math.pi * t / seconds)) / 2.0
        lines.append(f'{t:.2f},{36.0 + 0.976 * surge!r},0.0,{8.0 + 0.217 * surge!r}')
    path.write_text('\n'.join(lines) + '\n')
    return path


def payloads(bag):
    """{topic: [(log time, CDR bytes), ...]} of a bag."""
    out = {}
    for m in read_messages(bag):
        out.setdefault(m.topic, []).append((m.log_time_ns, m.data))
    return out


def tensions(bag, topic='/fairlead/tension'):
    values = []
    for m in read_messages(bag, [topic]):
        force, _ = decode_wrench(m.data)
        values.append(float(np.linalg.norm(force)))
    return np.array(values)


@pytest.fixture(scope='module')
def recorded(tmp_path_factory):
    base = tmp_path_factory.mktemp('resim')
    motion = write_motion(base / 'motion.csv')
    bag = base / 'original'
    assert cli.main(['run', '--motion', str(motion), '--bag', str(bag), '--quiet',
                     '--set', 'segments=16']) == 0
    first, second = base / 'again1', base / 'again2'
    assert cli.main(['resim', str(bag), '--out', str(first), '--quiet']) == 0
    assert cli.main(['resim', str(bag), '--out', str(second), '--quiet']) == 0
    return base, bag, first, second


def test_twice_gives_byte_identical_payloads(recorded):
    _, _, first, second = recorded
    a, b = payloads(first), payloads(second)
    assert a.keys() == b.keys() == {'/fairlead/pose', *OUTPUTS}
    for topic in a:
        assert len(a[topic]) == len(b[topic]) > 0
        assert a[topic] == b[topic], topic


def test_resim_reproduces_the_recorded_run(recorded):
    """Stored parameters + recorded inputs: the run's own messages, byte for byte."""
    _, original, first, _ = recorded
    a, b = payloads(original), payloads(first)
    assert a.keys() == b.keys()
    for topic in a:
        assert a[topic] == b[topic], topic


def test_another_material_gives_another_finite_series(recorded, capsys):
    base, original, _, _ = recorded
    hmpe = base / 'hmpe'
    assert cli.main(['resim', str(original), '--out', str(hmpe), '--set', 'material=hmpe',
                     '--set', 'segments=16']) == 0
    assert 'hmpe' in capsys.readouterr().out
    before, after = tensions(original), tensions(hmpe)
    assert len(before) == len(after) == 401
    assert np.isfinite(after).all() and (after > 0).all()
    # This line sags (40 m over a 36.9 m chord): its tension is set by its weight, and
    # HMPE weighs 496 d^2 kg/m against polyester's 679 d^2.
    assert np.abs(after - before).max() > 100.0
    assert after.mean() / before.mean() == pytest.approx(496.0 / 679.0, rel=0.03)
    for m in read_messages(hmpe, ['/rope/particles']):
        points = decode_pose_array(m.data)[3][:, :3]
        assert points.shape == (17, 3) and np.isfinite(points).all()


def test_rate_follows_the_recording_or_the_option(recorded):
    base, original, _, _ = recorded
    assert cli.main(['resim', str(original), '--out', str(base / 'slow'), '--rate', '20',
                     '--quiet']) == 0
    counts = {n: t.message_count for n, t in bag_info(base / 'slow').topics.items()}
    assert counts['/fairlead/pose'] == 401
    assert counts['/fairlead/tension'] == counts['/rope/particles'] == 81


def test_bad_input_is_one_line_and_exit_2(recorded, tmp_path, capsys):
    base, original, _, _ = recorded
    cases = [
        (['resim', str(tmp_path / 'missing'), '--out', str(tmp_path / 'x')], 'does not exist'),
        (['resim', str(original), '--out', str(base / 'again1')], 'not overwriting'),
        (['resim', str(original), '--out', str(tmp_path / 'y'), '--set', 'length=0'],
         "'length'"),
        (['resim', str(original), '--out', str(tmp_path / 'z'), '--namespace', 'ship2'],
         '/ship2/fairlead/pose'),
    ]
    for argv, words in cases:
        assert cli.main(argv) == 2, argv
        err = capsys.readouterr().err
        assert words in err and err.count('\n') == 1, err


def test_epoch_stamped_rows_resimulate_exactly(tmp_path):
    """Times like 1767225600.01 s are not floats; their nanoseconds are kept exactly."""
    lines = ['t,fairlead_x,fairlead_y,fairlead_z']
    for k in range(101):
        lines.append(f'{1767225600 + k / 100:.2f},{36.0 + 0.2 * math.sin(k / 50):.9f},0,8')
    (tmp_path / 'motion.csv').write_text('\n'.join(lines) + '\n')
    bag, again = tmp_path / 'epoch', tmp_path / 'again'
    assert cli.main(['run', '--motion', str(tmp_path / 'motion.csv'), '--bag', str(bag),
                     '--quiet', '--set', 'segments=8']) == 0
    assert cli.main(['resim', str(bag), '--out', str(again), '--quiet']) == 0
    original = payloads(bag)
    assert [t for t, _ in original['/fairlead/tension']] == [
        1767225600 * 10**9 + k * 10**7 for k in range(101)]
    assert payloads(again) == original
