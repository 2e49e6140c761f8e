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
Every room imports downward only, and the rooms below the ROS side import no ROS.

The rooms, bottom up (a module's room is its subpackage of rope_sim_ros):

- bag (bag/): the rosbag2/MCAP container; imports only itself;
- model (model/): what a mooring is: objects, forces, statics, frames; imports only itself;
- stepping (stepping/): the integrators, their step rules, bringing a shape to rest: model;
- params (params/): the parameter table, the arrangement format, the files they come from:
  model;
- mooring (mooring/): the one Mooring of 1..n lines and its one Driver: model, stepping,
  params;
- messages (messages/): every topic once and the outputs as message bytes: bag and the
  mooring (with what it imports);
- offline (offline/): run, resim, plot, info, the command line: everything above, no ROS;
- ros2bag (ros2bag/): message objects, QoS and installed types for bags: bag only;
- ros (ros/): the one node and the tool nodes: everything but offline;
- entry (rope_sim_ros/__main__.py, ``python -m rope_sim_ros``): goes through the launcher of
  the executables (ros/executables.py, standard library only) like the rope_sim command; it
  is checked by running it: the offline commands through it load no ROS.

Below ros and ros2bag no room imports ROS, and the nodes and the offline commands never
import each other: what both need lives below both. Two independent checks: a static one
(every import statement, also inside functions, and every ``importlib.import_module`` /
``__import__`` call with a literal name, in every .py file) and dynamic ones in fresh
interpreters (import a whole room, and run the offline commands on a bag, then look at
``sys.modules``).
"""

import ast
import json
import os
from pathlib import Path
import subprocess
import sys
import textwrap

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
PACKAGE = 'rope_sim_ros'
PACKAGE_DIR = REPO_ROOT / PACKAGE

ENTRY = 'entry'
OFFLINE = 'offline'
# rope_sim_ros/__init__.py, which every import of ours loads: imports nothing of ours
ROOT = 'root'
# room -> the rooms of ours it may import (besides the root package); every subpackage is a
# room of its own name
ALLOWED = {
    ROOT: set(),
    'bag': {'bag'},
    'model': {'model'},
    'stepping': {'model', 'stepping'},
    'params': {'model', 'params'},
    'mooring': {'model', 'stepping', 'params', 'mooring'},
    'messages': {'bag', 'model', 'stepping', 'params', 'mooring', 'messages'},
    OFFLINE: {'bag', 'model', 'stepping', 'params', 'mooring', 'messages', OFFLINE},
    'ros2bag': {'bag', 'ros2bag'},
    'ros': {'bag', 'model', 'stepping', 'params', 'mooring', 'messages', 'ros2bag', 'ros'},
    ENTRY: {'ros'},
}
ROS_FREE = (ROOT, 'bag', 'model', 'stepping', 'params', 'mooring', 'messages', OFFLINE)

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


def layer_of(name):
    """
    Return the room of one of our dotted names, or None for a name not ours.

    'rope_sim_ros.offline.run.BagSink' (from 'from .run import BagSink') is offline's; a
    module outside the rooms, or a new subpackage, is 'unassigned' (give it a room here).
    """
    parts = name.split('.')
    if parts[0] != PACKAGE:
        return None
    if len(parts) == 1 or parts[1] == '__init__':
        return ROOT
    if parts[1] == '__main__':
        return ENTRY
    if parts[1] in ALLOWED:
        return parts[1]
    return 'unassigned'  # give it a room (a module outside the rooms has none)


def module_name(path):
    """Return the dotted module name of a .py file of ours."""
    parts = list(path.relative_to(REPO_ROOT).with_suffix('').parts)
    if parts[-1] == '__init__':
        parts.pop()
    return '.'.join(parts)


def module_layer(path):
    """Return the layer of a .py file: that of its module ('rope_sim_ros' itself: ROOT)."""
    name = module_name(path)
    if name == PACKAGE:
        return ROOT
    return layer_of(name)


def _package_of(path):
    """Return the package a module file belongs to (its own package for __init__.py)."""
    return '.'.join(path.relative_to(REPO_ROOT).parts[:-1])


def _resolve_relative(module, level, current_package):
    """Turn ``from ..x import y`` in current_package into an absolute dotted name."""
    parts = current_package.split('.')
    if level > len(parts):
        return module or ''
    base = parts[:len(parts) - level + 1]
    return '.'.join(base + ([module] if module else []))


def imported_modules(source, current_package, filename='<snippet>'):
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


def forbidden_imports(source, layer, current_package, filename='<snippet>'):
    """Return 'line N: name (why)' for every import the layer must not make."""
    flagged = []
    for lineno, name in imported_modules(source, current_package, filename):
        target = layer_of(name)
        if layer in ROS_FREE and is_ros_module(name):
            flagged.append((lineno, name, 'ROS'))
        elif target not in (None, ROOT) and target not in ALLOWED[layer]:
            flagged.append((lineno, name, f'layer {target}'))
    # 'from rclpy.node import Node' flags rclpy.node; do not repeat it as rclpy.node.Node
    return [f'line {lineno}: {name} ({why})' for lineno, name, why in flagged
            if not any(line == lineno and name.startswith(other + '.')
                       for line, other, _ in flagged)]


def sources():
    return sorted(p for p in PACKAGE_DIR.rglob('*.py') if '__pycache__' not in p.parts)


def test_detector_catches_forbidden_imports():
    ros = {
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
    }
    for layer in ROS_FREE:
        for snippet, name in ros.items():
            problems = forbidden_imports(textwrap.dedent(snippet), layer, 'rope_sim_ros.model')
            assert any(name in p and '(ROS)' in p for p in problems), (layer, snippet, problems)
    # the ROS side may import ROS
    assert forbidden_imports('import rclpy', 'ros2bag', 'rope_sim_ros.ros2bag') == []
    upward = [
        ('model', 'rope_sim_ros.model', 'from ..stepping import kernels',
         'rope_sim_ros.stepping'),
        ('model', 'rope_sim_ros.model', 'from ..mooring import driver', 'rope_sim_ros.mooring'),
        ('model', 'rope_sim_ros.model', 'from rope_sim_ros.bag import writer',
         'rope_sim_ros.bag'),
        ('stepping', 'rope_sim_ros.stepping', 'from ..params import table',
         'rope_sim_ros.params'),
        ('params', 'rope_sim_ros.params', 'from ..mooring.line import MooringLine',
         'rope_sim_ros.mooring'),
        ('mooring', 'rope_sim_ros.mooring', 'from ..messages import topics',
         'rope_sim_ros.messages'),
        ('messages', 'rope_sim_ros.messages', 'from ..offline import run',
         'rope_sim_ros.offline'),
        ('bag', 'rope_sim_ros.bag', 'from ..model.frames import pose_point',
         'rope_sim_ros.model'),
        ('offline', 'rope_sim_ros.offline', 'from ..ros.conversions import pose_point',
         'rope_sim_ros.ros.conversions'),
        ('offline', 'rope_sim_ros.offline', 'def f():\n    from ..ros2bag import deserialize',
         'rope_sim_ros.ros2bag'),
        ('offline', 'rope_sim_ros.offline', 'import importlib\nimportlib.import_module(RECORDER)'
         .replace('RECORDER', repr('rope_sim_ros.ros.recorder')), 'rope_sim_ros.ros.recorder'),
        ('ros', 'rope_sim_ros.ros', 'from ..offline.run import simulate', 'rope_sim_ros.offline'),
        ('ros2bag', 'rope_sim_ros.ros2bag', 'from ..ros import conversions', 'rope_sim_ros.ros'),
        ('ros2bag', 'rope_sim_ros.ros2bag', 'from ..mooring import driver',
         'rope_sim_ros.mooring'),
        ('root', 'rope_sim_ros', 'from .offline import cli', 'rope_sim_ros.offline'),
    ]
    for layer, package, snippet, name in upward:
        problems = forbidden_imports(textwrap.dedent(snippet), layer, package)
        assert any(name in p for p in problems), (layer, snippet, problems)
    clean = [
        ('model', 'rope_sim_ros.model', 'from . import rope\nimport numpy as np\n'
         'from .statics.catenary import solve_catenary\nfrom rope_sim_ros.model import '
         'materials\nimport importlib\nimportlib.import_module("numba")'),
        ('bag', 'rope_sim_ros.bag', 'from . import cdr\nfrom .errors import BagError\n'
         'from mcap.writer import Writer\nimport yaml'),
        ('mooring', 'rope_sim_ros.mooring', 'from ..model.frames import pose_point\n'
         'from ..stepping.step import step\nfrom ..params.table import SPECS'),
        ('offline', 'rope_sim_ros.offline', 'from ..bag import cdr\nfrom ..mooring.driver import '
         'Driver\nfrom ..messages.encode import OutputEncoder\nfrom . import run'),
        ('ros2bag', 'rope_sim_ros.ros2bag', 'from ..bag import schema\nimport rclpy'),
        ('ros', 'rope_sim_ros.ros', 'from ..mooring.driver import Driver\nfrom ..ros2bag import '
         'RosBagWriter\nfrom ..bag import cdr\nimport rclpy\nfrom . import conversions'),
    ]
    for layer, package, snippet in clean:
        assert forbidden_imports(snippet, layer, package) == [], (layer, snippet)
    for name in ('numpy', 'numba', 'scipy', 'yaml', 'mcap', 'math'):
        assert not is_ros_module(name), name
    for name in ('rclpy', 'nav_msgs.msg', 'rmw_fastrtps_cpp', 'rosidl_parser', 'launch_ros'):
        assert is_ros_module(name), name


def test_layers_are_assigned():
    assert layer_of('rope_sim_ros.offline.run.BagSink') == OFFLINE
    assert layer_of('rope_sim_ros.model.frames') == 'model'
    assert layer_of('rope_sim_ros.frames') == 'unassigned'
    assert layer_of('rope_sim_ros.ros.conversions.pose_point') == 'ros'
    assert layer_of('rope_sim_ros') == ROOT
    assert layer_of('numpy') is None
    files = sources()
    assert len(files) > 20, 'too few sources found under {}'.format(PACKAGE_DIR)
    layers = {path: module_layer(path) for path in files}
    unassigned = [str(p.relative_to(REPO_ROOT)) for p, layer in layers.items()
                  if layer not in ALLOWED]
    assert not unassigned, 'give these a layer in test_layers.py: ' + ', '.join(unassigned)
    assert set(layers.values()) == set(ALLOWED)


@pytest.mark.parametrize('layer', sorted(ALLOWED))
def test_layer_imports_downward_only(layer):
    files = [path for path in sources() if module_layer(path) == layer]
    assert files, f'no modules in layer {layer}: nothing checked'
    problems = []
    for path in files:
        found = forbidden_imports(path.read_text(encoding='utf-8'), layer, _package_of(path),
                                  str(path))
        problems.extend('{}: {}'.format(path.relative_to(REPO_ROOT), p) for p in found)
    allowed = sorted(ALLOWED[layer])
    assert not problems, (
        f'the {layer} layer may import {", ".join(allowed) or "nothing"} of ours'
        + (' and no ROS' if layer in ROS_FREE else '') + ':\n' + '\n'.join(problems))


def run_fresh(script, cwd=REPO_ROOT):
    """Run a script in a fresh interpreter; return the JSON list of its last stdout line."""
    env = dict(os.environ)
    env['PYTHONPATH'] = str(REPO_ROOT)
    env['PYTHONDONTWRITEBYTECODE'] = '1'
    result = subprocess.run(
        [sys.executable, '-c', textwrap.dedent(script)], cwd=str(cwd), env=env,
        stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-4000:]
    return json.loads(result.stdout.strip().splitlines()[-1])


def loaded_problems(modules, layer):
    """Return the loaded modules a ROS-free layer must not have pulled in."""
    bad = [m for m in modules if is_ros_module(m)]
    bad += [m for m in modules
            if layer_of(m) not in (None, ROOT) and layer_of(m) not in ALLOWED[layer]]
    return sorted(bad)


@pytest.mark.parametrize('layer', ['bag', 'model', 'stepping', 'params', 'mooring', 'messages',
                                   OFFLINE])
def test_importing_a_layer_loads_nothing_above_it(layer):
    names = sorted(module_name(p) for p in sources()
                   if module_layer(p) == layer and p.name != '__main__.py')
    modules = run_fresh(f"""
        import importlib, json, sys
        for name in {names!r}:
            importlib.import_module(name)
        print(json.dumps(sorted(sys.modules)))
        """)
    assert set(names) <= set(modules)
    assert 'rclpy' not in modules
    assert loaded_problems(modules, layer) == [], \
        f'importing the {layer} layer ({len(names)} modules) loaded modules above it or ROS'


def test_offline_commands_run_without_ros(tmp_path):
    """Run `python -m rope_sim_ros` run, info, plot and recover: no ROS module is loaded."""
    motion = tmp_path / 'motion.csv'
    motion.write_text('t,fairlead_x,fairlead_y,fairlead_z\n0,36,0,8\n0.2,36.1,0,8\n')
    modules = run_fresh(f"""
        import json, runpy, sys

        def rope_sim(*args):
            sys.argv = ['rope_sim', *args]
            try:
                runpy.run_module('rope_sim_ros', run_name='__main__', alter_sys=True)
            except SystemExit as exit:
                assert exit.code == 0, (args, exit.code)

        rope_sim('run', '--motion', {str(motion)!r}, '--bag', 'run', '--quiet',
                 '--rate', '20', '--set', 'segments=6')
        rope_sim('info', 'run')
        rope_sim('plot', 'run', '-o', 'run.png', '--shapes', '2')
        rope_sim('recover', 'run', '--out', 'copy')
        print(json.dumps(sorted(sys.modules)))
        """, cwd=tmp_path)
    assert (tmp_path / 'run.png').stat().st_size > 0
    assert (tmp_path / 'copy' / 'metadata.yaml').exists()
    for name in ('rope_sim_ros.offline.cli', 'rope_sim_ros.offline.plot',
                 'rope_sim_ros.bag.writer', 'rope_sim_ros.bag.recover'):
        assert name in modules
    assert loaded_problems(modules, OFFLINE) == [
        'rope_sim_ros.ros', 'rope_sim_ros.ros.executables']  # the launcher, stdlib only


# rclpy's private attributes a node could reach for, each with its public way
PRIVATE_RCLPY = {
    '_parameter_overrides': 'automatically_declare_parameters_from_overrides and '
                            'get_parameters_by_prefix',
    '_parameters': 'set_parameters, declare_parameter',
    '_descriptors': 'describe_parameter',
}


def test_the_nodes_use_rclpys_public_api_only():
    # (issue: the node read _parameter_overrides twice and wrote _parameters once)
    found = []
    for path in sorted((PACKAGE_DIR / 'ros').glob('*.py')):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Attribute) and node.attr in PRIVATE_RCLPY:
                found.append(f'{path.name}:{node.lineno}: {node.attr} (public: '
                             f'{PRIVATE_RCLPY[node.attr]})')
            if isinstance(node, ast.Call) and getattr(node.func, 'id', '') == 'getattr' and \
                    len(node.args) > 1 and getattr(node.args[1], 'value', '') in PRIVATE_RCLPY:
                found.append(f'{path.name}:{node.lineno}: getattr {node.args[1].value}')
    assert found == []
