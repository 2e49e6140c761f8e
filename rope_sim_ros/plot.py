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
Look at a bag: a summary (``rope_sim info``) and a plot (``rope_sim plot``).

Tensions are the magnitudes of the recorded fairlead/tension and bollard/tension wrenches'
forces, at their log times. The plot draws them with the material's minimum breaking load
(MBL) and working load limit (WLL) and a few rope shapes (x-z) from rope/particles.
"""

from dataclasses import dataclass
import os
from typing import Dict, List, Optional, Tuple

import numpy as np

from .bag import bag_info, BagError, BagInfo, read_messages
from .bag.cdr import decode_pose_array, decode_wrench
from .params.materials import load_materials
from .params.table import LineParams
from .runner import BOLLARD_TENSION, FAIRLEAD_TENSION, PARTICLES, topic_name

ENDS = ('fairlead', 'bollard')
_TENSION_TOPICS = {'fairlead': FAIRLEAD_TENSION, 'bollard': BOLLARD_TENSION}


@dataclass(frozen=True)
class TensionSeries:
    """
    The tension recorded at one end.

    :param topic: the Wrench topic.
    :param times_ns: log times [ns], shape (n,).
    :param tension: |force| [N], shape (n,).
    """

    topic: str
    times_ns: np.ndarray
    tension: np.ndarray

    def peak(self) -> Tuple[float, int]:
        """Return the largest tension [N] and its log time [ns] (nan, 0 when empty)."""
        if not len(self.tension):
            return float('nan'), 0
        i = int(np.argmax(self.tension))
        return float(self.tension[i]), int(self.times_ns[i])


def tension_namespaces(info: BagInfo) -> List[str]:
    """Return the namespaces ('' = root) with a fairlead or bollard tension topic, sorted."""
    found = set()
    for name in info.topics:
        for relative in _TENSION_TOPICS.values():
            if name.endswith('/' + relative):
                found.add(name[:-len(relative) - 1])
    return sorted(found)


def read_tensions(path, namespace: str = '') -> Dict[str, TensionSeries]:
    """
    Return the tension series of both ends of one line (empty series for a missing topic).

    :raises BagError: the bag cannot be read.
    """
    series = {}
    for end in ENDS:
        topic = topic_name(namespace, _TENSION_TOPICS[end])
        times, values = [], []
        for message in read_messages(path, [topic]):
            force, _ = decode_wrench(message.data)
            times.append(message.log_time_ns)
            values.append(float(np.linalg.norm(force)))
        series[end] = TensionSeries(topic, np.array(times, dtype=np.int64),
                                    np.array(values, dtype=float))
    return series


def _seconds(ns: int) -> str:
    return f'{ns / 1e9:.3f} s'


def describe(path) -> str:
    """
    Return the text of ``rope_sim info``: topics, counts, duration, peak tensions.

    :raises BagError: path is not a readable bag.
    """
    info = bag_info(path)
    lines = [f'bag:       {os.fspath(path)}'
             + ('' if info.complete else
                f'  (cut short: not closed; `rope_sim recover {os.fspath(path)}` completes it)'),
             f'duration:  {_seconds(info.duration_ns)}  '
             f'(log time {_seconds(info.start_ns)} .. {_seconds(info.end_ns)})',
             f'messages:  {info.message_count}',
             'topics:']
    width = max([len(name) for name in info.topics] + [5])
    type_width = max([len(topic.type_name) for topic in info.topics.values()] + [4])
    for name in sorted(info.topics):
        topic = info.topics[name]
        lines.append(f'  {name:<{width}}  {topic.type_name:<{type_width}}  '
                     f'{topic.message_count:>8d}')
    for namespace in tension_namespaces(info):
        for end, series in read_tensions(path, namespace).items():
            if not len(series.tension):
                continue
            peak, at = series.peak()
            lines.append(
                f'peak {end} tension {series.topic}: {peak:.1f} N at log time {_seconds(at)} '
                f'({_seconds(at - info.start_ns)} after the start)')
    return '\n'.join(lines)


def _shapes(path, namespace: str, count: int,
            start_ns: int) -> List[Tuple[float, np.ndarray]]:
    topic = topic_name(namespace, PARTICLES)
    messages = list(read_messages(path, [topic]))
    if not messages:
        return []
    picks = sorted(set(np.linspace(0, len(messages) - 1, count).round().astype(int).tolist()))
    shapes = []
    for i in picks:
        poses = decode_pose_array(messages[i].data)[3]
        # on the tension plot's time axis (a node bag's stamps are epoch times)
        stamp = (messages[i].log_time_ns - start_ns) / 1e9
        shapes.append((stamp, poses[:, :3]))
    return shapes


def plot_bag(path, out_path, params: LineParams, namespace: Optional[str] = None,
             shapes: int = 5) -> str:
    """
    Draw a bag's tensions with MBL and WLL, and rope shapes, into a PNG file.

    :param path: the bag.
    :param out_path: the image file to write.
    :param params: parameters giving the material and diameter (for MBL and WLL).
    :param namespace: the line's namespace ('' = root); None = the only one there is.
    :param shapes: how many rope shapes to draw, evenly spaced over the run.
    :returns: the image path.
    :raises BagError: unreadable bag, no tension topics, or several lines and none chosen.
    :raises OSError: the image cannot be written.
    """
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    info = bag_info(path)
    found = tension_namespaces(info)
    if namespace is None:
        if len(found) != 1:
            raise BagError(
                f'bag {os.fspath(path)} has tension topics in '
                f'{len(found) or "no"} namespace(s) {", ".join(repr(n or "/") for n in found)}'
                + ('; choose one with --namespace' if found else '; nothing to plot'))
        namespace = found[0]
    else:
        namespace = '/' + namespace.strip('/') if namespace.strip('/') else ''
        if namespace not in found:
            raise BagError(f'bag {os.fspath(path)} has no tension topics in namespace '
                           f'{namespace or "/"!r}')
    material = load_materials().properties(params.material, params.diameter)
    series = read_tensions(path, namespace)

    figure = Figure(figsize=(10, 8), dpi=100, layout='constrained')
    FigureCanvasAgg(figure)
    top, bottom = figure.subplots(2, 1, gridspec_kw={'height_ratios': [3, 2]})
    start = info.start_ns
    peak = 0.0
    for end, colour in zip(ENDS, ('tab:blue', 'tab:green')):
        s = series[end]
        if len(s.tension):
            top.plot((s.times_ns - start) / 1e9, s.tension / 1e3, color=colour,
                     label=f'{end} tension ({s.topic})')
            peak = max(peak, float(s.tension.max()))
    describe_line = f'{params.material} {params.diameter * 1e3:g} mm'
    top.axhline(material.mbl / 1e3, color='tab:red', linestyle='--',
                label=f'MBL {material.mbl / 1e3:.0f} kN ({describe_line})')
    top.axhline(material.working_load_limit / 1e3, color='tab:orange', linestyle='--',
                label=f'working load limit {material.working_load_limit / 1e3:.0f} kN')
    if 0.0 < peak < 0.1 * material.working_load_limit:
        # On a linear axis the tension would be a flat line at the bottom.
        top.set_yscale('log')
        top.set_ylabel('tension [kN] (log scale)')
    else:
        top.set_ylabel('tension [kN]')
        top.set_ylim(bottom=0.0)
    top.set_xlabel(f'time since bag start [s] (start at log time {start / 1e9:.3f} s)')
    folder = os.path.normpath(os.fspath(path))
    title = os.path.join(os.path.basename(os.path.dirname(folder)), os.path.basename(folder))
    top.set_title(f'{title}: line tension')
    top.grid(True, which='both', alpha=0.3)
    top.legend(loc='best', fontsize='small')

    drawn = _shapes(path, namespace, shapes, start)
    cmap = matplotlib.colormaps['viridis']
    for k, (stamp, points) in enumerate(drawn):
        bottom.plot(points[:, 0], points[:, 2], '.-', markersize=3,
                    color=cmap(k / max(1, len(drawn) - 1)), label=f't = {stamp:.2f} s')
    bottom.set_xlabel(f'x [m] ({params.frame_id})')
    bottom.set_ylabel('z [m]')
    bottom.set_title('rope shapes (rope/particles)')
    bottom.set_aspect('equal', adjustable='datalim')
    bottom.grid(True, alpha=0.3)
    if drawn:
        bottom.legend(loc='best', fontsize='small')
    else:
        bottom.text(0.5, 0.5, 'no rope/particles recorded', ha='center', va='center',
                    transform=bottom.transAxes)
    figure.savefig(os.fspath(out_path))
    return os.fspath(out_path)
