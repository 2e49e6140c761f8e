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
``rope_sim run``: MOTION.csv in, OUT.csv out, bad input as one line and exit code 2.

The good run drives the fairlead with the first 12 s of the MoorDyn reference motion and
checks every row against a Mooring of the line given the whole motion.
"""

import csv
import math
import os
from pathlib import Path
import subprocess
import sys

import numpy as np
from one_line import OneLine
import pytest
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.motion import read_motion
from rope_sim_ros.offline.sinks import LINE_COLUMNS, STATE_COLUMN
from rope_sim_ros.params.arrangement import read_setup
from rope_sim_ros.params.files import parse_set
from rope_sim_ros.params.materials import default_config_dir

REPO_ROOT = Path(__file__).resolve().parent.parent
SECONDS = 12.0
HEADER = 't,fairlead_x,fairlead_y,fairlead_z'


def reference_motion(reference_dir: Path, path: Path, seconds: float = SECONDS) -> Path:
    """Write the first seconds of the dynamic reference case as a MOTION.csv."""
    with open(reference_dir / 'dynamic_polyester_N20.csv', newline='') as source:
        rows = [row for row in csv.DictReader(source) if float(row['t_s']) <= seconds + 1e-9]
    with open(path, 'w') as out:
        out.write(HEADER + '\n')
        for row in rows:
            out.write(f"{row['t_s']},{row['xB_m']},{row['yB_m']},{row['zB_m']}\n")
    return path


def resolve_params(overrides=None):
    """Return the line `rope_sim run` runs without --params: the default file's."""
    default = default_config_dir() / 'mooring_line.yaml'
    return read_setup(default if default.exists() else None, overrides).lines[0].params


def motion_points(path: Path) -> tuple:
    """Return (t [s] (n,), fairlead points (n, 3)) of a MOTION.csv."""
    streams = read_motion(path)  # no fairlead_offset: the ship's poses are the points
    return np.array([ns / 10**9 for ns in streams.t_ns.tolist()]), streams.position


def read_out(path: Path) -> tuple:
    """Return (header, rows as a float array) of a single line's OUT.csv: all but its state."""
    with open(path, newline='') as f:
        reader = csv.reader(f)
        header = next(reader)
        assert header[-1] == STATE_COLUMN  # the one word, last
        rows = list(reader)
    assert {row[-1] for row in rows} == {'fast'}
    return header, np.array([[float(v) for v in row[:-1]] for row in rows])


def simulation(params, times, points, rate: float) -> np.ndarray:
    """Rows of the line given the whole motion, then advanced to each row's time."""
    sim = OneLine(params, output_interval=1.0 / rate, history=math.inf)
    for t, point in zip(times.tolist(), points):
        sim.push_fairlead(t, point)
    sim.start(float(times[0]))
    rows = []
    for t in times.tolist():
        sim.advance_to(t)
        out = sim.output()
        rows.append([t, *out.fairlead_force, out.fairlead_tension, *out.bollard_force,
                     out.bollard_tension, out.max_strain, out.fairlead_peak, out.bollard_peak,
                     out.line_length, float(out.parted)])
    return np.array(rows)


@pytest.fixture(scope='module')
def good_run(reference_dir, tmp_path_factory):
    base = tmp_path_factory.mktemp('run')
    motion = reference_motion(reference_dir, base / 'motion.csv')
    out = base / 'out.csv'
    assert cli.main(['run', '--motion', str(motion), '--out', str(out), '--quiet']) == 0
    return motion, out


def test_rows_every_step_from_first_to_last_time(good_run):
    motion_path, out = good_run
    header, rows = read_out(out)
    assert tuple(header) == LINE_COLUMNS + (STATE_COLUMN,)
    times, _ = motion_points(motion_path)
    assert rows[0, 0] == times[0] == 0.0
    assert rows[-1, 0] == pytest.approx(times[-1], abs=1e-12)
    assert len(rows) == round(SECONDS * 100) + 1
    assert np.allclose(np.diff(rows[:, 0]), 0.01, rtol=0, atol=1e-12)
    assert np.isfinite(rows).all()


