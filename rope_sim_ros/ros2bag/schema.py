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
Message definitions, type hashes and classes of the installed ROS 2 message packages.

The ROS side of rope_sim_ros.bag.schema: where that module knows only the types whose
definitions it carries (bag/definitions.py), this one reads any type from the ament index
(AMENT_PREFIX_PATH), exactly where rosbag2 looks, and imports its rosidl Python class.
It also writes bag/definitions.py from the installed files::

    python -m rope_sim_ros.ros2bag > rope_sim_ros/bag/definitions.py
"""

import functools
import importlib
import json
import os
import sys
from typing import Iterable, List

from ament_index_python.packages import get_package_share_directory
from ament_index_python.packages import PackageNotFoundError

from ..bag import schema as stored
from ..bag.errors import BagError

#: The message types bag/definitions.py carries: what the nodes and the offline commands
#: record or are about to (their nested types come along).
RECORDED_TYPES = (
    'diagnostic_msgs/msg/DiagnosticArray',
    'geometry_msgs/msg/PoseArray',
    'geometry_msgs/msg/PoseStamped',
    'geometry_msgs/msg/Vector3Stamped',
    'geometry_msgs/msg/Wrench',
    'geometry_msgs/msg/WrenchStamped',
    'nav_msgs/msg/Odometry',
    'std_msgs/msg/Bool',
    'std_msgs/msg/Float64',
    'std_msgs/msg/Float64MultiArray',
    'std_msgs/msg/String',
    'visualization_msgs/msg/MarkerArray',
)


def _interface_file(type_name: str, extension: str) -> str:
    package, name = stored.split_type_name(type_name)
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
def installed_msg_text(type_name: str) -> str:
    """
    Return the installed .msg file text of a message type.

    :raises BagError: the package is not in the ament index or has no such file.
    """
    path = _interface_file(type_name, '.msg')
    try:
        with open(path, encoding='utf-8', newline='') as stream:
            return stream.read()
    except OSError as exc:
        raise BagError(
            f'cannot read the definition of {type_name!r} from {path}: {exc.strerror}; '
            'only message types with a .msg file in share/<pkg>/msg are supported') from None


@functools.lru_cache(maxsize=None)
def installed_type_hash(type_name: str) -> str:
    """
    Return the RIHS01 type description hash of an installed message type.

    :returns: The 'RIHS01_<sha256>' string from share/<pkg>/msg/<Type>.json.

    :raises BagError: the .json file is missing, unreadable or does not list the type.
    """
    canonical = stored.canonical_type_name(type_name)
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
def message_definition(type_name: str) -> str:
    """
    Return the full ros2msg definition of a message type as rosbag2 Jazzy embeds it.

    :param type_name: 'pkg/msg/Type' (or 'pkg/Type'), any installed message type.

    :raises BagError: the type is unknown or its .msg files cannot be read.
    """
    return stored.expand_definition(type_name, installed_msg_text)


def type_hash(type_name: str) -> str:
    """
    Return the RIHS01 type description hash of any installed message type.

    :raises BagError: the type is unknown or its .json file cannot be read.
    """
    return installed_type_hash(type_name)


@functools.lru_cache(maxsize=None)
def message_class(type_name: str) -> type:
    """
    Import the Python class of a message type.

    :param type_name: 'pkg/msg/Type' (or 'pkg/Type').

    :returns: The generated rosidl class, e.g. geometry_msgs.msg.PoseStamped.

    :raises BagError: the package has no Python message module or lacks the type.
    """
    package, name = stored.split_type_name(type_name)
    try:
        module = importlib.import_module(f'{package}.msg')
        return getattr(module, name)
    except (ImportError, AttributeError) as exc:
        raise BagError(
            f'cannot import the Python class of {type_name!r}: {exc}; '
            f'the package {package!r} must be installed with its Python bindings') from None


def closure(type_names: Iterable[str]) -> List[str]:
    """Return the given types and every type nested in them, canonical and sorted."""
    found = set()
    todo = [stored.canonical_type_name(name) for name in type_names]
    while todo:
        name = todo.pop()
        if name in found:
            continue
        found.add(name)
        package, _ = stored.split_type_name(name)
        todo.extend(stored.canonical_type_name(dependency) for dependency in
                    stored.dependencies(installed_msg_text(name), package))
    return sorted(found)


def _literal(text: str) -> str:
    escaped = (text.replace('\\', '\\\\').replace("'", "\\'").replace('\n', '\\n')
               .replace('\r', '\\r').replace('\t', '\\t'))
    return "'" + escaped + "'"


def _text_lines(text: str, indent: str, width: int = 99) -> List[str]:
    # one literal per source line, long lines cut into pieces that fit
    room = width - len(indent) - 2
    lines = []
    for line in text.splitlines(keepends=True):
        piece = ''
        for char in line:
            if len(_literal(piece + char)) > room:
                lines.append(indent + _literal(piece))
                piece = ''
            piece += char
        lines.append(indent + _literal(piece))
    return lines or [indent + "''"]


def definitions_source(type_names: Iterable[str] = RECORDED_TYPES) -> str:
    """Return the text of bag/definitions.py for the given types and their nested types."""
    with open(__file__, encoding='utf-8') as stream:
        header = ''.join(line for line in stream.readlines()[:14])
    out = [header + '"""',
           'The .msg texts and RIHS01 hashes of the message types recorded without ROS.',
           '',
           'Generated from the installed message packages by',
           '`python -m rope_sim_ros.ros2bag > rope_sim_ros/bag/definitions.py`; a test',
           'fails when they differ from what is installed. Do not edit by hand.',
           '"""',
           '',
           '#: canonical type name -> (the share/<pkg>/msg/<Type>.msg text, its RIHS01 hash)',
           'DEFINITIONS = {']
    for name in closure(type_names):
        out.append(f"    '{name}': (")
        out.extend(_text_lines(installed_msg_text(name), ' ' * 8))
        out[-1] += ','
        out.append(f"        '{installed_type_hash(name)}'),")
    out.append('}')
    return '\n'.join(out) + '\n'


def main() -> int:
    """Print bag/definitions.py for RECORDED_TYPES."""
    sys.stdout.write(definitions_source())
    return 0
