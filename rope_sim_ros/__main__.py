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


"""``python -m rope_sim_ros``: the rope_sim command line, quiet on Ctrl-C as rope_sim is."""

import sys

from .ros.executables import rope_sim

if __name__ == '__main__':  # python -m rope_sim_ros; an import runs nothing
    sys.exit(rope_sim())
