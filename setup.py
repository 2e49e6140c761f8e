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

from setuptools import find_packages, setup
from setuptools.command.develop import develop
from setuptools.command.install import install

package_name = 'rope_sim_ros'

# Compiling the numba kernels took 7.7 s (quiet 2 cores) to 44 s (loaded) at the first start
# after every fresh build; compiled here, right after installing, numba's cache lands next to
# the installed sources and every start only loads it (0.4 s). See rope_sim_ros/precompile.py.
PRECOMPILE = 'import sys; from rope_sim_ros.precompile import main; sys.exit(main())'


def precompile(package_parent):
    """Compile the kernels of the package installed under package_parent, in a subprocess."""
    if os.environ.get('ROPE_SIM_PRECOMPILE', '1') == '0':
        print('ROPE_SIM_PRECOMPILE=0: the numba kernels compile at the first start instead')
        return
    env = dict(os.environ)
    env['PYTHONPATH'] = os.pathsep.join(
        [package_parent] + [p for p in env.get('PYTHONPATH', '').split(os.pathsep) if p])
    print('compiling the numba kernels into ' + package_parent, flush=True)
    try:
        # cwd: the installed package, never the source tree beside setup.py, is imported
        result = subprocess.run([sys.executable, '-c', PRECOMPILE], cwd=package_parent,
                                env=env, stdin=subprocess.DEVNULL, timeout=1800)
        failed = result.returncode != 0
    except (OSError, subprocess.TimeoutExpired) as e:
        print(e, file=sys.stderr)
        failed = True
    if failed:
        # the package works without it: the kernels then compile at the first start
        print('warning: compiling the numba kernels failed (see above); they will compile at '
              'the first start instead', file=sys.stderr)


class InstallAndPrecompile(install):
    """setup.py install (colcon build), then compile the kernels next to the installed files."""

    def run(self):
        super().run()
        if self.root:
            return  # a staging tree (wheel, distribution package): built for another machine
        precompile(os.path.abspath(self.install_lib))


class DevelopAndPrecompile(develop):
    """setup.py develop (colcon build --symlink-install), then compile the kernels."""

    def run(self):
        super().run()
        if not self.uninstall:
            precompile(os.path.abspath(self.egg_path))


setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test', 'benchmarks']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config', glob('config/*.yaml')),
        ('share/' + package_name + '/launch', glob('launch/*.launch.py')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='rope_sim_ros maintainers',
    maintainer_email='maintainers@rope-sim-ros.invalid',
    description='Real-time mooring line simulation (mass-spring rope) for ROS 2 Jazzy.',
    license='Apache-2.0',
    tests_require=['pytest'],
    cmdclass={'install': InstallAndPrecompile, 'develop': DevelopAndPrecompile},
    entry_points={
        'console_scripts': [
            'rope_sim = rope_sim_ros.ros.executables:rope_sim',
            'mooring_line = rope_sim_ros.ros.executables:mooring_line',
            'ship_motion = rope_sim_ros.ros.executables:ship_motion',
            'line_monitor = rope_sim_ros.ros.executables:line_monitor',
            'bag_replay = rope_sim_ros.ros.executables:bag_replay',
        ],
    },
)
