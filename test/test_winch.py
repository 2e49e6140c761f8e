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
The fairlead's winch: speed, brake and constant tension, against MoorDyn where it has them.

The MoorDyn case (test/data/winch/, see test/data/README.md): a 40 m polyester line, N 20,
between A (0, 0, 0) and B (28, 0, 8), both fixed, in air; hauled in to 30 m at 0.5 m/s and
paid out again, with 2 s cosine ramps.
"""

import csv
import math

import numpy as np
from one_line import OneLine
from physics_cases import reference_params
import pytest
from rope_sim_ros.params.table import from_values, ParameterError

# MoorDyn's line in air (its drag and added mass): the reference's numbers
AIR = dict(diameter=0.064, volume_diameter=0.064, mass_per_length=2.6, air_density=1.225,
           normal_drag_coefficient=1.2, tangential_drag_coefficient=0.008,
           normal_added_mass_coefficient=1.0, tangential_added_mass_coefficient=0.0)
B = np.array([28.0, 0.0, 8.0])


def _number(text):
    try:
        return float(text)
    except ValueError:
        return text


def _rows(path):
    with open(path, newline='') as f:
        return [{k: _number(v) for k, v in row.items()}
                for row in csv.DictReader(line for line in f if not line.startswith('#'))]


def _moordyn_rate(t):
    """Return the reference's pay-out speed at t: 0.5 m/s moves with 2 s cosine ramps."""
    for start, sign in ((5.0, -1.0), (47.0, 1.0)):
        tau = t - start
        if 0.0 <= tau <= 22.0:
            ramp = min(tau, 22.0 - tau)
            return sign * 0.5 * (0.5 * (1.0 - math.cos(math.pi * ramp / 2.0))
                                 if ramp < 2.0 else 1.0)
    return 0.0


def _line(integrator, fairlead=B, **winch):
    sim = OneLine(reference_params('polyester', 20, integrator=integrator, **winch, **AIR),
                  history=math.inf, output_interval=0.01)
    sim.push_fairlead(0.0, fairlead)
    sim.push_fairlead(1000.0, fairlead)
    sim.start(0.0)
    return sim


def _run(sim, end, command=None):
    """Return outputs every 10 ms to `end`; command(t) sets the winch speed before each."""
    times = np.round(np.arange(0.01, end + 1e-9, 0.01), 2)
    outputs = []
    for t in times:
        if command is not None:
            speed = command(float(t))
            if speed is not None:
                sim.command_winch(speed)
        sim.advance_to(float(t))
        outputs.append(sim.output())
    return times, outputs


@pytest.mark.parametrize('integrator, bound', [('improved_euler', 0.004),
                                               ('implicit_euler', 0.012)])
def test_haul_in_and_pay_out_follow_moordyn(reference_dir, integrator, bound):
    # MoorDyn's schedule commanded every 10 ms (the winch's own ramps out of the way)
    sim = _line(integrator, winch_mode='speed', winch_max_speed=0.5, winch_acceleration=10.0)
    times, outputs = _run(sim, 90.0, lambda t: _moordyn_rate(t - 0.005))
    moordyn = _rows(reference_dir / 'winch' / 'winch_polyester_N20_1s.csv')
    at = np.searchsorted(times, [r['t_s'] for r in moordyn[1:]])
    force = np.array([outputs[k].fairlead_tension for k in at])
    length = np.array([outputs[k].line_length for k in at])
    reference = np.array([r['F_B_N'] for r in moordyn[1:]])
    assert np.abs(length - [r['L_m'] for r in moordyn[1:]]).max() < 0.01
    # largest difference as a share of the tension: measured 0.26 % (improved_euler at its
    # 0.2 ms step; MoorDyn's own spread with N is 0.4 %) and 1.0 % (implicit_euler at 3.3 ms,
    # which lags the sag in the ramps); without the damper's rest-length rate 5 %
    error = np.abs(force - reference).max() / reference.max()
    print(f'{integrator}: max |F_B - MoorDyn| {error:.2%} of {reference.max():.0f} N')
    assert error < bound
    held = force[(times[at] >= 30.0) & (times[at] <= 46.0)]  # held at 30 m
    assert np.abs(held - 1023.61).max() < 5.0  # the 20-segment chain's statics at 30 m


