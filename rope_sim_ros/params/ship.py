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
The ship of an arrangement and what stands around it: the parameter tables and their values.

`ship_mode` says who moves the ship: `driven` (a ship simulator: the ship follows
ship/pose) or `free` (a rigid body in six degrees of freedom that moves under its lines, its
fenders and the loads on it). `ship.*` is the ship itself; `fenders` names the fenders on the
quay, each with its settings under its name (`fender_1.position`), as `lines` names the
lines. Every error is one line naming the parameter and what is allowed.

The defaults are a loaded 225 m Panamax bulk carrier (225 m x 32.2 m x 14.0 m, block
coefficient 0.85, in sea water): its displaced mass, radii of gyration of 0.35 B in roll and
0.25 L in pitch and yaw, added masses and damping of the usual orders for such a hull (a few
per cent of critical in surge, sway and yaw, more in heave and pitch). They let a free ship
start without further settings; a study of a real ship gives that ship's numbers.
"""

from dataclasses import dataclass, field, fields
import math
import os
from typing import Any, Dict, List, Mapping, Tuple

from .materials import default_config_dir
from .names import check_names
from .table import ParameterError, Spec
from ..model.ship.coefficients import CoefficientFileError, parse_coefficient_csv
from ..model.ship.motions import MOTION_CRITERIA, MotionLimits

SHIP = 'ship'
PASSING_SHIP = 'passing_ship'
WAVES = 'waves'
FENDERS = 'fenders'
SHIP_MODES = ('driven', 'free')
WIND_SPECTRA = ('none', 'api', 'npd')
WAVE_SPECTRA = ('none', 'regular', 'jonswap')
MAX_FENDERS = 32
FENDERS_DESCRIPTION = 'names of the fenders on the quay; each has its settings under its name'
# The ship's settings a run may change (as the lines' shared `current`): the wind, the waves.
WIND_SETTINGS = ('wind_speed', 'wind_direction')
WAVE_SETTINGS = ('waves.height', 'waves.period', 'waves.direction')
SHIP_SETTINGS = WIND_SETTINGS + WAVE_SETTINGS
# What of the mooring's one environment a run may change, on its topics or as parameters.
ENVIRONMENT_SETTINGS = ('current',) + SHIP_SETTINGS

# The ship as a whole: what the arrangement's top level takes (`ship.mass`, ...).
SHIP_SPECS: Mapping[str, Spec] = {
    'ship_mode': Spec(
        'driven', '', 'driven: the ship follows ship/pose (a ship simulator integrates it); '
        'free: a rigid body in six degrees of freedom, moved by its lines, fenders and the '
        'loads on it, publishing ship/pose and ship/odometry', choices=SHIP_MODES),
    'ship.mass': Spec(8.84e7, 'kg', "the ship's mass: its displaced water's at the start pose",
                      0.0, 1.0e10, low_open=True),
    'ship.center_of_gravity': Spec(
        [0.0, 0.0, -3.0], 'm', 'its centre of gravity in the body frame (x forward, y to '
        'port, z up from the body origin)', high=1.0e4),
    'ship.radii_of_gyration': Spec(
        [11.3, 56.3, 56.3], 'm', 'radii of gyration in roll, pitch and yaw about the centre '
        'of gravity', low=0.0, high=1.0e4),
    'ship.added_mass': Spec(
        [4.4e6, 7.0e7, 8.5e7, 2.3e9, 2.8e11, 3.0e11], 'kg, kg*m^2', 'added mass in surge, sway, '
        'heave [kg] and added inertia in roll, pitch, yaw [kg*m^2], about the centre of '
        'gravity in body axes', low=0.0, high=1.0e16, size=6),
    'ship.linear_damping': Spec(
        [7.5e5, 7.5e5, 2.1e7, 6.0e8, 7.0e10, 3.0e9], 'N*s/m, N*m*s/rad', 'linear damping in '
        'surge, sway, heave [N per m/s] and roll, pitch, yaw [N*m per rad/s], about the centre '
        'of gravity in body axes', low=0.0, high=1.0e16, size=6),
    'ship.quadratic_damping': Spec(
        [0.0] * 6, 'N*s^2/m^2, N*m*s^2/rad^2', 'quadratic damping in surge, sway, heave '
        '[N per (m/s)^2] and roll, pitch, yaw [N*m per (rad/s)^2], about the centre of gravity '
        "in body axes (0 by default: the current's load, taken on the velocity of the water "
        'relative to the ship, is already the drag of a ship moving in still water)',
        low=0.0, high=1.0e16, size=6),
    'ship.waterplane_area': Spec(
        6520.0, 'm^2', 'waterplane area: the heave stiffness is rho g times it', 0.0, 1.0e7,
        low_open=True),
    'ship.metacentric_height': Spec(
        [3.0, 250.0], 'm', 'transverse and longitudinal metacentric heights GM_T, GM_L: the '
        'roll and pitch stiffnesses are m g times them', low=0.0, high=1.0e5, size=2),
    'ship.start_position': Spec(
        [0.0, 0.0, 0.0], 'm', 'where the body origin floats without its lines, in frame_id: '
        'the free ship starts there, at rest', high=1.0e7),
    'ship.start_yaw': Spec(
        0.0, 'rad', "the ship's heading at the start: yaw of its body x from frame_id's x, "
        'counter-clockwise', -2.0 * math.pi, 2.0 * math.pi),
    'ship.length': Spec(225.0, 'm', 'length between perpendiculars: the hull box the fenders '
                        'touch, and the wind, current and passing-ship loads', 0.0, 1.0e4,
                        low_open=True),
    'ship.beam': Spec(32.2, 'm', 'beam: the hull box the fenders touch', 0.0, 1.0e3,
                      low_open=True),
    'ship.draft': Spec(14.0, 'm', 'draft: the hull box reaches this far below the body origin',
                       0.0, 1.0e3, low_open=True),
    'ship.block_coefficient': Spec(
        0.85, '', 'block coefficient C_b: the passing-ship loads take the hull as a parabolic '
        'sectional-area curve holding C_b L B T', 0.3, 1.0),
    'ship.motion_criteria': Spec(
        'bulk_cranes', '', "the row of PIANC's (1995) motion criteria for safe working that a "
        "run's ship motions are held to (rope_sim info, a study's results): the kind of ship "
        'and of its cargo handling', choices=tuple(MOTION_CRITERIA)),
    'ship.mesh': Spec(
        '', '', "the hull's mesh for rope_sim hydro, in a format Capytaine reads (GDF, STL, "
        'OBJ, PNL, ...), body axes with z = 0 at the still water, absolute or relative to the '
        "parameter file's folder; empty = the parametric hull of ship.length, beam, draft and "
        'block_coefficient'),
    'ship.wind_area_front': Spec(
        450.0, 'm^2', 'front projected area above the water, A_T of the wind coefficients',
        0.0, 1.0e6, low_open=True),
    'ship.wind_area_side': Spec(
        2500.0, 'm^2', 'side projected area above the water, A_L of the wind coefficients',
        0.0, 1.0e6, low_open=True),
    'ship.current_area_front': Spec(
        0.0, 'm^2', 'front projected area below the water, A_T of the current coefficients; '
        '0 = beam x draft', 0.0, 1.0e6),
    'ship.current_area_side': Spec(
        0.0, 'm^2', 'side projected area below the water, A_L of the current coefficients; '
        '0 = length x draft', 0.0, 1.0e6),
    'ship.wind_coefficients': Spec(
        '', '', 'CSV table angle_deg, cx, cy, cmz of the wind loads (OCIMF form), absolute or '
        "relative to the parameter file's folder; empty = the shipped loaded tanker "
        "(config/ship/wind_coefficients_tanker_loaded.csv): use your own ship's"),
    'ship.current_coefficients': Spec(
        '', '', 'CSV table(s) angle_deg, cx, cy, cmz of the current loads, as '
        'ship.wind_coefficients: one path (one table at every depth), or a list of '
        '[ratio, path] pairs, one table per water depth / draft ratio (the depth: '
        'water_level - seabed_level), ratios >= 1 and rising, interpolated linearly in the '
        "ratio (a ROS parameter file takes the flat form ['1.1', a.csv, '1.5', b.csv]); "
        'empty = the shipped loaded tanker or bulk carrier, deep '
        '(config/ship/current_coefficients_tanker_loaded.csv) and at 1.1 to 5 times the '
        "draft (UFC 4-159-03's depth factor: current_coefficients_tanker_loaded_depth_*.csv)"),
    'ship.hydrodynamics': Spec(
        '', '', "the hull's hydrodynamic database (`rope_sim hydro` writes it), absolute or "
        "relative to the parameter file's folder: a free ship then takes its added mass at "
        'infinite frequency, 6x6 with its couplings, in place of ship.added_mass and the '
        'radiation memory of its damping (the Cummins equation); ship.linear_damping and '
        'ship.quadratic_damping still add; empty = none (docs/waves.md)'),
    'stiffness_rate': Spec(
        1.0, 'Hz', 'rate of ship/stiffness (the 6x6 stiffness of the lines and fenders about '
        "the ship's present pose); 0 = off", 0.0, 100.0, read_only=False),
    # the wind on the ship (the current is the lines' `current`)
    'wind_speed': Spec(
        0.0, 'm/s', 'mean wind speed at 10 m: with the wind coefficients, the load on the ship '
        '(a free ship moves under it; environment/wind sets it at run time)', 0.0, 100.0,
        read_only=False),
    'wind_direction': Spec(
        0.0, 'rad', 'direction the wind comes FROM in frame_id, counter-clockwise from +x',
        -2.0 * math.pi, 2.0 * math.pi, read_only=False),
    'wind_spectrum': Spec(
        'none', '', 'none: a steady wind; api or npd: gusts from that spectrum about the mean, '
        'repeatable with wind_seed', choices=WIND_SPECTRA),
    'wind_seed': Spec(0, '', "seed of the gusts' random phases", 0, 2 ** 31 - 1),
    # the waves on the ship (long-crested; their loads need ship.hydrodynamics)
    'waves.spectrum': Spec(
        'none', '', 'none: no waves; regular: one wave of height H and period T; jonswap: '
        'an irregular sea of significant height Hs and peak period Tp, repeatable with '
        'waves.seed; their loads on the ship come from its hydrodynamic database',
        choices=WAVE_SPECTRA),
    'waves.height': Spec(
        0.0, 'm', 'wave height H (regular) or significant wave height Hs (jonswap); 0 = calm',
        0.0, 30.0, read_only=False),
    'waves.period': Spec(
        8.0, 's', 'wave period T (regular) or peak period Tp (jonswap)', 1.0, 40.0,
        read_only=False),
    'waves.direction': Spec(
        0.0, 'rad', 'direction the waves come FROM in frame_id, counter-clockwise from +x',
        -2.0 * math.pi, 2.0 * math.pi, read_only=False),
    'waves.peak_enhancement': Spec(
        3.3, '', "JONSWAP's peak enhancement factor gamma (1 = Pierson-Moskowitz)", 1.0, 10.0),
    'waves.seed': Spec(0, '', "seed of the irregular sea's frequencies and phases", 0,
                       2 ** 31 - 1),
}
# A ship passing the moored one (Wang's slender-body loads, at the water's depth):
# `passing_ship.*`.
PASSING_SPECS: Mapping[str, Spec] = {
    'passing_ship.speed': Spec(
        0.0, 'm/s', "the passing ship's speed through the water; 0 = no passing ship", 0.0,
        20.0),
    'passing_ship.length': Spec(200.0, 'm', 'its length between perpendiculars', 0.0, 1.0e3,
                                low_open=True),
    'passing_ship.beam': Spec(32.0, 'm', 'its beam', 0.0, 200.0, low_open=True),
    'passing_ship.draft': Spec(12.0, 'm', 'its draft', 0.0, 50.0, low_open=True),
    'passing_ship.block_coefficient': Spec(0.8, '', 'its block coefficient', 0.3, 1.0),
    'passing_ship.separation': Spec(
        60.0, 'm', 'distance between the two centrelines, positive with the passing ship on '
        "the moored ship's starboard side (body -y); at least half the two beams",
        -1.0e4, 1.0e4),
    'passing_ship.start_x': Spec(
        -1000.0, 'm', "its midship's place along the moored ship's body x at t = 0",
        -1.0e5, 1.0e5),
    'passing_ship.direction': Spec(
        1, '', "+1: it moves along the moored ship's body +x; -1: along -x", -1, 1),
    'passing_ship.image_pairs': Spec(
        0, '', "at a finite depth (water_level - seabed_level), the sea bed's images its "
        'loads sum: 0 = until the sum changes by less than 1e-4 of itself; n > 0 = the '
        'images -n..n only (the legacy programs sum -10..10, 0.6 to 1.2 % low abeam)',
        0, 1000),
}
# A fender's settings, under its name (`fender_1.position`).
FENDER_SPECS: Mapping[str, Spec] = {
    'position': Spec([0.0, 0.0, 0.0], 'm', 'the centre of its face, uncompressed, in frame_id'),
    'normal': Spec([0.0, 0.0, 0.0], '', 'direction out of the quay toward the ship, in '
                   'frame_id (normalised)'),
    'curve': Spec([0.0, 0.0], 'm, N', 'its load-compression curve as the manufacturer rates '
                  'it: compression [m] and reaction [N] pairs, from (0, 0) (added when left '
                  'out), linear between the points and with the last slope past them',
                  low=0.0, pairs=True),
    'friction': Spec(0.2, '', 'friction coefficient of its face against the hull (0: none)',
                     0.0, 2.0),
    'rated_compression': Spec(
        0.0, 'm', 'the compression it is rated for: diagnostics warn past it (0: the last '
        "point of the curve's)", 0.0, 100.0),
}
# What every fender must set itself: where it is and how it pushes.
FENDER_REQUIRED = ('position', 'normal', 'curve')


@dataclass(frozen=True)
class ShipParams:
    """
    Validated ship parameters (SHIP_SPECS: units and meanings); names without `ship.`.

    :ivar mode: 'driven' or 'free'.
    """

    mode: str = SHIP_SPECS['ship_mode'].default
    mass: float = SHIP_SPECS['ship.mass'].default
    center_of_gravity: list = field(
        default_factory=lambda: list(SHIP_SPECS['ship.center_of_gravity'].default))
    radii_of_gyration: list = field(
        default_factory=lambda: list(SHIP_SPECS['ship.radii_of_gyration'].default))
    added_mass: list = field(default_factory=lambda: list(SHIP_SPECS['ship.added_mass'].default))
    linear_damping: list = field(
        default_factory=lambda: list(SHIP_SPECS['ship.linear_damping'].default))
    quadratic_damping: list = field(
        default_factory=lambda: list(SHIP_SPECS['ship.quadratic_damping'].default))
    waterplane_area: float = SHIP_SPECS['ship.waterplane_area'].default
    metacentric_height: list = field(
        default_factory=lambda: list(SHIP_SPECS['ship.metacentric_height'].default))
    start_position: list = field(
        default_factory=lambda: list(SHIP_SPECS['ship.start_position'].default))
    start_yaw: float = SHIP_SPECS['ship.start_yaw'].default
    length: float = SHIP_SPECS['ship.length'].default
    beam: float = SHIP_SPECS['ship.beam'].default
    draft: float = SHIP_SPECS['ship.draft'].default
    block_coefficient: float = SHIP_SPECS['ship.block_coefficient'].default
    motion_criteria: str = SHIP_SPECS['ship.motion_criteria'].default
    mesh: str = SHIP_SPECS['ship.mesh'].default
    wind_area_front: float = SHIP_SPECS['ship.wind_area_front'].default
    wind_area_side: float = SHIP_SPECS['ship.wind_area_side'].default
    current_area_front: float = SHIP_SPECS['ship.current_area_front'].default
    current_area_side: float = SHIP_SPECS['ship.current_area_side'].default
    wind_coefficients: str = SHIP_SPECS['ship.wind_coefficients'].default
    # a path, or [ratio, path, ratio, path, ...] as text (check_current_tables)
    current_coefficients: Any = SHIP_SPECS['ship.current_coefficients'].default
    hydrodynamics: str = SHIP_SPECS['ship.hydrodynamics'].default
    stiffness_rate: float = SHIP_SPECS['stiffness_rate'].default
    wind_speed: float = SHIP_SPECS['wind_speed'].default
    wind_direction: float = SHIP_SPECS['wind_direction'].default
    wind_spectrum: str = SHIP_SPECS['wind_spectrum'].default
    wind_seed: int = SHIP_SPECS['wind_seed'].default
    waves_spectrum: str = SHIP_SPECS['waves.spectrum'].default
    waves_height: float = SHIP_SPECS['waves.height'].default
    waves_period: float = SHIP_SPECS['waves.period'].default
    waves_direction: float = SHIP_SPECS['waves.direction'].default
    waves_peak_enhancement: float = SHIP_SPECS['waves.peak_enhancement'].default
    waves_seed: int = SHIP_SPECS['waves.seed'].default

    @property
    def free(self) -> bool:
        """Tell whether the ship is a free body (ship_mode free)."""
        return self.mode == 'free'

    @property
    def motion_limits(self) -> MotionLimits:
        """Return the motion criteria of safe cargo handling it is held to."""
        return MOTION_CRITERIA[self.motion_criteria]

    def values(self) -> Dict[str, Any]:
        """Return every value under its parameter name (`ship.mass`, `ship_mode`)."""
        return {parameter_name(f.name): getattr(self, f.name) for f in fields(self)}


def parameter_name(name: str) -> str:
    """Return a ShipParams field's parameter name: mode -> ship_mode, mass -> ship.mass."""
    if name == 'mode':
        return 'ship_mode'
    if name.startswith(WAVES + '_'):
        return f'{WAVES}.{name[len(WAVES) + 1:]}'
    return name if name in SHIP_SPECS else f'{SHIP}.{name}'


