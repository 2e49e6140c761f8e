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
No setting blows the rope up: unstable steps are refused, coarse ones divided, far ends held.

Every output of every run here is checked: finite, and within the line's tension_bound.
"""

import math
import os
from pathlib import Path
import re
import subprocess
import sys

import numpy as np
from one_line import OneLine
from physics_cases import reference_params
import pytest
from rope_sim_ros.model.rope import tension_bound
from rope_sim_ros.params.table import from_values, ParameterError
from rope_sim_ros.stepping.rules import automatic_time_step, stability_limit

REPO_ROOT = Path(__file__).resolve().parent.parent
START = np.array([36.0, 0.0, 8.0])
LARGEST = re.compile(r'largest stable step ([0-9.e-]+) s\): set time_step <= ([0-9.e-]+) or 0')


def smoothstep(t, start, duration):
    """0 before start, 1 after start + duration, a smooth S between."""
    s = min(max((t - start) / duration, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


def run(params, fairlead, duration, rate=100.0, sample=0.01):
    """
    Drive the fairlead as a node or `rope_sim run` does (samples one ahead of the state).

    :returns: (simulator, outputs, advances) at every 1/rate s; every output is checked.
    """
    sim = OneLine(params, output_interval=1.0 / rate)
    times = np.arange(0.0, duration + 2.0 * sample, sample)
    pushed = 0

    def feed(until):
        nonlocal pushed
        while pushed < len(times) and (pushed < 2 or times[pushed - 2] < until):
            sim.push_fairlead(float(times[pushed]), fairlead(times[pushed]))
            pushed += 1

    feed(0.0)
    sim.start(0.0)
    samples = np.array([fairlead(t) for t in times])
    speed = (np.linalg.norm(np.diff(samples, axis=0), axis=1) / sample).max()
    # a spline runs up to 1.5 times the secant
    bound = tension_bound(sim.props, sim.environment, 1.5 * speed)
    outputs, advances = [sim.output()], []
    for t in np.arange(1.0, round(duration * rate) + 1.0) / rate:
        feed(t)
        advances.append(sim.advance_to(t))
        if abs(sim.time - t) < 1e-6 * sim.time_step:
            sim.skip_to(t)
        out = sim.output()
        assert np.isfinite(out.positions).all(), f't = {t}'
        assert np.isfinite(out.fairlead_force).all() and np.isfinite(out.bollard_force).all()
        assert max(out.fairlead_tension, out.bollard_tension) <= bound, f't = {t}'
        outputs.append(out)
    return sim, outputs, advances


def jerk(distance, start=0.5, duration=0.5):
    """Pull the fairlead `distance` outward along x in `duration` s."""
    return lambda t: START + [distance * smoothstep(t, start, duration), 0.0, 0.0]


def peak(outputs):
    return max(out.fairlead_tension for out in outputs)


# -- time_step ------------------------------------------------------------------------------

LINES = {
    'reference polyester N20': lambda **kw: reference_params('polyester', 20, **kw),
    'reference wire N50': lambda **kw: reference_params('wire', 50, **kw),
    'nylon N10': lambda **kw: from_values(dict(material='nylon', segments=10, **kw)),
    'hmpe N40, stiff bending': lambda **kw: from_values(dict(
        material='hmpe', segments=40, bending_stiffness_ratio=0.5, **kw)),
    'manila N7, seed damping': lambda **kw: from_values(dict(
        material='manila', segments=7, damping_model='seed', **kw)),
}


def test_the_users_step_is_refused_naming_the_largest_stable_one():
    """improved_euler at 0.5 ms put the jerked reference line at 14.5 MN (converged 53 kN)."""
    with pytest.raises(ParameterError) as error:
        OneLine(reference_params('polyester', 20, integrator='improved_euler',
                                 time_step=0.0005))
    assert str(error.value) == (
        "time_step 0.0005 s is above improved_euler's stability limit for this line (largest "
        'stable step 0.00026 s): set time_step <= 0.00026 or 0 (automatic)')


@pytest.mark.parametrize('line', LINES)
def test_improved_euler_refuses_exactly_the_unstable_steps(line):
    sim = OneLine(LINES[line]())
    limit = stability_limit(sim.props, sim.environment)
    for step in (1.01 * limit, 2.0 * limit, 0.1):
        with pytest.raises(ParameterError, match='above improved_euler') as error:
            OneLine(LINES[line](integrator='improved_euler', time_step=step))
        largest, advised = (float(v) for v in LARGEST.search(str(error.value)).groups())
        # the step quoted is stable and only rounded down (2 significant digits)
        assert largest == advised and 0.9 * limit <= largest <= limit
    for step in (largest, 0.999 * limit, 1e-6):
        assert OneLine(LINES[line](integrator='improved_euler', time_step=step)).time_step \
            == step


@pytest.mark.parametrize('line', ['reference polyester N20', 'reference wire N50',
                                  'hmpe N40, stiff bending'])
def test_improved_euler_at_its_largest_step_matches_the_automatic_step(line):
    sim = OneLine(LINES[line]())
    limit = stability_limit(sim.props, sim.environment)
    _, automatic, _ = run(LINES[line](integrator='improved_euler'), jerk(3.0), 2.0)
    sim, largest, advances = run(
        LINES[line](integrator='improved_euler', time_step=0.999 * limit), jerk(3.0), 2.0)
    assert not any(a.restarted for a in advances)
    # 1.0003, 1.0000 and 1.043 measured
    assert peak(largest) == pytest.approx(peak(automatic), rel=0.1)


def test_a_run_time_change_that_makes_the_step_unstable_is_refused():
    sim = OneLine(reference_params('polyester', 20, integrator='improved_euler',
                                   time_step=0.00025))
    before = sim.props
    for values, largest in (({'axial_damping': 1000.0}, '0.00017'),
                            ({'bending_damping_ratio': 10.0}, '0.00016')):
        expected = (f'with {", ".join(f"{k} = {v}" for k, v in values.items())}, time_step '
                    "0.00025 s is above improved_euler's stability limit for this line "
                    f'(largest stable step {largest} s): set time_step <= {largest} or 0 '
                    '(automatic)')
        with pytest.raises(ParameterError) as error:
            sim.check_update(values)
        assert str(error.value) == expected
        with pytest.raises(ParameterError):
            sim.update(values)
        assert sim.props is before and sim.time_step == 0.00025
    sim.update({'axial_damping': 5000.0})  # more damping, a larger limit (0.00035 s)
    assert sim.props.axial_damping == 5000.0 and sim.time_step == 0.00025


@pytest.mark.parametrize('line', LINES)
def test_implicit_euler_divides_a_coarse_step_into_automatic_ones(line):
    sim = OneLine(LINES[line]())
    automatic = automatic_time_step(sim.props, sim.environment, 'implicit_euler')
    for step in (0.1, 0.01, 1.5 * automatic):
        sim = OneLine(LINES[line](integrator='implicit_euler', time_step=step))
        assert sim.time_step == pytest.approx(step / math.ceil(step / automatic - 1e-9))
        assert sim.time_step <= automatic * (1.0 + 1e-12)
    fine = OneLine(LINES[line](integrator='implicit_euler', time_step=0.5 * automatic))
    assert fine.time_step == 0.5 * automatic


@pytest.mark.parametrize('material, segments, distance', [
    ('wire', 50, 1.0), ('wire', 50, 2.5), ('polyester', 20, 2.0)])
def test_implicit_euler_at_10_ms_stays_near_the_converged_peak(material, segments, distance):
    """Before: 2.68, 3869 and 2.54 times the converged peak; now 1.18, 0.93 and 1.13."""
    _, converged, _ = run(reference_params(material, segments, integrator='improved_euler'),
                          jerk(distance), 3.0)
    _, coarse, _ = run(reference_params(material, segments, integrator='implicit_euler',
                                        time_step=0.01), jerk(distance), 3.0)
    assert 0.5 * peak(converged) < peak(coarse) < 1.5 * peak(converged)


# -- nothing absurd -------------------------------------------------------------------------

@pytest.mark.parametrize('values', [
    dict(material='nylon', segments=13, integrator='improved_euler'),
    dict(material='steel_wire', segments=35),
    dict(material='hmpe', segments=3, integrator='improved_euler'),
    dict(material='manila', segments=64, max_strain=0.01),
    dict(bending_stiffness_ratio=10.0, bending_damping_ratio=10.0),
    dict(air_drag_coefficient=1.0e4, integrator='improved_euler'),
    dict(superelastic_adjustment=False, segments=30),
    dict(max_strain=10.0, integrator='improved_euler', segments=9),
    dict(gravity=[3.0, -2.0, -40.0], damping_model='seed'),
])
def test_a_violent_jerk_stays_finite_and_bounded(values):
    """A 6 m jerk in 0.3 s (to 1.06 L): every output finite and within tension_bound."""
    sim, outputs, advances = run(from_values(values), jerk(6.0, duration=0.3), 3.0)
    assert not any(a.restarted for a in advances)
    assert peak(outputs) > 10.0 * outputs[0].fairlead_tension


@pytest.mark.parametrize('velocity, reason', [
    (1.0e5, 'unphysical state'), (1.0e200, 'non-finite state')])
def test_a_state_past_the_bound_is_restarted_at_rest(velocity, reason):
    """A particle flung at 100 km/s stretches a line without the strain limit 28-fold."""
    # parting off: a line parts long before this bound (test_parting); with it off, the
    # bound is what keeps a fault from being published
    sim = OneLine(from_values({'superelastic_adjustment': False, 'parting': False}))
    sim.push_fairlead(0.0, START)
    sim.start(0.0)
    settled = sim.output().fairlead_tension
    sim.rope.v[1] = [-velocity, 0.0, 0.0]  # finite, but nothing the ends do gets it there
    advance = sim.advance_to(0.05)
    assert advance.restarted == reason
    assert sim.output().fairlead_tension == pytest.approx(settled, rel=1e-9)


def test_the_bound_of_the_reference_line():
    sim = OneLine(reference_params('polyester', 20))
    props, air = sim.props, sim.environment
    # 2 EA max_strain = 25 MN; dampers at twice (c max_strain + sqrt(2 g L)), 3.4 MN; the
    # weight, 1 kN; an end at 10 m/s adds 29 kN
    assert tension_bound(props, air) == pytest.approx(28.27e6, rel=1e-3)
    assert tension_bound(props, air, 10.0) - tension_bound(props, air) == pytest.approx(
        29.03e3, rel=1e-3)


# -- ends beyond reach ----------------------------------------------------------------------

@pytest.mark.parametrize('far', [[120.0, 0.0, 8.0], [1.0e9, 0.0, 8.0], [-30.0, 90.0, -60.0]])
def test_a_fairlead_out_of_reach_is_held_at_the_reach(far):
    """Three lengths away published 95 MN, x = 1e9 m 3.7e15 N: now EA max_strain, 4.4 MN."""
    sim, outputs, advances = run(  # parting off: with it on, the line parts (test_parting)
        from_values({'parting': False}), lambda t: np.array(far) if 1.0 <= t < 3.0 else START,
        5.0)
    ea_strain = sim.props.axial_stiffness * sim.props.max_strain
    held = [out for out in outputs if 1.1 <= out.t < 2.99]
    for out in held:
        assert out.fairlead_tension == pytest.approx(ea_strain, rel=0.01)
        assert np.linalg.norm(out.positions[-1]) == pytest.approx(sim.reach)
    assert max(a.beyond_reach for a in advances) == pytest.approx(np.linalg.norm(far))
    assert peak(outputs) < 1.01 * ea_strain
    # back (a jump: the rope restarts at the new place): the start tension at once
    for out in outputs[301:]:
        assert out.fairlead_tension == pytest.approx(outputs[0].fairlead_tension, rel=0.02)
        assert out.max_strain < 1e-3


@pytest.mark.parametrize('values', [{}, dict(material='steel_wire', segments=50),
                                    dict(integrator='improved_euler', material='nylon')])
def test_a_line_pulled_past_its_reach_and_back_is_never_pinned(values):
    """To 1.5 times the reach in 1 s, held 2 s, back in 1 s: before, pinned at the limit."""
    def fairlead(t):
        s = smoothstep(t, 1.0, 1.0) - smoothstep(t, 4.0, 1.0)
        return START + s * (np.array([75.0, 0.0, 8.0]) - START)

    sim, outputs, advances = run(from_values({**values, 'parting': False}), fairlead, 10.0)
    assert [a.restarted for a in advances if a.restarted] == ['back within reach']
    assert max(a.beyond_reach for a in advances) == pytest.approx(math.hypot(75.0, 8.0),
                                                                  rel=1e-4)
    after = [out for out in outputs if out.t >= 6.0]
    # the slack line swings on (a 48 m excursion that never left the reach rings alike)
    assert max(out.max_strain for out in after) < 0.01
    assert max(out.fairlead_tension for out in after) < 0.01 * sim.props.axial_stiffness


def test_a_line_let_go_at_its_limit_rings_down():
    """
    The default line at 22 % strain let go in 0.05 s: the particles fly at up to 660 m/s.

    5 ms implicit steps linearised about shapes left 3 m behind kept it whipping at the
    strain limit (0.25) with MN tensions for as long as it ran; divided steps let it ring down.
    """
    def fairlead(t):
        return np.array([45.0 - 9.0 * smoothstep(t, 1.0, 0.05), 0.0, 8.0])

    sim, outputs, advances = run(from_values({'segments': 50}), fairlead, 6.0)
    after = [out for out in outputs if out.t >= 3.0]
    assert max(out.max_strain for out in after) < 0.005
    assert max(out.fairlead_tension for out in after) < 0.01 * sim.props.axial_stiffness


# -- ends at one point ----------------------------------------------------------------------

@pytest.mark.parametrize('values, over', [
    ({}, 0.01), (dict(segments=21), 0.01), (dict(material='hmpe', segments=51), 0.01),
    (dict(integrator='improved_euler', segments=8), 0.06)])
def test_ends_at_one_point_hang_still(values, over):
    """Before: the fold's bending springs kicked it open; 2 N to 4.4 kN for 14 s."""
    sim, outputs, _ = run(from_values(values), lambda t: np.zeros(3), 4.0)
    share = 0.5 * sim.props.weight_per_length(sim.environment) * sim.props.length
    tensions = np.array([out.fairlead_tension for out in outputs])
    assert tensions.max() - tensions.min() < 1e-3 * share
    # each end holds half the weight; the bending springs holding the bottom of the fold
    # open add a sideways pull: 0.02 to 0.42 % of the share at N >= 20, 5.6 % with 5 m
    # segments
    lifts = np.array([-out.fairlead_force[2] for out in outputs])
    assert np.all(np.abs(lifts / share - 1.0) < 1e-3)
    assert np.all((tensions / share - 1.0 < over) & (tensions >= lifts))


