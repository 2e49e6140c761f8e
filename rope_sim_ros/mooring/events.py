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
A live node's decisions and a model's doings as events: one JSON object each.

The node publishes them on its events topic and records them in its bag; `rope_sim resim`
reads them back and takes the same decisions at the same points (offline/resim.py).
"""

import json
from typing import Any, Dict

# The decisions a node records (one JSON object each, encode_event), and what a model did
# ('parted', 'ship_restart', 'released': replayed, the model does it again). A line-handling
# command is 'command' (line, command, t, text: what was done or why it was refused); a line
# its quick-release hook let go is 'released' (line, tension, t).
EVENT_KINDS = ('silent', 'skip', 'reset', 'clock_back', 'drop', 'restamp', 'set', 'winch',
               'start', 'load', 'parted', 'ship_restart', 'command', 'released')


def encode_event(kind: str, **fields: Any) -> str:
    """Return one event as JSON text: {'event': kind, ...fields}."""
    return json.dumps({'event': kind, **fields}, sort_keys=True)


def decode_event(text: str) -> Dict[str, Any]:
    """
    Return an event of encode_event's as a dict with at least 'event'.

    :raises ValueError: not a JSON object naming one of EVENT_KINDS.
    """
    event = json.loads(text)
    if not isinstance(event, dict) or event.get('event') not in EVENT_KINDS:
        raise ValueError(f'not an event: {text!r}')
    return event
