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
bag_replay: play a bag's input poses with their timing, and a /clock from the bag.

``bag_replay BAG [--rate R] [--loop]`` publishes the recorded fairlead/pose and bollard/pose
messages (byte for byte, under their recorded topic names) at their log times, scaled by
the rate, and publishes /clock (rosgraph_msgs/Clock) with the bag time: at every message,
after it, and at ``--clock-rate`` Hz in between. So ``mooring_line`` with use_sim_time:=true
re-runs the recording::

    ros2 run rope_sim_ros mooring_line --ros-args -p use_sim_time:=true
    ros2 run rope_sim_ros bag_replay run1 --rate 1.0

Before playing it waits (at most ``--wait`` seconds) until every topic it plays and /clock
have a subscriber, then ``--delay`` seconds more: DDS matches the two sides of a connection
one after the other, and what is sent before the subscriber's side has matched is lost (a
node on a loaded machine missed the first 0.32 s of poses). Remap topics with the usual
``--ros-args -r /fairlead/pose:=/ship/line1/fairlead/pose``.
"""

import argparse
import sys
import time
from typing import List, Optional

import rclpy
from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rosgraph_msgs.msg import Clock as ClockMsg

from .discovery import use_quick_discovery
from ..bag import bag_info, BagError, read_messages
from ..ros2bag import message_class

NODE_NAME = 'bag_replay'
INPUT_SUFFIXES = ('/fairlead/pose', '/bollard/pose')


def input_topics(path) -> List[str]:
    """
    Return the bag's input topics (names ending in fairlead/pose or bollard/pose), sorted.

    :raises BagError: path is not a readable bag.
    """
    return sorted(name for name in bag_info(path).topics if name.endswith(INPUT_SUFFIXES))


def _ns_to_clock(ns: int) -> ClockMsg:
    msg = ClockMsg()
    msg.clock.sec, msg.clock.nanosec = divmod(int(ns), 1_000_000_000)
    return msg


class BagReplay(Node):
    """Publishes a bag's input messages at their recorded timing, with a /clock."""

    # After the last message, keep the node alive this long [s] so reliable delivery ends.
    LINGER = 0.5

    def __init__(self, path: str, rate: float = 1.0, loop: bool = False,
                 clock_rate: float = 100.0, wait: float = 5.0,
                 topics: Optional[List[str]] = None, delay: float = 0.5, **kwargs) -> None:
        """
        Read the bag and create one publisher per played topic and /clock.

        :param path: the bag directory (or .mcap file).
        :param rate: playback speed: 2.0 plays twice as fast.
        :param loop: start again from the beginning after the end.
        :param clock_rate: /clock messages per wall second between bag messages.
        :param wait: the longest wait [s] for subscribers (played topics, /clock) before
            playing.
        :param topics: topics to play; None = the input topics (fairlead/pose, bollard/pose).
        :param delay: how long [s] to wait after the subscribers appeared before playing.
        :raises BagError: unreadable bag, or nothing to play.
        :raises ValueError: a non-positive rate or clock rate, or a negative delay.
        """
        super().__init__(NODE_NAME, **kwargs)
        if not rate > 0.0 or not clock_rate > 0.0:
            raise ValueError(f'--rate {rate} and --clock-rate {clock_rate} must be > 0')
        if not 0.0 <= delay < float('inf'):
            raise ValueError(f'--delay {delay} must be >= 0 seconds')
        info = bag_info(path)
        wanted = input_topics(path) if topics is None else list(topics)
        missing = [t for t in wanted if t not in info.topics]
        if missing:
            raise BagError(f'bag {path} has no topic {", ".join(missing)}; it has '
                           f'{", ".join(sorted(info.topics))}')
        self._messages = [(m.log_time_ns, m.topic, m.data)
                          for m in read_messages(path, wanted)]
        if not self._messages:
            raise BagError(f'bag {path} has no messages on {", ".join(wanted) or "any input"}'
                           ' topic to replay')
        qos = QoSProfile(depth=100)
        self._players = {
            name: self.create_publisher(message_class(info.topics[name].type_name), name, qos)
            for name in wanted}
        self._clock_publisher = self.create_publisher(ClockMsg, '/clock', qos)
        self.rate = rate
        self.loop = loop
        self.wait = wait
        self.delay = delay
        self._found_at: Optional[float] = None  # when the subscribers were found
        self._start_ns = self._messages[0][0]
        self._end_ns = self._messages[-1][0]
        self._next = 0
        self._wall_start: Optional[float] = None
        self._created = time.monotonic()
        self._done_at: Optional[float] = None
        self.loops = 0
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._timer = self.create_timer(1.0 / clock_rate, self._on_tick, clock=steady)
        self.get_logger().info(
            f'{len(self._messages)} messages on {", ".join(wanted)}, '
            f'{(self._end_ns - self._start_ns) / 1e9:.3f} s of bag time at rate {rate:g}'
            + (', looping' if loop else ''))

    @property
    def finished(self) -> bool:
        """Return True once everything was played (and delivery had time to end)."""
        return (self._done_at is not None
                and time.monotonic() - self._done_at >= self.LINGER)

    def _subscribed(self) -> bool:
        publishers = [*self._players.values(), self._clock_publisher]
        return all(p.get_subscription_count() > 0 for p in publishers)

    def _on_tick(self) -> None:
        now = time.monotonic()
        if self._done_at is not None:
            return
        if self._wall_start is None:
            if self._found_at is None:
                if not self._subscribed() and now - self._created < self.wait:
                    return
                if not self._subscribed():
                    self.get_logger().warning(
                        f'not every played topic and /clock has a subscriber after '
                        f'{self.wait:g} s: playing anyway')
                self._found_at = now
            if now - self._found_at < self.delay:
                return
            self._wall_start = now
            self._clock_publisher.publish(_ns_to_clock(self._start_ns))
        bag_now = self._start_ns + int((now - self._wall_start) * self.rate * 1e9)
        while self._next < len(self._messages) and self._messages[self._next][0] <= bag_now:
            log_ns, topic, data = self._messages[self._next]
            self._players[topic].publish(data)
            self._next += 1
            if (self._next == len(self._messages)
                    or self._messages[self._next][0] != log_ns):
                self._clock_publisher.publish(_ns_to_clock(log_ns))
        self._clock_publisher.publish(_ns_to_clock(min(bag_now, self._end_ns)))
        if self._next >= len(self._messages) and bag_now >= self._end_ns:
            self.loops += 1
            if self.loop:
                self._next = 0
                self._wall_start = now
                self.get_logger().info(f'end of bag: loop {self.loops + 1}')
            else:
                self._done_at = now
                self.get_logger().info('end of bag')


