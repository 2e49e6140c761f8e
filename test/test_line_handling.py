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
Lines made fast, let go and stowed at run time: their physics, and every refusal.

The numbers they are held to: a line let go recoils at eps c (the parting test's analytic
bar); a line let go hangs with its weight (in water its submerged weight) on its fairlead;
a stowed line made fast lies on the elastic catenary of its length; a free ship feels a let
go when the release wave reaches its fairlead; a towline pulls a free ship exactly as its
wrench, given to the ship as an external load, does.
"""

import math
import re

import numpy as np
from one_line import OneLine
import pytest
from rope_sim_ros.model.frames import rotation_matrix
from rope_sim_ros.model.statics.catenary import solve_catenary
from rope_sim_ros.mooring.driver import Driver
from rope_sim_ros.mooring.handling import CommandError
from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.mooring.records import mooring_wrench
from rope_sim_ros.mooring.status import bollard_loads
from rope_sim_ros.params.arrangement import from_values
from rope_sim_ros.params.table import from_values as line_values, ParameterError
from test_free_ship import SETTLE_DAMPING, setup as free_ship_setup

LEVEL = [0.0, 0.0, 0.0, 1.0]
# the parting test's bar (test_parting.py): 40 m, EA 50 MN, 2.6 kg/m, stretched 1 %
EA, MASS, L0, EPS = 5.0e7, 2.6, 40.0, 0.01
WAVE = math.sqrt(EA / MASS)  # 4385.29 m/s


def berth(**lines):
    """Return a driven ship's arrangement: two bollards, the lines given by their settings."""
    values = {'lines': list(lines), 'bollards': ['bollard_1', 'bollard_2'],
              'bollard_1': {'position': [40.0, 30.0, 3.0], 'safe_working_load': 2.0e4},
              'bollard_2': {'position': [-40.0, 30.0, 3.0]}, 'segments': 30}
    values.update(lines)
    return from_values(values)


def line(fairlead, bollard, **settings):
    """Return one line's settings: 60 m of the default polyester, with a speed winch."""
    return {'fairlead_offset': list(fairlead), 'bollard': bollard, 'length': 60.0,
            'winch_mode': 'speed', **settings}


def moored(setup, until=0.5):
    """Return a Mooring of a driven ship standing at the origin, run to `until` [s]."""
    mooring = Mooring(setup, output_interval=0.1)
    mooring.push_ship(0.0, [0.0, 0.0, 0.0], LEVEL)
    mooring.push_ship(1000.0, [0.0, 0.0, 0.0], LEVEL)
    mooring.start(0.0)
    mooring.advance_to(until)
    return mooring


def run(mooring, until, every=0.1):
    """Advance to `until` [s]; return (time, output) at every `every` [s] on the way."""
    outputs = []
    for t in np.arange(mooring.time + every, until + 1e-9, every):
        mooring.advance_to(t)
        outputs.append((mooring.time, mooring.output()))
    return outputs


@pytest.mark.parametrize('integrator', ['adaptive', 'improved_euler'])
def test_a_taut_line_let_go_recoils_at_strain_times_wave_speed(integrator):
    params = line_values(dict(
        segments=100, length=L0, mass_per_length=MASS, axial_stiffness=EA,
        axial_damping=2903.43, bending_stiffness_ratio=0.0, bending_damping_ratio=0.0,
        air_drag_coefficient=0.0, air_density=0.0, gravity=[0.0, 0.0, 0.0],
        bollard_position=[0.0, 0.0, 0.0], superelastic_adjustment=False,
        integrator=integrator))
    sim = OneLine(params, history=math.inf)
    sim.push_fairlead(0.0, [L0 * (1.0 + EPS), 0.0, 0.0])
    sim.push_fairlead(10.0, [L0 * (1.0 + EPS), 0.0, 0.0])
    sim.start(0.0)
    sim.advance_to(0.1)  # some steps first: the snap watch compares a step with the one before
    assert sim.output().fairlead_tension == pytest.approx(EA * EPS, rel=1e-6)
    start = sim.time
    assert 'let go' in sim.mooring.command(0, 'let_go')
    t1 = L0 / WAVE  # the release wave reaches the fairlead
    times, ends = [0.0], [sim.rope.x[0, 0]]
    for t in start + np.linspace(0.0, 2.0 * t1, 100)[1:]:
        sim.advance_to(t)
        times.append(sim.time - start)
        ends.append(sim.rope.x[0, 0])
    speed = (np.interp(2.0 * t1, times, ends) - np.interp(0.2 * t1, times, ends)) / (1.8 * t1)
    assert speed == pytest.approx(EPS * WAVE, rel=0.02)  # measured -0.11 % with both


