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
The moored ship at rest: equilibrium and stiffness against MoorPy, fenders, rope_sim stiffness.

MoorPy (NREL's quasi-static mooring model, on PyPI) is the independent judge: a body with
lines between fixed points and points on the body, and an external force and moment,
solved by its own catenary and Newton. Its body is set to match the ship: mass m at rCG,
displaced volume v = m / rho at the reference point (the ship's origin, on the waterline at
rest), waterplane area AWP, metacentre rM = rCG + (0, 0, GM) (one GM for roll and pitch:
MoorPy's metacentre is a point, so the test ship has GM_T = GM_L). Its lines' weight w is
what MoorPy takes for a line whose ends are both above the water (its wet weight: the
lineType's w), set to ours in air. Its body stiffness getStiffnessA is -dF/dx about the
reference point, rotations about the world axes: the convention of ShipStatics.stiffness;
lines_only=True leaves out the weight, buoyancy and waterplane terms.
"""

import math

import moorpy
import numpy as np
import pytest

from rope_sim_ros.model.body import Body, Fender
from rope_sim_ros.model.objects import Environment
from rope_sim_ros.model.rope import RopeProperties
from rope_sim_ros.model.statics.pretension import length_for_tension
from rope_sim_ros.model.statics.ship import Pose, ShipStatics, StaticLine, StaticsError
from rope_sim_ros.mooring.mooring import Mooring
from rope_sim_ros.mooring.statics import (ship_equilibrium, ship_statics, ship_stiffness,
                                          stiffness_now)
from rope_sim_ros.offline import berth_check, cli
from rope_sim_ros.params.arrangement import read_setup
from rope_sim_ros.params.ship import DEFAULT_CURRENT_TABLES

WATER = 1025.0
G = 9.81
MASS = 8.84e7  # the default ship: a loaded 225 m Panamax bulk carrier
CENTRE = (0.0, 0.0, -3.0)
GM = 3.0
WATERPLANE = 6520.0
START = (0.0, -17.6, 0.0)
HULL = (225.0, 32.2, 14.0)

# (mass [kg/m], EA [N], diameter [m]): MoorPy's 64 mm polyester and nylon, 48 mm HMPE
POLYESTER = (2.78, 1.77e7, 0.064)
NYLON = (2.40, 4.2e6, 0.064)
HMPE = (1.14, 7.5e7, 0.048)
# rope, fairlead (body frame), bollard (world, the ship heading +x), fairlead tension at the
# start pose [N] (< 0: slack, its length that many times the distance between its ends)
LINES = (
    (POLYESTER, (106.0, 13.0, 10.0), (150.0, 3.0, 3.5), 1.2e5),
    (NYLON, (82.0, 15.0, 12.0), (88.0, 12.0, 3.5), 8.0e4),
    (HMPE, (62.0, 15.5, 10.0), (12.0, 3.0, 3.5), 1.4e5),
    (HMPE, (-62.0, 15.5, 6.0), (-12.0, 3.0, 3.5), 1.4e5),
    (NYLON, (-82.0, 15.0, 10.0), (-88.0, 12.0, 3.5), -1.2),  # slack: 20 % longer
    (POLYESTER, (-104.0, 13.0, 12.0), (-150.0, 3.0, 3.5), 1.0e5),
)
# off the quay, ahead, and a yawing moment: every line but the slack one stays taut
LOAD = (2.0e5, -4.0e5, 0.0, 0.0, 0.0, -8.0e6)
# config/berth.yaml's ship where its comments put it, with MoorPy's one metacentre
BERTH = {'ship.start_position': list(START), 'ship.metacentric_height': [GM, GM]}


def ship_body(yaw: float = 0.0) -> Body:
    """Return the test ship (GM_T = GM_L: MoorPy's metacentre is one point) at its start."""
    zeros = [0.0] * 6
    return Body.ship(MASS, CENTRE, [11.3, 56.3, 56.3], zeros, zeros, zeros, WATERPLANE,
                     [GM, GM], START, yaw, HULL, WATER, G)


IN_AIR = Environment(gravity=(0.0, 0.0, -G))  # what the lines hang in


def rope(kind, length: float = 1.0) -> RopeProperties:
    """Return a line of MoorPy's numbers (mass, EA, diameter) (in IN_AIR)."""
    mass, ea, diameter = kind
    return RopeProperties(segments=20, length=length, mass_per_length=mass, axial_stiffness=ea,
                          axial_damping=0.0, diameter=diameter)


def turn(yaw: float, point) -> np.ndarray:
    """Return a point of the berth (given for heading +x) turned with the ship by yaw."""
    c, s = math.cos(yaw), math.sin(yaw)
    x, y, z = np.subtract(point, START)
    return np.add(START, (c * x - s * y, s * x + c * y, z))


def statics(yaw: float = 0.0, load=LOAD) -> ShipStatics:
    """Return the test ship and LINES turned by yaw about its start, lengths at the start."""
    body = ship_body(yaw)
    start = Pose.of([*START, 0.0, 0.0, yaw])
    lines = []
    for k, (kind, fairlead, bollard, tension) in enumerate(LINES):
        bollard = turn(yaw, bollard)
        end = start.position + start.rotation @ np.array(fairlead)
        if tension > 0.0:
            length = length_for_tension(rope(kind), IN_AIR, bollard, end, tension)
        else:
            length = -tension * float(np.linalg.norm(end - bollard))
        lines.append(StaticLine(rope(kind, length), IN_AIR, bollard, np.array(fairlead),
                                f'line_{k}'))
    force = turn(yaw, np.add(START, load[:3])) - START
    return ShipStatics(lines, body, None, [*force, *load[3:]])


def moorpy_system(ship: ShipStatics, pose: Pose):
    """Return MoorPy's System of the ship's lines and body (at pose) and its Body."""
    body = ship.body
    restoring = body.restoring
    assert body.rest_z == 0.0 and restoring[1] == restoring[2]  # MoorPy's hydrostatics
    gm = restoring[1] / (body.mass * G)
    centre = -np.asarray(body.origin)
    system = moorpy.System(depth=500.0, rho=WATER, g=G)
    mooring = system.addBody(0, pose.vector, m=body.mass, v=body.mass / WATER, rCG=centre,
                             AWP=restoring[0] / (WATER * G), rM=centre + [0.0, 0.0, gm],
                             f6Ext=ship.external_load)
    for k, line in enumerate(ship.lines):
        props = line.props
        # MoorPy's weight is (m - rho pi d_vol^2 / 4) g: d_vol follows from w
        system.setLineType(dnommm=1e3 * props.diameter, name=f'type_{k}',
                           mass=props.mass_per_length,
                           w=props.weight_per_length(line.environment),
                           EA=props.axial_stiffness)
        bollard = system.addPoint(1, line.bollard)
        fairlead = system.addPoint(1, line.fairlead, body=1)
        system.addLine(props.length, f'type_{k}', pointA=bollard.number,
                       pointB=fairlead.number)
    system.initialize()
    return system, mooring


def moorpy_at(ship: ShipStatics, pose: Pose):
    """Return MoorPy's System and Body held at pose (its lines solved there)."""
    system, body = moorpy_system(ship, pose)
    body.type = 1  # fixed: solveEquilibrium only solves the lines
    system.solveEquilibrium()
    return system, body


def assert_close_matrix(ours: np.ndarray, theirs: np.ndarray, rtol: float) -> None:
    """Every term within rtol of MoorPy's, or within 1e-4 of the diagonal terms' scale."""
    scale = np.sqrt(np.outer(np.abs(np.diag(theirs)), np.abs(np.diag(theirs))))
    bad = np.abs(ours - theirs) > rtol * np.abs(theirs) + 1e-4 * scale
    assert not bad.any(), (np.argwhere(bad).tolist(), ours, theirs)


# ------------------------------------------------------------------------ against MoorPy


@pytest.mark.parametrize('yaw', [0.0, 0.6])
def test_equilibrium_against_moorpy(yaw):
    ship = statics(yaw)
    ours = ship.equilibrium()
    # the case is what it says: lines taut but one, at MoorPy's pose too
    tensions = ours.loads.fairlead_tensions
    assert (np.delete(tensions, 4) > 2.0e4).all() and tensions[4] < 5.0e3, tensions
    system, body = moorpy_system(ship, ship.start)
    assert system.solveEquilibrium(tol=1e-7, maxIter=1000)
    theirs = body.r6
    pose = ours.pose.vector
    # the offsets: 0.3 m to 1.9 m of surge and sway, 0.8 degrees of yaw, millimetres of
    # heave, a few thousandths of a radian of roll and pitch
    offset = theirs - ship.start.vector
    assert np.abs(offset[:2]).min() > 0.3 and abs(offset[5]) > 1e-2, offset
    assert ours.offset == pytest.approx(offset, rel=1e-2, abs=1e-9)
    assert pose[:3] == pytest.approx(theirs[:3], abs=1e-4)
    assert ours.loads.fairlead_tensions == pytest.approx([line.TB for line in system.lineList],
                                                         rel=1e-2)
    assert ours.loads.bollard_tensions == pytest.approx([line.TA for line in system.lineList],
                                                        rel=1e-2)
    # (measured: offsets within 1.3e-5 and tensions within 7e-8 of MoorPy's)
    assert np.abs(ours.loads.total[:3]).max() < 1e-3 * np.abs(ship.external_load[:3]).max()


@pytest.mark.parametrize('yaw', [0.0, 0.6])
def test_stiffness_against_moorpy(yaw):
    ship = statics(yaw)
    for pose in (ship.start, ship.equilibrium().pose):
        _, body = moorpy_at(ship, pose)
        assert_close_matrix(ship.stiffness(pose), body.getStiffnessA(lines_only=True), 1e-2)
        assert_close_matrix(ship.stiffness(pose, hydrostatics=True),
                            body.getStiffnessA(lines_only=False), 1e-2)


def test_stiffness_of_the_berth_against_moorpy(repo_root):
    setup = read_setup(repo_root / 'config' / 'berth.yaml', BERTH)
    ship = ship_statics(setup)
    _, body = moorpy_at(ship, ship.start)
    lines = ship.stiffness(fenders=False)  # the berth's fenders touch the hull: MoorPy has none
    assert_close_matrix(lines, body.getStiffnessA(lines_only=True), 1e-2)
    assert np.diag(lines)[[0, 1, 5]].min() > 0.0
    # the fenders in contact stiffen sway and yaw only, and only add to them
    fenders = ship_stiffness(setup) - lines
    assert fenders[1, 1] > 0.0 and fenders[5, 5] > 0.0
    assert np.abs(fenders[[0, 2, 3, 4]][:, [0, 2, 3, 4]]).max() < 1e-6 * lines[0, 0]


def test_stiffness_is_symmetric_but_for_the_moment_of_the_lines():
    # -dM/dtheta of a pull f at lever r holds [f]x [r]x, whose skew part is [r x f]x / 2:
    # K - K^T is the cross-product matrix of the lines' moment (0 where the loads balance)
    ship = statics()
    stiffness = ship.stiffness()
    moment = ship.loads(hydrostatics=False, external=False).lines[3:]
    cross = np.array([[0.0, -moment[2], moment[1]], [moment[2], 0.0, -moment[0]],
                      [-moment[1], moment[0], 0.0]])
    skew = stiffness - stiffness.T
    scale = np.abs(stiffness).max()
    assert np.abs(skew[:3]).max() < 1e-7 * scale
    assert skew[3:, 3:] == pytest.approx(cross, abs=1e-7 * scale)
    assert np.abs(moment).max() > 1e6


# ---------------------------------------------------------------------------- the model


CURVE = ((0.0, 0.0), (0.4, 3.0e5), (0.8, 9.0e5), (1.2, 2.1e6))


def curve_compression(reaction: float) -> float:
    """Return the compression at which CURVE reacts with `reaction` [N]."""
    compressions, reactions = zip(*CURVE)
    return float(np.interp(reaction, reactions, compressions))


def test_one_fender_compressed_by_a_constant_load():
    # the ship's port side lies 1.5 m off the fender face; a steady push of 6e5 N toward
    # the quay at its origin, level with the fender: the fender must give 6e5 N
    fender = Fender((0.0, -0.0, 0.0), (0.0, -1.0, 0.0), CURVE)
    ship = ShipStatics([], ship_body(), [fender.row()], [0.0, 6.0e5, 0.0, 0.0, 0.0, 0.0])
    result = ship.equilibrium()
    compression = curve_compression(6.0e5)  # 0.6 m
    assert result.loads.fender_reactions[0] == pytest.approx(6.0e5, rel=1e-9)
    assert result.loads.fender_compressions[0] == pytest.approx(compression, abs=1e-9)
    assert result.offset[1] == pytest.approx(1.5 + compression, abs=1e-9)


def test_two_fenders_share_an_eccentric_load():
    # 1.5e6 N toward the quay, 20 m forward of midships, on fenders at x = +-50 m: they share
    # it as the moments about the ship's origin say (about 1.05 and 0.45 MN; nothing holds
    # the ship in surge, so its origin may end up anywhere along x), each compressed as its
    # curve says, and the ship yaws by the difference of their compressions over 100 m
    fenders = [Fender((x, 0.0, 0.0), (0.0, -1.0, 0.0), CURVE) for x in (50.0, -50.0)]
    load = [0.0, 1.5e6, 0.0, 0.0, 0.0, 20.0 * 1.5e6]
    result = ShipStatics([], ship_body(), fenders, load).equilibrium()
    reactions = result.loads.fender_reactions
    levers = np.array([50.0, -50.0]) - result.pose.position[0]
    shares = np.linalg.solve([[1.0, 1.0], levers], [load[1], load[5]])
    assert reactions == pytest.approx(shares, rel=1e-9)
    assert reactions == pytest.approx([1.05e6, 0.45e6], rel=1e-3)
    compressions = result.loads.fender_compressions
    assert compressions == pytest.approx([curve_compression(r) for r in reactions], abs=1e-7)
    assert math.tan(result.offset[5]) == pytest.approx(
        (compressions[0] - compressions[1]) / 100.0, rel=1e-6)


def test_hydrostatics_hold_heave_roll_and_pitch():
    # a free-floating ship under a steady vertical force and moments: heave F_z / (rho g
    # A_wp), roll M_x / (m g GM_T), pitch M_y / (m g GM_L); no load: the start pose itself
    ship = ShipStatics([], ship_body())
    assert ship.equilibrium().iterations == 0
    # (one moment at a time: nothing holds the free-floating ship in yaw, and the moments
    # are in world axes)
    for load in ([0.0, 0.0, -2.0e6, 3.0e7, 0.0, 0.0], [0.0, 0.0, 1.0e6, 0.0, -5.0e7, 0.0]):
        result = ShipStatics([], ship_body(), None, load).equilibrium()
        expected = [load[2] / (WATER * G * WATERPLANE), load[3] / (MASS * G * GM),
                    load[4] / (MASS * G * GM)]
        assert result.offset[2:5] == pytest.approx(expected, rel=1e-6)
        assert result.offset[[0, 1, 5]] == pytest.approx([0.0] * 3, abs=1e-12)


def test_a_ship_nothing_holds_has_no_equilibrium():
    ship = ShipStatics([], ship_body(), None, [1.0e5, 0.0, 0.0, 0.0, 0.0, 0.0])
    with pytest.raises(StaticsError, match='no equilibrium of the ship found'):
        ship.equilibrium()


def test_a_line_beyond_its_reach_pulls_its_limit_tension():
    props = rope(HMPE, 40.0)
    line = StaticLine(props, IN_AIR, np.zeros(3), np.zeros(3))
    far = np.array([60.0, 0.0, 5.0])  # 60.2 m > 40 (1 + 0.25) = 50 m
    force, fairlead, bollard, beyond = line.force(far)
    assert beyond and fairlead == bollard == pytest.approx(HMPE[1] * 0.25)
    assert force == pytest.approx(-fairlead * far / np.linalg.norm(far))
    assert not line.force(np.array([45.0, 0.0, 5.0]))[3]


# ------------------------------------------------------------------ the arrangement's ship


def test_pretensioned_lines_start_at_their_pretension(repo_root):
    setup = read_setup(repo_root / 'config' / 'berth.yaml')
    loads = ship_statics(setup).loads()
    pretensions = [line.pretension for line in setup.lines]
    assert loads.fairlead_tensions == pytest.approx(pretensions, rel=1e-9)


def test_the_berth_under_an_off_quay_load_against_moorpy(repo_root):
    # config/berth.yaml's lines, pretensioned at the start pose as a run starts them, hold
    # the ship against a push off the quay (clear of any fender), ahead and yawing
    setup = read_setup(repo_root / 'config' / 'berth.yaml', BERTH)
    load = [1.0e5, -6.0e5, 0.0, 0.0, 0.0, 5.0e6]
    ours = ship_equilibrium(setup, load)
    assert not ours.loads.fender_reactions.any()
    ship = ship_statics(setup, load=load)
    system, body = moorpy_system(ship, ship.start)
    assert system.solveEquilibrium(tol=1e-7, maxIter=1000)
    offset = body.r6 - ship.start.vector
    assert np.abs(offset[[0, 1, 5]]).min() > 1e-3, offset
    assert ours.offset == pytest.approx(offset, rel=1e-2, abs=1e-9)
    assert ours.loads.fairlead_tensions == pytest.approx([line.TB for line in system.lineList],
                                                         rel=1e-2)


def beam_coefficient(repo_root, ratio: float) -> float:
    """Return the shipped set's C_y at 90 degrees at a depth / draft ratio, read by hand."""
    rows = []
    for ratio_of, name in DEFAULT_CURRENT_TABLES:
        with open(repo_root / 'config' / 'ship' / name) as stream:
            for line in stream:
                if line.startswith('90,'):
                    rows.append((ratio_of, float(line.split(',')[2])))
    for (low, low_cy), (high, high_cy) in zip(rows, rows[1:]):
        if low <= ratio <= high:
            return low_cy + (high_cy - low_cy) * (ratio - low) / (high - low)
    raise AssertionError(f'ratio {ratio} outside the set')


@pytest.mark.parametrize('depth', [16.0, 28.0])
def test_the_berth_in_a_beam_current_at_its_depth_against_moorpy(repo_root, depth):
    # OCIMF MEG4's beam current, 0.75 kn from port, pushes the ship off the quay onto its
    # lines at 16 m and 28 m of water (depth / draft 1.14 and 2): the berth check's
    # equilibrium against MoorPy's under the load worked out here from the shipped tables
    speed = 0.75 * 1852.0 / 3600.0
    setup = read_setup(repo_root / 'config' / 'berth.yaml',
                       {**BERTH, 'water_level': 0.0, 'seabed_level': -depth})
    case, = berth_check.check(setup, 0.0, [(0.0, -speed, 0.0)], directions=1)
    assert case.status == 'ok' and not case.fenders.any()
    ship = setup.ship
    # from port (90 degrees): F_y = 1/2 rho V^2 L T C_y(90); C_x(90) = C_mz(90) = 0
    force = 0.5 * WATER * speed ** 2 * ship.length * ship.draft * beam_coefficient(
        repo_root, depth / ship.draft)
    statics = ship_statics(setup, load=[0.0, force, 0.0, 0.0, 0.0, 0.0])
    system, body = moorpy_system(statics, statics.start)
    assert system.solveEquilibrium(tol=1e-7, maxIter=1000)
    offset = body.r6 - statics.start.vector
    assert case.offset[0] == pytest.approx(offset[0], rel=0.02, abs=2e-3)
    assert case.offset[1] == pytest.approx(offset[1], rel=0.01)
    assert case.offset[2] == pytest.approx(offset[5], rel=0.02, abs=1e-5)
    assert case.tensions == pytest.approx([line.TB for line in system.lineList], rel=0.01)


def test_the_same_beam_current_moves_the_ship_further_in_shallower_water(repo_root):
    speed = 0.75 * 1852.0 / 3600.0
    cases = []
    for depth in (16.0, 28.0, None):
        values = dict(BERTH, water_level=0.0,
                      seabed_level=-depth if depth else -math.inf)
        setup = read_setup(repo_root / 'config' / 'berth.yaml', values)
        cases.append(berth_check.check(setup, 0.0, [(0.0, -speed, 0.0)], directions=1)[0])
    shallow, middle, deep = cases
    # the current's lateral coefficient is 2.6 at 1.14 T, 1.25 at 2 T, 0.6 in deep water:
    # 0.77 m off the quay, 0.11 m, and in deep water the lines' pretension still holds the
    # ship on its fenders
    assert -shallow.offset[1] > 5.0 * -middle.offset[1] > 0.0
    assert deep.offset[1] > 0.0 and deep.fenders.sum() > 0.0
    assert not shallow.fenders.any() and not middle.fenders.any()
    assert shallow.tensions.max() > 1.5 * middle.tensions.max()


def rope_sim_matrix(capsys, *args) -> np.ndarray:
    assert cli.main(['stiffness', *args]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    rows = [[float(v) for v in line.split()] for line in out[-6:]]
    assert all(len(row) == 6 for row in rows), out
    return np.array(rows)


def test_rope_sim_stiffness_of_the_berth(capsys, repo_root):
    params = str(repo_root / 'config' / 'berth.yaml')
    matrix = rope_sim_matrix(capsys, '--params', params)
    assert matrix == pytest.approx(ship_stiffness(read_setup(params)), rel=1e-9)
    diagonal = np.abs(np.diag(matrix))
    scale = np.sqrt(np.outer(diagonal, diagonal))
    assert np.abs(matrix - matrix.T).max() < 1e-2 * scale.max()
    assert (np.abs(matrix - matrix.T) <= 1e-2 * scale).all()
    assert matrix[0, 0] > 0.0 and matrix[1, 1] > 0.0 and matrix[5, 5] > 0.0
    with_water = rope_sim_matrix(capsys, '--params', params, '--hydrostatics')
    assert with_water[2, 2] - matrix[2, 2] == pytest.approx(WATER * G * WATERPLANE, rel=1e-6)


@pytest.mark.parametrize('override, message', [
    ('head_1.pretension=1.0e7', "line 'head_1'"),
    ('ship.start_position=[0.0, -17.6]', 'ship.start_position'),
])
def test_rope_sim_stiffness_bad_input_is_one_line(capsys, repo_root, override, message):
    code = cli.main(['stiffness', '--params', str(repo_root / 'config' / 'berth.yaml'),
                     '--set', override])
    err = capsys.readouterr().err.strip()
    assert code == 2 and '\n' not in err and message in err, err


def test_rope_sim_stiffness_of_a_single_line(capsys, repo_root):
    # one line is a mooring of one line: its stiffness at the default ship's start pose
    params = str(repo_root / 'config' / 'mooring_line.yaml')
    matrix = rope_sim_matrix(capsys, '--params', params)
    assert matrix == pytest.approx(ship_stiffness(read_setup(params)), rel=1e-9)
    assert np.diag(matrix)[:3].max() > 0.0
    assert cli.main(['stiffness', '--params', params, '--set', 'payload_mass=100.0']) == 2
    err = capsys.readouterr().err.strip()
    assert '\n' not in err and 'payload' in err, err


def test_the_stiffness_of_a_running_driven_mooring_where_its_ship_is(repo_root):
    # What ship/stiffness publishes for a driven ship: the running Mooring's lines at the
    # ship's pose. At the start pose it is `rope_sim stiffness`; 0.5 m off the quay, the
    # breast lines stiffen the sway and the fenders let go.
    setup = read_setup(repo_root / 'config' / 'berth.yaml')
    mooring = Mooring(setup)
    rest = np.array(setup.ship.start_position)
    quaternion = np.array([0.0, 0.0, 0.0, 1.0])
    mooring.push_ship(0.0, rest, quaternion)
    mooring.start(0.0)
    at_rest = stiffness_now(mooring, rest, quaternion)
    np.testing.assert_allclose(at_rest, ship_stiffness(setup), rtol=1e-9,
                               atol=1e-9 * np.abs(at_rest).max())
    off = stiffness_now(mooring, rest + [0.0, -0.5, 0.0], quaternion)
    lines_only = ship_statics(setup).stiffness([*(rest + [0.0, -0.5, 0.0]), 0.0, 0.0, 0.0],
                                               fenders=False)
    np.testing.assert_allclose(off, lines_only, rtol=1e-9, atol=1e-9 * np.abs(off).max())
    assert off[1, 1] > ship_statics(setup).stiffness(fenders=False)[1, 1]
