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
Cold start: the first start of the node and of the offline runner right after a colcon build.

For each of the two programs, builds the package with colcon into a fresh temporary
workspace (timed), then starts it twice with HOME on a fresh empty folder and NUMBA_CACHE_DIR
unset: (a) cold, the first start after the build, (b) warm, the second start.

- mooring_line: from the node process start to the first fairlead/tension message received
  by a subscriber here (which publishes fairlead poses at 50 Hz from before the start), in
  its own ROS domain, discovery on localhost, namespaces /cold_start_cold and _warm.
- rope_sim run: 60 s of examples/surge.csv on a 50-segment steel_wire line, whole process.

    python benchmarks/cold_start.py [--source DIR] [--symlink-install] [--keep]

--source builds another checkout (e.g. `git archive HEAD | tar -x -C DIR` of an older
commit) for a before/after comparison; ROPE_SIM_PRECOMPILE=0 in the environment builds
without compiling the kernels. A --symlink-install runs the package from the source tree, so
its kernels compile into the source tree's __pycache__ (once: the second build finds them).
"""

import argparse
import math
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import tempfile
import time

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


def overlay(prefix: Path, home: Path) -> dict:
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
    return env


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

    def time_to_tension(self, prefix: Path, home: Path, log: Path) -> tuple:
        """Start the node; return (seconds to the first tension or None, logged PREPARING)."""
        self.first_tension = None
        with open(log, 'w') as out:
            start, wall = time.monotonic(), time.time()
            node = subprocess.Popen(
                [str(prefix / 'lib' / 'rope_sim_ros' / 'mooring_line'), '--ros-args',
                 '-r', f'__ns:={self.namespace}'],
                env=overlay(prefix, home), stdin=subprocess.DEVNULL, stdout=out,
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
        if ready:  # '[INFO] [<wall clock s>] [name]: ...': the end of the node's start-up
            stamp = float(ready[0].split(']')[1].strip(' ['))
            print(f'  {log.name}: node ready {stamp - wall:.2f} s after its start, first '
                  f'tension after {seconds or math.nan:.2f} s')
        return seconds, PREPARING in text


def run_time(prefix: Path, home: Path, out: Path) -> tuple:
    """Run `rope_sim run` (60 s, 50 segments, steel_wire); return (seconds, PREPARING seen)."""
    command = [str(prefix / 'lib' / 'rope_sim_ros' / 'rope_sim'), 'run',
               '--motion', str(REPO / 'examples' / 'surge.csv'), '--out', str(out),
               '--set', 'segments=50', '--set', 'material=steel_wire']
    start = time.monotonic()
    result = subprocess.run(command, env=overlay(prefix, home), stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.monotonic() - start
    if result.returncode:
        sys.exit(f'rope_sim run failed ({result.returncode}):\n{result.stdout[-4000:]}')
    return seconds, PREPARING in result.stdout


def cell(measure: tuple) -> str:
    seconds, compiled = measure
    text = 'timeout' if seconds is None else f'{seconds:.1f} s'
    return text + (' (compiled)' if compiled else '')


def main(argv=None) -> int:
    """Build, start each program twice, print the table."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--source', type=Path, default=REPO,
                        help='checkout to build (default: this one)')
    parser.add_argument('--symlink-install', action='store_true',
                        help='colcon build --symlink-install')
    parser.add_argument('--keep', action='store_true', help='keep the temporary workspaces')
    args = parser.parse_args(argv)

    root = Path(tempfile.mkdtemp(prefix='rope_sim_cold_start_'))
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    rows, builds = [], []

    def node_start(prefix: Path, home: Path, log: Path) -> tuple:
        probe = Probe(context, f'{NAMESPACE}_{log.stem}')
        try:
            return probe.time_to_tension(prefix, home, log)
        finally:
            probe.node.destroy_node()

    try:
        prefix, seconds = build(args.source.resolve(), root / 'node', args.symlink_install)
        builds.append(seconds)
        home = root / 'node' / 'home'
        rows.append(('mooring_line: process start -> first fairlead/tension',
                     node_start(prefix, home, root / 'node' / 'cold.log'),
                     node_start(prefix, home, root / 'node' / 'warm.log')))
        prefix, seconds = build(args.source.resolve(), root / 'run', args.symlink_install)
        builds.append(seconds)
        home = root / 'run' / 'home'
        rows.append(('rope_sim run: 60 s, 50 segments steel_wire, whole process',
                     run_time(prefix, home, root / 'run' / 'out.csv'),
                     run_time(prefix, home, root / 'run' / 'out.csv')))
    finally:
        rclpy.try_shutdown(context=context)
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)
    load = ', '.join(f'{v:.2f}' for v in os.getloadavg())
    print(f'cold start of {args.source.resolve()}'
          f'{" (--symlink-install)" if args.symlink_install else ""}: {os.cpu_count()} CPUs, '
          f'load average {load}; ROS_DOMAIN_ID={os.environ["ROS_DOMAIN_ID"]}')
    width = max(len(r[0]) for r in rows)
    print(f'{"":{width}}  {"first after build":>20}  {"second":>14}')
    for name, cold, warm in rows:
        print(f'{name:{width}}  {cell(cold):>20}  {cell(warm):>14}')
    print(f'{"colcon build of a fresh workspace":{width}}  '
          + '  '.join(f'{s:.1f} s' for s in builds))
    if args.keep:
        print(f'workspaces kept in {root}')
    return 0 if all(r[1][0] is not None and r[2][0] is not None for r in rows) else 1


if __name__ == '__main__':
    sys.exit(main())
