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
A ship's arrangement of lines stepped in one System (mooring/mooring.py, mooring/driver.py).

Eight lines stepped together against the same eight lines each run alone (a Driver of a
mooring of that one line), the total wrench against the per-line forces and against a hand
computation, pretension, the Driver's rules on an arrangement (skip ahead, clock back, rate
change, the bollards' levers), and the one-line refusals of bad arrangements
(params/arrangement.py).
"""

import math

import numpy as np
import pytest
from rope_sim_ros.model import frames
from rope_sim_ros.model.statics.catenary import solve_catenary
from rope_sim_ros.model.statics.pretension import length_for_tension, PretensionError
from rope_sim_ros.mooring.driver import Driver, SHIP
from rope_sim_ros.mooring.records import mooring_wrench
from rope_sim_ros.params import arrangement
from rope_sim_ros.params.table import ParameterError

T0 = 1_000_000_000  # [ns] the first pose's stamp
SECOND = 1_000_000_000
RATE = 50.0
SHIP_Y = -18.0  # the ship's centreline, 18 m off the quay face (world y = 0)
# Eight lines of a ship lying port side to the quay (body y to port = world y towards the
# quay), heading +x: offsets in the body frame, bollards on the quay in the world frame;
# each about 5 % of its MBL at rest (lengths from length_for_tension, to the millimetre).
BERTH = {
    'head_1': dict(material='polyester', fairlead_offset=[95.0, 12.0, 12.0],
                   bollard_position=[140.0, 6.0, 2.5], length=47.364),
    'head_2': dict(material='nylon', diameter=0.056, fairlead_offset=[93.0, 13.0, 12.0],
                   bollard_position=[135.0, 8.0, 2.5], length=44.537),
    'breast_fwd': dict(material='polyester', fairlead_offset=[70.0, 15.0, 11.0],
                       bollard_position=[72.0, 10.0, 2.5], length=15.605, segments=8),
    'spring_fwd': dict(material='hmpe', diameter=0.04, fairlead_offset=[40.0, 15.0, 11.0],
                       bollard_position=[-5.0, 6.0, 2.5], length=46.63),
    'spring_aft': dict(material='steel_wire', diameter=0.036, fairlead_offset=[-40.0, 15.0, 11.0],
                       bollard_position=[5.0, 6.0, 2.5], length=46.652),
    'breast_aft': dict(material='polyester', fairlead_offset=[-70.0, 15.0, 11.0],
                       bollard_position=[-72.0, 10.0, 2.5], length=15.605, segments=8),
    'stern_1': dict(material='nylon', fairlead_offset=[-95.0, 12.0, 12.0],
                    bollard_position=[-140.0, 6.0, 2.5], pretension=80.0e3),
    'stern_2': dict(material='polyester', fairlead_offset=[-93.0, 13.0, 12.0],
                    bollard_position=[-135.0, 8.0, 2.5], length=44.821),
}


def berth_values(**top):
    """Return the eight-line arrangement's parameter values, 12 segments a line by default."""
    return {'lines': list(BERTH), 'segments': 12, 'publish_rate': RATE, **BERTH, **top}


def ship_pose(t):
    """Surge, sway, yaw and roll of a ship at the berth: (position, quaternion (x, y, z, w))."""
    surge = 0.3 * math.sin(2.0 * math.pi * t / 7.0)
    sway = 0.3 * math.sin(2.0 * math.pi * t / 9.0)
    yaw = 0.004 * math.sin(2.0 * math.pi * t / 11.0)
    roll = 0.02 * math.sin(2.0 * math.pi * t / 5.0)
    cy, sy, cr, sr = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(roll / 2), math.sin(roll / 2)
    return [surge, SHIP_Y + sway, 0.1 * math.sin(t)], [cy * sr, sy * sr, sy * cr, cy * cr]


def run_arrangement(values, seconds=3.0, pose=ship_pose, rate=RATE, winches=None):
    """
    Drive a Driver with ship poses at `rate` for `seconds`; return it and its outputs.

    :param winches: {line: speed [m/s]} commanded before the first pose.
    """
    driver = Driver(arrangement.from_values(values), rate=rate, history=math.inf)
    for name, speed in (winches or {}).items():
        driver.command_winch(name, speed)
    outputs = []
    for i in range(round(seconds * rate) + 1):
        t = i / rate
        position, orientation = pose(t)
        driver.push_ship(T0 + round(t * 1e9), position, orientation)
        outputs += driver.advance(math.inf, max_lag=math.inf).outputs
    driver.silence(SHIP)
    outputs += driver.advance(seconds, max_lag=math.inf).outputs
    return driver, outputs


