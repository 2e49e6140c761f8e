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
Gust spectra (API, NPD) against their formulas, and the wind series built from them.

The spectrum values are computed here by hand from the published equations (see the
docstring of rope_sim_ros.model.ship.wind). The series is checked exactly where the method
makes it exact: over one period T the harmonics k/T are orthogonal, so the sample mean of
the gust over a full period sampled at M > 2N points is 0 and its sample variance is
sum(a_k^2)/2, to rounding. A record shorter than a period is random; its variance is checked
as an average over seeds.
"""

import math

import numpy as np
import pytest

from rope_sim_ros.model.ship.wind import (
    api_sigma, gust_spectrum, GustyWind, npd_reference_speed, npd_variance, SPECTRA)


def one_period(wind):
    """Return sample times covering exactly one period of the series, 4 per component."""
    count = 4 * wind.frequencies.size
    return np.arange(count) * (wind.duration / count)


# ---------------------------------------------------------------------- the spectra


def test_api_spectrum_by_hand():
    # U = 20 m/s at z = 10 m: I = 0.15 (10/20)^-0.125 = 0.163576, sigma = 3.27152 m/s,
    # f_p = 0.025 * 20 / 10 = 0.05 Hz, S(f) = sigma^2 / f_p / (1 + 1.5 f / f_p)^(5/3)
    sigma = 0.15 * (10.0 / 20.0) ** -0.125 * 20.0
    assert sigma == pytest.approx(3.2715232, rel=1e-7)
    assert api_sigma(20.0, 10.0) == pytest.approx(sigma, rel=1e-15)
    frequencies = np.array([0.0, 0.01, 0.05, 0.2])
    expected = [214.0572807, 138.2370371, 46.4832683, 8.3566704]
    np.testing.assert_allclose(gust_spectrum('api', 20.0, frequencies), expected, rtol=1e-8)
    # above the surface layer (z_s = 20 m) the exponent is -0.275: z = 40 m, f_p = 0.0125
    sigma40 = 0.15 * (40.0 / 20.0) ** -0.275 * 20.0
    value = sigma40 ** 2 / 0.0125 / (1.0 + 1.5 * 0.05 / 0.0125) ** (5.0 / 3.0)
    assert value == pytest.approx(19.198587, rel=1e-7)
    assert gust_spectrum('api', 20.0, 0.05, height=40.0) == pytest.approx(value, rel=1e-12)


def test_npd_spectrum_by_hand():
    # U0 = 20 m/s at z = 10 m: f~ = 172 f (20/10)^-0.75, S = 320 (2)^2 / (1 + f~^0.468)^(5/1.404)
    frequencies = np.array([0.001, 0.01, 0.1])
    reduced = 172.0 * frequencies * 2.0 ** -0.75
    expected = 320.0 * 4.0 / (1.0 + reduced ** 0.468) ** (5.0 / (3.0 * 0.468))
    np.testing.assert_allclose(expected, [446.622835, 106.417855, 9.446547], rtol=1e-8)
    np.testing.assert_allclose(gust_spectrum('npd', 20.0, frequencies), expected, rtol=1e-12)


def test_npd_height_goes_through_the_froya_profile():
    # the mean speed at 40 m of U0 = 20 m/s: U = U0 (1 + 0.0573 (1 + 0.148 U0)^0.5 ln 4)
    u0 = 20.0
    mean_40 = u0 * (1.0 + 5.73e-2 * math.sqrt(1.0 + 0.148 * u0) * math.log(4.0))
    assert mean_40 == pytest.approx(23.16146, rel=1e-6)
    assert npd_reference_speed(mean_40, 40.0) == pytest.approx(u0, rel=1e-12)
    assert npd_reference_speed(17.0, 10.0) == 17.0
    # S at 40 m uses U0 and z = 40 m
    f = 0.02
    reduced = 172.0 * f * 4.0 ** (2.0 / 3.0) * 2.0 ** -0.75
    expected = 320.0 * 4.0 * 4.0 ** 0.45 / (1.0 + reduced ** 0.468) ** (5.0 / (3.0 * 0.468))
    assert gust_spectrum('npd', mean_40, f, height=40.0) == pytest.approx(expected, rel=1e-10)


def test_total_variances():
    # API: the integral of S over all f is sigma^2 (closed form); a fine numerical integral
    # on a log grid agrees to 0.1 %
    f = np.concatenate([[0.0], np.geomspace(1e-7, 1e5, 400001)])
    api = gust_spectrum('api', 20.0, f)
    assert np.trapezoid(api, f) == pytest.approx(api_sigma(20.0, 10.0) ** 2, rel=1e-3)
    # NPD: closed form 320 (U0/10)^2 / (172 (U0/10)^-0.75) * G(1+1/n) G(2/3n) / G(5/3n)
    # = 7.0992 m^2/s^2 at U0 = 20 m/s, z = 10 m (sigma 2.6644 m/s)
    npd = gust_spectrum('npd', 20.0, f)
    assert npd_variance(20.0, 10.0) == pytest.approx(7.099163, rel=1e-6)
    assert math.sqrt(npd_variance(20.0, 10.0)) == pytest.approx(2.664426, rel=1e-6)
    assert np.trapezoid(npd, f) == pytest.approx(7.099163, rel=2e-3)
    # not DNV's Frøya turbulence standard deviation 0.06 (1 + 0.043 U0) U0 = 2.232 m/s,
    # which belongs to the wind profile's gust factor, not to the spectrum's integral
    assert 0.06 * (1.0 + 0.043 * 20.0) * 20.0 == pytest.approx(2.232)
    assert math.sqrt(npd_variance(20.0, 10.0)) / 2.232 == pytest.approx(1.1937, rel=1e-3)


def test_zero_mean_speed_gives_no_gust():
    for name in SPECTRA:
        np.testing.assert_array_equal(gust_spectrum(name, 0.0, [0.0, 0.1]), [0.0, 0.0])
        wind = GustyWind(name, 0.0, seed=3)
        assert wind.variance == 0.0
        assert wind.speed(12.5) == 0.0


# ---------------------------------------------------------------------- the series


@pytest.mark.parametrize('name', SPECTRA)
def test_mean_and_variance_over_one_period_are_exact(name):
    wind = GustyWind(name, 20.0, seed=11)
    assert wind.frequencies.size == 1800  # f_k = k / 3600 s up to 0.5 Hz
    assert wind.frequencies[0] == pytest.approx(1.0 / 3600.0, rel=1e-15)
    step = 1.0 / 3600.0
    np.testing.assert_allclose(wind.amplitudes,
                               np.sqrt(2.0 * gust_spectrum(name, 20.0, wind.frequencies)
                                       * step), rtol=1e-15)
    speeds = wind.speed(one_period(wind))
    assert speeds.min() > 0.0  # no clamping at 20 m/s, so the moments are those of the sum
    assert speeds.mean() == pytest.approx(20.0, abs=1e-12)
    assert speeds.var() == pytest.approx(wind.variance, rel=1e-11)
    assert wind.variance == pytest.approx(0.5 * np.sum(wind.amplitudes ** 2), rel=1e-15)


def test_variance_is_the_spectrum_over_the_represented_band():
    # The sum S(f_k) df is the midpoint rule over (df/2, f_max + df/2): against the exact
    # integral of the API spectrum over that band (closed form) it is within 1e-5; the band
    # holds 84 % of sigma^2 (the rest is above 0.5 Hz, and 0.3 % below 1/7200 Hz).
    wind = GustyWind('api', 20.0, seed=5)
    sigma, peak, df = api_sigma(20.0, 10.0), 0.05, 1.0 / 3600.0

    def below(f):
        return sigma ** 2 * (1.0 - (1.0 + 1.5 * f / peak) ** (-2.0 / 3.0))

    band = below(0.5 + df / 2) - below(df / 2)
    assert wind.variance == pytest.approx(band, rel=1e-5)
    assert band / sigma ** 2 == pytest.approx(0.8398, abs=1e-4)
    # NPD: against a fine numerical integral over the same band
    wind = GustyWind('npd', 20.0, seed=5)
    f = np.geomspace(df / 2, 0.5 + df / 2, 200001)
    band = np.trapezoid(gust_spectrum('npd', 20.0, f), f)
    assert wind.variance == pytest.approx(band, rel=1e-3)
    assert band / npd_variance(20.0, 10.0) == pytest.approx(0.8401, abs=1e-3)


@pytest.mark.parametrize('name, low', [('api', 0.95), ('npd', 0.93)])
def test_half_period_records_have_about_the_variance(name, low):
    # Half a period is a random sample of the process: its variance scatters (here from
    # -14 % to +15 % for NPD, whose energy sits at lower frequencies), so the check is on
    # the average of 20 seeds (fixed, so the numbers are repeatable): 0.99 for API, 0.96 for
    # NPD (the low frequencies are undersampled by half a period, biasing it low).
    ratios = []
    for seed in range(20):
        wind = GustyWind(name, 20.0, seed=seed)
        ratios.append(wind.speed(np.arange(0.0, 1800.0, 0.5)).var() / wind.variance)
    assert low <= np.mean(ratios) <= 1.02


def test_same_seed_same_series_and_other_seeds_differ():
    t = np.linspace(0.0, 600.0, 1201)
    first = GustyWind('npd', 15.0, seed=42).speed(t)
    np.testing.assert_array_equal(first, GustyWind('npd', 15.0, seed=42).speed(t))
    other = GustyWind('npd', 15.0, seed=43).speed(t)
    assert np.max(np.abs(first - other)) > 1.0
    # a scalar time gives the same number as the array path
    wind = GustyWind('api', 15.0, seed=42)
    assert wind.speed(123.4) == pytest.approx(float(wind.speed(np.array([123.4]))[0]),
                                              rel=1e-13)


def test_no_repeat_within_duration_and_period_duration():
    wind = GustyWind('api', 10.0, seed=1, duration=600.0, max_frequency=0.5)
    t = np.linspace(0.0, 100.0, 201)
    # periodic with period T ...
    np.testing.assert_allclose(wind.speed(t + 600.0), wind.speed(t), atol=1e-9)
    # ... and not with a shorter one: a shift of T/2 or T/3 changes the series
    for shift in (300.0, 200.0):
        assert np.max(np.abs(wind.speed(t + shift) - wind.speed(t))) > 0.5


def test_speed_is_clamped_at_zero():
    # With the published spectra the gust hardly ever reaches -U (sigma / U is at most
    # 0.16 for API at 10 m, 0.04 for NPD at U0 = 1 m/s: a 6-sigma excursion), so the clamp is
    # exercised with the components scaled up tenfold.
    wind = GustyWind('api', 1.0, seed=2)
    t = one_period(wind)
    assert (wind.mean_speed + wind.gust(t)).min() > 0.0
    wind.amplitudes = 10.0 * wind.amplitudes
    raw = wind.mean_speed + wind.gust(t)
    speeds = wind.speed(t)
    assert raw.min() < -1.0
    np.testing.assert_array_equal(speeds, np.maximum(raw, 0.0))
    assert speeds.min() == 0.0
    assert wind.speed(float(t[np.argmin(raw)])) == 0.0
    assert np.count_nonzero(speeds == 0.0) > 100


# ---------------------------------------------------------------------- bad input


def test_unknown_spectrum_lists_the_allowed_ones():
    with pytest.raises(ValueError, match="'kaimal' is unknown; allowed: api, npd"):
        gust_spectrum('kaimal', 10.0, [0.1])
    with pytest.raises(ValueError, match='allowed: api, npd'):
        GustyWind('none', 10.0, seed=0)


@pytest.mark.parametrize('kwargs, match', [
    (dict(mean_speed=-1.0), 'mean_speed'), (dict(mean_speed=math.nan), 'mean_speed'),
    (dict(mean_speed=math.inf), 'mean_speed'), (dict(height=0.0), 'height'),
    (dict(seed=-1), 'seed'), (dict(seed=1.5), 'seed'), (dict(duration=0.0), 'duration'),
    (dict(max_frequency=1e-4), 'max_frequency'), (dict(max_frequency=math.nan),
                                                  'max_frequency')])
def test_bad_wind_arguments_are_refused(kwargs, match):
    arguments = dict(name='api', mean_speed=10.0, seed=0)
    arguments.update(kwargs)
    with pytest.raises(ValueError, match=match):
        GustyWind(**arguments)


def test_bad_spectrum_arguments_are_refused():
    with pytest.raises(ValueError, match='frequencies_hz'):
        gust_spectrum('npd', 10.0, [-0.1])
    with pytest.raises(ValueError, match='frequencies_hz'):
        gust_spectrum('api', 10.0, [math.nan])
    with pytest.raises(ValueError, match='mean_speed'):
        gust_spectrum('api', -3.0, [0.1])
    with pytest.raises(ValueError, match='t '):
        GustyWind('api', 10.0, seed=0).speed(math.nan)
