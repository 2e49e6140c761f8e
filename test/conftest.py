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
Shared pytest setup: DDS isolation, ament index, the colcon install, reference data.

The environment is fixed at import time, before any test module imports rclpy, so every
node created in this run (in-process or as a subprocess) sees the same settings:

- ``ROS_DOMAIN_ID``: kept when set, else derived from the pid in 1..101. Domain 0 is what
  every unconfigured ROS machine uses; ids above 101 map DDS ports into Linux's ephemeral
  range (32768..60999) and can collide with unrelated sockets (ROS 2 docs, About Domain ID).
  Under ``pytest -n`` each worker takes the next ids after it, one each.
- ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``: discovery never leaves this machine.
- ``AMENT_PREFIX_PATH`` includes ``sys.prefix``, where the PyPI ROS wheels put their share/.
- The repository root is on ``sys.path`` so tests import the source tree.
- numba's cache in the source tree is dropped when a compiled source changed since it was
  made: numba checks a kernel against its own file only, and implicit_euler_run holds a
  compiled copy of superelastic.adjust, so an edit of superelastic.py alone would otherwise
  be tested with the old code.
"""

import os
from pathlib import Path
import subprocess
import sys
import time

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
PACKAGE_NAME = 'rope_sim_ros'

_TEST_START = pytest.StashKey[float]()

# Highest ROS_DOMAIN_ID whose DDS ports stay below Linux's ephemeral port range.
MAX_SAFE_DOMAIN_ID = 101


def _domain_id_for(pid):
    """Return a ROS_DOMAIN_ID in 1..MAX_SAFE_DOMAIN_ID derived from a process id."""
    return pid % MAX_SAFE_DOMAIN_ID + 1


def _configure_environment():
    if not os.environ.get('ROS_DOMAIN_ID'):
        os.environ['ROS_DOMAIN_ID'] = str(_domain_id_for(os.getpid()))
    worker = os.environ.get('PYTEST_XDIST_WORKER', '')  # 'gw0', 'gw1', ... under -n
    if worker.startswith('gw'):
        # each worker its own domain, next to the run's: their nodes never meet
        os.environ['ROS_DOMAIN_ID'] = str(
            _domain_id_for(int(os.environ['ROS_DOMAIN_ID']) + int(worker[2:])))
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'

    prefixes = [p for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    if sys.prefix not in prefixes:
        prefixes.append(sys.prefix)
    os.environ['AMENT_PREFIX_PATH'] = os.pathsep.join(prefixes)

    if str(REPO_ROOT) not in sys.path:
        sys.path.insert(0, str(REPO_ROOT))


_configure_environment()


def _refresh_kernel_cache():
    from rope_sim_ros.mooring import precompile
    fingerprint = precompile.sources_fingerprint(precompile.PACKAGE_DIR)
    precompile.refresh_in_tree_cache(precompile.PACKAGE_DIR, fingerprint)
    precompile.record_fingerprint(precompile.PACKAGE_DIR, fingerprint)


_refresh_kernel_cache()


# The fixtures of the tests that run the installed nodes as processes over DDS.
NODE_FIXTURES = {'colcon_build', 'colcon_install', 'colcon_env'}


def pytest_configure(config):
    # ament_flake8 and ament_pep257 register their own markers; ament_lint (which registers
    # 'linter') and ament_copyright are not installed here.
    config.addinivalue_line('markers', 'linter: marks tests that run a linter')
    config.addinivalue_line('markers', 'copyright: marks tests checking copyright headers')
    config.addinivalue_line(
        'markers', 'alone: runs the installed nodes on the wall clock: `make test` runs these '
        'one at a time, after the others have run side by side (pytest -n)')


def pytest_collection_modifyitems(config, items):
    """Mark `alone` every test that runs the installed nodes (NODE_FIXTURES)."""
    for item in items:
        if NODE_FIXTURES & set(getattr(item, 'fixturenames', ())):
            item.add_marker(pytest.mark.alone)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """Attach the log of every node that ran during a failed test: timing faults need it."""
    outcome = yield
    report = outcome.get_result()
    if report.when == 'setup':
        item.stash[_TEST_START] = time.monotonic()
    if not report.failed or 'node_harness' not in sys.modules:
        return
    start = item.stash.get(_TEST_START, 0.0)
    for node in sys.modules['node_harness'].STARTED:
        if node.started >= start or node.process.poll() is None:
            report.sections.append((f'node log {node.log}', _tail(node.log, 80)))


def pytest_report_header(config):
    return 'ROS_DOMAIN_ID={} ROS_AUTOMATIC_DISCOVERY_RANGE={}'.format(
        os.environ['ROS_DOMAIN_ID'], os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'])


@pytest.fixture(scope='session')
def repo_root():
    """Return the root of the source checkout."""
    return REPO_ROOT


@pytest.fixture(scope='session')
def reference_dir():
    """
    Return test/data: the MoorDyn, MoorPy and analytic catenary numbers to check against.

    The repository carries them, so a plain clone tests itself; test/data/README.md says how
    each file was made.
    """
    return REPO_ROOT / 'test' / 'data'


def _tail(path, lines=60):
    try:
        return '\n'.join(Path(path).read_text(errors='replace').splitlines()[-lines:])
    except OSError:
        return '(no {})'.format(path)


@pytest.fixture(scope='session')
def colcon_build(tmp_path_factory):
    """
    Build the package with colcon into a fresh temporary workspace, once per session.

    Returns a dict with ``base`` (the temporary directory holding build/, install/, log/),
    ``install_base`` (``base/install``), ``prefix`` (``install_base/rope_sim_ros``) and
    ``seconds`` (duration of the build).
    """
    base = tmp_path_factory.mktemp('colcon')
    command = [
        sys.executable, '-m', 'colcon',
        '--log-base', str(base / 'log'),  # a global option: it goes before the verb
        'build',
        '--paths', str(REPO_ROOT),
        '--build-base', str(base / 'build'),
        '--install-base', str(base / 'install'),
        '--event-handlers', 'console_direct+', 'status-', 'summary+',
    ]
    env = dict(os.environ)
    # Bytecode in the source tree would be written by other people's processes too.
    env['PYTHONDONTWRITEBYTECODE'] = '1'
    start = time.monotonic()
    try:
        result = subprocess.run(
            command, cwd=str(base), env=env, stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=900)
    except subprocess.TimeoutExpired as exc:
        pytest.fail('colcon build timed out after {} s: {}\n{}'.format(
            exc.timeout, ' '.join(command), exc.output or ''), pytrace=False)
    seconds = time.monotonic() - start
    if result.returncode != 0:
        pytest.fail(
            'colcon build failed (exit {}) in {:.1f} s: {}\n{}\n--- {} ---\n{}'.format(
                result.returncode, seconds, ' '.join(command), result.stdout[-8000:],
                base / 'log' / 'latest_build' / PACKAGE_NAME / 'stdout_stderr.log',
                _tail(base / 'log' / 'latest_build' / PACKAGE_NAME / 'stdout_stderr.log')),
            pytrace=False)
    return {
        'base': base,
        'install_base': base / 'install',
        'prefix': base / 'install' / PACKAGE_NAME,
        'seconds': seconds,
        'output': result.stdout,
    }


@pytest.fixture(scope='session')
def colcon_install(colcon_build):
    """
    Return the package's install prefix Path (``<tmp>/install/rope_sim_ros``).

    Executables are ``prefix / 'lib' / 'rope_sim_ros' / <name>`` (where ``ros2 run`` looks);
    the share directory is ``prefix / 'share' / 'rope_sim_ros'``. Use ``colcon_env`` to run
    them.
    """
    return colcon_build['prefix']


@pytest.fixture(scope='session')
def colcon_env(colcon_install):
    """
    Return an environment (dict) that runs the installed package like a sourced overlay.

    The install prefix comes first on ``AMENT_PREFIX_PATH`` (so get_package_share_directory
    finds the installed config/launch files) and its site-packages first on ``PYTHONPATH``.
    """
    env = dict(os.environ)
    prefixes = [str(colcon_install)] + [
        p for p in env.get('AMENT_PREFIX_PATH', '').split(os.pathsep)
        if p and p != str(colcon_install)]
    env['AMENT_PREFIX_PATH'] = os.pathsep.join(prefixes)
    site_packages = colcon_install / 'lib' / 'python{}.{}'.format(
        *sys.version_info[:2]) / 'site-packages'
    python_path = [str(site_packages)] + [
        p for p in env.get('PYTHONPATH', '').split(os.pathsep)
        if p and Path(p).resolve() != REPO_ROOT]
    env['PYTHONPATH'] = os.pathsep.join(python_path)
    env['PATH'] = os.pathsep.join(
        [str(colcon_install / 'bin'), str(Path(sys.executable).parent), env.get('PATH', '')])
    env['PYTHONUNBUFFERED'] = '1'
    return env
