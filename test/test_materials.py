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

"""Material presets reproduce the MoorPy fits and the OCIMF MEG4 working load limits."""

from one_line import OneLine
import pytest

from rope_sim_ros.model.materials import MaterialError
from rope_sim_ros.params.materials import load_materials
from rope_sim_ros.params.table import from_values, MATERIALS

D = 0.064
# MoorPy and MEG4 values, written out independently of config/materials.yaml
EXPECTED = {
    'nylon': (585 * D**2, 5 * (230e6 * D**3 + 207e6 * D**2), 230e6 * D**3 + 207e6 * D**2, 0.50),
    'polyester': (679 * D**2, 14 * 308e6 * D**2, 308e6 * D**2, 0.50),
    'hmpe': (496 * D**2, 56 * (651e6 * D**3 + 580e6 * D**2), 651e6 * D**3 + 580e6 * D**2,
             0.50),
    'steel_wire': (5293 * D**2, 97.1e9 * D**2, 1022e6 * D**2, 0.55),
}


@pytest.mark.parametrize('name', sorted(EXPECTED))
def test_moorpy_fits(name):
    mass, ea, mbl, wll = EXPECTED[name]
    props = load_materials().properties(name, D)
    assert props.mass_per_length == pytest.approx(mass, rel=1e-12)
    assert props.axial_stiffness == pytest.approx(ea, rel=1e-12)
    assert props.mbl == pytest.approx(mbl, rel=1e-12)
    assert props.working_load_limit == pytest.approx(wll * mbl, rel=1e-12)


def test_manila_48mm_catalogue_values():
    props = load_materials().properties('manila', 0.048)
    assert props.mass_per_length == pytest.approx(1.52, rel=1e-4)
    assert props.mbl == pytest.approx(120e3, rel=1e-4)


def test_every_parameter_preset_is_in_the_file():
    assert set(load_materials().names) == set(MATERIALS)


def test_unknown_material_is_named():
    with pytest.raises(MaterialError, match="unknown material 'kevlar'; allowed: hmpe"):
        load_materials().properties('kevlar', D)


def test_overrides_beat_the_preset():
    sim = OneLine(from_values({'mass_per_length': 3.0, 'axial_stiffness': 1e8}))
    assert sim.props.mass_per_length == 3.0
    assert sim.props.axial_stiffness == 1e8
    default = OneLine(from_values({}))
    assert default.props.mass_per_length == pytest.approx(679 * D**2)
    # automatic damping: 1 % of critical for the first axial mode
    assert default.props.axial_damping > 0.0
