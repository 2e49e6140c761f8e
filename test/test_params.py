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

"""Parameters: every bad value is one clear error naming it and what is allowed."""

import math

import pytest

from rope_sim_ros.params.files import load_params, read_params_file
from rope_sim_ros.params.table import check, from_values, LineParams, ParameterError, SPECS


@pytest.mark.parametrize('name, value, allowed', [
    ('length', -1.0, '> 0 and <= 10000 m'),
    ('length', 0.0, '> 0 and <= 10000 m'),
    ('segments', 1, '>= 2'),
    ('segments', 2.5, '>= 2'),
    ('material', 'kevlar', 'one of nylon, polyester, hmpe, steel_wire, manila'),
    ('max_strain', 0.0, '> 0'),
    ('max_strain', -0.1, '> 0'),
    ('diameter', math.nan, '> 0'),
    ('axial_damping', math.inf, '>= 0'),
    ('gravity', [0.0, math.nan, -9.81], 'a list of 3 finite numbers'),
    ('gravity', [0.0, -9.81], 'a list of 3 finite numbers'),
    ('integrator', 'rk4', 'one of adaptive, improved_euler, implicit_euler'),
    ('time_step', -0.001, '>= 0'),
    ('superelastic_adjustment', 'yes', 'true or false'),
])
def test_bad_value_names_parameter_and_range(name, value, allowed):
    with pytest.raises(ParameterError) as error:
        from_values({name: value})
    message = str(error.value)
    assert repr(name) in message
    assert allowed in message


def test_unknown_parameter_is_named():
    with pytest.raises(ParameterError, match="unknown parameter 'lenght'"):
        check('lenght', 40.0)


def test_good_values_are_canonical():
    params = from_values({'segments': 30.0, 'length': 25, 'gravity': [0, 0, -9.8]})
    assert params.segments == 30 and isinstance(params.segments, int)
    assert params.length == 25.0 and isinstance(params.length, float)
    assert params.gravity == [0.0, 0.0, -9.8]


def test_defaults_obey_their_own_specs():
    for name, spec in SPECS.items():
        assert check(name, spec.default) == spec.default
    assert LineParams().as_dict().keys() == SPECS.keys()


def test_params_file_forms(tmp_path):
    plain = tmp_path / 'plain.yaml'
    plain.write_text('mooring_line:\n  ros__parameters:\n    length: 30.0\n    segments: 12\n')
    wildcard = tmp_path / 'wildcard.yaml'
    wildcard.write_text('/**/mooring_line:\n  ros__parameters:\n    length: 31.0\n'
                        '    use_sim_time: true\n')
    assert load_params(plain).length == 30.0
    assert load_params(plain, {'length': 35.0}).length == 35.0
    assert read_params_file(wildcard) == {'length': 31.0}


def test_params_file_errors(tmp_path):
    with pytest.raises(ParameterError, match='cannot read parameter file'):
        read_params_file(tmp_path / 'missing.yaml')
    other = tmp_path / 'other.yaml'
    other.write_text('some_node:\n  ros__parameters:\n    length: 30.0\n')
    with pytest.raises(ParameterError, match='no "mooring_line: ros__parameters:" section'):
        read_params_file(other)
    broken = tmp_path / 'broken.yaml'
    broken.write_text('mooring_line: [unclosed\n')
    with pytest.raises(ParameterError, match='not valid YAML'):
        read_params_file(broken)


def test_default_config_file_is_valid(repo_root):
    params = load_params(repo_root / 'config' / 'mooring_line.yaml')
    assert params.material in ('nylon', 'polyester', 'hmpe', 'steel_wire', 'manila')
