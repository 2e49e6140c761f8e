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

"""ROS 2 parameter files (`node: ros__parameters: {...}`) read as the nodes would read them."""

from typing import Any, Mapping, Optional

import yaml

from .table import from_values, LineParams, NODE_NAME, ParameterError


def read_params_file(path, node_name: str = NODE_NAME) -> dict:
    """
    Read the `ros__parameters` of `node_name` from a ROS 2 parameter YAML file.

    Accepts the node name with or without a namespace and the `/**` wildcard, as the ROS
    parameter file format does.

    :raises ParameterError: unreadable file or no parameters for the node.
    """
    try:
        with open(path, encoding='utf-8') as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise ParameterError(f'cannot read parameter file {path}: {e.strerror}') from None
    except yaml.YAMLError as e:
        raise ParameterError(f'parameter file {path} is not valid YAML: {e}') from None
    if not isinstance(data, dict):
        raise ParameterError(f'parameter file {path} has no "{node_name}:" section')
    values = {}
    for key, section in data.items():
        short = str(key).rstrip('/').split('/')[-1]
        if short in (node_name, '**') and isinstance(section, dict):
            values.update(section.get('ros__parameters') or {})
    if not values:
        raise ParameterError(
            f'parameter file {path} has no "{node_name}: ros__parameters:" section')
    values.pop('use_sim_time', None)
    return values


def load_params(path, overrides: Optional[Mapping[str, Any]] = None) -> LineParams:
    """Read and validate a parameter file, with optional overrides on top."""
    values = read_params_file(path)
    values.update(overrides or {})
    return from_values(values)
