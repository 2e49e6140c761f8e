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
Cold start: the first start of the node and the runner after a colcon build, and later ones.

Builds the package with colcon into a fresh temporary workspace (timed), then starts each
program as a user's shell does (HOME on a fresh empty folder, NUMBA_CACHE_DIR and
PYTHONDONTWRITEBYTECODE unset: a start may write bytecode into the install for the next):
(a) the first start after the build, (b) --later more starts (default 5). Before the
runner's first start, whatever the node's starts wrote into the install is removed: that one
is a first start after the build too.

- mooring_line: from the node process start to its last start-up line ("ready") and to the
  first fairlead/tension message received by a subscriber here (which publishes fairlead
  poses at 50 Hz from before the start; the difference is mostly DDS discovery), in its own
  ROS domain, discovery on localhost, a namespace a start.
- rope_sim run: 60 s of examples/surge.csv on a 50-segment steel_wire line, whole process.

    python benchmarks/cold_start.py [--source DIR] [--symlink-install] [--later N] [--keep]

--source builds another checkout (e.g. `git archive HEAD | tar -x -C DIR` of an older
commit) for a before/after comparison; ROPE_SIM_PRECOMPILE=0 in the environment builds
without compiling the kernels. A --symlink-install runs the package from the source tree, so
its kernels compile into the source tree's __pycache__, and no start writes bytecode there.

    python benchmarks/cold_start.py --make-demo [--source DIR]

A newcomer's `make demo`: clones the checkout's committed HEAD into a temporary folder, links
its .venv to this checkout's (the venv's own set-up is not timed: `make -o .venv/.installed`)
and runs `make demo` with HOME on an empty folder until the demo's first live row; prints when
the build ended and when that row came, then stops the demo.
"""

import argparse
import math
import os
from pathlib import Path
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Optional

REPO = Path(__file__).resolve().parent.parent
MAX_SAFE_DOMAIN_ID = 101  # above it DDS ports reach Linux's ephemeral range
NAMESPACE = '/cold_start'  # and a number: each start has its own
FAIRLEAD = (36.0, 0.0, 8.0)  # the default 40 m line between the bollard at 0 and here
TIMEOUT = 300.0  # [s] for one start; the slowest cold start measured was 44 s
PREPARING = 'preparing the physics kernels'
READY = 'waiting for the first pose'  # the node's last start-up line

os.environ.setdefault('ROS_DOMAIN_ID', str(os.getpid() % MAX_SAFE_DOMAIN_ID + 1))
os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'

from geometry_msgs.msg import PoseStamped, Wrench  # noqa: E402
import rclpy  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.qos import QoSProfile  # noqa: E402
from rclpy.signals import SignalHandlerOptions  # noqa: E402


def build(source: Path, base: Path, symlink_install: bool) -> tuple:
    """Build source with colcon into base/install (as test/conftest.py); return (prefix, s)."""
    base.mkdir(parents=True)
    command = [sys.executable, '-m', 'colcon', '--log-base', str(base / 'log'), 'build',
               '--paths', str(source), '--build-base', str(base / 'build'),
               '--install-base', str(base / 'install'),
               '--event-handlers', 'console_cohesion-', 'status-', 'summary-']
    if symlink_install:
        command.append('--symlink-install')
    env = clean_environment(base / 'build_home')
    env['PYTHONDONTWRITEBYTECODE'] = '1'
    start = time.monotonic()
    result = subprocess.run(command, cwd=str(base), env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.monotonic() - start
    if result.returncode:
        sys.exit(f'colcon build failed ({result.returncode}):\n{result.stdout[-4000:]}')
    return base / 'install' / 'rope_sim_ros', seconds


def clean_environment(home: Path) -> dict:
    """os.environ with HOME on a new empty folder and no numba cache setting."""
    home.mkdir(parents=True, exist_ok=True)  # the second start reuses the first one's
    env = dict(os.environ)
    env['HOME'] = str(home)
    for name in ('NUMBA_CACHE_DIR', 'XDG_CACHE_HOME'):
        env.pop(name, None)
    prefixes = [p for p in env.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    if sys.prefix not in prefixes:
        prefixes.append(sys.prefix)  # the ROS wheels' share/ (message packages)
    env['AMENT_PREFIX_PATH'] = os.pathsep.join(prefixes)
    return env


def hook_paths(prefix: Path, dsv: Path, variable: str) -> list:
    """Return the paths colcon's environment hooks (package.dsv and its sources) prepend."""
    paths = []
    for line in dsv.read_text().splitlines():
        kind, _, rest = line.partition(';')
        if kind == 'source' and rest.endswith('.dsv'):
            paths = hook_paths(prefix, (prefix / rest).resolve(), variable) + paths
        elif kind.startswith('prepend') and rest.startswith(variable + ';'):
            value = rest[len(variable) + 1:]
            paths.insert(0, str(prefix / value) if value else str(prefix))
    return paths


