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
import importlib.util
import json
import os
from pathlib import Path
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest
from rope_sim_ros.mooring import precompile

REPO_ROOT = Path(__file__).resolve().parent.parent
PACKAGE = 'rope_sim_ros'
EXECUTABLES = ('mooring_line', 'mooring', 'ship_motion', 'line_monitor', 'bag_replay',
               'rope_sim')
SHARE_FILES = (
    'package.xml',
    'config/mooring_line.yaml',
    'config/berth.yaml',
    'config/berth_motion.yaml',
    'config/mooring.foxglove.json',
    'config/mooring.rviz',
    'config/materials.yaml',
    'launch/mooring_line.launch.py',
    'launch/mooring.launch.py',
)


# Kernels the node and the runner cannot do without: the two steps, the state check (it
# also gives the tensions) and the end trajectories. Any other kernel they call must not
# compile either.
ENTRY_KERNELS = tuple('rope_sim_ros.' + name for name in (
    'stepping.kernels.implicit_euler_run', 'stepping.kernels.improved_euler_run',
    'model.forces.assembly.largest_load', 'mooring.trajectory._sample',
    'stepping.adaptive._clear_watch', 'stepping.adaptive._read_watch',
    'stepping.rules.step_divisions', 'stepping.rules.fine_steps'))

# Runs the runner (every integrator) and the node's warm-up from the installed package, then
# prints numba's statistics of every dispatcher: what came from the cache, what compiled.
KERNEL_PROBE = r"""
import json, sys
from numba.core.dispatcher import Dispatcher
import rope_sim_ros
from rope_sim_ros.offline import cli
from rope_sim_ros.params.table import LineParams
from rope_sim_ros.params.arrangement import single_line
from rope_sim_ros.ros.node import warm_up
motion, out = sys.argv[1:]
codes = [cli.main(['run', '--motion', motion, '--out', out, '--quiet', '--set', 'segments=50',
                   '--set', 'material=steel_wire', '--set', 'integrator=' + name])
         for name in ('adaptive', 'implicit_euler', 'improved_euler')]
said = []
warm_up(single_line(LineParams()), said.append)
stats = {}
for name, module in list(sys.modules.items()):
    for attribute, value in vars(module or object).items():
        if name.startswith('rope_sim_ros') and isinstance(value, Dispatcher) \
                and value.py_func.__module__ == name:
            stats[name + '.' + attribute] = {
                'loaded': sum(value.stats.cache_hits.values()),
                'compiled': sum(value.stats.cache_misses.values())}
print(json.dumps({'file': rope_sim_ros.__file__, 'codes': codes, 'said': said,
                  'stats': stats}))
"""


# A process that multiprocessing spawns (Dask's nanny starts a study's workers so) runs its
# parent's main file again, as __mp_main__, before what it was given. The parent here is a
# launcher that has started: python -S, then site; its main file the launcher.
SPAWN_PROBE = r"""
import site, sys
site.main()
import multiprocessing
sys.modules['__main__'].__file__ = sys.argv[1]
child = multiprocessing.get_context('spawn').Process(target=print, args=('spawned',))
child.start()
child.join(30)
if child.exitcode is None:
    child.kill()  # it ran the executable, which runs on
    child.join()
print('exit', child.exitcode)
"""


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
    # '#!<python> -S' or, where env can hold SIGINT back, '#!/usr/bin/env -S ... <python> -S'
    programs = [word for word in first_line[2:].split() if word.startswith('/')]
    assert programs and programs[-1].startswith(sys.prefix), first_line
    for interpreter in programs:
        assert os.access(interpreter, os.X_OK), \
            '{} runs {}, which is not an executable interpreter'.format(path, interpreter)
    assert first_line.endswith(' -S'), first_line  # site runs under the launcher's handler
    assert path.read_text().split('\n', 1)[1] == \
        (REPO_ROOT / 'bin' / name).read_text().split('\n', 1)[1]


