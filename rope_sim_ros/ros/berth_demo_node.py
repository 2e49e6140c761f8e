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
The berth demo's clock and its instructor's table, beside a mooring node (`make demo`).

The mooring node (ship_mode: free, use_sim_time) moves the ship itself, under its lines, its
fenders and a passing ship (passing_ship.*). This node publishes /clock only: sim time
running at --speed times the wall clock, from CLOCK_ORIGIN s (slower while the mooring node
cannot keep up: BerthDemo.run). It prints one row per simulated second of the ship's
outputs, at the first output of each second (t: its time since the free ship's start, its
first pose): where the passing ship is then (its stagger: its midship's distance ahead of
the moored ship's, + ahead, - astern; its separation: the two centrelines apart; both in the
moored ship's axes where it is then); the ship's surge and sway [m] and yaw [deg] from its
start pose (ship.start_position, ship.start_yaw; surge and sway in that pose's axes: x
forward, y to port); the passing ship's surge and sway force on it
(ship/passing_ship_wrench, body axes); and the most loaded line (the newest tensions) with
its tension and its share of its MBL. The passing ship's place comes from the same
parameters the mooring node reads (--params, as many files as the node's --params-file, the
later ones on top). The clock stops once the ship's outputs reached --duration simulated
seconds.

    python -m rope_sim_ros.ros.berth_demo_node --params config/berth.yaml \
        --params config/berth_demo.yaml [--speed 2] [--duration 200]
"""

import argparse
import math
import sys
import time
from typing import Dict, List, Optional, Sequence, Tuple

from geometry_msgs.msg import PoseStamped, Wrench, WrenchStamped
import rclpy
from rclpy.node import Node
from rosgraph_msgs.msg import Clock

from ..messages.topics import FAIRLEAD_TENSION, PASSING_WRENCH, SHIP_POSE
from ..model.ship.loads import PassingShip
from ..mooring.driver import MAX_LAG
from ..mooring.ship import ship_loads
from ..params import arrangement
from ..params.files import read_params_file
from ..params.materials import load_materials
from ..params.table import ParameterError

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
# The table: (group, [(column, width)]), its numbers right-aligned in those widths.
COLUMNS = (('', [('t [s]', 7)]),
           ('passing ship (*)', [('stagger [m]', 12), ('separ. [m]', 11)]),
           ('moored ship (**)', [('surge [m]', 11), ('sway [m]', 8), ('yaw [deg]', 9)]),
           ('passing ship force', [('Fx [kN]', 9), ('Fy [kN]', 9)]),
           ('most loaded line', [('name', -12), ('T [kN]', 7), ('% MBL', 6)]))
GAP = '  '
HEADER = '\n'.join([
    GAP.join(group.center(sum(abs(w) for _, w in cols) + len(cols) - 1)
             for group, cols in COLUMNS).rstrip(),
    GAP.join(' '.join(name.ljust(-w) if w < 0 else name.rjust(w) for name, w in cols)
             for _, cols in COLUMNS)])
FOOTNOTE = ("(*) its midship ahead (+) or astern (-) of the moored ship's, and the two "
            'centrelines apart\n(**) from its start pose: surge + ahead, sway + to port, '
            'yaw + bow to port; forces in its axes')


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


def offsets(start: Sequence[float], start_yaw: float, position: Sequence[float],
            yaw: float) -> Tuple[float, float, float]:
    """Return surge, sway [m] (in the start pose's axes) and yaw [deg] from the start pose."""
    dx, dy = position[0] - start[0], position[1] - start[1]
    c, s = math.cos(start_yaw), math.sin(start_yaw)
    turn = math.remainder(yaw - start_yaw, 2.0 * math.pi)
    return c * dx + s * dy, -s * dx + c * dy, math.degrees(turn)


def format_row(t: float, where: Optional[Tuple[float, float]],
               moved: Optional[Tuple[float, float, float]],
               force: Optional[Tuple[float, float]],
               line: Optional[Tuple[str, float, float]]) -> str:
    """
    Return one table row (HEADER's columns); a value not received yet is a dash.

    :param where: stagger, separation [m]; moved: surge, sway [m], yaw [deg]; force: Fx,
        Fy [N]; line: the most loaded line's name, tension [N] and share of its MBL [0-1].
    """
    def numbers(values, formats):
        if values is None:
            return ' '.join('-'.rjust(len(format(0.0, f))) for f in formats)
        return ' '.join(format(v, f) for v, f in zip(values, formats))

    force_kn = None if force is None else (force[0] / 1e3, force[1] / 1e3)
    last = '-'.ljust(12) if line is None else (
        f'{line[0]:<12} {line[1] / 1e3:7.1f} {100.0 * line[2]:6.1f}')
    return GAP.join([f'{t:7.1f}', numbers(where, ('12.1f', '11.1f')),
                     numbers(moved, ('+11.3f', '+8.3f', '+9.3f')),
                     numbers(force_kn, ('+9.1f', '+9.1f')), last]).rstrip()


class BerthDemo(Node):
    """Runs /clock in sim time and prints a row a simulated second of the ship's outputs."""

    def __init__(self, setup: arrangement.ArrangementParams, duration: float = math.inf,
                 say=print, context=None):
        """
        Create the clock publisher and the subscriptions the table reads.

        :param duration: no row after this time [s].
        :param say: takes each row (a line of text).
        :param context: the rclpy context (None: the default one).
        """
        super().__init__('berth_demo', context=context)
        library = load_materials()
        self.setup = setup
        self.names = setup.names
        self.mbl = {line.name: library.properties(line.params.material,
                                                  line.params.diameter).mbl
                    for line in setup.lines}
        self.passer = passing_ship(setup)
        self.duration = duration
        self.say = say
        self.clock_pub = self.create_publisher(Clock, '/clock', 10)
        self.tensions: Dict[str, float] = {}
        self.first_pose_ns: Optional[int] = None
        self.pose: Optional[Tuple[int, List[float], float]] = None  # stamp, position, yaw
        # the outputs not in a row yet, by stamp: (position, yaw) and (Fx, Fy)
        self._poses: Dict[int, Tuple[List[float], float]] = {}
        self._forces: Dict[int, Tuple[float, float]] = {}
        self.next_row = 0.0  # [s] the time of the next row
        self.rows = 0
        self.held = 0.0  # [s] wall time the clock waited for the mooring node (run)
        self._subs = [self.create_subscription(
            Wrench, f'{name}/{FAIRLEAD_TENSION}', self._keeper(name), 100)
            for name in self.names]
        self._subs.append(self.create_subscription(PoseStamped, SHIP_POSE, self._on_pose, 100))
        self._subs.append(self.create_subscription(
            WrenchStamped, PASSING_WRENCH, self._on_passing, 100))

    @property
    def time(self) -> float:
        """Return the time of the newest ship pose since the first [s] (-inf: none yet)."""
        if self.pose is None:
            return -math.inf
        return (self.pose[0] - self.first_pose_ns) / 1e9

    def _keeper(self, name: str):
        def keep(msg: Wrench) -> None:
            f = msg.force
            self.tensions[name] = math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)
        return keep

    def _on_pose(self, msg: PoseStamped) -> None:
        ns = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        if self.first_pose_ns is None:
            self.first_pose_ns = ns  # the free ship's first output: its start
        p, o = msg.pose.position, msg.pose.orientation
        self.pose = (ns, [p.x, p.y, p.z], yaw_of((o.x, o.y, o.z, o.w)))
        self._poses[ns] = self.pose[1:]
        self._maybe_row(ns)

    def _on_passing(self, msg: WrenchStamped) -> None:
        ns = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        self._forces[ns] = (msg.wrench.force.x, msg.wrench.force.y)
        self._maybe_row(ns)

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
        self.say(self.row(t, pose, force))
        self.rows += 1
        self.next_row = math.floor(t + 1e-9) + 1.0
        self._poses = {k: v for k, v in self._poses.items() if k > ns}
        self._forces = {k: v for k, v in self._forces.items() if k > ns}

    def wait_for_mooring(self) -> bool:
        """Wait until the mooring node listens to /clock and publishes the ship's pose."""
        end = time.monotonic() + START_TIMEOUT
        while time.monotonic() < end:
            if (self.clock_pub.get_subscription_count() and self.count_publishers(SHIP_POSE)
                    and all(self.count_publishers(f'{name}/{FAIRLEAD_TENSION}')
                            for name in self.names)):
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

    def row(self, t: float, pose: Tuple[List[float], float],
            force: Optional[Tuple[float, float]]) -> str:
        """
        Return the table row of the output at t [s] (see the module docstring).

        :param pose: the ship's position and yaw then; force: the passing ship's Fx, Fy.
        """
        ship = self.setup.ship
        position, yaw = pose
        where = None
        if self.passer is not None:
            where = where_passing(self.passer, t, position, yaw)
        line = None
        if self.tensions:
            name = max(self.tensions, key=lambda n: self.tensions[n] / self.mbl[n])
            line = (name, self.tensions[name], self.tensions[name] / self.mbl[name])
        return format_row(t, where, offsets(ship.start_position, ship.start_yaw, position, yaw),
                          force, line)

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
    """Run the clock for --duration simulated seconds; 0 when the mooring node answered."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--params', action='append', required=True,
                        help="the mooring node's parameter file (repeatable: the later on top)")
    parser.add_argument('--speed', type=float, default=2.0, help='sim seconds per wall second')
    parser.add_argument('--duration', type=float, default=200.0, help='sim seconds')
    args = parser.parse_args(argv)
    for name in ('speed', 'duration'):
        value = getattr(args, name)
        if not (math.isfinite(value) and value > 0.0):
            print(f'berth demo: --{name} {value!r} is not allowed: must be a number > 0',
                  file=sys.stderr)
            return 2
    try:
        setup = read_setup(args.params)
    except ParameterError as e:
        print(f'berth demo: {e}', file=sys.stderr)
        return 2
    files = ' + '.join(args.params)
    if setup.single:
        print(f'berth demo: {files}: no mooring node parameters (mooring: ros__parameters: '
              'lines: ...)', file=sys.stderr)
        return 2
    if not setup.ship.free:
        print(f"berth demo: {files}: ship_mode is '{setup.ship.mode}': the demo's ship moves "
              'by itself: set ship_mode: free', file=sys.stderr)
        return 2
    rclpy.init()
    node = BerthDemo(setup, args.duration, lambda row: print(row, flush=True))
    try:
        if not node.wait_for_mooring():
            print(f'berth demo: no mooring node publishing {SHIP_POSE} (ship_mode: free) '
                  f'within {START_TIMEOUT:g} s', file=sys.stderr)
            return 1
        print(HEADER, flush=True)
        node.run(args.duration, args.speed)
        print(FOOTNOTE, flush=True)
        if node.held > 1.0:
            print(f'berth demo: the clock waited {node.held:.1f} s in all for the mooring node '
                  f'to keep up (a busy machine): slower than {args.speed:g}x', flush=True)
        if node.time < args.duration:
            print(f"berth demo: the ship's outputs reached t = {node.time:.1f} s only, not "
                  f'{args.duration:g} s: the mooring node fell behind the clock',
                  file=sys.stderr)
        return 0 if node.rows else 1
    except KeyboardInterrupt:
        return 130
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    raise SystemExit(main())
