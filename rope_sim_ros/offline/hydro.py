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
``rope_sim hydro``: a ship's hydrodynamic database from Capytaine, kept in a NetCDF file.

The hull: the user's mesh (ship.mesh, any format Capytaine reads, body axes with z = 0 at
the still water) or the parametric hull of ship.length, beam, draft and block_coefficient
(hull_mesh). Capytaine's boundary-element solver gives, about the centre of gravity
(ship.center_of_gravity) at the arrangement's water depth, density and gravity: the added
mass and radiation damping A(omega), B(omega), the added mass at infinite frequency, the
Froude-Krylov and diffraction excitation per wave heading and the mean drift loads in
surge, sway and yaw (Capytaine's far-field formula from the Kochin functions, for the
freely floating ship's motions). The file is Capytaine's own dataset, complex values
separated (re, im), written as NetCDF 3 so that scipy alone reads it back
(params/hydro_file.py).

Capytaine's conventions are the record's (model/ship/hydro.py): exp(-i omega t), the wave
direction the one the waves travel toward, counter-clockwise from body x, the incident
wave's elevation Re(a exp(i(k (x cos b + y sin b) - omega t))), so of phase 0 at the body
origin; the forces are those on the body, the dofs rigid rotations about the rotation
centre (here the centre of gravity).
"""

from dataclasses import dataclass, replace
import importlib.metadata
import logging
import math
import os
import tempfile
from typing import Callable, Optional

import numpy as np

from ..params.table import ParameterError

# The default frequencies and headings (docs/waves.md: how they were chosen).
OMEGA_MIN = 0.05
OMEGA_MAX = 2.0
OMEGA_COUNT = 40
HEADING_STEP = 30.0
# Panel size of the parametric hull [m]: on the default ship (config/berth.yaml) 4 m and 3 m
# panels give A within 1.1 % and B within 1 % (roll's, small, 5 %) of each other at 0.3,
# 0.6 and 1.0 rad/s; at 1.3 rad/s 4 m panels give B33 < 0, 3 m ones keep B positive
# semi-definite up to 1.3 rad/s (test/data/hydro/berth_ship.nc). Finer panels for the
# higher frequencies: --panel-size.
PANEL_SIZE = 3.0
# Angles of the Kochin functions for the mean drift: every degree, one more each side of
# [0, 2 pi] (Capytaine's far-field formula differentiates and interpolates in theta).
KOCHIN_STEP = math.radians(1.0)
DRIFT_DOFS = ('surge', 'sway', 'yaw')
CAPYTAINE_DOFS = ('Surge', 'Sway', 'Heave', 'Roll', 'Pitch', 'Yaw')
# Capytaine's finite-depth Green function: its default (python) Prony decomposition of the
# depth term fails below kh ~ 0.13 (16 m of water: omega < 0.12 rad/s); Delhommeau's own
# (fortran) one holds down to kh ~ 0.03 and gives A and B within 2 % of the python one
# where both hold (0.12 to 0.15 rad/s, the default ship). It knows no infinite frequency,
# which the python one solves.
PRONY_FINITE = 'fortran'
PRONY_INFINITE = 'python'


class HydroError(ParameterError):
    """A hull, a mesh or a frequency set the solver cannot take (one line)."""


@dataclass(frozen=True)
class HydroSettings:
    """
    What to solve: frequencies, headings, the parametric hull's panels, the lid.

    :ivar omega: wave frequencies [rad/s], > 0, rising.
    :ivar headings: wave headings [rad] in [0, 2 pi), rising: the direction the waves travel
        toward, counter-clockwise from body x.
    :ivar panel_size: the parametric hull's panel size [m].
    :ivar lid: add a lid at the waterline (removes the irregular frequencies).
    """

    omega: np.ndarray
    headings: np.ndarray
    panel_size: float = PANEL_SIZE
    lid: bool = True


def default_settings(omega_min: float = OMEGA_MIN, omega_max: float = OMEGA_MAX,
                     omega_count: int = OMEGA_COUNT, heading_step: float = HEADING_STEP,
                     panel_size: float = PANEL_SIZE, lid: bool = True) -> HydroSettings:
    """
    Return settings of evenly spaced frequencies and headings over the full circle.

    :param heading_step: [deg], dividing 360.
    :raises HydroError: a range, count or step out of bounds.
    """
    if not (0.0 < omega_min < omega_max and math.isfinite(omega_max)) or omega_count < 2:
        raise HydroError(f'hydro: frequencies {omega_min:g} .. {omega_max:g} rad/s in '
                         f'{omega_count}: need 0 < min < max and at least 2 frequencies')
    count = 360.0 / heading_step if heading_step > 0.0 else 0.0
    if not (1.0 <= count <= 360.0 and abs(count - round(count)) < 1e-9):
        raise HydroError(f'hydro: heading step {heading_step:g} deg: must divide 360 '
                         '(30: 12 headings)')
    if not (0.0 < panel_size <= 100.0):
        raise HydroError(f'hydro: panel size {panel_size:g} m: must be > 0 and <= 100 m')
    headings = np.radians(heading_step) * np.arange(int(round(count)))
    return HydroSettings(np.linspace(omega_min, omega_max, omega_count), headings,
                         panel_size, lid)


def _exponent(block_coefficient: float, stations: np.ndarray) -> float:
    """
    Return n such that the waterline 1 - |s|^n, drawn through `stations`, holds C_b.

    The exact curve's area is n / (n + 1); the polygon through the stations a little less:
    n is solved on the polygon (bisection) so that the mesh's volume is L B T C_b.
    """
    def area(n: float) -> float:
        return float(np.trapezoid(1.0 - stations ** n, stations))
    low, high = 1e-3, 1e3
    for _ in range(100):
        middle = math.sqrt(low * high)
        low, high = (middle, high) if area(middle) < block_coefficient else (low, middle)
    return math.sqrt(low * high)


def hull_mesh(length: float, beam: float, draft: float, block_coefficient: float,
              panel_size: float):
    """
    Return the parametric hull: wall-sided, flat-bottomed, waterline y = B/2 (1 - |2x/L|^n).

    Every section is a rectangle of the local beam and the draft, so the block coefficient
    is the waterline's area coefficient, n / (n + 1): n = C_b / (1 - C_b) (5.7 for the
    default 0.85: a parallel middle body running into fine ends; C_b 1: a box). Symmetric
    port/starboard and fore/aft: one quarter is meshed (Capytaine solves a quarter-size
    system per symmetry class, about 16 times as fast).

    :returns: a capytaine ReflectionSymmetricMesh, normals out of the hull into the water.
    """
    import capytaine as cpt
    half_length, half_beam = 0.5 * length, 0.5 * beam
    nx = max(4, math.ceil(half_length / panel_size))
    ny = max(2, math.ceil(half_beam / panel_size))
    nz = max(2, math.ceil(draft / panel_size))
    stations = np.linspace(0.0, 1.0, nx + 1)
    if block_coefficient >= 1.0 - 1e-9:
        widths = np.ones_like(stations)
    else:
        widths = 1.0 - stations ** _exponent(block_coefficient, stations)
    xs, ys = half_length * stations, half_beam * widths
    zs = np.linspace(-draft, 0.0, nz + 1)
    fractions = np.linspace(0.0, 1.0, ny + 1)
    side = np.stack(np.broadcast_arrays(xs[:, None], ys[:, None], zs[None, :]), axis=-1)
    bottom = np.stack(np.broadcast_arrays(xs[:, None], ys[:, None] * fractions[None, :],
                                          -draft), axis=-1)
    # the end: a box's transom at x = L/2 (the other hulls' waterline closes there)
    end = np.stack(np.broadcast_arrays(half_length, half_beam * widths[-1] * fractions[:, None],
                                       zs[None, :]), axis=-1)
    vertices = np.concatenate([side.reshape(-1, 3), bottom.reshape(-1, 3), end.reshape(-1, 3)])
    i, k = np.meshgrid(np.arange(nx), np.arange(nz), indexing='ij')
    s = (i * (nz + 1) + k).ravel()
    # side: normal +y (out of the port side of this quarter)
    faces = [np.stack([s, s + 1, s + nz + 2, s + nz + 1], axis=1)]
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing='ij')
    b = side.shape[0] * side.shape[1] + (i * (ny + 1) + j).ravel()
    # bottom: normal -z
    faces.append(np.stack([b, b + 1, b + ny + 2, b + ny + 1], axis=1))
    if widths[-1] > 0.0:
        j, k = np.meshgrid(np.arange(ny), np.arange(nz), indexing='ij')
        e = side.size // 3 + bottom.size // 3 + (j * (nz + 1) + k).ravel()
        # end: normal +x
        faces.append(np.stack([e, e + nz + 1, e + nz + 2, e + 1], axis=1))
    quarter = cpt.Mesh(vertices, np.concatenate(faces), name='hull')
    return cpt.ReflectionSymmetricMesh(
        cpt.ReflectionSymmetricMesh(quarter, plane='xOz'), plane='yOz', name='hull')


def load_hull(path: str, depth: float):
    """
    Return the immersed part of the user's mesh (ship.mesh) as Capytaine reads it.

    :raises HydroError: no such file, a file Capytaine cannot read, nothing below the water
        or a hull reaching the sea bed.
    """
    import capytaine as cpt
    if not os.path.isfile(path):
        raise HydroError(f"parameter 'ship.mesh': no such file {path}")
    try:
        mesh = cpt.load_mesh(path)
    except Exception as e:  # noqa: B902: every reader's own error: one line
        raise HydroError(f"parameter 'ship.mesh': Capytaine cannot read {path} as a mesh: "
                         f'{" ".join(str(e).split()) or type(e).__name__}') from None
    if mesh.nb_faces == 0 or mesh.vertices[:, 2].min() >= 0.0:
        raise HydroError(f"parameter 'ship.mesh': {path} has no faces below the water "
                         '(z < 0: the body axes, z = 0 at the still water)')
    bottom = float(mesh.vertices[:, 2].min())
    if -bottom >= depth:
        raise HydroError(f"parameter 'ship.mesh': {path} reaches {-bottom:g} m below the "
                         f'water, which is {depth:g} m deep (water_level - seabed_level)')
    return mesh.immersed_part()


@dataclass(frozen=True)
class Environment:
    """The water the hull floats in: depth [m] (inf: deep), density [kg/m^3], g [m/s^2]."""

    depth: float
    density: float
    g: float


def environment_of(setup) -> Environment:
    """Return the arrangement's water: water_level - seabed_level, water_density, |gravity|."""
    shared = setup.shared
    if not math.isfinite(shared.water_level):
        raise HydroError('hydro: the arrangement has no water (water_level -.inf): set '
                         'water_level (and seabed_level for a finite depth)')
    depth = shared.water_level - shared.seabed_level
    g = float(np.linalg.norm(shared.gravity))
    if not g > 0.0:
        raise HydroError('hydro: gravity is zero: the waves need it')
    return Environment(depth, float(shared.water_density), g)


