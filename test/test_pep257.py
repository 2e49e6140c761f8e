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
PEP 257 docstring check with ament's convention, as ``ros2 pkg create`` sets it.

pydocstyle skips folders whose name starts with '.' or '_'; colcon's build/, install/ and
log/ (and the out/ scratch folder) are excluded explicitly.
"""

import os

import pytest

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXCLUDES = [os.path.join(REPO_ROOT, d) for d in ('build', 'install', 'log', 'out')]


@pytest.mark.linter
@pytest.mark.pep257
def test_pep257(monkeypatch):
    # Imported here, not at module level as the template does: ament_pep257 needs pydocstyle,
    # which its PyPI wheel does not declare, and a collection error would stop the whole run.
    from ament_pep257.main import main
    monkeypatch.chdir(REPO_ROOT)
    rc = main(argv=['.', 'test', '--exclude'] + EXCLUDES)
    assert rc == 0, 'Found code style errors / warnings'
