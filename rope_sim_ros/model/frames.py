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
Poses, rotations and time stamps as plain numbers, shared by the offline runner and nodes.

No message objects here (ros/conversions.py wraps these for geometry_msgs), so the offline
commands compute input points exactly as the node does without importing ROS. Conventions:
quaternions are (x, y, z, w), as in geometry_msgs; positions are in the pose's frame axes;
time stamps are integer nanoseconds.
"""

import math
from typing import NamedTuple, Sequence, Tuple

import numba
import numpy as np

NANOSECONDS = 1_000_000_000
# A quaternion shorter than this cannot be normalised into a meaningful rotation.
MIN_QUATERNION_NORM = 1e-6


class PoseError(ValueError):
    """A pose cannot be used (non-finite numbers, zero quaternion)."""


class PosePoint(NamedTuple):
    """
    A rope end computed from a pose.

    :ivar point: pose position ⊕ offset: the end point in the pose's frame [m], shape (3,).
    :ivar lever: the offset rotated into that frame: point minus the pose origin [m], shape (3,).
    :ivar quaternion_norm: |q| of the pose before normalisation (1 for a clean pose).
    """

    point: np.ndarray
    lever: np.ndarray
    quaternion_norm: float


def unit_quaternion(orientation: Sequence[float]) -> Tuple[np.ndarray, float]:
    """
    Return (q normalised as an (x, y, z, w) array, |q| before).

    :param orientation: x, y, z, w.
    :raises PoseError: a component is NaN or infinite, or |q| is (nearly) zero.
    """
    q, norm = _checked_orientation(orientation)
    return np.array(q) / norm, norm


def rotate(q: np.ndarray, v) -> np.ndarray:
    """Rotate vector(s) v, shape (3,) or (n, 3), by the unit quaternion q = (x, y, z, w)."""
    u, w = np.asarray(q[:3], dtype=float), float(q[3])
    v = np.asarray(v, dtype=float)
    uv = np.cross(u, v)
    return v + 2.0 * w * uv + 2.0 * np.cross(u, uv)


def pose_point(position: Sequence[float], orientation: Sequence[float], offset) -> PosePoint:
    """
    Return the point pose ⊕ offset: the offset (body frame) rotated and added.

    In plain floats, as rotate() for one vector: this runs for every pose, and with numpy's
    cross products the node's pose callback took 43 us, 14 us without (5000 poses).

    :param position: x, y, z of the pose origin [m].
    :param orientation: x, y, z, w of the pose; normalised here if it is not a unit quaternion.
    :param offset: the point in the pose's body frame [m], shape (3,).
    :raises PoseError: non-finite position or orientation, or a zero quaternion.
    """
    position, q, norm = _checked_pose(position, orientation)
    ux, uy, uz, w = (c / norm for c in q)
    vx, vy, vz = (float(c) for c in offset)
    # v + 2 w (u × v) + 2 u × (u × v)
    cx, cy, cz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    lever = np.array([vx + 2.0 * (w * cx + uy * cz - uz * cy),
                      vy + 2.0 * (w * cy + uz * cx - ux * cz),
                      vz + 2.0 * (w * cz + ux * cy - uy * cx)])
    return PosePoint(np.add(position, lever), lever, norm)


def _checked_pose(position: Sequence[float], orientation: Sequence[float]) -> tuple:
    """Return the position and orientation as float tuples and |q| (PoseError: see pose_point)."""
    px, py, pz = position
    position = px, py, pz = float(px), float(py), float(pz)
    if not (math.isfinite(px) and math.isfinite(py) and math.isfinite(pz)):
        raise PoseError(f'non-finite position {list(position)}')
    return (position,) + _checked_orientation(orientation)


def _checked_orientation(orientation: Sequence[float]) -> tuple:
    """
    Return the orientation as a float tuple and |q|.

    In plain floats, without generators: this runs for every pose, where numpy's checks took
    8 us, these 1 us.
    """
    ox, oy, oz, ow = orientation
    q = ox, oy, oz, ow = float(ox), float(oy), float(oz), float(ow)
    if not (math.isfinite(ox) and math.isfinite(oy) and math.isfinite(oz)
            and math.isfinite(ow)):
        raise PoseError(f'non-finite orientation {list(q)}')
    norm = math.sqrt(ox * ox + oy * oy + oz * oz + ow * ow)
    if norm < MIN_QUATERNION_NORM:
        raise PoseError(f'zero quaternion {list(q)}')
    return q, norm


def pose_points(position: Sequence[float], orientation: Sequence[float],
                offsets) -> np.ndarray:
    """
    Return the points pose ⊕ offset of many offsets (n, 3) at once.

    pose_point's arithmetic, the same operations in the same order, compiled: each point is
    the very float pose_point gives (a ship's fairleads, at every pose).

    :raises PoseError: as pose_point.
    """
    return unit_pose_points(position, orientation, offsets)[1]


def unit_pose_points(position: Sequence[float], orientation: Sequence[float],
                     offsets) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return the unit quaternion (x, y, z, w) of a pose and its points pose ⊕ offset (n, 3).

    unit_quaternion and pose_points with the pose checked once: a ship pose needs both.

    :raises PoseError: as pose_point.
    """
    (x, y, z), (qx, qy, qz, qw), norm = _checked_pose(position, orientation)
    ux, uy, uz, w = qx / norm, qy / norm, qz / norm, qw / norm
    offsets = np.ascontiguousarray(offsets, dtype=float).reshape(-1, 3)
    return np.array((ux, uy, uz, w)), _pose_points(x, y, z, ux, uy, uz, w, offsets)


@numba.njit(cache=True)
def _pose_points(x, y, z, ux, uy, uz, w, offsets):
    points = np.empty_like(offsets)
    for i in range(len(offsets)):
        vx, vy, vz = offsets[i, 0], offsets[i, 1], offsets[i, 2]
        cx, cy, cz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
        points[i, 0] = x + (vx + 2.0 * (w * cx + uy * cz - uz * cy))
        points[i, 1] = y + (vy + 2.0 * (w * cy + uz * cx - ux * cz))
        points[i, 2] = z + (vz + 2.0 * (w * cz + ux * cy - uy * cx))
    return points


def rotation_matrix(q: Sequence[float]) -> np.ndarray:
    """Return the 3x3 rotation matrix of a unit quaternion (x, y, z, w)."""
    x, y, z, w = np.asarray(q, dtype=float).tolist()
    return np.array([
        [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w)],
        [2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w)],
        [2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y)]])


