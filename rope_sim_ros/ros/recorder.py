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
Recording of the mooring_line node: its inputs and outputs to a rosbag2 Jazzy bag.

A thin layer over bag.BagWriter that the node feeds from its record() hook. It encodes
the message types itself (numpy/struct CDR with zeroed padding, as the offline
runner does: rclpy's serialize_message leaves padding bytes uninitialised, and is slower),
sets publish_time from the header stamp where there is one, and never lets a recording
problem reach the simulation: write() cannot raise and never waits for the disk; an error
stops recording, is logged once and the node goes on.

Log times strictly increase in the order the node hands the messages over (a log time not
after the previous one becomes 1 ns after it): read in log-time order, as every bag reader
does, the bag is the node's own sequence of inputs, decisions and outputs, which `rope_sim
resim` replays. Under use_sim_time the clock stands still between /clock messages, so a
pose and the outputs it let through share a clock reading, and readers order ties as they
please; a clock jumping back would put later messages before earlier ones.

Input topics are registered with the QoS their publishers offer, looked up on the graph
when the first message arrives (what `ros2 bag record` stores); an input that never
arrives is still listed, with rclpy's default publisher profile.
"""

import atexit
import logging
import os
from typing import Any, Callable, Dict, Optional

from geometry_msgs.msg import PoseArray, PoseStamped, Wrench
import numpy as np
from std_msgs.msg import Bool, Float64, String

from ..bag import BagError, cdr
from ..messages.topics import BOOL, FLOAT64, POSE_ARRAY, POSE_STAMPED, STRING, WRENCH
from ..ros2bag import QosSpec
from ..ros2bag import RosBagWriter as BagWriter

# Bytes of messages per MCAP chunk. The node's chunks are cut by the writer's flush
# interval (1 s) rather than by their size: the summary keeps an index entry per chunk for
# the whole recording, and the eight-line berth at 50 Hz (0.8 MB a second) cut the default
# 256 kB three times a second.
CHUNK_SIZE = 4 * 1024 * 1024


def pose_stamped_cdr(msg: PoseStamped) -> bytes:
    """Return a PoseStamped as CDR bytes with zero padding (see bag.cdr)."""
    p, q = msg.pose.position, msg.pose.orientation
    stamp = msg.header.stamp
    return cdr.pose_stamped(stamp.sec, stamp.nanosec, msg.header.frame_id,
                            (p.x, p.y, p.z, q.x, q.y, q.z, q.w))


def pose_array_cdr(msg: PoseArray) -> bytes:
    """Return a PoseArray as CDR bytes with zero padding (see bag.cdr)."""
    poses = [(p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y,
              p.orientation.z, p.orientation.w) for p in msg.poses]
    stamp = msg.header.stamp
    return cdr.pose_array(stamp.sec, stamp.nanosec, msg.header.frame_id, np.array(poses))


def wrench_cdr(msg: Wrench) -> bytes:
    """Return a Wrench as CDR bytes (the same bytes as serialize_message)."""
    f, t = msg.force, msg.torque
    return cdr.wrench((f.x, f.y, f.z), (t.x, t.y, t.z))


def string_cdr(msg: String) -> bytes:
    """Return a String as CDR bytes with zero padding (see bag.cdr)."""
    return cdr.string(msg.data)


# type name -> (message class, encoder, has a header)
_TYPES = {
    POSE_STAMPED: (PoseStamped, pose_stamped_cdr, True),
    POSE_ARRAY: (PoseArray, pose_array_cdr, True),
    WRENCH: (Wrench, wrench_cdr, False),
    STRING: (String, string_cdr, False),
    FLOAT64: (Float64, lambda msg: cdr.float64(msg.data), False),
    BOOL: (Bool, lambda msg: cdr.boolean(msg.data), False),
}


class _Topic:
    """One recorded topic: its resolved name, type, encoder and how to find its QoS."""

    def __init__(self, name: str, type_name: str, qos: QosSpec,
                 offered_qos: Optional[Callable[[], QosSpec]]) -> None:
        self.name = name
        self.type_name = type_name
        # another installed type (the mooring node's): RosBagWriter serialises it
        self.cls, self.encode, self.stamped = _TYPES.get(type_name, (None, None, False))
        self.qos = qos
        # Set for an input: registration waits for its first message (or close()).
        self.offered_qos = offered_qos


class Recorder:
    """
    Records the messages the node hands it to a new bag, never blocking the caller.

    ::

        recorder = Recorder('run1', parameters_text, node.get_logger())
        recorder.add_topic('fairlead/tension', '/line_1/fairlead/tension', WRENCH, qos)
        recorder.write('fairlead/tension', wrench, now_ns)
        recorder.close()
    """

    def __init__(self, path: str, custom_data: Dict[str, str], logger: Any, *,
                 queue_size: int = BagWriter.DEFAULT_QUEUE_SIZE,
                 flush_interval: float = BagWriter.DEFAULT_FLUSH_INTERVAL,
                 chunk_size: int = CHUNK_SIZE) -> None:
        """
        Create the bag directory and start its writer thread.

        :param path: the new bag directory; an existing non-empty one is refused.
        :param custom_data: metadata.yaml custom_data (e.g. the node's parameters).
        :param logger: an rclpy logger (info, warning, error) for what happens to the bag.
        :param queue_size: messages that may wait for the disk before new ones are dropped.
        :param flush_interval: seconds between chunk flushes at most (what a kill loses).
        :param chunk_size: bytes of messages after which a chunk is written out anyway.
        :raises BagError: the path exists and is not an empty directory, or is not writable.
        """
        self.logger = logger
        self.writer = BagWriter(path, queue_size=queue_size, flush_interval=flush_interval,
                                chunk_size=chunk_size, custom_data=custom_data)
        _quiet_writer_log()
        self._topics: Dict[str, _Topic] = {}
        self._offered = 0
        self._last_log_ns = None  # log time of the last message (they strictly increase)
        self._failure: Optional[str] = None  # why recording stopped, once logged
        # Closed at the interpreter's exit if the node never closes it: a Ctrl-C that cuts
        # the node's start short after this point leaves no node to close it.
        atexit.register(self._close_at_exit)

    @property
    def path(self) -> str:
        """Return the bag directory."""
        return self.writer.path

    @property
    def recording(self) -> bool:
        """Return whether messages are still being recorded (not closed, no error)."""
        return self._failure is None and not self.writer.closed

    @property
    def dropped(self) -> int:
        """Return how many messages handed to write() were not recorded."""
        return self.writer.dropped

    def add_topic(self, relative: str, name: str, type_name: str, qos: QosSpec = None,
                  offered_qos: Optional[Callable[[], QosSpec]] = None) -> None:
        """
        Register a topic the node will hand to write() under its relative name.

        :param relative: the name the node uses, e.g. 'fairlead/tension'.
        :param name: the resolved name recorded, e.g. '/line_1/fairlead/tension'.
        :param type_name: POSE_STAMPED, POSE_ARRAY, WRENCH, STRING (encoded here) or any
            other installed type (serialised by RosBagWriter).
        :param qos: the offered QoS profile(s) stored; None = rclpy's default publisher's.
        :param offered_qos: for an input: a callable returning the QoS its publishers offer
            (None or empty for the default), asked when the first message arrives.
        :raises BagError: the type is not installed, or the name is not absolute.
        """
        topic = _Topic(name, type_name, qos, offered_qos)
        if offered_qos is None:
            self.writer.add_topic(name, type_name, qos)
        self._topics[relative] = topic

    def write(self, relative: str, msg: Any, log_time_ns: int,
              publish_time_ns: Optional[int] = None) -> None:
        """
        Queue one message; never raises, never waits for the disk.

        publish_time is publish_time_ns if given, else the header stamp where the message
        has a non-zero one, else the log time. The log time is made 1 ns after the previous
        one if it is not after it. A message that cannot be queued (queue full, recording
        stopped) is counted in `dropped`; the first error is logged once.

        :param relative: a topic given to add_topic().
        :param msg: the message as received or published, or its CDR bytes as published.
        :param log_time_ns: receive/record time on the node clock [ns].
        :param publish_time_ns: its publish time [ns], or None (see above).
        """
        if self._failure is not None or self.writer.closed:
            return
        try:
            topic = self._topics[relative]
            if topic.offered_qos is not None:
                self._register(topic)
            if self._last_log_ns is not None and log_time_ns <= self._last_log_ns:
                log_time_ns = self._last_log_ns + 1
            self._last_log_ns = log_time_ns
            raw = isinstance(msg, bytes)
            if publish_time_ns is None:
                publish_time_ns = log_time_ns
                if topic.stamped and not raw:
                    stamp = msg.header.stamp
                    if stamp.sec or stamp.nanosec:
                        publish_time_ns = stamp.sec * 1_000_000_000 + stamp.nanosec
            if not raw and topic.cls is not None and type(msg) is not topic.cls:
                raise BagError(f'{topic.name} records {topic.type_name}, got '
                               f'{type(msg).__module__}.{type(msg).__name__}')
            self._offered += 1
            data = msg if raw or topic.encode is None else topic.encode(msg)
            self.writer.write(topic.name, data, log_time_ns, publish_time_ns)
            error = self.writer.error
        except Exception as exc:  # noqa: B902 - recording must never stop the simulation
            error = exc
        if error is not None:
            self._stop(error)

    def _register(self, topic: _Topic) -> None:
        """Register an input topic now, with the QoS its publishers offer."""
        qos = topic.qos
        try:
            offered = topic.offered_qos()
            if offered:
                qos = offered
        except Exception:  # noqa: B902 - a graph query failing costs the QoS, not the topic
            pass
        topic.offered_qos = None
        self.writer.add_topic(topic.name, topic.type_name, qos)

    def _stop(self, error: BaseException) -> None:
        """Stop recording for good and log why, once."""
        text = str(error)
        if error is not self.writer.error:  # the writer's own errors name the file already
            text = f'recording to {self.path} stopped: {text}'
        self._failure = text
        self.logger.error(f'{text}; the simulation goes on without recording')

    def _close_at_exit(self) -> None:
        """Complete the bag the node never closed, quietly: the process is ending."""
        try:
            self.writer.close()
        except BagError:
            pass  # readable up to its last chunk; `rope_sim recover` completes it

    def close(self) -> bool:
        """
        Complete the bag (summary, metadata.yaml) and log what it holds and what was dropped.

        Never raises; calling it again has no effect.

        :returns: True if the bag is complete, False if recording failed (the bag is then
            readable up to its last chunk; `rope_sim recover` completes it).
        """
        atexit.unregister(self._close_at_exit)
        if self.writer.closed:
            return self._failure is None
        for topic in self._topics.values():
            if topic.offered_qos is not None:
                try:
                    self._register(topic)
                except Exception as exc:  # noqa: B902
                    self.logger.error(f'bag {self.path}: cannot list {topic.name}: {exc}')
        try:
            self.writer.close()
        except Exception as exc:  # noqa: B902 - the node must still shut down cleanly
            if self._failure is None:
                self._stop(exc)
            self.logger.error(
                f'bag {self.path} is not complete: it is readable up to its last chunk; '
                f'`rope_sim recover {self.path}` makes it a complete bag')
            return False
        self.logger.info(
            f'bag {os.path.abspath(self.path)} closed: {self._offered - self.writer.dropped} '
            f'messages on {len(self._topics)} topics, {self.writer.dropped} dropped')
        if self.writer.dropped:
            self.logger.warning(
                f'bag {self.path}: {self.writer.dropped} messages were dropped, not '
                'recorded (the disk could not keep up)')
        return True


def _quiet_writer_log() -> None:
    """Leave BagWriter's errors to the Recorder, which logs them through the node logger."""
    writer_log = logging.getLogger(BagWriter.__module__)
    if not any(isinstance(h, logging.NullHandler) for h in writer_log.handlers):
        writer_log.addHandler(logging.NullHandler())
    writer_log.propagate = False
