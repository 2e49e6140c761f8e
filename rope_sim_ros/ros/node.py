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
The one node: a mooring of one line (mooring_line) or of a ship's lines (mooring).

ROS glue only. Its parameters (ros/parameters.py, from the one table) become a Driver
(mooring/driver.py), which holds the input and output rules the offline commands use too:
simulated time 0 at the first pose, the ropes one sample behind a live pose stream, outputs
every 1 / publish_rate from the last (re)start, skip ahead past MAX_LAG, each output's
torque levers. Outputs are published as soon as the ropes reach them: in the pose callback
that lets them, or in a timer tick when no pose stream is live. Its topics are the node
kind's (messages/topics.py): the two executables differ in their parameters and topics
only.

Inputs: the ship's pose (mooring_line: fairlead/pose, its fairlead the pose ⊕
fairlead_offset; mooring: ship/pose, every fairlead moving with it), each line's
bollard/pose (optional: a bollard that moves) and winch/command. Outputs per line: its
particles, the forces on both ends, their peaks, its winch length, whether it parted
(latched), a payload's pose; for a ship (mooring): the total wrench of the lines on it,
markers and diagnostics. Decisions taken on the node clock (a stream taken for silent, a
skip ahead, a restart by ~/reset or by a clock jump back, a pose dropped for its stamp or
stamped on receipt, a parameter set and a winch commanded at run time) and partings are
published on the events topic (std_msgs/String, one JSON object each) and recorded, so that
`rope_sim resim` of the node's bag takes them at the same points and reproduces its outputs.

Time: the ropes follow the node clock, so use_sim_time and /clock work. The clock rules (when
a stream is silent, which stamps are taken, how many outputs one call reaches, when a held
output goes out) are mooring/pacing.py's Pacer: the node hands it each reading of its clock
with what happened and acts on what it decides. A pose jump larger than teleport_distance
restarts its line there. The pose queues hold POSE_QUEUE_DEPTH poses; poses DDS lost before
they reached the node are counted.

