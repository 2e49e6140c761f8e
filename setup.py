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

from glob import glob
import os
import subprocess
import sys

from setuptools import Distribution, find_packages, setup
from setuptools.command.build_py import build_py
from setuptools.command.develop import develop
from setuptools.command.install import install
from setuptools.command.install_lib import install_lib

package_name = 'rope_sim_ros'

# setuptools' own build_scripts (the one of its bundled distutils), whichever version it is
build_scripts = Distribution().get_command_class('build_scripts')

# The executables (ros2 run rope_sim_ros <name>) are bin/launcher under each name (bin/<name> is a
# link to it: the launcher runs what its file is named for), not console scripts:
# a console script's preamble (importlib.metadata, 50 ms) runs before any code of the package,
# so Ctrl-C in it printed a KeyboardInterrupt traceback (80 of 140 tries in the first 75 ms).
# A launcher takes SIGINT over in its first statements; see bin/launcher.
EXECUTABLES = ('mooring_line', 'mooring', 'ship_motion', 'line_monitor', 'bag_replay',
               'rope_sim')

# Before those statements the interpreter starts (1 to 10 ms) and turns a Ctrl-C into a
# KeyboardInterrupt whose traceback it prints (1 of 60 tries in the first 10 ms). GNU env (8.31 and
# later) starts it with SIGINT held back, which the launcher lets through once it has taken
# SIGINT over; a Ctrl-C before env holds it back ends the process by the signal, silently.
ENV = '/usr/bin/env'
SHEBANG_MAX = 127  # bytes of '#!' line Linux reads (before 5.1; 255 since)


def launcher_interpreter(python):
    """Return what the launchers' first line runs: python behind env, where env can do it."""
    held = '{} -S --block-signal=INT {}'.format(ENV, python)
    if not os.path.isabs(python) or len('#!{} -S'.format(held)) > SHEBANG_MAX:
        return python  # a wheel: pip writes the first line ('#!python') on installing it
    try:
        # exactly what the kernel runs for the first line '#!<held> -S'
        works = subprocess.run([ENV, held[len(ENV) + 1:] + ' -S -c pass'],
                               stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL, timeout=60).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        works = False
    return held if works else python


HERE = os.path.dirname(os.path.abspath(__file__))

# Compiling the numba kernels took 7.7 s (quiet 2 cores) to 44 s (loaded) at the first start
# after every fresh build, 90 s to 3 minutes since; compiled here, right after installing,
# numba's cache lands next to the installed sources and every start only loads it (0.5 s):
# rope_sim_ros/mooring/precompile.py. It starts from the source tree's cache (the one
# `make test` compiles) where that was compiled from these very sources.
PRECOMPILE = ('import sys; from rope_sim_ros.mooring.precompile import main; '
              'sys.exit(main(sys.argv[1:]))')


def precompile(package_parent):
    """Compile the kernels of the package installed under package_parent, in a subprocess."""
    if os.environ.get('ROPE_SIM_PRECOMPILE', '1') == '0':
        print('ROPE_SIM_PRECOMPILE=0: the numba kernels compile at the first start instead')
        return
    env = dict(os.environ)
    env['PYTHONPATH'] = os.pathsep.join(
        [package_parent] + [p for p in env.get('PYTHONPATH', '').split(os.pathsep) if p])
    print('compiling the numba kernels into ' + package_parent, flush=True)
    source = os.path.join(HERE, package_name)
    seed = [] if os.path.realpath(source) == os.path.realpath(
        os.path.join(package_parent, package_name)) else ['--seed-from', source]
    try:
        # cwd: the installed package, never the source tree beside setup.py, is imported
        result = subprocess.run([sys.executable, '-c', PRECOMPILE] + seed, cwd=package_parent,
                                env=env, stdin=subprocess.DEVNULL, timeout=1800)
        failed = result.returncode != 0
    except (OSError, subprocess.TimeoutExpired) as e:
        print(e, file=sys.stderr)
        failed = True
    if failed:
        # the package works without it: the kernels then compile at the first start
        print('warning: compiling the numba kernels failed (see above); they will compile at '
              'the first start instead', file=sys.stderr)


