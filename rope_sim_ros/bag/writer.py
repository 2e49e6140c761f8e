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
BagWriter: record CDR messages to a rosbag2 Jazzy MCAP bag from a background thread.

The caller's write() only enqueues bytes (cdr.py encodes them; rope_sim_ros.ros2bag's
RosBagWriter takes message objects and rclpy QoS profiles), so a slow or stalled disk never
stalls a simulation step; a full queue drops the message and counts it. The thread
writes chunks of at most chunk_size bytes and finishes the chunk in progress at least
every flush_interval seconds, so a killed process leaves a bag readable up to the last
such flush (see reader.py and recover.py). close(), e.g. after Ctrl-C, completes it.
"""

import logging
import os
import queue
import threading
import time
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

from . import metadata as meta
from . import schema
from . import storage
from .errors import BagError

# Tells the thread that close() was called and everything before it is queued.
_STOP = object()


class BagWriter:
    """
    Writes a rosbag2 Jazzy bag: `<path>/<name>_0.mcap` and `<path>/metadata.yaml`.

    Use it as a context manager, or call close() yourself (e.g. in the node's shutdown)::

        with BagWriter('run1') as bag:
            bag.add_topic('/fairlead/tension', 'geometry_msgs/msg/Wrench')
            bag.write('/fairlead/tension', cdr.wrench(force, torque), now_ns)

    The types it can record are those of schema.known_types(); errors are logged to the
    logger named after the class's module.
    """

    DEFAULT_QUEUE_SIZE = 10000
    DEFAULT_CHUNK_SIZE = storage.DEFAULT_CHUNK_SIZE
    DEFAULT_FLUSH_INTERVAL = 1.0
    # Messages the thread takes from the queue before handing data to the OS again.
    _BATCH = 256

    def __init__(
        self,
        path: Union[str, 'os.PathLike[str]'],
        *,
        queue_size: int = DEFAULT_QUEUE_SIZE,
        chunk_size: int = DEFAULT_CHUNK_SIZE,
        flush_interval: float = DEFAULT_FLUSH_INTERVAL,
        custom_data: Optional[Mapping[str, str]] = None,
    ) -> None:
        """
        Create the bag directory and its MCAP file and start the writer thread.

        :param path: The bag directory to create; it must not exist or be empty.
        :param queue_size: Messages that may wait for the thread before write() drops.
        :param chunk_size: Bytes of messages per MCAP chunk.
        :param flush_interval: Seconds after which a chunk in progress is written out
            anyway; a kill loses at most about this much recording.
        :param custom_data: Free key/value strings for metadata.yaml's custom_data.

        :raises BagError: a bad argument, or the path exists already, or is not writable.
        """
        if queue_size < 1 or chunk_size < 1 or not flush_interval > 0:
            raise BagError(
                f'bag {os.fspath(path)}: queue_size={queue_size}, chunk_size={chunk_size} '
                f'and flush_interval={flush_interval} must all be positive')
        if custom_data is not None and not all(
                isinstance(key, str) and isinstance(value, str)
                for key, value in custom_data.items()):
            raise BagError(
                f'bag {os.fspath(path)}: custom_data must map strings to strings, '
                f'got {custom_data!r}')
        self._custom_data = dict(custom_data) if custom_data else None
        self._path = storage.create_bag_directory(path)
        self._file = storage.McapFile(storage.new_file_name(self._path), chunk_size=chunk_size,
                                      custom_data=self._custom_data)
        self._flush_interval = float(flush_interval)
        self._queue: 'queue.Queue[Any]' = queue.Queue(queue_size)
        # Topic name -> type name, filled by add_topic().
        self._topics: Dict[str, str] = {}
        self._pending: List[Tuple[meta.TopicRecord, str]] = []
        self._lock = threading.Lock()
        self._dropped = 0
        self._error: Optional[BagError] = None
        self._closed = False
        # A daemon: an owner that forgets close() must not hang the interpreter's exit.
        self._thread = threading.Thread(
            target=self._run, name=f'BagWriter {self._path}', daemon=True)
        self._thread.start()

    @property
    def path(self) -> str:
        """Return the bag directory."""
        return self._path

    @property
    def storage_path(self) -> str:
        """Return the MCAP file inside the bag directory."""
        return self._file.path

    @property
    def dropped(self) -> int:
        """Return how many messages were not recorded (queue full, error or closed)."""
        return self._dropped

    @property
    def error(self) -> Optional[BagError]:
        """Return the error that stopped recording, or None while all is well."""
        return self._error

    @property
    def closed(self) -> bool:
        """Return whether close() was called."""
        return self._closed

    def add_topic(self, name: str, type_name: str, qos: meta.QosSpec = None) -> None:
        """
        Register a topic before writing to it (again with the same type: no effect).

        :param name: Fully qualified topic name, e.g. '/mooring_line/fairlead/tension'.
        :param type_name: Message type, 'pkg/msg/Type', one of schema.known_types().
        :param qos: The publisher's offered QoS profile(s) as rosbag2 dicts (see
            metadata.qos_profiles_yaml); None for rclpy's default publisher profile.

        :raises BagError: the bag is closed, the name is not absolute, the type is unknown
            or the topic was added before with another type.
        """
        if self._closed:
            raise BagError(f'bag {self._path} is closed; cannot add topic {name!r}')
        if not isinstance(name, str) or not name.startswith('/') or len(name) < 2:
            raise BagError(
                f'bag {self._path}: topic name {name!r} is not fully qualified; pass it as '
                "resolved by the node, e.g. '/mooring_line/fairlead/tension'")
        canonical = schema.canonical_type_name(type_name)
        known = self._topics.get(name)
        if known is not None:
            if known != canonical:
                raise BagError(
                    f'bag {self._path}: topic {name} is recorded as {known} already, '
                    f'cannot add it again as {canonical}; one type per topic')
            return
        definition, type_hash = self._describe(canonical)
        record = meta.TopicRecord(name, canonical, self._qos_yaml(qos), type_hash)
        with self._lock:
            # Queued for the thread before write() can accept a message on the topic.
            self._pending.append((record, definition))
            self._topics[name] = canonical

    def _describe(self, type_name: str) -> Tuple[str, str]:
        """Return the MCAP schema text and the type hash of a canonical type name."""
        return schema.message_definition(type_name), schema.type_hash(type_name)

    def _qos_yaml(self, qos: Any) -> str:
        """Return the offered_qos_profiles string of the qos given to add_topic()."""
        return meta.qos_profiles_yaml(qos)

    def topic_type(self, topic: str) -> str:
        """
        Return the type a topic was added with.

        :raises BagError: the topic was not added.
        """
        known = self._topics.get(topic)
        if known is None:
            raise BagError(
                f'bag {self._path}: topic {topic!r} was not added; call add_topic() first')
        return known

    def write(
        self,
        topic: str,
        message: Any,
        log_time_ns: int,
        publish_time_ns: Optional[int] = None,
    ) -> bool:
        """
        Queue one message for recording; never blocks on the disk.

        :param topic: A topic registered with add_topic().
        :param message: The message's CDR bytes (bytes, bytearray or memoryview), e.g. from
            cdr.py or as received.
        :param log_time_ns: Receive/record time [ns] (MCAP log_time).
        :param publish_time_ns: Send time [ns] (MCAP publish_time); log_time_ns if None.

        :returns: True if queued; False if dropped (queue full, recording stopped by an error
            or the bag closed), which the `dropped` count records.

        :raises BagError: the topic was not added or the message is not bytes.
        """
        type_name = self.topic_type(topic)
        if not isinstance(message, (bytes, bytearray, memoryview)):
            raise BagError(
                f'bag {self._path}: topic {topic} records {type_name} as CDR bytes, got '
                f'{type(message).__module__}.{type(message).__name__}; encode it with '
                'rope_sim_ros.bag.cdr, or record message objects with '
                'rope_sim_ros.ros2bag.RosBagWriter')
        data = bytes(message)
        if self._closed or self._error is not None:
            self._count_dropped()
            return False
        log_time_ns = int(log_time_ns)
        publish_time_ns = log_time_ns if publish_time_ns is None else int(publish_time_ns)
        try:
            self._queue.put_nowait((topic, data, log_time_ns, publish_time_ns))
        except queue.Full:
            self._count_dropped()
            return False
        return True

    def close(self) -> None:
        """
        Write what is queued, complete the MCAP file and write metadata.yaml.

        Waits for the writer thread. Calling it again has no effect.

        :raises BagError: recording stopped on an error (the bag is then left as a killed
            recording would be: recover() makes it whole up to its last chunk).
        """
        if self._closed:
            return
        self._closed = True
        # Blocks only while the queue is full, i.e. while the thread is still draining it.
        self._queue.put(_STOP)
        self._thread.join()
        if self._error is None:
            try:
                self._register_pending()
                metadata = storage.metadata_for([self._file], self._custom_data)
                self._file.close(metadata)
                storage.write_metadata_yaml(self._path, metadata)
            except (BagError, OSError, ValueError) as exc:
                self._fail(exc)
        else:
            self._file.abort()
        if self._error is not None:
            raise self._error

    def __enter__(self) -> 'BagWriter':
        """Return the open writer."""
        return self

    def __exit__(self, exc_type: Any, exc: Any, traceback: Any) -> None:
        """Close; an error of close() does not hide an exception already on its way."""
        try:
            self.close()
        except BagError as error:
            if exc_type is None:
                raise
            self._log.error('%s', error)

    @property
    def _log(self) -> logging.Logger:
        # The subclass's module: its owner quiets the logger of the class it uses.
        return logging.getLogger(type(self).__module__)

    def _count_dropped(self, count: int = 1) -> None:
        with self._lock:
            self._dropped += count

    def _fail(self, exc: BaseException) -> None:
        if self._error is None:
            detail = exc.strerror if isinstance(exc, OSError) and exc.strerror else exc
            self._error = BagError(
                f'recording to {self._file.path} stopped: {detail}; later messages are '
                'dropped, the file is readable up to its last complete chunk '
                '(rope_sim_ros.bag.recover() makes it a complete bag)')
            self._error.__cause__ = exc
            self._log.error('%s', self._error)

    def _register_pending(self) -> None:
        with self._lock:
            pending, self._pending = self._pending, []
        for record, definition in pending:
            self._file.add_topic(record, definition)

    def _run(self) -> None:
        # Monotonic time the chunk in progress got its first message, None if it has none.
        chunk_start: Optional[float] = None
        stop = False
        while not stop:
            timeout = None
            if chunk_start is not None:
                timeout = max(0.0, chunk_start + self._flush_interval - time.monotonic())
            try:
                batch = [self._queue.get(timeout=timeout)]
            except queue.Empty:
                batch = []
            while batch and batch[-1] is not _STOP and len(batch) < self._BATCH:
                try:
                    batch.append(self._queue.get_nowait())
                except queue.Empty:
                    break
            if batch and batch[-1] is _STOP:
                stop = True
                batch.pop()
            if self._error is not None:
                self._count_dropped(len(batch))
                continue
            try:
                self._register_pending()
                for item in batch:
                    self._file.write(*item)
                now = time.monotonic()
                if batch and chunk_start is None:
                    chunk_start = now
                if chunk_start is not None and now - chunk_start >= self._flush_interval:
                    self._file.flush_chunk()
                    chunk_start = None
                else:
                    # Chunks the size limit closed reach the OS now, not at the next flush.
                    self._file.flush_stream()
            except Exception as exc:  # noqa: B902 - a failure stops recording, not the caller
                self._fail(exc)
                # The batch may be partly written; report it whole as lost.
                self._count_dropped(len(batch))
