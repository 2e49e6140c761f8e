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
A berthing's orders: the pilot's tugs and the crew's schedule (the berth demo's).

The pilot lands a free ship lying parallel to the berth with tugs pushing (or pulling) her
sideways, a force towards the quay through her origin (Pilot.push), from what a pilot
watches: her distance off the fenders and her speed towards them. Coming in, the tugs hold
her at the approach speed until she has just the room left to slow to the landing speed at
the planned deceleration, then slow her so: the speed the pilot wants is
min(approach_speed, sqrt(landing_speed^2 + 2 deceleration distance)), and the tugs push
`gain` N per m/s she is slower than that (pull when faster), within max_push and max_pull.
Once she has touched a fender they hold her alongside: `hold` N, and the same gain against
her speed either way: they push harder while she comes off the fenders and pull back while
she presses onto them, as a pilot's tugs check her. The fenders give back the energy they
take (they have no hysteresis here): without that check the ship landing at 0.1 m/s
bounced 1.8 m off them and back, again and again, a swing her own damping took minutes to
calm. Told to stop, the tugs ease off over ease_time s and stop.

The crew's schedule is a list of orders, each a line of text, `T WHAT`, at T simulated
seconds from the ship's start, in time order:

- `T tugs push`: the pilot's tugs start; `T tugs stop`: they ease off and stop.
- `T LINE COMMAND`: a line-handling command (make_fast, let_go, stow; handling.py).
- `T let_go_all`: every fast line let go.
- `T LINE.PARAMETER VALUE`: a line's parameter set at run time (winch_mode,
  winch_tension, ...), VALUE read as a parameter file reads it.

The berth demo node's parameters (`berth_demo: ros__parameters:`, berthing()) are the
schedule, the pilot's settings and the demo's duration; every order is checked against the
arrangement before anything starts (read_berthing). No ROS.
"""

from dataclasses import dataclass, field
import difflib
import math
from typing import Any, List, Mapping, Optional, Sequence, Tuple

import numpy as np
from yaml import YAMLError

from .handling import COMMANDS, LINE_COMMANDS
from .ship import fender_gaps, quay_normal
from ..params.arrangement import ArrangementParams, check_line_value, LINE_SPECS
from ..params.files import load_yaml, read_params_file
from ..params.table import ParameterError

TUGS = 'tugs'
TUG_ORDERS = ('push', 'stop')
PILOT = 'pilot'
SCHEDULE = 'schedule'
DURATION = 'duration'
DEMO_NODE = 'berth_demo'
# The pilot's settings: name: (default, unit, what it is). The defaults land a loaded 225 m
# Panamax bulk carrier (config/berth.yaml's): two tugs of about 60 t bollard pull each; a
# sideways approach at 0.25 m/s (half a knot); a landing at 0.1 m/s, the order of the design
# berthing speeds PIANC's fender guidelines (2002) give a ship of her size in sheltered
# water. At 4e7 N per m/s the tugs answer in m / gain = 4 s (m with her added mass in sway,
# 1.58e8 kg): she lands at 0.110 m/s; at 2e7 N per m/s, lagging, at 0.120 m/s. The planned
# deceleration, 0.003 m/s^2, is what the tugs' pull and her drag give with room to spare.
PILOT_SETTINGS = {
    'approach_speed': (0.25, 'm/s', 'her speed towards the quay while far off'),
    'landing_speed': (0.1, 'm/s', 'her speed when she touches the fenders'),
    'deceleration': (0.003, 'm/s^2', 'the slowing down the pilot plans for'),
    'gain': (4.0e7, 'N per m/s', 'the tugs push this much more per m/s she is too slow'),
    'hold': (3.0e5, 'N', 'their push holding her alongside'),
    'max_push': (1.2e6, 'N', 'the most the tugs push'),
    'max_pull': (6.0e5, 'N', 'the most they pull her back (0: they only push)'),
    'ease_time': (20.0, 's', 'they ease off over this when told to stop'),
}


@dataclass(frozen=True)
class Berthing:
    """
    The berth demo's plan (its node's parameters).

    :ivar orders: the schedule, in time order.
    :ivar pilot: the pilot's settings.
    :ivar duration: how long the demo runs [s] (None: not said).
    """

    orders: Tuple['Order', ...] = ()
    pilot: 'PilotSettings' = field(default_factory=lambda: PilotSettings())
    duration: Optional[float] = None


def berthing(values: Mapping[str, Any], names: Sequence[str]) -> Berthing:
    """
    Read the berth demo node's parameters: schedule, pilot and duration (all optional).

    :param names: the arrangement's lines, which the orders name.
    :raises ParameterError: an unknown parameter, or a bad one (one line saying what).
    """
    try:
        known = (SCHEDULE, PILOT, DURATION)
        for name in values:
            if name not in known:
                raise ParameterError(f'unknown parameter {name!r}: the berth demo takes '
                                     f'{", ".join(known)}')
        duration = values.get(DURATION)
        if duration is not None and not _positive(duration):
            raise ParameterError(f'{DURATION} = {duration!r} is not allowed: must be a number '
                                 'of seconds > 0')
        return Berthing(tuple(parse_schedule(values.get(SCHEDULE) or [], names)),
                        pilot_settings(values.get(PILOT)),
                        None if duration is None else float(duration))
    except ParameterError as e:
        raise ParameterError(f'{DEMO_NODE}: {e}') from None


def _positive(value: Any, low: float = 0.0) -> bool:
    """Tell whether value is a finite number > low (>= 0 when low is None)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return False
    return value >= 0.0 if low is None else value > low


