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
One line of the tests: a Mooring of one line, driven by its end points.

The physics tests drive a single line's ends through given points, as the seed paper and
the MoorDyn cases do: this holds a Mooring of that line (the one stack, nothing beside it)
and speaks in ends and single-line outputs. A fairlead point is the ship's pose with
identity orientation plus the line's fairlead_offset, as the node takes it.
"""

from typing import NamedTuple, Optional

import numpy as np
from rope_sim_ros.mooring.line import Parting
from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.params.arrangement import single_line

LEVEL = (0.0, 0.0, 0.0, 1.0)


class Output(NamedTuple):
    """What the line looks like at one instant (MooringOutput's row of the line)."""

    t: float
    positions: np.ndarray
    fairlead_force: np.ndarray
    bollard_force: np.ndarray
    max_strain: float
    payload_position: Optional[np.ndarray]
    fairlead_peak: float
    bollard_peak: float
    line_length: float
    winch_speed: float
    parted: bool
    payload_velocity: Optional[np.ndarray]

    @property
    def fairlead_tension(self) -> float:
        return float(np.linalg.norm(self.fairlead_force))

    @property
    def bollard_tension(self) -> float:
        return float(np.linalg.norm(self.bollard_force))


class Advance(NamedTuple):
    """What an advance did to the line (MooringAdvance of the line)."""

    steps: int
    lag: float
    restarted: str
    beyond_reach: float
    parted: Optional[Parting]


class OneLine:
    """A Mooring of one line (see the module docstring)."""

    def __init__(self, params, materials=None, output_interval: float = 0.0,
                 compiled: bool = True, history: float = 5.0):
        self.mooring = Mooring(single_line(params), materials, output_interval, history,
                               compiled)

    @property
    def line(self):
        return self.mooring.lines[0]

    params = property(lambda self: self.line.params)
    props = property(lambda self: self.line.props)
    environment = property(lambda self: self.mooring.environment)
    material = property(lambda self: self.line.material)
    time_step = property(lambda self: self.line.time_step)
    reach = property(lambda self: self.line.reach)
    parting = property(lambda self: self.line.parting)
    length = property(lambda self: self.line.length)
    time = property(lambda self: self.mooring.time)
    last_jump = property(lambda self: float(self.mooring.last_jumps[0]))
    held = property(lambda self: bool(self.mooring.held[0]))
    started = property(lambda self: self.mooring.started)

    @property
    def rope(self):
        return self.mooring.rope(0) if self.mooring.started else None

    @property
    def system(self):
        return self.mooring.where(0)[0].system if self.mooring.started else None

    def push_fairlead(self, t: float, point) -> str:
        position = np.subtract(point, self.params.fairlead_offset)
        return 'teleport' if self.mooring.push_ship(t, position, LEVEL) else ''

    def push_bollard(self, t: float, point) -> str:
        return self.mooring.push_bollard(0, t, point)

    def start(self, t: float, shape=None) -> None:
        self.mooring.start(t)
        if shape is not None:
            self.mooring.place_line(0, shape)

    def advance_to(self, t: float) -> Advance:
        done = self.mooring.advance_to(t)
        return Advance(done.steps, done.lag, done.restarted.get(0, ''),
                       done.beyond_reach.get(0, 0.0), done.parted.get(0))

    def run(self, times) -> tuple:
        """Advance to each of times: return the outputs there and the partings on the way."""
        outputs, partings = [], []
        for t in times:
            advance = self.advance_to(float(t))
            outputs.append(self.output())
            if advance.parted is not None:
                partings.append(advance.parted)
        return outputs, partings

    def output(self) -> Output:
        out = self.mooring.output()
        velocity = None
        if self.line.payload:
            velocity = self.system.point_v[self.rope.ends[0]].copy()
        return Output(out.t, out.positions[0], out.fairlead_forces[0], out.bollard_forces[0],
                      float(out.max_strains[0]), out.payload_positions[0],
                      float(out.fairlead_peaks[0]), float(out.bollard_peaks[0]),
                      float(out.line_lengths[0]), float(out.winch_speeds[0]),
                      bool(out.parted[0]), velocity)

    def ends_at(self, times) -> tuple:
        return self.mooring.drive(0, times)[:2]

    def command_winch(self, speed: float) -> None:
        self.mooring.command_winch(0, speed)

    def check_update(self, values: dict) -> None:
        self.mooring.check_update(0, values)

    def update(self, values: dict) -> None:
        self.mooring.update(0, values)

    def restart(self, t: Optional[float] = None) -> None:
        self.mooring.restart(t)

    def restore(self) -> None:
        self.mooring.restore()

    def skip_to(self, t: float) -> None:
        self.mooring.skip_to(t)
