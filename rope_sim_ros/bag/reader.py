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
Read rosbag2 MCAP bags, complete ones and ones cut short by a killed recorder.

A complete file (footer and summary present) is read through its index in log-time
order. A file without footer, as SIGKILL or a power cut leaves it, is read front to
back with mcap's non-seeking stream reader, which stops at the first chunk that is not
whole: every chunk written out before the kill is returned, nothing half-written.
"""

import dataclasses
import glob
import os
import struct
from typing import Any, Dict, Iterable, Iterator, List, NamedTuple, Optional, Tuple, Union

from mcap.exceptions import McapError
from mcap.reader import SeekingReader
from mcap.records import Channel, Chunk, Message, Metadata, Schema
from mcap.stream_reader import breakup_chunk, StreamReader

from . import metadata as meta
from . import storage
from .errors import BagError

# First and last 8 bytes of a complete MCAP file.
_MAGIC = b'\x89MCAP0\r\n'
# What a file cut short (or garbled at its end) raises while it is streamed.
_TRUNCATION = (McapError, EOFError, struct.error, ValueError, UnicodeDecodeError)

PathLike = Union[str, 'os.PathLike[str]']


class BagMessage(NamedTuple):
    """
    One recorded message.

    :ivar topic: Topic name.
    :ivar type_name: Message type, 'pkg/msg/Type'.
    :ivar log_time_ns: Receive/record time [ns].
    :ivar publish_time_ns: Send time [ns].
    :ivar data: The serialized (CDR) message: bag.cdr decodes the types we record,
        rope_sim_ros.ros2bag.deserialize() makes any type an rclpy message object.
    """

    topic: str
    type_name: str
    log_time_ns: int
    publish_time_ns: int
    data: bytes


@dataclasses.dataclass(frozen=True)
class TopicInfo:
    """
    One topic of a bag.

    :ivar name: Topic name.
    :ivar type_name: Message type, 'pkg/msg/Type'.
    :ivar message_count: Messages readable on the topic.
    :ivar offered_qos_profiles: The QoS profiles as stored in the channel (YAML string).
    :ivar type_hash: RIHS01 type description hash ('' if the bag has none).
    """

    name: str
    type_name: str
    message_count: int
    offered_qos_profiles: str
    type_hash: str


@dataclasses.dataclass(frozen=True)
class BagInfo:
    """
    What a bag holds.

    :ivar path: The bag directory or file as given.
    :ivar files: Its MCAP files.
    :ivar topics: TopicInfo by topic name.
    :ivar message_count: Messages readable in all files.
    :ivar start_ns: Earliest log time [ns] (0 for an empty bag).
    :ivar end_ns: Latest log time [ns] (0 for an empty bag).
    :ivar duration_ns: end_ns - start_ns.
    :ivar complete: Every file has its summary; False for a recording cut short.
    """

    path: str
    files: Tuple[str, ...]
    topics: Dict[str, TopicInfo]
    message_count: int
    start_ns: int
    end_ns: int
    duration_ns: int
    complete: bool


def bag_files(path: PathLike) -> List[str]:
    """
    Return the MCAP files of a bag directory (or the file itself).

    :param path: A bag directory, or one .mcap file.

    :returns: The files in recording order: as metadata.yaml lists them, else sorted by
        name (a bag killed before close has no metadata.yaml yet).

    :raises BagError: path does not exist, is not an MCAP bag, or lists missing files.
    """
    path = os.fspath(path)
    if os.path.isfile(path):
        if not path.endswith('.mcap'):
            raise BagError(f'{path} is not a bag: expected a bag directory or a .mcap file')
        return [path]
    if not os.path.isdir(path):
        raise BagError(f'bag {path} does not exist; expected a bag directory or a .mcap file')
    metadata_path = os.path.join(path, meta.METADATA_FILE)
    if not os.path.exists(metadata_path):
        files = sorted(glob.glob(os.path.join(glob.escape(path), '*.mcap')))
        if not files:
            raise BagError(f'{path} has neither {meta.METADATA_FILE} nor a .mcap file; '
                           'not a bag')
        return files
    metadata = meta.load_metadata(metadata_path)
    identifier = metadata.get('storage_identifier')
    if identifier != meta.STORAGE_IDENTIFIER:
        raise BagError(f'bag {path} is stored as {identifier!r}; only mcap bags are supported')
    files = []
    for relative in metadata.get('relative_file_paths') or []:
        # Before Humble the paths started with the bag directory's own name.
        candidates = (os.path.join(path, relative),
                      os.path.join(path, os.path.basename(relative)))
        found = next((name for name in candidates if os.path.isfile(name)), None)
        if found is None:
            raise BagError(f'{metadata_path} lists {relative}, which is not in {path}')
        files.append(found)
    return files


def _is_complete(stream: Any) -> bool:
    # Only a file that ends in the magic after a footer has a summary to trust.
    stream.seek(0, os.SEEK_END)
    if stream.tell() < 2 * len(_MAGIC):
        return False
    stream.seek(-len(_MAGIC), os.SEEK_END)
    complete = stream.read(len(_MAGIC)) == _MAGIC
    stream.seek(0)
    return complete


def _summary(stream: Any) -> Any:
    try:
        return SeekingReader(stream).get_summary() if _is_complete(stream) else None
    except _TRUNCATION:
        return None
    finally:
        stream.seek(0)


def stream_records(stream: Any) -> Iterator[Union[Schema, Channel, Message, Metadata]]:
    """
    Yield the schemas, channels, messages and metadata records of an MCAP file in order.

    Reading stops quietly at the end of the last whole chunk: a missing footer or a
    chunk cut off or damaged by a kill ends the records, it is not an error.

    :param stream: The file, open for binary reading at its start.

    :yields: Schema, Channel, Message and Metadata records.
    """
    reader = StreamReader(stream, emit_chunks=True, record_size_limit=2**31)
    try:
        for record in reader.records:
            if isinstance(record, Chunk):
                # A chunk is whole or not at all: its records are yielded only after
                # its length and CRC are checked.
                for inner in breakup_chunk(record, validate_crc=True):
                    if isinstance(inner, (Schema, Channel, Message)):
                        yield inner
            elif isinstance(record, (Schema, Channel, Message, Metadata)):
                yield record
    except _TRUNCATION:
        return


def open_file(path: str) -> Any:
    """
    Open an MCAP file for reading.

    :param path: The file.

    :returns: The binary stream.

    :raises BagError: the file cannot be opened.
    """
    try:
        return open(path, 'rb')
    except OSError as exc:
        raise BagError(f'cannot read {path}: {exc.strerror or exc}') from None


def _read_file(path: str, topics: Optional[frozenset]) -> Iterator[BagMessage]:
    with open_file(path) as stream:
        if _summary(stream) is not None:
            reader = SeekingReader(stream)
            for schema, channel, message in reader.iter_messages(
                    topics=None if topics is None else sorted(topics), log_time_order=True):
                yield BagMessage(channel.topic, schema.name if schema else '',
                                 message.log_time, message.publish_time, bytes(message.data))
            return
        schemas: Dict[int, Schema] = {}
        channels: Dict[int, Channel] = {}
        messages = []
        for record in stream_records(stream):
            if isinstance(record, Schema):
                schemas[record.id] = record
            elif isinstance(record, Channel):
                channels[record.id] = record
            elif isinstance(record, Message):
                channel = channels.get(record.channel_id)
                if channel is None or (topics is not None and channel.topic not in topics):
                    continue
                schema = schemas.get(channel.schema_id)
                messages.append(BagMessage(
                    channel.topic, schema.name if schema else '', record.log_time,
                    record.publish_time, bytes(record.data)))
    # No index to merge by: sort what was read (stable, so equal times keep file order).
    messages.sort(key=lambda message: message.log_time_ns)
    yield from messages


def read_messages(
    path: PathLike, topics: Optional[Iterable[str]] = None,
) -> Iterator[BagMessage]:
    """
    Yield the messages of a bag in log-time order.

    Works on complete bags and on bags whose recorder was killed: then every chunk
    written out before the kill is read, and the cut-off rest is ignored.

    :param path: A bag directory, or one .mcap file.
    :param topics: Topic names to read; None for all.

    :yields: BagMessage records.

    :raises BagError: path is not a readable MCAP bag.
    """
    wanted = None if topics is None else frozenset(topics)
    for name in bag_files(path):
        yield from _read_file(name, wanted)


def _file_info(path: str) -> Tuple[Dict[str, TopicInfo], int, int, int, bool]:
    with open_file(path) as stream:
        summary = _summary(stream)
        if summary is not None:
            statistics = summary.statistics
            counts = dict(statistics.channel_message_counts) if statistics else {}
            channels = summary.channels
            schemas = summary.schemas
            total = sum(counts.values())
            start = statistics.message_start_time if statistics and total else 0
            end = statistics.message_end_time if statistics and total else 0
            complete = True
        else:
            counts, channels, schemas = {}, {}, {}
            total, start, end = 0, 0, 0
            for record in stream_records(stream):
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message) and record.channel_id in channels:
                    counts[record.channel_id] = counts.get(record.channel_id, 0) + 1
                    start = record.log_time if not total else min(start, record.log_time)
                    end = max(end, record.log_time)
                    total += 1
            complete = False
    topics = {}
    for channel_id, channel in channels.items():
        schema = schemas.get(channel.schema_id)
        topics[channel.topic] = TopicInfo(
            channel.topic, schema.name if schema else '', counts.get(channel_id, 0),
            channel.metadata.get(storage.QOS_KEY, ''),
            channel.metadata.get(storage.TYPE_HASH_KEY, ''))
    return topics, total, start, end, complete


def bag_info(path: PathLike) -> BagInfo:
    """
    Summarise a bag: its topics, types, message counts and time range.

    Counts are of the messages actually readable, so for a recording cut short they
    are what read_messages() will yield.

    :param path: A bag directory, or one .mcap file.

    :returns: The BagInfo.

    :raises BagError: path is not a readable MCAP bag.
    """
    files = bag_files(path)
    topics: Dict[str, TopicInfo] = {}
    total, start, end, complete = 0, 0, 0, True
    for name in files:
        file_topics, count, file_start, file_end, file_complete = _file_info(name)
        for topic in file_topics.values():
            known = topics.get(topic.name)
            topics[topic.name] = topic if known is None else dataclasses.replace(
                known, message_count=known.message_count + topic.message_count)
        if count:
            start = file_start if not total else min(start, file_start)
            end = max(end, file_end)
            total += count
        complete = complete and file_complete
    return BagInfo(os.fspath(path), tuple(files), topics, total, start, end, end - start,
                   complete)
