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
Every topic name and type of the nodes, once: what both nodes, the bags and resim use.

Every name is relative, so that namespaces separate lines and ships. A line's topics sit in
its own namespace under the mooring node (`head_1/rope/particles`) and at the root under
the mooring_line node (`rope/particles`): the one difference between the two nodes'
topics, with the name of the ship's pose stream (`ship/pose`, and `fairlead/pose` for a
single line, whose fairlead is that pose ⊕ its offset), of the events topic, and the field
the events name a stream with (`stream`: ship or a line; `end`: fairlead or bollard).
No ROS here: type names are strings.
"""

from dataclasses import dataclass
from typing import Dict, Optional

from ..mooring.driver import SHIP

POSE_STAMPED = 'geometry_msgs/msg/PoseStamped'
POSE_ARRAY = 'geometry_msgs/msg/PoseArray'
WRENCH = 'geometry_msgs/msg/Wrench'
WRENCH_STAMPED = 'geometry_msgs/msg/WrenchStamped'
FLOAT64 = 'std_msgs/msg/Float64'
BOOL = 'std_msgs/msg/Bool'
STRING = 'std_msgs/msg/String'
MARKER_ARRAY = 'visualization_msgs/msg/MarkerArray'
ODOMETRY = 'nav_msgs/msg/Odometry'
FLOAT64_MULTI_ARRAY = 'std_msgs/msg/Float64MultiArray'
VECTOR3_STAMPED = 'geometry_msgs/msg/Vector3Stamped'
DIAGNOSTIC_ARRAY = 'diagnostic_msgs/msg/DiagnosticArray'

# A line's topics, relative to its namespace.
PARTICLES = 'rope/particles'
FAIRLEAD_TENSION = 'fairlead/tension'
BOLLARD_TENSION = 'bollard/tension'
FAIRLEAD_PEAK = 'fairlead/peak_tension'
BOLLARD_PEAK = 'bollard/peak_tension'
WINCH_LENGTH = 'winch/length'
PARTED = 'rope/parted'  # latched: whether the line has parted, sent when it changes
PAYLOAD_POSE = 'payload/pose'  # a payload line's payload
BOLLARD_POSE = 'bollard/pose'  # in: a line's bollard poses
WINCH_COMMAND = 'winch/command'  # in: a line's winch speed
# Every output of a line at each output, in the order they are built, and its type (a
# payload line has PAYLOAD_POSE too; PARTED goes out when it changes).
LINE_OUTPUTS: Dict[str, str] = {
    PARTICLES: POSE_ARRAY, FAIRLEAD_TENSION: WRENCH, BOLLARD_TENSION: WRENCH,
    FAIRLEAD_PEAK: FLOAT64, BOLLARD_PEAK: FLOAT64, WINCH_LENGTH: FLOAT64,
}
# The line outputs with a header: a bag gives them their stamp for a publish time, the others
# their log time (rosbag2's meaning: when it was published).
STAMPED = (PARTICLES, PAYLOAD_POSE)
# The ship's topics (mooring node).
SHIP_POSE = 'ship/pose'
MOORING_WRENCH = 'ship/mooring_wrench'  # body frame, ship_frame_id
MOORING_WRENCH_WORLD = 'ship/mooring_wrench_world'  # frame_id axes
SHIP_OUTPUTS: Dict[str, str] = {MOORING_WRENCH: WRENCH_STAMPED,
                                MOORING_WRENCH_WORLD: WRENCH_STAMPED}
# A free ship's: its pose is an output on SHIP_POSE, with its odometry (the body origin's
# pose in frame_id, its velocity in ship_frame_id axes, as nav_msgs has it).
SHIP_ODOMETRY = 'ship/odometry'
FREE_SHIP_OUTPUTS: Dict[str, str] = {SHIP_POSE: POSE_STAMPED, SHIP_ODOMETRY: ODOMETRY}
EXTERNAL_WRENCH = 'ship/external_wrench'  # in: the external load on a free ship
# A passing ship's load on the ship (body axes, about its origin), when one passes.
PASSING_WRENCH = 'ship/passing_ship_wrench'
# The waves, when set (waves.spectrum not none): their first- and second-order load on the
# ship together (body axes, about its origin) and their elevation at its origin.
WAVE_WRENCH = 'ship/wave_wrench'
WAVE_ELEVATION = 'environment/wave_elevation'
WAVE_OUTPUTS: Dict[str, str] = {WAVE_WRENCH: WRENCH_STAMPED, WAVE_ELEVATION: FLOAT64}
WIND = 'environment/wind'  # in: the air's velocity, where it goes TO
CURRENT = 'environment/current'  # in: the water's velocity, where it goes TO
STIFFNESS = 'ship/stiffness'  # the 6x6 stiffness of the lines and fenders, row-major
STIFFNESS_DIMENSIONS = ('rows', 'cols')
FENDER_REACTION = 'reaction'  # a fender's force on the ship, in its namespace
BOLLARD_LOAD = 'load'  # a named bollard's load (its lines' forces on it), in its namespace
MARKERS = 'mooring/markers'
DIAGNOSTICS = '/diagnostics'
# Services (std_srvs/Trigger): each line's commands (mooring/handling.py LINE_COMMANDS) are
# named by line_topic(line, command): head_1/make_fast, or make_fast for the single line;
# the mooring node's let go all is this one.
LET_GO_ALL = 'mooring/let_go_all'


@dataclass(frozen=True)
class Layout:
    """
    The topics of one kind of node (LINE_NODE or MOORING_NODE).

    :ivar node_name: the node's name.
    :ivar ship_pose: the ship's pose stream, relative.
    :ivar events: the events topic (std_msgs/String, one JSON object per decision).
    :ivar stream_field: the field an event names its stream with.
    :ivar ship_outputs: the node publishes the ship's wrenches (and markers, diagnostics).
    """

    node_name: str
    ship_pose: str
    events: str
    stream_field: str
    ship_outputs: bool

    def line_topic(self, line: str, relative: str) -> str:
        """Return a line's topic (relative): in its namespace, or at the root (no name)."""
        return f'{line}/{relative}' if line else relative

    def stream_topic(self, stream: str) -> str:
        """Return the pose topic of a stream: the ship's, or a line's bollard poses."""
        return self.ship_pose if stream == SHIP else self.line_topic(stream, BOLLARD_POSE)

    def event_stream(self, stream: str) -> Dict[str, str]:
        """Return the field an event names a stream with, as the node's events have it."""
        if self.stream_field == 'end':  # the single line's: fairlead or bollard
            return {'end': 'fairlead' if stream == SHIP else 'bollard'}
        return {'stream': stream}

    def line_field(self, line: str) -> Dict[str, str]:
        """Return the field an event names its line with (none for the single line)."""
        return {'line': line} if line else {}


LINE_NODE = Layout('mooring_line', 'fairlead/pose', 'rope/events', 'end', False)
MOORING_NODE = Layout('mooring', SHIP_POSE, 'mooring/events', 'stream', True)
LAYOUTS = {layout.node_name: layout for layout in (LINE_NODE, MOORING_NODE)}


def stream_of_event(event: dict, line: str) -> Optional[str]:
    """
    Return the stream an event names, in either node's field: SHIP, a line's name, or None.

    :param line: the name of the single line (the mooring_line node's: its bollard stream).
    """
    if 'stream' in event:
        return event['stream']
    if 'end' in event:
        return {'fairlead': SHIP, 'bollard': line}.get(event['end'])
    return None