@pytest.mark.parametrize('water', [False, True])
def test_a_line_let_go_hangs_from_its_fairlead_with_its_weight(water):
    top = -5.0 if water else 50.0
    values = dict(segments=20, length=40.0, bollard_position=[2.0, 0.0, top - 39.0])
    if water:  # wholly under water, far above the sea bed
        values.update(water_level=0.0, seabed_level=-200.0)
    sim = OneLine(line_values(values), history=math.inf)
    sim.push_fairlead(0.0, [0.0, 0.0, top])
    sim.push_fairlead(1000.0, [0.0, 0.0, top])
    sim.start(0.0)
    sim.advance_to(0.5)
    sim.mooring.command(0, 'let_go')
    forces = []
    for t in np.arange(1.0, 90.0, 0.1):
        sim.advance_to(t)
        out = sim.output()
        forces.append((out.t, -out.fairlead_force[2]))
        assert np.isfinite(out.positions).all()
    forces = np.array(forces)
    props, environment = sim.props, sim.environment
    density = environment.water_density if water else environment.air_density
    weight = (props.mass_per_length - density * props.volume_area) * props.length * 9.81
    late = forces[forces[:, 0] > 60.0, 1]
    # in air it still swings from its 2 m start offset (+-1.3 %): its mean is its weight
    assert late.mean() == pytest.approx(weight, rel=0.005)  # measured 5e-5, 6e-8 in water
    if water:  # the drag has settled it
        assert late.max() == pytest.approx(weight, rel=0.005)
        assert late.min() == pytest.approx(weight, rel=0.005)
    eye = sim.output().positions[0]
    assert eye[2] < top - 39.0  # it hangs under where the bollard stood


def test_a_stowed_line_made_fast_lies_at_rest_on_its_catenary():
    mooring = moored(berth(head=line([0.0, 0.0, 10.0], 'bollard_1', start_state='stowed',
                                     winch_mode='brake')))
    out = mooring.output()
    assert out.states == ('stowed',)
    assert out.fairlead_tensions[0] == 0.0 and np.ptp(out.positions[0], axis=0).max() == 0.0
    text = mooring.command(0, 'make_fast')
    assert text == 'line head made fast to bollard_1: 53.0 m out, 50.5 m from the fairlead'
    rope, props, environment = mooring.lines[0], mooring.lines[0].line_props, mooring.environment
    fairlead, bollard = np.array([0.0, 0.0, 10.0]), np.array([40.0, 30.0, 3.0])
    assert rope.length == pytest.approx(1.05 * np.linalg.norm(fairlead - bollard), rel=1e-12)
    weight = (props.mass_per_length - environment.air_density * props.volume_area) * 9.81
    catenary = solve_catenary(50.0, 7.0, rope.length, weight, props.axial_stiffness)
    for t, out in [(mooring.time, mooring.output()), *run(mooring, 20.0)[-1:]]:
        assert out.states == ('fast',)
        assert out.fairlead_tensions[0] == pytest.approx(catenary.tension_b, rel=0.005), t
    # measured -0.034 % at the make fast and 20 s later: it was at rest


def test_a_constant_tension_winch_heaves_a_line_made_fast_to_its_tension():
    mooring = moored(berth(head=line([0.0, 0.0, 10.0], 'bollard_1', start_state='stowed')))
    mooring.command(0, 'make_fast')
    mooring.update(0, {'winch_mode': 'constant_tension', 'winch_tension': 5.0e4})
    tensions = np.array([out.fairlead_tensions[0] for _, out in run(mooring, 120.0)])
    # from 1.5 kN slack: it rings about its set tension as the winch answers, and settles
    assert tensions[-200:].mean() == pytest.approx(5.0e4, rel=0.01)
    assert tensions[-1] == pytest.approx(5.0e4, rel=0.01)  # measured -0.27 %
    assert mooring.lines[0].length < 53.0