def test_rows_equal_the_simulator(good_run):
    motion_path, out = good_run
    _, rows = read_out(out)
    times, points = motion_points(motion_path)
    expected = simulation(resolve_params(), times, points, 100.0)
    assert rows.shape == expected.shape
    np.testing.assert_allclose(rows[:, 0], expected[:, 0], rtol=0, atol=1e-12)
    # Same steps, same numbers: only the state time's rounding differs.
    np.testing.assert_allclose(rows[:, 1:], expected[:, 1:], rtol=1e-9, atol=1e-6)
    # The columns are what they say: tension = |force|, and a real load on the line.
    np.testing.assert_allclose(rows[:, 4], np.linalg.norm(rows[:, 1:4], axis=1), rtol=1e-12)
    np.testing.assert_allclose(rows[:, 8], np.linalg.norm(rows[:, 5:8], axis=1), rtol=1e-12)
    assert 500.0 < rows[:, 4].mean() < 5000.0
    # the peak since the row before is at least the tension now; the line keeps its 40 m
    assert np.all(rows[:, 10] >= rows[:, 4]) and np.all(rows[:, 11] >= rows[:, 8])
    assert np.all(rows[:, 12] == 40.0) and not rows[:, 13].any()


def test_rate_and_bollard_columns(tmp_path):
    motion = tmp_path / 'motion.csv'
    lines = ['t,bollard_x,bollard_y,bollard_z,fairlead_x,fairlead_y,fairlead_z,comment']
    for k in range(21):
        t = k * 0.1
        lines.append(f'{t:.1f},{0.1 * t:.4f},0,0,36,0,8,row{k}')
    motion.write_text('\n'.join(lines) + '\n')
    out = tmp_path / 'out.csv'
    assert cli.main(['run', '--motion', str(motion), '--out', str(out), '--rate', '40',
                     '--quiet', '--set', 'segments=10']) == 0
    _, rows = read_out(out)
    assert len(rows) == 81
    assert np.allclose(np.diff(rows[:, 0]), 0.025, rtol=0, atol=1e-12)
    assert np.isfinite(rows).all()


BAD_FILES = {
    'missing_column': ('t,fairlead_x,fairlead_y\n0,36,0\n', ['file line 1', 'fairlead_z']),
    'partial_bollard': (HEADER + ',bollard_x\n0,36,0,8,0\n', ['file line 1', 'bollard_y']),
    'non_numeric': (HEADER + '\n0,36,0,8\n0.1,36,abc,8\n',
                    ['data row 2', 'file line 3', "'fairlead_y'", "'abc'"]),
    'empty_cell': (HEADER + '\n0,36,0,8\n0.1,36,0,\n', ['data row 2', "'fairlead_z'"]),
    'nan': (HEADER + '\n0,36,0,8\n0.1,36,0,8\n0.2,nan,0,8\n',
            ['data row 3', 'file line 4', "'fairlead_x'", 'finite']),
    'inf': (HEADER + '\n0,36,0,8\n0.1,36,0,inf\n', ['data row 2', "'fairlead_z'", 'finite']),
    'not_increasing': (HEADER + '\n0,36,0,8\n0.1,36,0,8\n0.1,36,0,8\n',
                       ['data row 3', 'file line 4', "'t'", 'increase']),
    'decreasing': (HEADER + '\n0,36,0,8\n0.2,36,0,8\n0.1,36,0,8\n', ['data row 3', "'t'"]),
    'short_row': (HEADER + '\n0,36,0,8\n0.1,36,0\n', ['data row 2', '3 cells']),
    'empty': ('', ['empty']),
    'header_only': (HEADER + '\n', ['no data rows']),
}


@pytest.mark.parametrize('case', sorted(BAD_FILES))
def test_bad_motion_file_is_one_line_and_exit_2(case, tmp_path, capsys):
    text, words = BAD_FILES[case]
    motion = tmp_path / f'{case}.csv'
    motion.write_text(text)
    code = cli.main(['run', '--motion', str(motion), '--out', str(tmp_path / 'out.csv')])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count('\n') == 1, err
    assert str(motion) in err
    for word in words:
        assert word in err, err
    assert 'Traceback' not in err


def test_missing_motion_file(tmp_path, capsys):
    code = cli.main(['run', '--motion', str(tmp_path / 'nope.csv'), '--out', 'x.csv'])
    err = capsys.readouterr().err
    assert code == 2 and 'nope.csv' in err and err.count('\n') == 1