def field_name(name: str) -> str:
    """Return the ShipParams field of a parameter name (parameter_name's inverse)."""
    if name == 'ship_mode':
        return 'mode'
    if name.startswith(WAVES + '.'):
        return f'{WAVES}_{name.partition(".")[2]}'
    return name.partition('.')[2] if name.startswith(SHIP + '.') else name


@dataclass(frozen=True)
class PassingShipParams:
    """Validated passing_ship.* parameters (PASSING_SPECS: units and meanings)."""

    speed: float = PASSING_SPECS['passing_ship.speed'].default
    length: float = PASSING_SPECS['passing_ship.length'].default
    beam: float = PASSING_SPECS['passing_ship.beam'].default
    draft: float = PASSING_SPECS['passing_ship.draft'].default
    block_coefficient: float = PASSING_SPECS['passing_ship.block_coefficient'].default
    separation: float = PASSING_SPECS['passing_ship.separation'].default
    start_x: float = PASSING_SPECS['passing_ship.start_x'].default
    direction: int = PASSING_SPECS['passing_ship.direction'].default
    image_pairs: int = PASSING_SPECS['passing_ship.image_pairs'].default

    @property
    def present(self) -> bool:
        """Tell whether a ship passes (speed > 0)."""
        return self.speed > 0.0

    def values(self) -> Dict[str, Any]:
        """Return every value under its parameter name (`passing_ship.speed`)."""
        return {f'{PASSING_SHIP}.{f.name}': getattr(self, f.name) for f in fields(self)}


