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
Re-simulate a bag: its recorded input poses through a fresh Simulator, offline.

The fairlead and bollard poses of a bag (stamps from their headers, end point = pose ⊕
offset as the node computes it) drive the same offline loop as ``rope_sim run``; the new
bag has the same layout (the input messages byte for byte, stamped with their header
stamps, and the outputs). Nothing depends on the wall clock, so the same bag and
parameters give byte-identical payloads.
"""

from dataclasses import dataclass, field
import math
import os
from typing import Dict, List, Optional, Tuple

import numpy as np

from .bag import bag_info, BagError, deserialize, read_messages
from .bag.metadata import load_metadata, METADATA_FILE
from .params import LineParams
from .ros.conversions import pose_point, PoseError, stamp_to_ns
from .runner import (BagSink, BOLLARD_POSE, check_line, DEFAULT_RATE, EndSamples,
                     FAIRLEAD_POSE, parameters_from_yaml, PARAMETERS_KEY, PARTICLES, POSE_TYPE,
                     RunSummary, simulate, topic_name)


@dataclass
class ResimSummary:
    """
    What a re-simulation did.

    :param run: the offline run's summary.
    :param namespace: namespace of the topics re-simulated ('' = root).
    :param rate: output rate used [Hz].
    :param skipped: input messages left out, with the reason.
    """

    run: RunSummary
    namespace: str
    rate: float
    skipped: List[str] = field(default_factory=list)


def bag_namespaces(path) -> List[str]:
    """
    Return the namespaces of the bag's fairlead/pose topics ('' = root), sorted.

    :raises BagError: path is not a readable bag.
    """
    suffix = '/' + FAIRLEAD_POSE
    return sorted(name[:-len(suffix)] for name, topic in bag_info(path).topics.items()
                  if name.endswith(suffix) and topic.type_name == POSE_TYPE)


def choose_namespace(path, namespace: Optional[str] = None) -> str:
    """
    Return the namespace of the line to use from a bag.

    :param path: the bag.
    :param namespace: the wanted one (e.g. '/ship/line1'), or None to take the only one.
    :raises BagError: no fairlead/pose topic, the wanted one is missing, or several lines
        are recorded and none was chosen.
    """
    found = bag_namespaces(path)
    shown = ', '.join(repr(ns or '/') for ns in found)
    if namespace is not None:
        wanted = '/' + namespace.strip('/') if namespace.strip('/') else ''
        if wanted not in found:
            raise BagError(
                f'bag {os.fspath(path)} has no {topic_name(wanted, FAIRLEAD_POSE)} '
                f'({POSE_TYPE}); its lines are in namespace(s): {shown or "none"}')
        return wanted
    if not found:
        raise BagError(
            f'bag {os.fspath(path)} has no .../{FAIRLEAD_POSE} topic of type {POSE_TYPE}; '
            'nothing to re-simulate')
    if len(found) > 1:
        raise BagError(
            f'bag {os.fspath(path)} records several lines (namespaces {shown}); choose one '
            'with --namespace')
    return found[0]


def stored_parameters(path) -> Optional[Dict]:
    """
    Return the parameters a bag was made with (metadata.yaml custom_data), or None.

    ``rope_sim run --bag`` and ``rope_sim resim`` store them; a bag without them (or
    without metadata.yaml, as a killed recording) gives None.
    """
    metadata_path = os.path.join(os.fspath(path), METADATA_FILE)
    if not os.path.isfile(metadata_path):
        return None
    try:
        custom = load_metadata(metadata_path).get('custom_data') or {}
    except BagError:
        return None
    text = custom.get(PARAMETERS_KEY) if isinstance(custom, dict) else None
    return parameters_from_yaml(text) if text else None


def _rounded_rate(interval_ns: float) -> float:
    rate = 1e9 / interval_ns
    digits = 3 - int(math.floor(math.log10(rate)))
    return round(rate, digits)


def recorded_rate(path, namespace: str = '') -> Optional[float]:
    """
    Return the output rate of a bag's rope/particles (3 significant digits), or None.

    The rate is the inverse of the median interval of the header stamps.
    """
    stamps = [stamp_to_ns(deserialize(m).header.stamp) for m in read_messages(
        path, [topic_name(namespace, PARTICLES)])]
    intervals = np.diff(np.unique(stamps))
    if not len(intervals):
        return None
    return _rounded_rate(float(np.median(intervals)))


@dataclass
class _End:
    stamps: List[int] = field(default_factory=list)
    points: List[np.ndarray] = field(default_factory=list)
    levers: List[np.ndarray] = field(default_factory=list)
    raw: List[Tuple[int, str, bytes]] = field(default_factory=list)

    def samples(self, base_ns: int) -> Optional[EndSamples]:
        if not self.stamps:
            return None
        t = (np.array(self.stamps, dtype=np.int64) - base_ns) / 1e9
        return EndSamples(t, np.array(self.points), np.array(self.levers))


def _read_end(path, topic: str, offset: np.ndarray, skipped: List[str]) -> _End:
    records = []
    for message in read_messages(path, [topic]):
        pose = deserialize(message)
        records.append((stamp_to_ns(pose.header.stamp), message.data, pose.pose))
    records.sort(key=lambda record: record[0])  # stable: equal stamps keep bag order
    end = _End()
    for ns, data, pose in records:
        # The node's rules: pose ⊕ offset, no non-finite pose, strictly newer stamps.
        try:
            point = pose_point(pose, offset)
        except PoseError as e:
            skipped.append(f'{topic} at {ns / 1e9:.9f} s: {e}')
            continue
        if end.stamps and ns <= end.stamps[-1]:
            skipped.append(f'{topic} at {ns / 1e9:.9f} s: stamp not after the previous one')
            continue
        if ns < 0:
            skipped.append(f'{topic} at {ns / 1e9:.9f} s: negative stamp')
            continue
        end.stamps.append(ns)
        end.points.append(point.point)
        end.levers.append(point.lever)
        end.raw.append((ns, topic, data))
    return end


def resim(path, out_path, params: LineParams, rate: Optional[float] = None,
          namespace: Optional[str] = None, progress=None) -> ResimSummary:
    """
    Re-simulate a bag's inputs with the given parameters into a new bag.

    :param path: the recorded bag.
    :param out_path: the new bag directory (must not exist or be empty).
    :param params: validated parameters for the fresh line.
    :param rate: output rate [Hz]; None = the recorded rope/particles rate, else 100 Hz.
    :param namespace: the line's namespace in the bag; None = the only one there is.
    :param progress: callable progress(done, total, t), or None.
    :returns: the ResimSummary.
    :raises BagError: the bag cannot be read, holds no usable fairlead pose, or the new
        bag cannot be written.
    :raises ParameterError: a bad rate.
    """
    namespace = choose_namespace(path, namespace)
    skipped: List[str] = []
    fairlead = _read_end(path, topic_name(namespace, FAIRLEAD_POSE),
                         np.asarray(params.fairlead_offset, dtype=float), skipped)
    bollard_topic = topic_name(namespace, BOLLARD_POSE)
    has_bollard = bollard_topic in bag_info(path).topics
    bollard = _read_end(path, bollard_topic, np.asarray(params.bollard_offset, dtype=float),
                        skipped) if has_bollard else _End()
    if not fairlead.stamps:
        raise BagError(
            f'bag {os.fspath(path)} has no usable message on '
            f'{topic_name(namespace, FAIRLEAD_POSE)}; nothing to re-simulate')
    if rate is None:
        rate = recorded_rate(path, namespace) or DEFAULT_RATE
    base_ns = fairlead.stamps[0]
    topics = {topic_name(namespace, FAIRLEAD_POSE): POSE_TYPE}
    if has_bollard:
        topics[bollard_topic] = POSE_TYPE
    fairlead_samples = fairlead.samples(base_ns)
    bollard_samples = bollard.samples(base_ns)
    check_line(params, rate)  # a refused line leaves no bag behind
    sink = BagSink(out_path, params, fairlead.raw + bollard.raw, topics, namespace,
                   fairlead_samples, bollard_samples, base_ns=base_ns)
    try:
        summary = simulate(params, fairlead_samples, bollard_samples, rate, [sink], progress)
    except BaseException:
        try:
            sink.close(complete=False)
        except BagError:
            pass
        raise
    summary.dropped = sink.close()
    summary.start += base_ns / 1e9
    summary.end += base_ns / 1e9
    return ResimSummary(summary, namespace, rate, skipped)
