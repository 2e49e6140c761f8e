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
Conversions between geometry_msgs objects and the simulator's numpy arrays.

Thin wrappers over rope_sim_ros.frames, which does the arithmetic on plain numbers (so the
offline runner, which imports no ROS, gets the same results). Conventions: quaternions as
numpy arrays are (x, y, z, w), as in geometry_msgs; positions and forces are in frame_id
axes; time stamps are integer nanoseconds.
"""

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Pose, PoseArray, Vector3, Wrench
import numpy as np

from ..model import frames
from ..model.frames import (all_finite, MIN_QUATERNION_NORM, NANOSECONDS, PoseError, PosePoint,
                            rotate, tangent_quaternions)

__all__ = [
    'MIN_QUATERNION_NORM', 'NANOSECONDS', 'PoseError', 'PosePoint', 'all_finite', 'ns_to_stamp',
    'pose_array', 'pose_point', 'rotate', 'stamp_to_ns', 'tangent_quaternions',
    'unit_quaternion', 'wrench',
]


def unit_quaternion(q) -> tuple:
    """
    Return (q normalised as an (x, y, z, w) array, |q| before) of a Quaternion message.

    :raises PoseError: a component is NaN or infinite, or |q| is (nearly) zero.
    """
    return frames.unit_quaternion((q.x, q.y, q.z, q.w))


def pose_point(pose: Pose, offset) -> PosePoint:
    """
    Return the point pose ⊕ offset: the offset (body frame) rotated and added.

    :raises PoseError: non-finite position or orientation, or a zero quaternion.
    """
    p, o = pose.position, pose.orientation
    return frames.pose_point((p.x, p.y, p.z), (o.x, o.y, o.z, o.w), offset)


def stamp_to_ns(stamp: Time) -> int:
    """Return a builtin_interfaces/Time as integer nanoseconds."""
    return frames.stamp_ns(stamp.sec, stamp.nanosec)


def ns_to_stamp(ns: int) -> Time:
    """Return integer nanoseconds as a builtin_interfaces/Time."""
    sec, nanosec = frames.split_ns(ns)
    return Time(sec=sec, nanosec=nanosec)


def pose_array(positions: np.ndarray, frame_id: str, stamp_ns: int) -> PoseArray:
    """Return the particles as a PoseArray, each pose oriented along the local tangent."""
    msg = PoseArray()
    msg.header.frame_id = frame_id
    msg.header.stamp = ns_to_stamp(stamp_ns)
    quaternions = tangent_quaternions(positions)
    poses = []
    for (px, py, pz), (qx, qy, qz, qw) in zip(np.asarray(positions, dtype=float).tolist(),
                                              quaternions.tolist()):
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = px, py, pz
        pose.orientation.x, pose.orientation.y = qx, qy
        pose.orientation.z, pose.orientation.w = qz, qw
        poses.append(pose)
    msg.poses = poses
    return msg


def wrench(force, lever) -> Wrench:
    """
    Return a Wrench: the force and its moment lever × force about the pose origin.

    :param force: force of the line on the end point [N], shape (3,).
    :param lever: end point minus the pose origin [m], shape (3,).
    """
    force = np.asarray(force, dtype=float)
    torque = np.cross(np.asarray(lever, dtype=float), force)
    return Wrench(force=_vector3(force), torque=_vector3(torque))


def _vector3(v: np.ndarray) -> Vector3:
    x, y, z = (float(c) for c in v)
    return Vector3(x=x, y=y, z=z)