def rigid_body(mesh, ship, settings: HydroSettings):
    """Return the Capytaine body: six rigid dofs about the centre of gravity, the lid."""
    import capytaine as cpt
    cog = np.asarray(ship.center_of_gravity, dtype=float)
    lid = None
    if settings.lid:
        # Under the still water by 1 % of the draft: at 0.1 % (0.014 m on the default ship)
        # the system is ill-conditioned (B55 -3.5e11 at 1.15 rad/s, B not positive); at 1 %
        # and 5 % B is positive semi-definite (eigenvalues > -1e-5 of the largest) and
        # within 1 % of itself at 1.15 rad/s.
        lid = mesh.generate_lid(z=-0.01 * float(-mesh.vertices[:, 2].min()))
    return cpt.FloatingBody(mesh=mesh, lid_mesh=lid, name='ship',
                            dofs=cpt.rigid_body_dofs(rotation_center=cog),
                            center_of_mass=cog, mass=float(ship.mass))


def inertia_matrix(ship) -> np.ndarray:
    """Return the ship's 6x6 mass matrix about its centre of gravity (radii of gyration)."""
    radii = np.asarray(ship.radii_of_gyration, dtype=float)
    return np.diag(ship.mass * np.concatenate([np.ones(3), radii ** 2]))


def _solvers():
    import capytaine as cpt
    return tuple(cpt.BEMSolver(green_function=cpt.Delhommeau(
        finite_depth_prony_decomposition_method=method), method='indirect')
        for method in (PRONY_FINITE, PRONY_INFINITE))


