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

"""Wind, current and a passing ship on the moored ship; the berth check against a run."""

import csv
from dataclasses import replace
import math

import numpy as np
import pytest

from rope_sim_ros.model.frames import rotation_matrix
from rope_sim_ros.model.layout import BODY_LINEAR_DAMPING
from rope_sim_ros.model.objects import Environment
from rope_sim_ros.model.ship.coefficients import parse_coefficient_csv
from rope_sim_ros.model.ship.loads import PassingShip, ShipLoads, world_load
from rope_sim_ros.model.ship.passing import Hull, passing_loads
from rope_sim_ros.model.ship.wind import Wind
from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.mooring.ship import ship_loads
from rope_sim_ros.offline import berth_check, cli
from rope_sim_ros.params import arrangement
from rope_sim_ros.params.table import from_values

# a table the test can compute by hand: cx = -0.9 cos, cy = -0.7 sin, cmz = -0.1 sin 2theta
TABLE = parse_coefficient_csv('angle_deg,cx,cy,cmz\n' + '\n'.join(
    f'{a},{-0.9 * math.cos(math.radians(a))!r},{-0.7 * math.sin(math.radians(a))!r},'
    f'{-0.1 * math.sin(math.radians(2 * a))!r}' for a in range(0, 360, 5)), 'test table')
HULL = Hull(225.0, 32.2, 14.0, 0.85)
AIR, WATER = 1.225, 1025.0


class Loads:
    """ShipLoads in an environment of their own: AIR, water, a wind and a current."""

    def __init__(self, model: ShipLoads, water: float = WATER, wind: Wind = Wind(),
                 current=(0.0, 0.0, 0.0)):
        self.model = model
        self.environment = Environment(air_density=AIR, water_density=water, wind=wind,
                                       current=tuple(current))

    @property
    def passing(self) -> PassingShip:
        return self.model.passing

    @property
    def current(self) -> tuple:
        return self.environment.current

    @current.setter
    def current(self, value) -> None:
        self.environment = replace(self.environment, current=tuple(value))

    def at(self, t: float, position, rotation, velocity) -> np.ndarray:
        return self.model.at(t, self.environment, position, rotation, velocity)


def loads(wind: Wind = Wind(), current=(0.0, 0.0, 0.0), **changes) -> Loads:
    """Return loads of TABLE for wind and current, windage 450 x 2500, below water B T x L T."""
    return Loads(ShipLoads(HULL, TABLE, TABLE, (450.0, 2500.0), (32.2 * 14.0, 225.0 * 14.0),
                           **changes), wind=wind, current=current)


def heading(yaw: float) -> np.ndarray:
    """Return the rotation of a ship heading yaw [rad] (level)."""
    return rotation_matrix([0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)])


@pytest.mark.parametrize('relative', [0.0, 40.0, 90.0, 135.0, 215.0])
def test_the_wind_load_is_ocimfs_formula(relative):
    """F_x = 1/2 rho V^2 A_T cx, F_y = 1/2 rho V^2 A_L cy, M_z = 1/2 rho V^2 A_L L cmz."""
    yaw = 0.4
    wind = Wind(20.0, yaw + math.radians(relative))  # from `relative` off the bow
    fx, fy, mz = loads(wind=wind).at(0.0, np.zeros(3), heading(yaw), np.zeros(3))[0]
    theta = math.radians(relative)
    pressure = 0.5 * AIR * 20.0 ** 2
    assert fx == pytest.approx(pressure * 450.0 * -0.9 * math.cos(theta), abs=1e-6)
    assert fy == pytest.approx(pressure * 2500.0 * -0.7 * math.sin(theta), abs=1e-6)
    assert mz == pytest.approx(pressure * 2500.0 * 225.0 * -0.1 * math.sin(2 * theta),
                               abs=1e-3)


