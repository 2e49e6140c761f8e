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
The radiation memory two ways: the convolution summed over the history, or modes.

    PYTHONPATH=$PWD:$PWD/test .venv/bin/python benchmarks/radiation_memory.py

test/hydro_cases.py's barge, its six degrees of freedom linear, (M + A_inf) x'' +
int K(t - tau) x'(tau) dtau + C x = 0, released 0.3 m high, stepped 40 s by improved Euler
at dt with the memory load either
- convolution: the trapezoid sum of K (sampled at dt over its memory,
  radiation.retardation_function) against the velocities of every past step, or at a
  history of every n-th step (K sampled there; the newest interval by the trapezoid too);
- modes: radiation_modes' states, each stepped exactly over a step for velocities linear
  in it (as forces/body.py does).
Printed: the heave period and damping ratio against the exact pole of the same equation
(hydro_cases.heave_poles), and the memory's cost per step (the whole step less the same
step without memory, best of 5).

Measured (2 shared cores, load average 1, the barge's 12 modes, its K's memory 21 s):

    method                    dt [s]  period err  zeta err  memory us/step
    convolution                0.010      -0.03%     0.06%           19.99
    convolution, every 10      0.010      -0.04%    -6.14%            2.24
    modes                      0.010       0.00%    -0.47%            0.38
    convolution                0.002      -0.00%    -0.03%          102.71
    convolution, every 10      0.002      -0.01%    -1.33%           13.12
    modes                      0.002       0.00%    -0.47%            0.37

