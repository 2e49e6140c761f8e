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
The mooring node: a ship's whole mooring arrangement, every line stepped in one System.

ROS glue only. The parameters (arrangement.py: `lines`, each line's settings under its
name with the single-line node's descriptors and validation, the shared ones at the top)
become a mooring_driver.MooringDriver, which holds the same input and output rules as the
single-line node: simulated time 0 at the first pose, the ropes one sample behind a live
pose stream, outputs every 1 / publish_rate, skip ahead past MAX_LAG.

Inputs: ship/pose (geometry_msgs/PoseStamped) drives every fairlead (pose ⊕ the line's
fairlead_offset); <line>/bollard/pose, optional, moves that line's bollard (ship-to-ship
mooring); <line>/winch/command (std_msgs/Float64) commands that line's winch speed, as the
single-line node's winch/command. Outputs per line under its name, as the single-line
node's: <line>/rope/particles (PoseArray), <line>/fairlead/tension and
<line>/bollard/tension (Wrench, torque about the pose origin), <line>/fairlead/peak_tension,
<line>/bollard/peak_tension and <line>/winch/length (Float64), <line>/rope/parted (Bool,
latched, sent when it changes), <line>/payload/pose with a payload. For the ship:
ship/mooring_wrench (WrenchStamped in ship_frame_id: the total force and moment about the
ship's origin, what a ship simulator adds to its equations of motion) and
ship/mooring_wrench_world (the same in frame_id axes, about the same origin). For people:
mooring/markers (mooring_display.py) at marker_rate and /diagnostics at 1 Hz of the node's
clock. Decisions taken on the clock, winch commands and partings go to mooring/events
(std_msgs/String, JSON; each names its line).

QoS: as the single-line node, the pose subscriptions are reliable (pose_reliability,
qos_overrides) with a deep queue, so every pose is simulated in order; every output is
published reliable, depth 10 (REP 2003's default for publishers), which reliable and
best-effort (sensor-data) subscribers, RViz and Foxglove, all take. The particles and
tensions go out as CDR bytes built from the numbers (bag/cdr.py): 16 lines of 51 Pose
objects at 100 Hz cost more than the lines' physics.
"""

import functools
import gc
import math
from typing import Any, Dict, List, Optional, Tuple

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseArray, PoseStamped, Wrench, WrenchStamped
import numpy as np
from rcl_interfaces.msg import ParameterDescriptor, ParameterType, SetParametersResult
import rclpy
from rclpy.event_handler import QoSMessageLostInfo, SubscriptionEventCallbacks
from rclpy.exceptions import ParameterException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSPolicyKind, QoSProfile
from rclpy.qos_overriding_options import InvalidQosOverridesError, QoSOverridingOptions
from std_msgs.msg import Bool, Float64, String
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

from . import conversions
from .mooring_display import line_diagnostics, LineMarkers
from .mooring_line_node import (check_pose_qos, describe, MooringLineNode, POSE_QUEUE_DEPTH,
                                POSE_RELIABILITY, QOS_OVERRIDES_ALLOWED, StartupError,
                                warm_up)
from .outputs import OutputPublishers
from .recorder import Recorder
from .spinning import set_timer_period, signals_ignored, spin_until_shutdown
from ..bag import BagError, cdr
from ..line_driver import encode_event, PARTED_TOPIC
from ..line_status import Rating
from ..model.frames import cross_rows, lines_tangent_quaternions, split_ns
from ..mooring_driver import MooringDriver, MooringPublished, SHIP
from ..params import arrangement
from ..params.arrangement import (ARRANGEMENT_SPECS, LINE_SPECS, LINES, LINES_DESCRIPTION,
                                  OWN_SPECS, SHARED)
from ..params.table import ParameterError, SPECS
from ..runner import pose_stamped_cdr
from ..trajectory import TrajectoryError

NODE_NAME = arrangement.NODE_NAME
ROS_PARAMETERS = ('use_sim_time', 'start_type_description_service')
SHIP_POSE = 'ship/pose'
WRENCH_TOPIC = 'ship/mooring_wrench'
WORLD_WRENCH_TOPIC = 'ship/mooring_wrench_world'
MARKERS_TOPIC = 'mooring/markers'
DIAGNOSTICS_TOPIC = '/diagnostics'
EVENTS_TOPIC = 'mooring/events'
DIAGNOSTICS_PERIOD = 1.0  # [s] of the node's clock
# Every output topic of a line, relative to its namespace, and its type.
LINE_OUTPUTS = {'rope/particles': 'geometry_msgs/msg/PoseArray',
                'fairlead/tension': 'geometry_msgs/msg/Wrench',
                'bollard/tension': 'geometry_msgs/msg/Wrench',
                'fairlead/peak_tension': 'std_msgs/msg/Float64',
                'bollard/peak_tension': 'std_msgs/msg/Float64',
                'winch/length': 'std_msgs/msg/Float64',
                PARTED_TOPIC: 'std_msgs/msg/Bool'}
PAYLOAD_OUTPUT = ('payload/pose', 'geometry_msgs/msg/PoseStamped')
MESSAGE_CLASSES = {'geometry_msgs/msg/PoseArray': PoseArray, 'geometry_msgs/msg/Wrench': Wrench,
                   'geometry_msgs/msg/PoseStamped': PoseStamped,
                   'std_msgs/msg/Float64': Float64, 'std_msgs/msg/Bool': Bool}
WINCH_COMMAND = 'winch/command'  # a line's, relative to its namespace
# whether a line has parted is a state, not a stream: latched, so that a monitor started later
# sees it (as the single-line node's rope/parted)
PARTED_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


def spec_of(name: str):
    """Return the Spec of a parameter name of this node (`head_1.length` -> length's)."""
    line, dot, base = name.partition('.')
    if dot:
        return LINE_SPECS.get(base)
    return ARRANGEMENT_SPECS.get(name) or SPECS.get(name) or OWN_SPECS.get(name)


def _plain(value: Any) -> Any:
    """Return a parameter value as the checks expect it (arrays as lists)."""
    if hasattr(value, 'tolist'):
        return value.tolist()
    if isinstance(value, (tuple, list)) or type(value).__name__ == 'array':
        return list(value)
    return value


class MooringNode(Node):
    """A ship's mooring lines in one node; see the module docstring and the README."""

    LIVE_INPUT = MooringLineNode.LIVE_INPUT
    MAX_LAG = MooringLineNode.MAX_LAG
    OUTPUTS_PER_CALL = MooringLineNode.OUTPUTS_PER_CALL
    # The timer ticks at publish_rate but no faster than this [Hz]. A tick only counts
    # quiet ticks and advances when no pose stream is live (the pose callbacks publish the
    # outputs), and each wake-up costs (on rclpy's Python executor, which a test or a
    # composing program may spin this node with, a walk of all of its 16 lines' entities);
    # above this rate a tick publishes the few outputs due since the last one.
    MAX_TICK_RATE = 50.0
    STAMP_AHEAD_LIMIT = MooringLineNode.STAMP_AHEAD_LIMIT
    STAMP_BEHIND_LIMIT = MooringLineNode.STAMP_BEHIND_LIMIT
    THROTTLE = MooringLineNode.THROTTLE

    def __init__(self, **kwargs):
        """
        Declare the parameters, build the lines, then create the ROS interfaces.

        :raises StartupError: a parameter is not allowed or a line cannot be built.
        """
        super().__init__(NODE_NAME, **kwargs)
        self._last_log: Dict[str, float] = {}
        self.driver: Optional[MooringDriver] = None
        self.recorder: Optional[Recorder] = None
        self.received: Dict[str, int] = {}
        self.dropped: Dict[str, int] = {}
        self.lost: Dict[str, int] = {}
        self.skips = 0
        self.add_pre_set_parameters_callback(self._coerce_parameters)
        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._apply_parameters)
        setup = self._declare_parameters()
        try:
            self.driver = MooringDriver(setup)
            warm_up(setup.lines[0].params, self.get_logger().info)
        except ValueError as e:  # ParameterError, MaterialError, an unstable line
            raise StartupError(str(e)) from None
        mooring = self.driver.mooring
        self.names = list(mooring.names)
        self.ratings = [Rating(sim.material.mbl, sim.material.working_load_limit)
                        for sim in mooring.sims]
        self._quiet_ticks = {stream: 0 for stream in self.driver.streams}
        self._bollard_levers = np.zeros((len(self.names), 3))
        # the newest output and what the diagnostics gather between reports
        self._latest: Optional[MooringPublished] = None
        self._peaks = np.zeros(len(self.names))
        self._restarted: List[Optional[str]] = [None] * len(self.names)
        self._parted_said: List[Optional[bool]] = [None] * len(self.names)  # on rope/parted
        self._line_markers = LineMarkers()

        self._outputs: Dict[str, Any] = {}
        # each output's line topics: (line index, relative name)
        self._line_topics: Dict[str, Tuple[int, str]] = {}
        self._taken_outputs = OutputPublishers(self)
        for k, name in enumerate(self.names):
            topics = dict(LINE_OUTPUTS)
            if mooring.sims[k].payload:
                topics[PAYLOAD_OUTPUT[0]] = PAYLOAD_OUTPUT[1]
            for relative, type_name in topics.items():
                if relative != PARTED_TOPIC:  # published when it changes (_publish_parted)
                    self._line_topics[f'{name}/{relative}'] = (k, relative)
                self._outputs[f'{name}/{relative}'] = self._publisher(
                    MESSAGE_CLASSES[type_name], f'{name}/{relative}',
                    PARTED_QOS if relative == PARTED_TOPIC else 10)
        self._wrench_pub = self._publisher(WrenchStamped, WRENCH_TOPIC, 10)
        self._world_wrench_pub = self._publisher(WrenchStamped, WORLD_WRENCH_TOPIC, 10)
        self._markers_pub = self._publisher(MarkerArray, MARKERS_TOPIC, 10)
        self._diagnostics_pub = self._publisher(DiagnosticArray, DIAGNOSTICS_TOPIC, 10)
        self._events_pub = self._publisher(String, EVENTS_TOPIC, 100)
        self._pose_subs = {SHIP: self._pose_subscription(SHIP_POSE, self._on_ship)}
        for name in self.names:
            self._pose_subs[name] = self._pose_subscription(
                f'{name}/bollard/pose', functools.partial(self._on_bollard, name))
        # without event handlers: rclpy's Python executor walks every handler at every
        # wake-up (on the events executor of spin_until_shutdown they cost nothing idle)
        self._winch_subs = [self.create_subscription(
            Float64, f'{name}/{WINCH_COMMAND}', functools.partial(self._on_winch_command, name),
            10, event_callbacks=SubscriptionEventCallbacks(use_default_callbacks=False))
            for name in self.names]
        self._reset_srv = self.create_service(Trigger, '~/reset', self._on_reset)
        rate = setup.shared.publish_rate
        self._timer = self.create_timer(self._tick_period(rate), self._on_tick)
        self._markers_timer = self.create_timer(1.0 / setup.marker_rate, self._on_markers)
        self._diagnostics_timer = self.create_timer(DIAGNOSTICS_PERIOD, self._on_diagnostics)
        self._start_recording()
        self.get_logger().info(
            f'{len(self.names)} lines ({", ".join(self.names)}), {setup.shared.integrator} '
            f'step {mooring.time_step * 1e3:.4g} ms, {rate:g} Hz; waiting for the first '
            f'pose on {self._pose_subs[SHIP].topic_name}')

    def _publisher(self, cls, topic: str, qos):
        """
        Create an output's publisher, its subscribers counted (OutputPublishers.taken).

        Without rclpy's default incompatible-QoS handler: our outputs are reliable and
        volatile, which every subscriber's QoS takes, so there is no incompatibility to
        report, and rclpy's Python executor would walk 98 of them at every wake-up.
        """
        return self._taken_outputs.create(cls, topic, qos, default_events=False)

    # -- parameters -----------------------------------------------------------------------

    def _declare_parameters(self) -> arrangement.ArrangementParams:
        """Declare every parameter with its descriptor; return the validated arrangement."""
        given = self._start_values()
        try:
            setup = arrangement.from_values(given)
        except ParameterError as e:
            raise StartupError(str(e)) from None
        declared = [(LINES, setup.names, ParameterDescriptor(
            name=LINES, type=ParameterType.PARAMETER_STRING_ARRAY,
            description=LINES_DESCRIPTION, read_only=True))]
        declared += [(name, getattr(setup.shared, name), describe(name, SPECS[name]))
                     for name in SHARED]
        declared += [(name, getattr(setup, name), describe(name, spec))
                     for name, spec in ARRANGEMENT_SPECS.items()]
        for name, value in given.items():  # top-level defaults of the lines' settings
            if name in LINE_SPECS:
                descriptor = describe(name, LINE_SPECS[name])
                descriptor.description = (f"default of every line's {name} (each line's own: "
                                          f'<line>.{name}): ' + descriptor.description)
                descriptor.read_only = True
                declared.append((name, arrangement.check_top_value(name, value), descriptor))
        for line in setup.lines:
            values = {**line.params.as_dict(), 'pretension': line.pretension}
            declared += [(f'{line.name}.{name}', values[name],
                          describe(f'{line.name}.{name}', spec))
                         for name, spec in LINE_SPECS.items()]
        self.declare_parameters('', declared, ignore_override=True)
        return setup

    def _start_values(self) -> dict:
        """Return the values of --params-file / -p (rclpy's overrides), ours only."""
        return {name: _plain(parameter.value)
                for name, parameter in getattr(self, '_parameter_overrides', {}).items()
                if name not in ROS_PARAMETERS and not name.startswith('qos_overrides.')}

    def _coerce_parameters(self, parameters: List[Parameter]) -> List[Parameter]:
        """Pre-set callback: integers given for double parameters become doubles."""
        out = []
        for p in parameters:
            spec = spec_of(p.name)
            default = None if spec is None else spec.default
            if isinstance(default, float) and p.type_ == Parameter.Type.INTEGER:
                p = Parameter(p.name, value=float(p.value))
            elif isinstance(default, list) and p.type_ == Parameter.Type.INTEGER_ARRAY:
                p = Parameter(p.name, value=[float(v) for v in p.value])
            out.append(p)
        return out

    def _validate_parameters(self, parameters: List[Parameter]) -> SetParametersResult:
        """On-set callback: refuse a value outside its range, or one a line cannot take."""
        try:
            for line, values in self._changes(parameters).items():
                if self.driver is not None and values:
                    self.driver.check_update(line, values)
        except (ParameterError, ValueError) as e:
            return SetParametersResult(successful=False, reason=str(e))
        return SetParametersResult(successful=True)

    def _changes(self, parameters: List[Parameter]) -> Dict[Optional[str], dict]:
        """
        Return validated changes by line (None: the shared ones), the arrangement's own apart.

        :raises ParameterError: a bad value, named.
        """
        changes: Dict[Optional[str], dict] = {}
        for p in parameters:
            line, dot, base = p.name.partition('.')
            value = _plain(p.value)
            if dot and line in getattr(self, 'names', ()):
                changes.setdefault(line, {})[base] = arrangement.check_line_value(
                    line, base, value)
            elif p.name in SHARED:
                changes.setdefault(None, {})[p.name] = arrangement.check_top_value(
                    p.name, value)
            elif p.name in ARRANGEMENT_SPECS:
                arrangement.check_top_value(p.name, value)
        return changes

    def _apply_parameters(self, parameters: List[Parameter]) -> None:
        """Post-set callback: hand run-time changes to the lines at once."""
        if self.driver is None:  # still declaring
            return
        for p in parameters:
            if p.name == 'marker_rate':
                set_timer_period(self._markers_timer, 1.0 / float(p.value))
        for line, values in self._changes(parameters).items():
            try:
                self.driver.update(line, values)
            except ValueError as e:  # validated already: the lines should never refuse
                self.get_logger().error(f'could not apply {values}: {e}')
                continue
            self._event('set', line=line, values=values)
            if 'publish_rate' in values:
                set_timer_period(self._timer, self._tick_period(self.driver.rate))
            self.get_logger().info(f'set {line + "." if line else ""}' + ', '.join(
                f'{k} = {v}' for k, v in values.items()))

    # -- inputs ---------------------------------------------------------------------------

    def _pose_subscription(self, topic: str, callback):
        """Subscribe to a pose topic as the single-line node does (reliable, deep, counted)."""
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
            use_default_callbacks=topic == SHIP_POSE)
        self.received[topic] = self.lost[topic] = 0
        try:
            return self.create_subscription(PoseStamped, topic, callback, qos,
                                            event_callbacks=events,
                                            qos_overriding_options=overrides)
        except (InvalidQosOverridesError, ParameterException, RuntimeError) as e:
            raise StartupError(f'qos_overrides of {self.resolve_topic_name(topic)}: {e}; '
                               f'allowed: {QOS_OVERRIDES_ALLOWED}') from None

    def _on_lost(self, topic: str, info: QoSMessageLostInfo) -> None:
        self.lost[topic] = info.total_count
        self._warn(f'{topic}: lost', f'{topic}: {info.total_count_change} pose(s) lost on the '
                   f'way ({info.total_count} so far)')

    def _on_ship(self, msg: PoseStamped) -> None:
        """Take a ship pose: every fairlead moves with it; advance."""
        stamp_ns = self._stamp(SHIP_POSE, SHIP, msg)
        self.record(SHIP_POSE, msg)
        if stamp_ns is None:
            return
        p, o = msg.pose.position, msg.pose.orientation
        self._check_frame(SHIP_POSE, msg)
        try:
            event = self.driver.push_ship(stamp_ns, (p.x, p.y, p.z), (o.x, o.y, o.z, o.w))
        except ParameterError as e:  # a pretension no length gives at this pose
            self._warn('start', f'cannot start the lines at this ship pose: {e}')
            return
        except (conversions.PoseError, TrajectoryError) as e:
            self._drop(SHIP_POSE, e)
            return
        self._quiet_ticks[SHIP] = 0
        if 'start' in event:
            chosen = ', '.join(f'{self.names[k]} {length:.3f} m' for k, length
                               in event['start'].items())
            self.get_logger().info('first ship pose: lines started at rest' + (
                f'; lengths for their pretension: {chosen}' if chosen else ''))
        elif event.get('teleport'):
            self.get_logger().warning(
                'the ship jumped more than teleport_distance: restarted at rest '
                + ', '.join(self.names[k] for k in event['teleport']))
        self._advance()

    def _on_bollard(self, name: str, msg: PoseStamped) -> None:
        """Take a bollard pose of one line (ship-to-ship mooring); advance."""
        topic = f'{name}/bollard/pose'
        stamp_ns = self._stamp(topic, name, msg)
        self.record(topic, msg)
        if stamp_ns is None:
            return
        k = self.names.index(name)
        offset = self.driver.mooring.sims[k].params.bollard_offset
        try:
            point = conversions.pose_point(msg.pose, offset)
            event = self.driver.push_bollard(name, stamp_ns, point.point)
        except (conversions.PoseError, TrajectoryError) as e:
            self._drop(topic, e)
            return
        self._check_frame(topic, msg)
        if event == 'ignored':
            self._warn(f'{topic}: payload', f'{topic}: ignored: the bollard end of {name} is '
                       'a free payload')
            return
        self._bollard_levers[k] = point.lever
        self._quiet_ticks[name] = 0
        if event == 'teleport':
            self.get_logger().warning(f'{name}: the bollard jumped more than '
                                      'teleport_distance: line restarted at rest')
        if self.driver.started:
            self._advance()

    def _check_frame(self, topic: str, msg: PoseStamped) -> None:
        frame_id = self.driver.arrangement.shared.frame_id
        if msg.header.frame_id and msg.header.frame_id != frame_id:
            self._warn(f'{topic}: frame', f'{topic}: header.frame_id is '
                       f'{msg.header.frame_id!r}, not {frame_id!r}: taken as {frame_id!r} '
                       '(no tf lookup)')

    def _stamp(self, topic: str, stream: str, msg: PoseStamped) -> Optional[int]:
        """Return a pose's stamp [ns], or None if it is too far off the node clock."""
        self.received[topic] += 1
        stamp_ns = conversions.stamp_to_ns(msg.header.stamp)
        now_ns = self.get_clock().now().nanoseconds
        if stamp_ns == 0 and now_ns:
            stamp_ns = now_ns
            self._event('restamp', stream=stream, stamp=now_ns)
            self._warn(f'{topic}: unstamped', f'{topic}: header.stamp is zero: using the '
                       'receive time as the sample time')
        skew = (stamp_ns - now_ns) * 1e-9
        if now_ns and not -self.STAMP_BEHIND_LIMIT <= skew <= self.STAMP_AHEAD_LIMIT:
            side, limit = (('ahead of', self.STAMP_AHEAD_LIMIT) if skew > 0
                           else ('behind', self.STAMP_BEHIND_LIMIT))
            self._event('drop', stream=stream, stamp=stamp_ns)
            self._drop(topic, ValueError(
                f'stamp {side} the node clock by {abs(skew):.3f} s, more than {limit:g} s: '
                'are the clocks in sync (use_sim_time)?'))
            return None
        return stamp_ns

    def _drop(self, topic: str, reason: Exception) -> None:
        count = self.dropped[topic] = self.dropped.get(topic, 0) + 1
        kind = ' '.join(str(reason).split()[:2])
        self._warn(f'{topic}: {kind}', f'{topic}: dropped a message: {reason} '
                   f'({count} dropped on {topic} so far)')

    # -- time -----------------------------------------------------------------------------

    def _tick_period(self, rate: float) -> float:
        """Return the timer period [s] at publish_rate `rate` (see MAX_TICK_RATE)."""
        return 1.0 / min(rate, self.MAX_TICK_RATE)

    def _on_tick(self) -> None:
        """Count a tick without poses for each stream, then advance."""
        if not self.driver.started:
            return
        live_ticks = max(2, math.ceil(self.LIVE_INPUT / self._tick_period(self.driver.rate)))
        for stream in self.driver.streams:
            self._quiet_ticks[stream] += 1
            if self.driver.live(stream) and self._quiet_ticks[stream] >= live_ticks:
                self.driver.silence(stream)
                self._event('silent', stream=stream, t=self.driver.time)
                topic = SHIP_POSE if stream == SHIP else f'{stream}/bollard/pose'
                self._warn(f'{stream}: silent', f'{topic}: no new pose for '
                           f'{self.LIVE_INPUT:g} s: it coasts to a stop and the lines go on '
                           f'with the clock from t = {self.driver.time:.3f} s')
        self._advance()

    def _advance(self) -> None:
        """Advance the lines towards the clock, publishing each output they reach."""
        driver = self.driver
        clock_ns = self.get_clock().now().nanoseconds
        now = driver.seconds(clock_ns) if clock_ns and driver.epoch_ns is not None else math.inf
        rate = driver.rate
        report = driver.advance(now, self.OUTPUTS_PER_CALL * math.ceil(
            rate * self._tick_period(rate) - 1e-9), self.MAX_LAG)
        if report.clock_back:
            self._event('clock_back', back=report.clock_back)
            self.get_logger().warning(
                f'clock jumped back by {report.clock_back:.2f} s: waiting for the next ship '
                'pose to restart the lines')
            return
        if report.skipped:
            self.skips += 1
            self._event('skip', t=report.skip_to)
            self.get_logger().warning(
                f'simulation fell {report.skipped:.2f} s behind the clock: skipped ahead and '
                f'restarted every line at rest (skips so far: {self.skips})')
        for t in report.faults:
            self.get_logger().error(f'non-finite output at t = {t:.3f} s: not published; '
                                    'lines restarted')
        for published in report.outputs:
            self._report(published)
            self._publish(published)

    def _report(self, published: MooringPublished) -> None:
        """Log what the advance to an output did to the lines; keep it for the diagnostics."""
        advance = published.advance
        if advance is None:
            return
        for k, parting in advance.parted.items():
            name = self.names[k]
            self._event('parted', line=name, t=parting.t, segment=parting.segment,
                        break_load=parting.break_load)
            self.get_logger().error(
                f'{name} parted at t = {parting.t:.3f} s, segment {parting.segment} of '
                f'{self.driver.mooring.sims[k].props.segments} (0 at the bollard): its tension '
                f'passed the break load of {parting.break_load / 1e3:.0f} kN. Both pieces go '
                'on; ~/reset restores every line')
        for k, distance in advance.beyond_reach.items():
            self._warn(f'reach {k}', f'{self.names[k]}: its ends are {distance:.1f} m apart, '
                       f"beyond the line's reach of {self.driver.mooring.sims[k].reach:.1f} m:"
                       ' its fairlead is held at the reach')
        for k, why in advance.restarted.items():
            self._restarted[k] = why
            log = (self.get_logger().warning if why == 'back within reach'
                   else self.get_logger().error)
            log(f'{self.names[k]}: {why} at t = {self.driver.time:.3f} s: restarted at rest')

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response):
        if not self.driver.started:
            response.success = False
            response.message = 'no ship pose received yet: nothing to reset'
            return response
        self.driver.reset()
        self._event('reset', t=self.driver.time)
        self._restarted = ['reset'] * len(self.names)
        self._publish_parted(np.zeros(len(self.names), dtype=bool))
        response.success = True
        response.message = f'every line restarted at rest at t = {self.driver.time:.3f} s'
        self.get_logger().info(response.message)
        return response

    # -- outputs --------------------------------------------------------------------------

    def _publish(self, published: MooringPublished) -> None:
        """
        Publish (and record) one output: every line's topics, then the ship's wrenches.

        An output nobody subscribes to (and no bag records) is neither built nor published:
        a ship simulator takes ship/mooring_wrench only, and the 16 lines' 96 other messages
        would go to nobody 100 times a second. A subscriber gets the outputs from the first
        one after its subscription is matched, as from any volatile publisher.
        """
        out, stamp_ns = published.output, published.stamp_ns
        frame_id = self.driver.arrangement.shared.frame_id
        taken = self._taken_outputs.taken
        taken_topics = self._taken_outputs.taken_among(self._line_topics, self.recorder)
        # every line's numbers at once (runner.particles_cdr and wrench_cdr line by line
        # cost a third of the node's time with 16 lines at 100 Hz); the same bytes
        sec, nanosec = split_ns(stamp_ns)
        kinds = {self._line_topics[topic][1] for topic in taken_topics}
        if 'rope/particles' in kinds:
            positions = np.concatenate(out.positions)
            starts = np.cumsum([0] + [len(x) for x in out.positions])
            poses = np.concatenate([positions, lines_tangent_quaternions(positions, starts)], 1)
        if 'fairlead/tension' in kinds:
            fairlead_torques = cross_rows(published.levers, out.fairlead_forces)
        if 'bollard/tension' in kinds:
            bollard_torques = cross_rows(self._bollard_levers, out.bollard_forces)
        build = {
            'rope/particles': lambda k: cdr.pose_array(sec, nanosec, frame_id,
                                                       poses[starts[k]:starts[k + 1]]),
            'fairlead/tension': lambda k: cdr.wrench(out.fairlead_forces[k],
                                                     fairlead_torques[k]),
            'bollard/tension': lambda k: cdr.wrench(out.bollard_forces[k], bollard_torques[k]),
            'fairlead/peak_tension': lambda k: cdr.float64(out.fairlead_peaks[k]),
            'bollard/peak_tension': lambda k: cdr.float64(out.bollard_peaks[k]),
            'winch/length': lambda k: cdr.float64(out.line_lengths[k]),
            PAYLOAD_OUTPUT[0]: lambda k: pose_stamped_cdr(stamp_ns, frame_id,
                                                          out.payload_positions[k]),
        }
        for topic in taken_topics:
            k, relative = self._line_topics[topic]
            data = build[relative](k)
            self._outputs[topic].publish(data)
            self.record(topic, data, stamp_ns)
        ship_frame_id = self.driver.arrangement.ship_frame_id
        for publisher, topic, frame, wrench in (
                (self._wrench_pub, WRENCH_TOPIC, ship_frame_id,
                 lambda: (published.force, published.moment)),
                (self._world_wrench_pub, WORLD_WRENCH_TOPIC, frame_id, published.world_wrench)):
            if taken(topic, self.recorder):
                data = cdr.wrench_stamped(sec, nanosec, frame, *wrench())
                publisher.publish(data)
                self.record(topic, data, stamp_ns)
        self._publish_parted(out.parted)
        self._latest = published
        self._peaks = np.maximum(self._peaks, out.peaks)  # every step's, not only outputs'

    def _publish_parted(self, parted: np.ndarray) -> None:
        """Publish (and record) on <line>/rope/parted whether each line has parted, if new."""
        for k, now in enumerate(parted.tolist()):
            if now is self._parted_said[k]:
                continue
            self._parted_said[k] = now
            topic = f'{self.names[k]}/{PARTED_TOPIC}'
            msg = Bool(data=now)
            self._outputs[topic].publish(msg)
            self.record(topic, msg)

    def _on_winch_command(self, name: str, msg: Float64) -> None:
        """Take a winch speed for one line [m/s] (+ pays out); refuse a non-finite one."""
        topic = f'{name}/{WINCH_COMMAND}'
        try:
            self.driver.command_winch(name, msg.data)
        except ParameterError as e:
            self._warn(f'{topic}: bad', f'{topic}: {e}; ignored')
            return
        self._event('winch', line=name, t=self.driver.time if self.driver.started else 0.0,
                    speed=msg.data)
        mode = self.driver.mooring.sims[self.names.index(name)].params.winch_mode
        if mode != 'speed':
            self._warn(f'{topic}: mode', f'{topic} {msg.data:g} m/s kept: it acts while '
                       f"{name}.winch_mode is 'speed' (now '{mode}')")

    def _on_markers(self) -> None:
        """Publish the lines as markers, coloured by their utilisation (mooring_display)."""
        published = self._latest
        if published is None or not self._taken_outputs.subscribed(MARKERS_TOPIC):
            return  # nobody looks: not built (16 strips of 51 points)
        out = published.output
        msg = self._line_markers(
            self.driver.arrangement.shared.frame_id, published.stamp_ns, self.names,
            out.positions, np.maximum(out.fairlead_tensions, out.bollard_tensions),
            self.ratings, out.parted, np.array([p[-1] for p in out.positions]),
            np.array([p[0] for p in out.positions]))
        self._markers_pub.publish(msg)

    def _on_diagnostics(self) -> None:
        """Publish one status per line; its peak and restarts count from the last report."""
        published = self._latest
        now_ns = self.get_clock().now().nanoseconds
        if published is None:
            msg = DiagnosticArray(status=[DiagnosticStatus(
                level=DiagnosticStatus.STALE, name=f'mooring: {name}', hardware_id=name,
                message=f'waiting for the first pose on {SHIP_POSE}',
                values=[KeyValue(key='state', value='not started')]) for name in self.names])
            msg.header.stamp = conversions.ns_to_stamp(now_ns)
        else:
            out = published.output
            msg = line_diagnostics(
                published.stamp_ns, self.names,
                np.maximum(out.fairlead_tensions, out.bollard_tensions), self._peaks,
                out.max_strains, self.ratings, out.parted, self._restarted)
            self._peaks = np.zeros(len(self.names))
            self._restarted = [None] * len(self.names)
        self._diagnostics_pub.publish(msg)

    def _event(self, kind: str, **fields: Any) -> None:
        """Publish and record a decision taken on the node clock."""
        msg = String(data=encode_event(kind, **fields))
        self._events_pub.publish(msg)
        self.record(EVENTS_TOPIC, msg)

    # -- recording ------------------------------------------------------------------------

    def _start_recording(self) -> None:
        """Start recording to record_path, if set: the poses, every output, the events."""
        setup = self.driver.arrangement
        path = setup.shared.record_path
        if not path:
            return
        try:
            recorder = Recorder(path, {arrangement.PARAMETERS_KEY: arrangement.parameters_yaml(
                setup)}, self.get_logger())
        except (BagError, OSError) as e:
            raise StartupError(f'record_path: {e}') from None
        for name, subscription in self._pose_subs.items():
            topic = SHIP_POSE if name == SHIP else f'{name}/bollard/pose'
            recorder.add_topic(topic, subscription.topic_name, 'geometry_msgs/msg/PoseStamped',
                               offered_qos=functools.partial(self._offered_qos,
                                                             subscription.topic_name))
        for topic, publisher in self._outputs.items():
            type_name = LINE_OUTPUTS.get(topic.split('/', 1)[1], PAYLOAD_OUTPUT[1])
            recorder.add_topic(topic, publisher.topic_name, type_name, publisher.qos_profile)
        for topic, publisher, type_name in (
                (WRENCH_TOPIC, self._wrench_pub, 'geometry_msgs/msg/WrenchStamped'),
                (WORLD_WRENCH_TOPIC, self._world_wrench_pub, 'geometry_msgs/msg/WrenchStamped'),
                (EVENTS_TOPIC, self._events_pub, 'std_msgs/msg/String')):
            recorder.add_topic(topic, publisher.topic_name, type_name, publisher.qos_profile)
        self.recorder = recorder
        self.get_logger().info(f'recording the poses, every line and the ship wrench to '
                               f'{recorder.path}')

    def _offered_qos(self, topic: str) -> List[QoSProfile]:
        return [info.qos_profile for info in self.get_publishers_info_by_topic(topic)]

    def record(self, topic: str, msg: Any, stamp_ns: Optional[int] = None) -> None:
        """Hand a received or published message (or its CDR bytes) to the recorder."""
        if self.recorder is not None:
            self.recorder.write(topic, msg, self.get_clock().now().nanoseconds, stamp_ns)

    def destroy_node(self) -> None:
        """Destroy the node, then close the bag (if recording)."""
        super().destroy_node()
        self.get_logger().info('poses: ' + ('; '.join(
            f'{topic}: {count} received, {self.dropped.get(topic, 0)} dropped, '
            f'{self.lost[topic]} lost on the way'
            for topic, count in self.received.items() if count or self.lost[topic])
            or 'none received'))
        if self.recorder is not None:
            self.recorder.close()

    def _warn(self, key: str, text: str) -> None:
        """Log a warning, at most once per THROTTLE seconds per key."""
        now = self.get_clock().now().nanoseconds * 1e-9
        last = self._last_log.get(key)
        if last is None or not 0.0 <= now - last < self.THROTTLE:
            self._last_log[key] = now
            self.get_logger().warning(text)


def main(args=None) -> int:
    """
    Run the node until Ctrl-C or SIGTERM, then close its bag (if recording).

    :returns: 0, or 2 when a parameter is not allowed or record_path cannot be used.
    """
    rclpy.init(args=args)
    try:
        node = MooringNode()
    except StartupError as e:
        rclpy.logging.get_logger(NODE_NAME).error(str(e))
        rclpy.try_shutdown()
        return 2
    except KeyboardInterrupt:
        rclpy.try_shutdown()
        return 0
    except Exception:
        if rclpy.ok():
            raise
        return 0  # SIGTERM during start-up: rclpy shut the context down under us
    # What start-up allocated lives as long as the node: keep it out of the cyclic
    # collector's full passes (mooring_line_node.main says what they cost).
    gc.freeze()
    try:
        if rclpy.ok():
            spin_until_shutdown(node)
    finally:
        with signals_ignored():  # a second Ctrl-C must not cut the bag short
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
