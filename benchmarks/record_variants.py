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
The kernels and records record_overhead.py times: a kernel of no work, four ways of calling it.

A module of its own (numba caches only a function that has a source file): with
RECORD_VARIANTS_CACHE=1 in the environment its kernels are compiled with cache=True.
The StructRef is the project's own (rope_sim_ros/model/record.py).
"""

import os
from typing import NamedTuple

import numba
from numba.experimental import jitclass
import numpy as np

CACHE = os.environ.get('RECORD_VARIANTS_CACHE') == '1'


def arrays(segments=50, points=2):
    """Return a 50-segment line's 13 arrays, as a System holds them, by name."""
    n = segments + 1
    return dict(x=np.zeros((n, 3)), v=np.zeros((n, 3)), point_x=np.zeros((points, 3)),
                point_v=np.zeros((points, 3)), accel=np.zeros((n, 3)),
                point_accel=np.zeros((points, 3)), particles=np.zeros((n, 14)),
                lines=np.zeros((1, 9), dtype=np.int64), line_real=np.zeros((1, 128)),
                points=np.zeros((points, 12)), env=np.zeros(20), bodies=np.zeros((0, 64)),
                fenders=np.zeros((0, 41)))


class Record(NamedTuple):
    """The 13 arrays as a NamedTuple."""

    x: np.ndarray
    v: np.ndarray
    point_x: np.ndarray
    point_v: np.ndarray
    accel: np.ndarray
    point_accel: np.ndarray
    particles: np.ndarray
    lines: np.ndarray
    line_real: np.ndarray
    points: np.ndarray
    env: np.ndarray
    bodies: np.ndarray
    fenders: np.ndarray


_FLOAT2 = numba.float64[:, ::1]


@jitclass([(name, _FLOAT2) for name in ('x', 'v', 'point_x', 'point_v', 'accel',
                                        'point_accel', 'particles', 'line_real', 'points',
                                        'bodies', 'fenders')]
          + [('lines', numba.int64[:, ::1]), ('env', numba.float64[::1])])
class JitRecord:
    """The 13 arrays as a jitclass."""

    def __init__(self, x, v, point_x, point_v, accel, point_accel, particles, lines,
                 line_real, points, env, bodies, fenders):
        self.x = x
        self.v = v
        self.point_x = point_x
        self.point_v = point_v
        self.accel = accel
        self.point_accel = point_accel
        self.particles = particles
        self.lines = lines
        self.line_real = line_real
        self.points = points
        self.env = env
        self.bodies = bodies
        self.fenders = fenders


@numba.njit(cache=CACHE)
def positional(x, v, point_x, point_v, drive_x, drive_v, dt, particles, lines, line_real,
               points, env, bodies, fenders, max_iterations, bending, gamma, beta, accel,
               point_accel):
    """Touch every array, as implicit_euler_run took them: x[0, 0] += dt a step."""
    for _ in range(drive_x.shape[0]):
        x[0, 0] += dt
    accel[0, 0] = (v[0, 0] + point_x[0, 0] + point_v[0, 0] + particles[0, 0] + lines[0, 0]
                   + line_real[0, 0] + points[0, 0] + env[0] + bodies.shape[0]
                   + fenders.shape[0] + point_accel[0, 0] + drive_v.shape[0]
                   + max_iterations + bending + gamma + beta)


@numba.njit(cache=CACHE)
def record(arrays, drive_x, drive_v, dt, max_iterations, bending, gamma, beta):
    """Do the same on a record with named fields (NamedTuple, StructRef or jitclass)."""
    x = arrays.x
    for _ in range(drive_x.shape[0]):
        x[0, 0] += dt
    arrays.accel[0, 0] = (arrays.v[0, 0] + arrays.point_x[0, 0] + arrays.point_v[0, 0]
                          + arrays.particles[0, 0] + arrays.lines[0, 0]
                          + arrays.line_real[0, 0] + arrays.points[0, 0] + arrays.env[0]
                          + arrays.bodies.shape[0] + arrays.fenders.shape[0]
                          + arrays.point_accel[0, 0] + drive_v.shape[0] + max_iterations
                          + bending + gamma + beta)


X, V, POINT_X, POINT_V, ACCEL, POINT_ACCEL, PARTICLES, LINES, LINE_REAL, POINTS, ENV, BODIES, \
    FENDERS = range(13)


@numba.njit(cache=CACHE)
def plain(arrays, drive_x, drive_v, dt, max_iterations, bending, gamma, beta):
    """Do the same on a plain tuple, its fields by index."""
    x = arrays[X]
    for _ in range(drive_x.shape[0]):
        x[0, 0] += dt
    arrays[ACCEL][0, 0] = (arrays[V][0, 0] + arrays[POINT_X][0, 0] + arrays[POINT_V][0, 0]
                           + arrays[PARTICLES][0, 0] + arrays[LINES][0, 0]
                           + arrays[LINE_REAL][0, 0] + arrays[POINTS][0, 0] + arrays[ENV][0]
                           + arrays[BODIES].shape[0] + arrays[FENDERS].shape[0]
                           + arrays[POINT_ACCEL][0, 0] + drive_v.shape[0] + max_iterations
                           + bending + gamma + beta)