def test_the_current_load_is_ocimfs_formula_on_the_areas_below_water():
    current = (-1.0, -1.0, 0.0)  # going to -x, -y: it comes from 45 degrees to port
    fx, fy, mz = loads(current=current).at(0.0, np.zeros(3), heading(0.0), np.zeros(3))[1]
    theta = math.radians(45.0)
    pressure = 0.5 * WATER * 2.0
    assert fx == pytest.approx(pressure * 32.2 * 14.0 * -0.9 * math.cos(theta))
    assert fy == pytest.approx(pressure * 225.0 * 14.0 * -0.7 * math.sin(theta))
    assert mz == pytest.approx(pressure * 225.0 * 14.0 * 225.0 * -0.1 * math.sin(2 * theta))


def test_a_moving_ship_feels_the_relative_velocity():
    """
    Surge ahead at 2 m/s into a 10 m/s head wind: a 12 m/s head wind, and a 2 m/s current.

    In still water that current's load is the ship's drag.
    """
    model = loads(wind=Wind(10.0, 0.0))
    wind, current, _ = model.at(0.0, np.zeros(3), heading(0.0), [2.0, 0.0, 0.0])
    assert wind[0] == pytest.approx(0.5 * AIR * 12.0 ** 2 * 450.0 * -0.9)
    assert current[0] == pytest.approx(0.5 * WATER * 2.0 ** 2 * 32.2 * 14.0 * -0.9)
    assert abs(wind[1]) < 1e-9 and abs(current[1]) < 1e-9


def test_the_passing_ship_is_where_its_track_puts_it():
    passer = Hull(200.0, 32.0, 12.0, 0.8)
    yaw, start = 0.3, np.array([5.0, -17.6, 0.0])
    track = PassingShip.beside(passer, 4.0, 1, 60.0, -400.0, start, yaw)
    model = loads(passing=track)
    moved = start + [0.5, 0.2, 0.0]  # the moored ship has moved a little
    t = 90.0  # its midship 400 m behind at t = 0, 360 m on: 40 m behind the start
    got = model.at(t, moved, heading(yaw), np.zeros(3))[2]
    apart = (track.midship(t) - moved) @ heading(yaw)
    assert apart[0] == pytest.approx(-40.0 - (0.5 * math.cos(yaw) + 0.2 * math.sin(yaw)))
    expected = passing_loads(HULL, passer, 4.0, -apart[1], apart[0], water_density=WATER)
    assert got == pytest.approx(expected)
    assert -apart[1] == pytest.approx(60.0 - 0.5 * math.sin(yaw) + 0.2 * math.cos(yaw))
    assert abs(got[1]) > 1e4  # abeam-ish, 60 m off: tens of kN


FT, KIP = 0.3048, 4448.2216152605  # m, N


def test_the_passing_ship_moves_at_its_speed_through_the_water_plus_the_current(
        reference_dir):
    """
    A passage of DYNMOOR's in a current: 6 kn over the ground, loads at 5.5 kn through water.

    The ship passes along -x with the current (0.5 kn, also along -x): its speed through the
    water is 5.5 kn, over the ground 6 kn, which sets where it is at each second of the
    printed history (test/data/passing_ship/legacy_dynmoor_parallel_50ft.csv).
    """
    with open(reference_dir / 'passing_ship' / 'legacy_dynmoor_parallel_50ft.csv') as stream:
        rows = list(csv.DictReader(line for line in stream if not line.startswith('#')))
    beam = 100.0 * FT
    moored = Hull(600.0 * FT, beam, 3000.0 * FT ** 2 / beam, 2.0 / 3.0)
    passer = Hull(650.0 * FT, beam, 3200.0 * FT ** 2 / beam, 2.0 / 3.0)
    through_water = (6.0 * 1.6888 - 0.5 * 1.6889) * FT  # [m/s] as PARSHIP takes it
    current = (-0.5 * 1.6889 * FT, 0.0, 0.0)  # along -x, with the passing ship
    # at t = 0 (DYNMOOR's step 10) two lengths ahead, 300 ft to port
    track = PassingShip.beside(passer, through_water, -1, -300.0 * FT, 1200.0 * FT,
                               np.zeros(3), 0.0)
    slug_per_ft3 = KIP / 1000.0 / FT ** 4  # [kg/m^3]: a slug is 1 lbf s^2 / ft
    model = Loads(ShipLoads(moored, TABLE, TABLE, (1.0, 1.0), (1.0, 1.0), passing=track,
                            depth=50.0 * FT, image_pairs=10),
                  water=1.9905 * slug_per_ft3, current=current)
    typo = math.pi / 3.1415279  # PARSHIP's pi
    for row in rows:
        t = float(row['step']) - 10.0  # [s]
        surge, sway, yaw = model.at(t, np.zeros(3), heading(0.0), np.zeros(3))[2]
        # over the ground at 6 kn: x = 2 L - t 6 x 1.6888 ft, printed as x / L
        stagger = (model.passing.midship(t)[0]) / FT
        assert stagger == pytest.approx(1200.0 - t * 6.0 * 1.6888, abs=1e-9)
        assert stagger / 600.0 == pytest.approx(float(row['x_over_l']), abs=5e-4)
        # port side: body sway and yaw are Wang's (toward the passing ship)
        for value, unit, column in ((surge, KIP, 'surge_kips'), (sway, KIP, 'sway_kips'),
                                    (yaw, KIP * FT, 'yaw_kip_ft')):
            printed = float(row[column])
            assert typo * value / unit == pytest.approx(printed, abs=0.05 + 1e-5 * abs(printed))
    # the loads went with the speed through the water: at 6 kn they would be 19 % larger
    assert (6.0 * 1.6888 * FT / through_water) ** 2 == pytest.approx(1.19, abs=0.005)


