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
CDR bytes of the message types we record, and back to plain numbers, without ROS.

rclpy's serialize_message leaves padding bytes uninitialised, so equal messages could be
stored as different bytes (re-simulation promises byte-identical payloads), and building N+1
Pose objects costs more than a short rope's steps. These write the same layout (XCDR1,
little endian, zeroed padding) from plain numbers, and the decoders read it (or what
rclpy or any other ROS 2 writer stored) back for the offline commands.
"""

import struct
from typing import Sequence, Tuple

import numpy as np

from .errors import BagError

# encapsulation header, as rclpy's serialize_message writes it
CDR_LE = b'\x00\x01\x00\x00'
# the two encapsulations a ROS 2 message is stored with: plain CDR, big or little endian
_BYTE_ORDERS = {b'\x00\x00': '>', b'\x00\x01': '<'}


def _pad(body: bytes, alignment: int) -> bytes:
    # CDR aligns from the end of the encapsulation header
    return body + bytes(-len(body) % alignment)


def _string(text: str) -> bytes:
    name = text.encode('utf-8') + b'\x00'
    return struct.pack('<I', len(name)) + name


def _header(sec: int, nanosec: int, frame_id: str) -> bytes:
    return struct.pack('<iI', sec, nanosec) + _string(frame_id)


def pose_stamped(sec: int, nanosec: int, frame_id: str, pose: Sequence[float]) -> bytes:
    """
    Return a geometry_msgs/PoseStamped as CDR bytes.

    :param pose: x, y, z, qx, qy, qz, qw (any orientation; it is stored as given).
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


def wrench_stamped(sec: int, nanosec: int, frame_id: str, force: Sequence[float],
                   torque: Sequence[float]) -> bytes:
    """Return a geometry_msgs/WrenchStamped as CDR bytes."""
    return (CDR_LE + _pad(_header(sec, nanosec, frame_id), 8)
            + struct.pack('<6d', *force, *torque))


def string(text: str) -> bytes:
    """Return a std_msgs/String as CDR bytes (length, UTF-8, NUL; no trailing padding)."""
    return CDR_LE + _string(text)


def float64(value: float) -> bytes:
    """Return a std_msgs/Float64 as CDR bytes."""
    return CDR_LE + struct.pack('<d', value)


def boolean(value: bool) -> bytes:
    """Return a std_msgs/Bool as CDR bytes (one byte, 0 or 1)."""
    return CDR_LE + struct.pack('<?', bool(value))


def odometry(sec: int, nanosec: int, frame_id: str, child_frame_id: str,
             pose: Sequence[float], twist: Sequence[float]) -> bytes:
    """
    Return a nav_msgs/Odometry as CDR bytes, its covariances zero (unknown).

    :param pose: x, y, z, qx, qy, qz, qw in frame_id.
    :param twist: linear and angular velocity, six numbers, in child_frame_id's axes.
    """
    body = _pad(_header(sec, nanosec, frame_id), 4) + _string(child_frame_id)
    body = _pad(body, 8) + struct.pack('<7d', *pose) + bytes(8 * 36)
    return CDR_LE + body + struct.pack('<6d', *twist) + bytes(8 * 36)


def float64_multi_array(dimensions: Sequence[Tuple[str, int, int]],
                        data: Sequence[float]) -> bytes:
    """
    Return a std_msgs/Float64MultiArray as CDR bytes, its data_offset 0.

    :param dimensions: (label, size, stride) of each dimension, outermost first.
    """
    body = struct.pack('<I', len(dimensions))
    for label, size, stride in dimensions:
        body = _pad(body, 4) + _string(label)
        body = _pad(body, 4) + struct.pack('<II', size, stride)
    values = np.asarray(data, dtype='<f8').reshape(-1)
    body = _pad(body, 4) + struct.pack('<II', 0, len(values))
    return CDR_LE + _pad(body, 8) + values.tobytes()


def vector3_stamped(sec: int, nanosec: int, frame_id: str, vector: Sequence[float]) -> bytes:
    """Return a geometry_msgs/Vector3Stamped as CDR bytes."""
    return CDR_LE + _pad(_header(sec, nanosec, frame_id), 8) + struct.pack('<3d', *vector)


