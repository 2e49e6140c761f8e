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
docs/parameters.md, written from the one parameter table: nothing in it is typed by hand.

    python -m rope_sim_ros.params.docs > docs/parameters.md

The mooring_line node's parameters are table.SPECS; the mooring node's are `lines`,
arrangement.ARRANGEMENT_SPECS, the SHARED parameters at the top level and each line's
LINE_SPECS (SPECS less SHARED, plus OWN_SPECS's pretension) under its name. Every row gives
the parameter's default, unit, what it allows (table.allowed, the words of its error
messages), whether a change needs a restart, and its description, the same text `ros2 param
describe` shows. test/test_docs.py fails when docs/parameters.md is not what markdown()
returns now. Standard library and params/ only: no ROS, no numpy.
"""

import math
import re
import sys
from typing import Any, Iterable, List, Mapping, Optional, Tuple

from .arrangement import (ARRANGEMENT_SPECS, LINE_NAME_RULE, LINE_SPECS, LINES, LINES_DESCRIPTION,
                          MAX_LINES, NODE_NAME, OWN_SPECS, REQUIRED, SHARED)
from .bollards import (BOLLARD_REQUIRED, BOLLARD_SPECS, BOLLARDS, BOLLARDS_DESCRIPTION,
                       MAX_BOLLARDS)
from .ship import (FENDER_REQUIRED, FENDER_SPECS, FENDERS, FENDERS_DESCRIPTION, MAX_FENDERS,
                   PASSING_SPECS, SHIP_SPECS)
from .table import allowed, NODE_NAME as LINE_NODE_NAME, Spec, SPECS

COMMAND = 'python -m rope_sim_ros.params.docs > docs/parameters.md'
COLUMNS = ('parameter', 'default', 'unit', 'allowed', 'set', 'meaning')
# A '<' that opens what a Markdown renderer would take for an HTML tag (`<topic>`).
TAG_OPEN = re.compile(r'<(?=[A-Za-z/!?])')


def value_text(value: Any) -> str:
    """Write a default as a ROS parameter file holds it (YAML: -.inf, true, [x, y, z])."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, str):
        return value if value else "''"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isinf(value):
            return '-.inf' if value < 0 else '.inf'
        if value == 0.0 or 1e-3 <= abs(value) < 1e5:
            return repr(value)
        return f'{value:.1e}'
    if isinstance(value, (list, tuple)):
        return '[' + ', '.join(value_text(v) for v in value) + ']'
    return str(value)


def cell(text: str) -> str:
    """Return text safe in a Markdown table cell: no column break, emphasis or HTML tag."""
    text = ' '.join(text.split()).replace('|', '\\|').replace('*', '\\*')
    return TAG_OPEN.sub('&lt;', text)


def row(name: str, spec: Spec) -> str:
    """Return the table row of one parameter."""
    unit = f'`{spec.unit}`' if spec.unit else '-'
    return '| ' + ' | '.join((
        f'`{name}`', f'`{value_text(spec.default)}`', unit, cell(allowed(spec)),
        'read-only' if spec.read_only else 'run time', cell(spec.description))) + ' |'


def table(rows: Iterable[str]) -> List[str]:
    """Return a Markdown table of rows under the COLUMNS header."""
    return ['| ' + ' | '.join(COLUMNS) + ' |', '|' + '---|' * len(COLUMNS), *rows]


def spec_rows(specs: Mapping[str, Spec], names: Optional[Iterable[str]] = None) -> List[str]:
    """Return the rows of the named parameters of specs (all of them, in order, by default)."""
    return [row(name, specs[name]) for name in (specs if names is None else names)]


def lines_row() -> str:
    """Return the row of `lines`, the one parameter without a Spec."""
    return '| ' + ' | '.join((
        f'`{LINES}`', '(required)', '-',
        cell(f'a list of 1 to {MAX_LINES} distinct names; {LINE_NAME_RULE}'), 'read-only',
        cell(LINES_DESCRIPTION))) + ' |'


def required_text() -> str:
    """Say in words what every line of an arrangement must set, from arrangement.REQUIRED."""
    settings = [f'`{name}` ({unit})' for name, unit in REQUIRED.items()]
    return ', '.join(settings) + ' and `length` or `pretension`'


