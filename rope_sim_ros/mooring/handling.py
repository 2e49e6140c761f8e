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
Line handling at run time: lines made fast, let go and stowed, and quick-release hooks.

Every line is in one of three states (MooringLine.state):

- stowed: aboard. It pulls nothing and is not stepped: it is in no group, and its particles
  are output at its fairlead.
- fast: its eye on its bollard, a point that stands or follows its samples.
- free: let go. Its bollard end is a free point (the eye is the line's own end particle):
  it falls, drags through air and water, and lies on the quay or the seabed like every
  other particle; its winch can heave it in.

The commands, each taken at the mooring's state time, between two steps:

- make_fast: a stowed line comes out lying slack from its fairlead to its bollard, at rest,
  its length the distance times (1 + make_fast_slack); a free line is put on its bollard
  with the length it has out, at rest. Refused if the bollard is out of reach.
- let_go: a fast line's eye leaves its bollard in this step, whatever its tension. Nothing
  else moves: the energy the line stored goes into its motion from the eye on, as a
  parting releases it, and the ship feels the pull change from the step after.
- stow: a free line whose winch has heaved it in to its shortest length goes aboard.
- let_go_all: every fast line let go in one step.

A fast line with a release_load lets go by itself once its tension at the bollard passed
it (release_hooks, after each advance: within one output interval of the step it passed
it in). A command that does not fit the line's state is refused with a CommandError that
names the state or the numbers; nothing changes then.
"""

import math
from typing import Dict, List

import numpy as np

from ..model.layout import PEAK_A
from ..stepping.adaptive import HOLD_TIME

COMMANDS = ('make_fast', 'let_go', 'stow', 'let_go_all')
LINE_COMMANDS = COMMANDS[:3]  # a line's own; let_go_all is the mooring's
# A line is heaved in to its shortest length when within this of it [m]: the winch stops
# there to rounding.
STOWED_LENGTH_TOLERANCE = 1e-3


class CommandError(ValueError):
    """A command refused: the message names the line's state or the numbers."""


def who(mooring, k: int) -> str:
    """Return how messages name line k ('line head_1', or 'the line' of a line node)."""
    name = mooring.names[k]
    return f'line {name}' if name else 'the line'


def bollard_name(mooring, k: int) -> str:
    """Return how messages name line k's bollard: its name, or where it stands."""
    setup = mooring.arrangement.lines[k]
    if setup.bollard:
        return setup.bollard
    x, y, z = setup.params.bollard_position
    return f'its bollard at ({x:g}, {y:g}, {z:g})'


def _check_can_handle(mooring, k: int) -> None:
    """Refuse any command on a line with a payload, a parted line, or before the start."""
    line = mooring.lines[k]
    if line.payload:
        raise CommandError(f'{who(mooring, k)} carries a payload: it hangs from its fairlead '
                           'and has no bollard to be made fast to or let go from')
    if line.parting is not None:
        raise CommandError(f'{who(mooring, k)} has parted: reset gives it back whole')
    if not mooring.started:
        raise CommandError(f'{who(mooring, k)} cannot be handled yet: the lines start at the '
                           'first ship pose')


def make_fast(mooring, k: int) -> str:
    """
    Make line k fast to its bollard (a stowed or a free line); return what was done.

    :raises CommandError: it is fast already, or the bollard is out of its reach.
    """
    _check_can_handle(mooring, k)
    line = mooring.lines[k]
    if line.state == 'fast':
        raise CommandError(f'{who(mooring, k)} is already fast to {bollard_name(mooring, k)}')
    t = mooring.time
    fairlead = mooring.free_ends(k, [t])[0][0, 1]
    bollard = mooring.ends.bollard(k, t)
    distance = float(np.linalg.norm(bollard - fairlead))
    if line.state == 'stowed':
        length = distance * (1.0 + line.params.make_fast_slack)
        most = line.winch().max_length
        if length > most:
            raise CommandError(
                f'{who(mooring, k)} cannot reach {bollard_name(mooring, k)}: it is '
                f'{distance:.1f} m from the fairlead, and {length:.1f} m with '
                f'make_fast_slack {line.params.make_fast_slack:g} is more than the '
                f'{most:.1f} m the line has (winch_max_length)')
    else:
        length = line.length
        if distance > length:
            raise CommandError(
                f'{who(mooring, k)} cannot reach {bollard_name(mooring, k)}: it is '
                f'{distance:.1f} m from the fairlead and the line has {length:.1f} m out: pay '
                'out first')
    line.length = length
    line.state = 'fast'
    mooring.ends.changed()
    mooring.place_out(k, mooring.at_rest_or_parted(k, t))
    return (f'{who(mooring, k)} made fast to {bollard_name(mooring, k)}: {length:.1f} m out, '
            f'{distance:.1f} m from the fairlead')


def let_go(mooring, k: int) -> str:
    """
    Let line k go from its bollard in this step; return what was done (its tension then).

    :raises CommandError: it is not fast.
    """
    _check_can_handle(mooring, k)
    line = mooring.lines[k]
    if line.state != 'fast':
        raise CommandError(f'{who(mooring, k)} is not fast ({_state_words(line.state)}): '
                           'there is nothing to let go')
    tension = _bollard_tension(mooring, k)
    _free_the_eye(mooring, [k])
    return f'{who(mooring, k)} let go from {bollard_name(mooring, k)} at {tension / 1e3:.1f} kN'


def let_go_all(mooring) -> str:
    """
    Let every fast line go in this step (an emergency release); return what was done.

    :raises CommandError: no line is fast.
    """
    fast = [k for k, line in enumerate(mooring.lines)
            if line.state == 'fast' and line.parting is None and not line.payload]
    if not fast or not mooring.started:
        raise CommandError('no line is fast: there is nothing to let go'
                           if mooring.started else
                           'the lines cannot be handled yet: they start at the first ship pose')
    _free_the_eye(mooring, fast)
    names = ', '.join(mooring.names[k] or 'the line' for k in fast)
    return f'let go all: {names} ({len(fast)} line{"s" if len(fast) > 1 else ""})'


def stow(mooring, k: int) -> str:
    """
    Take line k aboard: a free line heaved in to its winch_min_length; return what was done.

    :raises CommandError: it is not free, or still longer than its shortest length.
    """
    _check_can_handle(mooring, k)
    line = mooring.lines[k]
    if line.state != 'free':
        raise CommandError(f'{who(mooring, k)} is {_state_words(line.state)}: only a line let '
                           'go and heaved in can be stowed')
    shortest = line.winch().min_length
    out = line.length - shortest
    if out > STOWED_LENGTH_TOLERANCE:
        raise CommandError(
            f'{who(mooring, k)} still has {out:.1f} m more out than its winch_min_length '
            f'({line.length:.1f} m, shortest {shortest:.1f} m): heave it in first')
    line.state = 'stowed'
    mooring.ends.changed()
    mooring.regroup()
    return f'{who(mooring, k)} stowed'


def release_hooks(mooring) -> Dict[int, float]:
    """
    Let go every fast line whose tension at its bollard passed its release_load.

    The bollard end's peak since the last output (what every step raised) against the
    hook's load. Called after each advance.

    :returns: {line index: the peak tension [N] that released it}.
    """
    released = {}
    for k, line in enumerate(mooring.lines):
        load = line.params.release_load
        if load > 0.0 and line.state == 'fast' and line.parting is None:
            group, j = mooring.where(k)
            peak = float(group.system.line_real[j, PEAK_A])
            if peak > load:
                released[k] = peak
    if released:
        _free_the_eye(mooring, list(released))
    return released


def command(mooring, k: int, name: str) -> str:
    """
    Take one command by name (COMMANDS) on line k (any k for let_go_all).

    :raises CommandError: an unknown command, or one refused (the message says why).
    """
    if name == 'let_go_all':
        return let_go_all(mooring)
    actions = {'make_fast': make_fast, 'let_go': let_go, 'stow': stow}
    if name not in actions:
        raise CommandError(f'command {name!r} is not one of {", ".join(COMMANDS)}')
    return actions[name](mooring, k)


def recoiling(line, t: float) -> bool:
    """
    Tell whether a line let go may still be recoiling at t [s]: watched for its snaps.

    Its stored energy is released in the first 2 L / c (the release wave's way to the
    fairlead and back), and the adaptive integrator's hold after a snap is HOLD_TIME more.
    After that a line let go only falls, swings and lies: the adaptive integrator takes it
    in implicit steps. Watched, the flailing rope's slack segments kept it in improved Euler
    (each a snap about to come): one line let go of the sixteen-line berth put outputs 38
    ms behind, all of them 0.8 s.
    """
    props = line.line_props
    wave_speed = math.sqrt(props.axial_stiffness / props.mass_per_length)
    window = 2.0 * props.length / wave_speed + HOLD_TIME
    return not (line.state == 'free' and not line.payload and t > line.let_go_at + window)


def _state_words(state: str) -> str:
    return {'fast': 'fast on its bollard', 'free': 'let go, free',
            'stowed': 'stowed aboard'}[state]


def _bollard_tension(mooring, k: int) -> float:
    """Return line k's tension at its bollard now [N]."""
    group, j = mooring.where(k)
    return float(np.linalg.norm(group.system.loads()[0][j, 0]))


def _free_the_eye(mooring, lines: List[int]) -> None:
    """Make the bollard end of each of these fast lines a free point, where and as it moves."""
    systems = set()
    for k in lines:
        group, j = mooring.where(k)
        system = group.system
        system.points[system.lines[j].ends[0]].kind = 'free'
        systems.add(group)
        mooring.lines[k].state = 'free'
        mooring.lines[k].let_go_at = mooring.time
        mooring.held[k] = False
    mooring.ends.changed()
    for group in systems:
        group.system.refresh()
        group.refresh(mooring.lines, mooring.environment)