The modes are as right as the full convolution (their -0.47 % in damping is their fit of K,
within 1 %, the same at either step) at 50 to 280 times less cost, which does not grow as
the step shrinks; a history kept every 10th step costs an eighth to a ninth and errs 1 to 6 %
in damping.
A variable step (the adaptive integrator's) would need the history resampled besides.
"""

import math
import time

import hydro_cases as hc
import numba
import numpy as np

# the first-order hold of a mode over a step, as the body's step takes it
from rope_sim_ros.model.forces.body import _hold
from rope_sim_ros.model.ship.radiation import (radiation_modes, retardation,
                                               retardation_function)

DURATION = 40.0


@numba.njit(cache=True)
def _convolution_run(mass_inv, stiffness, kernel, every, dt, x, v, out):
    """Improved Euler with the memory summed over the history (history every `every` steps)."""
    n = out.shape[0]
    m = kernel.shape[0]  # K at 0, every dt, ... over the memory
    history = np.zeros((n + 1, 6))  # the velocities of every step (a ring would do as well)
    history[0] = v
    count = 1
    for k in range(n):
        mu = np.zeros(6)
        # trapezoid over the samples kept: the newest at lag 0
        newest = (count - 1) // every * every if every > 1 else count - 1
        lag0 = (count - 1) - newest
        for j in range(0, m, every):
            idx = newest - j
            if idx < 0:
                break
            lag = lag0 + j
            if lag >= m:
                break
            weight = every * dt * (0.5 if j == 0 else 1.0)
            for p in range(6):
                for q in range(6):
                    mu[p] += weight * kernel[lag, p, q] * history[idx, q]
        a = mass_inv @ (-stiffness @ x - mu)
        xp = x + dt * v
        vp = v + dt * a
        a2 = mass_inv @ (-stiffness @ xp - mu)
        x = x + 0.5 * dt * (v + vp)
        v = v + 0.5 * dt * (a + a2)
        history[count] = v
        count += 1
        out[k] = x


@numba.njit(cache=True)
def _modes_after(z, growth, g0, g1, inputs, u0, u1, after):
    """Put the modes z a step on into after (z itself may be it), velocities u0 to u1."""
    for i in range(z.shape[0]):
        b0 = 0j
        b1 = 0j
        for q in range(6):
            b0 += inputs[i, q] * u0[q]
            b1 += inputs[i, q] * u1[q]
        after[i] = growth[i] * z[i] + g0[i] * b0 + g1[i] * b1


@numba.njit(cache=True)
def _modes_run(mass_inv, stiffness, poles, weights, inputs, outputs, dt, x, v, out):
    """Improved Euler with the memory as modes (z exact for velocities linear over a step)."""
    r = poles.shape[0]
    z = np.zeros(r, dtype=np.complex128)
    growth = np.empty(r, dtype=np.complex128)
    g0 = np.empty(r, dtype=np.complex128)
    g1 = np.empty(r, dtype=np.complex128)
    for i in range(r):
        growth[i], g0[i], g1[i] = _hold(poles[i], dt)
    for k in range(out.shape[0]):
        mu = np.zeros(6)
        for i in range(r):
            for p in range(6):
                mu[p] += weights[i] * (outputs[i, p] * z[i]).real
        a = mass_inv @ (-stiffness @ x - mu)
        xp = x + dt * v
        vp = v + dt * a
        zp = np.empty(r, dtype=np.complex128)
        _modes_after(z, growth, g0, g1, inputs, v, vp, zp)
        mu2 = np.zeros(6)
        for i in range(r):
            for p in range(6):
                mu2[p] += weights[i] * (outputs[i, p] * zp[i]).real
        a2 = mass_inv @ (-stiffness @ xp - mu2)
        x1 = x + 0.5 * dt * (v + vp)
        v1 = v + 0.5 * dt * (a + a2)
        _modes_after(z, growth, g0, g1, inputs, v, v1, z)
        x, v = x1, v1
        out[k] = x


def _decay(heave, dt):
    """Return the period and damping ratio of a heave decay (crossings past the first)."""
    up = np.flatnonzero((heave[:-1] < 0.0) & (heave[1:] >= 0.0))
    times = (up + heave[up] / (heave[up] - heave[up + 1])) * dt
    period = float(np.diff(times[1:]).mean())
    crests = np.array([heave[a:b].max() for a, b in zip(up[1:-1], up[2:])])
    decrement = float(np.mean(np.log(crests[:-1] / crests[1:])))
    return period, decrement / math.sqrt(4.0 * math.pi ** 2 + decrement ** 2)


def _timed(run, *args):
    """Return the best of 5 wall times of run(*args) [s]."""
    best = math.inf
    for _ in range(5):
        start = time.perf_counter()
        run(*args)
        best = min(best, time.perf_counter() - start)
    return best


def main():
    db = hc.database()
    mass_inv = np.linalg.inv(hc.rigid_mass() + hc.ADDED_INFINITE)
    stiffness = hc.stiffness()
    pole = hc.heave_poles()[0]
    period_exact, zeta_exact = 2.0 * math.pi / abs(pole.imag), -pole.real / abs(pole)
    modes = radiation_modes(db.omega, db.radiation_damping)
    memory = retardation_function(db.omega, db.radiation_damping).memory
    x0 = np.array([0.0, 0.0, 0.3, 0.0, 0.0, 0.0])
    print(f'exact: period {period_exact:.4f} s, zeta {zeta_exact:.5f}; {modes.poles.size} '
          f'modes; memory of the convolution {memory:.1f} s')
    print(f'{"method":<24}{"dt [s]":>8}{"period err":>12}{"zeta err":>10}'
          f'{"memory us/step":>16}')
    for dt in (0.01, 0.002):
        n = int(round(DURATION / dt))
        out = np.empty((n, 6))
        zero_kernel = np.zeros((1, 6, 6))
        base = _timed(_convolution_run, mass_inv, stiffness, zero_kernel, 1, dt, x0.copy(),
                      np.zeros(6), out)
        t = np.arange(0.0, memory, dt)
        kernel = retardation(db.omega, db.radiation_damping, t)
        for every in (1, 10):
            _convolution_run(mass_inv, stiffness, kernel, every, dt, x0.copy(), np.zeros(6),
                             out)
            period, zeta = _decay(out[:, 2], dt)
            cost = _timed(_convolution_run, mass_inv, stiffness, kernel, every, dt, x0.copy(),
                          np.zeros(6), out)
            name = 'convolution' + (f', every {every}' if every > 1 else '')
            print(f'{name:<24}{dt:>8.3f}{period / period_exact - 1:>12.2%}'
                  f'{zeta / zeta_exact - 1:>10.2%}{(cost - base) / n * 1e6:>16.2f}')
        args = (mass_inv, stiffness, modes.poles, modes.weights, modes.inputs, modes.outputs,
                dt, x0.copy(), np.zeros(6), out)
        _modes_run(*args)
        period, zeta = _decay(out[:, 2], dt)
        cost = _timed(_modes_run, *args)
        print(f'{"modes":<24}{dt:>8.3f}{period / period_exact - 1:>12.2%}'
              f'{zeta / zeta_exact - 1:>10.2%}{(cost - base) / n * 1e6:>16.2f}')


if __name__ == '__main__':
    main()