@pytest.mark.parametrize('integrator', ['improved_euler', 'implicit_euler'])
def test_a_commanded_start_and_stop_ring_no_more_than_moordyn(reference_dir, integrator):
    # The winch's own ramps (0.25 m/s^2, eased in and out) from steps of the command: the
    # tension after each start and stop stays within MoorDyn's after its smooth ramps
    sim = _line(integrator, winch_mode='speed', winch_max_speed=0.5, winch_acceleration=0.25)
    commands = {5.01: -0.5, 25.01: 0.0, 47.01: 0.5, 67.01: 0.0}
    times, outputs = _run(sim, 90.0, lambda t: commands.get(t))
    force = np.array([o.fairlead_tension for o in outputs])
    peak = np.array([o.fairlead_peak for o in outputs])
    speed = np.array([o.winch_speed for o in outputs])
    length = np.array([o.line_length for o in outputs])
    assert length.min() == pytest.approx(30.0, abs=0.02) and length[-1] == pytest.approx(
        40.0, abs=0.02)
    assert np.abs(speed).max() == pytest.approx(0.5, abs=1e-6)
    assert np.all(peak >= force - 1e-9)
    transitions = {row['t_s']: row
                   for row in _rows(reference_dir / 'winch' / 'winch_transitions.csv')}
    moving = np.abs(speed) > 1e-9
    starts = np.flatnonzero(moving[1:] & ~moving[:-1]) + 1
    stops = np.flatnonzero(~moving[1:] & moving[:-1]) + 1
    assert len(starts) == len(stops) == 2
    for ours, theirs in zip((starts[0], stops[0], starts[1], stops[1]), (5.0, 27.0, 47.0, 69.0)):
        window = slice(ours, ours + 300)  # 3 s
        worst = peak[window].max()
        print(f'{integrator} from {times[ours]:.2f} s: {worst:.1f} N, MoorDyn '
              f"{transitions[theirs]['F_B_max_3s_N']:.1f} N")
        assert worst <= transitions[theirs]['F_B_max_3s_N'] + 2.0


def _lift(**winch):
    # launch and recovery: a 2 t payload on 40 m of polyester under a crane tip at 50 m
    params = from_values(dict(payload_mass=2000.0, length=40.0, segments=20,
                              winch_max_speed=0.5, **winch))
    sim = OneLine(params, history=math.inf)
    top = np.array([0.0, 0.0, 50.0])
    sim.push_fairlead(0.0, top)
    sim.push_fairlead(1000.0, top)
    sim.start(0.0)
    return sim


def test_a_payload_hauled_in_to_10_m_and_back_hangs_where_its_length_says():
    # the haul-in from 40 m to 10 m and back, at default settings but the speed
    sim = _lift(winch_mode='speed')
    weight = sim.props.mass_per_length * 9.81
    # 60 s at 0.5 m/s each way: the ramps to and from a speed are alike, so what the start's
    # ramp loses the stop's gains back
    commands = {1.0: -0.5, 61.0: 0.0, 80.0: 0.5, 140.0: 0.0}
    t = worst = 0.0
    for end, speed in sorted(commands.items()) + [(160.0, None)]:
        while t < end - 1e-9:
            t = round(t + 0.02, 2)
            sim.advance_to(t)
            out = sim.output()
            assert np.isfinite(out.positions).all() and not out.parted
            # hanging: the payload's weight and the line's, within the force that
            # accelerates them in the winch's ramps (0.5 m/s^2 by default; 5.3 % measured)
            static = 2000.0 * 9.81 + weight * out.line_length
            if abs(out.fairlead_tension - static) / static > worst:
                worst, when = abs(out.fairlead_tension - static) / static, t
            if abs(t - 79.0) < 1e-9:
                held_in = out
        if speed is not None:
            sim.command_winch(speed)
    print(f'largest departure from the static tension {worst:.2%} at {when} s')
    assert worst < 0.06
    assert held_in.line_length == pytest.approx(10.0, abs=0.05)
    stretch = held_in.fairlead_tension / sim.props.axial_stiffness
    assert 50.0 - held_in.payload_position[2] == pytest.approx(10.0 * (1.0 + stretch),
                                                               abs=0.01)
    assert out.line_length == pytest.approx(40.0, abs=0.05)
    assert 50.0 - out.payload_position[2] == pytest.approx(out.line_length, rel=0.01)


