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
rosbag2 Jazzy metadata: metadata.yaml (version 9) and the QoS profiles of a topic.

The layout follows rosbag2_storage's yaml.hpp and qos.cpp at Jazzy: the keys in the
order rosbag2 encodes them, QoS policies as strings ('keep_last', 'reliable', ...) since
version 9, offered_qos_profiles a YAML list in metadata.yaml and the same list dumped to a
string in the MCAP channel metadata.
"""

import dataclasses
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import yaml

from .errors import BagError

#: metadata.yaml version written by rosbag2 in ROS 2 Jazzy.
METADATA_VERSION = 9
#: Name of the metadata file inside a bag directory.
METADATA_FILE = 'metadata.yaml'
#: Top-level key of metadata.yaml.
TOP_KEY = 'rosbag2_bagfile_information'
#: The layout written here is Jazzy's, whatever ROS_DISTRO the process happens to have.
ROS_DISTRO = 'jazzy'
STORAGE_IDENTIFIER = 'mcap'
SERIALIZATION_FORMAT = 'cdr'
#: RMW_DURATION_INFINITE, what DDS reports for a policy duration left unspecified.
INFINITE_NS = 2**63 - 1
#: rosbag2 starts from time_point::max() and keeps it when no message was written.
EMPTY_BAG_START_NS = 2**63 - 1


@dataclasses.dataclass
class TopicRecord:
    """
    One topic of a bag as metadata.yaml lists it.

    :ivar name: Topic name, e.g. '/fairlead/pose'.
    :ivar type_name: Message type, e.g. 'geometry_msgs/msg/PoseStamped'.
    :ivar offered_qos_profiles: The profiles as the YAML string stored in MCAP channel metadata.
    :ivar type_hash: RIHS01 type description hash.
    :ivar message_count: Messages written on the topic.
    """

    name: str
    type_name: str
    offered_qos_profiles: str
    type_hash: str
    message_count: int = 0


@dataclasses.dataclass
class FileRecord:
    """
    One storage file of a bag.

    :ivar path: File name relative to the bag directory.
    :ivar message_count: Messages in the file.
    :ivar start_ns: Earliest log time [ns], EMPTY_BAG_START_NS if there is none.
    :ivar end_ns: Latest log time [ns], 0 if there is none.
    """

    path: str
    message_count: int = 0
    start_ns: int = EMPTY_BAG_START_NS
    end_ns: int = 0

    def add(self, log_time_ns: int) -> None:
        """Account for one message logged at log_time_ns."""
        self.message_count += 1
        self.start_ns = min(self.start_ns, log_time_ns)
        self.end_ns = max(self.end_ns, log_time_ns)

    @property
    def duration_ns(self) -> int:
        """Latest minus earliest log time, 0 for an empty file."""
        return max(0, self.end_ns - self.start_ns) if self.message_count else 0


def duration_dict(nanoseconds: int) -> Dict[str, int]:
    """Return a duration [ns] as rosbag2 writes a QoS duration (rmw_time_t: sec, nsec)."""
    return {'sec': nanoseconds // 10**9, 'nsec': nanoseconds % 10**9}


#: The keys of one offered QoS profile in rosbag2's version 9 form, in rosbag2's order.
QOS_KEYS = (
    'history', 'depth', 'reliability', 'durability', 'deadline', 'lifespan', 'liveliness',
    'liveliness_lease_duration', 'avoid_ros_namespace_conventions')

#: rclpy's default publisher profile (keep_last 10, reliable, volatile) as `ros2 bag record`
#: stores it: the durations it leaves unspecified are infinite, liveliness automatic.
DEFAULT_QOS: Dict[str, Any] = {
    'history': 'keep_last',
    'depth': 10,
    'reliability': 'reliable',
    'durability': 'volatile',
    'deadline': duration_dict(INFINITE_NS),
    'lifespan': duration_dict(INFINITE_NS),
    'liveliness': 'automatic',
    'liveliness_lease_duration': duration_dict(INFINITE_NS),
    'avoid_ros_namespace_conventions': False,
}

#: None (DEFAULT_QOS), one profile or one per publisher, each a dict with QOS_KEYS.
QosSpec = Union[None, Mapping[str, Any], Sequence[Mapping[str, Any]]]


def qos_profiles_yaml(qos: QosSpec) -> str:
    """
    Return the offered_qos_profiles string of MCAP channel metadata.

    :param qos: One profile, several (one per publisher) or None for DEFAULT_QOS; each a
        dict with the keys QOS_KEYS (rope_sim_ros.ros2bag.qos_to_dict makes one of an rclpy
        QoSProfile).

    :returns: The YAML list as rosbag2's serialize_rclcpp_qos_vector dumps it.

    :raises BagError: qos is not such a dict or a sequence of them.
    """
    if qos is None:
        profiles = [DEFAULT_QOS]
    elif isinstance(qos, Mapping):
        profiles = [qos]
    elif isinstance(qos, Sequence) and not isinstance(qos, (str, bytes)):
        profiles = list(qos)
    else:
        profiles = [qos]
    if not all(isinstance(profile, Mapping) and set(profile) == set(QOS_KEYS)
               for profile in profiles):
        raise BagError(
            f'offered QoS {qos!r} is not understood: pass a dict with the keys '
            f'{", ".join(QOS_KEYS)} (rosbag2\'s form), a list of them, or None for the '
            'default publisher profile; rope_sim_ros.ros2bag.RosBagWriter takes rclpy '
            'QoSProfile objects')
    return _dump([{key: profile[key] for key in QOS_KEYS} for profile in profiles]).rstrip('\n')


def parse_qos_profiles(text: str) -> List[Dict[str, Any]]:
    """
    Parse an offered_qos_profiles string back into its list.

    :param text: The channel metadata value; empty for a topic recorded without QoS.

    :returns: The list of profile dicts (empty when text is empty).

    :raises BagError: text is not a YAML list.
    """
    if not text.strip():
        return []
    try:
        profiles = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise BagError(f'offered_qos_profiles is not YAML: {exc}') from None
    if not isinstance(profiles, list):
        raise BagError(f'offered_qos_profiles is not a YAML list: {text!r}')
    return profiles


def bag_metadata(
    files: Sequence[FileRecord],
    topics: Iterable[TopicRecord],
    custom_data: Optional[Mapping[str, str]] = None,
) -> Dict[str, Any]:
    """
    Build the metadata map of a bag (metadata.yaml without its top-level key).

    :param files: The storage files in order, with their statistics.
    :param topics: The topics with their message counts.
    :param custom_data: Free key/value strings recorded with the bag.

    :returns: The map with rosbag2 Jazzy's keys in rosbag2's order.
    """
    count = sum(record.message_count for record in files)
    filled = [record for record in files if record.message_count]
    start = min((record.start_ns for record in filled), default=EMPTY_BAG_START_NS)
    end = max((record.end_ns for record in filled), default=start)
    return {
        'version': METADATA_VERSION,
        'storage_identifier': STORAGE_IDENTIFIER,
        'duration': {'nanoseconds': max(0, end - start)},
        'starting_time': {'nanoseconds_since_epoch': start},
        'message_count': count,
        'topics_with_message_count': [
            {
                'topic_metadata': {
                    'name': topic.name,
                    'type': topic.type_name,
                    'serialization_format': SERIALIZATION_FORMAT,
                    'offered_qos_profiles': parse_qos_profiles(topic.offered_qos_profiles),
                    'type_description_hash': topic.type_hash,
                },
                'message_count': topic.message_count,
            }
            for topic in topics
        ],
        'compression_format': '',
        'compression_mode': '',
        'relative_file_paths': [record.path for record in files],
        'files': [
            {
                'path': record.path,
                'starting_time': {'nanoseconds_since_epoch': record.start_ns},
                'duration': {'nanoseconds': record.duration_ns},
                'message_count': record.message_count,
            }
            for record in files
        ],
        # yaml-cpp writes an empty map as null.
        'custom_data': dict(custom_data) if custom_data else None,
        'ros_distro': ROS_DISTRO,
    }


class _Dumper(yaml.SafeDumper):
    """Block-style YAML laid out like yaml-cpp: sequences indented under their key."""

    def increase_indent(self, flow: bool = False, indentless: bool = False) -> None:
        super().increase_indent(flow, False)


def _represent_none(dumper: yaml.SafeDumper, _: None) -> yaml.Node:
    return dumper.represent_scalar('tag:yaml.org,2002:null', '~')


_Dumper.add_representer(type(None), _represent_none)


def _dump(data: Any) -> str:
    return yaml.dump(
        data, Dumper=_Dumper, default_flow_style=False, sort_keys=False, width=2**31,
        allow_unicode=True)


def metadata_yaml(metadata: Mapping[str, Any]) -> str:
    """Return the text of metadata.yaml for a metadata map."""
    return _dump({TOP_KEY: dict(metadata)})


def serialized_metadata(metadata: Mapping[str, Any]) -> str:
    """Return the 'serialized_metadata' value of the MCAP 'rosbag2' metadata record."""
    return _dump(dict(metadata))


def load_metadata(path: str) -> Dict[str, Any]:
    """
    Read a metadata.yaml and return its map below the top-level key.

    :param path: The metadata.yaml file.

    :returns: The metadata map.

    :raises BagError: the file cannot be read, is not YAML or lacks the top-level key.
    """
    try:
        with open(path, encoding='utf-8') as stream:
            document = yaml.safe_load(stream)
    except OSError as exc:
        raise BagError(f'cannot read {path}: {exc.strerror}') from None
    except yaml.YAMLError as exc:
        raise BagError(f'{path} is not valid YAML: {exc}') from None
    if not isinstance(document, dict) or not isinstance(document.get(TOP_KEY), dict):
        raise BagError(f'{path} has no {TOP_KEY!r} map; it is not rosbag2 metadata')
    return document[TOP_KEY]
