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
The mooring_line node: one simulated mooring line between a bollard and a fairlead.

ROS glue only. Parameters (params.SPECS) become ParameterDescriptors and then a
line_driver.LineDriver, which holds the input and output rules the offline runner uses
too: simulated time 0 at the first pose, the rope one sample behind a live pose stream,
outputs every 1 / publish_rate from the last (re)start, skip ahead past MAX_LAG, the torque
arm of each output. Outputs are published as soon as the rope reaches them: in the pose
callback that lets it, or in a timer tick when no pose stream is live.

Time: the rope follows the node clock, so use_sim_time and /clock work. It advances to
now, but while an end's pose stream is live never past that end's second-newest sample
(see line_driver). Running ahead instead (extrapolating, then pulling the end back when
the next pose arrives) costs a stiff line as much tension noise as the motion itself. When
a stream falls silent for LIVE_INPUT seconds the end coasts to a stop, the rope goes on to
now and a warning says so; poses that come late bring the end back onto its track smoothly
(Simulator._blend_ends). Under use_sim_time, until the first /clock message the poses alone
set the pace.

Decisions taken on the node clock (a stream taken for silent, a skip ahead, a restart by
~/reset or by a clock jump back, a pose dropped for its stamp or stamped on receipt, a
parameter set at run time) are published on rope/events (std_msgs/String, one JSON object
each, line_driver.encode_event) and recorded, so that `rope_sim resim` of the node's bag
takes them at the same points and reproduces its outputs.

Inputs: a pose stamped more than STAMP_AHEAD_LIMIT ahead of the node clock or
STAMP_BEHIND_LIMIT behind it is dropped and counted, like a non-finite one; a jump of either
end larger than teleport_distance restarts the rope there (the simulator's rule, so the
offline runner follows it too). The pose queues hold POSE_QUEUE_DEPTH poses; poses DDS lost
before they reached the node are counted (message_lost). publish_rate changed at run time
applies from the next output on.