def test_the_explicit_step_divides_as_the_winch_shortens_the_line():
    """
    improved_euler's step is chosen for the line at its length when it starts.

    Hauled in from 40 m to 10 m, the segments are a quarter as long and four times as stiff:
    before, the step chosen for 40 m blew up (380 times the payload's weight at 10 m).
    """
    sim = _lift(winch_mode='speed', integrator='improved_euler')
    weight = sim.props.mass_per_length * 9.81
    worst = 0.0
    for t in np.round(np.arange(0.02, 70.0, 0.02), 2):
        if t == 1.0:
            sim.command_winch(-0.5)
        elif t == 61.0:
            sim.command_winch(0.0)
        sim.advance_to(float(t))
        out = sim.output()
        static = 2000.0 * 9.81 + weight * out.line_length
        worst = max(worst, abs(out.fairlead_tension - static) / static)
    print(f'largest departure from the static tension {worst:.2%}')
    assert out.line_length == pytest.approx(10.0, abs=0.05)
    assert worst < 0.06  # the ramps' 5 %, as with the default integrator


def test_the_brake_renders_at_its_holding_load():
    # the fairlead pulled away 2 m in 20 s: the tension rises to the brake's load, then the
    # brake pays out and holds it there
    params = reference_params('polyester', 20, winch_mode='brake', winch_brake_load=5.0e4,
                              **AIR)
    sim = OneLine(params, history=math.inf)
    start = np.array([39.0, 0.0, 8.0])  # nearly taut
    for k in range(101):
        sim.push_fairlead(0.2 * k, start + [min(0.1 * 0.2 * k, 2.0), 0.0, 0.0])
    sim.start(0.0)
    tensions, lengths = [], []
    for t in np.arange(0.05, 20.0, 0.05):
        sim.advance_to(float(t))
        out = sim.output()
        tensions.append(out.fairlead_peak)
        lengths.append(out.line_length)
    tensions, lengths = np.array(tensions), np.array(lengths)
    print(f'peak {tensions.max():.0f} N, paid out {lengths[-1] - 40.0:.3f} m')
    assert tensions.max() <= 5.0e4 * 1.02
    assert tensions[-40:].min() >= 5.0e4 * 0.97  # rendering: held at its load
    assert lengths[-1] > 40.5 and np.all(np.diff(lengths) >= -1e-12)  # paid out, never in


def test_the_brake_holds_by_default_at_60_percent_of_the_mbl():
    sim = _line('implicit_euler', winch_mode='brake')
    assert sim.system.lines[0].winch.brake_load == pytest.approx(0.6 * sim.props.mbl)
    _, outputs = _run(sim, 2.0)
    assert outputs[-1].line_length == 40.0  # holding, below its load


# At B the tension is not monotonic in the length (it falls to 653 N at 36.3 m, then rises):
# constant tension is tried where a mooring line works, nearer taut: the fairlead at
# (36, 0, 8), where the 40 m line holds 927 N (1281 N at 38 m, 872 N at 41 m).
TAUTER = np.array([36.0, 0.0, 8.0])