def solve(mesh, ship, env: Environment, settings: HydroSettings,
          progress: Optional[Callable[[int, int, str], None]] = None):
    """
    Solve the hull: return Capytaine's dataset with the database's further variables.

    Variables beyond Capytaine's (assemble_dataset: added_mass, radiation_damping,
    Froude_Krylov_force, diffraction_force, excitation_force, the hydrostatics):
    added_mass_infinite (influenced_dof, radiating_dof), rao (omega, wave_direction,
    radiating_dof: the freely floating ship's motion per metre of wave amplitude, with
    ship.linear_damping's roll term as its viscous roll damping) and mean_drift_force
    (omega, wave_direction, drift_dof: surge, sway [N/m^2], yaw [N m/m^2]).

    :param progress: called (done, total, what) after each frequency.
    :raises HydroError: Capytaine fails on a problem (one line naming it).
    """
    import capytaine as cpt
    from capytaine.io.xarray import kochin_data_array
    from capytaine.post_pro import far_field_mean_drift_force, rao as motion_rao
    import xarray as xr
    logging.getLogger('capytaine').setLevel(logging.ERROR)
    body = rigid_body(mesh, ship, settings)
    finite, infinite = _solvers()
    water = dict(water_depth=env.depth, rho=env.density, g=env.g)
    theta = np.concatenate([[-KOCHIN_STEP], np.linspace(0.0, 2.0 * math.pi, int(round(
        2.0 * math.pi / KOCHIN_STEP)) + 1), [2.0 * math.pi + KOCHIN_STEP]])
    total = len(settings.omega) + 1
    results = []
    for done, omega in enumerate(settings.omega, start=1):
        problems = [cpt.RadiationProblem(body=body, radiating_dof=dof, omega=float(omega),
                                         **water) for dof in CAPYTAINE_DOFS]
        problems += [cpt.DiffractionProblem(body=body, wave_direction=float(heading),
                                            omega=float(omega), **water)
                     for heading in settings.headings]
        results += [_solve_one(finite, problem) for problem in problems]
        if progress is not None:
            progress(done, total, f'omega = {omega:.3f} rad/s')
    # Without the lid: at infinite frequency there is no irregular frequency, and with the
    # lid the default ship's A33 came out -1.1e11 kg (3.8e8 without, A33 at 2 rad/s 4.0e8).
    bare = rigid_body(mesh, ship, replace(settings, lid=False))
    infinite_results = [_solve_one(infinite, cpt.RadiationProblem(
        body=bare, radiating_dof=dof, omega=np.inf, **water)) for dof in CAPYTAINE_DOFS]
    if progress is not None:
        progress(total, total, 'omega = inf')
    dataset = cpt.assemble_dataset(results, hydrostatics=True)
    dataset.update(kochin_data_array(results, xr.DataArray(theta, dims='theta',
                                                           coords={'theta': theta})))
    infinite_set = cpt.assemble_dataset(infinite_results, hydrostatics=False)
    dataset['added_mass_infinite'] = infinite_set['added_mass'].isel(omega=0, drop=True)
    dataset['inertia_matrix'] = (('influenced_dof', 'radiating_dof'), inertia_matrix(ship))
    dissipation = np.zeros((6, 6))
    dissipation[3, 3] = ship.linear_damping[3]
    dataset['rao'] = motion_rao(dataset, dissipation=xr.DataArray(
        dissipation, dims=('influenced_dof', 'radiating_dof'),
        coords={'influenced_dof': list(CAPYTAINE_DOFS), 'radiating_dof': list(CAPYTAINE_DOFS)}))
    drift = far_field_mean_drift_force(dataset['rao'], dataset)
    dataset['mean_drift_force'] = xr.concat(
        [_diagonal(drift[f'drift_force_{name}']) for name in DRIFT_DOFS],
        dim=xr.DataArray(list(DRIFT_DOFS), dims='drift_dof')).transpose(
            'omega', 'wave_direction', 'drift_dof')
    dataset = dataset.drop_vars(['kochin_radiation', 'kochin_diffraction', 'theta'])
    dataset['mean_drift_force'].attrs.update(
        long_name='mean drift load per square metre of wave amplitude: far field, from the '
        'Kochin functions of the freely floating ship', units='N/m^2 (surge, sway), N m/m^2 '
        '(yaw)')
    dataset['added_mass_infinite'].attrs.update(long_name='added mass at infinite frequency')
    dataset['rao'].attrs.update(long_name='motion per metre of wave amplitude of the freely '
                                'floating ship (roll with ship.linear_damping[3])')
    dataset.attrs.update(_attributes(ship, env, mesh, settings))
    return dataset