def test_a_current_changed_on_the_way_changes_the_ground_speed_from_then_on():
    passer = Hull(200.0, 32.0, 12.0, 0.8)
    track = PassingShip.beside(passer, 4.0, 1, 60.0, -400.0, np.zeros(3), 0.0)
    model = loads(passing=track, current=(1.0, 0.5, 0.0))  # 1 m/s along the track
    model.at(10.0, np.zeros(3), heading(0.0), np.zeros(3))
    assert model.passing.midship(10.0)[0] == pytest.approx(-400.0 + 5.0 * 10.0)
    model.current = (-1.0, 0.0, 0.0)  # against it from t = 30 s (asked for then)
    model.at(30.0, np.zeros(3), heading(0.0), np.zeros(3))
    assert model.passing.midship(30.0)[0] == pytest.approx(-400.0 + 5.0 * 30.0)
    assert model.passing.midship(50.0)[0] == pytest.approx(-400.0 + 150.0 + 3.0 * 20.0)
    # the cross-track component does not move it: it holds its track 60 m off
    assert model.passing.midship(50.0)[1] == pytest.approx(-60.0)
    assert model.passing.speed == 4.0  # its speed through the water, for the loads


# ------------------------------------------------------------------ the depth and the tables

@pytest.mark.parametrize('value, canonical', [
    ('my.csv', 'my.csv'),
    ('', ''),
    ([[1.1, 'a.csv'], [1.5, 'b.csv']], ['1.1', 'a.csv', '1.5', 'b.csv']),
    (['1.1', 'a.csv', '1.5', 'b.csv'], ['1.1', 'a.csv', '1.5', 'b.csv']),  # a ROS file's
    ([1, 'a.csv', 4.4, 'b.csv'], ['1.0', 'a.csv', '4.4', 'b.csv']),
])
def test_current_tables_are_a_path_or_ratio_path_pairs(value, canonical):
    assert arrangement.check_top_value('ship.current_coefficients', value) == canonical


@pytest.mark.parametrize('value', [
    [[1.5, 'a.csv'], [1.1, 'b.csv']], [[0.9, 'a.csv']], [['deep', 'a.csv']], [1.1],
    [[1.1, '']], [[True, 'a.csv']], [], 5.0, [[1.1, 'a.csv', 2.0]], [['nan', 'a.csv']]])
def test_bad_current_tables_are_refused_in_one_line(value):
    with pytest.raises(arrangement.ParameterError,
                       match="'ship.current_coefficients'.*ratio, path"):
        arrangement.check_top_value('ship.current_coefficients', value)