class _Cursor:
    """Reads CDR fields in order, aligning each to its size from the end of the header."""

    def __init__(self, data: bytes, type_name: str) -> None:
        self.type_name = type_name
        view = memoryview(data)
        if len(view) < 4 or bytes(view[:2]) not in _BYTE_ORDERS:
            self.fail(f'it does not start with a CDR encapsulation header '
                      f'(got {bytes(view[:4]).hex() or "nothing"})')
        self.order = _BYTE_ORDERS[bytes(view[:2])]
        self.body = view[4:]
        self.offset = 0

    def fail(self, reason: str) -> None:
        raise BagError(f'cannot decode {self.type_name} from {reason}; expected the CDR '
                       'bytes of that type as rosbag2 stores them')

    def take(self, size: int, alignment: int) -> memoryview:
        start = self.offset + (-self.offset % alignment)
        end = start + size
        if end > len(self.body):
            self.fail(f'{len(self.body) + 4} bytes: the message is cut short')
        self.offset = end
        return self.body[start:end]

    def unpack(self, fmt: str, alignment: int) -> tuple:
        return struct.unpack(self.order + fmt, self.take(struct.calcsize('<' + fmt), alignment))

    def string(self) -> str:
        (length,) = self.unpack('I', 4)
        raw = bytes(self.take(length, 1))
        if not raw or raw[-1] != 0:
            self.fail('bytes whose string is not NUL-terminated')
        try:
            return raw[:-1].decode('utf-8')
        except UnicodeDecodeError:
            self.fail('bytes whose string is not UTF-8')

    def doubles(self, count: int) -> np.ndarray:
        raw = self.take(8 * count, 8)
        return np.frombuffer(raw, dtype=self.order + 'f8').astype(float)

    def header(self) -> Tuple[int, int, str]:
        sec, nanosec = self.unpack('iI', 4)
        return sec, nanosec, self.string()


def decode_pose_stamped(data: bytes) -> Tuple[int, int, str, np.ndarray, np.ndarray]:
    """
    Return the fields of a geometry_msgs/PoseStamped's CDR bytes.

    :returns: sec, nanosec, frame_id, position (3,) [x, y, z] and orientation (4,)
        [x, y, z, w], as stored (not checked for finiteness or unit length).
    :raises BagError: the bytes are not a PoseStamped.
    """
    cursor = _Cursor(data, 'geometry_msgs/msg/PoseStamped')
    sec, nanosec, frame_id = cursor.header()
    pose = cursor.doubles(7)
    return sec, nanosec, frame_id, pose[:3], pose[3:]


def decode_pose_array(data: bytes) -> Tuple[int, int, str, np.ndarray]:
    """
    Return the fields of a geometry_msgs/PoseArray's CDR bytes.

    :returns: sec, nanosec, frame_id and the poses (n, 7) as rows x, y, z, qx, qy, qz, qw.
    :raises BagError: the bytes are not a PoseArray.
    """
    cursor = _Cursor(data, 'geometry_msgs/msg/PoseArray')
    sec, nanosec, frame_id = cursor.header()
    (count,) = cursor.unpack('I', 4)
    if count > (len(cursor.body) - cursor.offset) // 56:
        cursor.fail(f'{len(data)} bytes: {count} poses do not fit in them')
    poses = cursor.doubles(7 * count).reshape(count, 7) if count else np.empty((0, 7))
    return sec, nanosec, frame_id, poses


def decode_wrench(data: bytes) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return force (3,) and torque (3,) of a geometry_msgs/Wrench's CDR bytes.

    :raises BagError: the bytes are not a Wrench.
    """
    values = _Cursor(data, 'geometry_msgs/msg/Wrench').doubles(6)
    return values[:3], values[3:]


def decode_wrench_stamped(data: bytes) -> Tuple[int, int, str, np.ndarray, np.ndarray]:
    """
    Return the fields of a geometry_msgs/WrenchStamped's CDR bytes.

    :returns: sec, nanosec, frame_id, force (3,) and torque (3,).
    :raises BagError: the bytes are not a WrenchStamped.
    """
    cursor = _Cursor(data, 'geometry_msgs/msg/WrenchStamped')
    sec, nanosec, frame_id = cursor.header()
    values = cursor.doubles(6)
    return sec, nanosec, frame_id, values[:3], values[3:]


def decode_float64(data: bytes) -> float:
    """
    Return the value of a std_msgs/Float64's CDR bytes.

    :raises BagError: the bytes are not a Float64.
    """
    return float(_Cursor(data, 'std_msgs/msg/Float64').unpack('d', 8)[0])


def decode_string(data: bytes) -> str:
    """
    Return the text of a std_msgs/String's CDR bytes.

    :raises BagError: the bytes are not a String.
    """
    return _Cursor(data, 'std_msgs/msg/String').string()