def parse_args(argv: List[str]) -> argparse.Namespace:
    """Parse bag_replay's own arguments (ROS arguments removed)."""
    parser = argparse.ArgumentParser(
        prog=NODE_NAME, description='Publish the input poses of a bag with their recorded '
        'timing and a /clock, so mooring_line with use_sim_time:=true re-runs the recording.')
    parser.add_argument('bag', metavar='BAG', help='bag directory (or .mcap file)')
    parser.add_argument('--rate', type=float, default=1.0, metavar='R',
                        help='playback speed factor (default 1.0)')
    parser.add_argument('--loop', action='store_true', help='play again from the start')
    parser.add_argument('--clock-rate', type=float, default=100.0, metavar='HZ',
                        help='/clock messages per second between bag messages (default 100)')
    parser.add_argument('--wait', type=float, default=5.0, metavar='S',
                        help='wait up to S seconds for subscribers before playing (default 5)')
    parser.add_argument('--delay', type=float, default=0.5, metavar='S',
                        help='then wait S seconds more, until the subscribers have matched '
                        'too (default 0.5)')
    parser.add_argument('--topics', nargs='+', metavar='TOPIC',
                        help='topics to play (default: the fairlead/pose and bollard/pose '
                        'topics)')
    return parser.parse_args(argv)


def main(args=None) -> int:
    """Play the bag until its end (or Ctrl-C); exit code 2 for a bad bag or argument."""
    argv = sys.argv if args is None else args
    options = parse_args(rclpy.utilities.remove_ros_args(argv)[1:])
    use_quick_discovery()
    rclpy.init(args=argv)
    try:
        node = BagReplay(options.bag, options.rate, options.loop, options.clock_rate,
                         options.wait, options.topics, options.delay)
    except (BagError, ValueError) as e:
        print(f'{NODE_NAME}: error: {e}', file=sys.stderr)
        rclpy.try_shutdown()
        return 2
    except KeyboardInterrupt:
        rclpy.try_shutdown()
        return 0
    try:
        while rclpy.ok() and not node.finished:
            rclpy.spin_once(node, timeout_sec=0.1)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
