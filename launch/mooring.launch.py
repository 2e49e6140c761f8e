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
Launch a ship's mooring arrangement: the mooring node with an arrangement file.

    ros2 launch rope_sim_ros mooring.launch.py namespace:=ship_a use_sim_time:=true
    ros2 launch rope_sim_ros mooring.launch.py params_file:=my_berth.yaml
    ros2 launch rope_sim_ros mooring.launch.py ship_motion:=true

With ship_motion:=true a scripted ship (the ship_motion node, in the same namespace) drives
the mooring: its fairlead/pose remapped to ship/pose, its parameters config/berth_motion.yaml
(motions config/berth.yaml's lines hold), oscillating around mean_position (the ship's
origin at rest, default config/berth.yaml's (0, -17.6, 0)).

Every topic of the node is relative, so two ships run side by side, one namespace each. The
parameter file must be an arrangement (`mooring: ros__parameters: lines: [...]`, as
config/berth.yaml); a single line's file (`mooring_line:`) is refused with the launch file
to use instead.
"""

import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
import yaml


def sections(path: str) -> set:
    """Return the node names a ROS parameter file has `ros__parameters` for (no namespace)."""
    with open(path, encoding='utf-8') as f:
        data = yaml.safe_load(f) or {}
    return {str(key).rstrip('/').split('/')[-1] for key, section in data.items()
            if isinstance(section, dict) and 'ros__parameters' in section}


def check_params_file(context):
    """Refuse a parameter file that is not an arrangement, naming the launch file to use."""
    path = LaunchConfiguration('params_file').perform(context)
    found = sections(path)
    if 'mooring' not in found and '**' not in found:
        other = ' (a single line: use mooring_line.launch.py)' if 'mooring_line' in found else ''
        raise RuntimeError(f'{path} has no "mooring: ros__parameters:" section{other}')
    return []


def generate_launch_description():
    config = os.path.join(get_package_share_directory('rope_sim_ros'), 'config')
    default_params_file = os.path.join(config, 'berth.yaml')
    return LaunchDescription([
        DeclareLaunchArgument(
            'namespace', default_value='',
            description='Namespace of the node and its topics (one per ship).'),
        DeclareLaunchArgument(
            'params_file', default_value=default_params_file,
            description='The arrangement (ROS 2 YAML: mooring: ros__parameters: lines: ...).'),
        DeclareLaunchArgument(
            'use_sim_time', default_value='false', choices=['true', 'false', 'True', 'False'],
            description='Follow /clock (a bag or a ship simulator) instead of the wall clock.'),
        OpaqueFunction(function=check_params_file),
        Node(
            package='rope_sim_ros',
            executable='mooring',
            name='mooring',
            namespace=LaunchConfiguration('namespace'),
            parameters=[
                LaunchConfiguration('params_file'),
                {'use_sim_time': ParameterValue(LaunchConfiguration('use_sim_time'),
                                                value_type=bool)},
            ],
            output='screen',
        ),
        DeclareLaunchArgument(
            'ship_motion', default_value='false', choices=['true', 'false', 'True', 'False'],
            description='Also start ship_motion, remapped to ship/pose, to drive the ship.'),
        DeclareLaunchArgument(
            'mean_position', default_value='[0.0, -17.6, 0.0]',
            description="ship_motion's mean position: the ship's origin at rest in frame_id "
                        '(config/berth.yaml: 1.5 m off the quay face).'),
        Node(
            package='rope_sim_ros',
            executable='ship_motion',
            name='ship_motion',
            namespace=LaunchConfiguration('namespace'),
            condition=IfCondition(LaunchConfiguration('ship_motion')),
            remappings=[('fairlead/pose', 'ship/pose')],
            parameters=[
                os.path.join(config, 'berth_motion.yaml'),
                {'mean_position': LaunchConfiguration('mean_position'),  # read as YAML
                 'use_sim_time': ParameterValue(LaunchConfiguration('use_sim_time'),
                                                value_type=bool)},
            ],
            output='screen',
        ),
    ])