def read_berthing(paths: Sequence[Any], setup: ArrangementParams) -> Berthing:
    """
    Read the berth demo's parameters from parameter files (the later on top).

    The files' `berth_demo:` sections; none: no orders, the pilot's defaults.

    :raises ParameterError: an unreadable file, a bad order or setting (one line); tugs
        ordered at a berth without fenders (the pilot steers by them).
    """
    values: dict = {}
    for path in paths:
        values.update(read_params_file(path, DEMO_NODE, optional=True))
    plan = berthing(values, setup.names)
    if any(order.kind == 'tugs' for order in plan.orders):
        quay_normal(setup)
    return plan


@dataclass(frozen=True)
class Order:
    """
    One order of the schedule.

    :ivar t: when [s], simulated time from the ship's start.
    :ivar kind: 'tugs' (what: push or stop), 'command' (line, what: the command; line ''
        for let_go_all) or 'set' (line, what: the parameter, value).
    :ivar text: the order as written.
    """

    t: float
    kind: str
    what: str
    line: str = ''
    value: Any = None
    text: str = ''


def parse_schedule(entries: Sequence[Any], names: Sequence[str]) -> List[Order]:
    """
    Read the schedule's orders (see the module docstring) for lines `names`.

    :raises ParameterError: one line naming the order and what is wrong: not `T WHAT`, a
        time that is not a finite number >= 0 or before the order above, an unknown line
        (with the nearest name), command or parameter, a parameter that cannot change at
        run time, or a bad value.
    """
    if isinstance(entries, str) or not isinstance(entries, Sequence):
        raise ParameterError(f'{SCHEDULE} must be a list of orders (text), e.g. '
                             "['0 tugs push', '120 spring_fwd make_fast']")
    orders: List[Order] = []
    for entry in entries:
        order = _parse_order(entry, names)
        if orders and order.t < orders[-1].t:
            raise ParameterError(f'{SCHEDULE}: order {entry!r} comes before the order above '
                                 f'it ({orders[-1].text!r}): list them in time order')
        orders.append(order)
    return orders


def _parse_order(entry: Any, names: Sequence[str]) -> Order:
    words = str(entry).split()
    bad = f'{SCHEDULE}: order {entry!r}'
    if not isinstance(entry, str) or len(words) < 2:
        raise ParameterError(f'{bad} is not an order: write T WHAT, e.g. '
                             "'120 spring_fwd make_fast'")
    try:
        t = float(words[0])
    except ValueError:
        t = math.nan
    if not (math.isfinite(t) and t >= 0.0):
        raise ParameterError(f'{bad}: its time {words[0]!r} is not a number of seconds >= 0')
    rest = words[1:]
    if rest[0] == TUGS:
        if len(rest) != 2 or rest[1] not in TUG_ORDERS:
            raise ParameterError(f'{bad}: the tugs take {" or ".join(TUG_ORDERS)}: '
                                 f"'{words[0]} tugs push'")
        return Order(t, 'tugs', rest[1], text=entry)
    if rest == ['let_go_all']:
        return Order(t, 'command', 'let_go_all', text=entry)
    line, dot, parameter = rest[0].partition('.')
    if line not in names:
        found = difflib.get_close_matches(line, list(names), n=1, cutoff=0.6)
        near = f'; did you mean {found[0]!r}?' if found else ''
        raise ParameterError(f'{bad}: {line!r} is not a line, nor tugs or let_go_all; the '
                             f'lines are {", ".join(names)}{near}')
    if not dot:
        if len(rest) != 2 or rest[1] not in LINE_COMMANDS:
            raise ParameterError(f'{bad}: a line takes one of {", ".join(LINE_COMMANDS)}, or '
                                 f'LINE.PARAMETER VALUE (the commands: {", ".join(COMMANDS)})')
        return Order(t, 'command', rest[1], line, text=entry)
    if len(rest) != 2:
        raise ParameterError(f'{bad}: a parameter takes one value: '
                             f"'{words[0]} {line}.winch_tension 141000'")
    try:
        value = check_line_value(line, parameter, load_yaml(rest[1]))
    except YAMLError:
        raise ParameterError(f'{bad}: {rest[1]!r} is not a YAML value') from None
    except ParameterError as e:
        raise ParameterError(f'{bad}: {e}') from None
    if LINE_SPECS[parameter].read_only:
        raise ParameterError(f'{bad}: {line}.{parameter} cannot change at run time (it needs a '
                             'restart of the node)')
    return Order(t, 'set', parameter, line, value, entry)


