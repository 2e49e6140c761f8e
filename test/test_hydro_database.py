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
rope_sim hydro: the solve, its file, the record read back, and what it refuses.

Solved here on coarse meshes at a few frequencies (seconds each); the shipped database
test/data/hydro/berth_ship.nc (the default ship of config/berth.yaml) is read for the checks
a whole band needs.
"""

import math
import os
from pathlib import Path
import stat
import subprocess
import sys

import numpy as np
import pytest
from rope_sim_ros.offline import cli
from rope_sim_ros.offline.hydro import (default_settings, hull_mesh, HydroError, HydroSettings,
                                        make_database)
from rope_sim_ros.params.hydro_file import HydroFileError, read_hydro_database

REPO_ROOT = Path(__file__).resolve().parent.parent
BERTH = str(REPO_ROOT / 'config' / 'berth.yaml')
RHO, G = 1025.0, 9.81
# A small box barge in deep water: L, B, T [m]
BOX = {'ship.length': 20.0, 'ship.beam': 4.0, 'ship.draft': 2.0, 'ship.block_coefficient': 1.0,
       'ship.mass': RHO * 20.0 * 4.0 * 2.0, 'ship.center_of_gravity': [0.0, 0.0, -1.0],
       'ship.radii_of_gyration': [1.4, 5.8, 5.8], 'seabed_level': -math.inf}


@pytest.fixture(scope='module')
def shipped():
    """Read the shipped database of the default ship (test/data/README.md: how it was made)."""
    return read_hydro_database(REPO_ROOT / 'test' / 'data' / 'hydro' / 'berth_ship.nc')


@pytest.fixture(scope='module')
def box(tmp_path_factory):
    """Solve the box barge at a long, a middle and a short wave, all round: (file, dataset)."""
    out = tmp_path_factory.mktemp('box') / 'box.nc'
    settings = HydroSettings(np.array([0.1, 1.5, 4.43]), np.radians([0.0, 90.0, 180.0, 270.0]),
                             panel_size=0.5)
    return out, make_database(BERTH, str(out), BOX, settings)


def test_the_parametric_hull_holds_the_block_coefficients_volume():
    for cb in (0.5, 0.85, 1.0):
        mesh = hull_mesh(225.0, 32.2, 14.0, cb, 4.0)
        assert mesh.merged().volume == pytest.approx(225.0 * 32.2 * 14.0 * cb, rel=1e-6)
        # the normals point out of the hull: its bottom's down
        merged = mesh.merged()
        bottom = merged.faces_centers[:, 2] < -14.0 + 1e-6
        assert (merged.faces_normals[bottom, 2] < -0.99).all()


def test_long_wave_heave_excitation_is_the_waterplane_stiffness(box):
    """At long waves the heave force is rho g A_wp a, in phase with the crest at the origin."""
    _, data = box
    x = data['excitation_force'].sel(omega=0.1, influenced_dof='Heave').values
    stiffness = RHO * G * 20.0 * 4.0
    # kL = 0.02, and the inertia's share omega^2 (T + A33 / rho A_wp) / g 0.4 %
    np.testing.assert_allclose(x.real, stiffness, rtol=0.01)
    assert abs(x.imag).max() < 0.001 * stiffness
    # the Froude-Krylov part: the bottom's pressure rho g e^{-kT} e^{ikx} over its area
    k = 0.1 ** 2 / G
    fk = data['Froude_Krylov_force'].sel(omega=0.1, influenced_dof='Heave').values
    np.testing.assert_allclose(
        fk, RHO * G * math.exp(-k * 2.0) * 4.0 * 2.0 * math.sin(10.0 * k) / k, rtol=1e-3)


def test_head_sea_surge_force_of_a_symmetric_box(box):
    """
    Waves toward +x: surge force along +x a quarter period before the crest is at the origin.

    The Froude-Krylov surge force of a box is -integral of p n_x: the pressure p = rho g a
    e^{kz} e^{ikx} on the ends x = +-L/2, which gives -2 i rho g a B sin(kL/2) (1 - e^{-kT})
    / k: purely imaginary and negative. With exp(-i omega t) the force is then
    -|F| sin(omega t): +|F| at omega t = -pi/2, a quarter period before the crest reaches the
    origin, when the water stands higher at the stern than at the bow.
    """
    _, data = box
    fk = data['Froude_Krylov_force'].sel(omega=0.1, wave_direction=0.0,
                                         influenced_dof='Surge').values
    k = 0.1 ** 2 / G
    expected = -2j * RHO * G * 4.0 * math.sin(k * 10.0) * (1.0 - math.exp(-k * 2.0)) / k
    assert fk.imag == pytest.approx(expected.imag, rel=0.02)
    assert abs(fk.real) < 0.01 * abs(fk)
    sway = data['excitation_force'].sel(omega=0.1, wave_direction=0.0,
                                        influenced_dof='Sway').values
    assert abs(sway) < 1e-6 * abs(fk)


def test_the_record_read_back_is_what_was_solved(box):
    out, data = box
    record = read_hydro_database(out)
    np.testing.assert_array_equal(record.omega, [0.1, 1.5, 4.43])
    np.testing.assert_allclose(record.headings, np.radians([-180.0, -90.0, 0.0, 90.0, 180.0]))
    np.testing.assert_array_equal(record.added_mass, data['added_mass'].values)
    np.testing.assert_array_equal(record.radiation_damping, data['radiation_damping'].values)
    np.testing.assert_array_equal(record.added_mass_infinite,
                                  data['added_mass_infinite'].values)
    # heading -90 deg is Capytaine's 270; -180 and 180 both its 180
    for heading, solved in ((-math.pi, 180.0), (-0.5 * math.pi, 270.0), (0.0, 0.0),
                            (0.5 * math.pi, 90.0), (math.pi, 180.0)):
        row = int(np.argmin(abs(record.headings - heading)))
        direction = math.radians(solved)
        np.testing.assert_array_equal(
            record.excitation[row],
            data['excitation_force'].sel(wave_direction=direction).values)
        np.testing.assert_array_equal(
            record.drift[row], data['mean_drift_force'].sel(wave_direction=direction).values)
    np.testing.assert_array_equal(record.reference_point, [0.0, 0.0, -1.0])
    assert record.water_depth == math.inf
    assert (record.water_density, record.g) == (RHO, G)


def test_beam_sea_drift_at_short_waves_is_the_reflection_limit(box):
    """
    Waves of 3.1 m on a 20 m wall-sided box (kT = 4): reflected whole, 1/2 rho g a^2 per metre.

    Capytaine's far-field (Maruo) drift from the Kochin functions, for the box's own (small)
    motions; the box's ends take off a little (the waves bend round them over a wavelength or
    so): 92 % of the limit here.
    """
    out, _ = box
    record = read_hydro_database(out)
    beam = int(np.argmin(abs(record.headings - 0.5 * math.pi)))
    surge, sway, yaw = record.drift[beam, -1]
    limit = 0.5 * RHO * G * 20.0
    assert sway == pytest.approx(limit, rel=0.1)
    assert sway < limit
    assert abs(surge) < 0.01 * limit and abs(yaw) < 0.01 * limit * 10.0
    # toward -y the same, the other way
    port = int(np.argmin(abs(record.headings + 0.5 * math.pi)))
    assert record.drift[port, -1, 1] == pytest.approx(-sway, rel=1e-6)


def test_infinite_frequency_heave_of_a_hemisphere_is_half_its_mass(tmp_path):
    """
    A floating hemisphere's heave added mass at infinite frequency is half its displaced mass.

    (The free surface a node of the potential: the hemisphere and its image are a sphere in
    unbounded fluid, whose added mass is half its displaced mass.) Also the user mesh route:
    ship.mesh, a GDF file written here.
    """
    import capytaine as cpt
    mesh = cpt.mesh_sphere(radius=5.0, center=(0.0, 0.0, 0.0), resolution=(20, 40)) \
        .immersed_part().merged()
    path = tmp_path / 'hemisphere.gdf'
    lines = ['hemisphere', '1.0 9.81', '0 0', str(mesh.nb_faces)]
    for face in mesh.faces:
        lines += [' '.join(f'{c:.9f}' for c in mesh.vertices[v]) for v in face]
    path.write_text('\n'.join(lines) + '\n')
    mass = RHO * 2.0 / 3.0 * math.pi * 5.0 ** 3
    overrides = {'ship.mesh': str(path), 'ship.mass': mass, 'seabed_level': -math.inf,
                 'ship.center_of_gravity': [0.0, 0.0, -1.875],
                 'ship.radii_of_gyration': [2.5, 2.5, 2.5]}
    data = make_database(BERTH, str(tmp_path / 'h.nc'), overrides,
                         HydroSettings(np.array([0.8, 1.2]), np.array([0.0]), lid=False))
    a33 = float(data['added_mass_infinite'].sel(influenced_dof='Heave',
                                                radiating_dof='Heave'))
    # 3.9 % high on 12 x 24 panels, 3.0 % on these 20 x 40
    assert a33 == pytest.approx(0.5 * mass, rel=0.04)


def test_added_mass_symmetric_damping_not_negative(shipped):
    """
    The shipped database: A and B symmetric, B positive semi-definite up to 1.3 rad/s.

    Above, its 3 m panels are too coarse for the heave and pitch damping (small there): B33
    and B55 dip below 0 between 1.35 and 2 rad/s (docs/waves.md).
    """
    for a, b in zip(shipped.added_mass, shipped.radiation_damping[shipped.omega < 1.3]):
        scale = np.abs(a).max()
        np.testing.assert_allclose(a, a.T, atol=1e-3 * scale)
        np.testing.assert_allclose(b, b.T, atol=1e-3 * np.abs(b).max())
        eigenvalues = np.linalg.eigvalsh(0.5 * (b + b.T))
        assert eigenvalues.min() > -1e-3 * eigenvalues.max()


def test_heave_damping_is_what_the_excitation_radiates(shipped):
    """
    Haskind-Newman: B33 = k / (8 pi rho g c_g) times the integral of |X3|^2 over headings.

    Ties the damping to the excitation of every heading (and the headings to the circle).
    Where the 45 degree headings resolve |X|^2 round the circle: long waves, 0.15 to
    0.3 rad/s (kh 0.19 to 0.39 in the berth's 16 m); below kh 0.19 the finite-depth Green
    function falls out with itself (docs/waves.md).
    """
    depth, g = shipped.water_depth, shipped.g
    for row in np.searchsorted(shipped.omega, [0.15 - 1e-9, 0.2 - 1e-9, 0.3 - 1e-9]):
        omega = shipped.omega[row]
        k = omega / math.sqrt(g * depth)  # Newton on k tanh(kh) = omega^2 / g from shallow
        for _ in range(50):
            t = math.tanh(k * depth)
            k -= (k * t - omega ** 2 / g) / (t + k * depth * (1.0 - t * t))
        group = 0.5 * omega / k * (1.0 + 2.0 * k * depth / math.sinh(2.0 * k * depth))
        for dof in (1, 2):  # sway, heave
            power = np.trapezoid(np.abs(shipped.excitation[:, row, dof]) ** 2,
                                 shipped.headings)
            expected = k / (8.0 * math.pi * shipped.water_density * g * group) * power
            assert shipped.radiation_damping[row, dof, dof] == pytest.approx(expected,
                                                                             rel=0.03)


def test_shipped_database_covers_what_the_waves_need(shipped):
    assert shipped.omega[0] <= 0.05 + 1e-9 and shipped.omega[-1] >= 2.0 - 1e-9
    for heading in (0.0, 45.0, 90.0, 135.0, 180.0):
        assert np.isclose(shipped.headings, math.radians(heading)).any()
    # the default ship, at the berth's 16 m, about its centre of gravity
    assert shipped.water_depth == 16.0
    np.testing.assert_array_equal(shipped.reference_point, [0.0, 0.0, -3.0])
    # long waves: heave force toward rho g A_wp a (the hull's waterplane: L B C_b); in 16 m
    # of water 0.05 rad/s is still kL = 0.9 (the wave 1.6 km long): 4.5 % short head on
    heave = shipped.excitation[:, 0, 2]
    np.testing.assert_allclose(np.abs(heave), RHO * G * 225.0 * 32.2 * 0.85, rtol=0.05)
    assert (np.abs(heave) < RHO * G * 225.0 * 32.2 * 0.85).all()


@pytest.mark.parametrize('overrides, settings, message', [
    ({'ship.draft': 16.0}, None, 'ship.draft 16 m is not less than the water depth 16 m'),
    ({'ship.mesh': '/no/such/hull.gdf'}, None, 'no such file /no/such/hull.gdf'),
    ({'seabed_level': -math.inf, 'water_level': -math.inf}, None, 'has no water'),
])
def test_bad_ships_are_one_line(tmp_path, overrides, settings, message):
    with pytest.raises(HydroError, match=message):
        make_database(BERTH, str(tmp_path / 'x.nc'), overrides, settings)
    assert not (tmp_path / 'x.nc').exists()


def test_a_file_capytaine_cannot_read_is_one_line(tmp_path, capsys):
    hull = tmp_path / 'hull.gdf'
    hull.write_text('not a mesh\nat all\n')
    out = tmp_path / 'x.nc'
    code = cli.main(['hydro', BERTH, '--out', str(out), '--set', f'ship.mesh={hull}'])
    err = capsys.readouterr().err
    assert code == 2
    assert f'Capytaine cannot read {hull} as a mesh' in err
    assert err.count('\n') == 1 and 'Traceback' not in err
    assert not out.exists()


def test_an_existing_out_is_kept_without_force(tmp_path, capsys):
    out = tmp_path / 'ship.nc'
    out.write_text('keep me')
    code = cli.main(['hydro', BERTH, '--out', str(out)])
    assert code == 2
    assert 'exists: give --force' in capsys.readouterr().err
    assert out.read_text() == 'keep me'


@pytest.mark.parametrize('argv, message', [
    (['--omega', '1.0', '0.5', '10'], 'need 0 < min < max'),
    (['--heading-step', '25'], 'must divide 360'),
    (['--panel-size', '0'], 'panel size 0 m'),
])
def test_bad_settings_are_one_line(tmp_path, capsys, argv, message):
    assert cli.main(['hydro', BERTH, '--out', str(tmp_path / 'x.nc'), *argv]) == 2
    assert message in capsys.readouterr().err


def test_not_an_arrangement_is_refused(tmp_path):
    with pytest.raises(HydroError, match='is not an arrangement'):
        make_database(str(REPO_ROOT / 'config' / 'mooring_line.yaml'), str(tmp_path / 'x.nc'))
    with pytest.raises(HydroError, match='no such file'):
        make_database(str(tmp_path / 'none.yaml'), str(tmp_path / 'x.nc'))


def test_bad_database_files_are_one_line(tmp_path, box):
    text = tmp_path / 'text.nc'
    text.write_text('hello')
    with pytest.raises(HydroFileError, match=f'{text}: not a NetCDF 3 file'):
        read_hydro_database(text)
    with pytest.raises(HydroFileError, match='cannot read it: No such file'):
        read_hydro_database(tmp_path / 'none.nc')
    import xarray as xr
    out, _ = box
    partial = tmp_path / 'partial.nc'
    with xr.open_dataset(out) as data:
        data.drop_vars('mean_drift_force').to_netcdf(partial, engine='scipy')
    with pytest.raises(HydroFileError, match='no mean_drift_force: not a file of rope_sim'):
        read_hydro_database(partial)


def test_default_settings_span_the_band():
    settings = default_settings()
    assert settings.omega[0] == 0.05 and settings.omega[-1] == 2.0
    np.testing.assert_allclose(np.degrees(settings.headings), np.arange(0.0, 360.0, 30.0))


def test_the_command_through_the_launcher(tmp_path):
    """`python -m rope_sim_ros hydro`: a tiny box solved, the file read back; a bad --set."""
    out = tmp_path / 'box.nc'
    env = dict(os.environ, PYTHONPATH=str(REPO_ROOT))
    sets = []
    for key, value in BOX.items():
        sets += ['--set', f'{key}={value}'.replace('-inf', '-.inf')]
    result = subprocess.run(
        [sys.executable, '-m', 'rope_sim_ros', 'hydro', BERTH, '--out', str(out), *sets,
         '--omega', '0.5', '1.0', '2', '--heading-step', '180', '--panel-size', '2'],
        env=env, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert f'2 frequencies x 2 headings, 96 panels -> {out}' in result.stdout
    record = read_hydro_database(out)
    assert record.excitation.shape == (3, 2, 6)
    # written as any file of the user's is: readable by others where the umask lets it be
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o666 & ~mask
    result = subprocess.run(
        [sys.executable, '-m', 'rope_sim_ros', 'hydro', BERTH, '--out', str(out), '--force',
         '--set', 'ship.draft=-1'], env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert "'ship.draft'" in result.stderr and 'Traceback' not in result.stderr
