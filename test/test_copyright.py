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
Every Python file starts with the project's Apache-2.0 header (ament_copyright's job).

ament_copyright is not on PyPI, so this checks the header directly: an optional shebang /
coding line, then ``# Copyright <year>[-<year>] rope_sim_ros contributors`` and the Apache
License 2.0 notice, line for line. It walks the whole repository (package, test/,
benchmarks/, launch/, setup.py) except folders starting with '.' or '_' (.venv, .git,
__pycache__), colcon's build/, install/, log/, the out/ scratch folder, and folders marked
AMENT_IGNORE or COLCON_IGNORE. Empty files (an empty ``__init__.py``) are skipped, as
ament_copyright does.
"""

import os
import re

import pytest

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXCLUDED_TOP_DIRS = {'build', 'install', 'log', 'out'}
IGNORE_MARKERS = {'AMENT_IGNORE', 'COLCON_IGNORE'}

COPYRIGHT_RE = re.compile(r'^# Copyright (\d{4})(-\d{4})? rope_sim_ros contributors$')
LICENSE_LINES = [
    '#',
    '# Licensed under the Apache License, Version 2.0 (the "License");',
    '# you may not use this file except in compliance with the License.',
    '# You may obtain a copy of the License at',
    '#',
    '#     http://www.apache.org/licenses/LICENSE-2.0',
    '#',
    '# Unless required by applicable law or agreed to in writing, software',
    '# distributed under the License is distributed on an "AS IS" BASIS,',
    '# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.',
    '# See the License for the specific language governing permissions and',
    '# limitations under the License.',
]


def python_files(root):
    """Yield the repository's .py files (paths relative to root), sorted."""
    found = []
    for dirpath, dirnames, filenames in os.walk(root):
        if IGNORE_MARKERS.intersection(filenames) and dirpath != root:
            dirnames[:] = []
            continue
        dirnames[:] = sorted(
            d for d in dirnames
            if d[0] not in '._' and not (dirpath == root and d in EXCLUDED_TOP_DIRS))
        found.extend(
            os.path.relpath(os.path.join(dirpath, f), root)
            for f in filenames if f.endswith('.py'))
    return sorted(found)


def header_problem(text):
    """Return why text does not start with the project header, or None if it does."""
    lines = text.splitlines()
    if not text.strip():
        return None
    start = 0
    while start < len(lines) and start < 2 and (
            lines[start].startswith('#!') or re.match(r'^#.*coding[:=]', lines[start])):
        start += 1
    if start >= len(lines) or not COPYRIGHT_RE.match(lines[start]):
        first = lines[start] if start < len(lines) else ''
        return 'line {}: expected "# Copyright <year> rope_sim_ros contributors", got {!r}'.format(
            start + 1, first[:80])
    for offset, expected in enumerate(LICENSE_LINES, start=start + 1):
        actual = lines[offset] if offset < len(lines) else '<end of file>'
        if actual.rstrip() != expected:
            return 'line {}: expected {!r}, got {!r}'.format(offset + 1, expected, actual[:80])
    return None


def test_header_check_catches_bad_files():
    good = '# Copyright 2026 rope_sim_ros contributors\n' + '\n'.join(LICENSE_LINES) + '\n'
    assert header_problem(good + '"""Doc."""\n') is None
    assert header_problem('#!/usr/bin/env python3\n' + good) is None
    assert header_problem('') is None
    assert header_problem('"""No header."""\n') is not None
    assert header_problem(good.replace('rope_sim_ros contributors', 'Someone Else')) is not None
    assert header_problem(good.replace('Version 2.0', 'Version 3.0')) is not None
    assert header_problem(good.replace('2026', 'twenty')) is not None
    assert header_problem('\n'.join(good.splitlines()[:5])) is not None


@pytest.mark.copyright
@pytest.mark.linter
def test_copyright():
    files = python_files(REPO_ROOT)
    assert 'setup.py' in files, 'the walk found no setup.py under {}'.format(REPO_ROOT)
    problems = []
    for name in files:
        with open(os.path.join(REPO_ROOT, name), encoding='utf-8', errors='replace') as f:
            problem = header_problem(f.read())
        if problem:
            problems.append('{}: {}'.format(name, problem))
    assert not problems, \
        '{} of {} Python files lack the Apache-2.0 header:\n'.format(
            len(problems), len(files)) + '\n'.join(problems)
