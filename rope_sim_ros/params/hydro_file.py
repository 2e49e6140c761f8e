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
A hydrodynamic database file (`rope_sim hydro`) read back as the record model/ship/hydro.py.

The file is Capytaine's NetCDF dataset (complex values as a leading `complex` dimension,
re and im), written as NetCDF 3; it is read with scipy's NetCDF reader alone: neither
Capytaine nor xarray (0.75 s to import) is loaded, and scipy.io only when a database is
read (0.29 s with numpy), so a node without one starts as fast as before.

Capytaine's conventions are the record's (exp(-i omega t), the heading the direction the
waves travel toward, the excitation's phase at the body origin, the dofs about the rotation
centre): only the layout changes. The headings, solved in [0, 2 pi), are taken to [-pi, pi]
and sorted; the heading pi is repeated at -pi so that the record spans the full circle.
"""

import math

from .table import ParameterError
from ..model.ship.hydro import DOF, HydroDatabase

DOFS = ('Surge', 'Sway', 'Heave', 'Roll', 'Pitch', 'Yaw')
DRIFT_DOFS = ('surge', 'sway', 'yaw')
# variable -> its dimensions, as the record wants them ('complex' first where complex)
LAYOUT = {
    'added_mass': ('omega', 'influenced_dof', 'radiating_dof'),
    'radiation_damping': ('omega', 'influenced_dof', 'radiating_dof'),
    'added_mass_infinite': ('influenced_dof', 'radiating_dof'),
    'excitation_force': ('complex', 'wave_direction', 'omega', 'influenced_dof'),
    'mean_drift_force': ('wave_direction', 'omega', 'drift_dof'),
}


class HydroFileError(ParameterError):
    """A hydrodynamic database file that cannot be read (one line naming it)."""


def read_hydro_database(path) -> HydroDatabase:
    """
    Read a `rope_sim hydro` file.

    :raises HydroFileError: no such file, not NetCDF, a variable missing or of the wrong
        shape, numbers that are not finite (one line naming the path and what is wrong).
    """
    import numpy as np
    from scipy.io import netcdf_file
    try:
        stream = netcdf_file(path, 'r', mmap=False)
    except OSError as e:
        raise HydroFileError(f'hydrodynamic database {path}: cannot read it: '
                             f'{e.strerror or e}') from None
    except Exception as e:  # noqa: B902: scipy's reader says "not a NetCDF file" many ways
        raise HydroFileError(f'hydrodynamic database {path}: not a NetCDF 3 file as rope_sim '
                             f'hydro writes ({" ".join(str(e).split())})') from None
    try:
        with stream:
            variables = stream.variables
            missing = [name for name in (*LAYOUT, 'omega', 'wave_direction')
                       if name not in variables]
            if missing:
                raise HydroFileError(f'hydrodynamic database {path}: no {", ".join(missing)}: '
                                     'not a file of rope_sim hydro')
            arrays = {name: _ordered(path, variables, name, dims)
                      for name, dims in LAYOUT.items()}
            omega = np.array(variables['omega'].data, dtype=float)
            headings = np.array(variables['wave_direction'].data, dtype=float)
            attributes = stream._attributes
            reference = np.array(attributes.get('reference_point', [math.nan] * 3), dtype=float)
            depth = float(attributes.get('water_depth', math.nan))
            density = float(attributes.get('water_density', math.nan))
            g = float(attributes.get('g', math.nan))
    except HydroFileError:
        raise
    except (KeyError, ValueError, TypeError, IndexError) as e:
        raise HydroFileError(f'hydrodynamic database {path}: {" ".join(str(e).split())}') \
            from None
    excitation = arrays['excitation_force'][0] + 1j * arrays['excitation_force'][1]
    drift = arrays['mean_drift_force']
    # [0, 2 pi) -> [-pi, pi], sorted; pi again at -pi
    wrapped = np.where(headings > math.pi + 1e-9, headings - 2.0 * math.pi, headings)
    order = np.argsort(wrapped)
    wrapped, excitation, drift = wrapped[order], excitation[order], drift[order]
    if np.isclose(wrapped[-1], math.pi) and not np.isclose(wrapped[0], -math.pi):
        wrapped = np.concatenate([[-math.pi], wrapped[:-1], [math.pi]])
        excitation = np.concatenate([excitation[-1:], excitation])
        drift = np.concatenate([drift[-1:], drift])
    try:
        return HydroDatabase(
            omega=omega, added_mass=arrays['added_mass'],
            radiation_damping=arrays['radiation_damping'],
            added_mass_infinite=arrays['added_mass_infinite'], headings=wrapped,
            excitation=excitation, drift=drift, reference_point=reference,
            water_depth=math.inf if depth < 0.0 else depth, water_density=density, g=g)
    except ValueError as e:
        raise HydroFileError(f'{path}: {e}') from None


def _ordered(path, variables, name: str, dims):
    """Return a variable's numbers in `dims` order, its dofs in the record's order."""
    import numpy as np
    variable = variables[name]
    have = tuple(_text(d) for d in variable.dimensions)
    if sorted(have) != sorted(dims):
        raise HydroFileError(f'hydrodynamic database {path}: {name} has dimensions '
                             f'{", ".join(have)}, not {", ".join(dims)}')
    data = np.array(variable.data, dtype=float).transpose([have.index(d) for d in dims])
    for axis, dim in enumerate(dims):
        wanted = {'influenced_dof': DOFS, 'radiating_dof': DOFS,
                  'drift_dof': DRIFT_DOFS}.get(dim)
        if wanted is None:
            continue
        names = _names(variables[dim].data)
        if sorted(names) != sorted(wanted) or len(names) != len(wanted):
            raise HydroFileError(f'hydrodynamic database {path}: {dim} holds '
                                 f'{", ".join(names)}, not {", ".join(wanted)}')
        data = np.take(data, [names.index(n) for n in wanted], axis=axis)
    if name != 'mean_drift_force' and data.shape[-1] != DOF:
        raise HydroFileError(f'hydrodynamic database {path}: {name} is not for 6 dofs')
    return data


def _names(data) -> list:
    """Return the names of a NetCDF 3 text coordinate (characters, one row per name)."""
    import numpy as np
    array = np.asarray(data)
    if array.dtype.kind == 'S' and array.ndim == 2:
        return [b''.join(row).decode('utf-8').rstrip('\x00 ') for row in array]
    return [_text(item) for item in array]


def _text(value) -> str:
    return value.decode('utf-8') if isinstance(value, bytes) else str(value)