def test_one_launcher_runs_every_executable():
    # bin/launcher is the one launcher; every executable is a link to it by its own name,
    # which says what it runs (setup.py installs a copy under each name)
    folder = REPO_ROOT / 'bin'
    names = sorted(p.name for p in folder.iterdir() if p.name != 'launcher')
    assert names == sorted(EXECUTABLES)
    assert _setup_py_constant('EXECUTABLES') == EXECUTABLES
    for name in names:
        assert (folder / name).is_symlink() and os.readlink(folder / name) == 'launcher', name
    text = (folder / 'launcher').read_text()
    assert text.startswith('#!python -S\n')
    assert text.endswith('    from rope_sim_ros.ros.executables import run_named  # noqa: '
                         'I100\n\n    sys.exit(run_named(__file__))\n')
    # imported, not run (a process multiprocessing spawns imports it as __mp_main__), it
    # only defines: its statements run under `if __name__ == '__main__':`
    body = ast.parse(text).body
    assert [type(s) for s in body] == [ast.Expr] + [ast.Import] * 3 + [ast.FunctionDef, ast.If]
    assert ast.unparse(body[-1].test) == "__name__ == '__main__'"
    from rope_sim_ros.ros import executables
    assert sorted(executables.ENTRY_POINTS) == sorted(EXECUTABLES)
    assert executables.run_named('/somewhere/not_ours') == 2  # refused, named


@pytest.mark.parametrize('name', EXECUTABLES)
def test_a_process_spawned_from_an_executable_runs_only_what_it_is_given(
        colcon_install, colcon_env, tmp_path, name):
    # the executable does not run again in the child: it prints what it was given, exits 0
    launcher = colcon_install / 'lib' / PACKAGE / name
    result = subprocess.run([sys.executable, '-S', '-c', SPAWN_PROBE, str(launcher)],
                            env=colcon_env, cwd=str(tmp_path), stdin=subprocess.DEVNULL,
                            capture_output=True, text=True, timeout=120)
    assert (result.returncode, result.stdout, result.stderr) == (0, 'spawned\nexit 0\n', ''), \
        result.stdout + result.stderr[-3000:]


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
    for module in ('__init__.py', 'model/__init__.py', 'stepping/__init__.py'):
        path = site_packages / PACKAGE / module
        assert path.is_file(), '{} missing; installed: {}'.format(
            path, _listing(site_packages))
    assert not (site_packages / 'test').exists(), 'test/ was installed as a package'
    assert not (site_packages / 'benchmarks').exists(), 'benchmarks/ was installed as a package'


def test_installed_kernels_load_from_the_install_tree(colcon_env, colcon_install, tmp_path):
    # The first start after the build, with HOME on an empty folder: every kernel the runner
    # and the node use loads from the cache the build left next to the installed sources.
    motion = tmp_path / 'motion.csv'
    lines = (REPO_ROOT / 'examples' / 'surge.csv').read_text().splitlines()
    motion.write_text('\n'.join(lines[:11]) + '\n')  # 1 s
    home = tmp_path / 'home'
    home.mkdir()
    env = dict(colcon_env, HOME=str(home))
    for name in ('NUMBA_CACHE_DIR', 'XDG_CACHE_HOME'):
        env.pop(name, None)
    result = subprocess.run(
        [sys.executable, '-c', KERNEL_PROBE, str(motion), str(tmp_path / 'out.csv')],
        cwd=str(tmp_path), env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
        timeout=600)
    assert result.returncode == 0, result.stderr[-3000:]
    report = json.loads(result.stdout.splitlines()[-1])
    assert Path(report['file']).is_relative_to(colcon_install), report['file']
    assert report['codes'] == [0, 0, 0]
    stats = report['stats']
    compiled = {name: s['compiled'] for name, s in stats.items() if s['compiled']}
    assert compiled == {}, 'compiled at the first start after the build: {}'.format(
        ', '.join(sorted(compiled)))
    # each loaded (trajectory._sample twice: one end's points, and a ship's fairleads)
    loaded = {name: stats.get(name, {}).get('loaded', 0) for name in ENTRY_KERNELS}
    assert loaded == {name: 2 if name.endswith('._sample') else 1 for name in ENTRY_KERNELS}
    assert report['said'] == [], 'the node said it was compiling: {}'.format(report['said'])
    assert list(home.iterdir()) == [], 'numba wrote to HOME: {}'.format(_listing(home))