def passing_ship(values: Mapping[str, Any]) -> PassingShipParams:
    """
    Return the passing ship of checked passing_ship.* values.

    :raises ParameterError: direction 0.
    """
    own = {name.partition('.')[2]: value for name, value in values.items()}
    if own.get('direction', 1) == 0:
        raise ParameterError(f"parameter '{PASSING_SHIP}.direction' = 0 is not allowed: must "
                             'be 1 (along body +x) or -1')
    return PassingShipParams(**own)


def check_passing_clear(ship: ShipParams, passing: PassingShipParams) -> None:
    """
    Refuse a passing ship whose hull would overlap the moored one's as it passes.

    Its loads hold for hulls apart only: one whose track overlaps (separation 10 m with
    beams of 32 m) passed silently, its load zero.

    :raises ParameterError: |separation| below half the sum of the beams.
    """
    clear = 0.5 * (ship.beam + passing.beam)
    if passing.present and abs(passing.separation) < clear:
        raise ParameterError(
            f"parameter '{PASSING_SHIP}.separation' = {passing.separation:g} is not allowed: "
            f'the hulls would overlap; at least {clear:g} m (half the sum of the beams, '
            f'{ship.beam:g} m and {passing.beam:g} m) off either side')


@dataclass(frozen=True)
class FenderSetup:
    """
    One fender on the quay (FENDER_SPECS: units and meanings).

    :ivar curve: (compression, reaction) pairs from (0, 0).
    :ivar rated_compression: > 0: the chosen one, or the curve's last compression.
    """

    name: str
    position: Tuple[float, float, float]
    normal: Tuple[float, float, float]
    curve: Tuple[Tuple[float, float], ...]
    friction: float
    rated_compression: float

    def values(self) -> Dict[str, Any]:
        """Return its settings as a parameter file holds them."""
        return {'position': list(self.position), 'normal': list(self.normal),
                'curve': [c for pair in self.curve for c in pair],
                'friction': self.friction, 'rated_compression': self.rated_compression}