@pytest.mark.parametrize('set_tension', [1100.0, 880.0])
def test_constant_tension_brings_the_tension_to_the_set_one(set_tension):
    sim = _line('implicit_euler', TAUTER, winch_mode='constant_tension',
                winch_tension=set_tension)
    times, outputs = _run(sim, 30.0)
    force = np.array([o.fairlead_tension for o in outputs])
    length = np.array([o.line_length for o in outputs])
    print(f'{set_tension} N: length {length[-1]:.3f} m, tension {force[-1]:.1f} N')
    assert np.abs(force[times > 20.0] - set_tension).max() < 0.01 * set_tension
    assert (length[-1] < 40.0) == (set_tension > 927.0)


def test_constant_tension_without_a_set_tension_holds_the_one_it_started_with():
    sim = _line('implicit_euler', TAUTER, winch_mode='constant_tension')
    start = sim.output().fairlead_tension
    # the fairlead moves 0.5 m away over 10 s: the winch pays out to hold the tension
    sim.push_fairlead(1000.0 + 1e-3, TAUTER)  # keeps the end's track past the move below
    for k in range(11):
        sim.push_fairlead(2000.0 + k, TAUTER + [0.05 * k, 0.0, 0.0])
    sim.skip_to(2000.0)
    sim.restart()
    start = sim.output().fairlead_tension
    outputs = []
    for t in np.arange(2000.05, 2040.0, 0.05):
        sim.advance_to(float(t))
        outputs.append(sim.output())
    force = np.array([o.fairlead_tension for o in outputs])
    length = np.array([o.line_length for o in outputs])
    print(f'start {start:.1f} N, end {force[-1]:.1f} N, length {length[-1]:.3f} m')
    assert abs(force[-1] - start) < 0.01 * start
    assert length[-1] > 40.3


def test_constant_tension_heaves_in_a_line_parted_at_its_own_segment():
    # The line nearly taut at 3.1 kN, its fairlead jerked 0.4 m away at 4 m/s: under implicit
    # Euler the tension front parts the segment at the winch first (the adaptive step parts
    # the one at the bollard). The winch steered by that segment's EA / l_i times l_i, 0 and
    # 1e300 m once parted: a division by zero. Now by the line's EA, as wherever it parts.
    params = reference_params('polyester', 20, integrator='implicit_euler', break_load=5.0e4,
                              winch_mode='constant_tension')
    sim = OneLine(params, history=math.inf)
    start = np.array([39.0, 0.0, 8.0])
    for t, away in ((0.0, 0.0), (0.5, 0.0), (0.6, 0.4), (10.0, 0.4)):
        sim.push_fairlead(t, start + [away, 0.0, 0.0])
    sim.start(0.0)
    held = sim.output().fairlead_tension
    outputs, partings = sim.run(np.arange(0.02, 3.0 + 1e-9, 0.02))
    print(f'held {held:.0f} N, parted at {partings[0].t:.4f} s, '
          f'length {outputs[-1].line_length:.3f} m')
    assert held == pytest.approx(3076.0, abs=1.0)
    assert len(partings) == 1 and sim.system.lines[0].parted == 19  # the winch's segment
    assert all(np.isfinite(o.positions).all() for o in outputs)
    # nothing holds the set tension any more: it heaves the piece in, at up to its 1 m/s
    lengths = np.array([o.line_length for o in outputs])
    assert np.all(np.diff(lengths) <= 0.0) and lengths[-1] < 39.5


def test_winch_parameters_are_checked():
    with pytest.raises(ParameterError, match="'winch_mode' = 'reel' is not allowed: must be one "
                                             'of none, speed, brake, constant_tension'):
        from_values({'winch_mode': 'reel'})
    with pytest.raises(ParameterError, match="'winch_max_speed' = 0"):
        from_values({'winch_max_speed': 0.0})
    sim = _line('implicit_euler', winch_mode='speed')
    with pytest.raises(ParameterError, match='winch speed nan is not allowed'):
        sim.command_winch(math.nan)
