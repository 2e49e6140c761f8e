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
rclpy QoS profiles in rosbag2 Jazzy's form (qos.cpp): what metadata.yaml and MCAP store.

Policies left at system_default and durations left unspecified (0) are written as DDS
resolves them (keep_last, reliable, volatile, automatic, infinite), which is what the ROS
graph reports for such a publisher and so what `ros2 bag record` stores.
"""

from typing import Any, Dict, List, Mapping, Sequence, Union

from rclpy.qos import QoSProfile

from ..bag.errors import BagError
from ..bag.metadata import duration_dict, INFINITE_NS

#: None (rclpy's default publisher profile), one profile, or one per publisher; a profile is
#: an rclpy QoSProfile or already a rosbag2 dict (rope_sim_ros.bag.metadata.QOS_KEYS).
QosSpec = Union[None, QoSProfile, Mapping[str, Any], Sequence[Union[QoSProfile, Mapping]]]

# What DDS makes of a policy left at system_default: the DataWriter defaults of the DDS
# specification.
_DDS_DEFAULTS = {
    'history': 'keep_last',
    'reliability': 'reliable',
    'durability': 'volatile',
    'liveliness': 'automatic',
}


def _policy(kind: str, value: Any) -> str:
    # rmw_qos_*_policy_to_str spells the enum names in lower case.
    name = value.name.lower()
    return _DDS_DEFAULTS[kind] if name == 'system_default' else name


def qos_to_dict(profile: QoSProfile) -> Dict[str, Any]:
    """
    Return one QoS profile in rosbag2's version 9 form.

    :param profile: The offered QoS of the publisher.

    :returns: A dict with the keys and order of rosbag2's Rosbag2QoS encoding.
    """
    def duration(value: Any) -> Dict[str, int]:
        nanoseconds = value.nanoseconds
        return duration_dict(INFINITE_NS if nanoseconds == 0 else nanoseconds)

    return {
        'history': _policy('history', profile.history),
        'depth': int(profile.depth),
        'reliability': _policy('reliability', profile.reliability),
        'durability': _policy('durability', profile.durability),
        'deadline': duration(profile.deadline),
        'lifespan': duration(profile.lifespan),
        'liveliness': _policy('liveliness', profile.liveliness),
        'liveliness_lease_duration': duration(profile.liveliness_lease_duration),
        'avoid_ros_namespace_conventions': bool(profile.avoid_ros_namespace_conventions),
    }


def qos_profiles(qos: QosSpec) -> Union[None, List[Any]]:
    """
    Return the profiles of qos as rope_sim_ros.bag takes them (rosbag2 dicts).

    :param qos: None, a QoSProfile or dict, or a sequence of them.

    :returns: None for None (the bag's default publisher profile), else a list of dicts
        (anything neither a QoSProfile nor a dict is passed on for the bag to refuse).

    :raises BagError: qos is neither None, a profile nor a sequence.
    """
    if qos is None:
        return None
    if isinstance(qos, (QoSProfile, Mapping)):
        qos = [qos]
    elif not isinstance(qos, Sequence) or isinstance(qos, (str, bytes)):
        raise BagError(
            f'offered QoS {qos!r} is not understood: pass an rclpy.qos.QoSProfile, '
            'a list of them, or None for the default publisher profile')
    return [qos_to_dict(p) if isinstance(p, QoSProfile) else p for p in qos]
