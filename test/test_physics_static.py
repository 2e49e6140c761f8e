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

"""Settled end forces against the lumped chain's exact equilibrium and the catenary."""

import numpy as np
from physics_cases import (
    AXIAL_STIFFNESS, BOLLARD, FAIRLEAD, GRAVITY, LENGTH, reference_params, run_motion,
    static_row)
import pytest

from rope_sim_ros.model.statics.catenary import catenary_points


@pytest.mark.parametrize('integrator', ['improved_euler', 'implicit_euler'])
@pytest.mark.parametrize('bending', ['off', 'default'])
@pytest.mark.parametrize('segments', [20, 50])
@pytest.mark.parametrize('material', ['polyester', 'wire'])
def test_settles_to_chain_equilibrium(reference_dir, material, segments, bending, integrator):
    row = static_row(reference_dir, material, segments)
    overrides = {'integrator': integrator}
    if bending == 'default':
        overrides.update(bending_stiffness_ratio=1e-4, bending_damping_ratio=1e-4)
    params = reference_params(material, segments, **overrides)
    # start on the continuous catenary, not the chain's equilibrium, so that settling is real
    shape = catenary_points(BOLLARD, FAIRLEAD, LENGTH, row['w_N_per_m'],
                            AXIAL_STIFFNESS[material], np.array([0.0, 0.0, -GRAVITY]),
                            np.linspace(0.0, LENGTH, segments + 1))
    outputs = run_motion(params, [0.0], [FAIRLEAD], np.arange(0.01, 20.0, 0.01), shape)
    settled = [o for o in outputs if o.t > 15.0]
    fairlead = np.mean([o.fairlead_tension for o in settled])
    bollard = np.mean([o.bollard_tension for o in settled])
    assert fairlead == pytest.approx(row['disc_F_B_N'], rel=1e-3)
    assert bollard == pytest.approx(row['disc_F_A_N'], rel=1e-3)
    assert fairlead == pytest.approx(row['an_T_B_N'], rel=5e-3)
    assert bollard == pytest.approx(row['an_T_A_N'], rel=5e-3)


def test_bending_springs_leave_the_sag_alone(reference_dir):
    """Default bending springs move the settled tension by far less than 0.1 %."""
    row = static_row(reference_dir, 'polyester', 20)
    tensions = []
    for ratio in (0.0, 1e-4):
        params = reference_params('polyester', 20, bending_stiffness_ratio=ratio,
                                  bending_damping_ratio=ratio, integrator='implicit_euler')
        outputs = run_motion(params, [0.0], [FAIRLEAD], np.arange(0.5, 10.0, 0.5))
        tensions.append(outputs[-1].fairlead_tension)
    assert tensions[0] == pytest.approx(row['disc_F_B_N'], rel=1e-5)
    assert tensions[1] == pytest.approx(tensions[0], rel=5e-4)
    # and a stiff bending spring (the seed's hard rope) does distort it: the check can fail
    params = reference_params('polyester', 20, bending_stiffness_ratio=1e-2,
                              integrator='implicit_euler')
    outputs = run_motion(params, [0.0], [FAIRLEAD], np.arange(0.5, 10.0, 0.5))
    assert abs(outputs[-1].fairlead_tension / tensions[0] - 1.0) > 5e-3