def test_install_tree_holds_the_kernel_cache(colcon_install):
    package = colcon_install / 'lib' / 'python{}.{}'.format(
        *sys.version_info[:2]) / 'site-packages' / PACKAGE
    for name in ENTRY_KERNELS:
        module, function = name[len(PACKAGE) + 1:].rsplit('.', 1)
        directory = (package / module.replace('.', '/')).parent / '__pycache__'
        pattern = '{}.{}-*.nbi'.format(module.rsplit('.', 1)[-1], function)
        assert list(directory.glob(pattern)), '{} missing in {}: {}'.format(
            pattern, directory, _listing(directory))
    fingerprint = package / '__pycache__' / precompile.FINGERPRINT_NAME
    assert fingerprint.is_file(), 'the build compiled no kernels: no {}'.format(fingerprint)
    recorded = fingerprint.read_text().strip()
    assert recorded == precompile.sources_fingerprint(package)


def _site_packages(prefix):
    return prefix / 'lib' / 'python{}.{}'.format(*sys.version_info[:2]) / 'site-packages'


def test_installed_sources_are_byte_compiled_with_their_sources_times(colcon_install):
    # PYTHONDONTWRITEBYTECODE is set for the build (test/conftest.py, the Makefile): the
    # install byte-compiles even so, and keeps each source's time to the nanosecond (numba
    # before 0.68 keys its cache by it: the source tree's cache then serves the install)
    package = _site_packages(colcon_install) / PACKAGE
    sources = sorted(package.rglob('*.py'))
    assert len(sources) > 50, _listing(package)
    for path in sources:
        source = REPO_ROOT / PACKAGE / path.relative_to(package)
        assert path.stat().st_mtime_ns == source.stat().st_mtime_ns, path
        cached = Path(importlib.util.cache_from_source(str(path)))
        assert cached.is_file(), '{} not byte-compiled: {} missing'.format(path, cached)
        header = cached.read_bytes()[:16]  # magic, flags, the source's time and size
        assert header[:4] == importlib.util.MAGIC_NUMBER, cached
        assert (int.from_bytes(header[4:8], 'little'), int.from_bytes(header[8:12], 'little'),
                int.from_bytes(header[12:16], 'little')) == \
            (0, int(path.stat().st_mtime) & 0xFFFFFFFF, path.stat().st_size), cached