@pytest.mark.parametrize('setting, name', [
    ('length=-1', 'length'),
    ('segments=1', 'segments'),
    ('material=cotton', 'material'),
    ('gravity=[0,0]', 'gravity'),
    ('max_strain=0', 'max_strain'),
    ('no_such=1', 'no_such'),
    ('length', 'key=value'),
])
def test_bad_set_names_the_parameter(setting, name, tmp_path, capsys):
    motion = tmp_path / 'motion.csv'
    motion.write_text(HEADER + '\n0,36,0,8\n1,36,0,8\n')
    code = cli.main(['run', '--motion', str(motion), '--out', str(tmp_path / 'out.csv'),
                     '--set', setting])
    err = capsys.readouterr().err
    assert code == 2
    assert name in err and err.count('\n') == 1, err
    assert not (tmp_path / 'out.csv').exists()


def test_set_parses_yaml_values():
    values = parse_set(['material=hmpe', 'gravity=[0,0,-9.81]', 'time_step=1e-4',
                        'segments=30', 'superelastic_adjustment=false'])
    assert values == {'material': 'hmpe', 'gravity': [0, 0, -9.81], 'time_step': 1e-4,
                      'segments': 30, 'superelastic_adjustment': False}
    assert resolve_params(overrides=values).material == 'hmpe'


def test_bad_params_file(tmp_path, capsys):
    params = tmp_path / 'p.yaml'
    params.write_text('other_node:\n  ros__parameters:\n    length: 3\n')
    motion = tmp_path / 'motion.csv'
    motion.write_text(HEADER + '\n0,36,0,8\n')
    code = cli.main(['run', '--params', str(params), '--motion', str(motion), '--out',
                     str(tmp_path / 'out.csv')])
    err = capsys.readouterr().err
    assert code == 2 and str(params) in err and err.count('\n') == 1


