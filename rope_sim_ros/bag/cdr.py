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
CDR bytes of the three message types we record, with zeroed padding.

rclpy's serialize_message leaves padding bytes uninitialised, so equal messages could be
stored as different bytes (re-simulation promises byte-identical payloads), and building N+1
Pose objects costs more than a short rope's steps. These write the same layout (XCDR1,
little endian) from plain numbers.
"""

import struct
from typing import Sequence

import numpy as np

# encapsulation header, as rclpy's serialize_message writes it
CDR_LE = b'\x00\x01\x00\x00'


def _pad(body: bytes, alignment: int) -> bytes:
    # CDR aligns from the end of the encapsulation header
    return body + bytes(-len(body) % alignment)


def _header(sec: int, nanosec: int, frame_id: str) -> bytes:
    name = frame_id.encode('utf-8') + b'\x00'
    return struct.pack('<iII', sec, nanosec, len(name)) + name


def pose_stamped(sec: int, nanosec: int, frame_id: str, pose: Sequence[float]) -> bytes:
    """
    Return a geometry_msgs/PoseStamped as CDR bytes.

    :param pose: x, y, z, qx, qy, qz, qw.
    """
    return CDR_LE + _pad(_header(sec, nanosec, frame_id), 8) + struct.pack('<7d', *pose)


def pose_array(sec: int, nanosec: int, frame_id: str, poses: np.ndarray) -> bytes:
    """
    Return a geometry_msgs/PoseArray as CDR bytes.

    :param poses: (n, 7) rows of x, y, z, qx, qy, qz, qw.
    """
    poses = np.asarray(poses, dtype='<f8').reshape(-1, 7)
    body = _pad(_pad(_header(sec, nanosec, frame_id), 4) + struct.pack('<I', len(poses)), 8)
    return CDR_LE + body + np.ascontiguousarray(poses).tobytes()


def wrench(force: Sequence[float], torque: Sequence[float]) -> bytes:
    """Return a geometry_msgs/Wrench as CDR bytes (six doubles, no padding)."""
    return CDR_LE + struct.pack('<6d', *force, *torque)
