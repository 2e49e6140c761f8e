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
Two checkouts of rope_sim_ros in one process, to time this tree against another by turns.

Each package is importable under a name of its own (before_tree, this_tree) and keeps a numba
cache of its own: a kernel cached for one name cannot be loaded under another.
"""

import os
from pathlib import Path
import sys

HERE = Path(__file__).resolve().parents[1]


def import_both(parser, before: Path, cache: Path) -> None:
    """
    Make `before`'s package importable as before_tree and this tree's as this_tree.

    Call before numba is imported (its cache folder is set here).

    :param parser: the benchmark's ArgumentParser, to refuse a --before without a package.
    """
    if not (before / 'rope_sim_ros').is_dir():
        parser.error(f'--before {before}: no rope_sim_ros/ there')
    names = cache / 'packages'
    names.mkdir(parents=True, exist_ok=True)
    for name, tree in (('before_tree', before.resolve()), ('this_tree', HERE)):
        link = names / name
        if link.is_symlink() or link.exists():
            link.unlink()
        link.symlink_to(tree / 'rope_sim_ros')
    os.environ['NUMBA_CACHE_DIR'] = str(cache / 'numba')
    sys.path.insert(0, str(names))
