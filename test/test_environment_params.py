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
Water and ground parameters: ranges, "none" levels, the materials' coefficients, the model.

Every new parameter refuses a bad value with one line naming it and what is allowed; a
level of -inf (no water, no seabed) is accepted from a dict, a YAML file, the CLI and a ROS
parameter file; the material presets carry MoorPy's coefficients; a line of the model gets
them.
"""

from dataclasses import fields
import math

import numpy as np
from one_line import OneLine
import pytest
import rclpy
from rclpy.exceptions import ParameterException
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions
from rope_sim_ros.model.objects import Environment
from rope_sim_ros.model.rope import RopeProperties
from rope_sim_ros.mooring.driver import Driver
from rope_sim_ros.params.arrangement import (from_stored, LINE_PARAMETERS_KEY, parameters_yaml,
                                             read_setup, single_line, stored)
from rope_sim_ros.params.files import load_params, parse_set, read_params_file
from rope_sim_ros.params.materials import load_materials
from rope_sim_ros.params.table import check, from_values, ParameterError, SPECS
from rope_sim_ros.ros.parameters import describe

LEVELS = ('water_level', 'seabed_level')
COEFFICIENTS = ('normal_drag_coefficient', 'tangential_drag_coefficient',
                'normal_added_mass_coefficient', 'tangential_added_mass_coefficient')
NEW = LEVELS + COEFFICIENTS + (
    'water_density', 'air_density', 'current', 'seabed_stiffness', 'seabed_damping',
    'seabed_friction', 'quay_edge', 'quay_normal', 'quay_depth', 'volume_diameter',
    'payload_volume', 'payload_drag_area', 'payload_added_mass_coefficient')
D = 0.064


# ------------------------------------------------------------------------- the table


def test_every_new_parameter_is_described():
    for name in NEW:
        spec = SPECS[name]
        assert spec.description and spec.read_only == (name != 'current'), name
    assert SPECS['current'].unit == 'm/s'
    assert SPECS['water_level'].unit == SPECS['seabed_level'].unit == 'm'
    assert SPECS['water_level'].default == SPECS['seabed_level'].default == -math.inf
    assert SPECS['water_density'].default == 1025.0 and SPECS['air_density'].default == 1.225
    # MoorDyn's defaults
    assert SPECS['seabed_stiffness'].default == 3.0e6
    assert SPECS['seabed_damping'].default == 3.0e5
    assert SPECS['seabed_friction'].default == 0.0
    for name in COEFFICIENTS:
        assert SPECS[name].default == -1.0 and "-1 = the material's" in SPECS[name].description


def _bad_values(name):
    """Values `name` must refuse: NaN, +inf, a wrong type, and out-of-range numbers."""
    spec = SPECS[name]
    if isinstance(spec.default, list):
        return [[0.0, math.nan, 0.0], [0.0, 0.0, math.inf], [1.0, 2.0], 'north', 3.0]
    values = [math.nan, math.inf, 'deep', True, [1.0, 2.0, 3.0]]
    if spec.low is not None:
        values.append(spec.low - 0.5)  # (-1 itself is a coefficient's "the material's")
    if spec.high is not None:
        values.append(spec.high * 2.0)
    return values


@pytest.mark.parametrize('name, value', [(n, v) for n in NEW for v in _bad_values(n)])
def test_bad_value_is_one_line_naming_parameter_and_range(name, value):
    with pytest.raises(ParameterError) as error:
        from_values({name: value})
    message = str(error.value)
    assert '\n' not in message
    assert message.startswith(f'parameter {name!r} = ')
    assert 'must be ' in message


@pytest.mark.parametrize('name, value, allowed', [
    ('water_density', -1025.0, '> 0 and <= 20000 kg/m^3'),
    ('water_density', 0.0, '> 0'),
    ('air_density', -1.0, '>= 0 and <= 100 kg/m^3'),
    ('water_level', math.nan, '>= -100000 and <= 100000 m, or -.inf (no water)'),
    ('water_level', math.inf, 'or -.inf (no water)'),
    ('water_level', '+inf', 'or -.inf (no water)'),
    ('seabed_level', math.inf, 'or -.inf (no seabed)'),
    ('seabed_stiffness', 0.0, '> 0'),
    ('seabed_friction', -0.1, '>= 0 and <= 10'),
    ('normal_drag_coefficient', -0.5, ">= 0 and <= 100, or -1 (the material's)"),
    ('tangential_drag_coefficient', -2.0, "or -1 (the material's)"),
    ('normal_added_mass_coefficient', -math.inf, "or -1 (the material's)"),
    ('current', [100.0, 0.0, 0.0], 'a list of 3 finite numbers, each within +-50 m/s'),
    ('current', [0.0, math.nan, 0.0], 'a list of 3 finite numbers'),
    ('quay_normal', [1.0, 0.0, 0.5], 'a list of 3 finite numbers [x, y, 0] (z must be 0)'),
    ('quay_depth', 0.0, '> 0'),
    ('volume_diameter', -0.05, '>= 0 and <= 2 m'),
    ('payload_volume', -1.0, '>= 0'),
])
def test_refusals_say_what_is_allowed(name, value, allowed):
    with pytest.raises(ParameterError) as error:
        check(name, value)
    assert allowed in str(error.value)


def test_special_values_are_accepted_exactly():
    # a level: -inf is "none", in every spelling a user meets; any finite level works
    for text in (-math.inf, '-inf', '-.inf', ' -Infinity', '-.INF'):
        assert check('water_level', text) == -math.inf
    assert check('seabed_level', -25.0) == -25.0
    # a coefficient: -1 is "the material's", 0 a legitimate value of its own
    assert check('tangential_drag_coefficient', -1) == -1.0
    assert check('tangential_drag_coefficient', 0) == 0.0
    assert check('normal_added_mass_coefficient', 0.0) == 0.0
    # nothing else takes -inf or text
    for name in ('water_density', 'normal_drag_coefficient', 'quay_depth'):
        with pytest.raises(ParameterError):
            check(name, -math.inf)
        with pytest.raises(ParameterError):
            check(name, '-inf')
    assert check('quay_normal', [0, -1, 0]) == [0.0, -1.0, 0.0]
    assert check('current', [0.5, -0.25, 0]) == [0.5, -0.25, 0.0]


def test_levels_from_dict_yaml_and_cli(tmp_path):
    params = from_values({'water_level': -math.inf, 'seabed_level': '-inf'})
    assert params.water_level == params.seabed_level == -math.inf
    assert not params.has_water and not params.has_seabed and not params.has_quay
    on = tmp_path / 'on.yaml'
    on.write_text('/**/mooring_line:\n  ros__parameters:\n    water_level: 12.5\n'
                  '    seabed_level: -30\n    current: [0.5, 0, 0]\n')
    params = load_params(on)
    assert (params.water_level, params.seabed_level) == (12.5, -30.0)
    assert params.current == [0.5, 0.0, 0.0] and params.has_water and params.has_seabed
    off = tmp_path / 'off.yaml'
    off.write_text('mooring_line:\n  ros__parameters:\n    water_level: -.inf\n'
                   '    seabed_level: -inf\n')
    params = load_params(off)
    assert params.water_level == params.seabed_level == -math.inf
    # the CLI's --set: '-inf' and '-.inf' both; 'nan' and 'inf' refused
    values = parse_set(['water_level=-inf', 'seabed_level=-.inf', 'current=[0.3,0,0]'])
    params = from_values(values)
    assert params.water_level == params.seabed_level == -math.inf
    assert params.current == [0.3, 0.0, 0.0]
    for item in ('water_level=nan', 'water_level=inf', 'water_level=.inf'):
        with pytest.raises(ParameterError, match="parameter 'water_level'"):
            from_values(parse_set([item]))
    nan_file = tmp_path / 'nan.yaml'
    nan_file.write_text('mooring_line:\n  ros__parameters:\n    seabed_level: .nan\n')
    with pytest.raises(ParameterError, match="parameter 'seabed_level' = nan"):
        load_params(nan_file)


# ---------------------------------------------------------------------- the materials

# MoorPy's line library (MoorProps_default.yaml): mass_d2 [kg/m^3] and density [kg/m^3]
# (fibres) or dvol_dnom (wire), its Cd (on the volume-equivalent diameter), Ca, Ca_ax;
# written out independently of config/materials.yaml.
MOORPY = {
    'polyester': (math.sqrt(4 * 679 / (math.pi * 1380)), 2.021, 1.1, 0.15),
    'nylon': (math.sqrt(4 * 585 / (math.pi * 1140)), 1.979, 1.1, 0.15),
    'hmpe': (math.sqrt(4 * 496 / (math.pi * 975)), 1.988, 1.1, 0.15),
    'steel_wire': (1.18, 1.021, 1.0, 0.0),  # Ca, CaAx: a circular cylinder's (MoorPy: none)
}


@pytest.mark.parametrize('name', sorted(MOORPY))
def test_material_coefficients_are_moorpys(name):
    ratio, cd_volume, ca, ca_axial = MOORPY[name]
    props = load_materials().properties(name, D)
    assert props.volume_diameter_ratio == pytest.approx(ratio, rel=1e-12)
    assert props.volume_diameter == pytest.approx(ratio * D, rel=1e-12)
    # MoorPy's Cd on dv, converted to the nominal diameter: the same force per metre
    assert props.normal_drag_coefficient == pytest.approx(cd_volume * ratio, rel=1e-12)
    assert props.tangential_drag_coefficient == 0.0  # MoorPy gives no Cd_ax for ropes
    assert props.normal_added_mass_coefficient == ca
    assert props.tangential_added_mass_coefficient == ca_axial


def test_material_coefficients_in_round_figures():
    """The figures water.md and the README quote: Cd 1.600 for fibres, 1.205 for wire."""
    materials = load_materials()
    for name in ('polyester', 'nylon', 'hmpe', 'manila'):
        assert materials.properties(name, D).normal_drag_coefficient == pytest.approx(
            1.600, abs=5e-4), name
    assert materials.properties('steel_wire', D).normal_drag_coefficient == pytest.approx(
        1.205, abs=5e-4)
    # manila: an estimated density of 1480 kg/m^3
    manila = materials.properties('manila', 0.048)
    assert manila.volume_diameter_ratio == pytest.approx(
        math.sqrt(4 * 1.52 / (math.pi * 1480)) / 0.048, rel=1e-4)
    # by the nominal diameter a 64 mm polyester rope would float (issue 11); by its volume
    # diameter it sinks, as polyester (1380 kg/m^3) does
    polyester = materials.properties('polyester', D)
    assert polyester.mass_per_length < 1025 * math.pi / 4 * D ** 2
    assert polyester.mass_per_length > 1025 * math.pi / 4 * polyester.volume_diameter ** 2


# ------------------------------------------------------------------------ the model


def test_simulator_takes_the_materials_coefficients():
    sim = OneLine(from_values({'water_level': 0.0, 'material': 'hmpe'}))
    material = load_materials().properties('hmpe', D)
    line_type = sim.props.line_type
    assert line_type.diameter == D
    assert line_type.volume_diameter == pytest.approx(material.volume_diameter)
    assert line_type.normal_drag == pytest.approx(material.normal_drag_coefficient)
    assert line_type.tangential_drag == material.tangential_drag_coefficient == 0.0
    assert line_type.normal_added_mass == 1.1 and line_type.tangential_added_mass == 0.15
    env = sim.environment
    assert env.water_level == 0.0 and env.water_density == 1025.0
    assert env.seabed_level == -math.inf and env.air_density == 1.225
    # explicit values beat the material's, 0 included
    sim = OneLine(from_values({
        'water_level': 5.0, 'normal_drag_coefficient': 1.2, 'tangential_drag_coefficient': 0,
        'normal_added_mass_coefficient': 0.0, 'tangential_added_mass_coefficient': 0.5,
        'volume_diameter': D, 'seabed_level': -60.0, 'seabed_friction': 0.5,
        'quay_edge': [3.0, -1.0, 2.0], 'quay_normal': [0.0, 2.0, 0.0], 'quay_depth': 8.0,
        'payload_mass': 500.0, 'payload_volume': 0.2, 'payload_drag_area': 0.3}))
    line_type = sim.props.line_type
    assert (line_type.normal_drag, line_type.tangential_drag) == (1.2, 0.0)
    assert (line_type.normal_added_mass, line_type.tangential_added_mass) == (0.0, 0.5)
    assert line_type.volume_diameter == D
    env = sim.environment
    assert (env.seabed_level, env.seabed_friction, env.quay_depth) == (-60.0, 0.5, 8.0)
    assert env.quay_edge == (3.0, -1.0, 2.0) and env.quay_normal == (0.0, 1.0, 0.0)
    sim.push_fairlead(0.0, [0.0, 0.0, 10.0])
    sim.start(0.0)
    assert sim.system.lines[0].line_type == line_type  # what the physics steps with
    assert sim.system.environment == env
    payload = sim.system.points[0]
    assert (payload.kind, payload.mass, payload.volume) == ('free', 500.0, 0.2)
    assert (payload.drag_area, payload.added_mass) == (0.3, 0.5)


def test_weight_for_the_start_shape_is_less_the_fluids_buoyancy():
    sim = OneLine(from_values({'water_level': 0.0}))
    props, material = sim.props, sim.material
    area = math.pi / 4 * material.volume_diameter ** 2
    assert props.weight_per_length(sim.environment) == pytest.approx(
        (material.mass_per_length - 1.225 * area) * 9.81, rel=1e-12)
    assert props.submerged_weight_per_length(sim.environment) == pytest.approx(
        (material.mass_per_length - 1025.0 * area) * 9.81, rel=1e-12)


def test_current_changes_at_run_time_without_a_restart():
    fairlead = np.array([30.0, 0.0, -5.0])
    sim = OneLine(from_values({'water_level': 5.0, 'segments': 10, 'length': 40.0}))
    sim.push_fairlead(0.0, fairlead)
    sim.push_fairlead(100.0, fairlead)
    sim.start(0.0)
    sim.advance_to(2.0)
    system, before = sim.system, sim.rope.x.copy()
    sim.check_update({'current': [0.0, 1.0, 0.0]})
    sim.update({'current': [0.0, 1.0, 0.0]})
    assert sim.system is system  # the same rope goes on
    assert np.array_equal(sim.rope.x, before)
    assert system.environment.current == (0.0, 1.0, 0.0)
    assert sim.params.current == [0.0, 1.0, 0.0]
    sim.advance_to(20.0)
    # the cross current carries the middle of the line along +y, by metres
    sideways = sim.rope.x[5, 1]
    assert sideways > 1.0, f'the line moved {sideways} m with the current'
    assert sim.system is system


# --------------------------------------------------------------- ROS descriptors


@pytest.fixture
def ros_context():
    context = rclpy.Context()
    yield context
    if context.ok():
        rclpy.shutdown(context=context)


def test_descriptors_declare_on_an_rclpy_node(ros_context, tmp_path):
    """Every parameter declares with its descriptor; -.inf comes through a ROS params file."""
    path = tmp_path / 'params.yaml'
    path.write_text('/**/mooring_line:\n  ros__parameters:\n    seabed_level: -.inf\n'
                    '    water_level: 3.5\n    normal_drag_coefficient: -1.0\n'
                    '    current: [0.25, 0.0, 0.0]\n')
    rclpy.init(args=['--ros-args', '--params-file', str(path)], context=ros_context,
               signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('mooring_line', context=ros_context)
    try:
        for name, spec in SPECS.items():
            node.declare_parameter(name, spec.default, describe(name, spec))
        assert node.get_parameter('seabed_level').value == -math.inf
        assert node.get_parameter('water_level').value == 3.5
        assert list(node.get_parameter('current').value) == [0.25, 0.0, 0.0]
        assert node.get_parameter('tangential_drag_coefficient').value == -1.0
        described = node.describe_parameter('water_level')
        assert described.read_only and 'or -.inf (no water)' in described.additional_constraints
        assert not described.floating_point_range  # no range holds -inf
        coefficient = node.describe_parameter('normal_drag_coefficient')
        assert coefficient.floating_point_range[0].from_value == -1.0
        # run time: current is settable, the levels are not
        assert node.set_parameters([Parameter('current', value=[0.0, 0.5, 0.0])])[0].successful
        refused = node.set_parameters([Parameter('water_level', value=-math.inf)])[0]
        assert not refused.successful and 'read-only' in refused.reason
        # rclpy itself refuses a drag coefficient below the range's -1
        with pytest.raises(ParameterException):
            node2 = rclpy.create_node('other', context=ros_context)
            try:
                node2.declare_parameter('normal_drag_coefficient', -3.0,
                                        describe('normal_drag_coefficient',
                                                 SPECS['normal_drag_coefficient']))
            finally:
                node2.destroy_node()
    finally:
        node.destroy_node()


def test_params_file_round_trip(tmp_path):
    """A file written with -inf levels (as the bags store parameters) reads back the same."""
    params = from_values({'seabed_level': -12.0, 'current': [0.1, 0.2, 0.0]})
    text = parameters_yaml(single_line(params))
    assert stored(single_line(params)) == {LINE_PARAMETERS_KEY: text}
    assert 'water_level: -.inf' in text
    assert from_stored({LINE_PARAMETERS_KEY: text}) == single_line(params)
    path = tmp_path / 'stored.yaml'
    path.write_text(text)
    assert from_values(read_params_file(path)) == params


def test_one_environment_per_mooring_its_lines_systems_and_ship_read_it(repo_root):
    # (issue: the environment was copied into every line, and the ship's current was the
    # last updated line's)
    setup = read_setup(repo_root / 'config' / 'berth.yaml',
                       {'ship_mode': 'free', 'segments': 8})
    driver = Driver(setup)
    driver.start_free(0)
    mooring = driver.mooring
    assert not {f.name for f in fields(RopeProperties)} & {f.name for f in fields(Environment)}
    assert all(group.system.environment is mooring.environment for group in mooring.groups)
    assert not driver.advance(0.0).outputs[-1].output.ship_loads[:2].any()
    driver.update(None, {'current': [0.0, -0.5, 0.0], 'wind_speed': 12.0})
    changed = mooring.environment
    assert changed.current == (0.0, -0.5, 0.0) and changed.wind.speed == 12.0
    assert changed.depth == 16.0  # the berth's: 0 - (-16)
    assert all(group.system.environment is changed for group in mooring.groups)
    assert driver.arrangement.shared.current == [0.0, -0.5, 0.0]
    assert all(line.params.current == [0.0, -0.5, 0.0] for line in driver.arrangement.lines)
    assert driver.arrangement.ship.wind_speed == 12.0
    mooring.advance_to(0.1)
    wind, current, _ = mooring.output().ship_loads
    assert wind[0] < 0.0  # from ahead (wind_direction 0): pushes the ship astern
    assert current[1] < 0.0  # the current goes to -y: off the quay