def test_console_entry_point_exit_codes(tmp_path):
    """The real command line: `python -m rope_sim_ros`, a bad file and a bad --set."""
    motion = tmp_path / 'motion.csv'
    motion.write_text(HEADER + '\n0,36,0,8\n0.5,36,zero,8\n')
    env = dict(os.environ, PYTHONPATH=str(REPO_ROOT))
    result = subprocess.run(
        [sys.executable, '-m', 'rope_sim_ros', 'run', '--motion', str(motion), '--out',
         str(tmp_path / 'out.csv')], env=env, capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    assert 'data row 2' in result.stderr and 'Traceback' not in result.stderr
    assert result.stderr.count('\n') == 1
    motion.write_text(HEADER + '\n0,36,0,8\n0.5,36,0,8\n')
    result = subprocess.run(
        [sys.executable, '-m', 'rope_sim_ros', 'run', '--motion', str(motion), '--out',
         str(tmp_path / 'out.csv'), '--set', 'length=-1'],
        env=env, capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    assert "'length'" in result.stderr and 'Traceback' not in result.stderr


def test_progress_bar_redraws_one_line_and_ends_it():
    import io
    from rope_sim_ros.offline.progress import Progress
    stream = io.StringIO()
    bar = Progress(stream, delay=0.0, enabled=True)
    for k in range(1, 11):
        bar(k, 10, k * 0.1)
    bar.finish()
    text = stream.getvalue()
    assert text.startswith('\r[') and text.endswith('\n') and text.count('\n') == 1
    assert '100.0 %' in text
    quiet = io.StringIO()  # not a TTY: nothing drawn
    bar = Progress(quiet, delay=0.0)
    bar(1, 1, 0.0)
    bar.finish()
    assert quiet.getvalue() == ''


def test_a_payload_adds_its_position_to_out_csv_and_the_bag(tmp_path):
    """payload_mass > 0: payload_x, payload_y, payload_z columns and payload/pose messages."""
    from rope_sim_ros.bag import read_messages
    from rope_sim_ros.bag.cdr import decode_pose_array, decode_pose_stamped
    from rope_sim_ros.offline.sinks import PAYLOAD_COLUMNS
    motion = tmp_path / 'motion.csv'
    lines = [HEADER + ',bollard_x,bollard_y,bollard_z']
    for k in range(101):
        t = k * 0.02
        lines.append(f'{t:.2f},{36.0 + 0.5 * math.sin(2.0 * t)!r},0,8,0,0,0')
    motion.write_text('\n'.join(lines) + '\n')
    out, bag = tmp_path / 'out.csv', tmp_path / 'bag'
    assert cli.main(['run', '--motion', str(motion), '--out', str(out), '--bag', str(bag),
                     '--rate', '50', '--quiet', '--set', 'segments=8',
                     '--set', 'payload_mass=500']) == 0
    header, rows = read_out(out)
    assert tuple(header) == LINE_COLUMNS + PAYLOAD_COLUMNS + (STATE_COLUMN,)
    assert len(rows) == 101 and np.isfinite(rows).all()
    payload = rows[:, len(LINE_COLUMNS):]
    # it hangs about a line's length under the fairlead (the bollard samples are ignored)
    assert payload[0] == pytest.approx([36.0, 0.0, 8.0 - 40.0], abs=0.1)
    assert np.abs(payload[:, 0] - 36.0).max() > 0.01  # the surge swings it
    # the bollard force is the line's pull on the payload: its weight, at rest
    assert rows[0, 8] == pytest.approx(500.0 * 9.81, rel=1e-3)
    poses = [decode_pose_stamped(m.data) for m in read_messages(bag, ['/payload/pose'])]
    particles = [decode_pose_array(m.data) for m in read_messages(bag, ['/rope/particles'])]
    assert len(poses) == len(particles) == 101
    for (sec, nanosec, frame, position, orientation), (psec, pnanosec, _, points) in zip(
            poses, particles):
        assert (sec, nanosec, frame) == (psec, pnanosec, 'world')
        assert np.array_equal(position, points[0, :3])
        assert np.array_equal(orientation, [0.0, 0.0, 0.0, 1.0])
    np.testing.assert_array_equal([p[3] for p in poses], payload)
    # resim of it: the same outputs, payload included
    again = tmp_path / 'again'
    assert cli.main(['resim', str(bag), '--out', str(again), '--quiet']) == 0
    assert [m.data for m in read_messages(again, ['/payload/pose'])] == [
        m.data for m in read_messages(bag, ['/payload/pose'])]


def test_a_number_without_a_dot_in_a_params_file_is_a_number(tmp_path, capsys):
    # `time_step: 5e-05` is a double for ROS's parameter parser; PyYAML alone read it as the
    # text '5e-05' and refused it: "'5e-05' is not allowed: must be >= 0 and <= 0.1 s".
    # Both kinds of file run with it, and the step is the one asked for.
    motion = tmp_path / 'motion.csv'
    motion.write_text(HEADER + '\n' + ''.join(f'{k * 0.1:.1f},36,0,8\n' for k in range(6)))
    line_file = tmp_path / 'line.yaml'
    line_file.write_text('/**/mooring_line:\n  ros__parameters:\n    time_step: 5e-05\n'
                         '    integrator: improved_euler\n    segments: 8\n')
    assert read_setup(line_file).lines[0].params.time_step == 5e-05
    out = tmp_path / 'out.csv'
    assert cli.main(['run', '--params', str(line_file), '--motion', str(motion), '--out',
                     str(out), '--quiet']) == 0, capsys.readouterr().err
    _, rows = read_out(out)
    expected = simulation(read_setup(line_file).lines[0].params, *motion_points(motion), 100.0)
    assert len(rows) == 51  # every 10 ms from 0 to 0.5 s; the samples' rows as the model's
    np.testing.assert_allclose(rows[::10, 1:], expected[:, 1:], rtol=1e-9, atol=1e-6)
    berth = tmp_path / 'berth.yaml'
    berth.write_text((REPO_ROOT / 'config' / 'berth.yaml').read_text().replace(
        'time_step: 0.0 ', 'time_step: 2.5E-4 '))
    assert read_setup(berth).shared.time_step == 2.5e-4
    quoted = tmp_path / 'quoted.yaml'
    quoted.write_text(line_file.read_text().replace('5e-05', "'5e-05'"))
    code = cli.main(['run', '--params', str(quoted), '--motion', str(motion), '--out',
                     str(tmp_path / 'quoted.csv')])
    err = capsys.readouterr().err
    assert code == 2 and "'5e-05'" in err and len(err.strip().splitlines()) == 1, err