def run_single(params, seconds=3.0, pose=ship_pose, rate=RATE, winch=None):
    """
    Drive one line alone with the same poses; return its outputs.

    A Driver of a mooring of that one line (single_line): its fairlead is the pose with
    the line's fairlead_offset, as in the arrangement.
    """
    driver = Driver(arrangement.single_line(params), rate=rate, history=math.inf)
    if winch is not None:
        driver.command_winch('', winch)
    outputs = []
    for i in range(round(seconds * rate) + 1):
        t = i / rate
        position, orientation = pose(t)
        driver.push_ship(T0 + round(t * 1e9), position, orientation)
        outputs += driver.advance(math.inf, max_lag=math.inf).outputs
    driver.silence(SHIP)
    outputs += driver.advance(seconds, max_lag=math.inf).outputs
    return outputs


def rotation_matrix(q):
    """Return the rotation matrix of a unit quaternion (x, y, z, w), written out by hand."""
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


@pytest.fixture(scope='module')
def eight_lines():
    """
    Run the eight-line berth together for 3 s, with implicit_euler.

    The adaptive integrator decides on each line alone, but by the line's tensions: the lines
    of an arrangement keep their step times to a few ulp of the lines alone, and where a
    line's tension change is that close to the snap threshold, one decides to take the step
    again and the other does not. So the equality to round-off is tested with implicit_euler.
    """
    return run_arrangement(berth_values(integrator='implicit_euler'))


# ------------------------------------------------------------------ lines together = alone


def test_eight_lines_together_step_as_eight_lines_alone(eight_lines):
    driver, together = eight_lines
    mooring = driver.mooring
    assert len(together) == 151  # 3 s at 50 Hz, from the first pose
    # lines of equal steps share a System: one kernel call per step a line takes
    steps = {line.time_step for line in mooring.lines}
    assert 1 < mooring.kernel_calls == len(steps) < len(mooring.lines)
    for k, line in enumerate(driver.arrangement.lines):
        alone = run_single(line.params)  # at its own step, as in the arrangement
        assert [o.stamp_ns for o in alone] == [o.stamp_ns for o in together], line.name
        for key in ('fairlead_force', 'bollard_force', 'fairlead_peak', 'bollard_peak'):
            mine = np.array([getattr(o.output, key + 's')[k] for o in together])
            single = np.array([getattr(o.output, key + 's')[0] for o in alone])
            scale = np.abs(single).max()
            assert scale > 1.0e3, line.name  # the lines pull: a real comparison
            assert np.abs(mine - single).max() <= 1e-9 * scale, (line.name, key)
        positions = np.array([o.output.positions[k] for o in together])
        assert np.abs(positions - np.array([o.output.positions[0] for o in alone])).max() < 1e-9


def test_peaks_hold_every_steps_tension_not_only_the_outputs(eight_lines):
    # The outputs sample at 50 Hz, the lines step at 2.5 to 5 ms: the peak since the previous
    # output is never below the tension at it, and on the snatching breast lines and springs
    # it is kilonewtons above every sampled tension around it.
    _, outputs = eight_lines
    for end in ('fairlead', 'bollard'):
        tensions = np.array([getattr(o.output, end + '_tensions') for o in outputs])
        peaks = np.array([getattr(o.output, end + '_peaks') for o in outputs])
        assert (peaks >= tensions).all()
        between = np.maximum(tensions[1:], tensions[:-1])  # the samples either side
        assert (peaks[1:] - between).max() > 1.0e3, end


def test_lines_pull_and_the_ship_moves_them(eight_lines):
    _, outputs = eight_lines
    tensions = np.array([o.output.fairlead_tensions for o in outputs])
    # every line pulls, and the motion changes its tension by more than 5 % (some go slack)
    assert tensions.max(axis=0).min() > 10.0e3
    swing = (tensions.max(axis=0) - tensions.min(axis=0)) / tensions.mean(axis=0)
    assert swing.min() > 0.05, swing


# ------------------------------------------------------------------ the total wrench


def test_wrench_is_the_sum_of_the_fairlead_forces_and_their_moments(eight_lines):
    driver, outputs = eight_lines
    offsets = np.array([line.params.fairlead_offset for line in driver.arrangement.lines])
    for published in outputs[::10]:
        t = published.output.t
        position, orientation = ship_pose(round(t * RATE) / RATE)  # outputs on pose times
        rotation = rotation_matrix(orientation)
        forces = published.output.fairlead_forces  # world frame
        body = forces @ rotation  # R^T F for each row
        force = body.sum(axis=0)
        moment = sum(np.cross(o, f) for o, f in zip(offsets, body))
        assert np.allclose(published.force, force, rtol=0, atol=1e-9 * np.abs(force).max())
        assert np.allclose(published.moment, moment, rtol=0,
                           atol=1e-9 * np.abs(moment).max())
        # the world copy: the same force and moment about the ship's origin, world axes
        levers = offsets @ rotation.T
        world_force, world_moment = published.world_wrench()
        assert np.allclose(world_force, forces.sum(axis=0), atol=1e-6)
        assert np.allclose(world_moment, np.cross(levers, forces).sum(axis=0),
                           atol=1e-9 * np.abs(world_moment).max())
        assert np.allclose(published.fairlead_levers, levers, atol=1e-12)
        assert np.allclose(published.ship_position, position, atol=1e-12)


