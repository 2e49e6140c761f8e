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
ROS 2 parameter files (`node: ros__parameters: {...}`), read as ROS itself reads them.

ROS's parameter file parser reads an unquoted scalar that looks like a number as a number:
`time_step: 5e-05` is a double. PyYAML follows YAML 1.1, whose floats need a dot (5.0e-05)
and which reads 5e-05 as the text '5e-05': a node given that file took 5e-05 s while the
offline commands refused it as text. ROS_LOADER reads such numbers as ROS does; a quoted
'5e-05' stays text, in both.
"""

import re
from typing import Any, Mapping, Optional

import yaml

from .table import from_values, LineParams, NODE_NAME, ParameterError


class RosLoader(getattr(yaml, 'CSafeLoader', yaml.SafeLoader)):
    """
    PyYAML's safe loader, with the numbers ROS's parser takes that YAML 1.1 does not.

    On libyaml's parser where PyYAML has it (its wheels do): nine times as fast as the pure
    Python one on config/berth.yaml (2 ms against 21 ms), which a study reading its base
    arrangement, and every command, feels.
    """


# an exponent without a dot in the mantissa (1e3, 5e-05, -2E+4): a float, as for ROS
RosLoader.add_implicit_resolver(
    'tag:yaml.org,2002:float', re.compile(r'^[-+]?[0-9][0-9_]*(?:\.[0-9_]*)?[eE][-+]?[0-9]+$'),
    list('-+0123456789'))


def load_yaml(text: str) -> Any:
    """Read YAML text as ROS's parameter parser would (RosLoader)."""
    return yaml.load(text, Loader=RosLoader)  # noqa: S506 (a safe loader)


def read_yaml_file(path, kind: str, error: type = ParameterError) -> Any:
    """
    Read a YAML file as load_yaml does.

    :param kind: what the file is, for the errors ('parameter file', 'study file').
    :raises error: unreadable or not YAML, in one line naming the file.
    """
    try:
        with open(path, encoding='utf-8') as stream:
            return load_yaml(stream.read())
    except OSError as e:
        raise error(f'cannot read {kind} {path}: {e.strerror or e}') from None
    except yaml.YAMLError as e:
        raise error(f'{kind} {path} is not valid YAML: {" ".join(str(e).split())}') from None


def read_params_file(path, node_name: str = NODE_NAME, optional: bool = False) -> dict:
    """
    Read the `ros__parameters` of `node_name` from a ROS 2 parameter YAML file.

    Accepts the node name with or without a namespace and the `/**` wildcard, as the ROS
    parameter file format does.

    :param optional: a file with no parameters for the node gives {} (one file may hold
        several nodes' parameters, or some of them).
    :raises ParameterError: unreadable file or (not optional) no parameters for the node.
    """
    data = read_yaml_file(path, 'parameter file')
    if optional and not isinstance(data, dict):
        return {}
    if not isinstance(data, dict):
        raise ParameterError(f'parameter file {path} has no "{node_name}:" section')
    values = {}
    for key, section in data.items():
        short = str(key).rstrip('/').split('/')[-1]
        if short in (node_name, '**') and isinstance(section, dict):
            values.update(section.get('ros__parameters') or {})
    if not values and not optional:
        raise ParameterError(
            f'parameter file {path} has no "{node_name}: ros__parameters:" section')
    values.pop('use_sim_time', None)
    return values


def load_params(path, overrides: Optional[Mapping[str, Any]] = None) -> LineParams:
    """Read and validate a parameter file, with optional overrides on top."""
    values = read_params_file(path)
    values.update(overrides or {})
    return from_values(values)


def parse_set(items) -> dict:
    """
    Parse ``--set key=value`` items of the offline commands; values are YAML, read as ROS does.

    :param items: the raw items (None: none).
    :returns: {key: value}, the last item winning.
    :raises ParameterError: an item is not key=value or its value is not YAML.
    """
    values = {}
    for item in items or []:
        key, sep, text = item.partition('=')
        key = key.strip()
        if not sep or not key:
            raise ParameterError(f'--set {item!r}: expected key=value, e.g. --set length=40')
        try:
            values[key] = load_yaml(text) if text.strip() else ''
        except yaml.YAMLError:
            raise ParameterError(f'--set {item!r}: {text!r} is not a YAML value') from None
    return values
