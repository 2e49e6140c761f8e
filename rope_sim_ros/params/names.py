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
Things of an arrangement by name: a list of names, and each thing's settings under its name.

Fenders and bollards are listed as `fenders: [names]` and `bollards: [names]`, each with
its settings under its name (`fender_1.position`); one rule checks such a list and one a
setting, so that both say the same about a bad name or value.
"""

import re
from typing import Any, List, Mapping, Sequence

from .table import check, ParameterError, Spec

NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]*\Z')
NAME_RULE = 'a name starts with a letter and holds letters, digits and _'


def check_names(parameter: str, value: Any, kind: str, most: int, taken: Sequence[str],
                holders: str) -> List[str]:
    """
    Validate a list of names, as `fenders`: up to `most` distinct names, none taken.

    :param kind: what is named (fender, bollard).
    :param taken: names that are not allowed; holders says whose they are.
    :raises ParameterError: not a list of names, a bad or repeated or taken name.
    """
    if value is None:
        return []
    if isinstance(value, str) or not isinstance(value, (list, tuple)) or len(value) > most:
        raise ParameterError(f'parameter {parameter!r} = {value!r} is not allowed: must be a '
                             f'list of at most {most} {kind} names')
    names: List[str] = []
    for name in value:
        if not isinstance(name, str) or not NAME.match(name):
            raise ParameterError(f'{kind} name {name!r} in {parameter!r} is not allowed: '
                                 f'{NAME_RULE}')
        if name in names or name in taken:
            raise ParameterError(f'{kind} name {name!r} in {parameter!r} is taken: '
                                 f'{holders} or another {kind} has it')
        names.append(name)
    return names


def check_setting(kind: str, owner: str, name: str, value: Any,
                  specs: Mapping[str, Spec]) -> Any:
    """
    Validate one setting `owner.name` of a named thing; return it in its canonical type.

    :raises ParameterError: an unknown setting or a bad value, named with its owner.
    """
    if name not in specs:
        raise ParameterError(f'unknown parameter {owner}.{name}; a {kind} takes: '
                             f'{", ".join(specs)}')
    try:
        return check(name, value, specs)
    except ParameterError as e:
        raise ParameterError(str(e).replace(f'parameter {name!r}', f'parameter '
                                            f'{owner + "." + name!r}', 1)) from None
