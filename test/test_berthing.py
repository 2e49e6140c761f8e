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
The berth demo's berthing (mooring/berthing.py).

The pilot's law, the schedule, and the demo's berthing itself run offline on the model, as
the berth demo node runs it beside the mooring node.
"""

import math

import numpy as np
import pytest
from rope_sim_ros.mooring.berthing import (berthing, Pilot, PilotSettings, read_berthing,
                                           watch)
from rope_sim_ros.mooring.driver import Driver
from rope_sim_ros.mooring.ship import fender_gaps, quay_normal, start_pose
from rope_sim_ros.params.arrangement import flatten, from_values, NODE_NAME, read_setup
from rope_sim_ros.params.files import read_params_file
from rope_sim_ros.params.table import ParameterError

NAMES = ['head_1', 'spring_fwd']


@pytest.fixture(scope='module')
def demo(repo_root):
    """Return the berth demo's arrangement and plan, as its node reads them."""
    paths = [repo_root / 'config' / 'berth.yaml', repo_root / 'config' / 'berth_demo.yaml']
    setup = read_setup(paths[0], flatten(read_params_file(paths[1], NODE_NAME)))
    return setup, read_berthing(paths, setup)


@pytest.fixture(scope='module')
def pretensions(repo_root):
    """Return each line's pretension at the berth (config/berth.yaml) [N]."""
    return {line.name: line.pretension
            for line in read_setup(repo_root / 'config' / 'berth.yaml').lines}


# -- the pilot --------------------------------------------------------------------------

def test_the_pilot_wants_the_approach_speed_far_off_and_the_landing_speed_at_the_fenders():
    pilot = Pilot(PilotSettings(approach_speed=0.25, landing_speed=0.1, deceleration=0.003))
    assert pilot.wanted_speed(30.0) == pytest.approx(0.25)
    # room to slow from 0.25 to 0.1 m/s at 0.003 m/s^2: (0.25^2 - 0.1^2) / 0.006 = 8.75 m
    assert pilot.wanted_speed(8.75) == pytest.approx(0.25)
    assert pilot.wanted_speed(4.0) == pytest.approx(math.sqrt(0.01 + 0.024))
    assert pilot.wanted_speed(0.0) == pytest.approx(0.1)
    assert pilot.wanted_speed(-0.3) == pytest.approx(0.1)


def test_the_tugs_push_by_the_speed_wanted_then_hold_her_alongside_then_ease_off():
    settings = PilotSettings(gain=4e7, hold=3e5, max_push=1.2e6, max_pull=6e5, ease_time=20.0)
    pilot = Pilot(settings)
    assert pilot.push(0.0, 30.0, 0.0) == 0.0  # idle until told
    pilot.start()
    assert pilot.push(0.0, 30.0, 0.0) == 1.2e6  # all they have: 4e7 x 0.25 is more
    assert pilot.push(50.0, 20.0, 0.24) == pytest.approx(4e7 * 0.01)
    assert pilot.push(100.0, 2.0, 0.2) == -6e5  # too fast so near: they pull, all they can
    assert not pilot.touched
    # touching a fender: from now on hold her there, checking her either way
    assert pilot.push(150.0, -0.01, 0.1) == -6e5
    assert pilot.touched
    assert pilot.push(160.0, 0.5, -0.02) == pytest.approx(3e5 + 4e7 * 0.02)  # coming off
    assert pilot.push(161.0, 0.1, 0.005) == pytest.approx(3e5 - 4e7 * 0.005)
    assert pilot.push(170.0, 0.0, 0.0) == pytest.approx(3e5)
    pilot.stop(180.0)
    assert pilot.push(185.0, 0.0, 0.0) == pytest.approx(3e5 * 0.75)
    assert pilot.push(190.0, 0.0, -0.01) == pytest.approx((3e5 + 4e5) * 0.5)
    assert pilot.pushing
    assert pilot.push(200.0, 0.0, -0.01) == 0.0
    assert not pilot.pushing


