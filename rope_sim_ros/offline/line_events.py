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
What an offline run did to its lines' states: the line events, and how a bag holds them.

A line event is a line-handling command the run took at its time (COMMANDS.csv), or
refused, or a line that its quick-release hook let go. A bag records them on the node's
events topic as the node's events (mooring/events.py): 'command' (line, command, t, text)
and 'released' (line, tension, t), the line '' for let_go_all and for the single line,
as the node names them. A node records only the commands it took; a run also
records the ones it refused, with ``refused: true`` and the text saying why, so that its
bag says what became of every row of its commands file. A command that named a bollard is
preceded by the parameter set of the line's bollard ('set'), as a node records both.

Such a bag is marked in its metadata as a run's (RECORDED_BY): its events are the run's
commands, which ``rope_sim resim`` takes again at their times (recorded_commands), not a
node's decisions to replay in order.
"""

from dataclasses import dataclass
import math
from typing import Callable, List

from .sinks import BagSink
from ..bag import BagError, cdr, read_messages
from ..messages.topics import Layout
from ..mooring.events import decode_event, encode_event
from ..mooring.records import ScheduledCommand

# metadata.yaml custom_data of a bag `rope_sim run` (or resim of one) records: its events
# topic holds the run's line events, not a node's decisions (resim replays those in order).
RECORDED_BY = ('rope_sim_ros.recorded_by', 'rope_sim run')


@dataclass(frozen=True)
class LineEvent:
    """
    What a run did to a line's state: a command taken (or refused), or a hook's release.

    :ivar kind: 'command' or 'released' (the events' kinds, mooring/events.py).
    :ivar t: the simulated time it happened at [s] (the state time between two steps).
    :ivar stamp_ns: its stamp [ns] (the run's epoch plus t).
    :ivar line: the line's name ('' for let_go_all, and the single line's).
    :ivar text: one line: what was done, why the command was refused, or the release.
    :ivar command: the command (mooring/handling.py COMMANDS); '' for a release.
    :ivar refused: the command was refused: nothing changed (but a bollard given first).
    :ivar bollard: the bollard the line was given before the command ('' none).
    :ivar tension: a release's tension at the bollard [N] (NaN for a command).
    """

    kind: str
    t: float
    stamp_ns: int
    line: str
    text: str
    command: str = ''
    refused: bool = False
    bollard: str = ''
    tension: float = math.nan

    def label(self) -> str:
        """Return a short label: 'head_1 make fast', 'let go all', 'head_1 released'."""
        return event_label(self.kind, self.line, self.command, self.refused)


EventSink = Callable[[LineEvent], None]


def event_label(kind: str, line: str, command: str = '', refused: bool = False) -> str:
    """Return a line event's short label: 'head_1 make fast', 'let go all', 'head_1 released'."""
    what = command.replace('_', ' ') if kind == 'command' else kind
    label = f'{line} {what}' if line else what
    return f'{label} (refused)' if refused else label


def event_texts(event: LineEvent, layout: Layout) -> List[str]:
    """Return a line event as the node's events (JSON texts, mooring/events.py), in order."""
    if event.kind == 'released':
        return [encode_event('released', line=event.line, tension=event.tension, t=event.t)]
    texts = []
    if event.bollard:  # a parameter set, which names its line as the node's do
        texts.append(encode_event('set', **layout.line_field(event.line),
                                  values={'bollard': event.bollard}))
    refused = {'refused': True} if event.refused else {}
    texts.append(encode_event('command', line=event.line, command=event.command, t=event.t,
                              text=event.text, **refused))
    return texts


class BagEvents:
    """Records a run's line events in its bag, on the events topic, at their stamps."""

    def __init__(self, bag: BagSink, layout: Layout) -> None:
        """Record into this bag, on this layout's events topic."""
        self.bag = bag
        self.layout = layout

    def __call__(self, event: LineEvent) -> None:
        """Record one event (two for a command that named a bollard: event_texts)."""
        for text in event_texts(event, self.layout):
            self.bag.write(self.layout.events, cdr.string(text), event.stamp_ns)


def recorded_commands(path, topic: str) -> List[ScheduledCommand]:
    """
    Return the line-handling commands a bag's events topic holds, at the times taken.

    Refused ones too: a run with other parameters may take them. A 'set' of a line's
    bollard before its command is the bollard the command named.

    :raises BagError: an event that cannot be read.
    """
    commands: List[ScheduledCommand] = []
    bollards = {}
    for message in read_messages(path, [topic]):
        text = cdr.decode_string(message.data)
        try:
            event = decode_event(text)
            line = str(event.get('line', ''))
            if event['event'] == 'set' and 'bollard' in event['values']:
                bollards[line] = str(event['values']['bollard'])
            elif event['event'] == 'command':
                commands.append(ScheduledCommand(float(event['t']), line,
                                                 str(event['command']), bollards.pop(line, '')))
        except (ValueError, KeyError, TypeError) as e:
            raise BagError(f'{topic}: cannot read {text!r}: {e}') from None
    return commands
