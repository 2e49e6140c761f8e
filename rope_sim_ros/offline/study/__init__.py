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
``rope_sim study STUDY.yaml --out DIR``: many cases of a berth, on Dask (docs/study.md).

- file.py: the study file and its cases, every one checked before any runs, and their keys;
- cluster.py: the cases on a local cluster of processes or a scheduler's workers, each a run
  summarised from its outputs as they come (offline/sinks.py SummarySink), its OUT.csv or
  bag written only where the study keeps them;
- results.py: each case's record, results.csv and results.parquet;
- plots.py: utilisation.png and heatmap.png;
- run.py: run_study, which ties them together.

cluster.py imports Dask (distributed): the others do not, and run_study imports it only to
run cases.
"""

from .file import StudyError
from .run import run_study
from .run import StudyInterrupted
from .run import StudyReport
from .run import summary_lines

__all__ = [
    'run_study',
    'StudyError',
    'StudyInterrupted',
    'StudyReport',
    'summary_lines',
]
