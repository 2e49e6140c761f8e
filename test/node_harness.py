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

"""The installed mooring_line executable as a child process, shared by the node tests."""

import contextlib
import gc
from pathlib import Path
import signal
import subprocess
import time
from typing import List

from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.signals import SignalHandlerOptions
from rosgraph_msgs.msg import Clock

# Every node started in this test session, for the failure report (conftest.py).
STARTED: List['NodeProcess'] = []


@contextlib.contextmanager
def no_gc_pauses():
    """
    Keep the cyclic garbage collector out of a timed publishing loop.

    A full collection in a pytest process holding the messages of earlier tests took up to
    0.13 s: long enough to look like a pose stream falling silent.
    """
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


class NodeProcess:
    """mooring_line from a colcon install with the package's parameter file, its log in a file."""

    def __init__(self, install: Path, env: dict, log: Path, namespace: str, *ros_args: str):
        """Start the node in namespace with extra --ros-args (e.g. '-p', 'length:=40')."""
        self.log = log
        self.namespace = namespace
        self.started = time.monotonic()
        command = [
            str(install / 'lib' / 'rope_sim_ros' / 'mooring_line'), '--ros-args',
            '--params-file', str(install / 'share' / 'rope_sim_ros' / 'config' /
                                 'mooring_line.yaml'),
            '-r', f'__ns:={namespace}', *ros_args]
        with open(log, 'w') as f:
            self.process = subprocess.Popen(
                command, env=env, stdin=subprocess.DEVNULL, stdout=f, stderr=subprocess.STDOUT)
        STARTED.append(self)

    def text(self) -> str:
        """Return the node's output so far."""
        return self.log.read_text(errors='replace')

    def stop(self, signum: int = signal.SIGINT, timeout: float = 20.0) -> int:
        """Send a signal (Ctrl-C by default), wait for the exit and return the exit code."""
        if self.process.poll() is None:
            self.process.send_signal(signum)
        try:
            return self.process.wait(timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            raise AssertionError(f'node ignored signal {signum} for {timeout} s:\n{self.text()}')

    def interrupt(self, timeout: float = 15.0) -> int:
        """Send SIGINT (Ctrl-C) and return the exit code."""
        return self.stop(signal.SIGINT, timeout)


class Executable(NodeProcess):
    """Any installed executable of the package with its arguments, its log in a file."""

    def __init__(self, install: Path, env: dict, log: Path, name: str, *args: str):
        """Start install/lib/rope_sim_ros/<name> with args (e.g. '--ros-args', ...)."""
        self.log = log
        self.namespace = name
        self.started = time.monotonic()
        with open(log, 'w') as f:
            self.process = subprocess.Popen(
                [str(install / 'lib' / 'rope_sim_ros' / name), *args], env=env,
                stdin=subprocess.DEVNULL, stdout=f, stderr=subprocess.STDOUT)
        STARTED.append(self)


def spin_until(executor, condition, timeout: float, what: str, node=None) -> None:
    """
    Spin an executor until condition() holds; fail after `timeout` [s] of the wall clock.

    :param node: a NodeProcess: fail at once, with its log, if it exits meanwhile.
    """
    end = time.monotonic() + timeout
    while not condition():
        if node is not None and node.process.poll() is not None:
            raise AssertionError(f'node exited:\n{node.text()}')
        if time.monotonic() > end:
            raise AssertionError(f'timed out after {timeout} s waiting for {what}')
        executor.spin_once(timeout_sec=0.01)


def bag_events(bag: Path) -> list:
    """Return the events a node recorded in its bag (decoded JSON), in log-time order."""
    import json
    from rope_sim_ros.bag import read_messages
    from rope_sim_ros.ros2bag import deserialize
    return [json.loads(deserialize(m).data)
            for m in read_messages(bag) if m.topic.endswith('/events')]


BERTH_SHARED = ('lines', 'ship_frame_id', 'frame_id', 'publish_rate', 'marker_rate', 'integrator',
                'time_step', 'segments')


def berth_file(path: Path, lengths=None) -> Path:
    """
    Write config/berth.yaml's ship and eight lines as an arrangement file; return its path.

    Only the lines and the settings they share (this file's ship needs no more). With
    `lengths` ({line: m}) each line has its length instead of its pretension.
    """
    import yaml
    berth = Path(__file__).resolve().parent.parent / 'config' / 'berth.yaml'
    values = yaml.safe_load(berth.read_text())['/**/mooring']['ros__parameters']
    values = {key: value for key, value in values.items()
              if key in BERTH_SHARED or key in values['lines']}
    for name, length in (lengths or {}).items():
        del values[name]['pretension']
        values[name]['length'] = length
    path.write_text(yaml.safe_dump({'/**/mooring': {'ros__parameters': values}}))
    return path


class SimClient:
    """
    A test node that drives a mooring_line node in sim time: /clock, poses, parameters.

    Every pose is published with an explicit stamp and /clock is published by this client
    only, so the node's time is what the test says. The node's outputs are kept as
    (stamp [ns], fairlead tension [N], bollard tension [N]) per output: the three topics of
    one output are paired by the writers' sequence numbers (the node publishes them together).
    """

    def __init__(self, namespace: str, pose_depth: int = 1000, output_depth: int = 2000,
                 bollard_depth: int = 0):
        """Create the test node; the pose publishers keep pose_depth (bollard_depth) poses."""
        self.context = rclpy.Context()
        rclpy.init(context=self.context, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node('guard_client', namespace=namespace, context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.fairlead_pub = self.node.create_publisher(PoseStamped, 'fairlead/pose', pose_depth)
        self.bollard_pub = self.node.create_publisher(PoseStamped, 'bollard/pose',
                                                      bollard_depth or pose_depth)
        self.clock_pub = self.node.create_publisher(Clock, '/clock', 10)
        self._particles, self._fairlead, self._bollard = {}, {}, {}
        self._subscriptions = [
            self.node.create_subscription(PoseArray, 'rope/particles',
                                          self._keep(self._particles, _stamp), output_depth),
            self.node.create_subscription(Wrench, 'fairlead/tension',
                                          self._keep(self._fairlead, _norm), output_depth),
            self.node.create_subscription(Wrench, 'bollard/tension',
                                          self._keep(self._bollard, _norm), output_depth),
        ]
        self.parameters = AsyncParameterClient(self.node, 'mooring_line')

    @staticmethod
    def _keep(store: dict, value):
        def keep(msg, info):
            store[info['publication_sequence_number']] = value(msg)
        return keep

    def close(self) -> None:
        """Destroy the test node and its context."""
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)

    def clear(self) -> None:
        """Forget the outputs received so far."""
        for store in (self._particles, self._fairlead, self._bollard):
            store.clear()

    def outputs(self) -> list:
        """Return [(stamp_ns, fairlead N, bollard N)] of every complete output, in order."""
        return [(self._particles[k], self._fairlead[k], self._bollard[k])
                for k in sorted(self._particles) if k in self._fairlead and k in self._bollard]

    def spin_once(self, timeout: float = 0.002) -> None:
        """Process the callbacks that are ready, waiting at most `timeout` [s]."""
        self.executor.spin_once(timeout_sec=timeout)

    def wait_for(self, condition, timeout: float, what: str) -> None:
        """Spin until condition() holds; fail after `timeout` [s] of the wall clock."""
        spin_until(self.executor, condition, timeout, what)

    def wait_for_node(self, node: NodeProcess, timeout: float = 60.0) -> None:
        """Wait until the node matches every topic both ways and serves its parameters."""
        def ready():
            if node.process.poll() is not None:
                raise AssertionError(f'node exited with {node.process.returncode}:\n'
                                     f'{node.text()}')
            return (self.parameters.services_are_ready()
                    and self.fairlead_pub.get_subscription_count() > 0
                    and self.bollard_pub.get_subscription_count() > 0
                    and self.clock_pub.get_subscription_count() > 0
                    and all(s.get_publisher_count() > 0 for s in self._subscriptions))
        self.wait_for(ready, timeout, f'the node in {node.namespace}')

    def clock(self, ns: int) -> None:
        """Publish /clock = ns."""
        sec, nanosec = divmod(ns, 1_000_000_000)
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = sec, nanosec
        self.clock_pub.publish(msg)

    def pose(self, position, stamp_ns: int, publisher=None,
             orientation=(0.0, 0.0, 0.0, 1.0)) -> None:
        """Publish a PoseStamped at `position` (x, y, z, w `orientation`) stamped stamp_ns."""
        msg = PoseStamped()
        msg.header.frame_id = 'world'
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (
            float(c) for c in position)
        (msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z,
         msg.pose.orientation.w) = (float(c) for c in orientation)
        (publisher or self.fairlead_pub).publish(msg)

    def set_parameter(self, name: str, value, timeout: float = 10.0):
        """Set one parameter of the node; return its SetParametersResult."""
        future = self.parameters.set_parameters([Parameter(name, value=value)])
        self.wait_for(future.done, timeout, f'setting {name}')
        return future.result().results[0]

    @no_gc_pauses()
    def drive(self, start_ns: int, seconds: float, fairlead, bollard=None, rate: float = 50.0,
              speed: float = 1.0, at=None) -> None:
        """
        Publish /clock and the poses of sim time [start_ns, start_ns + seconds] at `rate`.

        Sim time runs at `speed` times the wall clock with this process: a stall here pauses
        the node's time as well. fairlead(t) and bollard(t) give the positions at t [s] from
        start_ns, or None for no pose then (fairlead or bollard None: /clock only, or no
        bollard poses), or a (position, orientation (x, y, z, w)) pair; at(t), if given,
        runs before each sample.
        """
        wall = time.monotonic()
        for k in range(round(seconds * rate) + 1):
            t = k / rate
            while time.monotonic() - wall < t / speed:
                self.executor.spin_once(timeout_sec=0.002)
            if at is not None:
                at(t)
            ns = start_ns + round(t * 1e9)
            self.clock(ns)
            for end, publisher in ((fairlead, self.fairlead_pub), (bollard, self.bollard_pub)):
                position = None if end is None else end(t)
                if isinstance(position, tuple) and len(position) == 2:
                    self.pose(position[0], ns, publisher, position[1])
                elif position is not None:
                    self.pose(position, ns, publisher)


def _stamp(msg) -> int:
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


def _norm(msg) -> float:
    f = msg.force
    return (f.x * f.x + f.y * f.y + f.z * f.z) ** 0.5


def node_summary(node: NodeProcess, topic: str) -> tuple:
    """
    Return (received, dropped, lost) of a pose topic from the node's closing log line.

    The node writes it when it stops: 'poses: fairlead/pose: 10000 received, 0 dropped,
    0 lost on the way; bollard/pose: ...', without a topic that had none.
    """
    for line in node.text().splitlines():
        if ']: poses: ' in line:
            if f'{topic}: ' not in line:
                return (0, 0, 0)
            part = line.split(f'{topic}: ')[1].split(';')[0].split(', ')
            return tuple(int(p.split()[0]) for p in part)
    raise AssertionError(f'no summary of the poses in the node log:\n{node.text()}')
