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
Compile the numba kernels once, ahead of the first start, into numba's cache.

numba compiles a kernel on its first call and, with ``cache=True``, keeps the machine code in
``__pycache__`` next to the source file, keyed by that file (its content; its time and size
before numba 0.68) and the CPU. The default settings (config/mooring_line.yaml,
config/berth.yaml, the berth demo) run the adaptive integrator, which steps with both
integrators' kernels: its one line compiles 98 % of what all of CONFIGURATIONS do (128 of
131 s, two cores at load 2; about 2 minutes on a quiet machine, 5 at load 8). setup.py runs
this module right after installing (``colcon build``, with or without
``--symlink-install``), so the cache lands beside the installed sources and every start,
whatever HOME is, only loads it (0.5 s).
``--seed-from`` first copies the cache of another tree of the same sources (the source
tree's into the install, the install's into the source tree for ``make test``), which numba
then loads instead of compiling it again.

numba uses that cache only where it may also write: in a read-only install tree (another
user's) it caches in ``~/.cache/numba`` instead and compiles at the first start; a wheel
(``pip install .``) holds no compiled code, built for one CPU. Then run, as that user::

    python3 -m rope_sim_ros.mooring.precompile
"""

import argparse
from contextlib import contextmanager
import hashlib
import math
from pathlib import Path
import re
import shutil
import sys
import time
from typing import Callable, Dict, Iterator, List, Optional

PACKAGE_DIR = Path(__file__).resolve().parents[1]
PACKAGE = __package__.split('.')[0]  # rope_sim_ros
# Beside the cache: which sources it was compiled from (see refresh_in_tree_cache).
FINGERPRINT_NAME = 'numba-kernels.sha256'
CACHE_SUFFIXES = ('.nbi', '.nbc')  # numba's index and data files
COMPILED_ROOMS = frozenset({'model', 'stepping'})
# a module of kernels imports numba at its top (this one imports it in a function only: an
# edit of it threw every cache away)
USES_NUMBA = re.compile(rb'^(?:import|from)\s+numba\b', re.MULTILINE)

# Every kernel specialisation comes from one run of each integrator: all the other parameters
# (material, bending, interpolation, superelastic_adjustment, payload_mass) change values, not
# types (a System packs any lines and points into the same tables). The payload runs only
# make sure that stays so. The first (the default settings' line) compiles 128 of the 131 s
# all take, the others 0.3 s and exercise_mooring 2 s more: all are compiled at the build,
# so that no first use compiles anything.
CONFIGURATIONS = (
    {'integrator': 'adaptive', 'end_interpolation': 'cubic'},
    {'integrator': 'adaptive', 'payload_mass': 1000.0},
    {'integrator': 'implicit_euler', 'end_interpolation': 'cubic'},
    {'integrator': 'improved_euler', 'end_interpolation': 'linear'},
    {'integrator': 'implicit_euler', 'payload_mass': 1000.0},
    {'integrator': 'improved_euler', 'payload_mass': 1000.0},
    # a line with a strain-tension curve: the kernels take it in the same tables; this
    # compiles the curve's own evaluation (TensionCurve.tension) the start of one calls
    {'integrator': 'implicit_euler', 'material': 'nylon', 'load_extension': 'curve'},
    # a line crossing the water's surface: its start's statics call forces/fluid.py
    # wetted_fraction from Python (statics/catenary.py node_weights), a specialisation of its
    # own that no kernel compiles (they inline it); without it a study of a berth in water
    # compiled it in its first case, after the warm-up (test_study checks none does)
    {'integrator': 'adaptive', 'water_level': -1.0},
)

START_MESSAGE = ('preparing the physics kernels: numba is compiling them (its cache holds none '
                 'for this install yet), one to three minutes on two cores; later starts '
                 'load them from the cache (python3 -m rope_sim_ros.mooring.precompile prepares '
                 'them ahead)')


class _CompileNotice:
    """Listens to numba's compile events: says START_MESSAGE at the first one."""

    def __init__(self, say: Optional[Callable[[str], None]]):
        self.say = say
        self.started = math.nan  # time.monotonic() of the first compilation, if any

    def on_start(self, event) -> None:
        if math.isnan(self.started):
            self.started = time.monotonic()
            if self.say is not None:
                self.say(START_MESSAGE)

    def on_end(self, event) -> None:
        pass


@contextmanager
def announce_compilation(say: Optional[Callable[[str], None]]) -> Iterator[_CompileNotice]:
    """
    Within the block, say once that the kernels are being compiled, if numba compiles any.

    Loading kernels from numba's cache says nothing; compiling says so when it starts (it may
    take three minutes under load) and when the block ends.

    :param say: called with each message (a logger's info, a print to stderr), or None.
    :returns: (as the context) the listener; its ``started`` is NaN while nothing compiled.
    """
    from numba.core import event

    class Listener(_CompileNotice, event.Listener):
        pass

    notice = Listener(say)
    with event.install_listener('numba:compile', notice):
        yield notice
    if not math.isnan(notice.started) and say is not None:
        say(f'physics kernels ready, compiled in {time.monotonic() - notice.started:.1f} s')


def exercise(values: dict) -> None:
    """Run a short line with these parameter values through every compiled path it has."""
    import numpy as np
    from .mooring import Mooring
    from ..params.arrangement import single_line
    from ..params.table import LineParams

    line = LineParams().with_values(values)
    mooring = Mooring(single_line(line))
    fairlead = np.add(line.bollard_position, [0.9 * line.length, 0.0, 0.0])
    level = [0.0, 0.0, 0.0, 1.0]
    mooring.push_ship(0.0, fairlead, level)
    mooring.push_ship(0.1, fairlead + [0.01, 0.0, 0.0], level)
    mooring.push_bollard(0, 0.0, line.bollard_position)  # the bollard's trajectory too
    mooring.start(0.0)
    mooring.advance_to(3.0 * mooring.time_step)
    mooring.output()


def exercise_mooring() -> None:
    """Run a two-line arrangement: the kernels that drive a group of lines at once, its wrench."""
    from .mooring import Mooring
    from .records import mooring_wrench
    from ..params.arrangement import from_values

    line = {'length': 30.0, 'segments': 4, 'bollard_position': [0.0, 0.0, 0.0]}
    mooring = Mooring(from_values({
        'lines': ['a', 'b'], 'a': dict(line, fairlead_offset=[29.0, 0.0, 0.0]),
        'b': dict(line, fairlead_offset=[29.0, 1.0, 0.0])}))
    for t in (0.0, 0.1):
        mooring.push_ship(t, [0.01 * t, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0])
    mooring.start(0.0)
    mooring.advance_to(3.0 * mooring.time_step)
    out = mooring.output()
    mooring_wrench(out.fairlead_forces, mooring.offsets, [0.0, 0.0, 0.0, 1.0])


def dispatchers() -> Dict[str, object]:
    """Return the numba dispatchers of the loaded rope_sim_ros modules by qualified name."""
    from numba.core.dispatcher import Dispatcher

    found = {}
    for name, module in list(sys.modules.items()):
        if module is None or not (name == PACKAGE or name.startswith(PACKAGE + '.')):
            continue
        for attribute, value in vars(module).items():
            if isinstance(value, Dispatcher) and value.py_func.__module__ == name:
                found[f'{name}.{attribute}'] = value
    return found


def compiled_sources(package_dir: Path) -> List[Path]:
    """
    Return the files compiled code can come from: model/, stepping/, modules importing numba.

    The kernels compile in the constants of modules that import no numba themselves
    (model/layout.py's columns): every file of the two rooms the kernels are made of counts.
    """
    return [path for path in sorted(package_dir.rglob('*.py'))
            if COMPILED_ROOMS.intersection(path.relative_to(package_dir).parts[:-1])
            or USES_NUMBA.search(path.read_bytes())]


def sources_fingerprint(package_dir: Path) -> str:
    """Hash the compiled sources, with the numba and Python versions."""
    import numba

    digest = hashlib.sha256(f'{numba.__version__} {sys.version}'.encode())
    for path in compiled_sources(package_dir):
        digest.update(str(path.relative_to(package_dir)).encode() + b'\0')
        digest.update(path.read_bytes())
    return digest.hexdigest()


def refresh_in_tree_cache(package_dir: Path, fingerprint: str) -> int:
    """
    Remove numba's cache files next to the sources unless made from these very sources.

    numba checks a cached kernel against its own file only: implicit_euler_run holds a
    compiled copy of superelastic.adjust (and its constants), which would stay stale when
    only superelastic.py changed. Without a fingerprint the files' origin is unknown: they go.

    :returns: files removed (none where the tree is not writable: numba then caches in the
        user's cache directory, not ours to clear).
    """
    try:
        recorded = (package_dir / '__pycache__' / FINGERPRINT_NAME).read_text().strip()
    except OSError:
        recorded = ''
    if recorded == fingerprint:
        return 0
    removed = 0
    for path in package_dir.rglob('__pycache__/*'):
        if path.suffix in CACHE_SUFFIXES:
            try:
                path.unlink()
                removed += 1
            except OSError:
                pass
    return removed


def record_fingerprint(package_dir: Path, fingerprint: str) -> None:
    """Note which sources the cache next to them now comes from (nothing if read-only)."""
    try:
        (package_dir / '__pycache__').mkdir(exist_ok=True)
        (package_dir / '__pycache__' / FINGERPRINT_NAME).write_text(fingerprint + '\n')
    except OSError:
        pass


def installed_package(folder: Path) -> Path:
    """Return the package in folder: folder itself, or an install prefix's site-packages."""
    found = [folder] + sorted(folder.glob(f'lib/python*/site-packages/{PACKAGE}'))
    return next((path for path in found if (path / '__init__.py').is_file()), folder)


def seed_cache(source: Path, package_dir: Path, fingerprint: str) -> int:
    """
    Copy numba's cache of source, another tree of these sources, into package_dir.

    Only a cache whose recorded fingerprint is ``fingerprint`` (that of package_dir's
    sources), and only the kernels package_dir has no cache of: each with its index and its
    data files. numba takes an entry only for the source it was compiled from (numba before
    0.68: of that time and size; setup.py installs the sources with their times).

    :returns: files copied.
    """
    try:
        recorded = (source / '__pycache__' / FINGERPRINT_NAME).read_text().strip()
    except OSError:
        return 0
    if recorded != fingerprint or source.resolve() == package_dir.resolve():
        return 0
    copied = 0
    for index in source.rglob('__pycache__/*.nbi'):
        target = package_dir / index.relative_to(source)
        if target.exists():
            continue  # package_dir's own (its fingerprint is this one, or it was removed)
        base = index.name[:-len('.nbi')]
        try:
            target.parent.mkdir(exist_ok=True)
            for path in [*index.parent.glob(base + '.*.nbc'), index]:  # the index last
                shutil.copy2(path, target.parent / path.name)
                copied += 1
        except OSError:
            pass
    return copied


def main(argv: Optional[List[str]] = None) -> int:
    """Compile (or load) every kernel specialisation; print what it did and where."""
    parser = argparse.ArgumentParser(
        prog='python3 -m rope_sim_ros.mooring.precompile',
        description="Compile the numba kernels of rope_sim_ros into numba's cache, so that "
        'the first start of the node or the runner does not wait for them.')
    parser.add_argument(
        '--seed-from', type=Path, metavar='DIR',
        help='first copy the cache of the package in DIR (or in the install prefix DIR), '
        'where it was compiled from these very sources')
    args = parser.parse_args(argv)
    try:
        import numba  # noqa: F401
    except ImportError as e:
        print(f'rope_sim_ros: cannot compile the kernels: {e}', file=sys.stderr)
        return 1
    start = time.monotonic()
    fingerprint = sources_fingerprint(PACKAGE_DIR)
    removed = refresh_in_tree_cache(PACKAGE_DIR, fingerprint)
    seeded = 0
    if args.seed_from is not None:
        seeded = seed_cache(installed_package(args.seed_from), PACKAGE_DIR, fingerprint)
    for values in CONFIGURATIONS:
        exercise(values)
    exercise_mooring()
    found = dispatchers()
    compiled = sum(sum(d.stats.cache_misses.values()) for d in found.values())
    loaded = sum(sum(d.stats.cache_hits.values()) for d in found.values())
    record_fingerprint(PACKAGE_DIR, fingerprint)
    # where numba put them: next to the sources, or the user's cache if that is read-only
    places = sorted({str(getattr(getattr(d, '_cache', None), 'cache_path', '?'))
                     for d in found.values() if d.signatures})
    stale = f'; removed {removed} stale cache files first' if removed else ''
    if seeded:
        stale += f'; {seeded} cache files copied from {args.seed_from} first'
    print(f'rope_sim_ros: numba kernels: {compiled} specialisations compiled, {loaded} loaded '
          f'from the cache, in {time.monotonic() - start:.1f} s{stale}; cache: '
          + ', '.join(places))
    return 0


if __name__ == '__main__':
    sys.exit(main())
