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
Unit tests of rope_sim_ros.model.frames and its message wrappers in rope_sim_ros.ros.conversions.

Pose ⊕ offset, quaternions, messages and stamps: frames does the arithmetic on plain
numbers (the offline runner's way), conversions on geometry_msgs objects (the node's); both
must give the same numbers and the same errors.
"""

import math

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Pose, Quaternion
import numpy as np
import pytest
from rope_sim_ros.model import frames
from rope_sim_ros.ros import conversions


def pose(position=(0.0, 0.0, 0.0), orientation=(0.0, 0.0, 0.0, 1.0)) -> Pose:
    msg = Pose()
    msg.position.x, msg.position.y, msg.position.z = (float(c) for c in position)
    (msg.orientation.x, msg.orientation.y, msg.orientation.z,
     msg.orientation.w) = (float(c) for c in orientation)
    return msg


def about_z(angle: float) -> tuple:
    return (0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))


def test_pose_point_rotates_the_offset_into_the_frame():
    # a ship at (10, 5, 0) heading +y (yaw 90 deg), fairlead 2 m forward, 1 m to port, 3 m up
    end = conversions.pose_point(pose((10, 5, 0), about_z(math.pi / 2)), [2.0, 1.0, 3.0])
    assert np.allclose(end.lever, [-1.0, 2.0, 3.0])
    assert np.allclose(end.point, [9.0, 7.0, 3.0])
    assert end.quaternion_norm == pytest.approx(1.0)


def test_pose_point_roll_moves_an_offset_fairlead():
    roll = 0.1  # rad about x
    q = (math.sin(roll / 2), 0.0, 0.0, math.cos(roll / 2))
    end = conversions.pose_point(pose((0, 0, 0), q), [0.0, 5.0, 0.0])
    assert np.allclose(end.point, [0.0, 5.0 * math.cos(roll), 5.0 * math.sin(roll)])


def test_non_unit_quaternion_is_normalised():
    scaled = tuple(3.0 * c for c in about_z(math.pi / 2))
    end = conversions.pose_point(pose((0, 0, 0), scaled), [1.0, 0.0, 0.0])
    assert np.allclose(end.point, [0.0, 1.0, 0.0])
    assert end.quaternion_norm == pytest.approx(3.0)


@pytest.mark.parametrize('position, orientation, reason', [
    ((math.nan, 0, 0), (0, 0, 0, 1), 'non-finite position'),
    ((0, math.inf, 0), (0, 0, 0, 1), 'non-finite position'),
    ((0, 0, 0), (0, 0, -math.inf, 1), 'non-finite orientation'),
    ((0, 0, 0), (0, 0, 0, math.nan), 'non-finite orientation'),
    ((0, 0, 0), (0, 0, 0, 0), 'zero quaternion'),
    ((0, 0, 0), (1e-9, 0, 0, 0), 'zero quaternion'),
])
def test_bad_poses_are_refused(position, orientation, reason):
    with pytest.raises(conversions.PoseError, match=reason):
        conversions.pose_point(pose(position, orientation), [0.0, 0.0, 0.0])
    with pytest.raises(frames.PoseError, match=reason) as info:
        frames.pose_point(position, orientation, [0.0, 0.0, 0.0])
    assert isinstance(info.value, ValueError)


def test_frames_and_messages_give_the_same_point():
    rng = np.random.default_rng(7)
    for _ in range(100):
        position, orientation = rng.normal(scale=20.0, size=3), rng.normal(size=4)
        offset = rng.normal(scale=3.0, size=3)
        plain = frames.pose_point(position, orientation, offset)
        wrapped = conversions.pose_point(pose(position, orientation), offset)
        assert plain.point.tolist() == wrapped.point.tolist()
        assert plain.lever.tolist() == wrapped.lever.tolist()
        assert plain.quaternion_norm == wrapped.quaternion_norm
        q, norm = frames.unit_quaternion(orientation)
        assert np.allclose(plain.lever, frames.rotate(q, offset), atol=1e-12)
        assert norm == pytest.approx(np.linalg.norm(orientation))
        assert np.allclose(plain.point, position + plain.lever)


def test_many_points_are_each_the_point_of_one():
    # pose_points (compiled, a ship's fairleads at every pose) gives the very floats of
    # pose_point, offset by offset: an arrangement's lines and the lines alone agree
    rng = np.random.default_rng(11)
    for _ in range(200):
        position, orientation = rng.normal(scale=50.0, size=3), rng.normal(size=4)
        offsets = rng.normal(scale=100.0, size=(16, 3))
        points = frames.pose_points(position, orientation, offsets)
        assert points.shape == (16, 3)
        for point, offset in zip(points, offsets):
            alone = frames.pose_point(position, orientation, offset).point
            assert point.tolist() == alone.tolist()
    for position, orientation, reason in (((0, math.nan, 0), (0, 0, 0, 1), 'non-finite position'),
                                          ((0, 0, 0), (0, 0, 0, 0), 'zero quaternion')):
        with pytest.raises(frames.PoseError, match=reason):
            frames.pose_points(position, orientation, [[1.0, 0.0, 0.0]])


def test_stamp_ns_and_split_ns():
    assert frames.stamp_ns(12, 5) == 12_000_000_005
    assert frames.split_ns(12_000_000_005) == (12, 5)
    assert frames.split_ns(-1) == (-1, 999_999_999)
    assert frames.stamp_ns(*frames.split_ns(-1)) == -1


def test_unit_quaternion():
    q, norm = conversions.unit_quaternion(Quaternion(x=0.0, y=0.0, z=0.0, w=2.0))
    assert np.allclose(q, [0, 0, 0, 1]) and norm == 2.0


def test_rotate_many_vectors():
    q = np.array(about_z(math.pi))
    assert np.allclose(conversions.rotate(q, [[1, 0, 0], [0, 1, 1]]), [[-1, 0, 0], [0, -1, 1]])


def test_stamp_round_trip():
    for ns in (0, 1, 999_999_999, 1_000_000_000, 1_795_265_869_633_317_344):
        stamp = conversions.ns_to_stamp(ns)
        assert isinstance(stamp, Time) and 0 <= stamp.nanosec < 1_000_000_000
        assert conversions.stamp_to_ns(stamp) == ns
    assert conversions.stamp_to_ns(Time(sec=12, nanosec=5)) == 12_000_000_005


def x_axis(q: np.ndarray) -> np.ndarray:
    """Return the rotated x axis of an (x, y, z, w) quaternion."""
    return conversions.rotate(q, [1.0, 0.0, 0.0])


def test_tangent_quaternions_point_along_the_rope():
    s = np.linspace(0.0, 1.0, 21)
    positions = np.stack([36.0 * s, np.zeros_like(s), 8.0 * s - 4.0 * np.sin(math.pi * s)], 1)
    q = conversions.tangent_quaternions(positions)
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0)
    ends = [(0, positions[1] - positions[0]), (20, positions[20] - positions[19]),
            (7, positions[8] - positions[6])]
    for i, direction in ends:
        assert np.allclose(x_axis(q[i]), direction / np.linalg.norm(direction))


def test_tangent_quaternions_degenerate_cases():
    # along -x (the shortest arc is undefined: a half turn about z) and a zero tangent
    q = conversions.tangent_quaternions(np.array([[0.0, 0, 0], [-1, 0, 0], [-2, 0, 0]]))
    assert np.allclose([x_axis(r) for r in q], [[-1, 0, 0]] * 3)
    q = conversions.tangent_quaternions(np.zeros((3, 3)))
    assert np.allclose(q, [[0, 0, 0, 1]] * 3)


def test_pose_array():
    positions = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 2.0]])
    msg = conversions.pose_array(positions, 'world', 5_250_000_000)
    assert msg.header.frame_id == 'world'
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (5, 250_000_000)
    assert [p.position.z for p in msg.poses] == [0.0, 1.0, 2.0]
    o = msg.poses[1].orientation
    assert np.allclose(x_axis(np.array([o.x, o.y, o.z, o.w])), [0, 0, 1])


def test_wrench_torque_is_the_moment_about_the_pose_origin():
    # 1000 N pulling along -x at a fairlead 10 m to port (+y) and 2 m up of the ship's origin
    msg = conversions.wrench([-1000.0, 0.0, 0.0], [0.0, 10.0, 2.0])
    assert (msg.force.x, msg.force.y, msg.force.z) == (-1000.0, 0.0, 0.0)
    assert np.allclose([msg.torque.x, msg.torque.y, msg.torque.z], [0.0, -2000.0, 10000.0])


def test_all_finite():
    assert conversions.all_finite(np.zeros((3, 3)), [1.0], 2.0)
    assert not conversions.all_finite(np.zeros(3), [1.0, math.nan])
    assert not conversions.all_finite([math.inf])
