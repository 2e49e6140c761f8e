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
The nodes' parameters as ROS declares them: one table (params/), two kinds of node.

The mooring_line node declares every parameter of the line table (params/table.py) under
its own name; the mooring node declares `lines`, the settings its lines share at the top
level, its own (ship_frame_id, marker_rate) and each line's settings under the line's name
(`head_1.length`), with the same descriptors: description, unit, range, read-only.

One rule for a name the node does not know: a name meant for it is refused with the nearest
name, as the offline commands refuse it: one under one of its lines or its ship
(`head_1.lenght`, `ship.mas`), or one as near one of its names as a typo is (`wind_sped`).
Any other is warned about and left alone, because a parameter file's `/**:` section gives
every node every parameter in it, its neighbours' too.
"""

import array
import difflib
import math
from typing import Any, Dict, List, Optional, Tuple

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor, ParameterType
from rclpy.parameter import Parameter

from ..messages.topics import Layout, LINE_NODE
from ..params import arrangement
from ..params.arrangement import (ARRANGEMENT_SPECS, ArrangementParams, LINE_SPECS, LINES,
                                  LINES_DESCRIPTION, OWN_SPECS, SHARED, single_line)
from ..params.bollards import BOLLARD_SPECS, BOLLARDS, BOLLARDS_DESCRIPTION
from ..params.ship import (FENDER_SPECS, FENDERS, FENDERS_DESCRIPTION, PASSING_SHIP, PASSING_SPECS,
                           SHIP, SHIP_SETTINGS, SHIP_SPECS, WAVES)
from ..params.table import allowed, check, LineParams, ParameterError, Spec, SPECS

# Parameters rclpy itself declares or reads; not ours to warn about.
ROS_PARAMETERS = ('use_sim_time', 'start_type_description_service')


class StartupError(Exception):
    """The node cannot start with these parameters; the message names the culprit."""


def describe(name: str, spec: Spec) -> ParameterDescriptor:
    """Return the ParameterDescriptor of one parameter of the table."""
    unit = f' [{spec.unit}]' if spec.unit else ''
    descriptor = ParameterDescriptor(
        name=name,
        type=Parameter.Type.from_parameter_value(spec.default).value,
        description=spec.description + unit,
        additional_constraints=allowed(spec),
        read_only=spec.read_only)
    if _is_number(spec.default) and spec.low is not None and spec.high is not None:
        if isinstance(spec.default, int):
            descriptor.integer_range = [
                IntegerRange(from_value=int(spec.low), to_value=int(spec.high), step=1)]
        else:
            # the range must hold the special value too (-1: the material's), or rclpy
            # refuses it; a level's -inf (none) gets no range: additional_constraints says it
            low = spec.low if spec.special is None else min(spec.low, spec.special)
            if math.isfinite(low):
                descriptor.floating_point_range = [
                    FloatingPointRange(from_value=float(low), to_value=float(spec.high))]
    return descriptor


def arrangement_text(text: str, line: str = '<line>') -> str:
    """Return a line parameter's description as the mooring node's topics name things."""
    return (text.replace('fairlead/pose', 'ship/pose')
            .replace('bollard/pose', f'{line}/bollard/pose')
            .replace('winch/command', f'{line}/winch/command'))


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def plain(value: Any) -> Any:
    """Return a parameter value as the checks expect it (arrays as lists)."""
    if hasattr(value, 'tolist'):
        return value.tolist()
    if isinstance(value, (array.array, tuple, list)):
        return list(value)
    return value


# A name at least this near one of the node's (difflib's ratio) is a typo of it: 'wind_sped'
# is 0.95 from 'wind_speed', 'lenght' 0.83 from 'length'; 'publish_frequency', another node's
# parameter, 0.69 from 'publish_rate'.
TYPO = 0.8


def refuse_or_warn(name: str, known, warn, hint: str = '') -> None:
    """
    Refuse a name that is a typo of one of `known`; warn of any other unknown name.

    :raises ParameterError: the name is a typo, naming the one meant.
    """
    meant = difflib.get_close_matches(name, list(known), n=1, cutoff=TYPO)
    if meant:
        raise ParameterError(f'unknown parameter {name!r}; did you mean {meant[0]!r}?')
    warn(f'ignoring unknown parameter {name!r}{nearest(name, known)}{hint}')


def nearest(name: str, known) -> str:
    """Say which known name a mistyped one is nearest to ('' when none is near)."""
    found = difflib.get_close_matches(name, list(known), n=1, cutoff=0.6)
    return f'; did you mean {found[0]!r}?' if found else ''


class NodeParameters:
    """The parameters of one kind of node (see the module docstring)."""

    def __init__(self, layout: Layout):
        """Take the layout of the node kind (LINE_NODE or MOORING_NODE)."""
        self.layout = layout
        self.line_names: List[str] = []

    @property
    def single(self) -> bool:
        """Tell whether these are the mooring_line node's (one line, its own names)."""
        return self.layout is LINE_NODE

    def spec_of(self, name: str) -> Optional[Spec]:
        """Return the Spec of one of the node's parameter names (`head_1.length`: length's)."""
        if self.single:
            return SPECS.get(name)
        specs = {**ARRANGEMENT_SPECS, **SPECS, **OWN_SPECS, **SHIP_SPECS, **PASSING_SPECS}
        line, dot, base = name.partition('.')
        if dot and line not in (SHIP, PASSING_SHIP, WAVES):
            if line in self.line_names:
                return LINE_SPECS.get(base)
            return FENDER_SPECS.get(base) or BOLLARD_SPECS.get(base)
        return specs.get(name)

    # -- start ----------------------------------------------------------------------------

    def declare(self, node, overrides: Dict[str, Any], warn) -> ArrangementParams:
        """
        Declare every parameter with its descriptor; return the validated start values.

        :param overrides: the values of --params-file / -p (rclpy's overrides), plain.
        :param warn: warn(text): log a warning.
        :raises StartupError: a value that is not allowed, named.
        """
        given = {name: value for name, value in overrides.items()
                 if name not in ROS_PARAMETERS and not name.startswith('qos_overrides.')}
        try:
            if self.single:
                return self._declare_line(node, given, warn)
            return self._declare_arrangement(node, given, warn)
        except ParameterError as e:
            raise StartupError(str(e)) from None

    def _declare_line(self, node, given: Dict[str, Any], warn) -> ArrangementParams:
        values = {}
        for name, value in given.items():
            if name in SPECS:  # rclpy refuses `length: 40` for a double; the files take it
                values[name] = check(name, self._as_declared(name, value))
            else:
                refuse_or_warn(name, SPECS, warn)
        params = LineParams().with_values(values)
        for name, spec in SPECS.items():
            node.declare_parameter(name, getattr(params, name), describe(name, spec),
                                   ignore_override=True)
        setup = single_line(params)
        self.line_names = setup.names
        return setup

    def _declare_arrangement(self, node, given: Dict[str, Any], warn) -> ArrangementParams:
        names = arrangement.check_line_names(given.get(LINES))
        parts = []  # the fenders' and the bollards' names
        for key in (FENDERS, BOLLARDS):
            listed = given.get(key) or []
            parts += listed if isinstance(listed, list) else []  # (from_values says why)
        ours = {}
        for name, value in given.items():
            line, dot, _ = name.partition('.')
            if name in (LINES, FENDERS, BOLLARDS) or (dot and line in (*names, *parts, SHIP,
                                                                       PASSING_SHIP, WAVES)) or \
                    name in ARRANGEMENT_SPECS or name in SPECS or name in OWN_SPECS or \
                    name in SHIP_SPECS:
                ours[name] = value
            else:
                lined = [f'{line}.{setting}' for line in names for setting in LINE_SPECS]
                known = [LINES, FENDERS, BOLLARDS, *SHARED, *ARRANGEMENT_SPECS, *LINE_SPECS,
                         *SHIP_SPECS, *PASSING_SPECS, *lined]
                refuse_or_warn(name, known, warn, f' (a line takes its settings under its '
                               f'name: {names[0]}.length)')
        setup = arrangement.from_values(ours)
        self.line_names = setup.names
        lines = ParameterDescriptor(name=LINES, type=ParameterType.PARAMETER_STRING_ARRAY,
                                    description=LINES_DESCRIPTION, read_only=True)
        declared: List[Tuple[str, Any, ParameterDescriptor]] = [(LINES, setup.names, lines)]
        declared += [(name, getattr(setup.shared, name), describe(name, SPECS[name]))
                     for name in SHARED]
        declared += [(name, getattr(setup, name), describe(name, spec))
                     for name, spec in ARRANGEMENT_SPECS.items()]
        for name, value in ours.items():  # top-level defaults of the lines' settings
            if name in LINE_SPECS:
                descriptor = describe(name, LINE_SPECS[name])
                descriptor.description = (f"default of every line's {name} (each line's own: "
                                          f'<line>.{name}): '
                                          + arrangement_text(descriptor.description))
                descriptor.read_only = True
                declared.append((name, arrangement.check_top_value(name, value), descriptor))
        ship = {**setup.ship.values(), **setup.passing.values()}
        declared += [(name, ship[name], describe(name, spec))
                     for name, spec in [*SHIP_SPECS.items(), *PASSING_SPECS.items()]]
        for key, parts, specs, description in (
                (FENDERS, setup.fenders, FENDER_SPECS, FENDERS_DESCRIPTION),
                (BOLLARDS, setup.bollards, BOLLARD_SPECS, BOLLARDS_DESCRIPTION)):
            if parts:
                declared.append((key, [part.name for part in parts], ParameterDescriptor(
                    name=key, type=ParameterType.PARAMETER_STRING_ARRAY,
                    description=description, read_only=True)))
            for part in parts:
                values = part.values()
                declared += [(f'{part.name}.{name}', values[name],
                              describe(f'{part.name}.{name}', spec))
                             for name, spec in specs.items()]
        for line in setup.lines:
            values = {**line.params.as_dict(), 'pretension': line.pretension,
                      'bollard': line.bollard}
            for name, spec in LINE_SPECS.items():
                if name == 'length' and line.pretension > 0.0:
                    continue  # chosen at the start (declare_length)
                declared.append((f'{line.name}.{name}', values[name],
                                 self._line_descriptor(line.name, name)))
        node.declare_parameters('', declared, ignore_override=True)
        return setup

    @staticmethod
    def _line_descriptor(line: str, name: str) -> ParameterDescriptor:
        """Return the descriptor of a line's setting `<line>.<name>`."""
        descriptor = describe(f'{line}.{name}', LINE_SPECS[name])
        descriptor.description = arrangement_text(descriptor.description, line)
        return descriptor

    def declare_length(self, node, line: str, length: float) -> None:
        """
        Declare `<line>.length` of a pretensioned line: the length chosen for it at the start.

        Read-only, it shows the length in use, so that a dump of the parameters starts the
        same line again. Declared once: a line started again keeps the first start's.
        """
        name = f'{line}.length'
        if not node.has_parameter(name):
            node.declare_parameter(name, length, self._line_descriptor(line, 'length'),
                                   ignore_override=True)

    def _as_declared(self, name: str, value: Any) -> Any:
        """Return integers given for a double (array) parameter as doubles; else the value."""
        spec = self.spec_of(name)
        value = plain(value)
        default = None if spec is None else spec.default
        if isinstance(default, float) and _is_number(value):
            return float(value)
        if isinstance(default, list) and isinstance(value, list) and all(map(_is_number, value)):
            return [float(v) for v in value]
        return value

    # -- run time -------------------------------------------------------------------------

    def coerce(self, parameters: List[Parameter]) -> List[Parameter]:
        """Pre-set callback's work: integers given for double parameters become doubles."""
        out = []
        for p in parameters:
            spec = self.spec_of(p.name)
            default = None if spec is None else spec.default
            if (isinstance(default, float) and p.type_ == Parameter.Type.INTEGER) or (
                    isinstance(default, list) and p.type_ == Parameter.Type.INTEGER_ARRAY):
                p = Parameter(p.name, value=self._as_declared(p.name, p.value))
            out.append(p)
        return out

    def changes(self, parameters: List[Parameter]) -> Dict[Optional[str], dict]:
        """
        Return validated run-time changes by line (None: every line, a shared one).

        The arrangement's own parameters (marker_rate, stiffness_rate) are validated and left
        out; the wind's and the waves' (SHIP_SETTINGS) are every line's (None), as the Driver
        takes them.

        :raises ParameterError: a bad value, named as the node names it.
        """
        changes: Dict[Optional[str], dict] = {}
        for p in parameters:
            value = plain(p.value)
            if self.single:
                if p.name in SPECS:
                    changes.setdefault(None, {})[p.name] = check(p.name, value)
                continue
            line, dot, base = p.name.partition('.')
            if dot and line in self.line_names:
                changes.setdefault(line, {})[base] = arrangement.check_line_value(
                    line, base, value)
            elif p.name in SHARED or p.name in SHIP_SETTINGS:
                changes.setdefault(None, {})[p.name] = arrangement.check_top_value(p.name, value)
            elif p.name in ARRANGEMENT_SPECS or p.name in SHIP_SPECS:
                arrangement.check_top_value(p.name, value)
        return changes
