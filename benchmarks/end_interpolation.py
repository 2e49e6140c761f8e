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
How end interpolation between pose samples changes the tension of a stiff line.

The reference polyester line (N 20) under the reference surge, with the fairlead given as
samples every 10 ms (the reference CSV) or 20 ms (a 50 Hz pose stream), interpolated
linearly (secant velocity, which jumps at every sample) or with a cubic Catmull-Rom spline.
The yardstick is the same model driven by 1 ms samples. Prints the fairlead-force NRMSE over
t = 10..60 s for each integrator. An accuracy benchmark: machine load does not change it.

    python benchmarks/end_interpolation.py
"""

import math

import numpy as np

from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.params.table import from_values

FAIRLEAD = np.array([36.0, 0.0, 8.0])
LEVEL = (0.0, 0.0, 0.0, 1.0)  # the ship's orientation: its fairlead is position + offset
DURATION = 60.0
OUTPUT = 0.01


def fairlead(t):
    """Return the reference motion: 2 m along the chord, 10 s period, 10 s ramp."""
    ramp = 0.5 * (1.0 - math.cos(math.pi * t / 10.0)) if t < 10.0 else 1.0
    return FAIRLEAD + 2.0 * math.sin(2.0 * math.pi * t / 10.0) * ramp * FAIRLEAD / 36.878


def tension(integrator, interpolation, sample_interval):
    """Return the fairlead tension at 100 Hz for one way of feeding the motion."""
    params = from_values(dict(
        segments=20, mass_per_length=25.467341 / 9.81, axial_stiffness=5e7,
        axial_damping=2903.43, bending_stiffness_ratio=0.0, bending_damping_ratio=0.0,
        integrator=integrator, end_interpolation=interpolation))
    mooring = Mooring(single_line(params), history=math.inf, output_interval=OUTPUT)
    for t in np.arange(0.0, DURATION + 2 * sample_interval, sample_interval):
        mooring.push_ship(float(t), fairlead(t) - params.fairlead_offset, LEVEL)
    mooring.start(0.0)
    out = []
    for t in np.arange(OUTPUT, DURATION, OUTPUT):
        mooring.advance_to(t)
        out.append(mooring.output().fairlead_tensions[0])
    return np.array(out)


def main():
    window = np.arange(OUTPUT, DURATION, OUTPUT) >= 10.0
    print('| integrator | samples | interpolation | NRMSE vs 1 ms samples |')
    print('|---|---|---|---|')
    for integrator in ('improved_euler', 'implicit_euler'):
        reference = tension(integrator, 'linear', 0.001)[window]
        for interval in (0.01, 0.02):
            for interpolation in ('linear', 'cubic'):
                series = tension(integrator, interpolation, interval)[window]
                error = np.sqrt(np.mean((series - reference) ** 2)) / np.std(reference)
                print(f'| {integrator} | {1000 * interval:.0f} ms | {interpolation} | '
                      f'{100 * error:.1f} % |', flush=True)


if __name__ == '__main__':
    main()