def sections() -> List[Tuple[str, List[str]]]:
    """Return the page's sections as (heading line, body lines)."""
    own = [name for name in LINE_SPECS if name not in OWN_SPECS]
    return [
        (f'## {LINE_NODE_NAME}', [
            f"The `{LINE_NODE_NAME}` node, and `rope_sim` given a single line's parameter "
            f'file (`{LINE_NODE_NAME}: ros__parameters:`, as `config/mooring_line.yaml`), '
            f'take these {len(SPECS)} parameters under these names.',
            '',
            *table(spec_rows(SPECS)),
        ]),
        (f'## {NODE_NAME}', [
            f"The `{NODE_NAME}` node, and `rope_sim` given an arrangement's parameter file "
            f'(`{NODE_NAME}: ros__parameters: {LINES}: [...]`, as `config/berth.yaml`). '
            'The format, with an example, is in [arrangements.md](arrangements.md).',
        ]),
        ('### The arrangement', [
            *table([lines_row(), *spec_rows(ARRANGEMENT_SPECS)]),
        ]),
        ('### Shared by every line', [
            'One value for the whole arrangement (one environment, one integrator and step, '
            'one frame and output grid, one pose stream, one bag), set at the top level '
            f'under its `{LINE_NODE_NAME}` name; a line that sets one is refused.',
            '',
            *table(spec_rows(SPECS, SHARED)),
        ]),
        ("### Each line's settings", [
            'Each line takes these under its name, `<line>.<parameter>` (`head_1.length`, '
            'nested in a parameter file), with the meanings, ranges and messages of the '
            f'`{LINE_NODE_NAME}` node. Set at the top level (`segments: 30`), a setting is '
            'the default of every line that does not set its own; such a top-level default '
            f'is read-only. Every line must set, itself or by a default, {required_text()} '
            '(`bollard_position` is not needed when `payload_mass` > 0 or `bollard` names '
            'a bollard, whose position it takes).',
            '',
            *table([*spec_rows(LINE_SPECS, own), *spec_rows(OWN_SPECS)]),
        ]),
        ('### The ship', [
            'Who moves the ship (`ship_mode`), the free ship as a body, its hull for the '
            'fenders and the loads, its coefficient tables, the wind and the waves; the current '
            "is the lines' `current` above. [free_ship.md](free_ship.md), "
            '[ship_loads.md](ship_loads.md) and [waves.md](waves.md) say how each acts.',
            '',
            *table(spec_rows(SHIP_SPECS)),
        ]),
        ('### The fenders', [
            *table([fenders_row()]),
            '',
            f'Each fender takes these under its name, `<fender>.<parameter>`; it must set '
            f'{", ".join(f"`{name}`" for name in FENDER_REQUIRED)}.',
            '',
            *table(spec_rows(FENDER_SPECS)),
        ]),
        ('### The bollards', [
            *table([bollards_row()]),
            '',
            f'Each bollard takes these under its name, `<bollard>.<parameter>`; it must set '
            f'{", ".join(f"`{name}`" for name in BOLLARD_REQUIRED)}. A line names the one it '
            'is, or will be, made fast to with `<line>.bollard`; several lines may share one. '
            '[line_handling.md](line_handling.md) says how lines are made fast and let go.',
            '',
            *table(spec_rows(BOLLARD_SPECS)),
        ]),
        ('### A passing ship', [
            *table(spec_rows(PASSING_SPECS)),
        ]),
    ]


def fenders_row() -> str:
    """Return the row of `fenders`, a list of names without a Spec."""
    return names_row(FENDERS, f"a list of at most {MAX_FENDERS} distinct names, none a line's",
                     FENDERS_DESCRIPTION)


def bollards_row() -> str:
    """Return the row of `bollards`, a list of names without a Spec."""
    return names_row(BOLLARDS, f'a list of at most {MAX_BOLLARDS} distinct names, none a '
                     "line's or a fender's", BOLLARDS_DESCRIPTION)


def names_row(name: str, allowed_text: str, description: str) -> str:
    """Return the row of a list of names without a Spec (read-only)."""
    return '| ' + ' | '.join((f'`{name}`', '`[]`', '-', cell(allowed_text), 'read-only',
                              cell(description))) + ' |'


def markdown() -> str:
    """Return the whole text of docs/parameters.md."""
    out = [
        '<!-- Generated from rope_sim_ros/params/table.py and rope_sim_ros/params/'
        'arrangement.py',
        f'     by `{COMMAND}`:',
        '     do not edit by hand; test/test_docs.py checks it is up to date. -->',
        '',
        '# Parameters',
        '',
        'Every parameter of the two nodes, from the one table that the nodes declare, the '
        'offline commands read and this page is written from. *read-only*: taken at '
        'start-up, a change needs a restart (the node refuses it at run time); *run time*: '
        '`ros2 param set` changes it at once. A value outside *allowed* is one line naming '
        'the parameter and what it allows: at start-up the node exits with code 2 '
        '(`rope_sim` too), at run time the change is refused. `ros2 param describe` shows '
        'the same description, unit, range and read-only flag. Units are SI; frames follow '
        'REP-103 (z up).',
        '',
    ]
    parts = sections()
    for heading, _ in parts:
        level, title = heading.split(' ', 1)
        if level == '##':
            out.append(f'- [{title}](#{title})')
    for heading, body in parts:
        out += ['', heading, '', *body]
    return '\n'.join(out) + '\n'


def main() -> int:
    """Write docs/parameters.md's text to stdout."""
    sys.stdout.write(markdown())
    return 0


if __name__ == '__main__':
    sys.exit(main())
