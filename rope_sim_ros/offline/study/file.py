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
A study file (STUDY.yaml) and its cases: what ``rope_sim study`` runs.

A study is a mapping under ``study:``::

    study:
      arrangement: ../../config/berth.yaml   # the base parameter file (relative to this file)
      duration: 60.0                         # [s] every case's simulated time
      motion: passing.csv                    # SHIP.csv of a driven ship (or loads: LOADS.csv)
      # commands: lines.csv                  # COMMANDS.csv: lines made fast, let go, stowed
      rate: 10.0                             # [Hz] rows of each case's OUT.csv (default 10)
      set: {segments: 20}                    # fixed overrides of every case, as --set
      factors:                               # every combination is a case ...
        spring_fwd.material: [hmpe, polyester]
        spring_fwd.pretension: [100000, 141000]
      # cases: [{spring_fwd.material: nylon}, ...]   # ... or a list of cases
      seed: 0                                # the seed of every case's random inputs
      keep: csv                              # csv, bag, both or none: each case's files

A factor (or a key of a case) is any parameter `--set` takes (top-level, `head_1.pretension`,
`head_1.material`, `passing_ship.speed`, ...) or one of CASE_FILES (`arrangement`, `motion`,
`loads`, `commands`: a file per case, relative to the study file) or `seed`. The ship's
tables and database (`ship.hydrodynamics`, `ship.wind_coefficients`, ...) are relative to
the case's arrangement file wherever they are set, as `rope_sim run --set` takes them, and
made absolute here: a worker runs in any directory. Full factorial:
the last factor varies fastest; case k is the k-th combination (0-based). Every case's
parameters are validated here, before anything runs, and its commands against its lines
and bollards: a study with a bad value refuses at once, in one line naming the case; what
only a run can find (a pretension no length gives, a blow-up, a refused command) is the
case's failure or its run's business, recorded in the results (cluster.py).