def test_wrench_of_two_lines_by_hand():
    # A ship at rest at the origin, turned 90 degrees (its x axis along world y), held by
    # two polyester lines, one ahead and one astern, each from a bollard 10 m below its
    # fairlead: the ahead line over a 30 m span (32 m long), the astern one over 25 m
    # (26.5 m long). Each pulls its fairlead with its catenary's end force: H along the
    # line towards its bollard, V_B down. In the body frame the ahead line pulls +x, the
    # astern one -x; the fairleads sit at (+-40, 5, 10).
    yaw = math.pi / 2
    q = [0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)]
    line = dict(material='polyester', segments=40)
    values = {
        'lines': ['ahead', 'astern'],
        'ahead': dict(line, fairlead_offset=[40.0, 5.0, 10.0], bollard_position=[-5.0, 70.0, 0.0],
                      length=32.0),
        'astern': dict(line, fairlead_offset=[-40.0, 5.0, 10.0],
                       bollard_position=[-5.0, -65.0, 0.0], length=26.5),
    }
    driver = Driver(arrangement.from_values(values), rate=RATE, history=math.inf)
    driver.push_ship(T0, [0.0, 0.0, 0.0], q)
    published = driver.advance(math.inf, max_lag=math.inf).outputs[0]  # the start, at rest
    props = driver.mooring.lines[0].props
    w, ea = props.weight_per_length(driver.mooring.environment), props.axial_stiffness
    ahead = solve_catenary(30.0, 10.0, 32.0, w, ea)
    astern = solve_catenary(25.0, 10.0, 26.5, w, ea)
    h1, v1, h2, v2 = (ahead.horizontal_tension, ahead.vertical_b, astern.horizontal_tension,
                      astern.vertical_b)
    # F = (H1 - H2, 0, -V1 - V2); M = (40, 5, 10) x (H1, 0, -V1) + (-40, 5, 10) x (-H2, 0, -V2)
    by_hand_force = [h1 - h2, 0.0, -v1 - v2]
    by_hand_moment = [-5.0 * v1 - 5.0 * v2,
                      10.0 * h1 + 40.0 * v1 - 10.0 * h2 - 40.0 * v2,
                      -5.0 * h1 + 5.0 * h2]
    assert abs(h1 - h2) > 0.2 * h1 and abs(by_hand_moment[1]) > 0.2 * 40.0 * v1  # no cancel
    # 40 segments and the bending springs against the catenary: within 0.2 % of each term
    discrete = 2e-3
    assert published.force == pytest.approx(by_hand_force, abs=discrete * (h1 + v1 + h2 + v2))
    assert published.moment == pytest.approx(
        by_hand_moment, abs=discrete * 50.0 * (h1 + v1 + h2 + v2))


def test_mooring_wrench_of_given_forces():
    # one force, the ship turned 90 degrees about z: body x is world y
    q = [0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4)]
    force, moment = mooring_wrench(np.array([[0.0, 1000.0, -200.0]]),
                                   np.array([[10.0, 0.0, 5.0]]), q)
    assert force == pytest.approx([1000.0, 0.0, -200.0])
    # (10, 0, 5) x (1000, 0, -200) = (0 * -200 - 5 * 0, 5 * 1000 - 10 * -200, 0 - 0)
    assert moment == pytest.approx([0.0, 7000.0, 0.0], abs=1e-9)


# ------------------------------------------------------------------ pretension


def test_pretension_starts_the_line_at_its_tension(eight_lines):
    driver, outputs = eight_lines
    k = driver.mooring.names.index('stern_1')
    first = outputs[0].output.fairlead_tensions[k]
    assert first == pytest.approx(80.0e3, rel=2e-3)  # the catenary against 12 segments
    line = driver.arrangement.line('stern_1')
    assert line.pretension == 80.0e3
    assert 40.0 < line.params.length < 52.0  # chosen at the first pose


def test_length_for_tension_inverts_the_catenary():
    driver = Driver(arrangement.from_values(berth_values()), rate=RATE)
    props, air = driver.mooring.lines[0].props, driver.mooring.environment
    bollard, fairlead = np.array([0.0, 0.0, 0.0]), np.array([40.0, 5.0, 9.0])
    for tension in (2.0e3, 50.0e3, 400.0e3):
        length = length_for_tension(props, air, bollard, fairlead, tension)
        span, rise = math.hypot(40.0, 5.0), 9.0
        got = solve_catenary(span, rise, length, props.weight_per_length(air),
                             props.axial_stiffness).tension_b
        assert got == pytest.approx(tension, rel=1e-9)
    with pytest.raises(PretensionError, match='least fairlead tension'):
        length_for_tension(props, air, bollard, fairlead, 100.0)  # less than its weight holds
    with pytest.raises(PretensionError, match='reach'):
        length_for_tension(props, air, bollard, fairlead, 1e9)


