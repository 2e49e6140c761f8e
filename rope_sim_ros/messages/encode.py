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
A mooring's outputs as message bytes (CDR), built once from the numbers for every taker.

The nodes publish these bytes and record them; the offline bag writes the same bytes, so a
node's bag and a re-simulation of it hold the same messages. Only the topics asked for are
built: 16 lines' particles at 100 Hz, through rclpy's message classes, cost more than their
physics (370 us an output for one line's particles and tensions, as bytes 80 us).

- rope/particles: geometry_msgs/PoseArray, bollard first, each pose's x axis along the rope
  (frames.lines_tangent_quaternions: every line in one pass);
- fairlead/tension, bollard/tension: geometry_msgs/Wrench, the force of the line on the end
  [N, frame_id axes], the torque its moment about the end's pose origin (the lever × force);
- peaks and the winch's length: std_msgs/Float64; payload/pose: geometry_msgs/PoseStamped;
- ship/mooring_wrench (body axes, ship_frame_id) and ship/mooring_wrench_world (frame_id
  axes): geometry_msgs/WrenchStamped, about the ship's origin;
- a free ship's ship/pose (geometry_msgs/PoseStamped, its origin in frame_id) and
  ship/odometry (nav_msgs/Odometry: that pose, and the origin's velocity and the angular
  velocity in ship_frame_id axes, covariances unknown: zero);
- each fender's <fender>/reaction: geometry_msgs/WrenchStamped in frame_id, the force of the
  fender on the hull at its contact point (no torque about that point);
- each named bollard's <bollard>/load: geometry_msgs/WrenchStamped in frame_id, the sum of
  the forces of the lines fast on it (no torque about the bollard);
- ship/passing_ship_wrench: a passing ship's surge and sway force and yaw moment on the ship
  (geometry_msgs/WrenchStamped, body axes, about its origin);
- with waves, ship/wave_wrench: their first-order load and slow drift on the ship together
  (geometry_msgs/WrenchStamped, body axes, about its origin), and
  environment/wave_elevation: their elevation at the ship's origin (std_msgs/Float64).
"""

from typing import Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

from . import topics
from .topics import Layout
from ..bag import cdr
from ..model.frames import cross_rows, lines_tangent_quaternions, split_ns
from ..mooring.records import Published
from ..mooring.ship import reports_waves
from ..params.arrangement import ArrangementParams


def pose_stamped(stamp_ns: int, frame_id: str, position: Sequence[float],
                 orientation: Sequence[float] = (0.0, 0.0, 0.0, 1.0)) -> bytes:
    """Return a PoseStamped (identity orientation unless given) as CDR bytes."""
    sec, nanosec = split_ns(stamp_ns)
    return cdr.pose_stamped(sec, nanosec, frame_id,
                            [*map(float, position), *map(float, orientation)])


class OutputEncoder:
    """
    Builds an output's messages for one node kind's topics (see the module docstring).

    :ivar line_topics: {topic: (line index, relative name)} of every line output but the
        latched parted flag.
    :ivar parted_topics: each line's parted topic.
    :ivar output_topics: every topic an output may publish on: the lines', then the ship's.
    """

    def __init__(self, layout: Layout, names: Sequence[str], payloads: Sequence[bool],
                 frame_id: str, ship_frame_id: str = 'base_link', free: bool = False,
                 fenders: Sequence[str] = (), passing: bool = False,
                 bollards: Sequence[str] = (), waves: bool = False):
        """
        Name every output of these lines (payloads: which lines end in a payload).

        :param free: a free ship's (its pose and odometry are outputs).
        :param fenders: the fenders' names (their reactions are outputs).
        :param bollards: the named bollards' (their loads are outputs).
        :param passing: a ship passes (its load on the ship is an output).
        :param waves: waves are set (their load and elevation are outputs).
        """
        self.layout = layout
        self.frame_id = frame_id
        self.ship_frame_id = ship_frame_id
        self.line_topics: Dict[str, Tuple[int, str]] = {}
        self.types: Dict[str, str] = {}
        for k, (name, payload) in enumerate(zip(names, payloads)):
            outputs = dict(topics.LINE_OUTPUTS)
            if payload:
                outputs[topics.PAYLOAD_POSE] = topics.POSE_STAMPED
            for relative, type_name in outputs.items():
                topic = layout.line_topic(name, relative)
                self.line_topics[topic] = (k, relative)
                self.types[topic] = type_name
        self.parted_topics = [layout.line_topic(name, topics.PARTED) for name in names]
        self.types.update({topic: topics.BOOL for topic in self.parted_topics})
        self.ship_topics = dict(topics.SHIP_OUTPUTS) if layout.ship_outputs else {}
        if free:
            self.ship_topics.update(topics.FREE_SHIP_OUTPUTS)
        if passing:
            self.ship_topics[topics.PASSING_WRENCH] = topics.WRENCH_STAMPED
        if waves:
            self.ship_topics.update(topics.WAVE_OUTPUTS)
        self.fender_topics = {f'{name}/{topics.FENDER_REACTION}': f
                              for f, name in enumerate(fenders)}
        self.ship_topics.update({topic: topics.WRENCH_STAMPED for topic in self.fender_topics})
        self.bollard_topics = {f'{name}/{topics.BOLLARD_LOAD}': b
                               for b, name in enumerate(bollards)}
        self.ship_topics.update({topic: topics.WRENCH_STAMPED for topic in self.bollard_topics})
        self.types.update(self.ship_topics)
        # one tuple for the node's life: which of them are taken is kept while it is the same
        self.output_topics = tuple(self.line_topics) + tuple(self.ship_topics)
        self._parted: List[Optional[bool]] = [None] * len(names)  # what was said last

    def has_header(self, topic: str) -> bool:
        """Tell whether an output topic's messages carry a header stamp (the ship's do)."""
        line = self.line_topics.get(topic)
        if line is None:
            return topic in self.ship_topics and self.ship_topics[topic] != topics.FLOAT64
        return line[1] in topics.STAMPED

    def messages(self, published: Published,
                 wanted: Optional[Iterable[str]] = None) -> List[Tuple[str, bytes]]:
        """
        Return (topic, CDR bytes) of the output's messages on the wanted topics, in order.

        :param wanted: the topics to build (None: every one of output_topics).
        """
        wanted = self.output_topics if wanted is None else list(wanted)
        out = published.output
        sec, nanosec = split_ns(published.stamp_ns)
        kinds = {self.line_topics[topic][1] for topic in wanted if topic in self.line_topics}
        if topics.PARTICLES in kinds:
            positions = np.concatenate(out.positions)
            starts = np.cumsum([0] + [len(x) for x in out.positions])
            poses = np.concatenate([positions, lines_tangent_quaternions(positions, starts)],
                                   axis=1)
        if topics.FAIRLEAD_TENSION in kinds:
            fairlead_torques = cross_rows(published.fairlead_levers, out.fairlead_forces)
        if topics.BOLLARD_TENSION in kinds:
            bollard_torques = cross_rows(published.bollard_levers, out.bollard_forces)
        built = []
        for topic in wanted:
            if topic in self.line_topics:
                k, relative = self.line_topics[topic]
                if relative == topics.PARTICLES:
                    data = cdr.pose_array(sec, nanosec, self.frame_id,
                                          poses[starts[k]:starts[k + 1]])
                elif relative == topics.FAIRLEAD_TENSION:
                    data = cdr.wrench(out.fairlead_forces[k], fairlead_torques[k])
                elif relative == topics.BOLLARD_TENSION:
                    data = cdr.wrench(out.bollard_forces[k], bollard_torques[k])
                elif relative == topics.FAIRLEAD_PEAK:
                    data = cdr.float64(out.fairlead_peaks[k])
                elif relative == topics.BOLLARD_PEAK:
                    data = cdr.float64(out.bollard_peaks[k])
                elif relative == topics.WINCH_LENGTH:
                    data = cdr.float64(out.line_lengths[k])
                else:  # PAYLOAD_POSE
                    data = pose_stamped(published.stamp_ns, self.frame_id,
                                        out.payload_positions[k])
            elif topic == topics.MOORING_WRENCH:
                data = cdr.wrench_stamped(sec, nanosec, self.ship_frame_id, published.force,
                                          published.moment)
            elif topic == topics.MOORING_WRENCH_WORLD:
                data = cdr.wrench_stamped(sec, nanosec, self.frame_id,
                                          *published.world_wrench())
            elif topic in self.fender_topics:
                data = cdr.wrench_stamped(sec, nanosec, self.frame_id,
                                          out.fender_forces[self.fender_topics[topic]],
                                          (0.0, 0.0, 0.0))
            elif topic in self.bollard_topics:
                load = published.bollard_loads[self.bollard_topics[topic]]
                data = cdr.wrench_stamped(sec, nanosec, self.frame_id, load.force,
                                          (0.0, 0.0, 0.0))
            elif topic == topics.PASSING_WRENCH:
                fx, fy, mz = out.ship_loads[2]
                data = cdr.wrench_stamped(sec, nanosec, self.ship_frame_id, (fx, fy, 0.0),
                                          (0.0, 0.0, mz))
            elif topic == topics.WAVE_WRENCH:
                load = out.wave_loads.sum(axis=0)
                data = cdr.wrench_stamped(sec, nanosec, self.ship_frame_id, load[:3], load[3:])
            elif topic == topics.WAVE_ELEVATION:
                data = cdr.float64(out.wave_elevation)
            elif topic == topics.SHIP_POSE:
                data = cdr.pose_stamped(sec, nanosec, self.frame_id,
                                        [*out.ship.position, *out.ship.orientation])
            else:  # SHIP_ODOMETRY
                rotation = published.rotation  # the twist in the ship's axes
                data = cdr.odometry(sec, nanosec, self.frame_id, self.ship_frame_id,
                                    [*out.ship.position, *out.ship.orientation],
                                    [*(out.ship.velocity @ rotation),
                                     *(out.ship.omega @ rotation)])
            built.append((topic, data))
        return built

    def parted_changes(self, parted: Sequence[bool]) -> List[Tuple[str, bool]]:
        """Return (topic, flag) of each line whose parted flag changed since it was said."""
        changes = []
        for k, now in enumerate(np.asarray(parted, dtype=bool).tolist()):
            if now is not self._parted[k]:
                self._parted[k] = now
                changes.append((self.parted_topics[k], now))
        return changes


def encoder_for(setup: ArrangementParams) -> OutputEncoder:
    """Return the encoder of every output the node of this setup's kind publishes."""
    layout = topics.LINE_NODE if setup.single else topics.MOORING_NODE
    return OutputEncoder(layout, setup.names, [line.params.has_payload for line in setup.lines],
                         setup.shared.frame_id, setup.ship_frame_id, setup.ship.free,
                         [fender.name for fender in setup.fenders], setup.passing.present,
                         [bollard.name for bollard in setup.bollards],
                         reports_waves(setup))


def stiffness_message(matrix: np.ndarray) -> bytes:
    """Return ship/stiffness: the 6x6 matrix row-major, dimensions 'rows' and 'cols'."""
    rows, cols = topics.STIFFNESS_DIMENSIONS
    return cdr.float64_multi_array([(rows, 6, 36), (cols, 6, 6)], np.asarray(matrix).ravel())
