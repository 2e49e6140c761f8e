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
Synchronous MCAP storage in rosbag2 Jazzy's layout (no threads; see writer.py for those).

What rosbag2_storage_mcap (mcap_storage.cpp) writes and we write too: header profile
'ros2'; one schema per type, encoding 'ros2msg', with the full .msg text; one channel per
topic, message encoding 'cdr', metadata 'offered_qos_profiles' (YAML string) and
'topic_type_hash' (RIHS01); chunked, uncompressed messages; at close a metadata record
'rosbag2' whose 'serialized_metadata' is metadata.yaml's map, then the summary.
"""

import importlib.metadata
import os
from typing import Any, Dict, Mapping, Optional, Sequence, Union

from mcap.data_stream import RecordBuilder
from mcap.writer import CompressionType
from mcap.writer import LIBRARY_IDENTIFIER
from mcap.writer import Writer

from . import metadata as meta
from .errors import BagError
from .schema import SCHEMA_ENCODING

#: MCAP profile of ROS 2 bags.
PROFILE = 'ros2'
#: Name and key of the MCAP metadata record rosbag2 reads its metadata from.
METADATA_RECORD = 'rosbag2'
# custom_data again, at the start of the file: a killed recording has no metadata.yaml, and
# recover() takes it from here
CUSTOM_DATA_RECORD = 'rope_sim_ros.custom_data'
METADATA_RECORD_KEY = 'serialized_metadata'
#: Channel metadata keys of rosbag2_storage_mcap.
QOS_KEY = 'offered_qos_profiles'
TYPE_HASH_KEY = 'topic_type_hash'
#: Bytes of messages per chunk: small, so that a kill loses little.
DEFAULT_CHUNK_SIZE = 256 * 1024


def _library() -> str:
    try:
        version = importlib.metadata.version('rope_sim_ros')
    except importlib.metadata.PackageNotFoundError:
        version = 'source'
    return f'rope_sim_ros {version} bag writer; {LIBRARY_IDENTIFIER}'


#: MCAP header library string: who wrote the file, for whoever debugs it.
LIBRARY = _library()


def create_bag_directory(path: Union[str, 'os.PathLike[str]']) -> str:
    """
    Create the directory of a new bag, refusing to reuse one that holds anything.

    :param path: The bag directory to create (its parents are created too).

    :returns: The normalised path of the empty directory.

    :raises BagError: path exists and is not an empty directory, or it cannot be created.
    """
    path = os.path.normpath(os.fspath(path))
    if os.path.lexists(path):
        if not os.path.isdir(path):
            raise BagError(
                f'bag path {path} exists already and is not a directory, not overwriting; '
                'choose a new path')
        if os.listdir(path):
            raise BagError(
                f'bag directory {path} exists already and is not empty, not overwriting; '
                'choose a new path')
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as exc:
        raise BagError(
            f'cannot create bag directory {path}: {exc.strerror or exc}; '
            'choose a path in a writable directory') from None
    return path


def write_metadata_yaml(directory: str, metadata: Mapping[str, Any]) -> str:
    """
    Write metadata.yaml into a bag directory, atomically.

    :param directory: The bag directory.
    :param metadata: The metadata map (without the top-level key).

    :returns: The path of the metadata file.

    :raises BagError: the file cannot be written.
    """
    path = os.path.join(directory, meta.METADATA_FILE)
    temporary = path + '.tmp'
    try:
        with open(temporary, 'w', encoding='utf-8') as stream:
            stream.write(meta.metadata_yaml(metadata))
            stream.flush()
            os.fsync(stream.fileno())
        # Readers never see half a metadata.yaml: either none or the whole one.
        os.replace(temporary, path)
    except OSError as exc:
        raise BagError(f'cannot write {path}: {exc.strerror or exc}') from None
    return path


class _PackedChunkIndex:
    """
    A chunk's index record, serialised once: what the summary writes at the end, 6 x smaller.

    The mcap Writer keeps every chunk's ChunkIndex for the summary, each with a dict of its
    channels' message index offsets: 5 kB a chunk for the mooring node's 72 topics, three
    chunks a second, 1 MB a minute of a recording that runs for days.
    """

    __slots__ = ('_record',)

    def __init__(self, index) -> None:
        builder = RecordBuilder()
        index.write(builder)
        self._record = builder.end()

    def write(self, stream: RecordBuilder) -> None:
        stream.write(self._record)


class McapFile:
    """
    One MCAP storage file of a bag, written synchronously.

    :ivar path: The .mcap file.
    :ivar record: Its FileRecord (message count and time range so far).
    :ivar topics: The TopicRecords by topic name, with their message counts so far.
    """

    def __init__(self, path: str, *, chunk_size: int, name: Optional[str] = None,
                 custom_data: Optional[Mapping[str, str]] = None) -> None:
        """
        Create the file and write the MCAP header.

        :param path: The .mcap file to create; it must not exist.
        :param chunk_size: Bytes of messages after which a chunk is written out.
        :param name: The file's name in the bag's metadata, if it is written under another
            name first (default: the base name of path).
        :param custom_data: The bag's custom_data, written at once as a metadata record.

        :raises BagError: the file exists or cannot be created.
        """
        self.path = path
        self.record = meta.FileRecord(name or os.path.basename(path))
        self.topics: Dict[str, meta.TopicRecord] = {}
        self._schemas: Dict[str, int] = {}
        self._channels: Dict[str, int] = {}
        self._packed = 0  # chunk indices packed so far (_pack_chunk_indices)
        try:
            # 'x': never truncate a file someone else wrote.
            self._stream = open(path, 'xb')
        except OSError as exc:
            raise BagError(
                f'cannot create {path}: {exc.strerror or exc}; '
                'choose a new path in a writable directory') from None
        # rosbag2's defaults: chunked, uncompressed. Chunk CRCs are kept so that a reader
        # can tell a damaged chunk from a good one when it recovers a killed recording.
        self._writer = Writer(
            self._stream, chunk_size=chunk_size, compression=CompressionType.NONE)
        self._writer.start(profile=PROFILE, library=LIBRARY)
        if custom_data:
            self._writer.add_metadata(CUSTOM_DATA_RECORD, dict(custom_data))
        self._stream.flush()

    def add_topic(self, topic: meta.TopicRecord, definition: str) -> None:
        """
        Register a topic: its type's schema (once per type) and its channel.

        :param topic: Name, type, QoS string and type hash (its count is ignored).
        :param definition: The full ros2msg text of the type.

        :raises BagError: the topic is registered already with another type.
        """
        known = self.topics.get(topic.name)
        if known is not None:
            if known.type_name != topic.type_name:
                raise BagError(
                    f'{self.path}: topic {topic.name} is recorded as {known.type_name} '
                    f'already, cannot add it again as {topic.type_name}; one type per topic')
            return
        schema_id = self._schemas.get(topic.type_name)
        if schema_id is None:
            schema_id = self._writer.register_schema(
                topic.type_name, SCHEMA_ENCODING, definition.encode('utf-8'))
            self._schemas[topic.type_name] = schema_id
        self._channels[topic.name] = self._writer.register_channel(
            topic.name, meta.SERIALIZATION_FORMAT, schema_id,
            {QOS_KEY: topic.offered_qos_profiles, TYPE_HASH_KEY: topic.type_hash})
        self.topics[topic.name] = meta.TopicRecord(
            topic.name, topic.type_name, topic.offered_qos_profiles, topic.type_hash)

    def write(
        self, topic: str, data: bytes, log_time_ns: int, publish_time_ns: int,
        sequence: int = 0,
    ) -> None:
        """
        Append one serialized message to the current chunk.

        :param topic: A registered topic.
        :param data: The CDR bytes.
        :param log_time_ns: Receive/record time [ns].
        :param publish_time_ns: Send time [ns].
        :param sequence: Publisher sequence number, 0 if unknown.
        """
        self._writer.add_message(
            self._channels[topic], log_time_ns, data, publish_time_ns, sequence)
        self.topics[topic].message_count += 1
        self.record.add(log_time_ns)

    def flush_chunk(self) -> None:
        """
        Write out the chunk in progress and hand everything to the operating system.

        After this a kill of the process loses nothing written so far.
        """
        flush = getattr(self._writer, 'flush', None)
        if flush is not None:
            flush()
        else:  # mcap releases without Writer.flush()
            self._writer._Writer__finalize_chunk()
            self._stream.flush()
        self._pack_chunk_indices()

    def flush_stream(self) -> None:
        """Hand chunks already written out to the operating system."""
        self._stream.flush()
        self._pack_chunk_indices()

    def _pack_chunk_indices(self) -> None:
        """Keep the chunk indices written since the last call as bytes (_PackedChunkIndex)."""
        indices = getattr(self._writer, '_Writer__chunk_indices', None)
        if indices is None:  # another mcap release: left as it keeps them
            return
        for k in range(self._packed, len(indices)):
            indices[k] = _PackedChunkIndex(indices[k])
        self._packed = len(indices)

    def close(self, metadata: Mapping[str, Any]) -> None:
        """
        Write the rosbag2 metadata record, the summary and the footer; close the file.

        :param metadata: The bag's metadata map for the 'rosbag2' record.

        :raises BagError: the file cannot be completed.
        """
        try:
            self.flush_chunk()
            self._writer.add_metadata(
                METADATA_RECORD, {METADATA_RECORD_KEY: meta.serialized_metadata(metadata)})
            self._writer.finish()
            self._stream.flush()
            os.fsync(self._stream.fileno())
            self._stream.close()
        except OSError as exc:
            self.abort()
            raise BagError(f'cannot complete {self.path}: {exc.strerror or exc}') from None

    def abort(self) -> None:
        """Close the file as it is, without summary: readable up to its last chunk."""
        try:
            self._stream.close()
        except OSError:
            # Whatever the OS refused to take is lost either way.
            pass


def new_file_name(directory: str, index: int = 0) -> str:
    """Return rosbag2's name for storage file number index of a bag directory."""
    return os.path.join(directory, f'{os.path.basename(directory)}_{index}.mcap')


def metadata_for(
    files: Sequence[McapFile], custom_data: Optional[Mapping[str, str]] = None,
) -> Dict[str, Any]:
    """
    Build the metadata map of a bag from its storage files.

    :param files: The files in order.
    :param custom_data: Free key/value strings recorded with the bag.

    :returns: The metadata map (without the top-level key).
    """
    topics: Dict[str, meta.TopicRecord] = {}
    for storage in files:
        for record in storage.topics.values():
            total = topics.setdefault(record.name, meta.TopicRecord(
                record.name, record.type_name, record.offered_qos_profiles, record.type_hash))
            total.message_count += record.message_count
    return meta.bag_metadata([storage.record for storage in files], topics.values(), custom_data)