def test_length_for_tension_follows_the_lines_curve():
    """A nylon line on its strain-tension curve starts at its pretension, not at EA's."""
    values = berth_values()
    values['head_1'] = {**values['head_1'], 'material': 'nylon', 'load_extension': 'curve'}
    driver = Driver(arrangement.from_values(values), rate=RATE)
    props, air = driver.mooring.lines[0].props, driver.mooring.environment
    assert props.curve is not None
    bollard, fairlead = np.array([0.0, 0.0, 0.0]), np.array([40.0, 5.0, 9.0])
    for tension in (50.0e3, 300.0e3):
        length = length_for_tension(props, air, bollard, fairlead, tension)
        got = solve_catenary(math.hypot(40.0, 5.0), 9.0, length, props.weight_per_length(air),
                             props.axial_stiffness, props.curve).tension_b
        assert got == pytest.approx(tension, rel=1e-9)
        linear = solve_catenary(math.hypot(40.0, 5.0), 9.0, length,
                                props.weight_per_length(air), props.axial_stiffness).tension_b
        assert abs(linear / tension - 1.0) > 0.05  # EA alone would start it elsewhere


# ------------------------------------------------------------------ refusals


@pytest.mark.parametrize('change, message', [
    ({'lines': ['head 1']}, "line name 'head 1' in 'lines' is not allowed: a name starts"),
    ({'lines': ['head_1', 'head_1']}, "line name 'head_1' appears twice in 'lines'"),
    ({'lines': []}, "parameter 'lines' = [] is not allowed"),
    ({'lines': None}, "parameter 'lines' is missing"),
    ({'haed_1': {'length': 40.0}}, "parameter 'haed_1.length' is for no line: lines are"),
    ({'head_1': dict(BERTH['head_1'], lenght=40.0)}, 'unknown parameter head_1.lenght: not a '
     'line setting; did you mean head_1.length?'),
    ({'head_1': dict(BERTH['head_1'], length=-1.0)}, "parameter 'head_1.length' = -1.0 is not "
     'allowed: must be > 0'),
    ({'head_1': dict(BERTH['head_1'], integrator='improved_euler')},
     "parameter 'head_1.integrator' is not allowed: integrator is shared"),
    ({'head_1': {'length': 40.0}}, "line 'head_1' is missing settings: set "
     'head_1.fairlead_offset'),
    ({'head_1': {'fairlead_offset': [1.0, 2.0, 3.0], 'bollard_position': [0.0, 0.0, 0.0]}},
     "line 'head_1' is missing settings: set head_1.length (m) or head_1.pretension (N)"),
    ({'lenght': 40.0}, "unknown parameter 'lenght'"),
    # (issue: it passed silently through the moored ship, its load zero)
    ({'passing_ship': {'speed': 4.0, 'separation': -10.0}},
     "parameter 'passing_ship.separation' = -10 is not allowed: the hulls would overlap; at "
     'least 32.1 m (half the sum of the beams, 32.2 m and 32 m) off either side'),
])
def test_bad_arrangement_is_refused_in_one_line(change, message):
    values = berth_values()
    values.update(change)
    if values['lines'] is None:
        del values['lines']
    with pytest.raises(ParameterError) as error:
        arrangement.from_values(values)
    text = str(error.value)
    assert '\n' not in text
    assert text.startswith(message), text


def test_top_level_line_settings_are_every_lines_default():
    values = berth_values(segments=30, material='nylon')
    values['head_1'] = dict(BERTH['head_1'], segments=6)
    setup = arrangement.from_values(values)
    assert setup.line('head_1').params.segments == 6
    assert setup.line('head_2').params.segments == 30
    assert setup.line('spring_aft').params.material == 'steel_wire'  # its own
    assert setup.line('head_1').params.material == 'polyester'
    assert setup.line('breast_fwd').params.integrator == setup.shared.integrator


def test_nested_and_flat_names_are_the_same_arrangement():
    nested = arrangement.from_values(berth_values())
    flat = arrangement.flatten(berth_values())
    assert 'head_1.fairlead_offset' in flat
    assert arrangement.from_values(flat) == nested
    again = arrangement.from_stored(
        {arrangement.PARAMETERS_KEY: arrangement.parameters_yaml(nested)})
    assert again == nested


def test_a_line_that_cannot_be_built_is_named():
    values = berth_values(integrator='improved_euler', time_step=0.01)
    with pytest.raises(ParameterError, match=r"^line 'head_1': time_step 0.01 s is above"):
        Driver(arrangement.from_values(values))