def test_the_current_table_is_the_one_for_the_berths_depth(repo_root, tmp_path):
    """Two tables by depth, one beside the parameter file: 1.65 T is a quarter of the way."""
    shallow = tmp_path / 'shallow.csv'
    shallow.write_text('angle_deg,cx,cy,cmz\n0,-0.1,0,0\n90,0,-3.0,0\n180,0.1,0,0\n'
                       '270,0,3.0,0\n')
    setup = arrangement.read_setup(repo_root / 'config' / 'berth.yaml', {
        'water_level': 2.0, 'seabed_level': -21.1,  # 23.1 m: 1.65 times the 14 m draft
        # the deep table named relative to the parameter file's folder (config/)
        'ship.current_coefficients': [[1.2, str(shallow)],
                                      [3.0, 'ship/current_coefficients_tanker_loaded.csv']]})
    assert setup.ship.current_coefficients[3] == str(
        repo_root / 'config' / 'ship' / 'current_coefficients_tanker_loaded.csv')
    model = ship_loads(setup)
    assert model.depth == pytest.approx(23.1)
    assert model.current_table.at(90.0)[1] == pytest.approx(0.75 * -3.0 + 0.25 * -0.6)
    # no sea bed: deep water, the deepest table
    deep = ship_loads(arrangement.read_setup(repo_root / 'config' / 'berth.yaml', {
        'seabed_level': float('-inf'), 'ship.current_coefficients': str(shallow)}))
    assert deep.depth == math.inf and deep.current_table.at(90.0)[1] == -3.0


def test_a_passing_ship_in_water_shallower_than_a_draft_is_refused(repo_root):
    setup = arrangement.read_setup(repo_root / 'config' / 'berth.yaml', {
        'water_level': 0.0, 'seabed_level': -13.5, 'passing_ship.speed': 3.0,
        'passing_ship.image_pairs': 10})
    with pytest.raises(arrangement.ParameterError, match='13.5 m deep.*ship.draft 14 m'):
        ship_loads(setup)
    deeper = arrangement.read_setup(repo_root / 'config' / 'berth.yaml', {
        'water_level': 0.0, 'seabed_level': -16.0, 'passing_ship.speed': 3.0,
        'passing_ship.image_pairs': 10})
    model = ship_loads(deeper)
    assert (model.depth, model.image_pairs) == (16.0, 10)


def test_world_load_turns_body_loads_with_the_ship():
    rotation = heading(math.pi / 2)  # bow to +y
    world = world_load(np.array([[1.0, 2.0, 3.0], [10.0, 0.0, 0.0]]), rotation)
    assert world == pytest.approx([-2.0, 11.0, 0.0, 0.0, 0.0, 3.0])


# ------------------------------------------------------------------------ the berth check

def free_berth(repo_root, **values):
    """Return config/berth.yaml's arrangement as a free ship (12 segments a line)."""
    setup = arrangement.read_setup(repo_root / 'config' / 'berth.yaml')
    flat = arrangement.flatten(setup.values())
    flat = {k: v for k, v in flat.items() if not k.endswith('.segments')}
    flat.update({'ship_mode': 'free', 'segments': 12, **values})
    return arrangement.from_values(flat)


def test_a_current_pushes_a_driven_ship_but_not_a_single_lines(repo_root):
    """A single line's current drags its line; there is no ship for it to push."""
    current = [0.0, 0.5, 0.0]  # [m/s] off the quay
    flat = arrangement.flatten(arrangement.read_setup(repo_root / 'config' / 'berth.yaml')
                               .values())
    flat = {k: v for k, v in flat.items() if not k.endswith('.segments')}
    berth = arrangement.from_values({**flat, 'segments': 8, 'current': current})
    line = arrangement.single_line(from_values({'segments': 8, 'current': current}))
    outputs = []
    for setup in (berth, line):
        mooring = Mooring(setup, output_interval=0.01)
        for t in (0.0, 0.01, 0.02):
            mooring.push_ship(t, [0.0, -17.6 if setup is berth else 0.0, 0.0],
                              [0.0, 0.0, 0.0, 1.0])
        mooring.start(0.0)
        mooring.advance_to(0.01)
        outputs.append(mooring.output())
    # the berth's ship, heading +x, feels the current from its starboard side (body -y)
    fx, fy, mz = outputs[0].ship_loads[1]
    assert fy > 1e4 and abs(fx) < 0.1 * fy, (fx, fy, mz)
    assert not outputs[0].ship_loads[0].any() and not outputs[0].ship_loads[2].any()
    assert not outputs[1].ship_loads.any()


