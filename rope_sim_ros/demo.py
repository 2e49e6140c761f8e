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
`make demo`: a live mooring line in one command, recorded to a bag and plotted.

Starts the colcon-installed executables mooring_line (with config/mooring_line.yaml,
recording to a new bag out/demo_<time>/bag), ship_motion and line_monitor in their own ROS
domain (unless ROS_DOMAIN_ID is set), forwards the monitor's lines to stdout for --duration
seconds of output, then stops every child with SIGINT, by its process id, and waits for it.
Then `rope_sim info` describes the bag, `rope_sim plot` draws out/demo_<time>/tension.png,
and the demo says where both are.

    python -m rope_sim_ros.demo [--duration 30] [--install install] [--params FILE] [--out out]
"""

import argparse
import errno
import os
from pathlib import Path
import queue
import signal
import subprocess
import sys
import threading
import time

from .params import ParameterError, read_params_file

REPO = Path(__file__).resolve().parent.parent
PACKAGE = 'rope_sim_ros'
START_TIMEOUT = 90.0  # a fresh install compiles the rope kernels on the first start
STOP_TIMEOUT = 10.0
MAX_SAFE_DOMAIN_ID = 101  # DDS ports of higher ids can collide with ephemeral ports


def overlay_environment(prefix: Path) -> dict:
    """Return os.environ as `source install/setup.bash` would leave it for this package."""
    env = dict(os.environ)
    site = prefix / 'lib' / f'python{sys.version_info[0]}.{sys.version_info[1]}' / 'site-packages'
    ament = [str(prefix)] + [p for p in env.get('AMENT_PREFIX_PATH', '').split(os.pathsep)
                             if p and p != str(prefix)]
    if sys.prefix not in ament:
        ament.append(sys.prefix)  # the ROS wheels' share/ (message packages)
    env['AMENT_PREFIX_PATH'] = os.pathsep.join(ament)
    env['PYTHONPATH'] = os.pathsep.join(
        [str(site)] + [p for p in env.get('PYTHONPATH', '').split(os.pathsep) if p])
    env.setdefault('ROS_DOMAIN_ID', str(os.getpid() % MAX_SAFE_DOMAIN_ID + 1))
    env.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    env['PYTHONUNBUFFERED'] = '1'
    return env


def _forward_lines(stream, lines: queue.Queue) -> None:
    for line in stream:
        lines.put(line.rstrip('\n'))
    lines.put(None)


def stop(children: dict) -> dict:
    """Send SIGINT to every running child (by pid), wait, and return the exit codes."""
    for child in reversed(list(children.values())):
        if child.poll() is None:
            os.kill(child.pid, signal.SIGINT)
    codes = {}
    deadline = time.monotonic() + STOP_TIMEOUT
    for name, child in children.items():
        try:
            codes[name] = child.wait(max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            print(f'demo: {name} (pid {child.pid}) ignored SIGINT; killing it', file=sys.stderr)
            child.kill()
            codes[name] = child.wait()
    return codes


def main(argv=None) -> int:
    """Run the demo; return the exit code (0 when every child started and stopped cleanly)."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--duration', type=float, default=30.0,
                        help='seconds of live output before stopping (default 30)')
    parser.add_argument('--install', type=Path, default=REPO / 'install',
                        help='colcon install base (default: <repo>/install)')
    parser.add_argument('--params', type=Path, default=REPO / 'config' / 'mooring_line.yaml',
                        help='parameter file of mooring_line (default config/mooring_line.yaml)')
    parser.add_argument('--out', type=Path, default=REPO / 'out',
                        help='where the run directory demo_<time>/ (bag and plot) is made '
                        '(default: <repo>/out)')
    args = parser.parse_args(argv)

    prefix = args.install.resolve() / PACKAGE
    executables = prefix / 'lib' / PACKAGE
    missing = [name for name in ('mooring_line', 'ship_motion', 'line_monitor', 'rope_sim')
               if not (executables / name).is_file()]
    if missing:
        print(f'demo: {", ".join(missing)} not found in {executables}: run `make build` first',
              file=sys.stderr)
        return 2
    try:
        length = float(read_params_file(args.params).get('length', 40.0))
    except ParameterError as e:
        print(f'demo: {e}', file=sys.stderr)
        return 2

    try:
        run_dir = new_run_directory(args.out)
    except OSError as e:
        print(f'demo: cannot create a run directory in {args.out}: {e.strerror or e}',
              file=sys.stderr)
        return 2
    bag = run_dir / 'bag'

    env = overlay_environment(prefix)
    print(f'demo: ROS_DOMAIN_ID={env["ROS_DOMAIN_ID"]}, parameters {args.params}, '
          f'{args.duration:g} s, recording to {bag}; Ctrl-C stops early', flush=True)
    commands = {
        'mooring_line': ['--ros-args', '--params-file', str(args.params),
                         '-p', f'record_path:={bag}'],
        'ship_motion': [],
        'line_monitor': ['--ros-args', '-p', f'length:={length!r}'],
    }
    children = {}
    lines: queue.Queue = queue.Queue()
    ok = True
    try:
        for name, extra in commands.items():
            children[name] = subprocess.Popen(
                [str(executables / name), *extra], env=env, stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE if name == 'line_monitor' else None, text=True)
        threading.Thread(target=_forward_lines, args=(children['line_monitor'].stdout, lines),
                         daemon=True).start()
        ok = _show(children, lines, args.duration)
    except KeyboardInterrupt:
        print('demo: interrupted', flush=True)
    finally:
        codes = stop(children)
    bad = {name: code for name, code in codes.items() if code != 0}
    if bad:
        print(f'demo: exit codes {bad}', file=sys.stderr)
    print(f'demo: stopped {", ".join(codes)}', flush=True)
    shown = show_bag(executables / 'rope_sim', env, bag, run_dir / 'tension.png')
    return 0 if ok and not bad and shown else 1