def test_a_line_beyond_its_reach_is_held_and_restarted_as_alone():
    # The ship surges 4 m ahead and back: the short line's ends part farther than its reach
    # (14 m x 1.25), so its fairlead is held at the reach and the line restarts at rest
    # once they are back within it; the two long lines only pull. Each line as alone.
    # Parting off: with it on, the short line parts long before its reach (test_parting).
    def surge(t):
        return [4.0 * math.sin(math.pi * min(t, 2.0) / 2.0) ** 2, 0.0, 0.0], [0, 0, 0, 1.0]

    values = {  # implicit_euler: see eight_lines
        'lines': ['short', 'long', 'wire'], 'segments': 10, 'parting': False,
        'integrator': 'implicit_euler',
        'short': dict(material='polyester', fairlead_offset=[0.0, 0.0, 5.0],
                      bollard_position=[-14.0, 0.0, 0.0], length=14.0),
        'long': dict(material='polyester', fairlead_offset=[0.0, 5.0, 5.0],
                     bollard_position=[-40.0, 5.0, 0.0], length=42.0),
        'wire': dict(material='steel_wire', diameter=0.03, fairlead_offset=[0.0, -5.0, 5.0],
                     bollard_position=[40.0, -5.0, 0.0], length=40.5),
    }
    driver, together = run_arrangement(values, seconds=3.0, pose=surge)
    restarted = [(o.output.t, o.advance.restarted) for o in together
                 if o.advance is not None and o.advance.restarted]
    assert restarted and all(set(r) == {0} for _, r in restarted)
    assert {why for _, r in restarted for why in r.values()} == {'back within reach'}
    held = [o.advance.beyond_reach for o in together
            if o.advance is not None and o.advance.beyond_reach]
    assert held and all(set(h) == {0} for h in held)
    assert max(h[0] for h in held) > 17.5 + 1.0
    tensions = np.array([o.output.fairlead_tensions for o in together])
    assert np.isfinite(tensions).all()
    props = driver.mooring.lines[0].props
    assert tensions[:, 0].max() <= 1.01 * props.axial_stiffness * props.max_strain
    for k, line in enumerate(driver.arrangement.lines):
        alone = run_single(line.params, seconds=3.0, pose=surge)
        mine = np.array([o.output.fairlead_forces[k] for o in together])
        single = np.array([o.output.fairlead_forces[0] for o in alone])
        assert mine.shape == single.shape
        assert np.abs(mine - single).max() <= 1e-9 * np.abs(single).max(), line.name


def test_every_fairlead_follows_its_own_samples_through_jumps():
    # A 0.06 rad yaw jump at 1.5 s moves the four head and stern fairleads 5.6 to 5.7 m, past
    # teleport_distance (5 m), the others 2.4 to 4.2 m; an 8 m sway jump at 2.5 s moves all.
    # The lines share one sampling of their fairleads while their samples are the ship's; a
    # line that restarted at its jump has only the samples since, and from then on its rope
    # ends where they put it, not where the ship's samples before the jump would.
    def jumps(t):
        position, orientation = ship_pose(t)
        yaw = 0.06 if t >= 1.5 else 0.0
        x, y, z, w = orientation
        c, s = math.cos(yaw / 2), math.sin(yaw / 2)  # the yaw first, about the world z
        orientation = [c * x - s * y, c * y + s * x, c * z + s * w, c * w - s * z]
        return [position[0], position[1] + (8.0 if t >= 2.5 else 0.0), position[2]], orientation

    driver = Driver(arrangement.from_values(berth_values()), rate=RATE)
    events, checked = {}, 0
    for i in range(round(3.0 * RATE) + 1):
        t = i / RATE
        event = driver.push_ship(T0 + round(t * 1e9), *jumps(t))
        if 'teleport' in event:
            events[t] = [driver.mooring.names[k] for k in event['teleport']]
        for published in driver.advance(math.inf, max_lag=math.inf).outputs:
            out = published.output
            for k in range(len(BERTH)):
                # to round-off: divided steps' times
                ends = driver.mooring.drive(k, [out.t])[0][0]
                assert np.abs(out.positions[k][[0, -1]] - ends).max() < 1e-9, (out.t, k)
            checked += 1
    assert events == {1.5: ['head_1', 'head_2', 'stern_1', 'stern_2'], 2.5: list(BERTH)}
    assert checked == 150


# ------------------------------------------------------------------ winches and parting