def test_what_the_pilot_watches_at_the_berth(demo):
    setup, _ = demo
    # the demo's ship starts 30 m off the fenders' faces (config/berth.yaml's lies on them)
    position, orientation = start_pose(setup)
    assert position.tolist() == [0.0, -47.6, 0.0]
    assert fender_gaps(setup, position, orientation) == pytest.approx([30.0] * 4)
    assert quay_normal(setup) == pytest.approx([0.0, -1.0, 0.0])
    off, speed = watch(setup, [0.0, -17.2, 0.0], orientation, [0.05, 0.12, 0.0])
    assert (off, speed) == pytest.approx((-0.4, 0.12))
    # turned 1 degree bow to port (to the quay): the bow nearer; the port side's line is
    # y = y0 + (beam / 2) / cos(yaw) + x tan(yaw)
    yaw = math.radians(1.0)
    gaps = fender_gaps(setup, [0.0, -18.0, 0.0], [0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)])
    assert gaps == pytest.approx([-1.5 + 18.0 - 16.1 / math.cos(yaw) - x * math.tan(yaw)
                                  for x in (-60.0, -20.0, 20.0, 60.0)], abs=1e-9)


# -- the schedule -------------------------------------------------------------------------

def test_a_schedule_of_tugs_commands_and_parameters():
    plan = berthing({'schedule': ['0 tugs push', '5.5 head_1 make_fast',
                                  '6 head_1.winch_tension 1e5', '6 head_1.winch_mode brake',
                                  '7 let_go_all', '8 tugs stop'],
                     'pilot': {'gain': 2e7}, 'duration': 60}, NAMES)
    assert [(o.t, o.kind, o.line, o.what, o.value) for o in plan.orders] == [
        (0.0, 'tugs', '', 'push', None), (5.5, 'command', 'head_1', 'make_fast', None),
        (6.0, 'set', 'head_1', 'winch_tension', 1e5), (6.0, 'set', 'head_1', 'winch_mode',
                                                       'brake'),
        (7.0, 'command', '', 'let_go_all', None), (8.0, 'tugs', '', 'stop', None)]
    assert plan.pilot.gain == 2e7 and plan.pilot.hold == PilotSettings().hold
    assert plan.duration == 60.0
    assert berthing({}, NAMES).orders == ()


@pytest.mark.parametrize('values, message', [
    ({'schedule': ['x tugs push']},
     "schedule: order 'x tugs push': its time 'x' is not a number of seconds >= 0"),
    ({'schedule': ['nan tugs push']},
     "schedule: order 'nan tugs push': its time 'nan' is not a number of seconds >= 0"),
    ({'schedule': ['2 tugs push', '1 tugs stop']},
     "schedule: order '1 tugs stop' comes before the order above it ('2 tugs push'): list "
     'them in time order'),
    ({'schedule': ['1 tugs pull']},
     "schedule: order '1 tugs pull': the tugs take push or stop: '1 tugs push'"),
    ({'schedule': ['1 hed_1 make_fast']},
     "schedule: order '1 hed_1 make_fast': 'hed_1' is not a line, nor tugs or let_go_all; "
     "the lines are head_1, spring_fwd; did you mean 'head_1'?"),
    ({'schedule': ['1 head_1 lash']},
     "schedule: order '1 head_1 lash': a line takes one of make_fast, let_go, stow, or "
     'LINE.PARAMETER VALUE (the commands: make_fast, let_go, stow, let_go_all)'),
    ({'schedule': ['1 head_1.winch_tensoin 5']},
     "schedule: order '1 head_1.winch_tensoin 5': unknown parameter head_1.winch_tensoin: "
     'not a line setting; did you mean head_1.winch_tension? (docs/parameters.md lists them)'),
    ({'schedule': ['1 head_1.winch_tension -5']},
     "schedule: order '1 head_1.winch_tension -5': parameter 'head_1.winch_tension' = -5 is "
     'not allowed: must be >= 0 and <= 1e+10 N'),
    ({'schedule': ['1 head_1.length 50']},
     "schedule: order '1 head_1.length 50': head_1.length cannot change at run time (it "
     'needs a restart of the node)'),
    ({'schedule': ['1 head_1.winch_tension [']},
     "schedule: order '1 head_1.winch_tension [': '[' is not a YAML value"),
    ({'schedule': '0 tugs push'},
     "schedule must be a list of orders (text), e.g. ['0 tugs push', '120 spring_fwd "
     "make_fast']"),
    ({'pilot': {'gian': 3}},
     'unknown setting pilot.gian: the pilot has approach_speed, landing_speed, '
     'deceleration, gain, hold, max_push, max_pull, ease_time; did you mean pilot.gain?'),
    ({'pilot': {'gain': 0}}, 'pilot.gain = 0 is not allowed: must be a number > 0 (N per m/s)'),
    ({'pilot': {'max_pull': -1}},
     'pilot.max_pull = -1 is not allowed: must be a number >= 0 (N)'),
    ({'pilot': {'landing_speed': 0.5}},
     'pilot.landing_speed 0.5 m/s is more than pilot.approach_speed 0.25 m/s'),
    ({'duration': float('inf')},
     'duration = inf is not allowed: must be a number of seconds > 0'),
    ({'sched': []}, "unknown parameter 'sched': the berth demo takes schedule, pilot, duration"),
])
def test_a_bad_plan_is_one_line_naming_it(values, message):
    with pytest.raises(ParameterError) as raised:
        berthing(values, NAMES)
    assert str(raised.value) == 'berth_demo: ' + message


