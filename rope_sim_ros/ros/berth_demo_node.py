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
The berth demo's clock, pilot, crew and instructor's table, beside a mooring node (`make demo`).

The mooring node (ship_mode: free, use_sim_time) moves the ship itself, under its lines, its
fenders, the tugs' push and a passing ship (passing_ship.*). This node

- publishes /clock: sim time running at --speed times the wall clock, from CLOCK_ORIGIN s
  (slower while the mooring node cannot keep up: BerthDemo.run);
- is the pilot: once the schedule says `tugs push`, the tugs' push (mooring/berthing.py
  Pilot) on ship/external_wrench, in frame_id axes, once a simulated second from the
  ship's odometry, until they have eased off after `tugs stop`;
- is the crew: each order of the schedule, at the first output at or past its time, as the
  mooring node's services take it (`<line>/make_fast`, `<line>/let_go`, `<line>/stow`,
  `mooring/let_go_all`, std_srvs/Trigger) or as a parameter set on it
  (`mooring/set_parameters`); the answer is printed as a line `T  > ORDER: ANSWER`;
- prints one row per simulated second of the ship's outputs, at the first output of each
  second (t: its time since the free ship's start, its first pose): her least distance off
  the fenders' faces (< 0: compressing one) and her speed towards the quay (mooring/
  berthing.py watch), the tugs' push towards the quay (< 0: pulling her off), each
  fender's load (<fender>/reaction), each line's fairlead tension when fast, `-` while it
  is stowed aboard and `free` once let go (each line's state follows mooring/events), and a
  passing ship's stagger: its midship's distance ahead (+) of the moored ship's or astern
  (-), in her axes where she is then.

The arrangement, the passing ship's track, the pilot and the schedule come from the same
files the mooring node reads (--params, as many as the node's --params-file, the later ones
on top): the `mooring:` sections and the `berth_demo:` ones (mooring/berthing.py). The
clock stops once the ship's outputs reached --duration simulated seconds.

    python -m rope_sim_ros.ros.berth_demo_node --params config/berth.yaml \
        --params config/berth_demo.yaml [--speed 2] [--duration 360]
"""

import argparse
from collections import deque
import math
import sys
import time
from typing import Dict, List, Optional, Sequence, Tuple

from geometry_msgs.msg import PoseStamped, Wrench, WrenchStamped
from nav_msgs.msg import Odometry
import numpy as np
from rcl_interfaces.srv import SetParameters
import rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String
from std_srvs.srv import Trigger

from .discovery import use_quick_discovery
from ..messages.topics import (EXTERNAL_WRENCH, FAIRLEAD_TENSION, FENDER_REACTION, LET_GO_ALL,
                               MOORING_NODE, PASSING_WRENCH, SHIP_ODOMETRY, SHIP_POSE)
from ..model.frames import rotation_matrix
from ..model.ship.loads import PassingShip
from ..mooring.berthing import Berthing, DEMO_NODE, Order, Pilot, read_berthing, watch
from ..mooring.driver import MAX_LAG
from ..mooring.events import decode_event
from ..mooring.ship import quay_normal, ship_loads
from ..params import arrangement
from ..params.files import read_params_file
from ..params.table import not_positive, ParameterError

START_TIMEOUT = 90.0  # [s] a first start compiles or loads the kernels
DISCOVERY_SETTLE = 1.0  # [s] of wall time for the node to match the demo's subscriptions
CLOCK_ORIGIN = 1000.0  # [s] sim time at the demo's t = 0 (0 would read as 'no clock yet')
CLOCK_RATE = 50.0  # [Hz] /clock messages per simulated second
MAX_AHEAD = 0.4  # [s] simulated: the clock's most ahead of the ship's newest output
# A clock held back still ticks (BerthDemo.run): every CREEP s of wall time up to MAX_CREEP
# ahead (a node MAX_LAG behind skips ahead), every STALLED_CREEP s from there.
CREEP = 0.05  # [s] wall
MAX_CREEP = 0.8 * MAX_LAG  # [s] simulated
STALLED_CREEP = 1.0  # [s] wall
GRACE = 10.0  # [s] simulated: how long the clock waits past --duration for the outputs
DEFAULT_DURATION = 200.0  # [s] simulated, when neither --duration nor the files say
PILOT_PERIOD = 1.0  # [s] simulated: the pilot's orders to the tugs, one a second
# A line's state after each event of mooring/events that changes it (mooring/handling.py).
STATE_AFTER = {'make_fast': 'fast', 'let_go': 'free', 'stow': 'stowed', 'released': 'free'}
CELLS = {'stowed': '-', 'free': 'free', 'parted': 'PART'}  # a line's cell but when fast
GAP = '  '  # between the table's groups of columns (one space within a group)
FOOTNOTE = ("off: her least distance off a fender's face (- compressing it); in: her speed "
            "towards the quay; push: the tugs', towards the quay (- pulling her off)\n"
            "a line: its fairlead tension when fast, '-' stowed aboard, 'free' let go, 'PART' "
            'parted; passing ship: its midship ahead (+) or astern (-) of hers')


def read_setup(paths: Sequence[str]) -> arrangement.ArrangementParams:
    """
    Read the mooring node's parameter files as the node does: the later ones on top.

    :raises ParameterError: an unreadable file, a bad value (one line).
    """
    overrides: Dict[str, object] = {}
    for path in paths[1:]:
        overrides.update(arrangement.flatten(
            read_params_file(path, arrangement.NODE_NAME)))
    return arrangement.read_setup(paths[0], overrides)


def passing_ship(setup: arrangement.ArrangementParams) -> Optional[PassingShip]:
    """Return the ship passing this one as the mooring node moves it, or None."""
    return ship_loads(setup).passing


def yaw_of(q: Sequence[float]) -> float:
    """Return the yaw [rad] of a quaternion (x, y, z, w)."""
    x, y, z, w = q
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def where_passing(passer: PassingShip, t: float, position: Sequence[float],
                  yaw: float) -> Tuple[float, float]:
    """
    Return the passing ship's stagger and separation [m] at time t [s] from the moored ship.

    Both in the moored ship's axes at `position`, heading `yaw`: stagger along its x (+
    ahead), separation to its starboard (+: the passing_ship.separation sign).
    """
    midship = passer.midship(t)
    dx, dy = midship[0] - position[0], midship[1] - position[1]
    c, s = math.cos(yaw), math.sin(yaw)
    return c * dx + s * dy, -(-s * dx + c * dy)


def split_name(name: str) -> Tuple[str, str]:
    """Return a name in two header rows: 'breast_fwd' -> ('breast', 'fwd')."""
    top, _, bottom = name.rpartition('_')
    return (top, bottom) if top else ('', name)


class Table:
    """
    The table's layout: its header and how a row's numbers are written (module docstring).

    Columns in groups (the ship, the tugs, the fenders, the lines, a passing ship); each
    column named in two rows (a name and its unit, or a name split at its last '_'), its
    cells right-aligned in its width; `t [s]` in the second row, as tools that wait for the
    table look for it.
    """

    def __init__(self, lines: Sequence[str], fenders: Sequence[str], passing: bool):
        """Lay out the columns of these lines and fenders (and a passing ship's)."""
        groups = [('', [('', 't [s]', 6)]),
                  ('ship', [('off', '[m]', 6), ('in', '[m/s]', 6)]),
                  ('tugs', [('push', '[kN]', 5)])]
        if fenders:
            groups.append(('fender load [kN]', [(*split_name(n), 4) for n in fenders]))
        groups.append(('line tension [kN]', [(*split_name(n), 4) for n in lines]))
        if passing:
            groups.append(('passing', [('ship', '[m]', 7)]))
        self.groups = [(title, [(top, bottom, max(width, len(top), len(bottom)))
                                for top, bottom, width in columns])
                       for title, columns in groups]
        self.fenders, self.passing = bool(fenders), passing

    @property
    def header(self) -> str:
        """Return the header: the groups' titles, then the columns' names in two rows."""
        titles = GAP.join(title.center(self._width(columns)) for title, columns in self.groups)
        names = [GAP.join(' '.join(column[row].rjust(column[2]) for column in columns)
                          for _, columns in self.groups) for row in (0, 1)]
        return '\n'.join(text.rstrip() for text in [titles] + names)

    @staticmethod
    def _width(columns) -> int:
        return sum(width for _, _, width in columns) + len(columns) - 1

    def row(self, t: float, off: Optional[float], speed: Optional[float],
            push: Optional[float], fenders: Sequence[Optional[float]],
            lines: Sequence[str], stagger: Optional[float] = None) -> str:
        """
        Return one row; a value not known yet is a dash.

        :param off: her distance off the fenders [m]; speed: towards the quay [m/s]; push:
            the tugs' [N]; fenders: each one's load [N]; lines: each line's cell (cell());
            stagger: a passing ship's [m].
        """
        def number(value, form):
            if value is None:
                return '-'
            text = format(value, form)
            return format(0.0, form) if float(text) == 0.0 else text  # no -0.00

        cells = [[number(t, '.1f')], [number(off, '.2f'), number(speed, '+.3f')],
                 [number(None if push is None else push / 1e3, '.0f')]]
        if self.fenders:
            cells.append([number(None if f is None else f / 1e3, '.0f') for f in fenders])
        cells.append(list(lines))
        if self.passing:
            cells.append([number(stagger, '.0f')])
        return GAP.join(' '.join(cell.rjust(column[2]) for cell, column in zip(group, columns))
                        for group, (_, columns) in zip(cells, self.groups)).rstrip()


def cell(state: str, tension: Optional[float]) -> str:
    """Return a line's cell: its tension [kN] when fast, else what it is (CELLS)."""
    if state != 'fast':
        return CELLS.get(state, state)
    return '-' if tension is None else f'{tension / 1e3:.0f}'


class BerthDemo(Node):
    """Runs /clock in sim time, the pilot and the crew, and prints the table (module)."""

    def __init__(self, setup: arrangement.ArrangementParams, plan: Berthing = Berthing(),
                 duration: float = math.inf, say=print, context=None):
        """
        Create the clock, the tugs' publisher, the crew's clients and the table's inputs.

        :param plan: the schedule and the pilot (none: the clock and the table only).
        :param duration: no row after this time [s].
        :param say: takes each row and each order's answer (a line of text).
        :param context: the rclpy context (None: the default one).
        """
        super().__init__(DEMO_NODE, context=context)
        self.setup = setup
        self.names = setup.names
        self.fender_names = [fender.name for fender in setup.fenders]
        self.passer = passing_ship(setup)
        self.table = Table(self.names, self.fender_names, self.passer is not None)
        self.duration = duration
        self.say = say
        self.orders = deque(plan.orders)
        self.pilot = Pilot(plan.pilot)
        self.tugs = any(order.kind == 'tugs' for order in plan.orders)
        self.clock_pub = self.create_publisher(Clock, '/clock', 10)
        self.tugs_pub = self.create_publisher(WrenchStamped, EXTERNAL_WRENCH, 10)
        self.tensions: Dict[str, float] = {}
        self.states = {line.name: line.params.start_state for line in setup.lines}
        self.fender_loads: Dict[str, float] = {}
        self.first_pose_ns: Optional[int] = None
        self.pose: Optional[Tuple[int, List[float], float]] = None  # stamp, position, yaw
        self.seen: Optional[Tuple[float, float]] = None  # the pilot's distance off, speed
        self.push = 0.0  # [N] the tugs' newest push towards the quay
        self._next_push = 0.0  # [s] when the pilot gives the tugs their next order
        # the outputs not in a row yet, by stamp: (position, quaternion) and (Fx, Fy)
        self._poses: Dict[int, Tuple[List[float], Tuple[float, ...]]] = {}
        self._forces: Dict[int, Tuple[float, float]] = {}
        self.next_row = 0.0  # [s] the time of the next row
        self.rows = 0
        self.answers: List[Tuple[Order, bool, str]] = []  # each order's answer, in order
        self.held = 0.0  # [s] wall time the clock waited for the mooring node (run)
        self._subs = [self.create_subscription(
            Wrench, f'{name}/{FAIRLEAD_TENSION}', self._keeper(name), 100)
            for name in self.names]
        self._subs += [self.create_subscription(
            WrenchStamped, f'{name}/{FENDER_REACTION}', self._fender_keeper(name), 100)
            for name in self.fender_names]
        self._subs.append(self.create_subscription(PoseStamped, SHIP_POSE, self._on_pose, 100))
        self._subs.append(self.create_subscription(Odometry, SHIP_ODOMETRY,
                                                   self._on_odometry, 100))
        self._subs.append(self.create_subscription(String, MOORING_NODE.events,
                                                   self._on_event, 100))
        self._subs.append(self.create_subscription(
            WrenchStamped, PASSING_WRENCH, self._on_passing, 100))
        self._commands = {(order.line, order.what): self.create_client(
            Trigger, LET_GO_ALL if order.what == 'let_go_all'
            else MOORING_NODE.line_topic(order.line, order.what))
            for order in plan.orders if order.kind == 'command'}
        self._set = None
        if any(order.kind == 'set' for order in plan.orders):
            self._set = self.create_client(SetParameters,
                                           f'{MOORING_NODE.node_name}/set_parameters')

    @property
    def time(self) -> float:
        """Return the time of the newest ship pose since the first [s] (-inf: none yet)."""
        if self.pose is None:
            return -math.inf
        return (self.pose[0] - self.first_pose_ns) / 1e9

    # -- the table's inputs ----------------------------------------------------------------

    def _keeper(self, name: str):
        def keep(msg: Wrench) -> None:
            f = msg.force
            self.tensions[name] = math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)
        return keep

    def _fender_keeper(self, name: str):
        def keep(msg: WrenchStamped) -> None:
            f = msg.wrench.force
            self.fender_loads[name] = math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)
        return keep

    def _on_event(self, msg: String) -> None:
        """Follow each line's state: its commands, releases and partings (mooring/events)."""
        try:
            event = decode_event(msg.data)
        except ValueError:
            return
        kind, line = event['event'], event.get('line', '')
        if kind == 'command' and event.get('command') == 'let_go_all':
            for name, state in self.states.items():
                if state == 'fast':
                    self.states[name] = 'free'
        elif kind in ('command', 'released') and line in self.states:
            self.states[line] = STATE_AFTER.get(event.get('command', kind),
                                                self.states[line])
        elif kind == 'parted' and line in self.states:
            self.states[line] = 'parted'

    def _on_pose(self, msg: PoseStamped) -> None:
        ns = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        if self.first_pose_ns is None:
            self.first_pose_ns = ns  # the free ship's first output: its start
        p, o = msg.pose.position, msg.pose.orientation
        q = (o.x, o.y, o.z, o.w)
        self.pose = (ns, [p.x, p.y, p.z], yaw_of(q))
        self._poses[ns] = ([p.x, p.y, p.z], q)
        self._give_orders()
        self._maybe_row(ns)

    def _on_passing(self, msg: WrenchStamped) -> None:
        ns = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        self._forces[ns] = (msg.wrench.force.x, msg.wrench.force.y)
        self._maybe_row(ns)

    def _on_odometry(self, msg: Odometry) -> None:
        """See where the ship is and how fast she comes in; the pilot's order, once a second."""
        if not self.fender_names:
            return
        pose, twist = msg.pose.pose, msg.twist.twist.linear
        q = (pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w)
        velocity = rotation_matrix(q) @ np.array([twist.x, twist.y, twist.z])  # frame_id
        position = (pose.position.x, pose.position.y, pose.position.z)
        self.seen = watch(self.setup, position, q, velocity)
        if self.first_pose_ns is None or not self.pilot.pushing:
            return
        ns = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        t = (ns - self.first_pose_ns) / 1e9
        if t >= self._next_push - 1e-9:
            self._next_push = math.floor(t + 1e-9) + PILOT_PERIOD
            self._push_tugs(self.pilot.push(t, *self.seen))

    def _push_tugs(self, push: float) -> None:
        """Publish the tugs' push towards the quay [N] on ship/external_wrench."""
        self.push = push
        msg = WrenchStamped()
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.header.frame_id = self.setup.shared.frame_id
        force = -push * quay_normal(self.setup)
        msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z = (float(f) for f in force)
        self.tugs_pub.publish(msg)

    # -- the crew ----------------------------------------------------------------------------

    def _give_orders(self) -> None:
        """Give every order due by the newest output's time."""
        while self.orders and self.orders[0].t <= self.time + 1e-9:
            self.give(self.orders.popleft())

    def give(self, order: Order) -> None:
        """Give one order now: to the tugs, or to the mooring node (its answer comes later)."""
        if order.kind == 'tugs':
            if order.what == 'push':
                self.pilot.start()
                self._next_push = self.time
                self._answer(order, True, "the pilot's tugs push her in")
            else:
                self.pilot.stop(self.time)
                self._answer(order, True, 'the tugs ease off over '
                             f'{self.pilot.settings.ease_time:g} s and stop')
            return
        if order.kind == 'command':
            future = self._commands[(order.line, order.what)].call_async(Trigger.Request())
            future.add_done_callback(lambda done: self._answered(order, done))
            return
        request = SetParameters.Request()
        request.parameters = [Parameter(f'{order.line}.{order.what}',
                                        value=order.value).to_parameter_msg()]
        future = self._set.call_async(request)
        future.add_done_callback(lambda done: self._answered(order, done))

    def _answered(self, order: Order, future) -> None:
        response = future.result()
        if response is None:
            self._answer(order, False, 'no answer')
        elif isinstance(response, Trigger.Response):
            self._answer(order, response.success, response.message)
        else:
            result = response.results[0]
            self._answer(order, result.successful, 'set' if result.successful
                         else f'refused: {result.reason}')

    def _answer(self, order: Order, ok: bool, text: str) -> None:
        """Say an order's answer: `T  > ORDER: ANSWER` (T: when it was given)."""
        self.answers.append((order, ok, text))
        what = order.text.split(None, 1)[1]
        self.say(f'{max(self.time, order.t):6.1f}  > {what}: {text}')

    # -- the table -------------------------------------------------------------------------

    def _maybe_row(self, ns: int) -> None:
        """Say the row of the output stamped ns if it starts a new second and is complete."""
        if self.first_pose_ns is None:
            return
        t = (ns - self.first_pose_ns) / 1e9
        pose = self._poses.get(ns)
        force = self._forces.get(ns)
        if (t < self.next_row - 1e-9 or t > self.duration + 1e-9 or pose is None
                or (self.passer is not None and force is None)):
            if len(self._poses) + len(self._forces) > 400:  # outputs never completed
                self._poses.clear()
                self._forces.clear()
            return
        self.say(self.row(t, pose))
        self.rows += 1
        self.next_row = math.floor(t + 1e-9) + 1.0
        self._poses = {k: v for k, v in self._poses.items() if k > ns}
        self._forces = {k: v for k, v in self._forces.items() if k > ns}

    def row(self, t: float, pose: Tuple[List[float], Tuple[float, ...]]) -> str:
        """Return the table row of the output at t [s] with the ship at `pose` (module)."""
        position, q = pose
        off = speed = None
        if self.fender_names:
            off = watch(self.setup, position, q, np.zeros(3))[0]
            speed = None if self.seen is None else self.seen[1]
        stagger = None
        if self.passer is not None:
            stagger = where_passing(self.passer, t, position, yaw_of(q))[0]
        lines = [cell(self.states[name], self.tensions.get(name)) for name in self.names]
        return self.table.row(t, off, speed, self.push if self.tugs else None,
                              [self.fender_loads.get(name) for name in self.fender_names],
                              lines, stagger)

    # -- the clock -------------------------------------------------------------------------

    def wait_for_mooring(self) -> bool:
        """Wait until the mooring node publishes what the table reads and answers the crew."""
        end = time.monotonic() + START_TIMEOUT
        topics = [SHIP_POSE] + [f'{name}/{FAIRLEAD_TENSION}' for name in self.names]
        clients = list(self._commands.values()) + ([self._set] if self._set else [])
        while time.monotonic() < end:
            if (self.clock_pub.get_subscription_count()
                    and all(self.count_publishers(topic) for topic in topics)
                    and all(client.service_is_ready() for client in clients)):
                # the node may see these subscriptions a little after they see it (DDS
                # discovery is not symmetric): its first outputs would reach nobody
                settled = time.monotonic() + DISCOVERY_SETTLE
                while time.monotonic() < settled:
                    rclpy.spin_once(self, timeout_sec=0.05)
                return True
            rclpy.spin_once(self, timeout_sec=0.1)
        return False

    def publish_clock(self, t: float) -> None:
        """Publish /clock at the demo's sim time t [s] (CLOCK_ORIGIN + t)."""
        sec, nanosec = divmod(round((CLOCK_ORIGIN + t) * 1e9), 1_000_000_000)
        clock = Clock()
        clock.clock.sec, clock.clock.nanosec = sec, nanosec
        self.clock_pub.publish(clock)

    def ahead(self, t: float) -> float:
        """Return how far the clock at t [s] is ahead of the ship's newest output [s]."""
        newest = CLOCK_ORIGIN if self.pose is None else self.pose[0] / 1e9
        return CLOCK_ORIGIN + t - newest

    def run(self, duration: float, speed: float) -> None:
        """
        Publish /clock at `speed` until the ship's outputs reach `duration` (or GRACE s past it).

        The clock holds back whenever it is more than MAX_AHEAD s of sim time ahead of the
        ship's newest output (before the first, of the free ship's start at t = 0: the lines'
        lengths for their pretensions take a moment): a node that falls MAX_LAG behind the
        clock skips ahead and restarts the ropes at rest, and on a busy machine the demo had
        better run slower than that. Holding back, it still creeps on, a tick every CREEP s
        of wall time: the node steps in its timer, which only a moving clock fires, and each
        step it publishes lets the clock on. Up to MAX_CREEP ahead: there, only a tick every
        STALLED_CREEP s, for outputs that never reach the demo (the node may match its
        subscriptions late) without taking the node near MAX_LAG. `held` adds up the wall
        time the clock lost so [s]. Gives up when the node answers nothing for
        START_TIMEOUT s.
        """
        start = progress = published = time.monotonic()
        newest = None
        tick = 0
        while True:
            t = tick / CLOCK_RATE
            if t > duration and (self.time >= duration or t > duration + GRACE):
                end = time.monotonic() + 0.3  # the last output's other messages
                while time.monotonic() < end:
                    rclpy.spin_once(self, timeout_sec=0.05)
                return
            now = time.monotonic()
            if self.pose is not newest:
                newest, progress = self.pose, now
            ahead = self.ahead(t)
            if ahead > MAX_AHEAD:
                if now - progress > START_TIMEOUT:
                    return
                if now - published >= (CREEP if ahead < MAX_CREEP else STALLED_CREEP):
                    self.publish_clock(t)
                    tick += 1
                    published = now
                else:
                    rclpy.spin_once(self, timeout_sec=CREEP / 4)
                # the clock goes on from here at `speed`, without a burst to catch up
                late = time.monotonic() - (start + tick / CLOCK_RATE / speed)
                if late > 0.0:
                    start += late
                    self.held += late
                continue
            wait = start + t / speed - now
            if wait > 0.0:
                rclpy.spin_once(self, timeout_sec=wait)  # one callback, or the wait
                continue
            self.publish_clock(t)
            tick += 1
            published = time.monotonic()