def test_a_line_that_parts_leaves_the_others_and_its_pull_leaves_the_wrench():
    # stern_2 pulls 63 to 214 kN in the motion: at a break load of 150 kN it parts once; every
    # line, the parted one included, goes on exactly as it would alone, and the total wrench
    # keeps only what its piece on the ship still pulls.
    values = berth_values(stern_2=dict(BERTH['stern_2'], break_load=150.0e3),
                          integrator='implicit_euler')  # see eight_lines
    driver, together = run_arrangement(values)
    k = driver.mooring.names.index('stern_2')
    events = [(o.output.t, o.advance.parted) for o in together
              if o.advance is not None and o.advance.parted]
    assert len(events) == 1 and set(events[0][1]) == {k}
    when, parting = events[0][0], events[0][1][k]
    assert when - 1.0 / RATE < parting.t <= when and parting.break_load == 150.0e3
    assert 0 <= parting.segment < 12
    parted = np.array([o.output.parted for o in together])
    times = np.array([o.output.t for o in together])
    assert (parted[:, k] == (times >= when)).all() and 0.5 < when < 2.5
    assert not np.delete(parted, k, axis=1).any()
    for line_k, line in enumerate(driver.arrangement.lines):
        alone = run_single(line.params)
        mine = np.array([o.output.fairlead_forces[line_k] for o in together])
        single = np.array([o.output.fairlead_forces[0] for o in alone])
        assert np.isfinite(mine).all()
        assert np.abs(mine - single).max() <= 1e-9 * np.abs(single).max(), line.name
        assert [o.output.parted[0] for o in alone] == list(parted[:, line_k]), line.name
    # the pull before the break, and what the piece on the fairlead pulls a second later
    before = together[int(np.flatnonzero(times < when)[-1])].output.fairlead_tensions[k]
    assert before > 140.0e3
    offsets = np.array([line.params.fairlead_offset for line in driver.arrangement.lines])
    others = np.arange(len(offsets)) != k
    for published in together:
        if published.output.t < when + 1.0:
            continue
        out = published.output
        assert out.fairlead_tensions[k] < 0.05 * before  # a hanging piece of rope
        force, moment = mooring_wrench(out.fairlead_forces[others], offsets[others],
                                       published.ship_orientation)
        assert np.linalg.norm(published.force - force) == pytest.approx(
            out.fairlead_tensions[k], rel=1e-9)
        assert np.isfinite(published.force).all() and np.isfinite(published.moment).all()


def test_a_winch_command_changes_only_its_lines_length():
    # Every line has a speed winch; head_1's is told to heave in at 0.3 m/s from the start:
    # its length falls by 0.3 m/s for the 3 s less the ramp up, the others keep theirs (to
    # round-off: a winch at rest sums its rest lengths again), and each line goes on exactly
    # as alone with the same command.
    values = berth_values(winch_mode='speed', integrator='implicit_euler')  # see eight_lines
    driver, together = run_arrangement(values, winches={'head_1': -0.3})
    names = driver.mooring.names
    lengths = np.array([o.output.line_lengths for o in together])
    k = names.index('head_1')
    hauled = lengths[0, k] - lengths[-1, k]
    assert lengths[0, k] == pytest.approx(BERTH['head_1']['length'], abs=1e-9)
    assert 0.3 * (3.0 - 1.5) < hauled < 0.3 * 3.0
    assert (np.diff(lengths[:, k]) <= 0.0).all()
    assert np.abs(np.delete(lengths - lengths[0], k, axis=1)).max() < 1e-12  # round-off
    for line_k, line in enumerate(driver.arrangement.lines):
        alone = run_single(line.params, winch=-0.3 if line.name == 'head_1' else None)
        mine = np.array([o.output.fairlead_forces[line_k] for o in together])
        single = np.array([o.output.fairlead_forces[0] for o in alone])
        assert np.abs(mine - single).max() <= 1e-9 * np.abs(single).max(), line.name
        assert np.array_equal(lengths[:, line_k], [o.output.line_lengths[0] for o in alone])
    # heaved in 0.9 m on a 47 m line: it pulls harder than the same line without a command
    still = run_arrangement(values)[1]
    assert together[-1].output.fairlead_tensions[k] > 2.0 * still[-1].output.fairlead_tensions[k]


@pytest.mark.parametrize('rate', [25.0, 100.0, 1000.0])
def test_a_publish_rate_set_at_run_time_keeps_every_line_going(rate):
    """A legal publish_rate set while the lines run: the next outputs come at the new rate."""
    driver = Driver(arrangement.from_values(berth_values()), rate=RATE, history=math.inf)
    stamps = []
    for i in range(round(2.0 * RATE) + 1):
        t = i / RATE
        if i == RATE:  # 1 s in, as a user's `ros2 param set` would
            driver.update(None, {'publish_rate': rate})
        position, orientation = ship_pose(t)
        driver.push_ship(T0 + round(t * 1e9), position, orientation)
        stamps += [p.stamp_ns for p in driver.advance(math.inf, max_lag=math.inf).outputs]
    after = np.diff([s for s in stamps if s > T0 + 1.1e9]) / 1e9
    assert len(after) > 0.8 * 0.8 * rate
    assert np.allclose(after, 1.0 / rate, atol=1e-9)
    assert all(np.isfinite(p.output.fairlead_forces).all()
               for p in driver.advance(math.inf, max_lag=math.inf).outputs)