def _solve_one(solver, problem):
    try:
        return solver.solve(problem, keep_details=True, _check_wavelength=False)
    except Exception as e:  # noqa: B902: Capytaine's own errors, one line
        raise HydroError(f'hydro: Capytaine cannot solve {problem.__class__.__name__} at '
                         f'omega = {problem.omega:g} rad/s: '
                         f'{" ".join(str(e).split()) or type(e).__name__}') from None


def _diagonal(pairs):
    """Return the mean drift of each heading alone: the (k, k) terms of Capytaine's pairs."""
    import xarray as xr
    values = np.real(np.diagonal(pairs.values, axis1=1, axis2=2))
    return xr.DataArray(values, dims=('omega', 'wave_direction'),
                        coords={'omega': pairs['omega'].values,
                                'wave_direction': pairs['wave_direction_k'].values})


def _version() -> str:
    try:
        return importlib.metadata.version('rope_sim_ros')
    except importlib.metadata.PackageNotFoundError:
        return 'source'


def _attributes(ship, env: Environment, mesh, settings: HydroSettings) -> dict:
    return {
        'title': 'rope_sim_ros hydrodynamic database (rope_sim hydro)',
        'rope_sim_ros_version': _version(),
        'reference_point': np.asarray(ship.center_of_gravity, dtype=float),
        'reference_point_meaning': 'the centre of gravity (the rotation centre) from the body '
        'origin, body axes x forward, y to port, z up [m]',
        'water_depth': env.depth if math.isfinite(env.depth) else -1.0,
        'water_depth_meaning': '[m]; -1: deep water',
        'water_density': env.density,
        'g': env.g,
        'mesh': ship.mesh or 'parametric hull (rope_sim_ros.offline.hydro.hull_mesh)',
        'mesh_faces': int(mesh.nb_faces),
        'panel_size': settings.panel_size if not ship.mesh else 0.0,
        'lid': int(settings.lid),
        'excitation_phase': 'relative to the incident wave elevation at the body origin '
        '(x = y = 0), time as exp(-i omega t)',
        'wave_direction_meaning': 'the direction the waves travel toward, counter-clockwise '
        'from body x [rad]',
    }


