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
A ship's mooring arrangement: the parameters of many lines, each under its own name.

`lines` names the lines (`lines: [head_1, head_2, ...]`); each line's settings are the
single-line node's parameters (params.SPECS) under its name, `head_1.material`,
`head_1.fairlead_offset`, with the same meanings, ranges and messages, plus `pretension`
(OWN_SPECS). The settings one System must share to step every line in one call (SHARED:
the water, air, seabed and quay, gravity, the integrator and its step, the frame, the
rates, the recording) stay at the top level under their single-line names; a line that
sets one is refused. Every other parameter of params.SPECS is a line's own, so a parameter
added there appears per line without a change here. A line's own setting given at the top
level (`segments: 50`) is the default of every line that does not set it.

Each line must say where it is: `fairlead_offset` (in the ship's body frame),
`bollard_position` (in frame_id; not needed for a payload line) and `length` or
`pretension` (the length is then chosen at the first ship pose so that the line starts
with that fairlead tension). Every error is one line naming the parameter and what is
allowed. No ROS and no files here beyond reading a parameter file.
"""

from dataclasses import dataclass, replace
import difflib
import os
from typing import Any, Dict, List, Mapping, Optional, Tuple

import yaml

from .bollards import (bollard_setup, BOLLARDS, BollardSetup, check_bollard_names,
                       check_bollard_value, find_bollard)
from .files import read_params_file
from .names import check_setting, NAME, NAME_RULE
from .ship import (check_current_tables, check_fender_names, check_passing_clear,
                   CURRENT_TABLES, fender_setup, FENDER_SPECS, FENDERS, FenderSetup, field_name,
                   PASSING_SHIP, passing_ship, PASSING_SPECS, PassingShipParams, SHIP,
                   SHIP_SPECS, ShipParams, tables_relative_to, WAVES)
from .table import allowed, check, LineParams, ParameterError, Spec, SPECS
from .table import NODE_NAME as LINE_NODE_NAME

NODE_NAME = 'mooring'
LINES = 'lines'
# custom_data keys of metadata.yaml under which a bag stores the parameters it was made with:
# a single line's (the mooring_line node's parameter file) and an arrangement's.
LINE_PARAMETERS_KEY = 'rope_sim_ros.parameters'
PARAMETERS_KEY = 'rope_sim_ros.arrangement'
# Shared by every line: one Environment, one integrator and step (one kernel call steps them
# all), one frame and output grid, one ship pose stream and one bag.
SHARED = ('gravity', 'water_level', 'water_density', 'air_density', 'current', 'seabed_level',
          'seabed_stiffness', 'seabed_damping', 'seabed_friction', 'quay_edge', 'quay_normal',
          'quay_depth', 'integrator', 'time_step', 'end_interpolation', 'frame_id',
          'publish_rate', 'teleport_distance', 'record_path', 'pose_reliability')
# A line's own parameters beyond the single-line node's.
OWN_SPECS: Mapping[str, Spec] = {
    'pretension': Spec(
        0.0, 'N', 'fairlead tension the line starts with: > 0 chooses its unstretched length '
        'at the first ship pose (on the elastic catenary in air between its ends; give no '
        'length then); 0 = the line has its length', 0.0, 1.0e9),
    'bollard': Spec(
        '', '', 'the bollard (one of bollards) the line is, or will be, made fast to: its '
        'position is then the bollard_position; settable while the line is not fast; empty = '
        'the line has its own bollard_position', read_only=False),
}
LINE_SPECS: Mapping[str, Spec] = {
    **{name: spec for name, spec in SPECS.items() if name not in SHARED}, **OWN_SPECS}
# The arrangement's own top-level parameters (besides `lines`).
ARRANGEMENT_SPECS: Mapping[str, Spec] = {
    'ship_frame_id': Spec(
        'base_link', '', "the ship's body frame (x forward, y to port, z up): header.frame_id "
        'of ship/mooring_wrench; ship/pose gives its pose in frame_id'),
    'marker_rate': Spec(
        10.0, 'Hz', 'rate of mooring/markers (the lines and their utilisation for RViz and '
        'Foxglove)', 0.0, 100.0, low_open=True, read_only=False),
}
LINES_DESCRIPTION = ('names of the mooring lines; each line has its settings under its name '
                     '(head_1.material, head_1.fairlead_offset, ...) and its topics in its '
                     'namespace (head_1/fairlead/tension, ...)')
LINE_NAME_RULE = f'{NAME_RULE} (it becomes a parameter prefix and a topic namespace)'
MAX_LINES = 64
# Names a line or a fender cannot take: the prefixes of the ship's own parameters.
RESERVED = (SHIP, PASSING_SHIP, WAVES)
# What a line must set itself (or take from a top-level default): where it is.
REQUIRED = {
    'fairlead_offset': "m, in the ship's body frame",
    'bollard_position': 'm, in frame_id',
}


@dataclass(frozen=True)
class LineSetup:
    """
    One line of the arrangement.

    :ivar name: its name (parameter prefix and topic namespace).
    :ivar params: its parameters: the shared ones and its own.
    :ivar pretension: > 0: the fairlead tension its length is chosen for [N]; 0: it has
        params.length.
    :ivar bollard: the bollard it is made fast to, by name (params.bollard_position is its
        position); '': its own bollard_position.
    """

    name: str
    params: LineParams
    pretension: float = 0.0
    bollard: str = ''


@dataclass(frozen=True)
class ArrangementParams:
    """
    Validated parameters of an arrangement.

    :ivar lines: the lines, in the order of `lines`.
    :ivar shared: the SHARED values (the lines' too; its other fields are the defaults).
    :ivar ship_frame_id: the ship's body frame.
    :ivar marker_rate: rate of mooring/markers [Hz].
    :ivar ship: the ship (driven or free) and its body.
    :ivar fenders: the fenders on the quay, in the order of `fenders`.
    :ivar passing: the ship passing the moored one (passing_ship.*; speed 0: none).
    :ivar bollards: the bollards on the quay, in the order of `bollards`.
    """

    lines: Tuple[LineSetup, ...]
    shared: LineParams
    ship_frame_id: str = ARRANGEMENT_SPECS['ship_frame_id'].default
    marker_rate: float = ARRANGEMENT_SPECS['marker_rate'].default
    ship: ShipParams = ShipParams()
    fenders: Tuple[FenderSetup, ...] = ()
    passing: PassingShipParams = PassingShipParams()
    bollards: Tuple[BollardSetup, ...] = ()

    @property
    def single(self) -> bool:
        """Tell whether this is the one unnamed line of the mooring_line node (single_line)."""
        return len(self.lines) == 1 and not self.lines[0].name

    @property
    def names(self) -> List[str]:
        """Return the line names, in order."""
        return [line.name for line in self.lines]

    def line(self, name: str) -> LineSetup:
        """Return the line of that name (KeyError if there is none)."""
        for line in self.lines:
            if line.name == name:
                return line
        raise KeyError(name)

    def values(self) -> Dict[str, Any]:
        """
        Return every value as a parameter file holds it.

        `lines`, the top-level values, and each line's own under its name (nested).
        """
        values: Dict[str, Any] = {LINES: self.names}
        values.update({name: getattr(self.shared, name) for name in SHARED})
        values['ship_frame_id'] = self.ship_frame_id
        values['marker_rate'] = self.marker_rate
        for name, value in [*self.ship.values().items(), *self.passing.values().items()]:
            prefix, dot, own = name.partition('.')
            if dot:  # nested as the lines' settings are
                values.setdefault(prefix, {})[own] = value
            else:
                values[name] = value
        for key, parts in ((FENDERS, self.fenders), (BOLLARDS, self.bollards)):
            if parts:
                values[key] = [part.name for part in parts]
                for part in parts:
                    values[part.name] = part.values()
        for line in self.lines:
            own = {name: value for name, value in line.params.as_dict().items()
                   if name not in SHARED}
            if line.pretension > 0.0:  # the length it is given at the start
                del own['length']
                own['pretension'] = line.pretension
            if line.bollard:  # its position is the bollard's
                del own['bollard_position']
                own['bollard'] = line.bollard
            values[line.name] = own
        return values

    def with_line(self, name: str, params: LineParams) -> 'ArrangementParams':
        """Return a copy with one line's parameters replaced."""
        lines = tuple(replace(line, params=params) if line.name == name else line
                      for line in self.lines)
        return replace(self, lines=lines)

    def with_bollard(self, name: str, bollard: str) -> 'ArrangementParams':
        """
        Return a copy with line `name` made fast to another bollard ('': its own position).

        :raises ParameterError: no bollard has that name (the nearest one is named).
        """
        line = self.line(name)
        params = line.params
        if bollard:
            position = find_bollard(self.bollards, bollard, f"parameter '{name}.bollard'")
            params = replace(params, bollard_position=list(position.position))
        lines = tuple(replace(line, params=params, bollard=bollard) if line.name == name
                      else line for line in self.lines)
        return replace(self, lines=lines)

    def with_shared(self, values: Mapping[str, Any]) -> 'ArrangementParams':
        """Return a copy with SHARED values changed: its own and every line's (checked)."""
        if not values:
            return self
        lines = tuple(replace(line, params=line.params.with_values(values))
                      for line in self.lines)
        return replace(self, shared=self.shared.with_values(values), lines=lines)


def flatten(values: Mapping[str, Any], prefix: str = '') -> Dict[str, Any]:
    """Return nested parameter maps as ROS names them: {'a': {'length': 40}} -> a.length."""
    flat: Dict[str, Any] = {}
    for key, value in values.items():
        name = f'{prefix}{key}'
        if isinstance(value, Mapping):
            flat.update(flatten(value, name + '.'))
        else:
            flat[name] = value
    return flat


def check_line_names(value: Any) -> List[str]:
    """
    Validate the `lines` parameter: 1 to MAX_LINES distinct names.

    :raises ParameterError: missing, empty, not a list of names, a bad or repeated name.
    """
    if value is None:
        raise ParameterError(f'parameter {LINES!r} is missing: list the lines by name, e.g. '
                             f'{LINES}: [head_1, spring_1, stern_1]')
    if isinstance(value, str) or not isinstance(value, (list, tuple)) or not value:
        raise ParameterError(f'parameter {LINES!r} = {value!r} is not allowed: must be a list '
                             f'of 1 to {MAX_LINES} line names')
    if len(value) > MAX_LINES:
        raise ParameterError(f'parameter {LINES!r} names {len(value)} lines: at most '
                             f'{MAX_LINES} are allowed')
    names = []
    for name in value:
        if not isinstance(name, str) or not NAME.match(name):
            raise ParameterError(f'line name {name!r} in {LINES!r} is not allowed: '
                                 f'{LINE_NAME_RULE}')
        if name in names:
            raise ParameterError(f'line name {name!r} appears twice in {LINES!r}')
        if name in LINE_SPECS or name in SPECS or name in ARRANGEMENT_SPECS or \
                name in SHIP_SPECS or name in RESERVED or name in (FENDERS, BOLLARDS):
            raise ParameterError(f'line name {name!r} in {LINES!r} is not allowed: it is the '
                                 'name of a parameter')
        names.append(name)
    return names


def check_line_value(line: str, name: str, value: Any) -> Any:
    """
    Validate one setting of a line; return it in its canonical type.

    :raises ParameterError: a shared parameter, an unknown one or a bad value, named with
        the line (`head_1.length`).
    """
    if name in SHARED:
        raise ParameterError(f"parameter '{line}.{name}' is not allowed: {name} is shared by "
                             'every line (one system steps them together): set it at the top '
                             'level')
    if name not in LINE_SPECS:
        found = difflib.get_close_matches(name, list(LINE_SPECS), n=1, cutoff=0.6)
        near = f'did you mean {line}.{found[0]}?' if found else f'see {line}.length'
        raise ParameterError(f'unknown parameter {line}.{name}: not a line setting; {near} '
                             '(docs/parameters.md lists them)')
    try:
        return check(name, value, LINE_SPECS)
    except ParameterError as e:
        raise ParameterError(str(e).replace(f'parameter {name!r}', f'parameter '
                                            f'{line + "." + name!r}', 1)) from None


def check_top_value(name: str, value: Any) -> Any:
    """
    Validate one top-level value: a shared parameter, a line default or the arrangement's own.

    :raises ParameterError: an unknown name or a bad value, named.
    """
    if name in ARRANGEMENT_SPECS:
        return check(name, value, ARRANGEMENT_SPECS)
    if name == CURRENT_TABLES:  # a path, or tables by depth
        return check_current_tables(value)
    if name in SHIP_SPECS:
        return check(name, value, SHIP_SPECS)
    if name in PASSING_SPECS:
        return check(name, value, PASSING_SPECS)
    if name in SPECS or name in OWN_SPECS:
        return check(name, value, {**SPECS, **OWN_SPECS})
    for prefix, specs in ((SHIP, SHIP_SPECS), (PASSING_SHIP, PASSING_SPECS),
                          (WAVES, SHIP_SPECS)):
        if name.startswith(prefix + '.'):
            raise ParameterError(f'unknown parameter {name!r}; {prefix} takes: '
                                 f'{", ".join(n for n in specs if n.startswith(prefix + "."))}')
    raise ParameterError(
        f'unknown parameter {name!r}: not a shared parameter ({", ".join(SHARED)}), a line '
        f'setting, nor one of {LINES}, {FENDERS}, {", ".join(ARRANGEMENT_SPECS)}, '
        f'{", ".join(n for n in SHIP_SPECS if "." not in n)}, ship.*; a line takes its own '
        'settings under its name, e.g. head_1.length')


def check_fender_value(fender: str, name: str, value: Any) -> Any:
    """Validate one setting of a fender; return it in its canonical type."""
    return check_setting('fender', fender, name, value, FENDER_SPECS)


def from_values(values: Mapping[str, Any]) -> ArrangementParams:
    """
    Validate an arrangement's parameter values (flat `head_1.length` names or nested maps).

    :raises ParameterError: the first thing wrong, in one line: `lines` missing or bad, a
        setting for a line not in `lines`, an unknown or bad value, a line without
        fairlead_offset, bollard_position, or length or pretension.
    """
    flat = flatten(values)
    names = check_line_names(flat.get(LINES))
    fender_names = check_fender_names(flat.get(FENDERS), names)
    bollard_names = check_bollard_names(flat.get(BOLLARDS), names + fender_names)
    top: Dict[str, Any] = {}
    own: Dict[str, Dict[str, Any]] = {name: {} for name in names}
    fenders: Dict[str, Dict[str, Any]] = {name: {} for name in fender_names}
    bollard_values: Dict[str, Dict[str, Any]] = {name: {} for name in bollard_names}
    for key, value in flat.items():
        if key in (LINES, FENDERS, BOLLARDS):
            continue
        line, dot, name = key.partition('.')
        if not dot or line in RESERVED:
            top[key] = check_top_value(key, value)
        elif line in own:
            own[line][name] = check_line_value(line, name, value)
        elif line in fenders:
            fenders[line][name] = check_fender_value(line, name, value)
        elif line in bollard_values:
            bollard_values[line][name] = check_bollard_value(line, name, value)
        else:
            raise ParameterError(f'parameter {key!r} is for no line: {LINES} are '
                                 f'{", ".join(names)}; {FENDERS}: '
                                 f'{", ".join(fender_names) or "none"}; {BOLLARDS}: '
                                 f'{", ".join(bollard_names) or "none"}')
    shared_values = {k: v for k, v in top.items() if k in SHARED}
    shared = LineParams().with_values(shared_values)
    bollards = tuple(bollard_setup(name, bollard_values[name]) for name in bollard_names)
    setups = tuple(_line_setup(name, {k: v for k, v in top.items() if k in LINE_SPECS},
                               own[name], shared_values, bollards) for name in names)
    ship = ShipParams(**{field_name(k): v for k, v in top.items() if k in SHIP_SPECS})
    passing = passing_ship({k: v for k, v in top.items() if k in PASSING_SPECS})
    check_passing_clear(ship, passing)
    return ArrangementParams(
        setups, shared,
        top.get('ship_frame_id', ARRANGEMENT_SPECS['ship_frame_id'].default),
        top.get('marker_rate', ARRANGEMENT_SPECS['marker_rate'].default), ship,
        tuple(fender_setup(name, fenders[name]) for name in fender_names), passing, bollards)


def _line_setup(name: str, defaults: Dict[str, Any], own: Dict[str, Any],
                shared: Dict[str, Any], bollards: Tuple[BollardSetup, ...]) -> LineSetup:
    """
    Return one line's setup: shared values, then the defaults, then its own values.

    A line's bollard, by name, gives its bollard_position (its own or the default one).
    """
    values = {**defaults, **own}
    bollard = values.pop('bollard', '')
    if bollard:
        if 'bollard_position' in own and 'bollard' in own:
            raise ParameterError(f'line {name!r} sets both bollard and bollard_position: give '
                                 f'one ({name}.bollard names a bollard, which has a position)')
        values['bollard_position'] = list(
            find_bollard(bollards, bollard, f"parameter '{name}.bollard'").position)
    missing = [f'{name}.{key} ({unit})' for key, unit in REQUIRED.items()
               if key not in values
               and not (key == 'bollard_position' and values.get('payload_mass', 0.0) > 0.0)]
    # its own length or pretension wins over the top-level defaults; its own length wins over
    # its own pretension: a parameter dump of a started node has both, the length the
    # pretension chose, and must restart the same line
    pretension = 0.0 if 'length' in own else values.pop('pretension', 0.0)
    values.pop('pretension', None)
    if pretension > 0.0 and values.get('payload_mass', 0.0) > 0.0:
        raise ParameterError(f'line {name!r} has a payload and a pretension: a payload hangs '
                             f'under its own weight; give {name}.length (m)')
    if pretension > 0.0 and values.get('start_state') == 'stowed':
        raise ParameterError(f'line {name!r} starts stowed and has a pretension: a pretension '
                             f'chooses the length of a line that starts fast; give '
                             f'{name}.length (m), and heave it to a tension once made fast '
                             '(winch_mode constant_tension)')
    if 'length' not in values and pretension <= 0.0:
        missing.append(f'{name}.length (m) or {name}.pretension (N)')
    if missing:
        raise ParameterError(f'line {name!r} is missing settings: set {"; ".join(missing)}')
    if pretension > 0.0:
        values.pop('length', None)  # a top-level default length gives way to the pretension
    return LineSetup(name, LineParams().with_values({**shared, **values}), float(pretension),
                     bollard)


def single_line(params: LineParams) -> ArrangementParams:
    """
    Return the arrangement of one line of the mooring_line node: a mooring of that line.

    Its line has no name (its topics sit at the namespace root, its messages name no line)
    and its parameters are the shared ones too.
    """
    return ArrangementParams((LineSetup('', params),), params)


def is_arrangement_file(path) -> bool:
    """
    Tell whether a parameter file holds an arrangement: `lines` for the mooring node.

    A `/**:` section reaches every node: it is an arrangement only with `lines` in it.
    """
    try:
        return LINES in read_params_file(path, NODE_NAME)
    except ParameterError:
        return False


def read_setup(path, overrides: Optional[Mapping[str, Any]] = None) -> ArrangementParams:
    """
    Read a parameter file as the node it is for does: an arrangement, or a single line.

    :param path: a mooring node's file (with `lines`), or a mooring_line node's; None: the
        single line's defaults.
    :param overrides: values on top (`--set`): a line's own names for a single line,
        `head_1.length` for an arrangement.
    :raises ParameterError: unreadable file, no section for either node, a bad value.
    """
    overrides = dict(overrides or {})
    if path is not None and is_arrangement_file(path):
        setup = from_values({**flatten(read_params_file(path, NODE_NAME)), **overrides})
        return with_tables_from(setup, os.path.dirname(os.path.abspath(path)))
    values = read_params_file(path, LINE_NODE_NAME) if path is not None else {}
    return single_line(LineParams().with_values({**values, **overrides}))


def with_tables_from(setup: ArrangementParams, folder: str) -> ArrangementParams:
    """Return the setup with its ship's tables, mesh and database absolute, from `folder`."""
    ship = setup.ship
    tables = {name: tables_relative_to(getattr(ship, name), folder)
              for name in ('wind_coefficients', 'current_coefficients', 'mesh', 'hydrodynamics')}
    tables = {name: value for name, value in tables.items() if value != getattr(ship, name)}
    return replace(setup, ship=replace(ship, **tables)) if tables else setup


def read_arrangement_file(path) -> ArrangementParams:
    """
    Read and validate the `mooring: ros__parameters:` section of a ROS parameter file.

    :raises ParameterError: unreadable file, no such section, or a bad value (one line).
    """
    return from_values(read_params_file(path, NODE_NAME))


def parameters_yaml(arrangement: ArrangementParams) -> str:
    """Return the arrangement as a one-line ROS parameter file (stored in bags)."""
    if arrangement.single:
        node, values = LINE_NODE_NAME, arrangement.lines[0].params.as_dict()
    else:
        node, values = NODE_NAME, arrangement.values()
    values.pop('record_path', None)
    return yaml.safe_dump({node: {'ros__parameters': values}}, default_flow_style=True,
                          sort_keys=True, width=2**31).strip()


def stored(arrangement: ArrangementParams) -> Dict[str, str]:
    """Return the custom_data of a bag made with these parameters: {key: parameters_yaml}."""
    key = LINE_PARAMETERS_KEY if arrangement.single else PARAMETERS_KEY
    return {key: parameters_yaml(arrangement)}


def from_stored(custom_data: Mapping[str, Any],
                overrides: Optional[Mapping[str, Any]] = None) -> Optional[ArrangementParams]:
    """
    Return the parameters a bag stores in its custom_data (either kind), or None.

    :param overrides: values applied on top (--set): a line's own names for a single line,
        `head_1.length` for an arrangement.
    :raises ParameterError: the text is not a stored parameter file, or a value is not
        allowed.
    """
    for key, node in ((PARAMETERS_KEY, NODE_NAME), (LINE_PARAMETERS_KEY, LINE_NODE_NAME)):
        text = custom_data.get(key)
        if not text:
            continue
        try:
            values = yaml.safe_load(text)[node]['ros__parameters']
        except (yaml.YAMLError, KeyError, TypeError):
            values = None
        if not isinstance(values, dict):
            raise ParameterError(f'stored parameters are not a parameter map: {text[:80]!r}')
        values = {**flatten(values), **(overrides or {})}
        if node == LINE_NODE_NAME:
            return single_line(LineParams().with_values(values))
        return from_values(values)
    return None


def describe_own(name: str) -> Tuple[Spec, str]:
    """Return the Spec and the allowed text of a line setting or an arrangement parameter."""
    spec = LINE_SPECS.get(name) or ARRANGEMENT_SPECS[name]
    return spec, allowed(spec)