# ------------------------------------------------------------------ the driver's rules, many lines


def stamps(report):
    """Return the stamps [ns] of a report's outputs, from the first pose's."""
    return [p.stamp_ns - T0 for p in report.outputs]


def test_an_arrangement_too_far_behind_skips_ahead_and_restarts_every_line_at_rest():
    driver = Driver(arrangement.from_values(berth_values()), rate=RATE)
    mooring = driver.mooring
    got = []
    for i in range(6):
        t = i / RATE
        driver.push_ship(T0 + round(t * 1e9), *ship_pose(t))
        got += stamps(driver.advance(math.inf, max_lag=1.0))
    assert got == [20_000_000 * k for k in range(5)]  # to the second-newest pose, 0.08 s
    moving = [float(np.abs(mooring.rope(k).v).max()) for k in range(len(BERTH))]
    assert min(moving) > 1e-3, moving  # the ship moves every rope
    driver.silence(SHIP)
    report = driver.advance(0.08 + 1.0 + 0.5, max_lag=1.0)
    assert report.skipped == pytest.approx(1.5) and report.skip_to == 1.58
    assert report.clock_back == 0.0 and report.faults == []
    # the fresh state at the skip: every line restarted at rest between its ends there
    assert stamps(report) == [1_580_000_000] and report.outputs[0].advance is None
    out = report.outputs[0].output
    assert out.t == 1.58 and driver.time == 1.58
    for k, line in enumerate(mooring.lines):
        ends = mooring.drive(k, [1.58])[0][0]
        at_rest = line.at_rest(ends, bool(mooring.held[k]), mooring.environment).lines[0]
        assert np.array_equal(out.positions[k], at_rest.x), line.name
        assert np.abs(mooring.rope(k).v).max() == 0.0, line.name
    # then the grid from there: due 1/rate after the skip (here at most 3 per call)
    report = driver.advance(1.7, max_outputs=3, max_lag=1.0)
    assert stamps(report) == [1_600_000_000, 1_620_000_000, 1_640_000_000]
    assert report.skipped == 0.0
    assert all(p.advance.steps > 0 and not p.advance.restarted for p in report.outputs)
    assert driver.next_due() == pytest.approx(1.66, abs=1e-12)
    # within max_lag: no skip, the ropes catch up
    assert driver.advance(1.64 + 0.9, max_lag=1.0).skipped == 0.0
    assert driver.time == pytest.approx(2.54)


def test_a_clock_behind_an_arrangement_clears_it_and_the_next_pose_starts_it_again():
    driver = Driver(arrangement.from_values(berth_values()), rate=RATE)
    k = driver.mooring.names.index('stern_1')
    first = driver.push_ship(T0, *ship_pose(0.0))
    assert list(first) == ['start'] and list(first['start']) == [k]  # its pretension's length
    fresh = driver.advance(math.inf).outputs
    assert [p.stamp_ns - T0 for p in fresh] == [0]
    driver.push_ship(T0 + SECOND, *ship_pose(0.0))
    driver.silence(SHIP)
    driver.advance(3.0, max_lag=math.inf)
    assert driver.time == pytest.approx(3.0)
    report = driver.advance(3.0 - 1.0 - 0.1, max_lag=1.0)
    assert report.clock_back == pytest.approx(1.1) and report.outputs == []
    assert not driver.started and driver.epoch_ns is None
    assert driver.advance(math.inf).outputs == []  # nothing moves until a ship pose
    # the next ship pose starts every line again, its stamp the new epoch: a fresh output,
    # the very state of the first start at the same pose
    again = driver.push_ship(T0 - 5 * SECOND, *ship_pose(0.0))
    assert again == first
    report = driver.advance(math.inf)
    assert stamps(report) == [-5 * SECOND] and report.outputs[0].advance is None
    out, before = report.outputs[0].output, fresh[0].output
    assert out.t == 0.0
    assert np.array_equal(out.fairlead_forces, before.fairlead_forces)
    for mine, theirs in zip(out.positions, before.positions):
        assert np.array_equal(mine, theirs)
    assert out.fairlead_tensions[k] == pytest.approx(80.0e3, rel=2e-3)


