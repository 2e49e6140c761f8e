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

"""Recorded messages as rclpy message objects and back, for any installed type."""

from typing import Any

from rclpy.serialization import deserialize_message, serialize_message

from .schema import message_class
from ..bag.reader import BagMessage


def serialize(message: Any) -> bytes:
    """Return an rclpy message object as CDR bytes (rclpy's serialize_message)."""
    return serialize_message(message)


def deserialize(message: BagMessage) -> Any:
    """
    Turn a recorded BagMessage back into its rclpy message object.

    :param message: A record from rope_sim_ros.bag.read_messages().

    :returns: The message, e.g. a geometry_msgs.msg.PoseStamped.

    :raises BagError: the type has no Python class here.
    """
    return deserialize_message(message.data, message_class(message.type_name))
