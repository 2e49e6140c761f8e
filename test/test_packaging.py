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
colcon builds the package into the layout ``ros2 run`` and ``ros2 launch`` expect.

The build itself is the session fixture ``colcon_build`` (test/conftest.py): a fresh
``colcon build`` of this checkout into a temporary workspace.
"""

import ast
import os
from pathlib import Path
import sys
import xml.etree.ElementTree as ET

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
PACKAGE = 'rope_sim_ros'
EXECUTABLES = ('mooring_line', 'ship_motion', 'rope_sim', 'line_monitor', 'bag_replay')
SHARE_FILES = (
    'package.xml',
    'config/mooring_line.yaml',
    'config/materials.yaml',
    'launch/mooring_line.launch.py',
)


def test_colcon_build_duration(colcon_build):
    # Recorded so slow builds show up in the log (-rA or -s); the build ran in the fixture.
    print('colcon build took {:.1f} s'.format(colcon_build['seconds']))
    assert (colcon_build['base'] / 'install' / 'COLCON_IGNORE').exists()


@pytest.mark.parametrize('name', EXECUTABLES)
def test_executable_installed_for_ros2_run(colcon_install, name):
    path = colcon_install / 'lib' / PACKAGE / name
    assert path.is_file(), '{} missing (ros2 run {} {} would fail); lib/{} holds: {}'.format(
        path, PACKAGE, name, PACKAGE, _listing(path.parent))
    assert os.access(str(path), os.X_OK), '{} is not executable'.format(path)
    first_line = path.read_text(errors='replace').splitlines()[0]
    assert first_line.startswith('#!'), '{} has no shebang: {!r}'.format(path, first_line)
    interpreter = first_line[2:].strip().split()[0]
    assert os.access(interpreter, os.X_OK), \
        '{} runs {}, which is not an executable interpreter'.format(path, interpreter)


@pytest.mark.parametrize('relative', SHARE_FILES)
def test_share_file_installed(colcon_install, relative):
    path = colcon_install / 'share' / PACKAGE / relative
    source = REPO_ROOT / relative
    assert path.is_file(), '{} not installed{}; share/{}/{} holds: {}'.format(
        path, '' if source.exists() else ' (and {} does not exist in the source tree)'.format(
            source),
        PACKAGE, Path(relative).parent, _listing(path.parent))
    if source.is_file():
        assert path.read_bytes() == source.read_bytes(), \
            '{} differs from {}'.format(path, source)


def test_ament_index_marker(colcon_install):
    marker = colcon_install / 'share' / 'ament_index' / 'resource_index' / 'packages' / PACKAGE
    assert marker.is_file(), \
        '{} missing: get_package_share_directory({!r}) would fail'.format(marker, PACKAGE)


def test_python_package_installed(colcon_install):
    site_packages = colcon_install / 'lib' / 'python{}.{}'.format(
        *sys.version_info[:2]) / 'site-packages'
    for module in ('__init__.py', 'physics/__init__.py'):
        path = site_packages / PACKAGE / module
        assert path.is_file(), '{} missing; installed: {}'.format(
            path, _listing(site_packages))
    assert not (site_packages / 'test').exists(), 'test/ was installed as a package'
    assert not (site_packages / 'benchmarks').exists(), 'benchmarks/ was installed as a package'


def test_package_xml():
    root = ET.parse(str(REPO_ROOT / 'package.xml')).getroot()
    assert root.tag == 'package' and root.get('format') == '3'
    assert root.findtext('name') == PACKAGE
    assert root.findtext('export/build_type') == 'ament_python'
    assert [e.text for e in root.findall('license')] == ['Apache-2.0']
    assert root.findtext('version') == _setup_py_version(), \
        'package.xml and setup.py disagree on the version'


def test_package_xml_is_valid_for_catkin_pkg():
    # colcon-ros reads package.xml with catkin_pkg; validate() is what rosdep/bloom apply.
    from catkin_pkg.package import parse_package
    package = parse_package(str(REPO_ROOT / 'package.xml'))
    package.validate()
    assert package.get_build_type() == 'ament_python'


def _setup_py_version():
    tree = ast.parse((REPO_ROOT / 'setup.py').read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.keyword) and node.arg == 'version' and \
                isinstance(node.value, ast.Constant):
            return node.value.value
    return None


def _listing(directory):
    if not directory.is_dir():
        return '(no directory {})'.format(directory)
    names = sorted(p.name for p in directory.iterdir())
    return ', '.join(names) if names else '(empty)'