def test_a_free_ship_feels_a_let_go_when_the_release_wave_reaches_its_fairlead():
    ships = []
    for _ in range(2):
        mooring = Mooring(free_ship_setup(SETTLE_DAMPING), output_interval=0.1)
        mooring.start(0.0)
        for i in range(1, 51):
            mooring.advance_to(0.1 * i)
        ships.append(mooring)
    let_go, held = ships
    start, dt = let_go.time, let_go.time_step
    assert let_go.command(0, 'let_go').startswith('line head let go')
    head = let_go.lines[0]
    arrival = head.length / math.sqrt(head.props.axial_stiffness / head.props.mass_per_length)
    times, ratios, speeds = [], [], []
    for k in range(1, 40):
        for mooring in ships:
            mooring.advance_to(start + k * dt)
        forces = [np.linalg.norm(m.output().fairlead_forces[0]) for m in ships]
        times.append(let_go.time - start)
        ratios.append(forces[0] / forces[1])
        speeds.append(let_go.body.velocity[0] - held.body.velocity[0])
    half = np.interp(-0.5, -np.array(ratios), times)  # the fairlead's pull half gone
    # the wave takes L / c = 17.8 ms to the fairlead; the pull is half gone at 16.7 ms
    assert 0.8 * arrival < half < arrival + dt
    assert ratios[-1] < 0.05  # the line hangs from the fairlead: a few per cent of its pull
    assert abs(speeds[-1]) > 1e-7  # and the ship moves otherwise from then on


def test_a_towline_pulls_a_free_ship_as_its_wrench_says():
    def tow(state):
        return from_values({
            'lines': ['tow'], 'ship_mode': 'free', 'air_density': 0.0, 'segments': 20,
            'ship.start_position': [0.0, -17.6, 0.0],
            'tow': {'fairlead_offset': [112.0, 0.0, 10.0], 'length': 90.0, 'material': 'nylon',
                    'bollard_position': [200.0, -17.6, 5.0], 'start_state': state}})

    dt, duration = 0.05, 120.0
    towed = Mooring(tow('fast'), output_interval=dt)
    towed.start(0.0)
    for i in range(int(duration / dt) + 2):  # the tug, 0.1 m/s ahead from 2 s
        t = i * dt
        towed.push_bollard(0, t, [200.0 + 0.1 * max(t - 2.0, 0.0), -17.6, 5.0])
    times, loads = [], []
    for i in range(int(duration / dt) + 1):
        if i:
            towed.advance_to(i * dt)
        _, orientation = towed.ship_pose(towed.time)
        rotation = rotation_matrix(orientation)
        force, moment = mooring_wrench(towed.output().fairlead_forces, towed.offsets,
                                       orientation)
        times.append(towed.time)
        loads.append(np.concatenate([rotation @ force, rotation @ moment]))
    assert max(np.linalg.norm(load[:3]) for load in loads) < 6.0e5  # whole: below its MBL
    pushed = Mooring(tow('stowed'), output_interval=dt)  # its line aboard, the wrench a load
    pushed.start(0.0)
    pushed.set_load_schedule(np.array(times), np.array(loads))
    for i in range(1, int(duration / dt) + 1):
        pushed.advance_to(i * dt)
    moved = towed.ship_pose(towed.time)[0] - [0.0, -17.6, 0.0]
    assert moved[0] > 10.0  # measured 15.45 m
    difference = towed.ship_pose(towed.time)[0] - pushed.ship_pose(pushed.time)[0]
    assert np.abs(difference).max() < 1e-3 * moved[0]  # measured 1.0 mm
    assert pushed.body.velocity[0] == pytest.approx(towed.body.velocity[0], rel=1e-3)