Recording (record_path): every received pose and published message also goes to a bag
through recorder.Recorder, which never blocks the tick; Ctrl-C and SIGTERM close the bag,
after SIGKILL `rope_sim recover` completes it.
"""

import functools
import math
import os
import re
import sys
import time
from typing import Any, Dict, List, Optional
import warnings

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseArray, PoseStamped, Vector3Stamped, Wrench, WrenchStamped
from nav_msgs.msg import Odometry
import numpy as np
from rcl_interfaces.msg import SetParametersResult
from rclpy.clock import Clock, ClockType
from rclpy.event_handler import QoSMessageLostInfo, SubscriptionEventCallbacks
from rclpy.exceptions import ParameterException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import (DurabilityPolicy, HistoryPolicy, QoSPolicyKind, QoSProfile,
                       ReliabilityPolicy)
from rclpy.qos_overriding_options import InvalidQosOverridesError, QoSOverridingOptions
from std_msgs.msg import Bool, Float64, Float64MultiArray, String
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

from . import conversions
from .mooring_display import bollard_statuses, Fenders, line_diagnostics, LineMarkers
from .outputs import OutputPublishers
from .parameters import NodeParameters, plain, ROS_PARAMETERS, StartupError
from .recorder import Recorder
from .spinning import run_node, set_timer_period
from ..bag import BagError
from ..messages import topics
from ..messages.encode import encoder_for, stiffness_message
from ..messages.topics import Layout, LINE_NODE, MOORING_NODE
from ..model.statics.ship import StaticsError
from ..mooring.driver import Driver, SHIP
from ..mooring.events import encode_event
from ..mooring.handling import LINE_COMMANDS
from ..mooring.pacing import Pace, Pacer
from ..mooring.records import Published
from ..mooring.ship import damping_advice
from ..mooring.trajectory import TrajectoryError
from ..params import arrangement
from ..params.arrangement import stored
from ..params.table import ParameterError

POSE_RELIABILITY = {'reliable': ReliabilityPolicy.RELIABLE,
                    'best_effort': ReliabilityPolicy.BEST_EFFORT}
# History depth of the pose subscriptions (KEEP_LAST). A full queue drops its oldest pose
# without a trace (DDS reports no loss for it): at depth 50 a burst of 10,000 poses reached
# the node as 747 to 887, a 1 kHz stream for 30 s lost 3.5 %. This holds a whole burst, or
# 10 s at 1 kHz, for about 2.5 MB more memory per topic once full.
POSE_QUEUE_DEPTH = 10000
QOS_OVERRIDES_ALLOWED = ('reliability reliable or best_effort, history keep_last or keep_all, '
                         'depth >= 1 for keep_last')
MESSAGE_CLASSES = {topics.POSE_ARRAY: PoseArray, topics.WRENCH: Wrench,
                   topics.POSE_STAMPED: PoseStamped, topics.FLOAT64: Float64,
                   topics.BOOL: Bool, topics.WRENCH_STAMPED: WrenchStamped,
                   topics.ODOMETRY: Odometry}
# whether a line has parted is a state, not a stream: latched, so that a monitor started later
# sees it
PARTED_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


# A number in a warning's text: the same warning with other numbers is the same kind (_warn).
NUMBER = re.compile(r'[-+]?\d+(?:\.\d*)?(?:e[-+]?\d+)?')


def check_pose_qos(qos: QoSProfile) -> SetParametersResult:
    """Refuse pose subscription QoS overrides that would keep no pose or never get one."""
    if qos.history != HistoryPolicy.KEEP_ALL and qos.depth < 1:
        return SetParametersResult(successful=False, reason=f'depth {qos.depth} keeps no pose')
    if qos.reliability not in POSE_RELIABILITY.values():
        return SetParametersResult(successful=False,
                                   reason=f'reliability {qos.reliability.name.lower()}')
    return SetParametersResult(successful=True)


def _fmt(point) -> str:
    return '(' + ', '.join(f'{c:.2f}' for c in point) + ')'


class MooringNode(Node):
    """A mooring of one or many lines; see the module docstring and docs/ros.md."""

    THROTTLE = 5.0  # seconds between repeated warnings of one kind
    NO_CLOCK_NOTICE = 2.0  # [s] of the steady clock a free ship waits for /clock unnoticed
    DIAGNOSTICS_PERIOD = 1.0  # [s] of the node's clock

    def __init__(self, layout: Layout = MOORING_NODE, **kwargs):
        """
        Declare the parameters, build the lines, then create the ROS interfaces.

        :param layout: the node kind's topics (LINE_NODE: mooring_line, MOORING_NODE).
        :raises StartupError: a parameter value is not allowed or a line cannot be built.
        """
        # the values of --params-file and -p, declared so that they can be read (then
        # undeclared, to be declared again with their descriptors: _given_parameters)
        super().__init__(layout.node_name, automatically_declare_parameters_from_overrides=True,
                         **kwargs)
        self.layout = layout
        self._last_log: Dict[tuple, float] = {}  # (key, kind of text): when last logged
        # per pose topic: messages taken, dropped (bad or far-off stamps) and lost before they
        # reached the node (DDS's message_lost count)
        self.received: Dict[str, int] = {}
        self.dropped: Dict[str, int] = {}
        self.lost: Dict[str, int] = {}
        self.skips = 0  # times the ropes skipped ahead (MAX_LAG)
        self.recorder: Optional[Recorder] = None
        self.driver: Optional[Driver] = None
        self._quiet = False  # parameters set from a topic: not logged (_on_environment)
        self.parameters = NodeParameters(layout)
        self.add_pre_set_parameters_callback(self.parameters.coerce)
        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._apply_parameters)
        given = self._given_parameters()
        setup = self.parameters.declare(self, given, self.get_logger().warning)
        try:
            self.driver = Driver(setup)
            warm_up(setup, self.get_logger().info)
        except ValueError as e:  # ParameterError, MaterialError, an unstable line
            raise StartupError(str(e)) from None
        advice = damping_advice(setup)
        if advice:
            self.get_logger().warning(advice)
        driver = self.driver
        self.names = list(driver.names)
        self.ratings = driver.ratings
        self.encoder = encoder_for(setup)
        self.pacer = Pacer(self.driver)  # the clock rules: silence, stamps, what goes out when
        self._unlogged: List[tuple] = []  # recorded before the node knew any time (record)
        self._last_log_ns = 0
        self._told_payload = False
        self._starting = False
        # the newest output and what the diagnostics gather between reports
        self._latest: Optional[Published] = None
        self._peaks = np.zeros(len(self.names))
        self._bollard_peaks = np.zeros(len(setup.bollards))  # each bollard's, at the outputs
        self._restarted: List[Optional[str]] = [None] * len(self.names)
        self._line_markers = LineMarkers()

        self._taken = OutputPublishers(self)
        self._outputs: Dict[str, Any] = {}
        for topic in self.encoder.output_topics:
            self._outputs[topic] = self._publisher(
                MESSAGE_CLASSES[self.encoder.types[topic]], topic, 10)
        for topic in self.encoder.parted_topics:
            self._outputs[topic] = self._publisher(Bool, topic, PARTED_QOS)
        self._events_pub = self._publisher(String, layout.events, 100)
        if layout.ship_outputs:
            self._markers_pub = self._publisher(MarkerArray, topics.MARKERS, 10)
            self._diagnostics_pub = self._publisher(DiagnosticArray, topics.DIAGNOSTICS, 10)
        self._pose_subs = {}
        for stream in self.driver.streams:
            if stream == SHIP and driver.free:
                continue  # a free ship's pose is an output
            topic = layout.stream_topic(stream)
            self._pose_subs[stream] = self._pose_subscription(
                topic, functools.partial(self._on_pose, stream))
        for name in given:
            if name.startswith('qos_overrides.') and not self.has_parameter(name):
                self.get_logger().warning(
                    f'ignoring unknown parameter {name!r}: the pose subscriptions take '
                    f'qos_overrides.{self.resolve_topic_name(layout.ship_pose)}.subscription.'
                    'reliability (and .history, .depth; the same for the bollard poses)')
        if any(s.qos_profile.reliability == ReliabilityPolicy.RELIABLE
               for s in self._pose_subs.values()):
            # rclpy's incompatible-QoS event was missed in 1 of 6 start-ups; the graph is
            # not. On the steady clock: under use_sim_time there may be no /clock yet.
            self._qos_timer = self.create_timer(
                1.0, self._check_pose_publishers, clock=Clock(clock_type=ClockType.STEADY_TIME))
        # without event handlers: rclpy's Python executor walks every handler at every
        # wake-up (on the events executor of spin_until_shutdown they cost nothing idle)
        self._winch_subs = [self.create_subscription(
            Float64, layout.line_topic(name, topics.WINCH_COMMAND),
            functools.partial(self._on_winch_command, name), 10,
            event_callbacks=SubscriptionEventCallbacks(use_default_callbacks=False))
            for name in self.names]
        self._external_sub = None
        self._environment_subs = {}
        self._stiffness_timer = None
        if layout.ship_outputs:
            if driver.free:
                self._external_sub = self.create_subscription(
                    WrenchStamped, topics.EXTERNAL_WRENCH, self._on_external_wrench, 10)
            self._environment_subs = {topic: self.create_subscription(
                Vector3Stamped, topic, functools.partial(self._on_environment, topic), 10)
                for topic in (topics.WIND, topics.CURRENT)}
            self._stiffness_pub = self._publisher(Float64MultiArray, topics.STIFFNESS, 10)
            self._set_stiffness_rate(setup.ship.stiffness_rate)
        self._reset_srv = self.create_service(Trigger, '~/reset', self._on_reset)
        self._command_srvs = self._command_services()
        if driver.free and self.get_parameter('use_sim_time').value:
            # a free ship starts at the first tick of a running clock: say what it waits for
            # (on the steady clock: without /clock no timer of the node clock runs)
            self._clock_timer = self.create_timer(
                self.NO_CLOCK_NOTICE, self._check_clock,
                clock=Clock(clock_type=ClockType.STEADY_TIME))
        rate = setup.shared.publish_rate
        self._timer = self.create_timer(self.pacer.tick_period(rate), self._on_tick)
        if layout.ship_outputs:
            self._markers_timer = self.create_timer(1.0 / setup.marker_rate, self._on_markers)
            self._diagnostics_timer = self.create_timer(self.DIAGNOSTICS_PERIOD,
                                                        self._on_diagnostics)
        self._start_recording()
        self.get_logger().info(self._started_text())

    def _given_parameters(self) -> Dict[str, Any]:
        """
        Return the values --params-file and -p gave, and undeclare them.

        rclpy declared them from its overrides without descriptors; the node declares its
        own again with theirs (NodeParameters.declare), the pose subscriptions their
        qos_overrides, and rclpy keeps its own (use_sim_time).
        """
        given = {name: plain(p.value) for name, p in self.get_parameters_by_prefix('').items()
                 if name not in ROS_PARAMETERS}
        for name in given:
            self.undeclare_parameter(name)
        return given

    def _waiting_for(self) -> str:
        """Say what starts the lines: the first ship pose, or a free ship's first tick."""
        if self.driver.free:
            return 'the free ship starts at its start pose at the first tick of the clock'
        return f'waiting for the first pose on {self._pose_subs[SHIP].topic_name}'

    def _started_text(self) -> str:
        """Say what was built and what the node waits for."""
        driver = self.driver
        waiting = self._waiting_for()
        if self.parameters.single:
            p = driver.arrangement.lines[0].params
            return (f'{p.material} line, {p.diameter * 1e3:g} mm, {p.length:g} m, '
                    f'{p.segments} segments, MBL {self.ratings[0].mbl / 1e3:.0f} kN, '
                    f'{p.integrator} step {driver.time_step * 1e3:.4g} ms; {waiting}')
        shared = driver.arrangement.shared
        return (f'{len(self.names)} lines ({", ".join(self.names)}), {shared.integrator} '
                f'step {driver.time_step * 1e3:.4g} ms, {driver.rate:g} Hz; {waiting}')

    def _publisher(self, cls, topic: str, qos):
        """
        Create an output's publisher, its subscribers counted (OutputPublishers.taken).

        Without rclpy's default incompatible-QoS handler: the outputs are reliable and
        volatile (the parted flag transient-local), which every subscriber's QoS takes.
        """
        return self._taken.create(cls, topic, qos, default_events=False)

    # -- parameters -----------------------------------------------------------------------

    def _validate_parameters(self, parameters: List[Parameter]) -> SetParametersResult:
        """On-set callback: refuse a value outside its range, or one a line cannot take."""
        try:
            for line, values in self.parameters.changes(parameters).items():
                if self.driver is not None and values:
                    self.driver.check_update(line, values)
        except (ParameterError, ValueError) as e:
            return SetParametersResult(successful=False, reason=str(e))
        return SetParametersResult(successful=True)

    def _apply_parameters(self, parameters: List[Parameter]) -> None:
        """Post-set callback: hand run-time changes to the lines at once."""
        if self.driver is None:  # still declaring
            return
        for p in parameters:
            if p.name == 'marker_rate' and self.layout.ship_outputs:
                set_timer_period(self._markers_timer, 1.0 / float(p.value))
                self.get_logger().info(f'set marker_rate = {p.value}')
            if p.name == 'stiffness_rate' and self.layout.ship_outputs:
                self._set_stiffness_rate(float(p.value))
                self.get_logger().info(f'set stiffness_rate = {p.value}')
        for line, values in self.parameters.changes(parameters).items():
            try:
                self.driver.update(line, values)
            except ValueError as e:  # validated already: the lines should never refuse
                self.get_logger().error(f'could not apply {values}: {e}')
                continue
            self._event('set', line=line, values=values)
            if 'publish_rate' in values:
                # the driver re-anchored the outputs; the ticks follow the rate
                set_timer_period(self._timer, self.pacer.tick_period())
            if not self._quiet:
                self.get_logger().info(f'set {line + "." if line else ""}' + ', '.join(
                    f'{k} = {v}' for k, v in values.items()))

    # -- inputs ---------------------------------------------------------------------------

    def _pose_subscription(self, topic: str, callback):
        """
        Subscribe to a pose topic: pose_reliability, POSE_QUEUE_DEPTH, losses counted.

        The standard parameters qos_overrides.<topic>.subscription.reliability / history /
        depth (read-only, <topic> resolved, e.g. /line_1/fairlead/pose) override them.

        :raises StartupError: an override is not a valid QoS value.
        """
        reliability = POSE_RELIABILITY[self.driver.arrangement.shared.pose_reliability]
        qos = QoSProfile(depth=POSE_QUEUE_DEPTH, reliability=reliability)
        overrides = QoSOverridingOptions(
            (QoSPolicyKind.RELIABILITY, QoSPolicyKind.HISTORY, QoSPolicyKind.DEPTH),
            callback=check_pose_qos)
        # Only the ship's stream keeps rclpy's default incompatible-QoS handlers: rclpy's
        # Python executor walks every handler at every wake-up (16 lines' bollard streams
        # tripled its walk), and one warning for a best-effort ship pose publisher tells the
        # story.
        events = SubscriptionEventCallbacks(
            message_lost=functools.partial(self._on_lost, topic),
            use_default_callbacks=topic == self.layout.ship_pose)
        self.received[topic] = self.lost[topic] = 0
        try:
            with warnings.catch_warnings():  # rclpy warns of depth 0; check_pose_qos says it
                warnings.simplefilter('ignore', UserWarning)
                return self.create_subscription(PoseStamped, topic, callback, qos,
                                                event_callbacks=events,
                                                qos_overriding_options=overrides)
        except (InvalidQosOverridesError, ParameterException, RuntimeError) as e:
            # rclpy says 'Unexpected QoS override for policy `reliability`: `fast`'
            raise StartupError(f'qos_overrides of {self.resolve_topic_name(topic)}: {e}; '
                               f'allowed: {QOS_OVERRIDES_ALLOWED}') from None

    def _on_lost(self, topic: str, info: QoSMessageLostInfo) -> None:
        """Count and report poses DDS lost before they reached this node (message_lost)."""
        self.lost[topic] = info.total_count
        self._warn(f'{topic}: lost', f'{topic}: {info.total_count_change} pose(s) lost on the '
                   f'way ({info.total_count} so far): the queue of their publisher overflowed '
                   'before they were sent, or the network dropped them (a deeper publisher '
                   'queue or a lower rate keeps them)')

    def _check_clock(self) -> None:
        """Warn while a free ship under use_sim_time waits for its first /clock message."""
        if self.driver.started:
            self.destroy_timer(self._clock_timer)
        elif not self.get_clock().now().nanoseconds:
            self._warn('no clock', 'use_sim_time is true but no /clock message has come: the '
                       'free ship starts at rest at its start pose at the first one')

    def _check_pose_publishers(self) -> None:
        """
        Warn of best-effort pose publishers: they cannot reach a reliable subscription.

        Not while the ship's poses flow: the graph was then asked every second for nothing,
        and with other processes coming and going (ros2 param, ros2 topic) a mooring node
        that asked it stopped receiving poses for 0.3 s, on a 3 s grid, in 3 runs of 3 (a
        witness subscriber saw no gap): false silences. Without the asking, in 3 of 3 none.
        """
        if self.driver.started and self.driver.live(SHIP):
            return
        for topic in (s.topic_name for s in self._pose_subs.values()
                      if s.qos_profile.reliability == ReliabilityPolicy.RELIABLE):
            if any(info.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT
                   for info in self.get_publishers_info_by_topic(topic)):
                self._warn(f'{topic}: qos', f'{topic}: a best-effort publisher cannot reach '
                           'this reliable subscription, so its poses never arrive: set '
                           'pose_reliability:=best_effort')

    def _on_pose(self, stream: str, msg: PoseStamped) -> None:
        """Take a pose of a stream: record it, check it, push it, advance."""
        topic = self.layout.stream_topic(stream)
        self.received[topic] += 1
        now_ns = self.get_clock().now().nanoseconds
        stamp_ns = self._stamp(topic, stream, msg, now_ns)  # its events go to the bag first
        self.record(topic, msg)
        if stamp_ns is None:
            return
        frame_id = self.driver.arrangement.shared.frame_id
        if msg.header.frame_id and msg.header.frame_id != frame_id:
            self._warn(f'{topic}: frame', f'{topic}: header.frame_id is '
                       f'{msg.header.frame_id!r}, not {frame_id!r}: taken as {frame_id!r} '
                       '(no tf lookup)')
        if stream == SHIP:
            self._on_ship(topic, stamp_ns, msg, now_ns)
        else:
            self._on_bollard(topic, stream, stamp_ns, msg, now_ns)

    def _on_ship(self, topic: str, stamp_ns: int, msg: PoseStamped, now_ns: int) -> None:
        p, o = msg.pose.position, msg.pose.orientation
        try:
            norm = conversions.unit_quaternion(o)[1]
            event = self.driver.push_ship(stamp_ns, (p.x, p.y, p.z), (o.x, o.y, o.z, o.w))
        except ParameterError as e:  # a pretension no length gives at this pose
            self._warn('start', f'cannot start the lines at this ship pose: {e}')
            return
        except (conversions.PoseError, TrajectoryError) as e:
            self._drop(topic, e)
            return
        self._check_norm(topic, norm)
        self.pacer.arrived(SHIP, now_ns)
        driver = self.driver
        if 'start' in event:
            self._started(event['start'], 'first ship pose')
        elif event.get('teleport'):
            # Not throttled: each jump is a restart, a step in the published tension. The
            # ropes restarted at the state time, the last output's: the next output shows it.
            if self.parameters.single:
                distance = driver.arrangement.lines[0].params.teleport_distance
                self.get_logger().warning(
                    f'fairlead jumped {driver.last_jumps[0]:.2f} m, more than '
                    f'teleport_distance ({distance:g} m), to {_fmt(driver.fairlead(0))}: '
                    'rope restarted on the catenary there')
            else:
                self.get_logger().warning(
                    'the ship jumped more than teleport_distance: restarted at rest '
                    + ', '.join(self.names[k] for k in event['teleport']))
            self._parted_at_restart(event['teleport'])
        self._act(self.pacer.after_pose(SHIP, stamp_ns, now_ns))

    def _started(self, lengths: Dict[int, float], why: str) -> None:
        """Say that the lines started, with the lengths chosen for their pretensions."""
        self._starting = True  # the first output says which lines start past their WLL
        for k, length in lengths.items():  # the lengths in use (a dump holds them)
            self.parameters.declare_length(self, self.names[k], float(length))
        self._parted_at_restart(range(len(self.names)))
        if self.parameters.single:
            self.get_logger().info('first fairlead pose: rope started on the catenary to '
                                   f'{_fmt(self.driver.fairlead(0))}')
        else:
            chosen = ', '.join(f'{self.names[k]} {length:.3f} m'
                               for k, length in lengths.items())
            self.get_logger().info(f'{why}: lines started at rest' + (
                f'; lengths for their pretension: {chosen}' if chosen else ''))

    def _on_external_wrench(self, msg: WrenchStamped) -> None:
        """Hold the external load on the free ship (ship/external_wrench) until the next."""
        f, m = msg.wrench.force, msg.wrench.torque
        setup = self.driver.arrangement
        frame = msg.header.frame_id
        body = frame == setup.ship_frame_id
        name = self._external_sub.topic_name
        if not body and frame not in ('', setup.shared.frame_id):
            self._warn(topics.EXTERNAL_WRENCH, f'{name}: ignored: header.frame_id {frame!r} '
                       f'is neither {setup.shared.frame_id!r} nor {setup.ship_frame_id!r} '
                       '(no tf lookup)')
            return
        try:
            self.driver.set_external_load((f.x, f.y, f.z), (m.x, m.y, m.z), body)
        except ValueError as e:
            self._warn(topics.EXTERNAL_WRENCH, f'{name}: ignored: {e}')
            return
        self.record(topics.EXTERNAL_WRENCH, msg)
        self._event('load', force=[f.x, f.y, f.z], moment=[m.x, m.y, m.z],
                    frame='body' if body else 'world')

    def _on_environment(self, topic: str, msg: Vector3Stamped) -> None:
        """
        Take the wind's or the current's velocity (where it goes TO) from its topic.

        In the header's frame: frame_id (or empty), or ship_frame_id (turned with the ship
        as it is now). The node then uses it as if set as its parameters (wind_speed and
        wind_direction, current), which read it; an event records it for resim.
        """
        setup = self.driver.arrangement
        v = np.array([msg.vector.x, msg.vector.y, msg.vector.z], dtype=float)
        frame = msg.header.frame_id
        name = self._environment_subs[topic].topic_name
        if not np.all(np.isfinite(v)):
            self._warn(topic, f'{name}: ignored: {v.tolist()} is not finite')
            return
        if frame == setup.ship_frame_id:
            if self._latest is None:
                self._warn(topic, f'{name}: ignored: in {frame!r} axes before the ship has '
                           f'a pose; send it in {setup.shared.frame_id!r}')
                return
            v = self._latest.rotation @ v
        elif frame not in ('', setup.shared.frame_id):
            self._warn(topic, f'{name}: ignored: header.frame_id {frame!r} is neither '
                       f'{setup.shared.frame_id!r} nor {setup.ship_frame_id!r} (no tf lookup)')
            return
        if topic == topics.WIND:
            values = {'wind_speed': float(math.hypot(v[0], v[1])),
                      'wind_direction': float(math.atan2(-v[1], -v[0]))}  # comes FROM
        else:
            values = {'current': [float(c) for c in v]}
        try:
            for key, value in values.items():
                arrangement.check_top_value(key, value)
        except ParameterError as e:
            self._warn(topic, f'{name}: ignored: {e}')
            return
        self.record(topic, msg)
        # as if set as its parameters (the post-set callback applies them, with a 'set'
        # event), so that the parameters show the values in use; unlogged: a topic may
        # stream them
        self._quiet = True
        try:
            result = self.set_parameters([Parameter(key, value=value)
                                          for key, value in values.items()])
        finally:
            self._quiet = False
        for outcome in result:
            if not outcome.successful:
                self._warn(topic, f'{name}: ignored: {outcome.reason}')

    def _on_stiffness(self) -> None:
        """Publish ship/stiffness: the lines' and fenders' 6x6 stiffness where the ship is."""
        published = self._latest
        # only for a subscriber or the bag: at 1 Hz it took 10 % of a 16-line node's CPU
        if published is None or not self._taken.taken(topics.STIFFNESS, self.recorder):
            return
        try:
            matrix = self.driver.stiffness(published.ship_position,
                                           published.ship_orientation)
        except (ParameterError, StaticsError) as e:
            self._warn(topics.STIFFNESS, f'{topics.STIFFNESS}: not published: {e}')
            return
        if not np.all(np.isfinite(matrix)):
            return
        data = stiffness_message(matrix)
        self._stiffness_pub.publish(data)
        self.record(topics.STIFFNESS, data)

    def _on_bollard(self, topic: str, name: str, stamp_ns: int, msg: PoseStamped,
                    now_ns: int) -> None:
        k = self.names.index(name)
        params = self.driver.arrangement.lines[k].params
        offset = params.bollard_offset
        try:
            point = conversions.pose_point(msg.pose, offset)
            event = self.driver.push_bollard(name, stamp_ns, point.point, point.lever)
        except (conversions.PoseError, TrajectoryError) as e:
            self._drop(topic, e)
            return
        if event == 'ignored':
            if not self._told_payload:  # once: every bollard pose is ignored alike
                self._told_payload = True
                self.get_logger().warning(
                    f'{topic}: ignored: the bollard end{" of " + name if name else ""} is a '
                    f'free payload (payload_mass {params.payload_mass:g} kg > 0), see '
                    f'{self.layout.line_topic(name, topics.PAYLOAD_POSE)}')
            return
        self._check_norm(topic, point.quaternion_norm)
        self.pacer.arrived(name, now_ns)
        if event == 'teleport':
            self.get_logger().warning(
                f'{name + ": " if name else ""}bollard jumped '
                f'{self.driver.last_jumps[k]:.2f} m, more than teleport_distance '
                f'({params.teleport_distance:g} m), to {_fmt(point.point)}: '
                f'{"line" if name else "rope"} restarted on the catenary there')
            self._parted_at_restart([k])
        if self.driver.started:
            self._act(self.pacer.after_pose(name, stamp_ns, now_ns))

    def _check_norm(self, topic: str, norm: float) -> None:
        if abs(norm - 1.0) > 1e-3:
            self._warn(f'{topic}: norm', f'{topic}: normalised a non-unit quaternion '
                       f'(|q| = {norm:.4g})')

    def _stamp(self, topic: str, stream: str, msg: PoseStamped, now_ns: int) -> Optional[int]:
        """Return the sample stamp [ns] of a pose, or None if it is dropped for its stamp."""
        admission = self.pacer.admit(stream, conversions.stamp_to_ns(msg.header.stamp), now_ns)
        for kind, fields in admission.events:
            self._event(kind, **fields)
        if admission.stamp_ns is None:
            self._drop(topic, ValueError(admission.problem))
        elif admission.problem:
            self._warn(f'{topic}: unstamped', f'{topic}: {admission.problem}')
        return admission.stamp_ns

    def _drop(self, topic: str, reason: Exception) -> None:
        count = self.dropped[topic] = self.dropped.get(topic, 0) + 1
        kind = ' '.join(str(reason).split()[:2])  # e.g. 'zero quaternion'
        self._warn(f'{topic}: {kind}', f'{topic}: dropped a message: {reason} '
                   f'({count} dropped on {topic} so far)')

    def _on_winch_command(self, name: str, msg: Float64) -> None:
        """Take a winch speed for one line [m/s] (+ pays out); refuse a non-finite one."""
        topic = self.layout.line_topic(name, topics.WINCH_COMMAND)
        try:
            self.driver.command_winch(name, msg.data)
        except ParameterError as e:
            self._warn(f'{topic}: bad', f'{topic}: {e}; ignored')
            return
        self._event('winch', line=name, t=self.driver.time if self.driver.started else 0.0,
                    speed=msg.data)
        mode = self.driver.arrangement.lines[self.names.index(name)].params.winch_mode
        if mode != 'speed':
            setting = f'{name}.winch_mode' if name else 'winch_mode'
            self._warn(f'{topic}: mode', f'{topic} {msg.data:g} m/s kept: it acts while '
                       f"{setting} is 'speed' (now '{mode}')")

    # -- time -----------------------------------------------------------------------------

    def _on_tick(self) -> None:
        """Judge the streams' silence and move the ropes on, at the timer's tick."""
        self._act(self.pacer.tick(self.get_clock().now().nanoseconds))

    def _act(self, pace: Pace) -> None:
        """Record, log and publish what the clock rules decided (the Pacer's Pace)."""
        if pace.start_error:
            self._warn('start', f"cannot start the lines at the ship's start pose: "
                       f'{pace.start_error}')
        if pace.no_clock:
            self._warn('no clock', 'use_sim_time is true but no /clock message has come: '
                       'the ropes follow the pose stamps alone')
        for kind, fields in pace.events:
            self._event(kind, **fields)
        if pace.started is not None:
            self._started(pace.started, 'free ship at rest at its start pose')
        for stream in pace.silenced:
            self._say_silent(stream)
        if pace.clock_back:
            self.get_logger().warning(
                f'clock jumped back by {pace.clock_back:.2f} s: waiting for the next '
                f'{self.layout.ship_pose} pose to restart the ropes')
        if pace.skipped:
            self.skips += 1
            # Not throttled: each skip is a restart, a step in the published tension, and
            # there is at most one per MAX_LAG.
            self.get_logger().warning(
                f'simulation fell {pace.skipped:.2f} s behind the clock: skipped ahead and '
                f'restarted the ropes at rest (skips so far: {self.skips})')
        for t in pace.faults:
            self.get_logger().error(f'non-finite output at t = {t:.3f} s: not published; '
                                    'ropes restarted')
        for published in pace.reached:
            self._report(published)
        for published in pace.publish:
            self._publish(published)

    def _say_silent(self, stream: str) -> None:
        """Warn that a stream was taken for silent, and what the ropes do meanwhile."""
        topic = self.layout.stream_topic(stream)
        if self.parameters.single:
            what = 'the fairlead' if stream == SHIP else 'the bollard'
            rest = 'the rope goes'
        else:
            what = 'the ship' if stream == SHIP else f"{stream}'s bollard"
            rest = 'the lines go'
        self._warn(f'{stream}: silent', f'{topic}: no new pose for {Pacer.LIVE_INPUT:g} s: '
                   f'{what} coasts to a stop and {rest} on with the clock from '
                   f't = {self.driver.time:.3f} s')

    def _ship_pose_source(self) -> str:
        """Name where the ship's pose comes from: its topic, or a free ship's start pose."""
        if self.driver.free:
            return 'ship.start_position'
        return self._pose_subs[SHIP].topic_name

    def _set_stiffness_rate(self, rate: float) -> None:
        """Publish ship/stiffness at this rate [Hz] (0: not at all)."""
        if self._stiffness_timer is not None:
            self.destroy_timer(self._stiffness_timer)
            self._stiffness_timer = None
        if rate > 0.0:
            self._stiffness_timer = self.create_timer(1.0 / rate, self._on_stiffness)

    def _parted_at_restart(self, lines) -> None:
        """Log (and record) each (re)started line that parted at once (past its break load)."""
        partings = self.driver.partings
        for k in lines:
            parting = partings[k]
            if parting is None or parting.t != self.driver.time:
                continue
            name = self.names[k]
            self._event('parted', line=name, t=parting.t, segment=parting.segment,
                        break_load=parting.break_load)
            self.get_logger().error(
                f'{name or "the line"} parted at t = {parting.t:.3f} s as it (re)started: its '
                f'ends are too far apart for it to hold its break load of '
                f'{parting.break_load / 1e3:.0f} kN. ~/reset restores every line')

    def _warn_past_wll(self, published: Published) -> None:
        """Warn of each line that starts past its working load limit: one line each."""
        out = published.output
        tensions = np.maximum(out.fairlead_tensions, out.bollard_tensions)
        for name, tension, rating in zip(self.names, tensions, self.ratings):
            if tension > rating.wll:
                share = 100 * rating.utilisation(tension)
                self.get_logger().warning(
                    f'{name or "the line"} starts at {tension / 1e3:.0f} kN, past its working '
                    f'load limit of {rating.wll / 1e3:.0f} kN ({share:.1f} % of its MBL): is '
                    f'{self._ship_pose_source()} where the ship is?')

    def _report(self, published: Published) -> None:
        """Log what the advance to an output did to the lines; keep it for the diagnostics."""
        advance = published.advance
        if advance is None:
            if self._starting:
                self._starting = False
                self._warn_past_wll(published)
            return
        driver = self.driver
        for k, parting in advance.parted.items():
            name = self.names[k]
            segments = driver.arrangement.lines[k].params.segments
            self._event('parted', line=name, t=parting.t, segment=parting.segment,
                        break_load=parting.break_load)
            self.get_logger().error(
                f'{name or "the line"} parted at t = {parting.t:.3f} s, segment '
                f'{parting.segment} of {segments} (0 at the bollard): its tension passed the '
                f'break load of {parting.break_load / 1e3:.0f} kN. Both pieces go on; '
                '~/reset restores every line')
        for k, tension in advance.released.items():
            name = self.names[k]
            load = driver.arrangement.lines[k].params.release_load
            self._line_event('released', name, tension=tension, t=published.output.t)
            self.get_logger().warning(
                f'{name or "the line"}: its quick-release hook let go at t = '
                f'{published.output.t:.3f} s: {tension / 1e3:.1f} kN at the bollard, past its '
                f'release_load of {load / 1e3:.1f} kN')
        for k, distance in advance.beyond_reach.items():
            if driver.partings[k] is not None:
                continue  # it parted in these steps: its error says what became of it
            self._warn(f'reach {k}', f'{self.names[k] or "the line"}: its ends are '
                       f'{distance:.1f} m apart, beyond its reach of {driver.reaches[k]:.1f} m '
                       '(length x (1 + max_strain)): its fairlead is held at the reach')
        if advance.ship_restarted:
            self._event('ship_restart', why=advance.ship_restarted, t=self.driver.time)
            self.get_logger().error(
                f'the free ship {advance.ship_restarted} at t = {self.driver.time:.3f} s, past '
                'every bound of a moored ship: restarted at its start pose at rest, every '
                'line with it')
        for k, why in advance.restarted.items():
            self._restarted[k] = why
            if why == 'ship restarted':
                continue  # said once, above
            log = (self.get_logger().warning if why == 'back within reach'
                   else self.get_logger().error)
            log(f'{self.names[k] or "the line"}: {why} at t = {self.driver.time:.3f} s: '
                'restarted at rest on its catenary')

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response):
        if not self.driver.started:
            response.success = False
            response.message = f'not started ({self._waiting_for()}): nothing to reset'
            return response
        # outputs computed ahead of the clock are of the lines before the reset, the last at
        # the state time, where the reset's fresh output now stands: not published
        self.pacer.reset()
        self.driver.reset()
        self._event('reset', t=self.driver.time)
        self._restarted = ['reset'] * len(self.names)
        self._publish_parted(np.zeros(len(self.names), dtype=bool))
        response.success = True
        what = ('rope restarted on the catenary' if self.parameters.single
                else 'every line restarted at rest')
        response.message = f'{what} at t = {self.driver.time:.3f} s'
        self.get_logger().info(response.message)
        return response

    def _command_services(self) -> list:
        """
        Create the line-handling services (std_srvs/Trigger, the services' default QoS).

        Each line's make_fast, let_go and stow in its namespace, as its topics are (the single
        line's at the root), and the mooring node's mooring/let_go_all.
        """
        services = [self.create_service(Trigger, self.layout.line_topic(name, command),
                                        functools.partial(self._on_command, name, command))
                    for name in self.names for command in LINE_COMMANDS]
        if self.layout.ship_outputs:
            services.append(self.create_service(
                Trigger, topics.LET_GO_ALL,
                functools.partial(self._on_command, None, 'let_go_all')))
        return services

    def _on_command(self, name: Optional[str], command: str, request: Trigger.Request,
                    response: Trigger.Response) -> Trigger.Response:
        """
        Take a line-handling command at the present simulated time (the state time).

        Between two advances of the ropes, as ~/reset and winch commands are: the outputs
        reached before it are of the lines before it. One taken is logged, published and
        recorded as a 'command' event (resim takes it again there); one refused changed
        nothing and is logged only.
        """
        try:
            text = self.driver.command(name, command)
        except ValueError as e:  # CommandError: the line's state or the numbers say why
            response.success, response.message = False, str(e)
            self.get_logger().warning(f'{command} refused: {e}')
            return response
        self._line_event('command', name, command=command, t=self.driver.time, text=text)
        self.get_logger().info(text)
        response.success, response.message = True, text
        return response

    # -- outputs --------------------------------------------------------------------------

    def _publish(self, published: Published) -> None:
        """
        Publish (and record) one output: every line's topics, then the ship's wrenches.

        An output nobody subscribes to (and no bag records) is neither built nor published:
        a ship simulator takes ship/mooring_wrench only, and the 16 lines' 96 other messages
        would go to nobody 100 times a second. A subscriber gets the outputs from the first
        one after its subscription is matched, as from any volatile publisher.
        """
        wanted = self._taken.taken_among(self.encoder.output_topics, self.recorder)
        for topic, data in self.encoder.messages(published, wanted):
            self._outputs[topic].publish(data)
            # a message with a header is recorded with its stamp for a publish time, one
            # without it at its log time, as received
            self.record(topic, data,
                        published.stamp_ns if self.encoder.has_header(topic) else None)
        self._publish_parted(published.output.parted)
        self._latest = published
        self._peaks = np.maximum(self._peaks, published.output.peaks)  # every step's
        if published.bollard_loads:
            self._bollard_peaks = np.maximum(self._bollard_peaks,
                                             [load.load for load in published.bollard_loads])

    def _publish_parted(self, parted) -> None:
        """Publish (and record) on each line's parted topic whether it has parted, if new."""
        for topic, flag in self.encoder.parted_changes(parted):
            msg = Bool(data=flag)
            self._outputs[topic].publish(msg)
            self.record(topic, msg)

    def _on_markers(self) -> None:
        """Publish the lines as markers, coloured by their utilisation (mooring_display)."""
        published = self._latest
        if published is None or not self._taken.subscribed(topics.MARKERS):
            return  # nobody looks: not built (16 strips of 51 points)
        out = published.output
        msg = self._line_markers(
            self.driver.arrangement.shared.frame_id, published.stamp_ns, self.names,
            out.positions, np.maximum(out.fairlead_tensions, out.bollard_tensions),
            self.ratings, out.parted, np.array([p[-1] for p in out.positions]),
            np.array([p[0] for p in out.positions]), self._fenders(published), out.states,
            published.bollard_loads)
        self._markers_pub.publish(msg)

    def _on_diagnostics(self) -> None:
        """Publish one status per line, fender and bollard; peaks count from the last report."""
        published = self._latest
        prefix = self.get_fully_qualified_name().lstrip('/')
        if published is None:
            msg = DiagnosticArray(status=[DiagnosticStatus(
                level=DiagnosticStatus.STALE, name=f'{prefix}: {name}', hardware_id=name,
                message=self._waiting_for(),
                values=[KeyValue(key='state', value='not started')]) for name in self.names])
            msg.header.stamp = conversions.ns_to_stamp(self.get_clock().now().nanoseconds)
        else:
            out = published.output
            msg = line_diagnostics(
                published.stamp_ns, self.names,
                np.maximum(out.fairlead_tensions, out.bollard_tensions), self._peaks,
                out.max_strains, self.ratings, out.parted, self._restarted, prefix, out.states)
            self._peaks = np.zeros(len(self.names))
            self._restarted = [None] * len(self.names)
            fenders = self._fenders(published)
            if fenders is not None:
                msg.status += fenders.statuses(prefix)
            msg.status += bollard_statuses(published.bollard_loads, self._bollard_peaks, prefix)
            self._bollard_peaks = np.zeros(len(self._bollard_peaks))
        self._diagnostics_pub.publish(msg)

    def _fenders(self, published: Published) -> Optional[Fenders]:
        """Return the fenders' state at an output (None: there are none)."""
        setup = self.driver.arrangement.fenders
        if not setup:
            return None
        out = published.output
        return Fenders([f.name for f in setup], [f.normal for f in setup],
                       [f.rated_compression for f in setup], out.fender_points,
                       out.fender_compressions, out.fender_forces)

    def _event(self, kind: str, stream: Optional[str] = None, line: Any = (), **fields: Any):
        """Publish and record a decision taken on the node clock (see the module docstring)."""
        if stream is not None:
            fields.update(self.layout.event_stream(stream))
        if line != ():
            fields.update(self.layout.line_field(line))
        self._send_event(encode_event(kind, **fields))

    def _line_event(self, kind: str, line: Optional[str], **fields: Any) -> None:
        """
        Publish and record a line-handling event ('command', 'released').

        Its line is always named: '' for let_go_all and for the single line (the fields
        mooring/events.py gives them).
        """
        self._send_event(encode_event(kind, line=line or '', **fields))

    def _send_event(self, text: str) -> None:
        msg = String(data=text)
        self._events_pub.publish(msg)
        self.record(self.layout.events, msg)

    # -- recording ------------------------------------------------------------------------

    def _start_recording(self) -> None:
        """
        Start recording to record_path, if it is set: the poses, every output, the events.

        The bag stores the parameters at start-up as `rope_sim run` does (metadata.yaml's
        custom_data), so `rope_sim resim` and `rope_sim plot` use them.

        :raises StartupError: record_path exists and is not an empty directory, or it
            cannot be created or written.
        """
        setup = self.driver.arrangement
        path = setup.shared.record_path
        if not path:
            return
        try:
            recorder = Recorder(path, stored(setup), self.get_logger())
        except (BagError, OSError) as e:
            raise StartupError(f'record_path: {e}') from None
        for stream, subscription in self._pose_subs.items():
            # Stored with the QoS its publishers offer, as `ros2 bag record` does.
            recorder.add_topic(self.layout.stream_topic(stream), subscription.topic_name,
                               topics.POSE_STAMPED, offered_qos=functools.partial(
                                   self._offered_qos, subscription.topic_name))
        for topic, publisher in self._outputs.items():
            recorder.add_topic(topic, publisher.topic_name, self.encoder.types[topic],
                               publisher.qos_profile)
        recorder.add_topic(self.layout.events, self._events_pub.topic_name, topics.STRING,
                           self._events_pub.qos_profile)
        if self.layout.ship_outputs:
            recorder.add_topic(topics.STIFFNESS, self._stiffness_pub.topic_name,
                               topics.FLOAT64_MULTI_ARRAY, self._stiffness_pub.qos_profile)
        inputs = [(topic, sub, topics.VECTOR3_STAMPED)
                  for topic, sub in self._environment_subs.items()]
        if self._external_sub is not None:
            inputs.append((topics.EXTERNAL_WRENCH, self._external_sub, topics.WRENCH_STAMPED))
        for topic, subscription, type_name in inputs:
            recorder.add_topic(topic, subscription.topic_name, type_name,
                               offered_qos=functools.partial(self._offered_qos,
                                                             subscription.topic_name))
        self.recorder = recorder
        self.get_logger().info(f'recording the poses, every output and the events to '
                               f'{os.path.abspath(recorder.path)}')

    def _offered_qos(self, topic: str) -> List[QoSProfile]:
        """Return the QoS profiles the publishers of a topic offer (from the graph)."""
        return [info.qos_profile for info in self.get_publishers_info_by_topic(topic)]

    def record(self, topic: str, msg: Any, stamp_ns: Optional[int] = None) -> None:
        """
        Pass a received or published message to the recorder (the recording hook).

        :param topic: the topic name relative to the node's namespace.
        :param msg: the message, or its CDR bytes.
        :param stamp_ns: the publish time of CDR bytes with a header [ns] (see
            Recorder.write).
        """
        if self.recorder is None:
            return
        now = self.get_clock().now().nanoseconds
        if not now:  # use_sim_time before the first /clock: the poses' time, not 0
            header = getattr(msg, 'header', None)
            now = stamp_ns or (conversions.stamp_to_ns(header.stamp) if header else 0) or \
                self._last_log_ns
            if not now:  # (a parameter set before any pose) logged with the first time
                self._unlogged.append((topic, msg, stamp_ns))
                return
        for held in self._unlogged:
            self.recorder.write(held[0], held[1], now, held[2])
        self._unlogged.clear()
        self._last_log_ns = now
        self.recorder.write(topic, msg, now, stamp_ns)

    def destroy_node(self) -> None:
        """Destroy the node, then close the bag (if recording)."""
        # In this order the closing lines are not sent to /rosout, whose publisher is gone
        # after a signal shut the context down (rcl would complain about each line).
        super().destroy_node()
        self.get_logger().info('poses: ' + ('; '.join(
            f'{topic}: {count} received, {self.dropped.get(topic, 0)} dropped, '
            f'{self.lost[topic]} lost on the way'
            for topic, count in self.received.items() if count or self.lost[topic])
            or 'none received'))
        if self.recorder is not None:
            self.recorder.close()

    # -- logging --------------------------------------------------------------------------

    def _warn(self, key: str, text: str) -> None:
        """
        Log a warning, at most once per THROTTLE seconds per key and kind of text.

        The same warning with other numbers is throttled; another one under the same key
        (a second, different refusal on one topic) is not.
        """
        now = time.monotonic()  # (under use_sim_time the node clock may stand still)
        kind = (key, NUMBER.sub('#', text))
        last = self._last_log.get(kind)
        if last is None or not 0.0 <= now - last < self.THROTTLE:
            self._last_log[kind] = now
            self.get_logger().warning(text)