@pytest.mark.parametrize('name, args', [
    ('mooring_line', ['--help']),
    ('rope_sim', ['run', '--motion', '{motion}', '--out', '{out}', '--quiet']),
])
def test_a_first_start_compiles_nothing_into_the_install(
        colcon_install, colcon_env, tmp_path, name, args):
    # As a user's shell starts it: bytecode may be written, HOME has never run it. The node's
    # --help imports all the node is made of; the run also loads its kernels and runs them.
    motion = tmp_path / 'motion.csv'
    motion.write_text('\n'.join(
        (REPO_ROOT / 'examples' / 'surge.csv').read_text().splitlines()[:11]) + '\n')
    home = tmp_path / 'home'
    home.mkdir()
    env = dict(colcon_env, HOME=str(home))
    for variable in ('PYTHONDONTWRITEBYTECODE', 'NUMBA_CACHE_DIR', 'XDG_CACHE_HOME'):
        env.pop(variable, None)

    def files():
        return {str(p.relative_to(colcon_install)): p.stat().st_mtime_ns
                for p in colcon_install.rglob('*') if p.is_file()}

    before = files()
    command = [str(colcon_install / 'lib' / PACKAGE / name)] + [
        a.format(motion=motion, out=tmp_path / 'out.csv') for a in args]
    result = subprocess.run(command, env=env, cwd=str(tmp_path), stdin=subprocess.DEVNULL,
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr[-3000:]
    after = files()
    assert after == before, 'the first start wrote into the install: {}'.format(
        sorted(set(after.items()) - set(before.items()))[:20])


KERNEL = """
import numba


@numba.njit(cache=True)
def twice(x):
    return 2.0 * x
"""

# Loads the kernel of the package beside it, says whether numba compiled it or loaded it.
LOAD_KERNEL = """
from pkg.kernel import twice
assert twice(2.0) == 4.0
print(sum(twice.stats.cache_hits.values()), sum(twice.stats.cache_misses.values()))
"""


def test_a_cache_seeded_from_a_tree_of_the_same_sources_is_loaded(tmp_path):
    # What lets `make test` and the colcon build of the tests use the kernels compiled in
    # another tree instead of compiling them again (2-5 minutes each): precompile's seed_cache
    # copies them, and numba takes them for the same sources (with their times, as setup.py
    # installs them: numba before 0.68 compares the times too)
    def load(tree):
        result = subprocess.run([sys.executable, '-c', LOAD_KERNEL], cwd=str(tree),
                                env=dict(os.environ, PYTHONPATH=str(tree)),
                                capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, result.stderr[-3000:]
        return tuple(int(word) for word in result.stdout.split())  # (loaded, compiled)

    source, package = tmp_path / 'a' / 'pkg', tmp_path / 'b' / 'pkg'
    for folder in (source, package):
        folder.mkdir(parents=True)
    (source / '__init__.py').write_text('')
    (source / 'kernel.py').write_text(KERNEL)
    assert load(source.parent) == (0, 1)
    fingerprint = precompile.sources_fingerprint(source)
    precompile.record_fingerprint(source, fingerprint)
    for module in ('__init__.py', 'kernel.py'):
        (package / module).write_bytes((source / module).read_bytes())
        times = (source / module).stat()
        os.utime(package / module, ns=(times.st_atime_ns, times.st_mtime_ns))
    assert precompile.seed_cache(source, package, 'another fingerprint') == 0
    assert precompile.seed_cache(source, package, fingerprint) == 2  # the index and its data
    assert precompile.seed_cache(source, package, fingerprint) == 0  # it has its own now
    assert load(package.parent) == (1, 0)


def test_stale_kernel_cache_is_removed_when_a_compiled_source_changes(tmp_path):
    package = tmp_path / 'pkg'
    cache = package / 'stepping' / '__pycache__'
    cache.mkdir(parents=True)
    (package / 'stepping' / 'kernels.py').write_text('import numba\n')
    (package / 'trajectory.py').write_text('import numba\n')
    (package / 'cli.py').write_text('import sys\n')
    files = [cache / 'kernels.run-10.py311.nbi', cache / 'kernels.run-10.py311.1.nbc']
    for path in files + [cache / 'kernels.cpython-311.pyc']:
        path.write_bytes(b'x')
    fingerprint = precompile.sources_fingerprint(package)
    precompile.record_fingerprint(package, fingerprint)
    assert precompile.refresh_in_tree_cache(package, fingerprint) == 0
    (package / 'cli.py').write_text('import os\n')  # compiled code cannot come from here
    assert precompile.sources_fingerprint(package) == fingerprint
    (package / 'trajectory.py').write_text('import numba  # changed\n')
    changed = precompile.sources_fingerprint(package)
    assert changed != fingerprint
    assert precompile.refresh_in_tree_cache(package, changed) == 2
    assert sorted(p.name for p in cache.iterdir()) == ['kernels.cpython-311.pyc']


def test_compile_notice_only_when_numba_compiles():
    import numba

    @numba.njit
    def twice(x):
        return 2 * x

    said = []
    with precompile.announce_compilation(said.append):
        assert twice(3) == 6
        assert twice(4) == 8
    assert len(said) == 2, said
    assert said[0] == precompile.START_MESSAGE
    assert said[1].startswith('physics kernels ready, compiled in ')
    said.clear()
    with precompile.announce_compilation(said.append):
        assert twice(5) == 10  # compiled already
    assert said == []


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


def _setup_py_constant(name):
    tree = ast.parse((REPO_ROOT / 'setup.py').read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and [t.id for t in node.targets] == [name]:
            return ast.literal_eval(node.value)
    return None


def _listing(directory):
    if not directory.is_dir():
        return '(no directory {})'.format(directory)
    names = sorted(p.name for p in directory.iterdir())
    return ', '.join(names) if names else '(empty)'