def test_a_bollard_load_is_the_sum_of_the_forces_of_the_lines_fast_on_it():
    setup = berth(head=line([10.0, 0.0, 10.0], 'bollard_1', length=55.0),
                  breast=line([0.0, 0.0, 10.0], 'bollard_1', length=55.0),
                  stern=line([-10.0, 0.0, 10.0], 'bollard_2', length=55.0))
    mooring = moored(setup)
    out = mooring.output()
    loads = {load.name: load for load in bollard_loads(setup, out.states, out.bollard_forces)}
    first = loads['bollard_1']
    assert first.lines == ('head', 'breast')
    assert np.allclose(first.force, out.bollard_forces[0] + out.bollard_forces[1], rtol=1e-12)
    assert first.over == (first.load > 2.0e4)
    assert loads['bollard_2'].lines == ('stern',) and not loads['bollard_2'].over
    mooring.command(1, 'let_go')  # off the bollard: its force is no more the bollard's
    out = mooring.output()
    first = bollard_loads(setup, out.states, out.bollard_forces)[0]
    assert first.lines == ('head',)
    assert np.allclose(first.force, out.bollard_forces[0], rtol=1e-12)


def test_a_line_let_go_heaved_in_and_stowed_is_out_of_the_steps():
    mooring = moored(berth(head=line([0.0, 0.0, 10.0], 'bollard_1', length=55.0),
                           stern=line([-10.0, 0.0, 10.0], 'bollard_2', length=55.0)))
    mooring.command(0, 'let_go')
    mooring.command_winch(0, -1.0)
    outputs = run(mooring, 70.0)
    assert all(out.finite for _, out in outputs)
    out = outputs[-1][1]
    assert out.line_lengths[0] == pytest.approx(5.5, abs=1e-3)  # a tenth: winch_min_length
    assert mooring.command(0, 'stow') == 'line head stowed'
    assert [group.members for group in mooring.groups] == [[1]]
    out = run(mooring, 71.0)[-1][1]
    assert out.states == ('stowed', 'fast') and out.fairlead_tensions[0] == 0.0
    assert np.allclose(out.positions[0], [0.0, 0.0, 10.0])
    # made fast again, it comes out slack to its bollard
    assert mooring.command(0, 'make_fast').startswith('line head made fast to bollard_1')
    assert run(mooring, 72.0)[-1][1].states == ('fast', 'fast')


def test_a_line_let_go_at_its_working_load_limit_recoils_without_a_fault():
    setup = berth(head=line([0.0, 0.0, 10.0], 'bollard_1', length=55.0))
    driver = Driver(setup, rate=50.0)
    wll = driver.ratings[0].wll
    # pull it to its WLL: the ship stands where the pretension catenary puts that tension
    values = setup.values()
    del values['head']['length']
    values['head']['pretension'] = wll
    driver = Driver(from_values(values), rate=50.0)
    for k in range(3):
        driver.push_ship(k * 20_000_000, [0.0, 0.0, 0.0], LEVEL)
    driver.outputs_until(0.04)
    assert driver.mooring.output().fairlead_tensions[0] == pytest.approx(wll, rel=0.01)
    driver.command('head', 'let_go')
    outputs = []
    for k in range(3, 503):  # 10 s on
        driver.push_ship(k * 20_000_000, [0.0, 0.0, 0.0], LEVEL)
        report = driver.outputs_until((k - 1) * 0.02)
        assert not report.faults and report.skipped == 0.0
        outputs += report.outputs
    stamps = np.array([published.output.t for published in outputs])
    assert len(stamps) > 490 and np.allclose(np.diff(stamps), 0.02)  # none skipped
    assert all(published.output.finite for published in outputs)
    assert max(p.output.fairlead_tensions[0] for p in outputs) < wll


def test_a_quick_release_hook_lets_go_past_its_load():
    setup = berth(head=line([0.0, 0.0, 10.0], 'bollard_1', length=55.0, release_load=3.0e4))
    mooring = moored(setup)
    assert mooring.lines[0].state == 'fast'
    # the ship moves off the quay: the line comes taut past 30 kN
    mooring.push_ship(1000.5, [0.0, -8.0, 0.0], LEVEL)
    released = {}
    for t in np.arange(1.0, 60.0, 0.1):
        done = mooring.advance_to(t)
        released.update(done.released)
        if released:
            break
    assert list(released) == [0] and released[0] > 3.0e4
    assert mooring.lines[0].state == 'free'
    assert mooring.output().states == ('free',)