Each case has a key: a hash of everything its results depend on (its validated parameters,
the motion and the commands it runs, its duration, rate, seed and kept files). A study
started again skips the cases whose stored key matches, and runs a case again whose inputs
changed.
"""

from dataclasses import dataclass, field
import hashlib
import itertools
import json
import math
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from ..motion import MotionError, read_commands, read_ship_motion, Streams
from ...params.arrangement import (ArrangementParams, flatten, from_values,
                                   is_arrangement_file, NODE_NAME, with_tables_from)
from ...params.files import read_params_file, read_yaml_file
from ...params.table import ParameterError

STUDY = 'study'
ARRANGEMENT = 'arrangement'
MOTION = 'motion'
LOADS = 'loads'
COMMANDS = 'commands'
SEED = 'seed'
# Keys naming a file per case (relative to the study file): the case's inputs, not parameters.
CASE_FILES = (ARRANGEMENT, MOTION, LOADS, COMMANDS)
KEEP_CHOICES = ('csv', 'bag', 'both', 'none')
KEYS = (ARRANGEMENT, 'duration', MOTION, LOADS, COMMANDS, 'factors', 'cases', SEED, 'rate',
        'set', 'keep', 'heatmap')
DEFAULT_RATE = 10.0
MAX_RATE = 1000.0
MAX_DURATION = 1.0e6
MAX_CASES = 100000
MAX_SEED = 2**63 - 1


class StudyError(ParameterError):
    """A study file cannot be run; the message (one line) names the file and what is wrong."""


@dataclass(frozen=True)
class Case:
    """
    One case of a study, as the file gives it.

    :ivar index: its number (0-based), the `case` column of the results.
    :ivar values: its factors: (name as in the study, value as written), in column order.
    :ivar overrides: its parameter values (the values less CASE_FILES and seed), flat.
    :ivar arrangement, motion, loads, commands: its files (absolute paths; all but the
        arrangement may be None).
    :ivar seed: the seed of its random inputs.
    """

    index: int
    values: Tuple[Tuple[str, Any], ...]
    overrides: Mapping[str, Any]
    arrangement: str
    motion: Optional[str]
    loads: Optional[str]
    seed: int
    commands: Optional[str] = None

    def describe(self, limit: int = 160) -> str:
        """Return its values as name=value, ..., cut at `limit` characters."""
        text = ', '.join(f'{name}={format_value(value)}' for name, value in self.values)
        return text if len(text) <= limit else text[:limit - 3] + '...'


@dataclass(frozen=True)
class Study:
    """
    A study file, read and expanded into its cases (nothing validated beyond its form).

    :ivar path: the study file.
    :ivar duration: every case's simulated time [s].
    :ivar rate: outputs per simulated second of each case [Hz].
    :ivar fixed: the overrides every case takes (`set`), flat.
    :ivar factors: the varied names, in the order of the results' columns.
    :ivar cases: every case, in order.
    :ivar keep: the files kept per case: csv, bag, both or none.
    :ivar heatmap: the two factors of the heat map (None: the first two).
    :ivar factorial: the cases are every combination of `factors` (else a `cases` list).
    """

    path: str
    duration: float
    rate: float
    fixed: Mapping[str, Any]
    factors: Tuple[str, ...]
    cases: Tuple[Case, ...]
    keep: str = 'csv'
    heatmap: Optional[Tuple[str, str]] = None
    factorial: bool = True
    levels: Mapping[str, Tuple[Any, ...]] = field(default_factory=dict)

    def shape(self) -> str:
        """Return how the cases come about: '4 x 5 factorial' or 'a list of 3 cases'."""
        if self.factorial:
            sizes = ' x '.join(str(len(self.levels[name])) for name in self.factors)
            return f'{sizes} factorial' if sizes else 'one case'
        return f'a list of {len(self.cases)} cases'


@dataclass(frozen=True)
class PreparedCase:
    """
    A case ready to run: validated parameters and the inputs of its run.

    :ivar case: the case.
    :ivar setup: its parameters, validated.
    :ivar streams: the ship's motion cut to the duration (None for a free ship).
    :ivar key: hash of everything its results depend on (see the module docstring).
    :ivar commands: its line-handling commands (mooring/records.py ScheduledCommand), checked
        against its lines and bollards; () without a commands file.
    """

    case: Case
    setup: ArrangementParams
    streams: Optional[Streams]
    key: str
    commands: Tuple[Any, ...] = ()


def format_value(value: Any) -> str:
    """Return a factor's value as the results' CSV writes it (lists as JSON, e.g. [1.0, 2.0])."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, tuple, dict)):
        return json.dumps(value)
    return str(value)


def _where(path: str, key: str) -> str:
    return f'{path}: {STUDY}.{key}'


def _number(path: str, key: str, value: Any, low: float, high: float,
            low_open: bool = True) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            not math.isfinite(value) or value > high or \
            (value <= low if low_open else value < low):
        bound = '>' if low_open else '>='
        raise StudyError(f'{_where(path, key)} = {value!r} is not allowed: must be a number '
                         f'{bound} {low:g} and <= {high:g}')
    return float(value)


def _seed(path: str, place: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_SEED:
        raise StudyError(f'{path}: {place} = {value!r} is not allowed: a seed is an '
                         f'integer from 0 to 2**63 - 1')
    return value


def _file(path: str, where: str, value: Any) -> str:
    if not isinstance(value, str) or not value.strip():
        raise StudyError(f'{path}: {where} = {value!r} is not allowed: must be a file name '
                         '(relative to the study file, or absolute)')
    return os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), value))


def _name(path: str, where: str, name: Any) -> str:
    if not isinstance(name, str) or not name.strip() or name != name.strip():
        raise StudyError(f'{_where(path, where)}: {name!r} is not a parameter name: give a name '
                         'as --set takes it, e.g. head_1.pretension')
    if name in ('factors', 'cases', 'duration', 'rate', 'set', 'keep', 'heatmap'):
        raise StudyError(f"{_where(path, where)}: {name!r} cannot vary: it is the study's own "
                         'setting')
    return name


