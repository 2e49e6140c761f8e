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
The physics layer never imports ROS.

Two independent checks: a static one (every import statement, and every
``importlib.import_module`` / ``__import__`` call with a literal name, in every .py file under
rope_sim_ros/physics/) and a dynamic one (import the package and all its modules in a fresh
interpreter and look at ``sys.modules``). The static check also refuses imports of the rooms
above physics (simulator, node, bag, CLI): physics imports nothing of ours above it.
"""

import ast
import json
import os
from pathlib import Path
import subprocess
import sys
import textwrap

REPO_ROOT = Path(__file__).resolve().parent.parent
PHYSICS_DIR = REPO_ROOT / 'rope_sim_ros' / 'physics'
PHYSICS_PACKAGE = 'rope_sim_ros.physics'

# Top-level ROS 2 distributions (client library, middleware, code generation, index,
# launch, bags, tf); message/service/action packages are recognised by their suffix.
ROS_ROOTS = frozenset({
    'rclpy', 'rcl', 'rcl_interfaces', 'rcl_logging_interface', 'rmw', 'rmw_implementation',
    'rpyutils', 'rosidl_runtime_py', 'rosidl_parser', 'rosidl_pycommon', 'rosidl_adapter',
    'ament_index_python', 'launch', 'launch_ros', 'launch_testing', 'rosbag2_py',
    'tf2_ros', 'tf2_py', 'tf_transformations', 'message_filters', 'ros2cli',
    'builtin_interfaces', 'unique_identifier_msgs', 'type_description_interfaces',
    'service_msgs', 'action_msgs',
})
ROS_PREFIXES = ('rclpy', 'rcl_', 'rmw_', 'rosidl', 'ament', 'launch_', 'rosbag2', 'tf2_', 'ros2')
ROS_SUFFIXES = ('_msgs', '_srvs', '_interfaces', '_actions')


def is_ros_module(name):
    """Return True if a dotted module name belongs to ROS 2 (not pure numerics)."""
    root = name.split('.')[0]
    return (root in ROS_ROOTS or root.startswith(ROS_PREFIXES)
            or root.endswith(ROS_SUFFIXES))


def is_upper_layer(name):
    """Return True if name is one of our modules outside the physics package."""
    return (name.startswith('rope_sim_ros.')
            and not name.split('.')[-1].startswith('__')
            and not (name == PHYSICS_PACKAGE or name.startswith(PHYSICS_PACKAGE + '.')))


def _resolve_relative(module, level, current_package):
    """Turn ``from ..x import y`` in current_package into an absolute dotted name."""
    parts = current_package.split('.')
    if level > len(parts):
        return module or ''
    base = parts[:len(parts) - level + 1]
    return '.'.join(base + ([module] if module else []))


def imported_modules(source, current_package=PHYSICS_PACKAGE, filename='<snippet>'):
    """Return (lineno, absolute module name) for every import in source, static or literal."""
    tree = ast.parse(source, filename=filename)
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.extend((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = _resolve_relative(node.module, node.level, current_package)
            else:
                base = node.module or ''
            found.append((node.lineno, base))
            # 'from rope_sim_ros import ros' imports the module rope_sim_ros.ros
            found.extend((node.lineno, base + '.' + alias.name)
                         for alias in node.names if alias.name != '*')
        elif isinstance(node, ast.Call) and node.args:
            func = node.func
            called = (func.attr if isinstance(func, ast.Attribute)
                      else func.id if isinstance(func, ast.Name) else '')
            arg = node.args[0]
            if called in ('import_module', '__import__') and \
                    isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                found.append((node.lineno, arg.value))
    return found


def forbidden_imports(source, current_package=PHYSICS_PACKAGE, filename='<snippet>'):
    """Return 'line N: name' for every ROS or upper-layer import in source."""
    flagged = [(lineno, name)
               for lineno, name in imported_modules(source, current_package, filename)
               if is_ros_module(name) or is_upper_layer(name)]
    # 'from rclpy.node import Node' flags rclpy.node; do not repeat it as rclpy.node.Node
    return ['line {}: {}'.format(lineno, name) for lineno, name in flagged
            if not any(line == lineno and name.startswith(other + '.')
                       for line, other in flagged)]


def physics_sources():
    files = sorted(PHYSICS_DIR.rglob('*.py'))
    return [f for f in files if '__pycache__' not in f.parts]


def _package_of(path):
    """Return the package a module file belongs to (its own package for __init__.py)."""
    return '.'.join(path.relative_to(REPO_ROOT).parts[:-1])


def test_detector_catches_ros_imports():
    bad = {
        'import rclpy': 'rclpy',
        'import rclpy.node as rn': 'rclpy.node',
        'from rclpy.node import Node': 'rclpy.node',
        'from geometry_msgs.msg import PoseStamped': 'geometry_msgs.msg',
        'import std_srvs.srv': 'std_srvs.srv',
        'from rosidl_runtime_py.convert import message_to_ordereddict':
            'rosidl_runtime_py.convert',
        'from ament_index_python.packages import get_package_share_directory':
            'ament_index_python.packages',
        'from rcl_interfaces.msg import ParameterDescriptor': 'rcl_interfaces.msg',
        'import importlib\nimportlib.import_module("rclpy")': 'rclpy',
        '__import__("sensor_msgs.msg")': 'sensor_msgs.msg',
        'def f():\n    import rclpy\n    return rclpy': 'rclpy',
        'try:\n    import rclpy\nexcept ImportError:\n    rclpy = None': 'rclpy',
        'from ..ros import mooring_line_node': 'rope_sim_ros.ros',
        'from .. import simulator': 'rope_sim_ros.simulator',
        'from rope_sim_ros.bag import writer': 'rope_sim_ros.bag',
    }
    for snippet, name in bad.items():
        problems = forbidden_imports(textwrap.dedent(snippet))
        assert any(name in p for p in problems), (snippet, problems)
    clean = textwrap.dedent("""
        import math
        import numpy as np
        from numpy.linalg import solve
        import yaml
        import numba
        from . import rope
        from .catenary import elastic_catenary
        from rope_sim_ros.physics import materials
        import importlib
        importlib.import_module('numpy')
        """)
    assert forbidden_imports(clean) == []
    for name in ('numpy', 'numba', 'scipy', 'yaml', 'mcap', 'math'):
        assert not is_ros_module(name), name
    for name in ('rclpy', 'nav_msgs.msg', 'rmw_fastrtps_cpp', 'rosidl_parser', 'launch_ros'):
        assert is_ros_module(name), name


def test_physics_sources_import_no_ros():
    sources = physics_sources()
    assert sources, 'no Python files under {}: nothing checked'.format(PHYSICS_DIR)
    problems = []
    for path in sources:
        found = forbidden_imports(path.read_text(encoding='utf-8'), _package_of(path), str(path))
        problems.extend('{}: {}'.format(path.relative_to(REPO_ROOT), p) for p in found)
    assert not problems, \
        'rope_sim_ros/physics must not import ROS or the layers above it:\n' + \
        '\n'.join(problems)


def test_importing_physics_loads_no_ros():
    script = textwrap.dedent("""
        import importlib, json, pkgutil, sys
        import rope_sim_ros.physics as physics
        for info in pkgutil.walk_packages(physics.__path__, physics.__name__ + '.'):
            importlib.import_module(info.name)
        print(json.dumps(sorted(sys.modules)))
        """)
    env = dict(os.environ)
    env['PYTHONPATH'] = str(REPO_ROOT)
    env['PYTHONDONTWRITEBYTECODE'] = '1'
    result = subprocess.run(
        [sys.executable, '-c', script], cwd=str(REPO_ROOT), env=env,
        stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, \
        'importing {} failed:\n{}'.format(PHYSICS_PACKAGE, result.stderr[-4000:])
    modules = json.loads(result.stdout.strip().splitlines()[-1])
    assert PHYSICS_PACKAGE in modules
    assert 'rclpy' not in modules, 'importing {} loaded rclpy'.format(PHYSICS_PACKAGE)
    loaded = [m for m in modules if is_ros_module(m)]
    assert not loaded, \
        'importing {} (and all its modules) loaded ROS modules: {}'.format(
            PHYSICS_PACKAGE, ', '.join(loaded))