def overlay(prefix: Path, home: Path, bytecode: bool) -> dict:
    """Return the environment of a sourced install/setup.bash, with a fresh HOME."""
    env = clean_environment(home)
    package_dsv = prefix / 'share' / 'rope_sim_ros' / 'package.dsv'
    env['AMENT_PREFIX_PATH'] = os.pathsep.join(
        hook_paths(prefix, package_dsv, 'AMENT_PREFIX_PATH') + [env['AMENT_PREFIX_PATH']])
    # the installed package (with --symlink-install: the build directory), never this checkout
    python_path = [p for p in env.get('PYTHONPATH', '').split(os.pathsep)
                   if p and Path(p).resolve() != REPO]
    env['PYTHONPATH'] = os.pathsep.join(
        hook_paths(prefix, package_dsv, 'PYTHONPATH') + python_path)
    env['PYTHONUNBUFFERED'] = '1'
    if bytecode:  # a start may write it, as from a user's shell (the Makefile's make does not)
        env.pop('PYTHONDONTWRITEBYTECODE', None)
    else:  # --symlink-install: it would go into the source tree
        env['PYTHONDONTWRITEBYTECODE'] = '1'
    return env


def installed_files(prefix: Path) -> set:
    """Return every file of the install under prefix."""
    return {path for path in prefix.rglob('*') if path.is_file() or path.is_symlink()}