def read_study(path) -> Study:
    """
    Read a study file and expand its cases.

    :raises StudyError: unreadable, not YAML, no `study:` mapping, an unknown key, a missing
        or bad arrangement, duration, rate, seed, keep, set, factors or cases (one line).
    """
    path = os.fspath(path)
    data = read_yaml_file(path, 'study file', StudyError)
    if not isinstance(data, dict) or not isinstance(data.get(STUDY), dict):
        raise StudyError(f'{path}: expected a mapping `{STUDY}:` with {ARRANGEMENT}, duration '
                         'and factors or cases')
    spec = data[STUDY]
    unknown = [str(key) for key in spec if key not in KEYS]
    if unknown:
        raise StudyError(f'{path}: unknown key(s) {", ".join(unknown)} under {STUDY}: it takes '
                         f'{", ".join(KEYS)}')
    if ARRANGEMENT not in spec:
        raise StudyError(f'{_where(path, ARRANGEMENT)} is missing: name the base parameter '
                         'file (an arrangement, relative to the study file)')
    if 'duration' not in spec:
        raise StudyError(f'{_where(path, "duration")} is missing: every case\'s simulated '
                         'time [s]')
    duration = _number(path, 'duration', spec['duration'], 0.0, MAX_DURATION)
    rate = _number(path, 'rate', spec.get('rate', DEFAULT_RATE), 0.0, MAX_RATE)
    seed = _seed(path, f'{STUDY}.{SEED}', spec.get(SEED, 0))
    keep = spec.get('keep', 'csv')
    if keep not in KEEP_CHOICES:
        raise StudyError(f'{_where(path, "keep")} = {keep!r} is not allowed: one of '
                         f'{", ".join(KEEP_CHOICES)}')
    fixed = spec.get('set') or {}
    if not isinstance(fixed, dict):
        raise StudyError(f'{_where(path, "set")} must be a mapping of parameter name to value, '
                         'e.g. {segments: 20}')
    fixed = flatten(fixed)
    for name in fixed:
        if name in CASE_FILES or name == SEED:
            raise StudyError(f'{_where(path, "set")}: {name!r} is the study\'s own key: give it '
                             f'as {STUDY}.{name}')
    defaults = {ARRANGEMENT: spec[ARRANGEMENT], MOTION: spec.get(MOTION),
                LOADS: spec.get(LOADS), COMMANDS: spec.get(COMMANDS), SEED: seed}
    has_factors, has_cases = 'factors' in spec, 'cases' in spec
    if has_factors == has_cases:
        raise StudyError(f'{path}: give either {STUDY}.factors (a mapping of parameter name to '
                         f'a list of values: every combination is a case) or {STUDY}.cases (a '
                         'list of mappings of parameter name to value), not '
                         f'{"both" if has_factors else "neither"}')
    if has_factors:
        names, rows, levels = _factorial(path, spec['factors'])
    else:
        names, rows = _listed(path, spec['cases'])
        levels = {}
    cases = tuple(_case(path, index, names, row, defaults) for index, row in enumerate(rows))
    heatmap = _heatmap(path, spec.get('heatmap'), names)
    return Study(path, duration, rate, fixed, tuple(names), cases, keep, heatmap, has_factors,
                 levels)


def _factorial(path: str, factors: Any) -> Tuple[List[str], List[Dict[str, Any]], dict]:
    if not isinstance(factors, dict) or not factors:
        raise StudyError(f'{_where(path, "factors")} must be a mapping of parameter name to a '
                         'list of values, e.g. {head_1.pretension: [100000, 150000]}')
    names, levels = [], {}
    count = 1
    for name, values in factors.items():
        name = _name(path, 'factors', name)
        if not isinstance(values, list) or not values:
            raise StudyError(f'{_where(path, "factors." + name)} = {values!r} is not allowed: '
                             'must be a list of one or more values')
        names.append(name)
        levels[name] = tuple(values)
        count *= len(values)
        if count > MAX_CASES:
            raise StudyError(f'{_where(path, "factors")}: more than {MAX_CASES} combinations; '
                             'split the study')
    rows = [dict(zip(names, combination))
            for combination in itertools.product(*(levels[name] for name in names))]
    return names, rows, levels


