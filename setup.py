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

from setuptools import find_packages, setup

package_name = 'rope_sim_ros'

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
    entry_points={
        'console_scripts': [
            'rope_sim = rope_sim_ros.cli:main',
            'mooring_line = rope_sim_ros.ros.mooring_line_node:main',
            'ship_motion = rope_sim_ros.ros.ship_motion_node:main',
            'line_monitor = rope_sim_ros.ros.line_monitor_node:main',
            'bag_replay = rope_sim_ros.ros.bag_replay_node:main',
        ],
    },
)
