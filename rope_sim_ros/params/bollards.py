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
The quay's bollards by name: `bollards: [names]`, each with its settings under its name.

A line names the bollard it is, or will be, made fast to (`head_1.bollard: bollard_3`);
several lines may share one. A bollard is a point in frame_id with a safe working load:
its load is the sum of the forces of the lines fast on it. Every error is one line naming
the parameter and what is allowed.
"""

from dataclasses import dataclass
import difflib
from typing import Any, Dict, List, Mapping, Sequence, Tuple

from .names import check_names, check_setting
from .table import ParameterError, Spec

BOLLARDS = 'bollards'
MAX_BOLLARDS = 64
BOLLARDS_DESCRIPTION = ('names of the bollards on the quay; each has its settings under its '
                        'name (bollard_1.position, ...), and a line names the one it is made '
                        'fast to (head_1.bollard)')
BOLLARD_SPECS: Mapping[str, Spec] = {
    'position': Spec([0.0, 0.0, 0.0], 'm', 'the bollard in frame_id'),
    'safe_working_load': Spec(
        0.0, 'N', "the bollard's safe working load: the sum of its lines' forces past it is "
        'a WARN in the diagnostics; 0 = no limit', 0.0, 1.0e10),
}
BOLLARD_REQUIRED = ('position',)


@dataclass(frozen=True)
class BollardSetup:
    """One bollard on the quay (BOLLARD_SPECS: units and meanings)."""

    name: str
    position: Tuple[float, float, float]
    safe_working_load: float = 0.0

    def values(self) -> Dict[str, Any]:
        """Return its settings as a parameter file holds them."""
        return {'position': list(self.position), 'safe_working_load': self.safe_working_load}


def check_bollard_names(value: Any, taken: Sequence[str]) -> List[str]:
    """Validate the `bollards` parameter (names.check_names); taken: lines', fenders'."""
    return check_names(BOLLARDS, value, 'bollard', MAX_BOLLARDS, taken,
                       'a line, a fender, a parameter')


def check_bollard_value(bollard: str, name: str, value: Any) -> Any:
    """Validate one setting of a bollard; return it in its canonical type."""
    return check_setting('bollard', bollard, name, value, BOLLARD_SPECS)


def bollard_setup(name: str, values: Mapping[str, Any]) -> BollardSetup:
    """
    Return a bollard from its checked settings (check_bollard_value each).

    :raises ParameterError: its position missing.
    """
    missing = [f'{name}.{key}' for key in BOLLARD_REQUIRED if key not in values]
    if missing:
        raise ParameterError(f'bollard {name!r} is missing settings: set {"; ".join(missing)} '
                             '(m, in frame_id)')
    return BollardSetup(name, tuple(values['position']),
                        values.get('safe_working_load',
                                   BOLLARD_SPECS['safe_working_load'].default))


def find_bollard(bollards: Sequence[BollardSetup], name: str, what: str) -> BollardSetup:
    """
    Return the bollard of that name.

    :param what: who names it, for the message (`parameter 'head_1.bollard'`).
    :raises ParameterError: no bollard has that name (the nearest one is named).
    """
    for bollard in bollards:
        if bollard.name == name:
            return bollard
    names = [bollard.name for bollard in bollards]
    if not names:
        raise ParameterError(f'{what} = {name!r} is not allowed: the arrangement has no '
                             f'bollards; list them in {BOLLARDS!r}, each with its position')
    found = difflib.get_close_matches(name, names, n=1, cutoff=0.6)
    near = f'; did you mean {found[0]!r}?' if found else ''
    raise ParameterError(f'{what} = {name!r} is not a bollard: {BOLLARDS} are '
                         f'{", ".join(names)}{near}')
