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
    ros2 launch rope_sim_ros mooring.launch.py ship_mode:=free
    ros2 launch rope_sim_ros mooring.launch.py use_sim_time:=true \
        scenario_file:=install/rope_sim_ros/share/rope_sim_ros/config/berth_demo.yaml

With ship_motion:=true a scripted ship (the ship_motion node, in the same namespace) drives
the mooring: its fairlead/pose remapped to ship/pose, its parameters config/berth_motion.yaml
(motions config/berth.yaml's lines hold), oscillating around mean_position (the ship's
origin at rest, default config/berth.yaml's (0, -17.6, 0)). ship_mode:=free makes the ship
a rigid body moved by its lines, fenders and loads (driven: it follows ship/pose); empty,
the parameter files say. scenario_file is a parameter file on top of params_file, such as
config/berth_demo.yaml (the demo's free ship and passing ship: it needs a /clock, as `make
demo` gives one, or use_sim_time:=false).

Every topic of the node is relative, so two ships run side by side, one namespace each. The
parameter file must be an arrangement (`mooring: ros__parameters: lines: [...]`, as
config/berth.yaml); a single line's file (`mooring_line:`) is refused with the launch file
to use instead, a file without lines with the argument to give it as. A mooring node that
exits with an error (a parameter not allowed) ends the launch with an error too.
"""

import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction, RegisterEventHandler
from launch.conditions import IfCondition
from launch.event_handlers import OnProcessExit
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
import yaml


def sections(path: str) -> dict:
    """Return the `ros__parameters` of a ROS parameter file by node name (no namespace)."""
    with open(path, encoding='utf-8') as f:
        data = yaml.safe_load(f) or {}
    return {str(key).rstrip('/').split('/')[-1]: section.get('ros__parameters') or {}
            for key, section in data.items()
            if isinstance(section, dict) and 'ros__parameters' in section}


def check_params_file(context):
    """Refuse a parameter file that is not an arrangement, naming what to do instead."""
    path = LaunchConfiguration('params_file').perform(context)
    found = sections(path)
    ours = {**found.get('**', {}), **found.get('mooring', {})}
    if 'mooring' not in found and '**' not in found:
        other = ' (a single line: use mooring_line.launch.py)' if 'mooring_line' in found else ''
        raise RuntimeError(f'{path} has no "mooring: ros__parameters:" section{other}')
    if 'lines' not in ours:
        raise RuntimeError(f'{path} names no lines: it is not an arrangement; give it on top '
                           f'of one as scenario_file:={path}')
    return []


def mooring_parameters(context):
    """Return the mooring node: params_file, then scenario_file and ship_mode on top."""
    files = [LaunchConfiguration('params_file').perform(context)]
    scenario = LaunchConfiguration('scenario_file').perform(context)
    if scenario:
        files.append(scenario)
    overrides = {'use_sim_time': ParameterValue(LaunchConfiguration('use_sim_time'),
                                                value_type=bool)}
    ship_mode = LaunchConfiguration('ship_mode').perform(context)
    if ship_mode:
        overrides['ship_mode'] = ship_mode
    mooring = Node(
        package='rope_sim_ros',
        executable='mooring',
        name='mooring',
        namespace=LaunchConfiguration('namespace'),
        parameters=[*files, overrides],
        output='screen',
    )
    return [mooring, RegisterEventHandler(OnProcessExit(target_action=mooring,
                                                        on_exit=check_exit))]


def check_exit(event, context):
    """End the launch with an error when the mooring node exits with one (exit code 2)."""
    if event.returncode != 0:
        raise RuntimeError(f'the mooring node exited with code {event.returncode}: see its '
                           'error above')
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
            'scenario_file', default_value='',
            description='Parameters on top of params_file (e.g. the installed '
                        'config/berth_demo.yaml); empty: none.'),
        DeclareLaunchArgument(
            'ship_mode', default_value='', choices=['', 'driven', 'free'],
            description='driven: the ship follows ship/pose; free: it moves under its lines '
                        'and loads; empty: as the parameter files say.'),
        DeclareLaunchArgument(
            'use_sim_time', default_value='false', choices=['true', 'false', 'True', 'False'],
            description='Follow /clock (a bag or a ship simulator) instead of the wall clock.'),
        OpaqueFunction(function=check_params_file),
        OpaqueFunction(function=mooring_parameters),
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
