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

"""The reference mooring line of test/data/, as simulator parameters and motions."""

import csv
import math

import numpy as np

from one_line import OneLine
from rope_sim_ros.params.table import from_values

GRAVITY = 9.81
BOLLARD = np.zeros(3)
FAIRLEAD = np.array([36.0, 0.0, 8.0])
LENGTH = 40.0
AXIAL_STIFFNESS = {'polyester': 5.0e7, 'wire': 1.0e8}


def read_rows(path):
    """Rows of a reference CSV as dicts of floats (text columns kept)."""
    with open(path, newline='') as f:
        return [{k: _number(v) for k, v in row.items()} for row in csv.DictReader(f)]


def _number(text):
    try:
        return float(text)
    except ValueError:
        return text


def static_row(reference_dir, material, segments):
    """Find the moordyn_static.csv row of one material and N."""
    for row in read_rows(reference_dir / 'moordyn_static.csv'):
        if row['material'] == material and int(row['N']) == segments:
            return row
    raise KeyError((material, segments))


def reference_params(material, segments, **overrides):
    """
    Make the reference line's parameters: in air, mass w/g, the reference BA, no drag.

    w already holds the air's buoyancy (test/data/README.md), so the air itself is off.
    """
    weight = {'polyester': 25.467341, 'wire': 63.749899}[material]
    damping = {'polyester': 2903.43, 'wire': 6492.27}[material]
    values = dict(
        segments=segments, length=LENGTH, mass_per_length=weight / GRAVITY,
        axial_stiffness=AXIAL_STIFFNESS[material], axial_damping=damping,
        bending_stiffness_ratio=0.0, bending_damping_ratio=0.0, air_drag_coefficient=0.0,
        air_density=0.0, gravity=[0.0, 0.0, -GRAVITY], bollard_position=BOLLARD.tolist())
    values.update(overrides)
    return from_values(values)


def run_motion(params, times, fairlead, output_times, shape=None, compiled=True):
    """Drive the fairlead through (times, fairlead) and return outputs at output_times."""
    sim = OneLine(params, history=math.inf, compiled=compiled)
    for t, p in zip(times, fairlead):
        sim.push_fairlead(float(t), p)
    sim.start(float(times[0]), shape)
    outputs = []
    for t in output_times:
        sim.advance_to(float(t))
        outputs.append(sim.output())
    return outputs


def nrmse(series, reference):
    """RMS difference over the RMS of the reference about its mean."""
    series, reference = np.asarray(series), np.asarray(reference)
    return float(np.sqrt(np.mean((series - reference) ** 2)) / np.std(reference))
