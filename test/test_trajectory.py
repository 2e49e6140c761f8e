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

"""End trajectories: interpolation between samples, extrapolation, rejection of bad samples."""

import math

import numpy as np
import pytest

from rope_sim_ros.mooring.trajectory import EndBlend, EndTrajectory, TrajectoryError


def _filled(method, step=0.02):
    trajectory = EndTrajectory(keep=math.inf, method=method)
    for t in np.arange(0.0, 2.0 + 1e-9, step):
        trajectory.push(float(t), [math.sin(t), 2.0 * t, 0.0])
    return trajectory


def test_linear_is_the_secant():
    trajectory = _filled('linear', 0.5)
    positions, velocities = trajectory.sample(np.array([0.25, 0.75]))
    assert positions[0, 0] == pytest.approx(0.5 * math.sin(0.5))
    assert velocities[0, 0] == pytest.approx(math.sin(0.5) / 0.5)
    assert velocities[1, 1] == pytest.approx(2.0)


def test_cubic_is_smooth_and_accurate():
    times = np.linspace(0.1, 1.9, 500)
    cubic, linear = _filled('cubic'), _filled('linear')
    for trajectory, pos_tol, vel_tol in ((cubic, 2e-7, 2e-4), (linear, 6e-5, 1.1e-2)):
        positions, velocities = trajectory.sample(times)
        assert np.abs(positions[:, 0] - np.sin(times)).max() < pos_tol
        assert np.abs(velocities[:, 0] - np.cos(times)).max() < vel_tol
    # cubic velocity is continuous across a sample; linear jumps there
    for trajectory, continuous in ((cubic, True), (linear, False)):
        _, v = trajectory.sample(np.array([1.0 - 1e-9, 1.0 + 1e-9]))
        assert (abs(v[1, 0] - v[0, 0]) < 1e-6) == continuous


def test_before_first_and_past_last_sample():
    trajectory = _filled('cubic')
    positions, velocities = trajectory.sample(np.array([-1.0, 2.05, 10.0]))
    assert positions[0] == pytest.approx([0.0, 0.0, 0.0])
    assert velocities[0] == pytest.approx([0.0, 0.0, 0.0])
    # coasting from 2 m/s to a stop over 1 s: 5 % of the way there at 95 % of the speed ...
    assert trajectory.coast_time == 1.0
    assert positions[1, 1] == pytest.approx(4.0 + 2.0 * (0.05 - 0.05 ** 2 / 2.0))
    assert velocities[1, 1] == pytest.approx(1.9)
    # ... then held still, 1 m on
    assert positions[2, 1] == pytest.approx(5.0)
    assert velocities[2] == pytest.approx([0.0, 0.0, 0.0])


def test_coasting_is_continuous():
    trajectory = _filled('linear')
    end = 2.0 + trajectory.coast_time
    times = np.array([2.0 - 1e-9, 2.0 + 1e-9, end - 1e-9, end + 1e-9])
    positions, velocities = trajectory.sample(times)
    assert np.abs(np.diff(positions[:2], axis=0)).max() < 1e-8
    assert np.abs(np.diff(positions[2:], axis=0)).max() < 1e-8
    assert np.abs(np.diff(velocities[:2], axis=0)).max() < 1e-6
    assert np.abs(velocities[2:]).max() < 1e-6


def test_blend_starts_at_the_offset_and_rate_and_fades_out_smoothly():
    offset, rate = np.array([0.04, 0.0, -0.01]), np.array([-0.15, 0.0, 0.0])
    blend = EndBlend(start=3.0, duration=0.25, offset=offset, rate=rate)
    times = np.linspace(3.0, 3.5, 5001)
    offsets, rates = blend.at(times)
    assert offsets[0] == pytest.approx(offset)
    assert rates[0] == pytest.approx(rate)
    after = times >= 3.25
    assert np.abs(offsets[after]).max() == 0.0 and np.abs(rates[after]).max() == 0.0
    # the rate is the derivative of the offset, and the position never overshoots far
    numeric = np.gradient(offsets, times, axis=0)
    assert np.abs(numeric - rates).max() < 1e-3
    assert np.abs(offsets[:, 0]).max() < 0.04 + 0.25 * 0.15


def test_bad_samples_are_refused_and_change_nothing():
    trajectory = EndTrajectory()
    trajectory.push(1.0, [1.0, 2.0, 3.0])
    for t, p, message in ((2.0, [math.nan, 0, 0], 'non-finite'),
                          (math.inf, [0, 0, 0], 'non-finite'),
                          (1.0, [0, 0, 0], 'not after'), (0.5, [0, 0, 0], 'not after')):
        with pytest.raises(TrajectoryError, match=message):
            trajectory.push(t, p)
    assert len(trajectory) == 1
    assert trajectory.last_position == pytest.approx([1.0, 2.0, 3.0])


def test_history_is_bounded():
    trajectory = EndTrajectory(keep=1.0)
    for t in np.arange(0.0, 10.0, 0.1):
        trajectory.push(float(t), [t, 0.0, 0.0])
    assert len(trajectory) <= 12


@pytest.mark.parametrize('method', ['linear', 'cubic'])
def test_points_sampled_together_are_each_sampled_alone(method):
    # A trajectory of K points (a ship's fairleads) gives each point the very numbers of a
    # trajectory of that point alone: between samples, before the first, coasting past the
    # last, and after old samples are forgotten.
    rng = np.random.default_rng(3)
    together = EndTrajectory(keep=0.5, method=method, width=4)
    alone = [EndTrajectory(keep=0.5, method=method) for _ in range(4)]
    for t in np.arange(0.0, 2.0, 0.02):
        points = rng.normal(size=(4, 3))
        together.push(float(t), points)
        for trajectory, point in zip(alone, points.tolist()):
            trajectory.push(float(t), point)
    assert len(together) == len(alone[0]) < 30
    times = np.linspace(1.0, 3.5, 301)
    x, v = together.sample(times)
    assert x.shape == v.shape == (301, 4, 3)
    for k, trajectory in enumerate(alone):
        xk, vk = trajectory.sample(times)
        assert (x[:, k] == xk).all() and (v[:, k] == vk).all()
    assert np.abs(v[-1]).max() == 0.0 and np.abs(v[:150]).max() > 1.0  # coasted to a stop


def test_a_sample_of_many_points_is_checked_whole():
    trajectory = EndTrajectory(width=2)
    trajectory.push(0.0, [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    version = trajectory.version
    with pytest.raises(TrajectoryError, match=r'shape \(2, 3\), not \(3,\)'):
        trajectory.push(1.0, [1.0, 2.0, 3.0])
    with pytest.raises(TrajectoryError, match='non-finite'):
        trajectory.push(1.0, [[1.0, 2.0, 3.0], [4.0, math.inf, 6.0]])
    assert len(trajectory) == 1 and trajectory.version == version  # nothing changed
    assert trajectory.last_position == [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]
    trajectory.clear()
    assert len(trajectory) == 0 and trajectory.version == version + 1
