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
rosbag2-compatible (ROS 2 Jazzy, MCAP storage) bag writing, reading and recovery.

BagWriter records CDR bytes (cdr.py encodes and decodes the types we record) from a
background thread to `<dir>/<dir name>_0.mcap` and writes `<dir>/metadata.yaml` at close;
read_messages() reads a bag back (also one whose recorder was killed), bag_info()
summarises it and recover() makes a killed recording a complete bag again.

This package imports no ROS: the offline commands write and read bags without it. Message
objects, QoS profiles and types beyond those in definitions.py are rope_sim_ros.ros2bag's.
"""

from .errors import BagError
from .reader import bag_info
from .reader import BagInfo
from .reader import BagMessage
from .reader import read_messages
from .reader import TopicInfo
from .recover import recover
from .writer import BagWriter

__all__ = [
    'BagError',
    'BagInfo',
    'BagMessage',
    'BagWriter',
    'bag_info',
    'read_messages',
    'recover',
    'TopicInfo',
]