def test_tugs_need_fenders_to_steer_by(repo_root, tmp_path):
    plan = tmp_path / 'plan.yaml'
    plan.write_text("/**/berth_demo:\n  ros__parameters:\n    schedule: ['0 tugs push']\n")
    setup = from_values({'lines': ['head_1'], 'ship_mode': 'free',
                         'head_1': {'fairlead_offset': [100.0, 10.0, 10.0],
                                    'bollard_position': [140.0, 20.0, 3.0], 'length': 45.0}})
    with pytest.raises(ParameterError, match='the berth needs fenders on its quay'):
        read_berthing([plan], setup)
    berth = repo_root / 'config' / 'berth.yaml'
    assert read_berthing([berth], setup).orders == ()  # no berth_demo section: no orders


# -- the demo's berthing, offline -----------------------------------------------------------

def berth_offline(setup, plan, duration: float):
    """
    Run the plan on the model as the berth demo node runs it beside the node.

    Each order at the first output at or past its time; the pilot's push from the newest
    output, once a second, held until the next. Returns the outputs, the landing (time,
    speed) and the refused orders.
    """
    driver = Driver(setup, rate=10.0)
    driver.start_free(0)
    pilot = Pilot(plan.pilot)
    normal = quay_normal(setup)
    orders = list(plan.orders)
    outputs, refused, landing = [], [], None
    t = 0.0
    while t < duration - 1e-9:
        while orders and orders[0].t <= t + 1e-9:
            order = orders.pop(0)
            if order.kind == 'tugs':
                pilot.start() if order.what == 'push' else pilot.stop(t)
            elif order.kind == 'command':
                try:
                    driver.command(order.line or None, order.what)
                except ValueError as e:
                    refused.append((order.text, str(e)))
            else:
                driver.update(order.line, {order.what: order.value})
        if outputs:
            ship = outputs[-1].ship
            push = pilot.push(t, *watch(setup, ship.position, ship.orientation, ship.velocity))
            driver.set_external_load(-push * normal, np.zeros(3), False)
        t = round(t + 1.0, 9)
        for published in driver.outputs_until(t).outputs:
            out = published.output
            outputs.append(out)
            if landing is None and out.fender_compressions.max() >= 0.0:
                landing = (out.t, -float(np.dot(out.ship.velocity, normal)))
    return outputs, landing, refused


def test_the_demo_lands_her_at_the_pilots_speed_and_its_crew_moors_her(demo, pretensions):
    setup, plan = demo
    brakes = min(order.t for order in plan.orders if order.what == 'winch_mode')
    outputs, landing, refused = berth_offline(setup, plan, brakes + 5.0)
    assert not refused
    # about 0.1 m/s at the fenders (the pilot's gain lets her be a little faster)
    assert landing[1] == pytest.approx(0.1, abs=0.015)
    assert 140.0 < landing[0] < 165.0  # before the crew's breast lines, head and stern lines
    assert all(out.ship is not None for out in outputs)
    assert max(out.fender_compressions.max() for out in outputs) < 0.6  # rated: 1.2 m
    # every line made fast and at its pretension when the brakes go on, she on the fenders
    at_brakes = next(out for out in outputs if out.t >= brakes - 1e-9)
    assert at_brakes.states == ('fast',) * 8
    for k, name in enumerate(setup.names):
        assert at_brakes.fairlead_tensions[k] == pytest.approx(pretensions[name],
                                                               rel=0.12), name
    assert -0.3 < -at_brakes.fender_compressions.max() < 0.1
    assert np.linalg.norm(at_brakes.ship.velocity) < 0.02