Recording (record_path): every received pose and published message also goes to a bag
through recorder.Recorder, which never blocks the tick; Ctrl-C and SIGTERM close the bag,
after SIGKILL `rope_sim recover` completes it.
"""

import array
import functools
import gc
import math
import os
from typing import Any, Dict, List, Optional
import warnings

from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
import numpy as np
from rcl_interfaces.msg import (
    FloatingPointRange, IntegerRange, ParameterDescriptor, SetParametersResult)
import rclpy
from rclpy.clock import Clock, ClockType
from rclpy.event_handler import QoSMessageLostInfo, SubscriptionEventCallbacks
from rclpy.exceptions import ParameterException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import (DurabilityPolicy, HistoryPolicy, QoSPolicyKind, QoSProfile,
                       ReliabilityPolicy)
from rclpy.qos_overriding_options import InvalidQosOverridesError, QoSOverridingOptions
from std_msgs.msg import Bool, Float64, String
from std_srvs.srv import Trigger

from . import conversions
from .outputs import OutputPublishers
from .recorder import BOOL, FLOAT64, POSE_ARRAY, POSE_STAMPED, Recorder, STRING, WRENCH
from .spinning import set_timer_period, signals_ignored, spin_until_shutdown
from ..bag import BagError, cdr
from ..line_driver import (BOLLARD, encode_event, ENDS, EVENTS_TOPIC, FAIRLEAD, LineDriver,
                           MAX_LAG, PARAMETERS_KEY, parameters_yaml, PARTED_TOPIC, Published)
from ..params import table as params
from ..runner import particles_cdr, pose_stamped_cdr, wrench_cdr
from ..simulator import Simulator
from ..trajectory import TrajectoryError

NODE_NAME = params.NODE_NAME
# Parameters rclpy itself declares or reads; not ours to warn about.
ROS_PARAMETERS = ('use_sim_time', 'start_type_description_service')
POSE_RELIABILITY = {'reliable': ReliabilityPolicy.RELIABLE,
                    'best_effort': ReliabilityPolicy.BEST_EFFORT}
_OUTPUT_TYPES = {'rope/particles': POSE_ARRAY, 'fairlead/tension': WRENCH,
                 'bollard/tension': WRENCH, EVENTS_TOPIC: STRING,
                 'payload/pose': POSE_STAMPED, 'fairlead/peak_tension': FLOAT64,
                 'bollard/peak_tension': FLOAT64, 'winch/length': FLOAT64,
                 PARTED_TOPIC: BOOL}
# The outputs with a header: recorded at their stamp, the others at their log time.
STAMPED_OUTPUTS = ('rope/particles', 'payload/pose')
# History depth of the pose subscriptions (KEEP_LAST). A full queue drops its oldest pose
# without a trace (DDS reports no loss for it): at depth 50 a burst of 10,000 poses reached
# the node as 747 to 887, a 1 kHz stream for 30 s lost 3.5 %. This holds a whole burst, or
# 10 s at 1 kHz, for about 2.5 MB more memory per topic once full.
POSE_QUEUE_DEPTH = 10000
QOS_OVERRIDES_ALLOWED = ('reliability reliable or best_effort, history keep_last or keep_all, '
                         'depth >= 1 for keep_last')


class StartupError(Exception):
    """The node cannot start with these parameters; the message names the culprit."""


def describe(name: str, spec: params.Spec) -> ParameterDescriptor:
    """Return the ParameterDescriptor of one parameter of params.SPECS."""
    unit = f' [{spec.unit}]' if spec.unit else ''
    descriptor = ParameterDescriptor(
        name=name,
        type=Parameter.Type.from_parameter_value(spec.default).value,
        description=spec.description + unit,
        additional_constraints=params.allowed(spec),
        read_only=spec.read_only)
    if _is_number(spec.default) and spec.low is not None and spec.high is not None:
        if isinstance(spec.default, int):
            descriptor.integer_range = [
                IntegerRange(from_value=int(spec.low), to_value=int(spec.high), step=1)]
        else:
            # the range must hold the special value too (-1: the material's), or rclpy
            # refuses it; a level's -inf (none) gets no range: additional_constraints says it
            low = spec.low if spec.special is None else min(spec.low, spec.special)
            if math.isfinite(low):
                descriptor.floating_point_range = [
                    FloatingPointRange(from_value=float(low), to_value=float(spec.high))]
    return descriptor


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _plain(value: Any) -> Any:
    """Return a parameter value as params.check expects it (arrays as lists)."""
    if isinstance(value, (array.array, np.ndarray, tuple)):
        return list(value)
    return value


def _as_declared(name: str, value: Any) -> Any:
    """Return integers given for a double (array) parameter as doubles; else the value."""
    default = params.SPECS[name].default
    value = _plain(value)
    if isinstance(default, float) and _is_number(value):
        return float(value)
    if isinstance(default, list) and isinstance(value, list) and all(map(_is_number, value)):
        return [float(v) for v in value]
    return value


class MooringLineNode(Node):
    """One simulated mooring line; see the module docstring and the README's ROS section."""

    # A pose stream is live until the node has run this long [s] without a new sample of it:
    # the rope waits for its next sample instead of guessing. Counted in ticks, not from the
    # stamps, so that a node that was itself stalled first reads the poses queued meanwhile.
    LIVE_INPUT = 0.25
    # Falling further behind than this [s] restarts the rope at now instead of catching up.
    MAX_LAG = MAX_LAG
    # One tick or pose callback simulates and publishes at most this many output periods of
    # a tick, so that a node catching up stays responsive (ticks and poses together catch up
    # fast enough).
    OUTPUTS_PER_CALL = 2
    # The timer ticks at publish_rate, but no faster than this [Hz]; faster rates publish
    # several outputs per tick, their stamps still 1 / rate apart. At publish_rate 1000 with
    # 50 Hz poses the node took 54 % of a core with 1 kHz ticks, 38 % with these (both
    # delivered 1000 outputs a second).
    MAX_TICK_RATE = 200.0
    # A pose stamped further than this [s] ahead of the node clock is dropped. One stamped
    # 1 h ahead froze the fairlead for the hour (every later pose was not after the newest
    # one), one 15 s ahead for 15 s, then a 335 kN spike. Poses do not come from the future:
    # this allows for clocks a little out of sync (NTP keeps them within milliseconds).
    STAMP_AHEAD_LIMIT = 1.0
    # ... or further than this [s] behind it. A late pose is mostly harmless (the rope
    # follows the stream, late), but a stream that late holds the outputs back as long
    # after each silence. Poses wait for the node in transport and in its queue: the node
    # took the last of a burst of 10,000 1.9 s after its stamp (3.7 s while recording).
    STAMP_BEHIND_LIMIT = 10.0
    THROTTLE = 5.0  # seconds between repeated warnings of one kind

    def __init__(self, **kwargs):
        """
        Declare the parameters, build the simulator, then create the ROS interfaces.

        :raises StartupError: a parameter value is not allowed or the line cannot be built.
        """
        super().__init__(NODE_NAME, **kwargs)
        self._last_log: Dict[str, float] = {}
        # per pose topic: messages taken, dropped (bad or far-off stamps, see _drop) and lost
        # before they reached the node (DDS's message_lost count)
        self.received = {'fairlead/pose': 0, 'bollard/pose': 0}
        self.dropped: Dict[str, int] = {}
        self.lost = {'fairlead/pose': 0, 'bollard/pose': 0}
        self.skips = 0  # times the rope skipped ahead (MAX_LAG)
        # A Recorder while recording (record_path): gets every message via record().
        self.recorder: Optional[Recorder] = None
        self.driver: Optional[LineDriver] = None
        self.add_pre_set_parameters_callback(self._coerce_parameters)
        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._apply_parameters)
        values = self._declare_parameters()
        try:
            line = params.from_values(values)
            self.driver = LineDriver(line)
            warm_up(line, self.get_logger().info)
        except ValueError as e:  # ParameterError, MaterialError, an unstable line
            raise StartupError(str(e)) from None
        # ticks since the newest sample of each end (see LIVE_INPUT)
        self._quiet_ticks = {end: 0 for end in ENDS}
        self._told_payload = False

        self._taken_outputs = OutputPublishers(self)
        create = self._taken_outputs.create
        self._outputs = {
            'rope/particles': create(PoseArray, 'rope/particles', 10),
            'fairlead/tension': create(Wrench, 'fairlead/tension', 10),
            'bollard/tension': create(Wrench, 'bollard/tension', 10),
            'fairlead/peak_tension': create(Float64, 'fairlead/peak_tension', 10),
            'bollard/peak_tension': create(Float64, 'bollard/peak_tension', 10),
            'winch/length': create(Float64, 'winch/length', 10),
            # a state, not a stream: latched, so that a monitor started later sees it
            PARTED_TOPIC: create(Bool, PARTED_TOPIC, QoSProfile(
                depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)),
            EVENTS_TOPIC: create(String, EVENTS_TOPIC, 100),
        }
        self._parted = None  # what PARTED_TOPIC said last
        if self.driver.payload:
            self._outputs['payload/pose'] = create(PoseStamped, 'payload/pose', 10)
        self._fairlead_sub = self._pose_subscription(
            'fairlead/pose', functools.partial(self._on_pose, FAIRLEAD))
        self._bollard_sub = self._pose_subscription(
            'bollard/pose', functools.partial(self._on_pose, BOLLARD))
        for name in getattr(self, '_parameter_overrides', {}):
            if name.startswith('qos_overrides.') and not self.has_parameter(name):
                self.get_logger().warning(
                    f'ignoring unknown parameter {name!r}: the pose subscriptions take '
                    f'qos_overrides.{self._fairlead_sub.topic_name}.subscription.reliability '
                    '(and .history, .depth; the same for bollard/pose)')
        if any(s.qos_profile.reliability == ReliabilityPolicy.RELIABLE
               for s in (self._fairlead_sub, self._bollard_sub)):
            # rclpy's incompatible-QoS event was missed in 1 of 6 start-ups; the graph is
            # not. On the steady clock: under use_sim_time there may be no /clock yet.
            self._qos_timer = self.create_timer(
                1.0, self._check_pose_publishers, clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._winch_sub = self.create_subscription(Float64, 'winch/command',
                                                   self._on_winch_command, 10)
        self._reset_srv = self.create_service(Trigger, '~/reset', self._on_reset)
        self._timer = self.create_timer(_tick_period(line.publish_rate), self._on_tick)
        self._start_recording()
        props = self.simulator.props
        self.get_logger().info(
            f'{line.material} line, {line.diameter * 1e3:g} mm, {props.length:g} m, '
            f'{props.segments} segments, MBL {self.simulator.material.mbl / 1e3:.0f} kN, '
            f'{line.integrator} step {self.simulator.time_step * 1e3:.4g} ms; '
            f'waiting for the first pose on {self._fairlead_sub.topic_name}')

    # -- parameters ---------------------------------------------------------------------

    def _declare_parameters(self) -> dict:
        """Declare every parameter of params.SPECS; return their validated start values."""
        given = self._start_values()
        values = {}
        for name, spec in params.SPECS.items():
            value = given.get(name, spec.default)
            self.declare_parameter(name, value, describe(name, spec), ignore_override=True)
            values[name] = value
        return values

    def _start_values(self) -> dict:
        """
        Return the values of --params-file / -p, validated (doubles may be integers).

        rclpy would refuse `length: 40` for a double; the offline runner reading the same
        file accepts it, so the node does too. rclpy keeps these values in
        Node._parameter_overrides, which has no public accessor.

        :raises StartupError: the first value that is not allowed, named.
        """
        values = {}
        for name, parameter in getattr(self, '_parameter_overrides', {}).items():
            if name in params.SPECS:
                try:
                    values[name] = params.check(name, _as_declared(name, parameter.value))
                except params.ParameterError as e:
                    raise StartupError(str(e)) from None
            elif name not in ROS_PARAMETERS and not name.startswith('qos_overrides.'):
                self.get_logger().warning(f'ignoring unknown parameter {name!r}')
        return values

    def _coerce_parameters(self, parameters: List[Parameter]) -> List[Parameter]:
        """Pre-set callback: integers given for double parameters become doubles."""
        out = []
        for p in parameters:
            default = params.SPECS[p.name].default if p.name in params.SPECS else None
            if ((isinstance(default, float) and p.type_ == Parameter.Type.INTEGER)
                    or (isinstance(default, list) and p.type_ == Parameter.Type.INTEGER_ARRAY)):
                p = Parameter(p.name, value=_as_declared(p.name, p.value))
            out.append(p)
        return out

    def _validate_parameters(self, parameters: List[Parameter]) -> SetParametersResult:
        """On-set callback: refuse a value outside its range, with the reason."""
        for p in parameters:
            if p.name in params.SPECS:
                try:
                    params.check(p.name, _plain(p.value))
                except params.ParameterError as e:
                    return SetParametersResult(successful=False, reason=str(e))
        values = {p.name: _plain(p.value) for p in parameters if p.name in params.SPECS}
        if self.driver is not None and values:
            try:  # e.g. less damping under a fixed improved_euler step: unstable
                self.driver.check_update(values)
            except params.ParameterError as e:
                return SetParametersResult(successful=False, reason=str(e))
        return SetParametersResult(successful=True)

    def _apply_parameters(self, parameters: List[Parameter]) -> None:
        """Post-set callback: hand run-time changes to the simulator at once."""
        if self.driver is None:  # still declaring
            return
        values = {p.name: _plain(p.value) for p in parameters if p.name in params.SPECS}
        if not values:
            return
        try:
            self.driver.update(values)
        except ValueError as e:  # validated already: the simulator should never refuse
            self.get_logger().error(f'could not apply {values}: {e}')
            return
        self._event('set', values=values)
        if 'publish_rate' in values:
            # the driver re-anchored the outputs; the ticks follow the rate
            set_timer_period(self._timer, _tick_period(self.simulator.params.publish_rate))
        self.get_logger().info('set ' + ', '.join(f'{k} = {v}' for k, v in values.items()))

    # -- inputs -------------------------------------------------------------------------

    def _pose_subscription(self, topic: str, callback):
        """
        Subscribe to a pose topic: pose_reliability, POSE_QUEUE_DEPTH, losses counted.

        The standard parameters qos_overrides.<topic>.subscription.reliability / history /
        depth (read-only, <topic> resolved, e.g. /line_1/fairlead/pose) override them.

        :raises StartupError: an override is not a valid QoS value.
        """
        qos = QoSProfile(depth=POSE_QUEUE_DEPTH,
                         reliability=POSE_RELIABILITY[self.simulator.params.pose_reliability])
        overrides = QoSOverridingOptions(
            (QoSPolicyKind.RELIABILITY, QoSPolicyKind.HISTORY, QoSPolicyKind.DEPTH),
            callback=check_pose_qos)
        events = SubscriptionEventCallbacks(message_lost=functools.partial(self._on_lost, topic))
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

    def _on_pose(self, end: str, msg: PoseStamped) -> None:
        """Take a pose of an end: record it, check it, push its end point, advance."""
        topic = f'{end}/pose'
        self.received[topic] += 1
        stamp_ns = self._stamp(end, msg)  # its events go to the bag before the pose
        self.record(topic, msg)
        if stamp_ns is None:
            return
        offset = (self.simulator.params.fairlead_offset if end == FAIRLEAD
                  else self.simulator.params.bollard_offset)
        try:
            point = conversions.pose_point(msg.pose, offset)
        except conversions.PoseError as e:
            self._drop(topic, e)
            return
        if abs(point.quaternion_norm - 1.0) > 1e-3:
            self._warn(f'{topic}: norm', f'{topic}: normalised a non-unit quaternion '
                       f'(|q| = {point.quaternion_norm:.4g})')
        frame_id = self.simulator.params.frame_id
        if msg.header.frame_id and msg.header.frame_id != frame_id:
            self._warn(f'{topic}: frame', f'{topic}: header.frame_id is '
                       f'{msg.header.frame_id!r}, not {frame_id!r}: taken as {frame_id!r} '
                       '(no tf lookup)')
        try:
            event = self.driver.push(end, stamp_ns, point.point, point.lever)
        except TrajectoryError as e:
            self._drop(topic, e)
            return
        if event == 'ignored':
            if not self._told_payload:  # once: every bollard pose is ignored alike
                self._told_payload = True
                self.get_logger().warning(
                    'bollard/pose: ignored: the bollard end is a free payload (payload_mass '
                    f'{self.simulator.params.payload_mass:g} kg > 0), see payload/pose')
            return
        self._quiet_ticks[end] = 0
        if event == 'teleport':
            # Not throttled: each jump is a restart, a step in the published tension. The
            # rope restarted at the state time, the last output's: the next output shows it.
            self.get_logger().warning(
                f'{end} jumped {self.simulator.last_jump:.2f} m, more than teleport_distance '
                f'({self.simulator.params.teleport_distance:g} m), to {_fmt(point.point)}: '
                'rope restarted on the catenary there')
        elif event == 'start':
            self.get_logger().info(
                f'first fairlead pose: rope started on the catenary to {_fmt(point.point)}')
        if self.driver.started:
            self._advance()

    def _stamp(self, end: str, msg: PoseStamped) -> Optional[int]:
        """
        Return the sample stamp [ns] of a pose, or None if its stamp is too far off the clock.

        Both decisions depend on the node clock: they are events (see _event).
        """
        topic = f'{end}/pose'
        stamp_ns = conversions.stamp_to_ns(msg.header.stamp)
        now_ns = self.get_clock().now().nanoseconds
        if stamp_ns == 0 and now_ns:  # (a bag replayed from time 0 has both at 0 at first)
            stamp_ns = now_ns
            self._event('restamp', end=end, stamp=now_ns)
            self._warn(f'{topic}: unstamped', f'{topic}: header.stamp is zero: using the '
                       'receive time as the sample time')
        # Under use_sim_time the clock reads 0 until the first /clock: nothing to compare.
        skew = (stamp_ns - now_ns) * 1e-9
        if now_ns and not -self.STAMP_BEHIND_LIMIT <= skew <= self.STAMP_AHEAD_LIMIT:
            side, limit = (('ahead of', self.STAMP_AHEAD_LIMIT) if skew > 0
                           else ('behind', self.STAMP_BEHIND_LIMIT))
            self._event('drop', end=end, stamp=stamp_ns)
            self._drop(topic, ValueError(
                f'stamp {side} the node clock by {abs(skew):.3f} s, more than {limit:g} s: '
                'are the clocks in sync (use_sim_time)?'))
            return None
        return stamp_ns

    def _check_pose_publishers(self) -> None:
        """Warn of best-effort pose publishers: they cannot reach a reliable subscription."""
        for topic in (s.topic_name for s in (self._fairlead_sub, self._bollard_sub)
                      if s.qos_profile.reliability == ReliabilityPolicy.RELIABLE):
            if any(info.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT
                   for info in self.get_publishers_info_by_topic(topic)):
                self._warn(f'{topic}: qos', f'{topic}: a best-effort publisher cannot reach '
                           'this reliable subscription, so its poses never arrive: set '
                           'pose_reliability:=best_effort')

    def _drop(self, topic: str, reason: Exception) -> None:
        count = self.dropped[topic] = self.dropped.get(topic, 0) + 1
        kind = ' '.join(str(reason).split()[:2])  # e.g. 'zero quaternion'
        self._warn(f'{topic}: {kind}', f'{topic}: dropped a message: {reason} '
                   f'({count} dropped on {topic} so far)')

    # -- time ---------------------------------------------------------------------------

    @property
    def simulator(self) -> Optional[Simulator]:
        """Return the line's Simulator (None while the parameters are being declared)."""
        return None if self.driver is None else self.driver.simulator

    def _live_ticks(self) -> int:
        """Return after how many ticks without a sample a stream is silent (LIVE_INPUT)."""
        return max(2, math.ceil(self.LIVE_INPUT / _tick_period(
            self.simulator.params.publish_rate)))

    def _on_tick(self) -> None:
        """Count a tick without poses for each end, then advance (to now if none is live)."""
        if not self.driver.started:
            return
        for end in ENDS:
            self._quiet_ticks[end] += 1
            if self.driver.live(end) and self._quiet_ticks[end] >= self._live_ticks():
                self.driver.silence(end)
                self._event('silent', end=end, t=self.driver.time)
                self._warn(f'{end}: silent', f'{end}/pose: no new pose for '
                           f'{self.LIVE_INPUT:g} s: the {end} coasts to a stop and the rope goes '
                           f'on with the clock from t = {self.driver.time:.3f} s')
        self._advance()

    def _advance(self) -> None:
        """
        Advance the rope towards the clock, publishing each output it reaches (LineDriver).

        Outputs go out as soon as the input reaches them: from a pose callback when a pose
        stream is live, else from the tick. One call publishes at most OUTPUTS_PER_CALL
        ticks' worth of them, so that a node catching up stays responsive; a node further
        behind than MAX_LAG skips ahead instead of catching up.
        """
        driver = self.driver
        clock_ns = self.get_clock().now().nanoseconds
        # With use_sim_time the clock reads 0 until the first /clock message: until then
        # the poses alone say how far the rope may go.
        now = driver.seconds(clock_ns) if clock_ns and driver.epoch_ns is not None else math.inf
        if not clock_ns and driver.simulator.fairlead.last_time > self.LIVE_INPUT:
            self._warn('no clock', 'use_sim_time is true but no /clock message has come: '
                       'the rope follows the pose stamps alone')
        rate = driver.rate
        report = driver.advance(now, self.OUTPUTS_PER_CALL * math.ceil(
            rate * _tick_period(rate) - 1e-9), self.MAX_LAG)
        if report.clock_back:
            self._event('clock_back', back=report.clock_back)
            self.get_logger().warning(
                f'clock jumped back by {report.clock_back:.2f} s: waiting for the next '
                'fairlead pose to restart the rope')
            return
        if report.skipped:
            self.skips += 1
            self._event('skip', t=report.skip_to)
            # Not throttled: each skip is a restart, a step in the published tension, and
            # there is at most one per MAX_LAG.
            self.get_logger().warning(
                f'simulation fell {report.skipped:.2f} s behind the clock: skipped ahead '
                f'and restarted the rope on the catenary (skips so far: {self.skips})')
        for t in report.faults:
            self.get_logger().error(
                f'non-finite output at t = {t:.3f} s: not published; rope restarted')
        for published in report.outputs:
            self._report(published.advance)
            self._publish(published)

    def _report(self, advance) -> None:
        """Log what the advance to an output did to the rope."""
        if advance is None:
            return
        sim = self.simulator
        if advance.parted is not None:
            parting = advance.parted
            self._event('parted', t=parting.t, segment=parting.segment,
                        break_load=parting.break_load)
            self.get_logger().error(
                f'the line parted at t = {parting.t:.3f} s, segment {parting.segment} of '
                f'{sim.props.segments} (0 at the bollard): its tension passed the break load '
                f'of {parting.break_load / 1e3:.0f} kN. Both pieces go on; ~/reset restores '
                'the line')
        if advance.beyond_reach:
            self._warn('reach', f'the ends are {advance.beyond_reach:.1f} m apart, beyond '
                       f"the line's reach of {sim.reach:.1f} m (length x (1 + max_strain)):"
                       ' the fairlead is held at the reach')
        if advance.restarted == 'back within reach':
            self.get_logger().warning(
                f'the ends came back within reach at t = {sim.time:.3f} s: rope restarted '
                'at rest on the catenary')
        elif advance.restarted:
            self.get_logger().error(
                f'rope state turned {advance.restarted.split()[0]} at t = '
                f'{sim.time:.3f} s: restarted it on the catenary')

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response):
        if not self.driver.started:
            response.success = False
            response.message = 'no fairlead pose received yet: nothing to reset'
            return response
        self.driver.reset()
        self._event('reset', t=self.driver.time)
        self._publish_parted(False)
        response.success = True
        response.message = (
            f'rope restarted on the catenary at t = {self.driver.time:.3f} s')
        self.get_logger().info(response.message)
        return response

    # -- outputs ------------------------------------------------------------------------

    def _publish(self, published: Published) -> None:
        """
        Publish (and record) one output: particles, tensions, payload pose, peaks, length.

        Only the topics taken (subscribed to, or recorded) are built, as CDR bytes from the
        numbers: through rclpy's message classes the particles and tensions of one output
        cost 370 us, as bytes 80 us.
        """
        out, stamp_ns = published.output, published.stamp_ns
        frame_id = self.simulator.params.frame_id
        build = {
            'rope/particles': lambda: particles_cdr(stamp_ns, frame_id, out.positions),
            'fairlead/tension': lambda: wrench_cdr(out.fairlead_force, published.fairlead_lever),
            'bollard/tension': lambda: wrench_cdr(out.bollard_force, published.bollard_lever),
        }
        if out.payload_position is not None:
            build['payload/pose'] = lambda: pose_stamped_cdr(stamp_ns, frame_id,
                                                             out.payload_position)
        build['fairlead/peak_tension'] = lambda: cdr.float64(out.fairlead_peak)
        build['bollard/peak_tension'] = lambda: cdr.float64(out.bollard_peak)
        build['winch/length'] = lambda: cdr.float64(out.line_length)
        for topic, message in build.items():
            if self._taken_outputs.taken(topic, self.recorder):
                data = message()
                self._outputs[topic].publish(data)
                # a message without a header is recorded at its log time, as received
                self.record(topic, data, stamp_ns if topic in STAMPED_OUTPUTS else None)
        self._publish_parted(out.parted)

    def _publish_parted(self, parted: bool) -> None:
        """Publish (and record) whether the line has parted, when that changes."""
        if parted != self._parted:
            self._parted = parted
            msg = Bool(data=parted)
            self._outputs[PARTED_TOPIC].publish(msg)
            self.record(PARTED_TOPIC, msg)

    def _on_winch_command(self, msg: Float64) -> None:
        """Take a winch speed from winch/command [m/s] (+ pays out); refuse a non-finite one."""
        try:
            self.driver.command_winch(msg.data)
        except params.ParameterError as e:
            self._warn('winch', f'winch/command: {e}; ignored')
            return
        self._event('winch', t=self.driver.time if self.driver.started else 0.0,
                    speed=msg.data)
        if self.simulator.params.winch_mode != 'speed':
            self._warn('winch_mode', f'winch/command {msg.data:g} m/s kept: it acts while '
                       "winch_mode is 'speed' (now "
                       f"'{self.simulator.params.winch_mode}')")

    def _event(self, kind: str, **fields: Any) -> None:
        """Publish and record a decision taken on the node clock (see the module docstring)."""
        msg = String(data=encode_event(kind, **fields))
        self._outputs[EVENTS_TOPIC].publish(msg)
        self.record(EVENTS_TOPIC, msg)

    # -- recording ----------------------------------------------------------------------

    def _start_recording(self) -> None:
        """
        Start recording to record_path, if it is set: inputs and outputs, resolved names.

        The bag stores the parameters at start-up as `rope_sim run` does (custom_data
        rope_sim_ros.parameters), so `rope_sim resim` and `rope_sim plot` use them.

        :raises StartupError: record_path exists and is not an empty directory, or it
            cannot be created or written.
        """
        line = self.simulator.params
        if not line.record_path:
            return
        try:
            recorder = Recorder(line.record_path, {PARAMETERS_KEY: parameters_yaml(line)},
                                self.get_logger())
        except (BagError, OSError) as e:
            raise StartupError(f'record_path: {e}') from None
        for topic, subscription in (('fairlead/pose', self._fairlead_sub),
                                    ('bollard/pose', self._bollard_sub)):
            # Stored with the QoS its publishers offer, as `ros2 bag record` does.
            recorder.add_topic(topic, subscription.topic_name, POSE_STAMPED,
                               offered_qos=functools.partial(
                                   self._offered_qos, subscription.topic_name))
        for topic, publisher in self._outputs.items():
            recorder.add_topic(topic, publisher.topic_name, _OUTPUT_TYPES[topic],
                               publisher.qos_profile)
        self.recorder = recorder
        self.get_logger().info(
            f'recording {", ".join(self._outputs)}, fairlead/pose and bollard/pose to '
            f'{os.path.abspath(recorder.path)}')

    def _offered_qos(self, topic: str) -> List[QoSProfile]:
        """Return the QoS profiles the publishers of a topic offer (from the graph)."""
        return [info.qos_profile for info in self.get_publishers_info_by_topic(topic)]

    def close_recording(self) -> None:
        """Complete the bag, if recording: summary and metadata.yaml; log the drop count."""
        if self.recorder is not None:
            self.recorder.close()

    def destroy_node(self) -> None:
        """Destroy the node, then close the bag (see close_recording)."""
        # In this order the closing lines are not sent to /rosout, whose publisher is gone
        # after a signal shut the context down (rcl would complain about each line).
        super().destroy_node()
        self.get_logger().info('poses: ' + ('; '.join(
            f'{topic}: {count} received, {self.dropped.get(topic, 0)} dropped, '
            f'{self.lost[topic]} lost on the way'
            for topic, count in self.received.items() if count or self.lost[topic])
            or 'none received'))
        self.close_recording()

    def record(self, topic: str, msg: Any, stamp_ns: Optional[int] = None) -> None:
        """
        Pass a received or published message to the recorder (the recording hook).

        :param topic: the topic name relative to the node's namespace.
        :param msg: the message, or its CDR bytes.
        :param stamp_ns: the publish time of CDR bytes with a header [ns] (see
            Recorder.write).
        """
        if self.recorder is not None:
            self.recorder.write(topic, msg, self.get_clock().now().nanoseconds, stamp_ns)

    # -- logging ------------------------------------------------------------------------

    def _warn(self, key: str, text: str) -> None:
        """Log a warning, at most once per THROTTLE seconds per key."""
        now = self.get_clock().now().nanoseconds * 1e-9
        last = self._last_log.get(key)
        if last is None or not 0.0 <= now - last < self.THROTTLE:
            self._last_log[key] = now
            self.get_logger().warning(text)


