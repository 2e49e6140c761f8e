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
The parameter table of a line: one table for the ROS nodes, the offline commands and the docs.

Every parameter has a name, a default, a unit, a description and an allowed range. The node
turns the table into ParameterDescriptors; the runner reads the same keys from the standard
ROS parameter file (`mooring_line: ros__parameters: {...}`).
"""

from dataclasses import dataclass, field, fields, replace
import math
from typing import Any, Mapping, Optional, Sequence


NODE_NAME = 'mooring_line'
MATERIALS = ('nylon', 'polyester', 'hmpe', 'steel_wire', 'manila')
INTEGRATORS = ('adaptive', 'improved_euler', 'implicit_euler')
DAMPING_MODELS = ('axial', 'seed')
LOAD_EXTENSIONS = ('linear', 'curve')
RELIABILITIES = ('reliable', 'best_effort')
# A table given as pairs (a fender's load-compression curve): how many pairs it may hold.
MIN_PAIRS = 2
MAX_PAIRS = 15
WINCH_MODES = ('none', 'speed', 'brake', 'constant_tension')
LINE_STATES = ('fast', 'stowed')  # how a line may start (it may also be free, let go)


class ParameterError(ValueError):
    """A parameter value is not allowed; the message names it and the allowed range."""


@dataclass(frozen=True)
class Spec:
    """
    How one parameter may be set.

    :ivar default: value when the user gives none; its type is the parameter's type.
    :ivar unit: SI unit, '' when dimensionless.
    :ivar description: one line for `ros2 param describe` and the README.
    :ivar low / high: inclusive bounds for numbers (None = unbounded).
    :ivar low_open: the lower bound itself is not allowed (e.g. length > 0).
    :ivar choices: allowed strings.
    :ivar read_only: a change needs a restart (the node refuses it at run time).
    :ivar special: a number outside low..high that is allowed too, with its own meaning
        (-inf: no water; -1: the material's value), or None.
    :ivar special_meaning: what `special` means, a few words.
    :ivar horizontal: a vector whose z component must be 0.
    :ivar size: how many numbers a list parameter holds (a vector's 3 by default).
    :ivar pairs: a list parameter of any even length: pairs of numbers (x0, y0, x1, y1, ...),
        the flat form ROS parameters take a table in; its first numbers of a pair rise.
    """

    default: Any
    unit: str
    description: str
    low: Optional[float] = None
    high: Optional[float] = None
    low_open: bool = False
    choices: tuple = ()
    read_only: bool = True
    special: Optional[float] = None
    special_meaning: str = ''
    horizontal: bool = False
    size: int = 3
    pairs: bool = False


SPECS: Mapping[str, Spec] = {
    'material': Spec('polyester', '', 'rope material preset', choices=MATERIALS),
    'diameter': Spec(0.064, 'm', 'nominal rope diameter', 0.0, 1.0, low_open=True),
    'length': Spec(40.0, 'm', 'unstretched line length', 0.0, 10000.0, low_open=True),
    'segments': Spec(20, '', 'number of segments N (N+1 particles)', 2, 2000),
    'mass_per_length': Spec(
        0.0, 'kg/m', 'mass per unit length; 0 = from the material', 0.0, 1.0e4),
    'axial_stiffness': Spec(
        0.0, 'N', 'axial stiffness EA; 0 = from the material', 0.0, 1.0e13),
    'load_extension': Spec(
        'linear', '', 'linear: the segments pull EA times their strain; curve: they follow the '
        "material's strain-tension curve (config/materials.yaml; nylon and polyester have "
        'one), linear between its points and with its last slope past them; '
        'axial_stiffness then only sets the bending springs and the default damping, and '
        'max_strain is raised to the strain at which the curve pulls twice the breaking '
        'load', choices=LOAD_EXTENSIONS),
    'axial_damping': Spec(
        0.0, 'N*s', 'axial damping BA (per unit strain rate, as MoorDyn); '
        '0 = 1 % of critical for the first axial mode', 0.0, 1.0e10, read_only=False),
    'damping_model': Spec(
        'axial', '', 'axial: damp the stretch rate only; seed: K_SD (V_A - V_B), which also '
        'damps rigid rotation of a segment', choices=DAMPING_MODELS),
    'bending_stiffness_ratio': Spec(
        1.0e-4, '', 'bending spring (i, i+2) stiffness relative to a structural spring',
        0.0, 10.0),
    'bending_damping_ratio': Spec(
        1.0e-4, '', 'bending spring damping relative to a structural spring', 0.0, 10.0,
        read_only=False),
    'air_drag_coefficient': Spec(
        0.0, 'N*s^2/m^3', "the seed paper's isotropic quadratic drag K_A per metre of rope: "
        'f = -K_A |v| v (0.5 rho Cd d is about 0.05 for a 64 mm line in air), on top of the '
        "drag of the line's own coefficients in air and water", 0.0, 1.0e4, read_only=False),
    'gravity': Spec([0.0, 0.0, -9.81], 'm/s^2', 'gravity vector in frame_id (REP-103: z up)'),
    # Water and ground. Read-only because the line starts at rest in its equilibrium in
    # them (buoyant, lying on the seabed): a change needs that start again, i.e. a restart.
    'water_level': Spec(
        -math.inf, 'm', 'z of the still water surface in frame_id; -.inf (the default) = no '
        'water, a finite value switches the water on', -1.0e5, 1.0e5,
        special=-math.inf, special_meaning='no water'),
    'water_density': Spec(
        1025.0, 'kg/m^3', 'density of the water (sea water 1025, fresh water 1000)',
        0.0, 2.0e4, low_open=True),
    'air_density': Spec(
        1.225, 'kg/m^3', 'density of the air above the water: its buoyancy and, with the '
        "line's drag coefficients, its drag (0 = no air, as MoorDyn)", 0.0, 100.0),
    'current': Spec(
        [0.0, 0.0, 0.0], 'm/s', 'uniform current velocity below the water surface, in '
        'frame_id; settable at run time (no restart)', high=50.0, read_only=False),
    'seabed_level': Spec(
        -math.inf, 'm', 'z of the flat seabed in frame_id; -.inf (the default) = no seabed',
        -1.0e5, 1.0e5, special=-math.inf, special_meaning='no seabed'),
    'seabed_stiffness': Spec(
        3.0e6, 'Pa/m', "ground contact stiffness, MoorDyn's kBot: normal force k delta d per "
        "metre of line at a penetration delta (d: nominal diameter); also the quay's",
        0.0, 1.0e12, low_open=True),
    'seabed_damping': Spec(
        3.0e5, 'Pa*s/m', "ground contact damping, MoorDyn's cBot: -c v_normal d per metre of "
        "line in contact (fading in over the line's static sink depth); also the quay's",
        0.0, 1.0e12),
    'seabed_friction': Spec(
        0.0, '', "friction coefficient mu of the seabed and the quay, MoorDyn's "
        'FrictionCoefficient: against sliding, mu 200 N*s/m times the slip speed up to '
        "mu times the contact force (MoorDyn's regularised Coulomb); 0 = frictionless",
        0.0, 10.0),
    'quay_edge': Spec(
        [0.0, 0.0, 0.0], 'm', 'a point on the top edge of the quay face in frame_id; its z is '
        'the deck level'),
    'quay_normal': Spec(
        [0.0, 0.0, 0.0], '', 'horizontal direction [nx, ny, 0] out of the quay face towards '
        'the water (normalised); all zero (the default) = no quay', horizontal=True),
    'quay_depth': Spec(
        1.0e4, 'm', 'how far below the deck the quay block reaches (its face ends there)',
        0.0, 1.0e5, low_open=True),
    # The line's hydrodynamics, MoorDyn's meanings (its line tables carry over); -1 takes
    # the material's value (config/materials.yaml), since 0 is a legitimate coefficient.
    'normal_drag_coefficient': Spec(
        -1.0, '', "MoorDyn's Cd: drag normal to the line, on the nominal diameter; -1 = the "
        "material's", 0.0, 100.0, special=-1.0, special_meaning="the material's"),
    'tangential_drag_coefficient': Spec(
        -1.0, '', "MoorDyn's CdAx: drag along the line, on the circumference pi d; -1 = the "
        "material's", 0.0, 100.0, special=-1.0, special_meaning="the material's"),
    'normal_added_mass_coefficient': Spec(
        -1.0, '', "MoorDyn's Ca: added mass normal to the line, of the displaced volume; "
        "-1 = the material's", 0.0, 100.0, special=-1.0, special_meaning="the material's"),
    'tangential_added_mass_coefficient': Spec(
        -1.0, '', "MoorDyn's CaAx: added mass along the line, of the displaced volume; "
        "-1 = the material's", 0.0, 100.0, special=-1.0, special_meaning="the material's"),
    'volume_diameter': Spec(
        0.0, 'm', 'diameter of the volume the line displaces (buoyancy, added mass); 0 = the '
        "material's volume_diameter_ratio times diameter. Set it to diameter for MoorDyn's "
        'one-diameter convention', 0.0, 2.0),
    'payload_mass': Spec(
        0.0, 'kg', 'mass of a free payload hanging at the bollard end [kg]; 0 keeps a fixed '
        'or pose-driven bollard', 0.0, 1.0e7),
    'payload_volume': Spec(
        0.0, 'm^3', 'volume the payload displaces (its buoyancy and added mass in water), '
        "MoorDyn's point Volume", 0.0, 1.0e5),
    'payload_drag_area': Spec(
        0.0, 'm^2', "payload drag coefficient times area, MoorDyn's point CdA: isotropic "
        'drag 0.5 rho CdA |u| u in water and air', 0.0, 1.0e5),
    'payload_added_mass_coefficient': Spec(
        0.5, '', "payload added mass in units of the displaced fluid's mass, MoorDyn's point "
        'Ca (0.5: a sphere)', 0.0, 100.0),
    # The winch at the fairlead (model/winch.py) and parting (model/parting.py)
    'winch_mode': Spec(
        'none', '', "the fairlead's winch: none (the line keeps its length), speed (pays out "
        '(+) or heaves in at the speed commanded on winch/command), brake (holds; renders '
        'while the tension exceeds winch_brake_load), constant_tension (pays out or heaves in '
        'to hold winch_tension)', choices=WINCH_MODES, read_only=False),
    'winch_max_speed': Spec(
        1.0, 'm/s', 'largest pay-out or heave-in speed of the winch', 0.0, 10.0,
        low_open=True, read_only=False),
    'winch_acceleration': Spec(
        0.5, 'm/s^2', 'largest change of the winch speed per second: starts and stops ramp '
        'at this rate', 0.0, 100.0, low_open=True, read_only=False),
    'winch_brake_load': Spec(
        0.0, 'N', 'brake holding load: above it the brake renders (pays out); 0 = 60 % of '
        "the material's MBL, as OCIMF MEG4 recommends", 0.0, 1.0e10, read_only=False),
    'winch_tension': Spec(
        0.0, 'N', 'the tension a constant_tension winch holds at the fairlead; 0 = the '
        'tension there when the mode takes effect', 0.0, 1.0e10, read_only=False),
    'winch_min_length': Spec(
        0.0, 'm', 'shortest unstretched length the winch heaves in to; 0 = a tenth of length',
        0.0, 1.0e4, read_only=False),
    'winch_max_length': Spec(
        0.0, 'm', 'longest unstretched length the winch pays out to; 0 = 4 times length '
        '(the segments grow with it)', 0.0, 4.0e4, read_only=False),
    'break_load': Spec(
        0.0, 'N', "a segment pulling harder parts the line there; 0 = the material's MBL",
        0.0, 1.0e10, read_only=False),
    'parting': Spec(
        True, '', 'the line parts at break_load (false: it holds any tension, for studies '
        'that want it past the MBL)', read_only=False),
    # Line handling at run time (mooring/handling.py)
    'start_state': Spec(
        'fast', '', 'how the line starts: fast (its eye on its bollard) or stowed (aboard: no '
        'force, not stepped, until make_fast puts it on its bollard)', choices=LINE_STATES),
    'make_fast_slack': Spec(
        0.05, '', 'a stowed line made fast comes out lying slack from its fairlead to its '
        'bollard, this fraction longer than the distance between them', 0.0, 1.0,
        read_only=False),
    'release_load': Spec(
        0.0, 'N', 'a quick-release hook: a fast line whose tension at its bollard passes this '
        'lets go by itself; 0 = no hook', 0.0, 1.0e10, read_only=False),
    'max_strain': Spec(
        0.25, '', 'super-elasticity threshold: no structural spring is left stretched beyond '
        'this strain', 0.0, 10.0, low_open=True, read_only=False),
    'superelastic_adjustment': Spec(
        True, '', 'apply the position and velocity adjustment at max_strain', read_only=False),
    'integrator': Spec(
        'adaptive', '', 'adaptive: implicit steps, and improved_euler steps through a snap (a '
        'segment tension changing by more than 5 % in one implicit step), so that snap loads '
        'come out right; implicit_euler: stable at any step, fastest for stiff lines, but it '
        'damps snap loads; improved_euler: the explicit scheme of the seed paper',
        choices=INTEGRATORS),
    'time_step': Spec(
        0.0, 's', 'integration step; 0 = automatic (improved_euler: 0.8 of the smaller of its '
        'stability limit and the time an axial wave takes to cross a segment; implicit_euler '
        'and adaptive: a quarter of the first axial period, at most 5 ms). improved_euler '
        'takes it as given and refuses one above its stability limit; for implicit_euler and '
        'adaptive it is an upper bound: a larger one is divided into equal substeps no '
        'longer than the automatic step. Any step is divided further while the rope moves '
        'more than half a segment in one', 0.0, 0.1),
    'end_interpolation': Spec(
        'cubic', '', 'end motion between samples: linear (secant velocity, which jumps at '
        'every sample) or cubic (Catmull-Rom: continuous velocity, far smaller tension ripple '
        'on stiff lines)', choices=('linear', 'cubic')),
    'bollard_position': Spec(
        [0.0, 0.0, 0.0], 'm', 'bollard point in frame_id while no bollard/pose arrives'),
    'fairlead_offset': Spec(
        [0.0, 0.0, 0.0], 'm', 'fairlead in the body frame of fairlead/pose', read_only=False),
    'bollard_offset': Spec(
        [0.0, 0.0, 0.0], 'm', 'bollard in the body frame of bollard/pose', read_only=False),
    'frame_id': Spec('world', '', 'frame of all outputs and of bollard_position'),
    'publish_rate': Spec(
        50.0, 'Hz', 'rate of rope/particles and the tension topics', 0.0, 1000.0,
        low_open=True, read_only=False),
    'teleport_distance': Spec(
        5.0, 'm', 'a jump of either end (fairlead or bollard) larger than this restarts the '
        'rope on the catenary at the new place',
        0.0, 1.0e6, low_open=True, read_only=False),
    'record_path': Spec('', '', 'bag directory to record to; empty = no recording'),
    'pose_reliability': Spec(
        'reliable', '', 'QoS reliability of the pose subscriptions, the default of their '
        'qos_overrides.<topic>.subscription.reliability parameters: reliable (every pose, in '
        'order; reaches reliable publishers only, which REP 2003 asks drivers to be) or '
        'best_effort (the sensor-data profile REP 2003 gives subscribers: reaches every '
        'publisher, may lose a pose under load)', choices=RELIABILITIES),
}


def not_positive(options: Any, names: Sequence[str]) -> str:
    """
    Return why the first of a command line's options `names` is not a number > 0, or ''.

    :param options: argparse's namespace; an option left at None was not given.
    """
    for name in names:
        value = getattr(options, name)
        if value is not None and not (math.isfinite(value) and value > 0.0):
            return f'--{name} {value!r} is not allowed: must be a number > 0'
    return ''


def allowed(spec: Spec) -> str:
    """Say in words what a parameter accepts (errors, descriptors, the README)."""
    if spec.choices:
        return 'one of ' + ', '.join(spec.choices)
    if isinstance(spec.default, str):
        return 'any text'
    unit = f' {spec.unit}' if spec.unit else ''
    if isinstance(spec.default, list):
        if spec.pairs:
            low = '' if spec.low is None else f', each >= {spec.low:g}'
            return (f'a flat list of number pairs [x0, y0, x1, y1, ...] ({spec.unit}), at least '
                    f'{MIN_PAIRS} and at most {MAX_PAIRS}, the first of each pair rising{low}')
        if spec.horizontal:
            return 'a list of 3 finite numbers [x, y, 0] (z must be 0)'
        bounds = ''
        if spec.low is not None and spec.high is not None:
            bounds = f', each from {spec.low:g} to {spec.high:g}{unit}'
        elif spec.high is not None:
            bounds = f', each within +-{spec.high:g}{unit}'
        return f'a list of {spec.size} finite numbers{bounds}'
    if isinstance(spec.default, bool):
        return 'true or false'
    low = '' if spec.low is None else f'{">" if spec.low_open else ">="} {spec.low:g}'
    high = '' if spec.high is None else f'<= {spec.high:g}'
    text = ' and '.join(p for p in (low, high) if p) + unit
    if spec.special is not None:
        text += f', or {_special_text(spec.special)} ({spec.special_meaning})'
    return text


def _special_text(value: float) -> str:
    """Write a special value as a user types it (YAML's -.inf for minus infinity)."""
    return '-.inf' if value == -math.inf else f'{value:g}'


# How a level of "none" (-inf) may be written besides the number itself: YAML 1.1 reads
# -.inf as a float, but -inf (what Python and the ROS tools print) as a string.
MINUS_INFINITY = ('-inf', '-.inf', '-infinity')


def check(name: str, value: Any, specs: Mapping[str, Spec] = SPECS) -> Any:
    """
    Validate one parameter value and return it in its canonical type.

    :param specs: the table the name belongs to (another node's may add its own).
    :raises ParameterError: unknown name, wrong type, non-finite or out of range; the message
        names the parameter and what is allowed.
    """
    if name not in specs:
        raise ParameterError(
            f'unknown parameter {name!r}; known: {", ".join(sorted(specs))}')
    spec = specs[name]
    bad = ParameterError(
        f'parameter {name!r} = {value!r} is not allowed: must be {allowed(spec)}')
    default = spec.default
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise bad
        return value
    if isinstance(default, str):
        if not isinstance(value, str) or (spec.choices and value not in spec.choices):
            raise bad
        return value
    if isinstance(default, list):
        if spec.pairs:
            return _checked_pairs(spec, value, bad)
        if (not isinstance(value, (list, tuple)) or len(value) != spec.size
                or not all(_is_finite_number(v) for v in value)
                or (spec.high is not None and max(abs(v) for v in value) > spec.high)
                or (spec.low is not None and min(value) < spec.low)
                or (spec.horizontal and value[2] != 0.0)):
            raise bad
        return [float(v) for v in value]
    if isinstance(default, int):
        if isinstance(value, bool) or not isinstance(value, int):
            if not (_is_finite_number(value) and float(value).is_integer()):
                raise bad
        value = int(value)
    elif _is_special(spec, value):
        return float(spec.special)
    elif not _is_finite_number(value):
        raise bad
    else:
        value = float(value)
    if spec.low is not None and (value < spec.low or (spec.low_open and value == spec.low)):
        raise bad
    if spec.high is not None and value > spec.high:
        raise bad
    return value


def _checked_pairs(spec: Spec, value: Any, bad: ParameterError) -> list:
    """Return a flat list of number pairs as floats (see Spec.pairs), or raise `bad`."""
    if (not isinstance(value, (list, tuple)) or len(value) % 2
            or not MIN_PAIRS <= len(value) // 2 <= MAX_PAIRS
            or not all(_is_finite_number(v) for v in value)
            or (spec.low is not None and min(value) < spec.low)):
        raise bad
    firsts = value[0::2]
    if any(b <= a for a, b in zip(firsts, firsts[1:])):
        raise bad
    return [float(v) for v in value]


def _is_special(spec: Spec, value: Any) -> bool:
    """Tell whether value is the spec's special value (-inf may also be written as text)."""
    if spec.special is None or isinstance(value, bool):
        return False
    if isinstance(value, str):
        return spec.special == -math.inf and value.strip().lower() in MINUS_INFINITY
    return isinstance(value, (int, float)) and value == spec.special


def _is_finite_number(value: Any) -> bool:
    return (isinstance(value, (int, float)) and not isinstance(value, bool)
            and math.isfinite(value))


@dataclass(frozen=True)
class LineParams:
    """Validated values of every parameter in SPECS (see there for units and meaning)."""

    material: str = SPECS['material'].default
    diameter: float = SPECS['diameter'].default
    length: float = SPECS['length'].default
    segments: int = SPECS['segments'].default
    mass_per_length: float = SPECS['mass_per_length'].default
    axial_stiffness: float = SPECS['axial_stiffness'].default
    load_extension: str = SPECS['load_extension'].default
    axial_damping: float = SPECS['axial_damping'].default
    damping_model: str = SPECS['damping_model'].default
    bending_stiffness_ratio: float = SPECS['bending_stiffness_ratio'].default
    bending_damping_ratio: float = SPECS['bending_damping_ratio'].default
    air_drag_coefficient: float = SPECS['air_drag_coefficient'].default
    gravity: list = field(default_factory=lambda: list(SPECS['gravity'].default))
    water_level: float = SPECS['water_level'].default
    water_density: float = SPECS['water_density'].default
    air_density: float = SPECS['air_density'].default
    current: list = field(default_factory=lambda: list(SPECS['current'].default))
    seabed_level: float = SPECS['seabed_level'].default
    seabed_stiffness: float = SPECS['seabed_stiffness'].default
    seabed_damping: float = SPECS['seabed_damping'].default
    seabed_friction: float = SPECS['seabed_friction'].default
    quay_edge: list = field(default_factory=lambda: list(SPECS['quay_edge'].default))
    quay_normal: list = field(default_factory=lambda: list(SPECS['quay_normal'].default))
    quay_depth: float = SPECS['quay_depth'].default
    normal_drag_coefficient: float = SPECS['normal_drag_coefficient'].default
    tangential_drag_coefficient: float = SPECS['tangential_drag_coefficient'].default
    normal_added_mass_coefficient: float = SPECS['normal_added_mass_coefficient'].default
    tangential_added_mass_coefficient: float = SPECS[
        'tangential_added_mass_coefficient'].default
    volume_diameter: float = SPECS['volume_diameter'].default
    payload_mass: float = SPECS['payload_mass'].default
    payload_volume: float = SPECS['payload_volume'].default
    payload_drag_area: float = SPECS['payload_drag_area'].default
    payload_added_mass_coefficient: float = SPECS['payload_added_mass_coefficient'].default
    winch_mode: str = SPECS['winch_mode'].default
    winch_max_speed: float = SPECS['winch_max_speed'].default
    winch_acceleration: float = SPECS['winch_acceleration'].default
    winch_brake_load: float = SPECS['winch_brake_load'].default
    winch_tension: float = SPECS['winch_tension'].default
    winch_min_length: float = SPECS['winch_min_length'].default
    winch_max_length: float = SPECS['winch_max_length'].default
    break_load: float = SPECS['break_load'].default
    parting: bool = SPECS['parting'].default
    start_state: str = SPECS['start_state'].default
    make_fast_slack: float = SPECS['make_fast_slack'].default
    release_load: float = SPECS['release_load'].default
    max_strain: float = SPECS['max_strain'].default
    superelastic_adjustment: bool = SPECS['superelastic_adjustment'].default
    integrator: str = SPECS['integrator'].default
    time_step: float = SPECS['time_step'].default
    end_interpolation: str = SPECS['end_interpolation'].default
    bollard_position: list = field(
        default_factory=lambda: list(SPECS['bollard_position'].default))
    fairlead_offset: list = field(default_factory=lambda: list(SPECS['fairlead_offset'].default))
    bollard_offset: list = field(default_factory=lambda: list(SPECS['bollard_offset'].default))
    frame_id: str = SPECS['frame_id'].default
    publish_rate: float = SPECS['publish_rate'].default
    teleport_distance: float = SPECS['teleport_distance'].default
    record_path: str = SPECS['record_path'].default
    pose_reliability: str = SPECS['pose_reliability'].default

    @property
    def has_payload(self) -> bool:
        """Tell whether the bollard end is a free payload (payload_mass > 0)."""
        return self.payload_mass > 0.0

    @property
    def has_water(self) -> bool:
        """Tell whether there is water (a finite water_level)."""
        return math.isfinite(self.water_level)

    @property
    def has_seabed(self) -> bool:
        """Tell whether there is a seabed (a finite seabed_level)."""
        return math.isfinite(self.seabed_level)

    @property
    def has_quay(self) -> bool:
        """Tell whether there is a quay (a non-zero quay_normal)."""
        return any(self.quay_normal)

    def with_values(self, values: Mapping[str, Any]) -> 'LineParams':
        """
        Return a copy with `values` validated and applied.

        :raises ParameterError: the first bad value, named.
        """
        return replace(self, **{k: check(k, v) for k, v in values.items()})

    def as_dict(self) -> dict:
        """Plain {name: value} of every parameter."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


def from_values(values: Mapping[str, Any]) -> LineParams:
    """Validate a {name: value} map into parameters (defaults for the rest)."""
    return LineParams().with_values(values)