def main(argv=None) -> int:
    """Run the clock, pilot and crew for --duration simulated seconds; 0 when all went."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--params', action='append', required=True,
                        help="the mooring node's parameter file (repeatable: the later on top)")
    parser.add_argument('--speed', type=float, default=2.0, help='sim seconds per wall second')
    parser.add_argument('--duration', type=float, default=None,
                        help='sim seconds (default: berth_demo.duration, else 200)')
    args = parser.parse_args(argv)
    bad = not_positive(args, ('speed', 'duration'))
    if bad:
        print(f'berth demo: {bad}', file=sys.stderr)
        return 2
    files = ' + '.join(args.params)
    try:
        setup = read_setup(args.params)
        if setup.single:
            raise ParameterError(f'{files}: no mooring node parameters (mooring: '
                                 'ros__parameters: lines: ...)')
        if not setup.ship.free:
            raise ParameterError(f"{files}: ship_mode is '{setup.ship.mode}': the demo's ship "
                                 'moves by itself: set ship_mode: free')
        plan = read_berthing(args.params, setup)
    except ParameterError as e:
        print(f'berth demo: {e}', file=sys.stderr)
        return 2
    duration = args.duration or plan.duration or DEFAULT_DURATION
    use_quick_discovery()
    rclpy.init()
    node = BerthDemo(setup, plan, duration, lambda row: print(row, flush=True))
    try:
        if not node.wait_for_mooring():
            print(f'berth demo: no mooring node publishing {SHIP_POSE} (ship_mode: free)'
                  + (' and answering its line-handling services' if node._commands else '')
                  + f' within {START_TIMEOUT:g} s', file=sys.stderr)
            return 1
        print(node.table.header, flush=True)
        node.run(duration, args.speed)
        print(FOOTNOTE, flush=True)
        if node.held > 1.0:
            print(f'berth demo: the clock waited {node.held:.1f} s in all for the mooring node '
                  f'to keep up (a busy machine): slower than {args.speed:g}x', flush=True)
        if node.time < duration:
            print(f"berth demo: the ship's outputs reached t = {node.time:.1f} s only, not "
                  f'{duration:g} s: the mooring node fell behind the clock', file=sys.stderr)
        refused = [order.text for order, ok, _ in node.answers if not ok]
        if refused:
            print(f'berth demo: {len(refused)} order(s) refused: {"; ".join(refused)}',
                  file=sys.stderr)
        return 0 if node.rows and not refused else 1
    except KeyboardInterrupt:
        return 130
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    raise SystemExit(main())
