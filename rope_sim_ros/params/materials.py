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

"""The files of the configuration: where config/ is, and the materials file read from it."""

import functools
import os
from pathlib import Path
import sys

from .files import load_yaml
from ..model.materials import MaterialError, MaterialLibrary

CONFIG_DIR = Path(__file__).resolve().parents[2] / 'config'


def default_config_dir() -> Path:
    """
    Find config/: the source tree's, else the installed share/rope_sim_ros/config.

    An installed package lives in <prefix>/lib/pythonX.Y/site-packages/rope_sim_ros, so its
    own prefix is tried first: an executable started without a sourced setup file (no
    AMENT_PREFIX_PATH) still finds its materials.
    """
    if (CONFIG_DIR / 'materials.yaml').exists():
        return CONFIG_DIR
    own_prefix = Path(__file__).resolve().parents[:6][-1]
    prefixes = [own_prefix, Path(sys.prefix)]
    prefixes += [Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    for prefix in prefixes:
        candidate = prefix / 'share' / 'rope_sim_ros' / 'config'
        if (candidate / 'materials.yaml').exists():
            return candidate
    return CONFIG_DIR


def read_materials(path) -> MaterialLibrary:
    """
    Read a materials.yaml file (once while it stays as it is: a node's start reads it thrice).

    :raises MaterialError: the file is missing or has no `materials:` map.
    """
    try:
        changed = os.stat(path).st_mtime_ns
    except OSError as e:
        raise MaterialError(f'cannot read materials file {path}: {e.strerror}') from None
    return _read_materials(str(path), changed)


@functools.lru_cache(maxsize=8)
def _read_materials(path: str, changed: int) -> MaterialLibrary:
    """Read the materials file at path as it was when last changed (read_materials)."""
    try:
        with open(path, encoding='utf-8') as f:
            data = load_yaml(f.read())
    except OSError as e:
        raise MaterialError(f'cannot read materials file {path}: {e.strerror}') from None
    if not isinstance(data, dict) or not isinstance(data.get('materials'), dict):
        raise MaterialError(f'{path} has no "materials:" map')
    return MaterialLibrary(data['materials'])


def load_materials() -> MaterialLibrary:
    """Load the material presets of config/materials.yaml."""
    return read_materials(default_config_dir() / 'materials.yaml')