def check_fender_names(value: Any, taken) -> List[str]:
    """Validate the `fenders` parameter (names.check_names); taken: the lines', parameters'."""
    return check_names(FENDERS, value, 'fender', MAX_FENDERS, taken, 'a line, a parameter')


def fender_setup(name: str, values: Mapping[str, Any]) -> FenderSetup:
    """
    Return a fender from its checked settings (check_fender_value each).

    :raises ParameterError: a required setting missing, a zero normal, a curve whose
        reaction falls or that does not start at (0, 0).
    """
    missing = [f'{name}.{key}' for key in FENDER_REQUIRED if key not in values]
    if missing:
        raise ParameterError(f'fender {name!r} is missing settings: set {"; ".join(missing)} '
                             '(position and normal in frame_id, curve as compression [m] and '
                             'reaction [N] pairs)')
    normal = values['normal']
    norm = math.sqrt(sum(c * c for c in normal))
    if norm < 1e-9:
        raise ParameterError(f'parameter {name + ".normal"!r} = {normal!r} is not allowed: '
                             'must point out of the quay toward the ship (not zero)')
    flat = values['curve']
    pairs = [(flat[i], flat[i + 1]) for i in range(0, len(flat), 2)]
    if pairs[0][0] > 0.0:
        pairs.insert(0, (0.0, 0.0))
    if pairs[0] != (0.0, 0.0) or any(b[1] < a[1] for a, b in zip(pairs, pairs[1:])) or \
            pairs[-1][1] <= 0.0:
        raise ParameterError(f'parameter {name + ".curve"!r} = {flat!r} is not allowed: the '
                             'reaction must start at 0 at no compression and never fall')
    rated = values.get('rated_compression', 0.0) or pairs[-1][0]
    return FenderSetup(name, tuple(values['position']), tuple(c / norm for c in normal),
                       tuple(pairs), values.get('friction', FENDER_SPECS['friction'].default),
                       rated)