def warm_up(setup, say=None) -> None:
    """
    Run a few steps of a throw-away line, so the compiled kernels load before spinning.

    The build leaves them compiled in numba's cache (0.4 s to load); where it could not
    (read-only install, pip install), numba compiles them here, one to three minutes:
    say(message) tells when that starts and ends.
    """
    from ..mooring.precompile import announce_compilation, exercise
    with announce_compilation(say):
        exercise(setup.lines[0].params.as_dict())


HELP = {
    LINE_NODE.node_name: (
        'one mooring line between a bollard and a fairlead',
        'fairlead/pose (the fairlead is the pose + fairlead_offset), bollard/pose, '
        'winch/command', 'rope/particles, fairlead/tension, bollard/tension, ...',
        'config/mooring_line.yaml'),
    MOORING_NODE.node_name: (
        "a ship's whole mooring arrangement", 'ship/pose (ship_mode driven: every fairlead '
        'moves with it), <line>/bollard/pose,\n       <line>/winch/command, environment/wind, '
        'environment/current,\n       ship/external_wrench (ship_mode free: tugs, thrusters)',
        "each line's topics under its name, ship/mooring_wrench, ship/stiffness,\n       "
        'mooring/markers, /diagnostics; ship/pose and ship/odometry (ship_mode free),\n'
        '       ship/passing_ship_wrench (a passing ship), <fender>/reaction (fenders),\n'
        '       ship/wave_wrench, environment/wave_elevation (waves)',
        'config/berth.yaml'),
}