@dataclass(frozen=True)
class PilotSettings:
    """The pilot's settings (PILOT_SETTINGS says what each is)."""

    approach_speed: float = PILOT_SETTINGS['approach_speed'][0]
    landing_speed: float = PILOT_SETTINGS['landing_speed'][0]
    deceleration: float = PILOT_SETTINGS['deceleration'][0]
    gain: float = PILOT_SETTINGS['gain'][0]
    hold: float = PILOT_SETTINGS['hold'][0]
    max_push: float = PILOT_SETTINGS['max_push'][0]
    max_pull: float = PILOT_SETTINGS['max_pull'][0]
    ease_time: float = PILOT_SETTINGS['ease_time'][0]


def pilot_settings(values: Optional[Mapping[str, Any]]) -> PilotSettings:
    """
    Return the pilot's settings from `pilot: {...}` (missing ones at their defaults).

    :raises ParameterError: an unknown setting (the nearest named) or one that is not a
        finite number > 0 (>= 0 for max_pull).
    """
    values = dict(values or {})
    for name, value in values.items():
        if name not in PILOT_SETTINGS:
            found = difflib.get_close_matches(str(name), list(PILOT_SETTINGS), n=1, cutoff=0.6)
            near = f'; did you mean {PILOT}.{found[0]}?' if found else ''
            raise ParameterError(f'unknown setting {PILOT}.{name}: the pilot has '
                                 f'{", ".join(PILOT_SETTINGS)}{near}')
        pull = name == 'max_pull'
        if not _positive(value, None if pull else 0.0):
            raise ParameterError(f'{PILOT}.{name} = {value!r} is not allowed: must be a number '
                                 f'{">= 0" if pull else "> 0"} ({PILOT_SETTINGS[name][1]})')
        values[name] = float(value)
    settings = PilotSettings(**values)
    if settings.landing_speed > settings.approach_speed:
        raise ParameterError(f'{PILOT}.landing_speed {settings.landing_speed:g} m/s is more than '
                             f'{PILOT}.approach_speed {settings.approach_speed:g} m/s')
    return settings


def watch(setup: ArrangementParams, position, orientation, velocity) -> Tuple[float, float]:
    """
    Return what the pilot watches: her distance off the fenders [m] and speed towards them.

    The distance: the least of the hull's gaps to the fenders' faces (< 0: compressing
    one). The speed: her origin's velocity [m/s] along the fenders' normal, into the quay.

    :param position, orientation: her origin's pose in frame_id (x, y, z, w).
    :param velocity: her origin's velocity in frame_id axes.
    :raises ParameterError: the berth has no fenders (quay_normal).
    """
    speed = -float(np.dot(velocity, quay_normal(setup)))
    return float(fender_gaps(setup, position, orientation).min()), speed


class Pilot:
    """The tugs' push from the ship's distance off the fenders and her speed (module)."""

    def __init__(self, settings: PilotSettings = PilotSettings()):
        """Start with the tugs idle: push() gives 0 until start()."""
        self.settings = settings
        self.pushing = False
        self.touched = False  # she has touched a fender: hold her alongside
        self._stop_at = math.inf  # [s] when the tugs were told to stop

    def start(self) -> None:
        """Set the tugs pushing (the order `tugs push`)."""
        self.pushing = True
        self._stop_at = math.inf

    def stop(self, t: float) -> None:
        """Have the tugs ease off from t [s] to nothing: the order `tugs stop`."""
        self._stop_at = min(self._stop_at, t)

    def wanted_speed(self, distance: float) -> float:
        """Return the speed towards the quay [m/s] the pilot wants at `distance` m off."""
        s = self.settings
        return min(s.approach_speed,
                   math.sqrt(s.landing_speed ** 2 + 2.0 * s.deceleration * max(distance, 0.0)))

    def push(self, t: float, distance: float, speed: float) -> float:
        """
        Return the tugs' push towards the quay [N] (< 0: they pull her off) at t [s].

        :param distance: her least distance off a fender face [m] (< 0: compressing it).
        :param speed: her speed towards the quay [m/s].
        """
        s = self.settings
        if not self.pushing:
            return 0.0
        if distance <= 0.0:
            self.touched = True
        wanted = 0.0 if self.touched else self.wanted_speed(distance)
        push = min(max((0.0 if not self.touched else s.hold) + s.gain * (wanted - speed),
                       -s.max_pull), s.max_push)
        easing = min(max((t - self._stop_at) / s.ease_time, 0.0), 1.0)
        if easing >= 1.0:
            self.pushing = False
        return push * (1.0 - easing)
