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
flake8 with ament's configuration, as ``ros2 pkg create --build-type ament_python`` sets it.

ament_flake8 checks every .py file under the current directory (run from the repository root)
and skips folders whose name starts with '.' or '_' (.venv, .git, __pycache__) or that contain
an AMENT_IGNORE file. colcon's build/, install/ and log/ hold COLCON_IGNORE instead, which
ament_flake8 does not honour, so they (and the out/ scratch folder) are excluded explicitly.
"""

import os

from ament_flake8.main import main_with_errors
import pytest

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXCLUDES = [os.path.join(REPO_ROOT, d) for d in ('build', 'install', 'log', 'out')]


@pytest.mark.flake8
@pytest.mark.linter
def test_flake8(monkeypatch):
    monkeypatch.chdir(REPO_ROOT)
    rc, errors = main_with_errors(argv=['--exclude'] + EXCLUDES)
    assert rc == 0, \
        'Found %d code style errors / warnings:\n' % len(errors) + \
        '\n'.join(errors)
