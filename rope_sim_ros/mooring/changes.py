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
Run-time changes of a mooring: a line's parameters, and its one environment.

A change of the environment's (current, the wind's and the waves': ENVIRONMENT_SETTINGS)
replaces the mooring's one Environment everywhere at once: every line's step in it, its
groups' Systems, the ship's loads. A line's `bollard` names the bollard it will be made
fast to (set_bollard: while it is not fast). Any other change is a line's own (damping,
drag, max_strain, a winch's), applied to that line. Either way the ropes go on from where
they are; a line whose step changed is grouped again. Each function takes the Mooring it
changes (mooring.py, whose update and check_update call them).
"""

from dataclasses import replace
from typing import Optional, Tuple

from ..params.bollards import find_bollard
from ..params.resolve import environment
from ..params.ship import ENVIRONMENT_SETTINGS, field_name, SHIP_SETTINGS
from ..params.table import ParameterError


def check_update(mooring, k: Optional[int], values: dict) -> None:
    """Refuse run-time changes update() could not apply (k None: every line's)."""
    changes, own = _split(values)
    if changes:
        check_environment(mooring, changes)
    if BOLLARD in own:
        check_bollard(mooring, k, own.pop(BOLLARD))
    for i in _indices(mooring, k) if own else ():
        try:
            mooring.lines[i].updated(own, mooring.environment)
        except ParameterError as e:
            if not mooring.names[i]:  # the single line of a line node: its own parameters
                raise
            raise ParameterError(f'line {mooring.names[i]!r}: {e}') from None


def update(mooring, k: Optional[int], values: dict) -> None:
    """
    Apply run-time changes of line k's parameters (None: every line's).

    The environment's (current, the wind's, the waves') change the mooring's one
    environment (set_environment); the others line k's own. The ropes go on from where
    they are (no restart).

    :raises ParameterError: as check_update (nothing changed then).
    """
    check_update(mooring, k, values)
    changes, own = _split(values)
    if changes:
        set_environment(mooring, changes)
    if BOLLARD in own:
        set_bollard(mooring, k, own.pop(BOLLARD))
    for i in _indices(mooring, k) if own else ():
        _update_line(mooring, i, own)


def check_bollard(mooring, k: Optional[int], bollard: str) -> None:
    """
    Refuse a bollard line k cannot be given now: an unknown name, or the line is fast.

    :raises ParameterError: the message names the nearest bollard, or the line's state.
    """
    if k is None:
        raise ParameterError("parameter 'bollard' is a line's own: set <line>.bollard")
    name = mooring.names[k]
    if bollard:
        find_bollard(mooring.arrangement.bollards, bollard, f"parameter '{name}.bollard'")
    line = mooring.lines[k]
    if line.state == 'fast' and mooring.arrangement.lines[k].bollard != bollard:
        raise ParameterError(f"parameter '{name}.bollard' cannot change while line {name} is "
                             'fast: let it go first (its bollard changes while it is stowed '
                             'or free)')


def set_bollard(mooring, k: int, bollard: str) -> None:
    """
    Name the bollard line k will be made fast to ('': it keeps the position it has).

    :raises ParameterError: as check_bollard (nothing changed then).
    """
    check_bollard(mooring, k, bollard)
    mooring.arrangement = mooring.arrangement.with_bollard(mooring.names[k], bollard)
    line = mooring.lines[k]
    line.params = mooring.arrangement.lines[k].params
    mooring.ends.changed()


def _indices(mooring, k: Optional[int]) -> range:
    return range(len(mooring.lines)) if k is None else range(k, k + 1)


def _update_line(mooring, k: int, values: dict) -> None:
    """Apply checked run-time changes of line k's own parameters."""
    line = mooring.lines[k]
    dt = line.time_step
    line.update(values, mooring.environment)
    mooring.ends.changed()  # (a payload's, a bollard's place are its parameters)
    mooring.arrangement = mooring.arrangement.with_line(mooring.names[k], line.params)
    if not mooring.started:
        if line.time_step != dt:
            mooring.make_groups()
        return
    if not line.stepped:  # aboard: its winch and step count once it is made fast
        if line.time_step != dt:
            mooring.regroup()
        return
    group, j = mooring.where(k)
    group.system.lines[j].line_type = line.props.line_type
    mooring.apply_winch(k)  # also refreshes the tables
    if line.time_step != dt:
        mooring.regroup()
    else:
        group.refresh(mooring.lines, mooring.environment)


def check_environment(mooring, changes: dict) -> tuple:
    """
    Return (arrangement, environment) with run-time changes of the environment.

    :param changes: ENVIRONMENT_SETTINGS: current [m/s] (3,), wind_speed [m/s],
        wind_direction [rad] (where it comes FROM), waves.height [m], waves.period [s],
        waves.direction [rad] (where they come FROM).
    :raises ParameterError: a line cannot run in it (its step), or the ship's hydrodynamic
        database does not cover the waves; nothing changed.
    """
    shared = {k: v for k, v in changes.items() if k not in SHIP_SETTINGS}
    own = {field_name(k): float(v) for k, v in changes.items() if k in SHIP_SETTINGS}
    ship = replace(mooring.arrangement.ship, **own)
    setup = replace(mooring.arrangement.with_shared(shared), ship=ship)
    changed = environment(setup.shared, setup.ship)
    mooring.ship.check_waves(changed.waves)
    for k in range(len(mooring.lines)):
        try:
            mooring.lines[k].updated(shared, changed)
        except ParameterError as e:
            raise ParameterError(f'line {mooring.names[k]!r}: {e}' if mooring.names[k] else
                                 str(e)) from None
    return setup, changed


def set_environment(mooring, changes: dict) -> None:
    """
    Change the mooring's one environment from now on: its current, its wind, its waves.

    Every line, its System and the ship's loads take it from the next step; a line
    whose step changes with it (a current's drag) is grouped again. Gusty wind
    (wind_spectrum) keeps its spectrum and seed about a new mean; waves keep their
    spectrum, peak enhancement and seed (an irregular sea is drawn again for its new
    height, period or direction: the same seed gives the same phases).

    :raises ParameterError: as check_environment (nothing changed then).
    """
    mooring.arrangement, mooring.environment = check_environment(mooring, changes)
    shared = {k: v for k, v in changes.items() if k not in SHIP_SETTINGS}
    steps = [line.time_step for line in mooring.lines]
    for line in mooring.lines:
        line.update(shared, mooring.environment)
    if not mooring.started:
        if steps != [line.time_step for line in mooring.lines]:
            mooring.make_groups()
        return
    for group in mooring.groups:
        group.system.set_environment(mooring.environment)
    if steps != [line.time_step for line in mooring.lines]:
        mooring.regroup()
    else:
        for group in mooring.groups:
            group.refresh(mooring.lines, mooring.environment)


BOLLARD = 'bollard'  # a line's own setting, not of its parameters: set_bollard


def _split(values: dict) -> Tuple[dict, dict]:
    """Return run-time changes split: the environment's (ENVIRONMENT_SETTINGS), the lines'."""
    changed = {k: v for k, v in values.items() if k in ENVIRONMENT_SETTINGS}
    return changed, {k: v for k, v in values.items() if k not in ENVIRONMENT_SETTINGS}