# The shipped coefficient tables (config/ship/), for a table parameter left empty: the wind's,
# the current's in deep water, and the current's set by water depth / draft (its deepest
# entry the deep table: test/data/ship_coefficients/ufc_depth_current_tanker_loaded.py).
DEFAULT_TABLES = {'wind_coefficients': 'wind_coefficients_tanker_loaded.csv',
                  'current_coefficients': 'current_coefficients_tanker_loaded.csv'}
DEFAULT_CURRENT_TABLES = tuple(
    [(ratio, f'current_coefficients_tanker_loaded_depth_{ratio:g}T.csv')
     for ratio in (1.1, 1.2, 1.3, 1.5, 2.0, 3.0, 5.0)]
    + [(10.0, DEFAULT_TABLES['current_coefficients'])])
CURRENT_TABLES = f'{SHIP}.current_coefficients'


def check_current_tables(value: Any) -> Any:
    """
    Validate ship.current_coefficients: a path, or [ratio, path] pairs (flat or nested).

    :returns: the path, or the flat list [ratio, path, ...] as text (a ROS string array).
    :raises ParameterError: anything else, or ratios not >= 1 and rising.
    """
    bad = ParameterError(
        f'parameter {CURRENT_TABLES!r} = {value!r} is not allowed: must be a CSV path, or a '
        'list of [ratio, path] pairs, one table per water depth / draft ratio, the ratios '
        ">= 1 and rising (a ROS parameter file takes the flat form ['1.1', a.csv, '1.5', "
        'b.csv])')
    if isinstance(value, str):
        return value
    if not isinstance(value, (list, tuple)) or not value:
        raise bad
    if all(isinstance(pair, (list, tuple)) for pair in value):
        pairs = value
    elif len(value) % 2 == 0:
        pairs = [value[i:i + 2] for i in range(0, len(value), 2)]
    else:
        raise bad
    checked = []
    for pair in pairs:
        if len(pair) != 2 or not isinstance(pair[1], str) or not pair[1] \
                or isinstance(pair[0], bool):
            raise bad
        try:
            ratio = float(pair[0])
        except (TypeError, ValueError):
            raise bad from None
        if not (math.isfinite(ratio) and ratio >= 1.0) or \
                (checked and ratio <= float(checked[-2])):
            raise bad
        checked += [repr(ratio), pair[1]]
    return checked


