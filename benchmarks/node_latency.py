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
Latency of the mooring_line node: from a fairlead pose to the next tension message.

Starts the colcon-installed node (<repo>/install, built with colcon first if missing) in its
own ROS domain, publishes --count fairlead poses at --rate Hz (a 0.1 m, 0.5 Hz motion along
the chord, each pose computed at its stamp) after a second of warm-up, and measures, in
wall-clock time from each publish:

- next tension: the first fairlead/tension message received after it (what a ship
  simulator waiting for a force sees);
- simulated: the first rope/particles message whose state time has reached its stamp (to
  within one time step). The node never steps past the second-newest pose of a live
  stream, so it passes a pose's stamp only once the next pose has arrived, and its outputs
  fall every 1 / publish_rate of simulated time.

Queues grew if the effect latency of the last tenth of the poses is more than a publish
period above that of the first tenth, or if outputs went missing.

    python benchmarks/node_latency.py [--rate 50] [--count 1000] [--publish-rate 50]
"""

import argparse
import math
import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from geometry_msgs.msg import PoseArray, PoseStamped, Wrench  # noqa: E402
import numpy as np  # noqa: E402
import rclpy  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.qos import QoSProfile  # noqa: E402
from rclpy.signals import SignalHandlerOptions  # noqa: E402
from rope_sim_ros.mooring.mooring import Mooring  # noqa: E402
from rope_sim_ros.offline.demo import overlay_environment  # noqa: E402
from rope_sim_ros.params.arrangement import single_line  # noqa: E402
from rope_sim_ros.params.files import load_params  # noqa: E402

FAIRLEAD = np.array([36.0, 0.0, 8.0])
CHORD = FAIRLEAD / np.linalg.norm(FAIRLEAD)
NAMESPACE = '/bench'


def ensure_install(install: Path) -> Path:
    """Return the package prefix under `install`, building it with colcon if missing."""
    prefix = install / 'rope_sim_ros'
    if not (prefix / 'lib' / 'rope_sim_ros' / 'mooring_line').is_file():
        print(f'building into {install} with colcon ...', flush=True)
        subprocess.run(
            [sys.executable, '-m', 'colcon', '--log-base', str(install.parent / 'log'),
             'build', '--paths', str(REPO), '--build-base', str(install.parent / 'build'),
             '--install-base', str(install), '--event-handlers', 'console_cohesion-',
             'status-'], check=True, cwd=str(install.parent))
    return prefix


class Bench:
    """The measuring node: a pose publisher thread, tension and particle subscriptions."""

    def __init__(self, context: rclpy.Context):
        """Create the node, its publisher and subscriptions."""
        self.node = rclpy.create_node('latency_bench', namespace=NAMESPACE, context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.publisher = self.node.create_publisher(
            PoseStamped, 'fairlead/pose', QoSProfile(depth=1000))
        self.tension_times = []  # perf_counter at receipt
        self.particles = []  # (perf_counter at receipt, stamp ns)
        self.node.create_subscription(
            Wrench, 'fairlead/tension',
            lambda msg: self.tension_times.append(time.perf_counter()), 1000)
        self.node.create_subscription(PoseArray, 'rope/particles', self._on_particles, 1000)
        self.sent = []  # (perf_counter at publish, stamp ns)

    def _on_particles(self, msg: PoseArray) -> None:
        stamp = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        self.particles.append((time.perf_counter(), stamp))

    def spin_until(self, condition, timeout: float) -> bool:
        """Spin until condition() holds; return False on timeout."""
        end = time.monotonic() + timeout
        while not condition():
            if time.monotonic() > end:
                return False
            self.executor.spin_once(timeout_sec=0.01)
        return True

    def publish(self, rate: float, warm_up: int, count: int) -> None:
        """Publish warm_up + count poses at `rate` (run in a thread)."""
        start = time.perf_counter()
        start_ns = time.time_ns()
        for k in range(warm_up + count):
            due = start + k / rate
            time.sleep(max(0.0, due - time.perf_counter()))
            stamp_ns = time.time_ns()
            t = (stamp_ns - start_ns) * 1e-9
            p = FAIRLEAD + 0.1 * math.sin(math.pi * t) * min(t, 1.0) * CHORD
            msg = PoseStamped()
            msg.header.frame_id = 'world'
            msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
            msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = p.tolist()
            msg.pose.orientation.w = 1.0
            published = time.perf_counter()
            self.publisher.publish(msg)
            if k >= warm_up:
                self.sent.append((published, stamp_ns))


def percentiles(values) -> str:
    """Return 'median x ms, p99 y ms, max z ms' of seconds."""
    v = np.asarray(values) * 1e3
    return (f'median {np.median(v):6.2f} ms, p99 {np.percentile(v, 99):6.2f} ms, '
            f'max {v.max():6.2f} ms')


def analyse(bench: Bench, rate: float, publish_rate: float, time_step: float) -> int:
    """Print the latencies; return 0 when no queue grew."""
    sent = np.array([s[0] for s in bench.sent])
    stamps = np.array([s[1] for s in bench.sent])
    tensions = np.array(bench.tension_times)
    arrivals = np.array([p[0] for p in bench.particles])
    particle_stamps = np.array([p[1] for p in bench.particles])
    k = np.searchsorted(tensions, sent, side='right')
    next_tension = tensions[k[k < len(tensions)]] - sent[k < len(tensions)]
    # the first particles message whose state time reached the pose stamp (stamps rise)
    reached = np.maximum.accumulate(particle_stamps)
    j = np.searchsorted(reached, stamps - int(time_step * 1e9), side='left')
    ok = j < len(arrivals)
    effect = arrivals[j[ok]] - sent[ok]
    print(f'poses: {len(sent)} at {rate:g} Hz; node publish_rate {publish_rate:g} Hz')
    print(f'pose -> next fairlead/tension: {percentiles(next_tension)} '
          f'({len(next_tension)} poses)')
    print(f'pose -> simulated (particles stamp >= pose stamp - {time_step * 1e3:.3f} ms): '
          f'{percentiles(effect)} '
          f'({len(effect)} poses)')
    tenth = max(1, len(effect) // 10)  # effect: the 'simulated' latency
    growth = float(np.median(effect[-tenth:]) - np.median(effect[:tenth]))
    duration = sent[-1] - sent[0]
    in_window = np.count_nonzero((arrivals >= sent[0]) & (arrivals <= sent[-1]))
    expected = duration * publish_rate
    missing = in_window < 0.9 * expected
    grew = growth > 1.0 / publish_rate or missing or not ok.all()
    print(f'outputs while publishing: {in_window} (expected ~{expected:.0f}); effect latency '
          f'last tenth - first tenth: {growth * 1e3:+.2f} ms; unprocessed poses at the end: '
          f'{np.count_nonzero(~ok)}')
    print('queues grew: ' + ('YES' if grew else 'no'))
    return 1 if grew else 0


def main(argv=None) -> int:
    """Run the benchmark; exit code 1 if a queue grew."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--rate', type=float, default=50.0, help='pose rate [Hz] (50)')
    parser.add_argument('--count', type=int, default=1000, help='poses measured (1000)')
    parser.add_argument('--publish-rate', type=float, default=None,
                        help="the node's publish_rate [Hz] (default: config/mooring_line.yaml)")
    parser.add_argument('--install', type=Path, default=REPO / 'install',
                        help='colcon install base (default <repo>/install)')
    args = parser.parse_args(argv)

    prefix = ensure_install(args.install.resolve())
    env = overlay_environment(prefix)
    os.environ['ROS_DOMAIN_ID'] = env['ROS_DOMAIN_ID']
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = env['ROS_AUTOMATIC_DISCOVERY_RANGE']
    params_file = prefix / 'share' / 'rope_sim_ros' / 'config' / 'mooring_line.yaml'
    line = load_params(params_file)
    if args.publish_rate is not None:
        line = line.with_values({'publish_rate': args.publish_rate})
    node = subprocess.Popen(
        [str(prefix / 'lib' / 'rope_sim_ros' / 'mooring_line'), '--ros-args',
         '--params-file', str(params_file), '-r', f'__ns:={NAMESPACE}',
         '-p', f'publish_rate:={line.publish_rate}'],
        env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE, text=True)
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    bench = Bench(context)
    code = 2
    try:
        if not bench.spin_until(lambda: bench.publisher.get_subscription_count() > 0, 120.0):
            print('the node did not subscribe within 120 s', file=sys.stderr)
            return 2
        bench.spin_until(lambda: False, 1.0)  # discovery settles both ways
        warm_up = int(args.rate)  # one second
        thread = threading.Thread(target=bench.publish, args=(args.rate, warm_up, args.count))
        thread.start()
        bench.spin_until(lambda: not thread.is_alive(), args.count / args.rate + 60.0)
        bench.spin_until(lambda: False, 0.5)  # the last outputs
        # the node's step: a mooring of its one line, outputs every 1 / publish_rate
        mooring = Mooring(single_line(line), output_interval=1.0 / line.publish_rate)
        code = analyse(bench, args.rate, line.publish_rate, mooring.time_step)
    finally:
        bench.node.destroy_node()
        rclpy.try_shutdown(context=context)
        node.send_signal(signal.SIGINT)
        try:
            _, errors = node.communicate(timeout=15)
        except subprocess.TimeoutExpired:
            node.kill()
            _, errors = node.communicate()
        warnings = [line for line in errors.splitlines() if 'WARN' in line or 'ERROR' in line]
        if warnings:
            print('node warnings:\n  ' + '\n  '.join(warnings[:10]))
        print(f'node exit code {node.returncode}')
    return code


if __name__ == '__main__':
    sys.exit(main())
