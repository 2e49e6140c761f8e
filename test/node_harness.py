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

"""The installed nodes as child processes, and the test client that talks to them over DDS."""

import contextlib
import gc
from pathlib import Path
import signal
import subprocess
import time
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Tuple

from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.signals import SignalHandlerOptions
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Trigger

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

    def interrupt(self, timeout: float = 20.0) -> int:
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


class Inbox(list):
    """
    What a client keeps of one topic's messages, in arrival order.

    Each entry is value(message), by default the pair (arrival, message) (arrival:
    time.monotonic() [s] on receipt). The writer's sequence number of each is in
    `sequences`: the messages of one output of the node, published together, share it.
    """

    def __init__(self, value: Optional[Callable] = None):
        """Keep value(message) of each message; by default (arrival, message)."""
        super().__init__()
        self.sequences: List[int] = []
        self.subscription = None  # the client's subscription that fills it
        self._value = value
        self._messages = []

    def keep(self, msg, info) -> None:
        """Take a message (a subscription callback with its MessageInfo)."""
        self.append((time.monotonic(), msg) if self._value is None else self._value(msg))
        self.sequences.append(info['publication_sequence_number'])
        self._messages.append(msg)

    def clear(self) -> None:
        """Forget what was kept."""
        super().clear()
        self.sequences.clear()
        self._messages.clear()

    def by_sequence(self) -> dict:
        """Return {writer sequence number: message}."""
        return dict(zip(self.sequences, self._messages))


class Keep(NamedTuple):
    """A topic a client subscribes to, and what it keeps of each message (see Inbox)."""

    topic: str
    msg_type: type
    qos: Any = 2000  # a depth or a QoSProfile
    value: Optional[Callable] = None


# The mooring_line node's outputs: each publishes one of each, together.
LINE_OUTPUTS = {'particles': Keep('rope/particles', PoseArray),
                'fairlead': Keep('fairlead/tension', Wrench),
                'bollard': Keep('bollard/tension', Wrench)}


class Sent(NamedTuple):
    """A pose a client published."""

    stream: str  # 'fairlead', 'bollard', 'ship'
    stamp_ns: int
    position: Tuple[float, float, float]
    orientation: Tuple[float, float, float, float]  # x, y, z, w
    made: float  # time.monotonic() [s] when it was made (a held one is sent later)