def _listed(path: str, cases: Any) -> Tuple[List[str], List[Dict[str, Any]]]:
    if not isinstance(cases, list) or not cases or len(cases) > MAX_CASES:
        raise StudyError(f'{_where(path, "cases")} must be a list of 1 to {MAX_CASES} mappings '
                         'of parameter name to value')
    names: List[str] = []
    rows = []
    for index, case in enumerate(cases):
        if not isinstance(case, dict):
            raise StudyError(f'{_where(path, f"cases[{index}]")} = {case!r} is not a mapping of '
                             'parameter name to value')
        row = {}
        for name, value in flatten(case).items():
            name = _name(path, f'cases[{index}]', name)
            row[name] = value
            if name not in names:
                names.append(name)
        rows.append(row)
    return names, rows


def _case(path: str, index: int, names: Sequence[str], row: Mapping[str, Any],
          defaults: Mapping[str, Any]) -> Case:
    where = f'case {index}'
    files = {}
    for key in CASE_FILES:
        value = row.get(key, defaults[key])
        place = f'{where}: {key}' if key in row else f'{STUDY}.{key}'
        files[key] = None if value is None else _file(path, place, value)
    seed = _seed(path, f'{where}: {SEED}', row[SEED]) if SEED in row else defaults[SEED]
    overrides = {name: value for name, value in row.items()
                 if name not in CASE_FILES and name != SEED}
    values = tuple((name, row[name]) for name in names if name in row)
    return Case(index, values, overrides, files[ARRANGEMENT], files[MOTION], files[LOADS], seed,
                files[COMMANDS])


def _heatmap(path: str, value: Any, names: Sequence[str]) -> Optional[Tuple[str, str]]:
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != 2 or \
            not all(isinstance(v, str) and v in names for v in value) or value[0] == value[1]:
        raise StudyError(f'{_where(path, "heatmap")} = {value!r} is not allowed: two different '
                         f'factors of the study, of {", ".join(names)}')
    return value[0], value[1]


def _base_values(path: str) -> Dict[str, Any]:
    if not os.path.isfile(path):
        raise StudyError(f'{path}: no such arrangement file')
    if not is_arrangement_file(path):
        raise StudyError(f'{path}: not an arrangement (no `lines` in a "{NODE_NAME}: '
                         'ros__parameters:" section): a study runs a mooring of named lines')
    return flatten(read_params_file(path, NODE_NAME))


def cut(streams: Streams, duration: float) -> Streams:
    """Return the ship poses of the first `duration` seconds (rows up to first + duration)."""
    end = int(streams.t_ns[0]) + int(round(duration * 1e9))
    count = int(np.searchsorted(streams.t_ns, end, side='right'))
    if count == len(streams):
        return streams
    return Streams(streams.path, streams.t_ns[:count], streams.position[:count],
                   streams.orientation[:count], origin=streams.origin)


def _motion(path: str, duration: float) -> Streams:
    streams = read_ship_motion(path)
    covered = (int(streams.t_ns[-1]) - int(streams.t_ns[0])) / 1e9
    if covered < duration - 1e-9:
        raise StudyError(f'{path}: the motion covers {covered:g} s from its first row, less '
                         f"than the study's duration of {duration:g} s")
    return cut(streams, duration)


def _digest(*parts: bytes) -> str:
    digest = hashlib.sha256()
    for part in parts:
        digest.update(len(part).to_bytes(8, 'little'))
        digest.update(part)
    return digest.hexdigest()


def _streams_digest(streams: Optional[Streams]) -> str:
    if streams is None:
        return ''
    return _digest(np.ascontiguousarray(streams.t_ns, dtype='<i8').tobytes(),
                   np.ascontiguousarray(streams.position, dtype='<f8').tobytes(),
                   np.ascontiguousarray(streams.orientation, dtype='<f8').tobytes(),
                   repr(streams.origin).encode())


def _file_digest(path: Optional[str]) -> str:
    if path is None:
        return ''
    try:
        with open(path, 'rb') as stream:
            return _digest(stream.read())
    except OSError as e:
        raise StudyError(f'cannot read {path}: {e.strerror or e}') from None


def is_free(setup: ArrangementParams) -> bool:
    """Tell whether the setup's ship is a free body (ship_mode free)."""
    ship = getattr(setup, 'ship', None)
    return bool(ship is not None and getattr(ship, 'free', False))


