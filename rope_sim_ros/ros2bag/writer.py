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

"""RosBagWriter: bag.BagWriter for message objects, rclpy QoS and any installed type."""

from typing import Any, Dict, Optional, Tuple

from . import schema
from .messages import serialize
from .qos import qos_profiles, QosSpec
from ..bag.errors import BagError
from ..bag.writer import BagWriter


class RosBagWriter(BagWriter):
    """
    A BagWriter that also takes rclpy message objects and QoSProfile objects.

    add_topic() accepts any message type installed in the ament index (the schema text and
    type hash are read as rosbag2 reads them) and rclpy QoS profiles; write() accepts the
    topic's message objects, serialised here, as well as CDR bytes::

        with RosBagWriter('run1') as bag:
            bag.add_topic('/fairlead/tension', 'geometry_msgs/msg/Wrench', QoSProfile(depth=5))
            bag.write('/fairlead/tension', wrench_message, now_ns)
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        """Create the bag as BagWriter does (same arguments)."""
        # Topic name -> message class, filled by add_topic().
        self._classes: Dict[str, type] = {}
        super().__init__(*args, **kwargs)

    def add_topic(self, name: str, type_name: str, qos: QosSpec = None) -> None:
        """
        Register a topic before writing to it (again with the same type: no effect).

        :param name: Fully qualified topic name, e.g. '/mooring_line/fairlead/tension'.
        :param type_name: Message type, 'pkg/msg/Type', with an installed Python class.
        :param qos: The publisher's offered QoSProfile(s) (or rosbag2 dicts); None for
            rclpy's default.

        :raises BagError: as BagWriter.add_topic, or the type has no Python class.
        """
        cls = schema.message_class(type_name)
        super().add_topic(name, type_name, qos)
        self._classes.setdefault(name, cls)

    def _describe(self, type_name: str) -> Tuple[str, str]:
        return schema.message_definition(type_name), schema.type_hash(type_name)

    def _qos_yaml(self, qos: Any) -> str:
        return super()._qos_yaml(qos_profiles(qos))

    def write(
        self,
        topic: str,
        message: Any,
        log_time_ns: int,
        publish_time_ns: Optional[int] = None,
    ) -> bool:
        """
        Queue one message for recording; never blocks on the disk.

        :param topic: A topic registered with add_topic().
        :param message: The message object of the topic's type, or its CDR bytes.
        :param log_time_ns: Receive/record time [ns] (MCAP log_time).
        :param publish_time_ns: Send time [ns] (MCAP publish_time); log_time_ns if None.

        :returns: As BagWriter.write().

        :raises BagError: the topic was not added or the message is not of its type.
        """
        type_name = self.topic_type(topic)
        if not isinstance(message, (bytes, bytearray, memoryview)):
            cls = self._classes[topic]
            if type(message) is not cls:
                raise BagError(
                    f'bag {self.path}: topic {topic} records {type_name} '
                    f'({cls.__module__}.{cls.__name__}), '
                    f'got {type(message).__module__}.{type(message).__name__}')
            message = serialize(message)
        return super().write(topic, message, log_time_ns, publish_time_ns)
