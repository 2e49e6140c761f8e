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
What an instructor sees of a mooring: markers for RViz and Foxglove, and diagnostics.

mooring/markers (visualization_msgs/MarkerArray), in frame_id:

- ns 'lines', id k: line k as a LINE_STRIP through its particles, coloured by its band
  (mooring/status.py: green below the WLL, amber past it, red past 90 % of the MBL); a parted
  line as a grey, dashed LINE_LIST (every other segment); a line let go (free) light grey;
  a stowed line is not drawn (its markers are deleted: it lies coiled at its fairlead);
- ns 'labels', id k: its name and utilisation above its middle particle (TEXT_VIEW_FACING),
  or its name and 'let go';
- ns 'fairleads', id 0 and ns 'bollards', id 0: the ends as SPHERE_LISTs, white and blue
  (the bollard ends of the lines fast on them);
- ns 'fenders', id f: fender f as a CYLINDER at its contact point, its axis along its
  normal, green, amber past its rated compression; ns 'fender_labels', id f: its name and
  reaction [kN];
- ns 'quay_bollards', id b: named bollard b as an upright CYLINDER at its position, green,
  amber past its safe working load; ns 'quay_bollard_labels', id b: its name and load [kN].

/diagnostics (diagnostic_msgs/DiagnosticArray): one status per line, named
'<node>: <line>' (the node's full name: 'mooring: head_1', 'ship_a/mooring:
head_1'), hardware_id the line's name: OK below the WLL, WARN past it, ERROR once
it has parted or was restarted since the last report; a line let go says so first ('let
go: ...'), a stowed one is OK, 'stowed'; its values the state, tension, utilisation, peak since
the last report, strain, WLL and MBL. One status per fender too, '<node>: <fender>': OK,
WARN past its rated compression; its values the compression and reaction. One per named
bollard, '<node>: <bollard>': OK, WARN when its load at an output since the last report
passed its safe working load; its values the load, that peak, the safe working load and the
lines fast on it.
"""

from typing import List, Optional, Sequence

from builtin_interfaces.msg import Duration
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Point
import numpy as np
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from .conversions import ns_to_stamp
from ..mooring.status import ABOVE_WLL, BollardLoad, COLOURS, OK, PARTED, Rating, WORDS

LINE_WIDTH = 0.25  # [m]: a 64 mm line drawn at its size is lost beside a 200 m hull
END_SIZE = 1.0  # [m]: fairlead and bollard spheres
TEXT_SIZE = 2.0  # [m]: label height
TEXT_LIFT = 3.0  # [m]: labels float this high above the middle of their line
# A marker lives this long unless published again: a node that stops leaves no stale
# lines behind, and at marker_rate >= 1 Hz they are replaced well before.
LIFETIME = Duration(sec=2)
FAIRLEAD_COLOUR = (1.0, 1.0, 1.0)
FENDER_SIZE = (2.0, 2.0, 1.5)  # [m]: diameter across, length along the normal
BOLLARD_COLOUR = (0.2, 0.4, 1.0)
FREE_COLOUR = (0.80, 0.80, 0.80)  # a line let go: lighter than a parted line's grey
QUAY_BOLLARD_SIZE = (1.0, 1.0, 1.2)  # [m]: a bollard's diameter and height


def _colour(rgb, alpha: float = 1.0) -> ColorRGBA:
    r, g, b = rgb
    return ColorRGBA(r=float(r), g=float(g), b=float(b), a=float(alpha))


def _points(positions) -> List[Point]:
    return [Point(x=x, y=y, z=z) for x, y, z in np.asarray(positions, dtype=float).tolist()]


class LineMarkers:
    """
    Builds the markers of every line (see the module docstring), again and again.

    Its Marker messages are made once and updated in place: a Marker (with its texture,
    mesh and header sub-messages) takes 60 us to construct, 34 of them 2 ms, 10 times a
    second.
    """

    def __init__(self):
        """Start with no markers made."""
        self._markers = {}

    def _marker(self, frame_id: str, stamp_ns: int, ns: str, marker_id: int,
                kind: int) -> Marker:
        marker = self._markers.get((ns, marker_id))
        if marker is None:
            marker = self._markers[(ns, marker_id)] = Marker()
            marker.ns, marker.id, marker.action = ns, marker_id, Marker.ADD
            marker.pose.orientation.w = 1.0
            marker.lifetime = LIFETIME
        marker.header.frame_id = frame_id
        marker.header.stamp = ns_to_stamp(stamp_ns)
        marker.type = kind
        marker.action = Marker.ADD
        return marker

    def __call__(self, frame_id: str, stamp_ns: int, names: Sequence[str],
                 positions: Sequence[np.ndarray], tensions: Sequence[float],
                 ratings: Sequence[Rating], parted: Sequence[bool],
                 fairleads: np.ndarray, bollards: np.ndarray,
                 fenders: Optional['Fenders'] = None, states: Sequence[str] = (),
                 bollard_loads: Sequence[BollardLoad] = ()) -> MarkerArray:
        """
        Return the markers now (see line_markers), the fenders' and bollards' too if given.

        :param states: each line's state ('fast', 'free', 'stowed'); () = every line fast.
        :param bollard_loads: each named bollard's load (mooring/status.py).
        """
        array = _line_markers(self._marker, frame_id, stamp_ns, names, positions, tensions,
                              ratings, parted, fairleads, bollards,
                              states or ('fast',) * len(names))
        if fenders is not None:
            array.markers += fenders.markers(self._marker, frame_id, stamp_ns)
        array.markers += _bollard_markers(self._marker, frame_id, stamp_ns, bollard_loads)
        return array


class Fenders:
    """
    The fenders' state at one output, for their markers and diagnostics.

    :ivar names: their names; normals: each one's unit normal (F, 3), out of the quay.
    :ivar rated: each one's rated compression [m].
    :ivar points: the contact points (F, 3) [m]; compressions [m] (<= 0: untouched);
        forces: each one's force on the hull (F, 3) [N].
    """

    def __init__(self, names, normals, rated, points, compressions, forces):
        """Keep the fenders' state (see the class docstring)."""
        self.names, self.normals, self.rated = names, np.asarray(normals, dtype=float), rated
        self.points = np.asarray(points, dtype=float)
        self.compressions = np.maximum(np.asarray(compressions, dtype=float), 0.0)
        self.reactions = np.linalg.norm(np.asarray(forces, dtype=float).reshape(-1, 3), axis=1)

    def past_rated(self, f: int) -> bool:
        """Tell whether fender f is compressed past its rated compression."""
        return bool(self.compressions[f] > self.rated[f])

    def markers(self, _marker, frame_id: str, stamp_ns: int) -> List[Marker]:
        """Return each fender's cylinder and label (see the module docstring)."""
        markers = []
        for f, name in enumerate(self.names):
            rgb = COLOURS[ABOVE_WLL if self.past_rated(f) else OK]
            body = _marker(frame_id, stamp_ns, 'fenders', f, Marker.CYLINDER)
            x, y, z = self.points[f].tolist()
            body.pose.position = Point(x=x, y=y, z=z)
            q = _z_to(self.normals[f])
            body.pose.orientation.x, body.pose.orientation.y = q[0], q[1]
            body.pose.orientation.z, body.pose.orientation.w = q[2], q[3]
            body.scale.x, body.scale.y, body.scale.z = FENDER_SIZE
            body.color = _colour(rgb)
            label = _marker(frame_id, stamp_ns, 'fender_labels', f, Marker.TEXT_VIEW_FACING)
            label.pose.position = Point(x=x, y=y, z=z + TEXT_LIFT)
            label.scale.z = TEXT_SIZE
            label.color = _colour(rgb)
            label.text = f'{name} {self.reactions[f] / 1e3:.0f} kN'
            markers += [body, label]
        return markers

    def statuses(self, node: str) -> List[DiagnosticStatus]:
        """Return one DiagnosticStatus per fender (see the module docstring)."""
        statuses = []
        for f, name in enumerate(self.names):
            status = DiagnosticStatus(name=f'{node}: {name}', hardware_id=name)
            share = 100.0 * self.compressions[f] / self.rated[f]
            if self.past_rated(f):
                status.level = DiagnosticStatus.WARN
                status.message = f'compressed past its rating: {share:.0f} % of it'
            else:
                status.level = DiagnosticStatus.OK
                status.message = (f'{share:.0f} % of its rated compression'
                                  if self.compressions[f] > 0.0 else 'not touched')
            status.values = [KeyValue(key=key, value=value) for key, value in (
                ('compression [m]', f'{self.compressions[f]:.3f}'),
                ('rated compression [m]', f'{self.rated[f]:.3f}'),
                ('reaction [N]', f'{self.reactions[f]:.1f}'),
            )]
            statuses.append(status)
        return statuses


def _bollard_markers(_marker, frame_id: str, stamp_ns: int,
                     loads: Sequence[BollardLoad]) -> List[Marker]:
    """Return each named bollard's cylinder and label (see the module docstring)."""
    markers = []
    width, _, height = QUAY_BOLLARD_SIZE
    for b, load in enumerate(loads):
        rgb = COLOURS[ABOVE_WLL if load.over else OK]
        x, y, z = (float(c) for c in load.position)
        body = _marker(frame_id, stamp_ns, 'quay_bollards', b, Marker.CYLINDER)
        body.pose.position = Point(x=x, y=y, z=z + 0.5 * height)  # standing on the quay
        body.scale.x, body.scale.y, body.scale.z = QUAY_BOLLARD_SIZE
        body.color = _colour(rgb)
        label = _marker(frame_id, stamp_ns, 'quay_bollard_labels', b, Marker.TEXT_VIEW_FACING)
        label.pose.position = Point(x=x, y=y, z=z + height + TEXT_LIFT)
        label.scale.z = TEXT_SIZE
        label.color = _colour(rgb)
        label.text = f'{load.name} {load.load / 1e3:.0f} kN'
        markers += [body, label]
    return markers


def bollard_statuses(loads: Sequence[BollardLoad], peaks: Sequence[float],
                     node: str = 'mooring') -> List[DiagnosticStatus]:
    """
    Return one DiagnosticStatus per named bollard (see the module docstring).

    :param loads: each bollard's load now; peaks: the largest at an output since the last
        report [N].
    """
    statuses = []
    for load, peak in zip(loads, peaks):
        status = DiagnosticStatus(name=f'{node}: {load.name}', hardware_id=load.name)
        limit = load.safe_working_load
        if limit > 0.0 and peak > limit:
            status.level = DiagnosticStatus.WARN
            status.message = (f'past its safe working load: peak {peak / 1e3:.1f} kN, '
                              f'{100.0 * peak / limit:.0f} % of it')
        else:
            status.level = DiagnosticStatus.OK
            share = (f', {100.0 * load.load / limit:.0f} % of its safe working load'
                     if limit > 0.0 else '')
            status.message = (f'{load.load / 1e3:.1f} kN{share}' if load.lines
                              else 'no line fast on it')
        status.values = [KeyValue(key=key, value=value) for key, value in (
            ('load [N]', f'{load.load:.1f}'),
            ('peak since last report [N]', f'{peak:.1f}'),
            ('safe working load [N]', f'{limit:.0f}'),
            ('lines', ', '.join(load.lines)),
        )]
        statuses.append(status)
    return statuses


def _z_to(direction: np.ndarray) -> List[float]:
    """Return the unit quaternion (x, y, z, w) turning +z onto a unit direction."""
    d = direction / max(float(np.linalg.norm(direction)), 1e-12)
    axis = np.cross([0.0, 0.0, 1.0], d)
    w = 1.0 + float(d[2])
    if w < 1e-9:  # straight down: half a turn about x
        return [1.0, 0.0, 0.0, 0.0]
    q = np.array([*axis, w])
    return (q / np.linalg.norm(q)).tolist()


def line_markers(frame_id: str, stamp_ns: int, names: Sequence[str],
                 positions: Sequence[np.ndarray], tensions: Sequence[float],
                 ratings: Sequence[Rating], parted: Sequence[bool],
                 fairleads: np.ndarray, bollards: np.ndarray) -> MarkerArray:
    """
    Return the markers of every line (see the module docstring).

    :param positions: each line's particles (N_k + 1, 3) [m], bollard first.
    :param tensions: each line's tension [N] (the larger end's).
    :param ratings: each line's MBL and WLL.
    :param parted: whether each line has parted.
    :param fairleads: the fairlead points (L, 3) [m]; bollards likewise.
    """
    return LineMarkers()(frame_id, stamp_ns, names, positions, tensions, ratings, parted,
                         fairleads, bollards)


def _line_markers(_marker, frame_id, stamp_ns, names, positions, tensions, ratings, parted,
                  fairleads, bollards, states) -> MarkerArray:
    markers = []
    for k, name in enumerate(names):
        rating, points = ratings[k], np.asarray(positions[k], dtype=float)
        band = rating.band(tensions[k], parted[k])
        if band == PARTED:
            line = _marker(frame_id, stamp_ns, 'lines', k, Marker.LINE_LIST)
            # pairs (0, 1), (2, 3), ...: every other segment, dashes
            line.points = _points(points[:2 * (len(points) // 2)])
            line.color = _colour(COLOURS[PARTED], 0.6)
        else:
            line = _marker(frame_id, stamp_ns, 'lines', k, Marker.LINE_STRIP)
            line.points = _points(points)
            line.color = _colour(FREE_COLOUR if states[k] == 'free' else COLOURS[band])
        line.scale.x = LINE_WIDTH
        label = _marker(frame_id, stamp_ns, 'labels', k, Marker.TEXT_VIEW_FACING)
        middle = points[len(points) // 2]
        label.pose.position = Point(x=float(middle[0]), y=float(middle[1]),
                                    z=float(middle[2]) + TEXT_LIFT)
        label.scale.z = TEXT_SIZE
        label.color = line.color
        if band == PARTED:
            label.text = f'{name} parted'
        elif states[k] == 'free':
            label.text = f'{name} let go'
        else:
            label.text = f'{name} {100.0 * rating.utilisation(tensions[k]):.0f} %'
        if states[k] == 'stowed' and band != PARTED:  # aboard: not drawn
            line.action = label.action = Marker.DELETE
        markers += [line, label]
    fast = [k for k, state in enumerate(states) if state == 'fast']
    for ns, ends, rgb in (('fairleads', fairleads, FAIRLEAD_COLOUR),
                          ('bollards', np.asarray(bollards).reshape(-1, 3)[fast],
                           BOLLARD_COLOUR)):
        spheres = _marker(frame_id, stamp_ns, ns, 0, Marker.SPHERE_LIST)
        spheres.points = _points(ends)
        spheres.scale.x = spheres.scale.y = spheres.scale.z = END_SIZE
        spheres.color = _colour(rgb)
        markers.append(spheres)
    return MarkerArray(markers=markers)


def line_diagnostics(stamp_ns: int, names: Sequence[str], tensions: Sequence[float],
                     peaks: Sequence[float], strains: Sequence[float],
                     ratings: Sequence[Rating], parted: Sequence[bool],
                     restarted: Sequence[Optional[str]],
                     node: str = 'mooring', states: Sequence[str] = ()) -> DiagnosticArray:
    """
    Return one DiagnosticStatus per line (see the module docstring).

    :param node: the node's full name without its leading slash: a status is named
        '<node>: <line>', so two ships' nodes in two namespaces name theirs apart on the one
        /diagnostics topic.
    :param tensions: each line's tension now [N]; peaks: the largest since the last report.
    :param strains: each line's largest strain now.
    :param restarted: why each line was restarted since the last report, or None.
    :param states: each line's state ('fast', 'free', 'stowed'); () = every line fast.
    """
    states = states or ('fast',) * len(names)
    statuses = []
    for k, name in enumerate(names):
        rating = ratings[k]
        band = rating.band(peaks[k], parted[k])
        utilisation = 100.0 * rating.utilisation(tensions[k])
        status = DiagnosticStatus(name=f'{node}: {name}', hardware_id=name)
        if parted[k]:
            status.level, status.message = DiagnosticStatus.ERROR, 'parted'
        elif states[k] == 'stowed':  # aboard: nothing to grade
            status.level, status.message = DiagnosticStatus.OK, 'stowed'
        elif restarted[k]:
            status.level = DiagnosticStatus.ERROR
            status.message = f'restarted at rest: {restarted[k]}'
        elif peaks[k] >= rating.wll:
            status.level = DiagnosticStatus.WARN
            status.message = (f'{WORDS[band]}: peak {100.0 * rating.utilisation(peaks[k]):.1f} '
                              '% of MBL')
        else:
            status.level = DiagnosticStatus.OK
            status.message = f'{utilisation:.1f} % of MBL'
        if states[k] == 'free' and not parted[k]:
            status.message = f'let go: {status.message}'
        status.values = [KeyValue(key=key, value=value) for key, value in (
            ('state', states[k]),
            ('tension [N]', f'{tensions[k]:.1f}'),
            ('utilisation [%]', f'{utilisation:.2f}'),
            ('peak since last report [N]', f'{peaks[k]:.1f}'),
            ('strain [%]', f'{100.0 * strains[k]:.4f}'),
            ('WLL [N]', f'{rating.wll:.0f}'),
            ('MBL [N]', f'{rating.mbl:.0f}'),
        )]
        statuses.append(status)
    array = DiagnosticArray(status=statuses)
    array.header.stamp = ns_to_stamp(stamp_ns)
    return array
