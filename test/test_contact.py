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
Ground contact (forces/contact.py): the seabed and the quay block.

The law on its own (through .py_func), its matrix block against finite differences, then
whole systems: a chain resting on the seabed, a chain dragged along it, a line over a quay.
"""

import math

import numpy as np
import pytest

from rope_sim_ros.model.forces.contact import (add_contact, add_contact_block,
                                               FRICTION_DAMPING)
from rope_sim_ros.model.layout import (ENV_AIR_DENSITY, ENV_COLUMNS, ENV_GRAVITY,
                                       ENV_QUAY_DEPTH, ENV_QUAY_EDGE, ENV_QUAY_NORMAL,
                                       ENV_SEABED_DAMPING, ENV_SEABED_FRICTION,
                                       ENV_SEABED_LEVEL, ENV_SEABED_STIFFNESS,
                                       ENV_WATER_DENSITY, ENV_WATER_LEVEL)
from rope_sim_ros.model.objects import Environment, Line, LineType, Point, System
from rope_sim_ros.model.superelastic import MAX_ITERATIONS
from rope_sim_ros.stepping.step import step

G = 9.81
K_B = 3.0e6  # MoorDyn's kBot [Pa/m]
C_B = 3.0e5  # MoorDyn's cBot [Pa s/m]
WIDTH = 0.1  # d [m]
LENGTH = 2.0  # len_i [m]
AREA = WIDTH * LENGTH
SINK = 1e-3  # the damping's ramp depth [m]
INTEGRATORS = ['improved_euler', 'implicit_euler']


def env_array(seabed=0.0, friction=0.0, edge=(0.0, 0.0, 0.0), normal=(0.0, 0.0, 0.0),
              depth=1e4):
    """Return an ENV array: seabed at z = `seabed`, an optional quay, no water."""
    env = np.zeros(ENV_COLUMNS)
    env[ENV_GRAVITY:ENV_GRAVITY + 3] = (0.0, 0.0, -G)
    env[ENV_WATER_LEVEL] = -math.inf
    env[ENV_WATER_DENSITY] = 1025.0
    env[ENV_AIR_DENSITY] = 1.225
    env[ENV_SEABED_LEVEL] = seabed
    env[ENV_SEABED_STIFFNESS] = K_B
    env[ENV_SEABED_DAMPING] = C_B
    env[ENV_SEABED_FRICTION] = friction
    env[ENV_QUAY_EDGE:ENV_QUAY_EDGE + 3] = edge
    env[ENV_QUAY_NORMAL:ENV_QUAY_NORMAL + 3] = normal
    env[ENV_QUAY_DEPTH] = depth
    return env


def force(position, velocity, env, sink=SINK):
    """Return the contact force [N] on one particle (the interpreted law)."""
    x = np.array([position], dtype=float)
    v = np.array([velocity], dtype=float)
    out = np.zeros((2, 3))
    add_contact.py_func(x, v, 0, WIDTH, LENGTH, sink, env, out, 1)
    assert not out[0].any()  # only out_row is written
    return out[1]


def block(position, velocity, env, h, half_h2, sink=SINK):
    """Return h C + h^2/2 S of that force."""
    out = np.zeros((3, 3))
    add_contact_block.py_func(np.array([position], dtype=float),
                              np.array([velocity], dtype=float), 0, WIDTH, LENGTH, sink, env,
                              h, half_h2, out)
    return out


# -- the seabed's normal force ---------------------------------------------------------------

def test_a_particle_resting_in_the_seabed_feels_k_delta_d_len():
    env = env_array(seabed=-20.0)
    f = force([3.0, 4.0, -20.01], [0.0, 0.0, 0.0], env)
    assert f == pytest.approx([0.0, 0.0, K_B * 0.01 * AREA], rel=1e-12, abs=1e-12)
    assert f[2] == pytest.approx(6000.0, rel=1e-12)


def test_nothing_above_the_seabed_nor_without_one():
    assert not force([0.0, 0.0, 1e-9], [1.0, 2.0, -3.0], env_array(friction=0.5)).any()
    assert not force([0.0, 0.0, -5.0], [1.0, 2.0, -3.0],
                     env_array(seabed=-math.inf, friction=0.5)).any()
    # and none for a particle without a contact area (a point without volume)
    out = np.zeros((1, 3))
    add_contact.py_func(np.array([[0.0, 0.0, -0.1]]), np.zeros((1, 3)), 0, 0.0, 0.0, SINK,
                        env_array(), out, 0)
    assert not out.any()


def test_touchdown_has_no_force_step():
    """Start from 0 at touchdown (MoorDyn's law jumps by c_b v_z d len there)."""
    env = env_array()
    down = -2.0
    moordyn_step = C_B * abs(down) * AREA  # 1.2e5 N
    f = force([0.0, 0.0, -1e-9], [0.0, 0.0, down], env)
    assert f[2] == pytest.approx((K_B * 1e-9 - C_B * down * 1e-9 / SINK) * AREA, rel=1e-9)
    assert 0.0 < f[2] < 1e-5 * moordyn_step
    # the damping fades in linearly over the sink depth, then stays at c_b
    half = force([0.0, 0.0, -0.5 * SINK], [0.0, 0.0, down], env)[2]
    assert half == pytest.approx((K_B * 0.5 * SINK - C_B * down * 0.5) * AREA, rel=1e-12)
    deep = force([0.0, 0.0, -3.0 * SINK], [0.0, 0.0, down], env)[2]
    assert deep == pytest.approx((K_B * 3.0 * SINK - C_B * down) * AREA, rel=1e-12)
    # continuous along the way: no step larger than the stiffness alone explains
    depths = np.linspace(0.0, 3.0 * SINK, 3001)[1:]
    fz = np.array([force([0.0, 0.0, -s], [0.0, 0.0, down], env)[2] for s in depths])
    assert np.abs(np.diff(fz)).max() < 1.01 * (K_B + C_B * abs(down) / SINK) * AREA * (
        depths[1] - depths[0])


def test_the_ground_never_pulls():
    env = env_array(friction=0.5)
    # lifting off fast: the damper would pull (k delta - c v_z < 0); it lets go instead
    assert not force([0.0, 0.0, -0.01], [3.0, 0.0, 10.0], env).any()
    assert K_B * 0.01 - C_B * 10.0 < 0.0
    # lifting off slowly: still pushing, less
    f = force([0.0, 0.0, -0.01], [0.0, 0.0, 0.05], env)
    assert f[2] == pytest.approx((K_B * 0.01 - C_B * 0.05) * AREA, rel=1e-12)
    assert f[2] > 0.0


# -- friction ----------------------------------------------------------------------------

def test_friction_is_a_damper_below_saturation():
    mu = 0.5
    env = env_array(friction=mu)
    v = np.array([0.03, -0.04, 0.0])
    f = force([0.0, 0.0, -0.01], v, env)
    # 6000 N normal force; mu FricDamp |v_h| = 5 N, far below mu F_z = 3000 N
    assert f[:2] == pytest.approx(-mu * FRICTION_DAMPING * v[:2], rel=1e-12)
    assert FRICTION_DAMPING == 200.0
    assert np.hypot(*f[:2]) == pytest.approx(5.0, rel=1e-12)
    assert f[2] == pytest.approx(6000.0, rel=1e-12)  # friction does not change the normal


def test_friction_saturates_at_mu_times_the_normal_force():
    mu = 0.5
    env = env_array(friction=mu)
    f = force([0.0, 0.0, -1e-3], [3.0, 4.0, 0.0], env)
    normal = K_B * 1e-3 * AREA  # 600 N; FricDamp |v_h| = 1000 N is above it
    assert f[2] == pytest.approx(normal, rel=1e-12)
    assert f[:2] == pytest.approx([-mu * normal * 0.6, -mu * normal * 0.8], rel=1e-12)
    # continuous at the saturation speed |v_h| = F_z / FricDamp = 3 m/s
    edge = normal / FRICTION_DAMPING
    below = force([0.0, 0.0, -1e-3], [edge * (1 - 1e-9), 0.0, 0.0], env)[0]
    above = force([0.0, 0.0, -1e-3], [edge * (1 + 1e-9), 0.0, 0.0], env)[0]
    assert below == pytest.approx(-mu * normal, rel=1e-8)
    assert above == pytest.approx(-mu * normal, rel=1e-12)
    # no friction without the coefficient (MoorDyn's default 0), nor at rest
    assert force([0.0, 0.0, -1e-3], [3.0, 4.0, 0.0], env_array())[:2] == pytest.approx(
        [0.0, 0.0], abs=0.0)
    assert not force([0.0, 0.0, -1e-3], [0.0, 0.0, 0.0], env)[:2].any()


# -- the quay ------------------------------------------------------------------------------

QUAY = dict(edge=(10.0, 5.0, 2.0), normal=(0.6, 0.8, 0.0), depth=6.0, seabed=-math.inf)


def test_the_quay_top_pushes_up_and_its_face_pushes_out():
    env = env_array(**QUAY)
    n = np.array([0.6, 0.8, 0.0])
    behind = np.array([10.0, 5.0, 0.0]) - 3.0 * n  # 3 m behind the face
    # just under the deck, far from the face: out through the top, along +z
    f = force(behind + [0.0, 0.0, 1.99], [0.0, 0.0, 0.0], env)
    assert f == pytest.approx([0.0, 0.0, K_B * 0.01 * AREA], rel=1e-12, abs=1e-9)
    # 2 cm behind the face, 2 m under the deck: out through the face, along +n
    f = force(np.array([10.0, 5.0, 0.0]) - 0.02 * n + [0.8, -0.6, 0.0], [0.0, 0.0, 0.0],
              env)
    assert f == pytest.approx(K_B * 0.02 * AREA * n, rel=1e-12, abs=1e-9)
    # a normal given with another length means the same face
    f2 = force(np.array([10.0, 5.0, 0.0]) - 0.02 * n, [0.0, 0.0, 0.0],
               env_array(**dict(QUAY, normal=(3.0, 4.0, 0.0))))
    assert f2 == pytest.approx(K_B * 0.02 * AREA * n, rel=1e-12, abs=1e-9)
    # outside: in front of the face, above the deck, below the block's bottom; no quay
    for p in (np.array([10.0, 5.0, 0.0]) + 0.01 * n, behind + [0.0, 0.0, 2.01],
              behind + [0.0, 0.0, -4.01]):
        assert not force(p, [0.0, 0.0, -1.0], env).any()
    assert not force(behind, [0.0, 0.0, -1.0], env_array(seabed=-math.inf)).any()


def test_friction_on_the_quay_face_acts_in_the_face_plane():
    mu = 0.4
    env = env_array(**dict(QUAY, friction=mu))
    n = np.array([0.6, 0.8, 0.0])
    p = np.array([10.0, 5.0, 0.0]) - 0.02 * n
    normal = K_B * 0.02 * AREA
    # sliding down the face at 100 m/s (saturated), and pressed into it at 1 cm/s
    v = np.array([0.0, 0.0, -100.0]) - 0.01 * n
    f = force(p, v, env)
    pressed = normal + C_B * 0.01 * AREA
    assert f == pytest.approx(pressed * n + [0.0, 0.0, mu * pressed], rel=1e-12, abs=1e-9)
    # sliding slowly along the face, horizontally: the damper regime
    along = np.array([0.8, -0.6, 0.0])
    f = force(p, 0.01 * along, env)
    assert f == pytest.approx(normal * n - mu * FRICTION_DAMPING * 0.01 * along, rel=1e-12)


def test_a_particle_under_the_seabed_and_in_the_quay_feels_both():
    env = env_array(**dict(QUAY, seabed=1.0))
    n = np.array([0.6, 0.8, 0.0])
    p = np.array([10.0, 5.0, 0.99]) - 0.02 * n  # 1 cm under the seabed, 2 cm in the face
    f = force(p, [0.0, 0.0, 0.0], env)
    assert f == pytest.approx(K_B * AREA * (0.02 * n + [0.0, 0.0, 0.01]), rel=1e-12)


# -- the implicit step's block ------------------------------------------------------------

def jacobians(position, velocity, env, sink=SINK, step=1e-7):
    """Return dF/dx, dF/dv (3, 3) by central differences."""
    jx = np.empty((3, 3))
    jv = np.empty((3, 3))
    for q in range(3):
        e = np.zeros(3)
        e[q] = step
        jx[:, q] = (force(position + e, velocity, env, sink)
                    - force(position - e, velocity, env, sink)) / (2 * step)
        jv[:, q] = (force(position, velocity + e, env, sink)
                    - force(position, velocity - e, env, sink)) / (2 * step)
    return jx, jv


N_FACE = np.array([0.6, 0.8, 0.0])
UP = np.array([0.0, 0.0, 1.0])
FD_CASES = {
    # name: (env, position, velocity, the surface's normal if the friction saturates)
    'seabed, damper regime': (env_array(friction=0.5), [1.0, 2.0, -0.01],
                              [0.02, -0.01, 0.03], None),
    'seabed, inside the damping ramp, at rest': (env_array(friction=0.5),
                                                 [1.0, 2.0, -0.4 * SINK], [0.0, 0.0, 0.0],
                                                 None),
    'seabed, saturated': (env_array(friction=0.5), [1.0, 2.0, -0.01], [24.0, -32.0, 0.01],
                          UP),
    'quay top, damper regime': (env_array(friction=0.3, **QUAY),
                                np.array([10.0, 5.0, 1.98]) - 3.0 * N_FACE,
                                [0.01, 0.02, -0.01], None),
    'quay face, saturated': (env_array(friction=0.3, **QUAY),
                             np.array([10.0, 5.0, 0.0]) - 0.02 * N_FACE,
                             np.array([0.0, 0.0, -80.0]) + 60.0 * np.array([0.8, -0.6, 0.0]),
                             N_FACE),
}


@pytest.mark.parametrize('case', sorted(FD_CASES))
def test_the_block_is_minus_the_jacobians(case):
    """
    Check h C + h^2/2 S against finite differences of the force.

    Exact where the friction is a damper; once it saturates, the block leaves out the
    unsymmetric coupling of the friction to the normal force, mu t grad(F_n)^T, and only
    that.
    """
    env, position, velocity, normal = FD_CASES[case]
    position = np.asarray(position, dtype=float)
    velocity = np.asarray(velocity, dtype=float)
    jx, jv = jacobians(position, velocity, env)
    damping = block(position, velocity, env, 1.0, 0.0)
    stiffness = block(position, velocity, env, 0.0, 1.0)
    expected_c, expected_s = -jv, -jx
    if normal is not None:
        vt = velocity - velocity.dot(normal) * normal
        t = vt / np.linalg.norm(vt)
        mu = env[ENV_SEABED_FRICTION]
        # saturated: F_t = -mu F_n t, with dF_n/dv = -c_b d len n, dF_n/dx = -k_b d len n
        assert FRICTION_DAMPING * np.linalg.norm(vt) > force(position, velocity, env).dot(
            normal)
        expected_c = expected_c + mu * C_B * AREA * np.outer(t, normal)
        expected_s = expected_s + mu * K_B * AREA * np.outer(t, normal)
    scale_c = np.abs(expected_c).max()
    scale_s = np.abs(expected_s).max()
    assert scale_c > 0.0 and scale_s > 0.0
    assert damping == pytest.approx(expected_c, abs=1e-6 * scale_c)
    assert stiffness == pytest.approx(expected_s, abs=1e-6 * scale_s)
    # scaled by the step: h C + h^2/2 S
    h = 0.01
    assert block(position, velocity, env, h, 0.5 * h * h) == pytest.approx(
        h * damping + 0.5 * h * h * stiffness, rel=1e-12, abs=1e-12 * scale_c)


def test_the_block_is_symmetric_and_never_indefinite():
    rng = np.random.default_rng(11)
    env = env_array(friction=0.6, **dict(QUAY, seabed=0.5))
    n = N_FACE
    seen = 0
    for _ in range(400):
        # around the quay's lower face and the seabed, at all speeds
        position = (np.array([10.0, 5.0, 0.5]) + rng.uniform(-0.05, 0.05) * n
                    + rng.uniform(-0.05, 0.05, 3))
        velocity = rng.normal(size=3) * 10.0 ** rng.uniform(-4, 1)
        b = block(position, velocity, env, 0.01, 5e-5)
        assert b == pytest.approx(b.T, abs=1e-12 * max(np.abs(b).max(), 1.0))
        assert np.linalg.eigvalsh(b).min() >= -1e-9 * max(np.abs(b).max(), 1.0)
        seen += bool(b.any())
    assert seen > 100  # most samples were in contact


# -- whole systems -------------------------------------------------------------------------

CHAIN = LineType(mass_per_length=10.0, axial_stiffness=1.0e7, axial_damping=2.0e3,
                 diameter=0.03, normal_drag=0.0, tangential_drag=0.0)
SEABED = -20.0


def _water(**values):
    """Return the Environment of a 20 m deep harbour (water at z = 0)."""
    return Environment(gravity=(0.0, 0.0, -G), water_level=0.0, seabed_level=SEABED,
                       **values)


def _submerged_weight(line_type, environment):
    """Return the line's weight in water per metre [N/m]."""
    area = math.pi * line_type.diameter ** 2 / 4.0
    return (line_type.mass_per_length - environment.water_density * area) * G


def _laid_chain(environment, ends, length=10.0, segments=20):
    """Lay a chain straight along x on the seabed at its resting depth, on two points."""
    sink = _submerged_weight(CHAIN, environment) / (environment.seabed_stiffness
                                                    * CHAIN.diameter)
    shape = np.zeros((segments + 1, 3))
    shape[:, 0] = np.linspace(0.0, length, segments + 1)
    shape[:, 2] = SEABED - sink
    system = System(environment)
    for e, kind in enumerate(ends):
        system.add_point(Point(kind, shape[0 if e == 0 else -1]))
    system.add_line(Line.uniform(CHAIN, length, segments, shape, (0, 1)))
    system.pack()
    return system


@pytest.mark.parametrize('integrator', INTEGRATORS)
def test_a_chain_at_rest_on_the_seabed_stays_at_rest(integrator):
    """The whole line free (both ends on free points), friction on: 10 s without a move."""
    system = _laid_chain(_water(seabed_friction=0.5), ('free', 'free'))
    start = system.x.copy()
    dt = 1e-4 if integrator == 'improved_euler' else 1e-3
    drive_x, drive_v = system.drive_arrays(1000)
    for _ in range(int(round(10.0 / (1000 * dt)))):
        step(system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS)
    assert np.abs(system.x - start).max() < 1e-6
    assert np.abs(system.point_x - start[[0, -1]]).max() < 1e-6
    # the seabed carries the submerged weight: nothing is left for the (free) ends
    assert np.abs(system.end_forces()).max() < 1e-6 * _submerged_weight(CHAIN, _water()) * 10


@pytest.mark.parametrize('integrator', INTEGRATORS)
def test_a_chain_dragged_along_the_seabed_feels_mu_times_its_weight(integrator):
    """
    End A pulls the chain along its length, up to 0.5 m/s in 1 s; end B is free.

    At that speed every particle's friction is saturated (FricDamp v = 100 N is above its
    normal force, 45 N at most), so the tension at A is mu times the laid chain's submerged
    weight, and nothing is left at B.
    """
    mu = 0.5
    environment = _water(seabed_friction=mu)
    system = _laid_chain(environment, ('driven', 'free'))
    speed, ramp = 0.5, 1.0
    dt = 1e-4 if integrator == 'improved_euler' else 1e-3
    per = int(round(0.01 / dt))
    z_a = system.point_x[0, 2]
    forces = []
    for k in range(300):  # 3 s
        t = (k * per + 1 + np.arange(per)) * dt
        drive_x = np.zeros((per, 2, 3))
        drive_v = np.zeros((per, 2, 3))
        drive_x[:, 0, 0] = -speed * np.where(t < ramp, t * t / (2 * ramp), t - ramp / 2)
        drive_v[:, 0, 0] = -speed * np.minimum(t / ramp, 1.0)
        drive_x[:, 0, 2] = z_a
        drive_x[:, 1] = system.point_x[1]
        step(system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS)
        if k >= 200:  # the last second
            forces.append(system.end_forces()[0])
    forces = np.array(forces)
    friction = mu * _submerged_weight(CHAIN, environment) * 10.0  # 455 N
    assert friction == pytest.approx(455.0, rel=0.01)
    pull = forces[:, 0, 0] - forces[:, 1, 0]  # the line pulls A towards +x
    assert pull.mean() == pytest.approx(friction, rel=0.01)
    assert np.abs(pull - friction).max() < 0.03 * friction
    assert np.abs(forces[:, 1]).max() < 0.01 * friction
    # every particle slides with the end and stays on the seabed
    assert np.abs(system.v[:, 0] + speed).max() < 5e-3
    assert np.abs(system.x[:, 2] - z_a).max() < 1e-4


@pytest.mark.parametrize('integrator', INTEGRATORS)
def test_a_line_over_the_quay_edge_stays_out_of_the_block(integrator):
    """
    Hang a 20 kg payload 5 m down the face from a bollard 4 m back on the deck.

    The wire runs along the deck, over the edge and down; it starts 30 cm in front of the
    face, drops, swings onto the face, and the block holds it.
    """
    wire = LineType(mass_per_length=2.0, axial_stiffness=2.0e6, axial_damping=500.0,
                    diameter=0.03)
    environment = Environment(gravity=(0.0, 0.0, -G), quay_edge=(0.0, 0.0, 0.0),
                              quay_normal=(1.0, 0.0, 0.0), quay_depth=20.0,
                              seabed_friction=0.3)
    shape = np.zeros((19, 3))
    shape[:9, 0] = np.linspace(-4.0, 0.0, 9)  # along the deck
    shape[9:, 0] = 0.3  # hanging 30 cm in front of the face
    shape[8, 0] = 0.0
    shape[9:, 2] = -np.sqrt(0.25 - 0.09) - 0.5 * np.arange(10)
    rest = np.linalg.norm(np.diff(shape, axis=0), axis=1)
    system = System(environment)
    system.add_point(Point('fixed', shape[0]))
    system.add_point(Point('free', shape[-1], mass=20.0))
    system.add_line(Line(wire, rest, shape, (0, 1)))
    system.pack()
    dt = 1e-4 if integrator == 'improved_euler' else 1e-3
    per = int(round(0.01 / dt))
    drive_x, drive_v = system.drive_arrays(per)
    deepest = 0.0
    for _ in range(500):  # 5 s
        step(system, integrator, dt, drive_x, drive_v, MAX_ITERATIONS)
        x = system.x
        inside = (x[:, 0] < 0.0) & (x[:, 2] < 0.0)
        if inside.any():
            deepest = max(deepest, np.minimum(-x[inside, 0], -x[inside, 2]).max())
        assert np.isfinite(x).all()
    # contact is per particle: the segment over the edge cuts the corner, and the corner
    # particle, 15 cm down the face, takes the deck's tension (about 1000 N after the first
    # snatch) on k_b d len = 4.5e4 N/m: 2 to 3 cm; nothing goes deeper
    assert deepest < 0.05
    # the payload hangs against the face, 5 m of wire (and that corner) below the deck
    payload = system.point_x[1]
    assert -0.03 < payload[0] < 0.1
    assert -5.2 < payload[2] < -5.0