def help_asked(argv) -> bool:
    """Tell whether the command line (before --ros-args) asks for -h or --help."""
    argv = list(argv)
    if '--ros-args' in argv:
        argv = argv[:argv.index('--ros-args')]
    return any(arg in ('-h', '--help') for arg in argv[1:])


def usage(layout: Layout) -> str:
    """Return the --help text of a node kind."""
    name = layout.node_name
    what, inputs, outputs, config = HELP[name]
    return (f'usage: ros2 run rope_sim_ros {name} [--ros-args --params-file FILE '
            f'-p NAME:=VALUE ...]\n\n'
            f'The {name} node: {what}, simulated live.\n'
            f'  in:  {inputs}\n  out: {outputs}, events, ~/reset\n'
            f'  parameters: a ROS parameter file (the installed {config} lists them '
            'all), or -p; use_sim_time:=true follows /clock\n'
            '  see docs/ros.md and docs/parameters.md\n')


def run(layout: Layout, args=None) -> int:
    """
    Run a node of this kind until Ctrl-C or SIGTERM, then close its bag (if recording).

    Ctrl-C and SIGTERM end the spin (spin_until_shutdown) or the start-up alike: the same
    clean shutdown, exit code 0. -h or --help prints the usage and starts nothing.

    :returns: 0, or 2 when a parameter is not allowed or record_path cannot be used.
    """
    if help_asked(sys.argv if args is None else args):
        print(usage(layout), end='')
        return 0
    return run_node(lambda: MooringNode(layout), layout.node_name, (StartupError,), args)


def main_line(args=None) -> int:
    """Run the mooring_line node: one line between a bollard and a fairlead."""
    return run(LINE_NODE, args)


def main_mooring(args=None) -> int:
    """Run the mooring node: a ship's whole mooring arrangement."""
    return run(MOORING_NODE, args)