def bytecode_allowed(byte_compile):
    """Wrap a command's byte_compile so that it runs whatever PYTHONDONTWRITEBYTECODE says."""
    def run(command, files):
        dont_write_bytecode, sys.dont_write_bytecode = sys.dont_write_bytecode, False
        try:
            byte_compile(command, files)
        finally:
            sys.dont_write_bytecode = dont_write_bytecode
    return run


class BuildPy(build_py):
    """build_py, without its warning that byte-compiling is disabled: the install does it."""

    byte_compile = bytecode_allowed(build_py.byte_compile)  # compiles nothing: no --compile


class InstallLibCompiled(install_lib):
    """
    Install the package with its sources' times, and byte-compile it even so.

    PYTHONDONTWRITEBYTECODE (the Makefile's: no bytecode in the source tree) made setuptools
    skip the byte-compiling ('byte-compiling is disabled'), so the first start compiled the
    package's sources (the node's --help, which imports all it is made of, took 0.76 s of CPU
    instead of 0.59 s) and wrote them into the install, or every start did. The bytecode goes
    where it always would: __pycache__ beside each installed source, in the install's record.

    The installed sources keep their source's modification time to the nanosecond (copying
    keeps whole seconds): numba before 0.68 keys a cached kernel by its file's time and size
    (0.68 by its content), and a cache compiled in either tree serves the other
    (precompile's --seed-from: this build, `make test`).
    """

    def install(self):
        """Copy the build into the install, then give each source its source's time."""
        outfiles = super().install()
        for path in outfiles or ():
            source = os.path.join(HERE, os.path.relpath(path, self.install_dir))
            if path.endswith('.py') and os.path.isfile(source) and \
                    os.path.getsize(source) == os.path.getsize(path):
                status = os.stat(source)
                os.utime(path, ns=(status.st_atime_ns, status.st_mtime_ns))
        return outfiles

    byte_compile = bytecode_allowed(install_lib.byte_compile)


class InstallAndPrecompile(install):
    """setup.py install (colcon build), then compile the kernels next to the installed files."""

    def run(self):
        super().run()
        if self.root:
            return  # a staging tree (wheel, distribution package): built for another machine
        precompile(os.path.abspath(self.install_lib))


class BuildLaunchers(build_scripts):
    """Copy the launchers in bin/ with a first line that runs them behind env if it can."""

    def finalize_options(self):
        super().finalize_options()
        self.executable = launcher_interpreter(self.executable)


class DevelopAndPrecompile(develop):
    """setup.py develop (colcon build --symlink-install), then compile the kernels."""

    def run(self):
        super().run()
        if not self.uninstall:
            precompile(os.path.abspath(self.egg_path))

    def install_script(self, dist, script_name, script_text, dev_path=None):
        """Install a launcher as it is: no wrapper importing pkg_resources before it runs."""
        # setuptools' development wrapper imports pkg_resources (0.2 s) before the launcher
        # can take SIGINT over, and cannot import it at all under the launcher's -S.
        if dev_path is None or script_name not in EXECUTABLES:
            return super().install_script(dist, script_name, script_text, dev_path)
        interpreter = self.get_finalized_command('build_scripts').executable
        first, _, body = script_text.partition('\n')
        options = first.partition('python')[2]  # ' -S'
        self.write_script(script_name, '#!{}{}\n{}'.format(interpreter, options, body).encode(),
                          'b')


setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test', 'benchmarks']),
    package_data={'rope_sim_ros.ros': ['fastdds_discovery.xml']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config',
         glob('config/*.yaml') + glob('config/*.json') + glob('config/*.rviz')),
        ('share/' + package_name + '/config/ship', glob('config/ship/*.csv')),
        ('share/' + package_name + '/launch', glob('launch/*.launch.py')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='rope_sim_ros maintainers',
    maintainer_email='maintainers@rope-sim-ros.invalid',
    description='Real-time mooring line simulation (mass-spring rope) for ROS 2 Jazzy.',
    license='Apache-2.0',
    tests_require=['pytest'],
    cmdclass={'build_py': BuildPy, 'build_scripts': BuildLaunchers,
              'install': InstallAndPrecompile, 'install_lib': InstallLibCompiled,
              'develop': DevelopAndPrecompile},
    scripts=['bin/' + name for name in EXECUTABLES],
)
