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
The ROS side of bags: rclpy message objects, rclpy QoS profiles and any installed type.

rope_sim_ros.bag writes and reads rosbag2 bags of CDR bytes without ROS; this package sits
above it, below the nodes: RosBagWriter records message objects (serialised by rclpy) with
the QoS profiles rclpy reports, deserialize() turns a recorded message into its rclpy
object, and schema reads definitions, hashes and classes of any installed message type.
The offline commands never import it.
"""

from .messages import deserialize
from .messages import serialize
from .qos import qos_profiles
from .qos import qos_to_dict
from .qos import QosSpec
from .schema import message_class
from .writer import RosBagWriter

__all__ = [
    'QosSpec',
    'RosBagWriter',
    'deserialize',
    'message_class',
    'qos_profiles',
    'qos_to_dict',
    'serialize',
]
