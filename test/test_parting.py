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
A line parting past its break load, the snap-back of its pieces, and the peak hold.

The analytic case (test/data/winch/parting_exact.csv, see test/data/README.md): a straight
40 m polyester line (EA 50 MN, 2.6 kg/m) stretched 1 %, no gravity, released at one end:
the release wave runs to the fixed end and back in 2 L0 / c = 18.24 ms while everything
behind it moves at eps c = 43.853 m/s, and its 100 kJ turn into motion.
"""

import math
from pathlib import Path

import numpy as np
from one_line import OneLine
from physics_cases import reference_params
import pytest
from rope_sim_ros.model.objects import Environment, Line, LineType, Point, System
from rope_sim_ros.mooring.driver import Driver
from rope_sim_ros.offline.motion import read_motion
from rope_sim_ros.offline.run import run_motion
from rope_sim_ros.offline.sinks import LINE_COLUMNS, STATE_COLUMN
from rope_sim_ros.params.arrangement import flatten, read_setup, single_line
from rope_sim_ros.stepping.step import step

REPO_ROOT = Path(__file__).resolve().parent.parent
EA, MASS, L0, EPS = 5.0e7, 2.6, 40.0, 0.01
WAVE = math.sqrt(EA / MASS)  # 4385.29 m/s


def _bar(segments, break_load):
    kind = LineType(mass_per_length=MASS, axial_stiffness=EA, axial_damping=2903.43,
                    superelastic_adjustment=False)
    x = np.zeros((segments + 1, 3))
    x[:, 0] = np.linspace(0.0, L0 * (1.0 + EPS), segments + 1)
    # every segment pulls alike, and the line parts at its most loaded one: 1 um more on the
    # first (+50 N of 500 kN at N 40) makes that the one, as a flaw at A would
    x[1, 0] += 1e-6
    system = System(Environment(gravity=(0.0, 0.0, 0.0), air_density=0.0))
    system.add_point(Point('fixed', x[0]))
    system.add_point(Point('fixed', x[-1]))
    system.add_line(Line.uniform(kind, L0, segments, x, (0, 1), break_load=break_load))
    system.pack()
    return system


@pytest.mark.parametrize('segments, bound', [(40, 0.01), (100, 0.002)])
def test_the_free_end_flies_back_at_strain_times_wave_speed(segments, bound):
    # every segment pulls EA eps = 500 kN: past a 495 kN break load the first one from A
    # parts, and piece B's free end (particle 1) flies towards B
    system = _bar(segments, 0.99 * EA * EPS)
    before = system.energy()
    dt = 1e-5
    drive_x, drive_v = system.drive_arrays(1)
    times, ends, parted = [], [], []
    for k in range(int(round(2.0 * L0 / WAVE / dt))):
        parted += step(system, 'implicit_euler', dt, drive_x, drive_v, 200)
        times.append((k + 1) * dt)
        ends.append(system.x[1, 0])
    assert parted == [(0, 0)] and system.lines[0].parted == 0  # once, at the first step
    t1 = L0 / WAVE
    ends, times = np.array(ends), np.array(times)
    speed = (np.interp(2.0 * t1, times, ends) - np.interp(0.2 * t1, times, ends)) / (1.8 * t1)
    print(f'N {segments}: free end {speed:.3f} m/s, eps c {EPS * WAVE:.3f} m/s')
    assert speed == pytest.approx(EPS * WAVE, rel=bound)  # measured 0.34 % and 0.02 %
    kinetic, _, elastic = system.energy()
    assert before[2] == pytest.approx(100.0e3, rel=1e-8) and elastic < 1.0  # all released
    # less what the dampers took: 84.42 kJ for the converged damped chain (the reference's)
    assert kinetic == pytest.approx(84.42e3, rel=0.02)
    assert np.isfinite(system.x).all() and np.isfinite(system.v).all()


def _jerked(material='polyester', **values):
    # the reference line (polyester unless said) pulled 3 m past taut in 1 s: far past its MBL
    params = reference_params(material, 20, **values)
    sim = OneLine(params, history=math.inf)
    fairlead = np.array([38.0, 0.0, 8.0])
    for k in range(31):
        sim.push_fairlead(0.1 * k, fairlead + [min(0.3 * k, 3.0) if k > 5 else 0.0, 0, 0])
    sim.start(0.0)
    return sim


def test_a_line_pulled_past_its_break_load_parts_once_and_both_pieces_hang():
    sim = _jerked(break_load=2.0e5)
    outputs, partings = sim.run(np.arange(0.02, 3.0, 0.02))
    assert len(partings) == 1
    parting = partings[0]
    assert 0.5 < parting.t < 1.5 and parting.break_load == 2.0e5
    peaks = np.array([o.fairlead_peak for o in outputs])
    assert peaks.max() >= 2.0e5 * 0.98  # the peak that parted it is seen
    after = [o for o in outputs if o.t > parting.t + 1.5]
    assert all(o.parted for o in after) and all(np.isfinite(o.positions).all() for o in after)
    # the pieces whip and swing from their ends (1 kN of line): the 200 kN are gone
    assert after[-1].fairlead_tension + after[-1].bollard_tension < 0.05 * 2.0e5
    assert math.isinf(sim.reach)
    # restored where its ends still stand, 3 m past taut, it cannot hold its break load
    # whole: it parts again at once, and pulls no more than its pieces do
    sim.restore()
    again = sim.output()
    assert again.parted and again.fairlead_tension + again.bollard_tension < 0.05 * 2.0e5
    # with the fairlead back where the line hangs, it is restored whole
    sim.push_fairlead(3.1, np.array([38.0, 0.0, 8.0]))
    sim.advance_to(3.1)
    sim.restore()
    whole = sim.output()
    assert not whole.parted and whole.line_length == L0 and sim.system.lines[0].parted is None


@pytest.mark.parametrize('integrator', ['adaptive', 'implicit_euler'])
def test_a_parted_wires_piece_falls_into_the_water_and_sinks(integrator):
    # the reference wire jerked past 200 kN over water 10 m below its bollard: the long piece
    # falls through the surface. The parted segment's rest length (1e300 m) once made its
    # end 6.5e294 m wet there: a division by zero under the adaptive step, and under implicit
    # Euler the piece thrown back out of the water at 211 kN, then 4.4 MN
    level = -10.0
    sim = _jerked('wire', break_load=2.0e5, water_level=level, integrator=integrator)
    outputs, partings = sim.run(np.arange(0.02, 4.0 + 1e-9, 0.02))
    assert len(partings) == 1 and 0.3 < partings[0].t < 1.0
    assert all(np.isfinite(o.positions).all() and np.isfinite(o.fairlead_force).all()
               and np.isfinite(o.bollard_force).all() for o in outputs)
    after = [o for o in outputs if o.t > partings[0].t]
    # the pieces whip and hang (2.5 kN of wire in all): never the break load again (seen:
    # 40 kN adaptive, 36 kN implicit Euler)
    assert max(max(o.fairlead_tension, o.bollard_tension) for o in after) < 2.0e5
    # 6.5 kg/m of wire displacing 2.1 kg/m of water: in the water it goes on sinking
    lowest = {round(o.t, 2): o.positions[:, 2].min() for o in after}
    assert lowest[4.0] < lowest[3.0] < level
    # the drag holds it back: at 4 s 2.9 m (adaptive), 3.8 m (implicit Euler) below the level
    assert lowest[4.0] > level - 5.0


def test_parting_off_holds_any_tension():
    sim = _jerked(break_load=2.0e5, parting=False)
    sim.advance_to(2.0)
    out = sim.output()
    assert not out.parted and out.fairlead_tension > 2.0e5


def test_the_offline_runner_writes_the_peak_the_length_and_parted(tmp_path):
    motion = tmp_path / 'motion.csv'
    rows = ['t,fairlead_x,fairlead_y,fairlead_z,winch_speed']
    rows += [f'{0.1 * k:.1f},{38.0 + (min(0.3 * (k - 5), 3.0) if k > 5 else 0.0)},0,8,'
             f'{-0.2 if k < 5 else 0.0}' for k in range(31)]
    motion.write_text('\n'.join(rows) + '\n')
    out = tmp_path / 'out.csv'
    run_motion(single_line(reference_params('polyester', 20, break_load=2.0e5,
                                            winch_mode='speed')),
               read_motion(motion), out, rate=50.0)
    table = np.genfromtxt(out, delimiter=',', names=True)
    assert table.dtype.names == LINE_COLUMNS + (STATE_COLUMN,)
    assert np.all(table['fairlead_peak_tension'] >= table['fairlead_tension'] - 1e-6)
    assert table['line_length'][0] == L0 and table['line_length'].min() < L0 - 0.05
    assert set(np.unique(table['parted'])) == {0.0, 1.0}
    first = np.flatnonzero(table['parted'])[0]
    assert np.all(table['parted'][first:] == 1.0)
    assert table['fairlead_peak_tension'][first] > 1.9e5  # the snap's peak, in its row


def test_a_free_ships_line_parting_at_its_fairlead_beside_fast_lines_leaves_the_run_going():
    # The berth's free ship held off the fenders by lines made fast at run time while a
    # ship passes: spring_aft, alone on the ship's side, takes the passing ship's pull and
    # parts in its last segment, at the fairlead, while the others are stepped with the ship
    # in one implicit group. Such a parting once stopped the run (a division by zero in the
    # compiled step) or restarted the ship: here it goes on, the ship where it was, the piece
    # hanging from its bollard.
    overrides = {'ship_mode': 'free', 'publish_rate': 10.0,
                 'ship': {'start_position': [0.0, -20.6, 0.0]},
                 'passing_ship': {'speed': 5.0, 'length': 200.0, 'beam': 32.0, 'draft': 12.0,
                                  'block_coefficient': 0.8, 'separation': 57.0,
                                  'start_x': -175.0, 'direction': 1}}
    for name, length in (('spring_fwd', 51.0), ('breast_fwd', 17.0), ('breast_aft', 17.0)):
        overrides[name] = {'start_state': 'stowed', 'length': length,
                           'winch_mode': 'constant_tension', 'winch_tension': 1.0e4,
                           'winch_max_speed': 0.25}
    setup = read_setup(REPO_ROOT / 'config' / 'berth.yaml', flatten(overrides))
    names = [line.name for line in setup.lines]
    spring_aft = names.index('spring_aft')
    driver = Driver(setup, rate=10.0)
    driver.start_free(0)
    published, partings = [], {}
    for t in range(1, 31):
        if t == 10:
            driver.command('spring_fwd', 'make_fast')
        if t == 18:
            driver.command('breast_fwd', 'make_fast')
            driver.command('breast_aft', 'make_fast')
        report = driver.outputs_until(float(t))
        assert not report.faults
        for out in report.outputs:
            if out.advance is not None:
                assert not out.advance.restarted and not out.advance.ship_restarted
                partings.update(out.advance.parted)
            published.append(out.output)
    assert list(partings) == [spring_aft]
    parting = partings[spring_aft]
    segments = len(published[-1].positions[spring_aft]) - 1
    # the passing ship abeam takes it past its break load in its fairlead segment
    assert 23.0 < parting.t < 25.0 and parting.segment == segments - 1
    assert all(o.finite for o in published)
    before = [o for o in published if o.t < parting.t]
    after = [o for o in published if o.t > parting.t + 1.0]
    assert max(o.fairlead_peaks[spring_aft] for o in before) > 0.95 * parting.break_load
    # the ship is not sent back to its start: it moves on smoothly from where it was
    track = np.array([o.ship.position for o in published])
    assert np.abs(np.diff(track, axis=0)).max() < 0.05
    assert np.linalg.norm(track[-1] - track[len(before) - 1]) < 1.0
    # the bollard's piece hangs: its weight on the bollard, next to nothing on the fairlead
    # (9.5 N seen: the parted segment's end particle)
    last = after[-1]
    assert last.parted[spring_aft]
    assert last.fairlead_tensions[spring_aft] < 1.0e-4 * parting.break_load
    assert 0.0 < last.bollard_tensions[spring_aft] < 0.01 * parting.break_load
    piece = last.positions[spring_aft][:-1]
    assert piece[:, 2].min() < piece[0, 2] - 1.0
    # the lines that held on still hold the ship
    held = [k for k in range(len(names)) if k != spring_aft]
    assert all(np.isfinite(last.fairlead_tensions[held]))
    assert last.fairlead_tensions[held].max() > 1.0e5
