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


"""Output publishers that know whether anyone takes them (the nodes build nothing for nobody)."""

from typing import Dict, Iterable, List, Optional

from rclpy.event_handler import PublisherEventCallbacks, QoSPublisherMatchedInfo
from rclpy.node import Node

from .recorder import Recorder


class OutputPublishers:
    """
    A node's output publishers, each with its subscribers counted from its matched events.

    A node builds an output only when it is taken: subscribed to, or recorded. Asking each
    publisher for its subscription count at every output cost 2 % of a core with the 16-line
    mooring node's 98 publishers at 100 Hz; the matched events keep the counts instead, and
    on the events executor an idle event handler costs nothing.
    """

    def __init__(self, node: Node):
        """Count the subscribers of the output publishers created here for `node`."""
        self._node = node
        self._subscribers: Dict[str, int] = {}  # by topic, as the matched events said
        self._matches = 0  # matched events so far: the counts changed when this did
        self._among: Optional[tuple] = None  # taken_among's last (topics, key, answer)

    def create(self, cls, topic: str, qos, default_events: bool = True):
        """
        Create and return the publisher of `topic` (relative name) and count its subscribers.

        :param default_events: keep rclpy's default incompatible-QoS handler; rclpy's Python
            executor walks every handler at every wake-up, which a node with many publishers
            may not want to pay for.
        """
        self._subscribers[topic] = 0

        def matched(info: QoSPublisherMatchedInfo) -> None:
            self._subscribers[topic] = info.current_count
            self._matches += 1

        return self._node.create_publisher(
            cls, topic, qos, event_callbacks=PublisherEventCallbacks(
                matched=matched, use_default_callbacks=default_events))

    def subscribed(self, topic: str) -> bool:
        """Tell whether `topic` has a subscriber now (as its matched events said)."""
        return self._subscribers[topic] > 0

    def taken(self, topic: str, recorder: Optional[Recorder]) -> bool:
        """Tell whether an output of `topic` is to be built: subscribed to, or recorded."""
        return recorder is not None and recorder.recording or self.subscribed(topic)

    def taken_among(self, topics: Iterable[str], recorder: Optional[Recorder]) -> List[str]:
        """
        Return the topics of `topics` that are taken now, in their order (see taken).

        The answer is kept until a subscriber comes or goes or the recording starts or
        stops: the 16-line mooring node asked for its 96 line topics at every output.
        """
        key = (recorder is not None and recorder.recording, self._matches)
        if self._among is None or self._among[0] is not topics or self._among[1] != key:
            self._among = (topics, key, [topic for topic in topics
                                         if self.taken(topic, recorder)])
        return self._among[2]