def write_database(dataset, path: str) -> None:
    """
    Write the dataset as NetCDF 3 (scipy), complex values separated: (complex: re, im).

    Written to a temporary file beside `path`, then moved over it: a failed write leaves
    any file there as it was.

    :raises OSError: the folder is not writable.
    """
    from capytaine.io.xarray import separate_complex_values
    data = separate_complex_values(dataset)
    for name in ('radiating_dof', 'influenced_dof', 'drift_dof'):
        data[name] = data[name].astype(str)
    # NetCDF 3 attributes are numbers and text: Capytaine's settings may hold others
    data.attrs = {key: (value if isinstance(value, (int, float, str, np.ndarray))
                        and not isinstance(value, bool) else str(value))
                  for key, value in data.attrs.items()}
    for name in data.variables:
        data[name].attrs = {key: (value if isinstance(value, (int, float, str, np.ndarray))
                                  and not isinstance(value, bool) else str(value))
                            for key, value in data[name].attrs.items()}
    folder = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(suffix='.nc', dir=folder)
    os.close(handle)
    try:
        data.to_netcdf(temporary, engine='scipy', format='NETCDF3_64BIT')
        # a file as any other the user writes (mkstemp makes it the user's alone)
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(temporary, 0o666 & ~mask)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


def ship_mesh(setup, settings: HydroSettings, env: Environment):
    """
    Return the hull to solve: ship.mesh, else the parametric hull of the ship's dimensions.

    :raises HydroError: a mesh that cannot be read, a ship drawing more than the depth.
    """
    ship = setup.ship
    if ship.mesh:
        return load_hull(ship.mesh, env.depth)
    if ship.draft >= env.depth:
        raise HydroError(f'hydro: ship.draft {ship.draft:g} m is not less than the water '
                         f'depth {env.depth:g} m (water_level - seabed_level): the hull would '
                         'stand on the sea bed')
    return hull_mesh(ship.length, ship.beam, ship.draft, ship.block_coefficient,
                     settings.panel_size)


def make_database(arrangement: str, out: str, overrides=None,
                  settings: Optional[HydroSettings] = None, force: bool = False,
                  progress=None):
    """
    Solve an arrangement's ship and write its database to `out` (the command's work).

    :returns: (the dataset, the number of panels solved, the lid's included).
    :raises ParameterError: not an arrangement, a bad parameter, `out` exists without
        force, a mesh or a hull the solver cannot take.
    """
    from ..params.arrangement import is_arrangement_file, read_setup
    if not os.path.isfile(arrangement):
        raise HydroError(f'hydro: no such file {arrangement}')
    if not is_arrangement_file(arrangement):
        raise HydroError(f'hydro: {arrangement} is not an arrangement (a parameter file for '
                         "the mooring node, with 'lines' and the ship)")
    if os.path.exists(out) and not force:
        raise HydroError(f'hydro: {out} exists: give --force to overwrite it')
    if not os.path.isdir(os.path.dirname(os.path.abspath(out))):
        raise HydroError(f'hydro: no folder for {out}')
    setup = read_setup(arrangement, overrides)
    settings = settings or default_settings()
    env = environment_of(setup)
    mesh = ship_mesh(setup, settings, env)
    dataset = solve(mesh, setup.ship, env, settings, progress)
    write_database(dataset, out)
    return dataset