def warm_up(line: params.LineParams, say=None) -> None:
    """
    Run a few steps of a throw-away line, so the compiled kernels load before spinning.

    The build leaves them compiled in numba's cache (0.4 s to load); where it could not
    (read-only install, pip install), numba compiles them here, one to three minutes:
    say(message) tells when that starts and ends.
    """
    from ..precompile import announce_compilation
    with announce_compilation(say):
        sim = Simulator(line)
        sim.push_fairlead(0.0, np.add(line.bollard_position, [0.9 * line.length, 0.0, 0.0]))
        sim.start(0.0)
        sim.advance_to(3.0 * sim.time_step)
        sim.output()


def _tick_period(rate: float) -> float:
    """Return the timer period [s] at publish_rate `rate` (see MAX_TICK_RATE)."""
    return 1.0 / min(rate, MooringLineNode.MAX_TICK_RATE)


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


def main(args=None) -> int:
    """
    Run the node until Ctrl-C or SIGTERM, then close its bag (if recording).

    Ctrl-C and SIGTERM end the spin (spin_until_shutdown) or the start-up alike: the same
    clean shutdown, exit code 0.

    :returns: 0, or 2 when a parameter is not allowed or record_path cannot be used.
    """
    rclpy.init(args=args)
    try:
        node = MooringLineNode()
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
    # What start-up allocated (rclpy, numpy, numba: ~1e5 objects) lives as long as the node:
    # keep it out of the cyclic collector, whose full passes over it took ~45 ms mid-run.
    gc.freeze()
    try:
        if rclpy.ok():  # else SIGTERM came between start-up and spinning
            spin_until_shutdown(node)
    finally:
        with signals_ignored():  # a second Ctrl-C must not cut the bag short
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
