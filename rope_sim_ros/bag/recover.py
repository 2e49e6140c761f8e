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
Make a recording cut short by a kill (no summary, no metadata.yaml) a complete bag.

Everything readable is copied as it was written (schemas, QoS and type hashes of the
channels, log and publish times, sequence numbers) into a new MCAP file with summary
and rosbag2 metadata record, and metadata.yaml is written beside it.
"""

import os
from typing import Dict, List, Optional

from mcap.records import Channel, Metadata, Schema

from . import metadata as meta
from . import storage
from .errors import BagError
from .reader import bag_files, open_file, PathLike, stream_records

_SUFFIX = '.recovering'


def _custom_data(source: str) -> Optional[Dict[str, str]]:
    """Return the custom_data the recorder wrote at the start of the file, if any."""
    with open_file(source) as stream:
        for record in stream_records(stream):
            if isinstance(record, Metadata) and record.name == storage.CUSTOM_DATA_RECORD:
                return dict(record.metadata)
    return None


def _copy(source: str, target: storage.McapFile) -> None:
    schemas: Dict[int, Schema] = {}
    topics: Dict[int, str] = {}
    with open_file(source) as stream:
        for record in stream_records(stream):
            if isinstance(record, Metadata):
                continue
            if isinstance(record, Schema):
                schemas[record.id] = record
            elif isinstance(record, Channel):
                schema = schemas.get(record.schema_id)
                if schema is None:
                    # A channel without schema cannot be read by rosbag2 either.
                    continue
                target.add_topic(meta.TopicRecord(
                    record.topic, schema.name,
                    record.metadata.get(storage.QOS_KEY, ''),
                    record.metadata.get(storage.TYPE_HASH_KEY, '')),
                    schema.data.decode('utf-8'))
                topics[record.id] = record.topic
            elif record.channel_id in topics:
                target.write(topics[record.channel_id], bytes(record.data), record.log_time,
                             record.publish_time, record.sequence)


def recover(path: PathLike, output: Optional[PathLike] = None) -> int:
    """
    Rewrite the readable part of a bag as a complete bag.

    :param path: The bag directory (or its .mcap file) of the cut-short recording.
    :param output: A new bag directory to write; None repairs path in place (each .mcap
        file is replaced only once its complete copy is on disk).

    :returns: The number of messages in the recovered bag.

    :raises BagError: path is not an MCAP bag, output exists and is not empty, or a file
        cannot be written.
    """
    sources = bag_files(path)
    if output is None:
        directory = os.fspath(path)
        if os.path.isfile(directory):
            directory = os.path.dirname(directory) or '.'
        targets = [source + _SUFFIX for source in sources]
        for target in targets:
            # Left behind by a recovery that was itself interrupted.
            if os.path.exists(target):
                os.remove(target)
    else:
        directory = storage.create_bag_directory(output)
        targets = [storage.new_file_name(directory, index) for index in range(len(sources))]
    files: List[storage.McapFile] = []
    custom_data = _custom_data(sources[0]) if sources else None
    try:
        for source, target in zip(sources, targets):
            files.append(storage.McapFile(
                target, chunk_size=storage.DEFAULT_CHUNK_SIZE,
                name=os.path.basename(target if output is not None else source),
                custom_data=custom_data))
            _copy(source, files[-1])
        metadata = storage.metadata_for(files, custom_data)
        for storage_file in files:
            storage_file.close(metadata)
    except BaseException:
        for storage_file in files:
            storage_file.abort()
        if output is None:
            for target in targets:
                if os.path.exists(target):
                    os.remove(target)
        raise
    if output is None:
        for source, target in zip(sources, targets):
            try:
                os.replace(target, source)
            except OSError as exc:
                raise BagError(
                    f'cannot replace {source} by its recovered copy {target}: '
                    f'{exc.strerror or exc}') from None
    storage.write_metadata_yaml(directory, metadata)
    return metadata['message_count']