def test_a_line_hanging_from_one_point_above_the_other_hangs_still():
    sim, outputs, _ = run(from_values({}), lambda t: np.array([0.0, 0.0, 10.0]), 4.0)
    tensions = np.array([out.fairlead_tension for out in outputs])
    assert tensions.max() - tensions.min() < 1e-3 * tensions.mean()


# -- the command line -----------------------------------------------------------------------

def test_rope_sim_run_refuses_an_unstable_step_in_one_line(tmp_path):
    motion = tmp_path / 'motion.csv'
    motion.write_text('t,fairlead_x,fairlead_y,fairlead_z\n0,36,0,8\n0.5,37,0,8\n')
    out = tmp_path / 'out.csv'
    result = subprocess.run(
        [sys.executable, '-m', 'rope_sim_ros', 'run', '--motion', str(motion), '--out',
         str(out), '--quiet', '--set', 'integrator=improved_euler', '--set',
         'time_step=0.01'], env=dict(os.environ, PYTHONPATH=str(REPO_ROOT)),
        capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert result.stderr.count('\n') == 1 and 'Traceback' not in result.stderr
    assert result.stderr.startswith(
        "rope_sim run: error: time_step 0.01 s is above improved_euler's stability limit "
        'for this line (largest stable step ')
    line = OneLine(from_values({}))
    limit = stability_limit(line.props, line.environment)
    largest = float(LARGEST.search(result.stderr).group(1))
    assert 0.9 * limit <= largest <= limit
    assert not out.exists()  # refused before anything was written