class Client:
    """
    A test node beside an installed node: its poses (and /clock) out, its outputs kept.

    In sim time (sim_time True) the client publishes /clock and is the node's only clock:
    the node's time is what the test says (drive). On the wall clock its poses are
    stamped when they are sent (drive_wall). It publishes each pose stream's `<stream>/pose`
    (client.publishers, by topic), keeps each topic of `keep` as an Inbox named
    `client.<name>` (a dict of Keep: a dict of Inboxes), and calls the node's parameter and
    ~/reset services (client.parameters, client.reset). Topics are relative to `namespace`.
    """

    def __init__(self, namespace: str = '', node: str = 'mooring_line',
                 poses: Tuple[str, ...] = ('fairlead', 'bollard'),
                 keep: Optional[Dict[str, Any]] = None, sim_time: bool = True,
                 pose_depth: int = 1000, bollard_depth: int = 0):
        """
        Create the test node for the node named `node` (mooring_line, mooring).

        :param keep: {name: Keep or {key: Keep}}; None: the mooring_line node's outputs
            (LINE_OUTPUTS: client.particles, client.fairlead, client.bollard, outputs()).
        :param pose_depth: the pose publishers keep this many poses (the bollard's
            bollard_depth, if given).
        """
        self.context = rclpy.Context()
        rclpy.init(context=self.context, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node('test_client', namespace=namespace, context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.publishers = {}  # by topic, as given
        self._inboxes: List[Inbox] = []
        for stream in poses:
            self.publisher(f'{stream}/pose', PoseStamped,
                           bollard_depth if stream == 'bollard' and bollard_depth else pose_depth)
        if sim_time:
            self.publisher('/clock', Clock, 10)
        for name, spec in (LINE_OUTPUTS if keep is None else keep).items():
            setattr(self, name, self._subscribe_all(spec))
        self.parameters = AsyncParameterClient(self.node, node)
        self.reset = self.node.create_client(Trigger, f'{node}/reset')
        self._paired = ((), [])

    def _subscribe_all(self, spec):
        if isinstance(spec, dict):
            return {key: self._subscribe_all(each) for key, each in spec.items()}
        return self.subscribe(*spec)

    def publisher(self, topic: str, msg_type, qos=10):
        """Create client.publishers[topic]: the node must match it (wait_for_node)."""
        publisher = self.publishers[topic] = self.node.create_publisher(msg_type, topic, qos)
        return publisher

    def subscribe(self, topic: str, msg_type, qos=2000, value=None) -> Inbox:
        """Keep a topic's messages in an Inbox; the node must publish it (wait_for_node)."""
        inbox = Inbox(value)
        inbox.subscription = self.node.create_subscription(msg_type, topic, inbox.keep, qos)
        self._inboxes.append(inbox)
        return inbox

    def close(self) -> None:
        """Destroy the test node and its context."""
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)

    def clear(self) -> None:
        """Forget what was received so far."""
        for inbox in self._inboxes:
            inbox.clear()

    # -- waiting --------------------------------------------------------------------------

    def spin_once(self, timeout: float = 0.002) -> None:
        """Process the callbacks that are ready, waiting at most `timeout` [s]."""
        self.executor.spin_once(timeout_sec=timeout)

    def spin(self, seconds: float) -> None:
        """Process callbacks for `seconds` of the wall clock."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.executor.spin_once(timeout_sec=min(0.01, max(0.0, end - time.monotonic())))

    def wait_for(self, condition, timeout: float, what: str, node=None) -> None:
        """Spin until condition() holds; fail after `timeout` [s] (or if `node` exits)."""
        spin_until(self.executor, condition, timeout, what, node)

    def wait_for_node(self, node: NodeProcess, timeout: float = 90.0) -> None:
        """Wait until the node serves its services and matches every topic both ways."""
        def ready():
            if node.process.poll() is not None:
                raise AssertionError(f'node exited with {node.process.returncode}:\n'
                                     f'{node.text()}')
            return (self.parameters.services_are_ready() and self.reset.service_is_ready()
                    and all(p.get_subscription_count() > 0 for p in self.publishers.values())
                    and all(i.subscription.get_publisher_count() > 0 for i in self._inboxes))
        self.wait_for(ready, timeout, f'the node in {node.namespace}')

    def call(self, future, timeout: float = 10.0):
        """Spin until a service's future completes; return its result."""
        self.wait_for(future.done, timeout, 'a service response')
        return future.result()

    def set_parameter(self, name: str, value, timeout: float = 10.0):
        """Set one parameter of the node; return its SetParametersResult."""
        future = self.parameters.set_parameters([Parameter(name, value=value)])
        self.wait_for(future.done, timeout, f'setting {name}')
        return future.result().results[0]

    # -- the line node's outputs ----------------------------------------------------------

    def outputs(self) -> list:
        """
        Return [(stamp_ns, fairlead N, bollard N)] of every complete output, in order.

        The three topics of one output are paired by the writers' sequence numbers.
        """
        inboxes = (self.particles, self.fairlead, self.bollard)
        sizes = tuple(len(inbox) for inbox in inboxes)
        if sizes != self._paired[0]:
            particles, fairlead, bollard = (inbox.by_sequence() for inbox in inboxes)
            self._paired = (sizes, [
                (_stamp(particles[k]), _norm(fairlead[k]), _norm(bollard[k]))
                for k in sorted(particles) if k in fairlead and k in bollard])
        return self._paired[1]

    # -- publishing -----------------------------------------------------------------------

    def clock(self, ns: int) -> None:
        """Publish /clock = ns."""
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = divmod(ns, 1_000_000_000)
        self.publishers['/clock'].publish(msg)

    def pose(self, position, stamp_ns: Optional[int] = None, to='fairlead',
             orientation=(0.0, 0.0, 0.0, 1.0)) -> Sent:
        """
        Publish a PoseStamped at position (x, y, z), orientation (x, y, z, w).

        :param stamp_ns: its stamp; None: now on the wall clock.
        :param to: a pose stream of this client ('fairlead', 'ship', ...) or a publisher.
        """
        sent = self._make(to if isinstance(to, str) else '', position, orientation, stamp_ns)
        msg = PoseStamped()
        msg.header.frame_id = 'world'
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(sent.stamp_ns, 1_000_000_000)
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = sent.position
        (msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z,
         msg.pose.orientation.w) = sent.orientation
        (self.publishers[f'{to}/pose'] if isinstance(to, str) else to).publish(msg)
        return sent

    @staticmethod
    def _make(stream: str, position, orientation, stamp_ns: Optional[int]) -> Sent:
        return Sent(stream, time.time_ns() if stamp_ns is None else stamp_ns,
                    tuple(float(c) for c in position), tuple(float(c) for c in orientation),
                    time.monotonic())

    @no_gc_pauses()
    def drive(self, start_ns: int, seconds: float, fairlead=None, bollard=None,
              rate=50.0, speed=1.0, at=None, ship=None) -> List[Sent]:
        """
        Publish /clock and the poses of sim time [start_ns, start_ns + seconds] at `rate`.

        Sim time runs at `speed` times the wall clock with this process: a stall here pauses
        the node's time as well. fairlead(t), bollard(t) and ship(t) give an end's position
        at t [s] from start_ns, or a (position, orientation (x, y, z, w)) pair, or None for
        no pose then (fairlead, bollard or ship None: none of that stream). at(t), if given,
        runs before each sample: it may publish poses of its own, or return False (no pose
        at t: /clock only) or 'hold' (the poses of t wait and go out with the next ones
        sent, as after a transport hiccup).

        :returns: the poses published, in publishing order.
        """
        return self._send(seconds, rate, speed, at, start_ns,
                          {'fairlead': fairlead, 'bollard': bollard, 'ship': ship})

    @no_gc_pauses()
    def drive_wall(self, seconds: float, fairlead=None, bollard=None, rate=50.0, at=None,
                   ship=None) -> List[Sent]:
        """
        Publish poses at `rate` for [0, seconds] of the wall clock, each stamped as it is made.

        As drive, without /clock: t [s] is when a pose is due (k / rate from the first);
        a late one (this process stalled) has the position of its due time.
        """
        return self._send(seconds, rate, 1.0, at, None,
                          {'fairlead': fairlead, 'bollard': bollard, 'ship': ship})

    def _send(self, seconds, rate, speed, at, start_ns, ends) -> List[Sent]:
        ends = {stream: end for stream, end in ends.items() if end is not None}
        sent, held = [], []
        wall = time.monotonic()
        for k in range(round(seconds * rate) + 1):
            t = k / rate
            while (wait := t / speed - (time.monotonic() - wall)) > 0:
                self.executor.spin_once(timeout_sec=min(0.002, wait))
            wanted = None if at is None else at(t)
            if start_ns is None:
                ns = time.time_ns()
            else:
                ns = start_ns + round(t * 1e9)
                self.clock(ns)
            if wanted is False:
                continue
            for stream, end in ends.items():
                value = end(t)
                if value is None:
                    continue
                position, orientation = (value if isinstance(value, tuple) and len(value) == 2
                                         else (value, (0.0, 0.0, 0.0, 1.0)))
                held.append(self._make(stream, position, orientation, ns))
            if wanted == 'hold':
                continue
            sent += [self.pose(p.position, p.stamp_ns, p.stream, p.orientation)._replace(
                made=p.made) for p in held]
            held = []
        return sent


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
