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
Ctrl-C during the start-up of an installed executable: no traceback, whenever it comes.

The executables are the launchers in bin/ as colcon installs them (what ``ros2 run`` runs).
Before a launcher's first statement the interpreter starts; these tries land there too.
"""

import functools
import os
import signal
import subprocess

import pytest

# exit 130: interrupted before main() took over; 0: main() handled it; 2: rope_sim reported
# its bad argument first; -SIGINT: the signal ended the process before env held it back (its
# first 2 ms, before any Python ran), which a shell reports as 130 too
QUIET_EXITS = (0, 130, 2, -signal.SIGINT)
NOISE = ('Traceback', 'KeyboardInterrupt', 'Fatal Python error', 'Exception ignored')
DELAYS = (0.0, 0.002, 0.005, 0.01, 0.02, 0.03, 0.05, 0.075, 0.1)  # [s] after the start
TRIES = 3


def _default_sigint(then=None):
    """In the child before exec: take SIGINT's default action back, then run `then`."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    if then is not None:
        then()


def _run(command, env, cwd, delay=None, **popen):
    """Start command, send SIGINT delay s later (None: never), return (exit code, output)."""
    # A test runner started in the background passes SIGINT on ignored, and the launchers
    # rightly keep it ignored: the user's Ctrl-C is what is tried here, so restore it.
    setup = popen.pop('preexec_fn', None)
    popen['preexec_fn'] = functools.partial(_default_sigint, setup)
    process = subprocess.Popen(command, env=env, cwd=cwd, stdin=subprocess.DEVNULL,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, **popen)
    if delay is not None:
        try:
            process.wait(delay)
        except subprocess.TimeoutExpired:
            process.send_signal(signal.SIGINT)
    try:
        output = process.communicate(timeout=30)[0].decode(errors='replace')
    except subprocess.TimeoutExpired:  # the Ctrl-C was lost: it runs on
        process.kill()
        output = 'still running 30 s later\n' + process.communicate()[0].decode(
            errors='replace')
    return process.returncode, output


@pytest.mark.parametrize('executable, args', [
    ('mooring_line', []),
    ('rope_sim', ['info', 'missing_bag']),
])
def test_ctrl_c_in_the_first_tenth_of_a_second_exits_quietly(colcon_install, colcon_env,
                                                             tmp_path, executable, args):
    command = [str(colcon_install / 'lib' / 'rope_sim_ros' / executable), *args]
    results = [(delay, *_run(command, colcon_env, tmp_path, delay))
               for delay in DELAYS for _ in range(TRIES)]
    bad = [(delay, code, output) for delay, code, output in results
           if code not in QUIET_EXITS or any(word in output for word in NOISE)]
    assert not bad, '\n'.join(f'Ctrl-C after {d} s: exit {c}\n{o}' for d, c, o in bad)
    print(executable, [(d, c) for d, c, _ in results])


@pytest.mark.parametrize('executable, args, delays', [
    ('mooring_line', [], [0.15, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5]),
    ('ship_motion', [], [0.1, 0.2, 0.3]),
    ('line_monitor', [], [0.1, 0.2, 0.3]),
    ('bag_replay', ['missing_bag'], [0.1, 0.2]),
    ('rope_sim', ['info', 'missing_bag'], [0.15, 0.2]),
])
def test_ctrl_c_later_in_start_up_exits_quietly(colcon_install, colcon_env, tmp_path,
                                                executable, args, delays):
    # Past the interpreter's start: exit 0 (main() handled it), 130 (the launcher or the
    # entry point did) or 2 (bag_replay and rope_sim reported their bad argument first);
    # never a traceback, nor an end by the signal itself.
    command = [str(colcon_install / 'lib' / 'rope_sim_ros' / executable), *args]
    results = [(delay, *_run(command, colcon_env, tmp_path, delay)) for delay in delays]
    bad = [(delay, code, output) for delay, code, output in results
           if code not in (0, 130, 2) or any(word in output for word in NOISE)]
    assert not bad, '\n'.join(f'Ctrl-C after {d} s: exit {c}\n{o}' for d, c, o in bad)


def _pending_ctrl_c():
    # In the child before exec: a Ctrl-C that came while the interpreter started, held back
    # as env holds it back; it outlives the exec, pending.
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    os.kill(os.getpid(), signal.SIGINT)


@pytest.mark.parametrize('executable', ['mooring_line', 'rope_sim'])
def test_a_ctrl_c_held_back_during_interpreter_start_ends_the_launcher_quietly(
        colcon_install, colcon_env, tmp_path, executable):
    # The launcher lets it through once it has taken SIGINT over: exit 130, nothing said.
    # Before that moment the interpreter would have raised KeyboardInterrupt; left held back,
    # the node would run on, deaf to Ctrl-C.
    command = [str(colcon_install / 'lib' / 'rope_sim_ros' / executable), '--help']
    assert _run(command, colcon_env, tmp_path, preexec_fn=_pending_ctrl_c) == (130, '')


def test_launchers_run_behind_env_holding_sigint_back(colcon_install):
    # where GNU env (8.31 or later) can: this machine's can
    probe = subprocess.run(['/usr/bin/env', '--block-signal=INT', 'true'],
                           stdin=subprocess.DEVNULL, capture_output=True)
    assert probe.returncode == 0, probe.stderr
    first = (colcon_install / 'lib' / 'rope_sim_ros' / 'mooring_line').read_text().split(
        '\n', 1)[0]
    assert first.startswith('#!/usr/bin/env -S --block-signal=INT /') and \
        first.endswith(' -S'), first
