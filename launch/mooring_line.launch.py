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
Launch one simulated mooring line.

    ros2 launch rope_sim_ros mooring_line.launch.py namespace:=line_1 use_sim_time:=true

Every topic of the node is relative, so a ship's lines run side by side, one namespace each.
An arrangement's file (`mooring: ros__parameters: lines: [...]`, as config/berth.yaml) is
refused with the launch file to use instead: the line's node would find none of its
parameters in it and start a default line.
"""

import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
import yaml


def check_params_file(context):
    """Refuse an arrangement's parameter file, naming the launch file to use."""
    path = LaunchConfiguration('params_file').perform(context)
    with open(path, encoding='utf-8') as f:
        data = yaml.safe_load(f) or {}
    for key, section in data.items():
        name = str(key).rstrip('/').split('/')[-1]
        if name in ('mooring', '**') and isinstance(section, dict) and \
                'lines' in (section.get('ros__parameters') or {}):
            raise RuntimeError(f'{path} is an arrangement (lines: ...): launch it with '
                               'mooring.launch.py')
    return []


def generate_launch_description():
    default_params_file = os.path.join(
        get_package_share_directory('rope_sim_ros'), 'config', 'mooring_line.yaml')

    namespace = LaunchConfiguration('namespace')
    params_file = LaunchConfiguration('params_file')
    use_sim_time = LaunchConfiguration('use_sim_time')

    return LaunchDescription([
        DeclareLaunchArgument(
            'namespace', default_value='',
            description='Namespace of the node and its topics (one per mooring line).'),
        DeclareLaunchArgument(
            'params_file', default_value=default_params_file,
            description='Parameter file for the node (ROS 2 YAML, ros__parameters).'),
        DeclareLaunchArgument(
            'use_sim_time', default_value='false', choices=['true', 'false', 'True', 'False'],
            description='Follow /clock (a bag or a ship simulator) instead of the wall clock.'),
        OpaqueFunction(function=check_params_file),
        Node(
            package='rope_sim_ros',
            executable='mooring_line',
            name='mooring_line',
            namespace=namespace,
            parameters=[
                params_file,
                {'use_sim_time': ParameterValue(use_sim_time, value_type=bool)},
            ],
            output='screen',
        ),
    ])