@pytest.mark.parametrize('rate, count', [(30.0, 30), (100.0, 102)])
def test_a_rate_change_on_an_arrangement_re_anchors_the_grid_at_the_last_output(rate, count):
    driver = Driver(arrangement.from_values(berth_values()), rate=RATE)
    got = []
    for i in range(101):
        if i == 50:  # the last output so far is at 0.96 s
            assert got[-1] == 960_000_000
            driver.update(None, {'publish_rate': rate})
            assert driver.rate == rate
        t = i / RATE
        driver.push_ship(T0 + round(t * 1e9), *ship_pose(t))
        report = driver.advance(math.inf)
        assert report.skipped == 0.0 and report.faults == []
        got += stamps(report)
    before = [20_000_000 * k for k in range(49)]
    after = [960_000_000 + round(k / rate * 1e9) for k in range(1, count + 1)]
    assert got == before + after  # no gap, no burst: 1/rate after 0.96 s, and on
    # every line's step divides the new period
    for line in driver.mooring.lines:
        assert line.params.publish_rate == rate
        period = 1.0 / rate / line.time_step
        assert period == pytest.approx(round(period), abs=1e-9), line.name


def test_each_output_has_the_levers_of_the_newest_samples_at_or_before_it():
    # Ship to ship: 'fore' is made fast to a bollard on a rolling vessel alongside (its
    # bollard_offset in that vessel's frame), 'aft' to a fixed bollard. The ship's poses
    # come every 100 ms, the vessel's every 80 ms, the outputs every 50 ms: an output gets
    # the fairlead levers of the ship's pose at or before it and the bollard lever of the
    # vessel's sample at or before it, not of the newest ones taken.
    values = {
        'lines': ['fore', 'aft'], 'segments': 8, 'material': 'polyester',
        'publish_rate': 20.0, 'integrator': 'implicit_euler',
        'fore': dict(fairlead_offset=[20.0, 5.0, 3.0], bollard_offset=[15.0, -4.0, 2.0],
                     bollard_position=[15.0, 16.0, 2.0], length=12.5),
        'aft': dict(fairlead_offset=[-20.0, 5.0, 3.0], bollard_position=[-25.0, 16.0, 0.0],
                    length=13.0),
    }
    setup = arrangement.from_values(values)
    offsets = np.array([line.params.fairlead_offset for line in setup.lines])
    bollard_offset = setup.line('fore').params.bollard_offset

    def ship(t):
        roll = 0.02 * math.sin(3.0 * t)
        return [0.1 * math.sin(2.0 * t), 0.0, 0.0], [math.sin(roll / 2), 0.0, 0.0,
                                                     math.cos(roll / 2)]

    def vessel(t):
        roll = 0.03 * math.sin(2.5 * t)
        return [0.0, 20.0 + 0.05 * math.sin(2.0 * t), 0.1 * math.sin(t)], [
            math.sin(roll / 2), 0.0, 0.0, math.cos(roll / 2)]

    ship_ns = [100_000_000 * i for i in range(11)]  # 0 .. 1 s
    vessel_ns = [80_000_000 * j for j in range(13)]  # 0 .. 0.96 s
    vessel_levers = [frames.pose_point(*vessel(ns / 1e9), bollard_offset).lever
                     for ns in vessel_ns]
    fairlead_levers = [
        offsets @ frames.rotation_matrix(frames.unit_quaternion(ship(ns / 1e9)[1])[0]).T
        for ns in ship_ns]
    # every sample in stamp order, the vessel's first at a tie (the bollard's stream first)
    samples = sorted([(ns, 0, j) for j, ns in enumerate(vessel_ns)]
                     + [(ns, 1, i) for i, ns in enumerate(ship_ns)])
    driver = Driver(setup, rate=20.0)
    got = []
    for ns, stream, _ in samples:
        if stream == 0:
            point = frames.pose_point(*vessel(ns / 1e9), bollard_offset)
            assert driver.push_bollard('fore', T0 + ns, point.point, point.lever) == ''
        else:
            assert 'teleport' not in driver.push_ship(T0 + ns, *ship(ns / 1e9))
        got += driver.advance(math.inf).outputs
    # every 50 ms up to the vessel's second-newest sample (0.88 s)
    assert [p.stamp_ns - T0 for p in got] == [50_000_000 * k for k in range(18)]
    chosen = set()
    for published in got:
        ns = published.stamp_ns - T0
        i = max(i for i, sample in enumerate(ship_ns) if sample <= ns)
        j = max(j for j, sample in enumerate(vessel_ns) if sample <= ns)
        chosen.add(j)
        assert np.array_equal(published.fairlead_levers, fairlead_levers[i]), ns
        assert np.array_equal(published.bollard_levers[0], vessel_levers[j]), ns
        assert np.array_equal(published.bollard_levers[1], np.zeros(3)), ns  # a fixed bollard
        assert np.array_equal(published.ship_position, ship(ship_ns[i] / 1e9)[0]), ns
    # the levers differ from sample to sample, by centimetres: the choice is seen
    assert len(chosen) == 11
    assert np.abs(np.diff(vessel_levers, axis=0)).max() > 0.01
    assert np.abs(np.diff(fairlead_levers, axis=0)).max() > 0.01