def new_run_directory(base: Path) -> Path:
    """
    Create and return a new directory base/demo_<date>-<time>[_<n>]; never reuse one.

    :param base: where to make it (created if missing).
    :returns: the new, empty directory.
    :raises OSError: base cannot be created or written.
    """
    base.mkdir(parents=True, exist_ok=True)
    stem = 'demo_' + time.strftime('%Y%m%d-%H%M%S')
    for n in range(1, 1000):
        path = base / (stem if n == 1 else f'{stem}_{n}')
        try:
            path.mkdir()
        except FileExistsError:
            continue
        return path.resolve()
    raise FileExistsError(errno.EEXIST, 'too many runs this second', str(base / stem))


def show_bag(rope_sim: Path, env: dict, bag: Path, png: Path) -> bool:
    """
    Run `rope_sim info` and `rope_sim plot` on the recorded bag and say where things are.

    A bag left incomplete (mooring_line had to be killed) is completed with
    `rope_sim recover` first.

    :param rope_sim: the installed rope_sim executable.
    :param env: the environment to run it in.
    :param bag: the bag directory mooring_line recorded.
    :param png: the plot to write.
    :returns: True if the bag was there and both commands succeeded.
    """
    if not (bag / 'metadata.yaml').is_file():
        if not bag.is_dir():
            print(f'demo: no bag was recorded at {bag}', file=sys.stderr)
            return False
        print(f'demo: {bag} was not closed; completing it with rope_sim recover', flush=True)
        if subprocess.run([str(rope_sim), 'recover', str(bag)], env=env).returncode != 0:
            return False
    ok = True
    for command in (['info', str(bag)], ['plot', str(bag), '-o', str(png)]):
        print(f'demo: rope_sim {" ".join(command)}', flush=True)
        ok = subprocess.run([str(rope_sim), *command], env=env).returncode == 0 and ok
    print(f'demo: bag  {bag}', flush=True)
    if png.is_file():
        print(f'demo: plot {png}', flush=True)
    return ok and png.is_file()


def _show(children: dict, lines: queue.Queue, duration: float) -> bool:
    """Print the monitor's lines until `duration` s after its first status line."""
    start = time.monotonic()
    end = start + START_TIMEOUT
    first_status = False
    while time.monotonic() < end:
        for name, child in children.items():
            if child.poll() is not None:
                print(f'demo: {name} exited early with code {child.returncode}',
                      file=sys.stderr)
                return False
        try:
            line = lines.get(timeout=0.2)
        except queue.Empty:
            continue
        if line is None:
            return False
        print(line, flush=True)
        if not first_status and _is_status(line):
            first_status = True
            end = time.monotonic() + duration
    if not first_status:
        print(f'demo: no status line within {START_TIMEOUT:g} s', file=sys.stderr)
    return first_status


def _is_status(line: str) -> bool:
    """Return True for a status line of line_monitor (it starts with the time)."""
    try:
        float(line.split()[0])
    except (IndexError, ValueError):
        return False
    return True


if __name__ == '__main__':
    sys.exit(main())