def test_commands_that_do_not_fit_are_refused_naming_the_state_and_nothing_changes():
    mooring = moored(berth(head=line([0.0, 0.0, 10.0], 'bollard_1', length=55.0),
                           stern=line([-10.0, 0.0, 10.0], 'bollard_2', start_state='stowed',
                                      winch_max_length=45.0)))
    cases = [
        (0, 'make_fast', 'line head is already fast to bollard_1'),
        (1, 'let_go', 'line stern is not fast (stowed aboard): there is nothing to let go'),
        (0, 'stow', 'line head is fast on its bollard: only a line let go and heaved in can '
                    'be stowed'),
        (1, 'make_fast', 'line stern cannot reach bollard_2: it is 43.0 m from the fairlead, '
                         'and 45.1 m with make_fast_slack 0.05 is more than the 45.0 m the '
                         'line has (winch_max_length)'),
        (0, 'heave', "command 'heave' is not one of make_fast, let_go, stow, let_go_all"),
    ]
    for k, command, text in cases:
        before = mooring.output()
        with pytest.raises(CommandError) as e:
            mooring.command(k, command)
        assert str(e.value) == text
        assert mooring.output().states == before.states
    mooring.command(0, 'let_go')
    with pytest.raises(CommandError, match=r'line head still has 49\.5 m more out than its '
                       r'winch_min_length \(55\.0 m, shortest 5\.5 m\): heave it in first'):
        mooring.command(0, 'stow')
    with pytest.raises(CommandError, match='no line is fast: there is nothing to let go'):
        mooring.command(0, 'let_go_all')
    mooring.update(0, {'bollard': 'bollard_2'})  # free: it may go to another bollard
    assert mooring.arrangement.lines[0].bollard == 'bollard_2'
    with pytest.raises(ParameterError, match=re.escape(
            "'head.bollard' = 'bollard_3' is not a bollard: bollards are bollard_1, bollard_2; "
            "did you mean 'bollard_2'?")):
        mooring.update(0, {'bollard': 'bollard_3'})
    mooring.command(0, 'make_fast')
    with pytest.raises(ParameterError, match="'head.bollard' cannot change while line head "
                       'is fast: let it go first'):
        mooring.update(0, {'bollard': 'bollard_1'})


@pytest.mark.parametrize('values, text', [
    ({'bollards': ['b1'], 'b1': {}}, "bollard 'b1' is missing settings: set b1.position"),
    ({'bollards': ['head']}, "bollard name 'head' in 'bollards' is taken"),
    ({'bollards': ['b1'], 'b1': {'position': [0, 0, 0], 'swl': 1}},
     'unknown parameter b1.swl; a bollard takes: position, safe_working_load'),
    ({'head.bollard': 'b2', 'bollards': ['b1'], 'b1': {'position': [0, 0, 0]}},
     "'head.bollard' = 'b2' is not a bollard: bollards are b1"),
    ({'head.bollard': 'b1', 'head.bollard_position': [1, 2, 3], 'bollards': ['b1'],
      'b1': {'position': [0, 0, 0]}}, "line 'head' sets both bollard and bollard_position"),
    ({'head.start_state': 'free'}, "'head.start_state' = 'free' is not allowed"),
    ({'head.make_fast_slack': -0.1}, "'head.make_fast_slack' = -0.1 is not allowed"),
])
def test_bad_bollards_and_line_states_are_refused_in_one_line(values, text):
    base = {'lines': ['head'], 'head': {'fairlead_offset': [0, 0, 10], 'length': 50.0,
                                        'bollard_position': [40, 30, 3]}}
    base['head'] = {**base['head'], **{k.partition('.')[2]: v for k, v in values.items()
                                       if k.startswith('head.')}}
    if 'head.bollard' in values and 'head.bollard_position' not in values:
        del base['head']['bollard_position']
    base.update({k: v for k, v in values.items() if not k.startswith('head.')})
    with pytest.raises(ParameterError) as e:
        from_values(base)
    assert text in str(e.value) and '\n' not in str(e.value)


def test_a_line_named_to_a_bollard_keeps_it_through_a_parameter_dump():
    setup = berth(head=line([0.0, 0.0, 10.0], 'bollard_1', start_state='stowed'))
    again = from_values(setup.values())
    assert again == setup
    assert again.lines[0].params.bollard_position == [40.0, 30.0, 3.0]