def cross(a, b) -> np.ndarray:
    """Return a x b of two 3-vectors (np.cross checks its axes for 10-40 us a call)."""
    a0, a1, a2 = float(a[0]), float(a[1]), float(a[2])
    b0, b1, b2 = float(b[0]), float(b[1]), float(b[2])
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def cross_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return the cross products of the rows of a and b (n, 3), compiled (np.cross: 10 us)."""
    return _cross_rows(np.ascontiguousarray(a, dtype=float),
                       np.ascontiguousarray(b, dtype=float))


@numba.njit(cache=True)
def _cross_rows(a, b):
    out = np.empty_like(a)
    for i in range(len(a)):
        out[i, 0] = a[i, 1] * b[i, 2] - a[i, 2] * b[i, 1]
        out[i, 1] = a[i, 2] * b[i, 0] - a[i, 0] * b[i, 2]
        out[i, 2] = a[i, 0] * b[i, 1] - a[i, 1] * b[i, 0]
    return out


def distances_beyond(a: np.ndarray, b: np.ndarray, limits: np.ndarray,
                     out: np.ndarray) -> int:
    """
    Write the distances between the rows of a and b (n, 3) into out (n,) [m].

    Compiled (numpy's took 8 us a ship pose, flagging the jumps as many again).

    :returns: how many of them are farther than their limit (n,) [m].
    """
    return _distances_beyond(np.ascontiguousarray(a, dtype=float),
                             np.ascontiguousarray(b, dtype=float), limits, out)


@numba.njit(cache=True)
def _distances_beyond(a, b, limits, out):
    count = 0
    for i in range(len(a)):
        out[i] = math.sqrt((a[i, 0] - b[i, 0]) ** 2 + (a[i, 1] - b[i, 1]) ** 2
                           + (a[i, 2] - b[i, 2]) ** 2)
        count += out[i] > limits[i]
    return count


def stamp_ns(sec: int, nanosec: int) -> int:
    """Return a time stamp's seconds and nanoseconds as integer nanoseconds."""
    return int(sec) * NANOSECONDS + int(nanosec)


def split_ns(ns: int) -> Tuple[int, int]:
    """Return integer nanoseconds as a time stamp's (sec, nanosec), nanosec in [0, 1e9)."""
    sec, nanosec = divmod(int(ns), NANOSECONDS)
    return sec, nanosec


def tangent_quaternions(positions: np.ndarray) -> np.ndarray:
    """
    Orientations (n, 4) whose x axis points along the rope, from the bollard onwards.

    The tangent at an inner particle is the central difference of its neighbours, at an end
    the adjacent segment; the rotation is the shortest arc from +x to it (so the roll about
    the rope is fixed, not physical). A zero tangent gives the identity.
    """
    x = np.asarray(positions, dtype=float)
    return _along(x, np.array([0, len(x)]))


def lines_tangent_quaternions(positions: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """
    tangent_quaternions of several lines at once: the same numbers, one numpy pass.

    :param positions: every line's particles stacked, (P, 3).
    :param starts: line k's rows are starts[k] .. starts[k + 1] - 1 (each line >= 2 rows).
    """
    return _along(np.asarray(positions, dtype=float), np.asarray(starts))


def _along(x: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Return the orientations of tangent_quaternions for the lines stacked in x."""
    tangent = np.empty_like(x)
    tangent[1:-1] = x[2:] - x[:-2]
    first, last = starts[:-1], starts[1:] - 1
    tangent[first] = x[first + 1] - x[first]
    tangent[last] = x[last] - x[last - 1]
    length = np.linalg.norm(tangent, axis=1)
    degenerate = length < 1e-12
    t = tangent / np.where(degenerate, 1.0, length)[:, None]
    # shortest arc from e_x to t: (e_x × t, 1 + e_x · t), normalised
    q = np.stack([np.zeros(len(t)), -t[:, 2], t[:, 1], 1.0 + t[:, 0]], axis=1)
    opposite = q[:, 3] < 1e-9
    q[opposite] = (0.0, 0.0, 1.0, 0.0)  # half turn about z
    q[degenerate] = (0.0, 0.0, 0.0, 1.0)
    return q / np.linalg.norm(q, axis=1)[:, None]


def all_finite(*arrays) -> bool:
    """Return True when every number in every array is finite."""
    return all(bool(np.isfinite(np.asarray(a, dtype=float)).all()) for a in arrays)