def test_the_berth_check_finds_where_a_run_settles(repo_root):
    """Wind from port, off the quay: the check's equilibrium is where the ship comes to rest."""
    wind = 20.0  # [m/s] from 60 degrees off the bow toward port
    setup = free_berth(repo_root, wind_speed=wind, wind_direction=math.radians(60.0))
    case = berth_check.check(setup, wind, [(0.0, 0.0, 0.0)], directions=6)[1]
    assert case.direction == 60.0 and case.status == 'ok'
    # settle the run: dampers near critical on the lines' stiffness
    mooring = Mooring(setup, output_interval=0.1)
    mooring.start(0.0)
    mooring.groups[0].system.body_table[0, BODY_LINEAR_DAMPING:BODY_LINEAR_DAMPING + 6] = [
        2.0e7, 1.5e7, 1.5e8, 1.2e10, 7.0e10, 5.0e10]
    for i in range(1, 4001):
        mooring.advance_to(0.1 * i)
    assert np.abs(mooring.body.velocity).max() < 1e-4
    position, orientation = mooring.ship_pose(mooring.time)
    offset = position - np.array([0.0, -17.6, 0.0])
    yaw = 2.0 * math.atan2(orientation[2], orientation[3])
    # decimetres of sway, centimetres of surge, a tenth of a degree of yaw
    assert case.offset[1] < -0.3 and abs(case.offset[2]) > 1e-3, case.offset
    assert offset[1] == pytest.approx(case.offset[1], rel=0.01)
    assert offset[0] == pytest.approx(case.offset[0], rel=0.02, abs=2e-3)
    assert yaw == pytest.approx(case.offset[2], rel=0.02)
    out = mooring.output()
    tensions = np.maximum(out.fairlead_tensions, out.bollard_tensions)
    assert tensions == pytest.approx(case.tensions, rel=0.01)


def test_rope_sim_berth_check_writes_its_table_and_plot(repo_root, tmp_path, capsys):
    out = tmp_path / 'check'
    assert cli.main(['berth-check', str(repo_root / 'config' / 'berth.yaml'), '--out', str(out),
                     '--directions', '8', '--wind-speed', '25', '--current', '0,0,0']) == 0
    printed = capsys.readouterr().out
    assert 'most loaded' in printed and (out / 'berth_check.png').stat().st_size > 10000
    with open(out / 'berth_check.csv', newline='') as stream:
        rows = list(csv.DictReader(stream))
    assert [float(row['wind_direction_deg']) for row in rows] == [45.0 * i for i in range(8)]
    assert all(row['status'] == 'ok' for row in rows)
    # wind from port (90) pushes the ship off the quay: the breast lines take it; from
    # starboard (270) onto its fenders, which take it
    port, starboard = rows[2], rows[6]
    assert float(port['breast_fwd_mbl_percent']) > 3 * float(starboard['breast_fwd_mbl_percent'])
    assert float(port['sway']) < 0.0 < float(starboard['sway'])
    assert float(starboard['fender_2_load']) > 1e5 and float(port['fender_2_load']) == 0.0


@pytest.mark.parametrize('arguments, message', [
    (['--current', '1,2'], "--current '1,2' is not allowed"),
    (['--directions', '0'], '--directions 0 is not allowed'),
    (['--set', 'ship.beam=-3'], "parameter 'ship.beam' = -3"),
])
def test_berth_check_refuses_bad_input_in_one_line(repo_root, tmp_path, capsys, arguments,
                                                   message):
    code = cli.main(['berth-check', str(repo_root / 'config' / 'berth.yaml'), '--out',
                     str(tmp_path / 'x'), *arguments])
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count('\n') == 1, err