def current_table_paths(value: Any) -> List[Tuple[float, str]]:
    """Return the (ratio, path) pairs of a checked ship.current_coefficients ('' included)."""
    if isinstance(value, str):
        return [(1.0, value)]
    return [(float(value[i]), value[i + 1]) for i in range(0, len(value), 2)]


def tables_relative_to(value: Any, folder: str) -> Any:
    """Return a table parameter's value with its relative paths taken from `folder`."""
    def absolute(path: str) -> str:
        return os.path.join(folder, path) if path and not os.path.isabs(path) else path
    if isinstance(value, str):
        return absolute(value)
    return [item if k % 2 == 0 else absolute(item) for k, item in enumerate(value)]


def read_coefficients(ship: ShipParams, name: str):
    """
    Return the ship's wind coefficient table, or a current table's (model/ship/coefficients.py).

    :param name: 'wind_coefficients' or 'current_coefficients' (one path only: a set by
        depth is read_current_tables'); an empty path takes the shipped (deep) table.
    :raises ParameterError: the file cannot be read or is not a coefficient table (one line
        naming the parameter, the file and what is wrong).
    """
    return _read_table(name, getattr(ship, name) or str(
        default_config_dir() / 'ship' / DEFAULT_TABLES[name]))


def read_current_tables(ship: ShipParams) -> List[Tuple[float, Any]]:
    """
    Return the ship's current tables by water depth / draft: (ratio, CoefficientTable) pairs.

    One path gives one pair (its ratio 1: one table at every depth); empty, the shipped set.

    :raises ParameterError: a file that cannot be read or is not a coefficient table.
    """
    if not ship.current_coefficients:
        folder = default_config_dir() / 'ship'
        pairs = [(ratio, str(folder / name)) for ratio, name in DEFAULT_CURRENT_TABLES]
    else:
        pairs = current_table_paths(ship.current_coefficients)
    return [(ratio, _read_table('current_coefficients', path)) for ratio, path in pairs]


def _read_table(name: str, path: str):
    """Read one coefficient table for the parameter `name` (ParameterError naming both)."""
    try:
        with open(path, encoding='utf-8') as stream:
            return parse_coefficient_csv(stream.read(), path)
    except OSError as e:
        raise ParameterError(f'parameter {SHIP}.{name!r}: cannot read {path}: '
                             f'{e.strerror or e}') from None
    except CoefficientFileError as e:
        raise ParameterError(f'parameter {SHIP}.{name!r}: {e}') from None
