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
a newline, a line of 80 '=' and 'MSG: pkg/Type'. The files come from the ament index
(AMENT_PREFIX_PATH), exactly where rosbag2 looks for them, so a bag written here carries
the same schema text a `ros2 bag record` of the same topics would.
"""

import functools
import importlib
import json
import os
import re
import sys
from typing import Tuple

from ament_index_python.packages import get_package_share_directory
from ament_index_python.packages import PackageNotFoundError

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
    'int32', 'uint32', 'int64', 'uint64', 'string'))
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
    match = _TYPE_NAME.match(type_name)
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


def _interface_file(type_name: str, extension: str) -> str:
    package, name = split_type_name(type_name)
    try:
        share = get_package_share_directory(package)
    except (PackageNotFoundError, LookupError, OSError) as exc:
        # ROS 2 from PyPI wheels keeps share/ in the Python prefix, which a shell that has
        # sourced no setup file does not name in AMENT_PREFIX_PATH
        share = os.path.join(sys.prefix, 'share', package)
        if os.path.isdir(os.path.join(share, 'msg')):
            return os.path.join(share, 'msg', name + extension)
        raise BagError(
            f'message package {package!r} of type {type_name!r} is not in the ament index '
            f'(AMENT_PREFIX_PATH={os.environ.get("AMENT_PREFIX_PATH", "")!r}): {exc}; '
            'install the package or add its prefix to AMENT_PREFIX_PATH') from None
    return os.path.join(share, 'msg', name + extension)


@functools.lru_cache(maxsize=None)
def _msg_text(type_name: str) -> str:
    path = _interface_file(type_name, '.msg')
    try:
        with open(path, encoding='utf-8', newline='') as stream:
            return stream.read()
    except OSError as exc:
        raise BagError(
            f'cannot read the definition of {type_name!r} from {path}: {exc.strerror}; '
            'only message types with a .msg file in share/<pkg>/msg are supported') from None


def _dependencies(text: str, package: str) -> list:
    found = set()
    for match in _FIELD_TYPE.finditer(text):
        field_type = match.group(1)
        if field_type in _PRIMITIVES:
            continue
        found.add(field_type if '/' in field_type else f'{package}/{field_type}')
    # std::set order in rosbag2: plain byte-wise string order.
    return sorted(found)


@functools.lru_cache(maxsize=None)
def message_definition(type_name: str) -> str:
    """
    Return the full ros2msg definition of a message type as rosbag2 Jazzy embeds it.

    :param type_name: 'pkg/msg/Type' (or 'pkg/Type').

    :returns: The root .msg text followed by each nested type's text, depth-first and sorted.

    :raises BagError: the type is unknown or its .msg files cannot be read.
    """
    seen = set()

    def append(name: str, depth: int) -> str:
        if depth <= 0:
            raise BagError(
                f'the definition of {type_name!r} nests deeper than {_MAX_DEPTH} levels; '
                'message types must not be recursive')
        package, _ = split_type_name(name)
        text = _msg_text(name)
        parts = [text]
        for dependency in _dependencies(text, package):
            if dependency not in seen:
                seen.add(dependency)
                parts.append('\n' + _DELIMITER + 'MSG: ' + dependency + '\n')
                parts.append(append(dependency, depth - 1))
        return ''.join(parts)

    return append(type_name, _MAX_DEPTH)


@functools.lru_cache(maxsize=None)
def type_hash(type_name: str) -> str:
    """
    Return the RIHS01 type description hash of a message type.

    :param type_name: 'pkg/msg/Type' (or 'pkg/Type').

    :returns: The 'RIHS01_<sha256>' string from share/<pkg>/msg/<Type>.json.

    :raises BagError: the .json file is missing, unreadable or does not list the type.
    """
    canonical = canonical_type_name(type_name)
    path = _interface_file(type_name, '.json')
    try:
        with open(path, encoding='utf-8') as stream:
            hashes = json.load(stream)['type_hashes']
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise BagError(
            f'cannot read the type hash of {canonical!r} from {path}: {exc}; '
            'a Jazzy message package installs share/<pkg>/msg/<Type>.json') from None
    for entry in hashes:
        if entry.get('type_name') == canonical:
            return entry['hash_string']
    raise BagError(f'{path} has no type hash for {canonical!r}; expected a "type_hashes" entry')


@functools.lru_cache(maxsize=None)
def message_class(type_name: str) -> type:
    """
    Import the Python class of a message type.

    :param type_name: 'pkg/msg/Type' (or 'pkg/Type').

    :returns: The generated rosidl class, e.g. geometry_msgs.msg.PoseStamped.

    :raises BagError: the package has no Python message module or lacks the type.
    """
    package, name = split_type_name(type_name)
    try:
        module = importlib.import_module(f'{package}.msg')
        return getattr(module, name)
    except (ImportError, AttributeError) as exc:
        raise BagError(
            f'cannot import the Python class of {type_name!r}: {exc}; '
            f'the package {package!r} must be installed with its Python bindings') from None
