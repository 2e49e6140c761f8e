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
Message definitions and type hashes as rosbag2 Jazzy embeds them in MCAP schemas.

rosbag2_storage_mcap (message_definition_cache.cpp) stores for each type the root .msg
file verbatim, then every nested type once, depth-first in sorted order, each preceded by
a newline, a line of 80 '=' and 'MSG: pkg/Type'. rosbag2 reads the .msg files from the
ament index; here they come from definitions.py, a copy of them for the types this package
records, so that the offline commands write the very schema a `ros2 bag record` would
without ROS installed (a test compares the copy with the installed files). Other types are
the ROS side's business: rope_sim_ros.ros2bag reads them from the ament index.
"""

import functools
import re
from typing import Callable, Tuple

from .definitions import DEFINITIONS
from .errors import BagError

#: MCAP schema encoding of a .msg text (ros2 profile).
SCHEMA_ENCODING = 'ros2msg'

# 'pkg/msg/Type' or 'pkg/Type', the forms rosbag2 accepts for a message type.
_TYPE_NAME = re.compile(r'^([a-zA-Z][a-zA-Z0-9_]*)/(?:msg/)?([a-zA-Z][a-zA-Z0-9_]*)$')
# The field types of a .msg text, the same expression rosbag2 uses, so that the set of
# nested types (and thus the schema text) comes out identical.
_FIELD_TYPE = re.compile(r'(?:^|\n)\s*([a-zA-Z0-9_/]+)(?:\[[^\]]*\])?\s+')
_PRIMITIVES = frozenset((
    'bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16', 'uint16',
    'int32', 'uint32', 'int64', 'uint64', 'string', 'wstring'))
_DELIMITER = '=' * 80 + '\n'
# rosbag2 gives up at this depth; a deeper nesting would be a cycle.
_MAX_DEPTH = 50


def split_type_name(type_name: str) -> Tuple[str, str]:
    """
    Split a message type name into its package and type.

    :param type_name: 'geometry_msgs/msg/PoseStamped' or 'geometry_msgs/PoseStamped'.

    :returns: The package and the type, e.g. ('geometry_msgs', 'PoseStamped').

    :raises BagError: the name is not of the form pkg/msg/Type.
    """
    match = _TYPE_NAME.match(type_name) if isinstance(type_name, str) else None
    if match is None:
        raise BagError(
            f'message type {type_name!r} is not understood: expected pkg/msg/Type, '
            "e.g. 'geometry_msgs/msg/PoseStamped'")
    return match.group(1), match.group(2)


def canonical_type_name(type_name: str) -> str:
    """
    Return the 'pkg/msg/Type' form of a message type name.

    :param type_name: 'pkg/msg/Type' or 'pkg/Type'.

    :returns: The name with its 'msg' namespace, as rosbag2 writes it in metadata.yaml.

    :raises BagError: the name is not of the form pkg/msg/Type.
    """
    package, name = split_type_name(type_name)
    return f'{package}/msg/{name}'


def known_types() -> Tuple[str, ...]:
    """Return the message types whose definitions this package carries, sorted."""
    return tuple(sorted(DEFINITIONS))


def _stored(type_name: str) -> Tuple[str, str]:
    canonical = canonical_type_name(type_name)
    try:
        return DEFINITIONS[canonical]
    except KeyError:
        raise BagError(
            f'message type {canonical!r} is not one this package records without ROS '
            f'({", ".join(known_types())}); record other types through '
            'rope_sim_ros.ros2bag.RosBagWriter, which reads the installed definitions') from None


def msg_text(type_name: str) -> str:
    """
    Return the .msg file text of a message type, as installed in share/<pkg>/msg.

    :raises BagError: the name is malformed or the type is not one of known_types().
    """
    return _stored(type_name)[0]


def dependencies(text: str, package: str) -> list:
    """Return the nested message types a .msg text names, as rosbag2 finds and orders them."""
    found = set()
    for match in _FIELD_TYPE.finditer(text):
        field_type = match.group(1)
        if field_type in _PRIMITIVES:
            continue
        found.add(field_type if '/' in field_type else f'{package}/{field_type}')
    # std::set order in rosbag2: plain byte-wise string order.
    return sorted(found)


def expand_definition(type_name: str, text_of: Callable[[str], str]) -> str:
    """
    Return a type's full ros2msg definition from its own and its nested types' .msg texts.

    :param type_name: 'pkg/msg/Type' (or 'pkg/Type').
    :param text_of: returns the .msg text of a type named 'pkg/Type' or 'pkg/msg/Type'.

    :returns: The root .msg text followed by each nested type's text, depth-first and sorted.

    :raises BagError: the name is malformed, a text cannot be had or the nesting is a cycle.
    """
    seen = set()

    def append(name: str, depth: int) -> str:
        if depth <= 0:
            raise BagError(
                f'the definition of {type_name!r} nests deeper than {_MAX_DEPTH} levels; '
                'message types must not be recursive')
        package, _ = split_type_name(name)
        text = text_of(name)
        parts = [text]
        for dependency in dependencies(text, package):
            if dependency not in seen:
                seen.add(dependency)
                parts.append('\n' + _DELIMITER + 'MSG: ' + dependency + '\n')
                parts.append(append(dependency, depth - 1))
        return ''.join(parts)

    return append(type_name, _MAX_DEPTH)


@functools.lru_cache(maxsize=None)
def message_definition(type_name: str) -> str:
    """
    Return the full ros2msg definition of a message type as rosbag2 Jazzy embeds it.

    :param type_name: 'pkg/msg/Type' (or 'pkg/Type'), one of known_types().

    :returns: The root .msg text followed by each nested type's text, depth-first and sorted.

    :raises BagError: the name is malformed or the type is not one of known_types().
    """
    return expand_definition(type_name, msg_text)


def type_hash(type_name: str) -> str:
    """
    Return the RIHS01 type description hash of a message type.

    :param type_name: 'pkg/msg/Type' (or 'pkg/Type'), one of known_types().

    :returns: The 'RIHS01_<sha256>' string of share/<pkg>/msg/<Type>.json.

    :raises BagError: the name is malformed or the type is not one of known_types().
    """
    return _stored(type_name)[1]