def prepare(study: Study) -> List[PreparedCase]:
    """
    Validate every case and read its inputs, before any case runs.

    :raises StudyError: a case's parameters are not allowed, or its files cannot be used:
        one line naming the case and its values.
    :raises MotionError: a motion file cannot be read.
    """
    bases: Dict[str, Dict[str, Any]] = {}
    motions: Dict[str, Tuple[Streams, str]] = {}
    loads: Dict[str, str] = {}
    commands: Dict[Tuple[str, Tuple[str, ...], Tuple[str, ...]], Tuple[Any, ...]] = {}
    prepared = []
    for case in study.cases:
        if case.arrangement not in bases:
            bases[case.arrangement] = _base_values(case.arrangement)
        try:
            setup = with_tables_from(
                from_values({**bases[case.arrangement], **study.fixed, **case.overrides}),
                os.path.dirname(case.arrangement))  # as rope_sim run's --set takes them
        except ParameterError as e:
            raise StudyError(f'{study.path}: case {case.index} ({case.describe()}): {e}') \
                from None
        free = is_free(setup)
        if free and case.motion is not None:
            raise StudyError(f'{study.path}: case {case.index} ({case.describe()}): ship_mode '
                             'free moves the ship itself: give loads (LOADS.csv) or nothing, '
                             'not a motion')
        if not free and case.loads is not None:
            raise StudyError(f'{study.path}: case {case.index} ({case.describe()}): loads '
                             '(LOADS.csv) move a free ship: set ship_mode: free, or give a '
                             'motion (SHIP.csv) for the driven ship')
        if not free and case.motion is None:
            raise StudyError(f'{study.path}: case {case.index} ({case.describe()}): the ship is '
                             'driven (ship_mode driven): give its motion, study.motion: SHIP.csv')
        if case.motion is not None and case.motion not in motions:
            streams = _motion(case.motion, study.duration)
            motions[case.motion] = (streams, _streams_digest(streams))
        if case.loads is not None and case.loads not in loads:
            loads[case.loads] = _file_digest(case.loads)
        database = setup.ship.hydrodynamics
        if database and database not in loads:  # a database solved again at its path
            loads[database] = _file_digest(database)
        streams, motion_digest = motions[case.motion] if case.motion else (None, '')
        scheduled = _commands(study, case, setup, commands)
        key = _digest(json.dumps({
            'parameters': setup.values(), 'motion': motion_digest,
            'loads': loads.get(case.loads, ''), 'duration': repr(study.duration),
            'rate': repr(study.rate), 'seed': case.seed, 'keep': study.keep,
            # only with commands, a database: a case without keeps the key it had before
            **({'commands': [[c.t, c.line, c.command, c.bollard] for c in scheduled]}
               if scheduled else {}),
            **({'hydrodynamics': loads[database]} if database else {}),
        }, sort_keys=True, default=repr).encode())
        prepared.append(PreparedCase(case, setup, streams, key, scheduled))
    return prepared


def _commands(study: Study, case: Case, setup: ArrangementParams,
              read: Dict[Tuple[str, Tuple[str, ...], Tuple[str, ...]], Tuple[Any, ...]]
              ) -> Tuple[Any, ...]:
    """
    Return a case's commands, read once per file and set of line and bollard names.

    A command at or after the study's duration would never be taken: refused, as a bad row.
    """
    if case.commands is None:
        return ()
    names = tuple(setup.names)
    bollards = tuple(bollard.name for bollard in setup.bollards)
    key = (case.commands, names, bollards)
    if key not in read:
        try:
            schedule = read_commands(case.commands, names, bollards)
        except MotionError as e:
            raise StudyError(f'{study.path}: case {case.index} ({case.describe()}): {e}') \
                from None
        for command, row in zip(schedule.commands, schedule.rows):
            if command.t >= study.duration:
                raise StudyError(
                    f'{study.path}: case {case.index} ({case.describe()}): {schedule.path}: '
                    f"data row {row}, column 't': {command.t:g} s is not before the study's "
                    f'duration of {study.duration:g} s: the command would never be taken')
        read[key] = schedule.commands
    return read[key]