class Probe:
    """Publishes fairlead poses at 50 Hz and notes the first tension message."""

    def __init__(self, context: rclpy.Context, namespace: str):
        """Create the node, the pose publisher (a timer) and the tension subscription."""
        self.namespace = namespace  # one per start: no late message of the previous one
        self.node = rclpy.create_node('cold_start_probe', namespace=namespace, context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.publisher = self.node.create_publisher(PoseStamped, 'fairlead/pose', 10)
        self.first_tension = None  # time.monotonic() at receipt
        self.node.create_subscription(Wrench, 'fairlead/tension', self._on_tension,
                                      QoSProfile(depth=10))
        self.node.create_timer(0.02, self._publish)

    def _on_tension(self, msg: Wrench) -> None:
        if self.first_tension is None:
            self.first_tension = time.monotonic()

    def _publish(self) -> None:
        msg = PoseStamped()
        msg.header.frame_id = 'world'
        msg.header.stamp = self.node.get_clock().now().to_msg()
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = FAIRLEAD
        msg.pose.orientation.w = 1.0
        self.publisher.publish(msg)

    def time_to_tension(self, prefix: Path, home: Path, log: Path, bytecode: bool) -> tuple:
        """
        Start the node; return (s to the first tension, s to ready, logged PREPARING).

        Either time is None when it never came (TIMEOUT).
        """
        self.first_tension = None
        with open(log, 'w') as out:
            start, wall = time.monotonic(), time.time()
            node = subprocess.Popen(
                [str(prefix / 'lib' / 'rope_sim_ros' / 'mooring_line'), '--ros-args',
                 '-r', f'__ns:={self.namespace}'],
                env=overlay(prefix, home, bytecode), stdin=subprocess.DEVNULL, stdout=out,
                stderr=subprocess.STDOUT)
            try:
                while self.first_tension is None and node.poll() is None \
                        and time.monotonic() - start < TIMEOUT:
                    self.executor.spin_once(timeout_sec=0.005)
            finally:
                node.send_signal(signal.SIGINT)
                try:
                    node.wait(30)
                except subprocess.TimeoutExpired:
                    node.kill()
                    node.wait()
        seconds = None if self.first_tension is None else self.first_tension - start
        text = log.read_text()
        ready = [line for line in text.splitlines() if READY in line]
        # '[INFO] [<wall clock s>] [name]: ...': the end of the node's start-up
        ready_seconds = float(ready[0].split(']')[1].strip(' [')) - wall if ready else None
        print(f'  {log.name}: node ready {ready_seconds or math.nan:.2f} s after its start, '
              f'first tension after {seconds or math.nan:.2f} s', flush=True)
        return seconds, ready_seconds, PREPARING in text


def run_time(prefix: Path, home: Path, out: Path, bytecode: bool) -> tuple:
    """Run `rope_sim run` (60 s, 50 segments, steel_wire); return (seconds, PREPARING seen)."""
    command = [str(prefix / 'lib' / 'rope_sim_ros' / 'rope_sim'), 'run',
               '--motion', str(REPO / 'examples' / 'surge.csv'), '--out', str(out),
               '--set', 'segments=50', '--set', 'material=steel_wire']
    start = time.monotonic()
    result = subprocess.run(command, env=overlay(prefix, home, bytecode), stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.monotonic() - start
    if result.returncode:
        sys.exit(f'rope_sim run failed ({result.returncode}):\n{result.stdout[-4000:]}')
    print(f'  rope_sim run: {seconds:.2f} s', flush=True)
    return seconds, PREPARING in result.stdout


def first_cell(seconds: Optional[float], compiled: bool) -> str:
    """Return one start's time, and whether it compiled kernels."""
    text = 'timeout' if seconds is None else f'{seconds:.2f} s'
    return text + (' (compiled)' if compiled else '')


def later_cell(starts: list) -> str:
    """Return the later starts' median and largest time."""
    if not starts or any(s is None for s in starts):
        return 'timeout'
    return f'{statistics.median(starts):.2f} s, max {max(starts):.2f} s'


def make_demo(source: Path, root: Path) -> int:
    """Clone source, run its `make demo` to the first live row; print when things came."""
    clone = root / 'clone'
    subprocess.run(['git', 'clone', '--quiet', str(source), str(clone)], check=True)
    (clone / '.venv').symlink_to((REPO / '.venv').resolve())
    home = root / 'home'
    env = clean_environment(home)
    for name in ('PYTHONPATH', 'AMENT_PREFIX_PATH'):  # as a new shell: the Makefile sets them
        env.pop(name, None)
    command = ['make', '-o', '.venv/.installed', 'demo']
    start = time.monotonic()
    process = subprocess.Popen(command, cwd=str(clone), env=env, stdin=subprocess.DEVNULL,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               start_new_session=True)  # its own group, for the one SIGINT
    built = row = None
    header = False
    try:
        for line in process.stdout:
            now = time.monotonic() - start
            if built is None and line.startswith('Finished <<< rope_sim_ros'):
                built = now
                print(f'{now:7.1f} s  {line.rstrip()}', flush=True)
            elif re.search(r'\bt \[s\]', line):
                header = True
            elif header and re.match(r'\s*[0-9]+\.[0-9]\s', line):
                row = now
                print(f'{now:7.1f} s  {line.rstrip()}', flush=True)
                break
            elif 'numba kernels:' in line or 'error' in line.lower():
                print(f'{now:7.1f} s  {line.rstrip()[:200]}', flush=True)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGINT)  # Ctrl-C, as in the terminal
        try:
            process.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.communicate()
    load = ', '.join(f'{v:.2f}' for v in os.getloadavg())
    print(f'make demo from a fresh clone of {source} (its venv linked, not timed): '
          f'{os.cpu_count()} CPUs, load average {load}')
    print(f'build finished after {built or math.nan:.1f} s; first live row after '
          f'{row or math.nan:.1f} s')
    return 0 if row is not None else 1


def main(argv=None) -> int:
    """Build, start each program, print the table (or time `make demo`)."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--source', type=Path, default=REPO,
                        help='checkout to build (default: this one)')
    parser.add_argument('--symlink-install', action='store_true',
                        help='colcon build --symlink-install')
    parser.add_argument('--later', type=int, default=5, metavar='N',
                        help='starts after the first (default 5)')
    parser.add_argument('--make-demo', action='store_true',
                        help="time a fresh clone's `make demo` to its first live row instead")
    parser.add_argument('--keep', action='store_true', help='keep the temporary workspaces')
    args = parser.parse_args(argv)

    root = Path(tempfile.mkdtemp(prefix='rope_sim_cold_start_'))
    if args.make_demo:
        try:
            return make_demo(args.source.resolve(), root)
        finally:
            if not args.keep:
                shutil.rmtree(root, ignore_errors=True)
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    count = [0]

    def node_start(prefix: Path, home: Path) -> tuple:
        count[0] += 1
        probe = Probe(context, f'{NAMESPACE}_{count[0]}')
        try:
            return probe.time_to_tension(prefix, home, root / f'node_{count[0]}.log',
                                         not args.symlink_install)
        finally:
            probe.node.destroy_node()

    try:
        prefix, build_seconds = build(args.source.resolve(), root / 'ws', args.symlink_install)
        built = installed_files(prefix)
        node = [node_start(prefix, root / 'home') for _ in range(1 + args.later)]
        for path in installed_files(prefix) - built:  # what the node's starts wrote
            path.unlink()
        runs = [run_time(prefix, root / 'home_run', root / 'out.csv', not args.symlink_install)
                for _ in range(1 + args.later)]
    finally:
        rclpy.try_shutdown(context=context)
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)
    load = ', '.join(f'{v:.2f}' for v in os.getloadavg())
    print(f'cold start of {args.source.resolve()}'
          f'{" (--symlink-install)" if args.symlink_install else ""}: {os.cpu_count()} CPUs, '
          f'load average {load}; ROS_DOMAIN_ID={os.environ["ROS_DOMAIN_ID"]}')
    rows = [('mooring_line: process start -> ready (its last start-up line)',
             first_cell(node[0][1], node[0][2]), later_cell([n[1] for n in node[1:]])),
            ('mooring_line: process start -> first fairlead/tension received',
             first_cell(node[0][0], node[0][2]), later_cell([n[0] for n in node[1:]])),
            ('rope_sim run: 60 s, 50 segments steel_wire, whole process',
             first_cell(*runs[0]), later_cell([r[0] for r in runs[1:]]))]
    width = max(len(r[0]) for r in rows)
    print(f'{"":{width}}  {"first after build":>20}  {f"{args.later} later: median, max":>26}')
    for name, first, later in rows:
        print(f'{name:{width}}  {first:>20}  {later:>26}')
    print(f'{"colcon build of a fresh workspace":{width}}  {build_seconds:.1f} s')
    if args.keep:
        print(f'workspace kept in {root}')
    return 0 if 'timeout' not in ''.join(r[1] + r[2] for r in rows) else 1


if __name__ == '__main__':
    sys.exit(main())
