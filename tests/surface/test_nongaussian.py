"""Non-Gaussian surfaces (roughstick.surface.height_distribution, generate_surfaces'
height_distribution=) and the height-distribution diagnostics (height_diagnostics, is_gaussian).

Tolerances: on 128 x 128 surfaces whose correlation length is 8 pixels (about 250 independent
patches each), 16 surfaces hold the ensemble-mean PSD in octave bands within 1-2 % of the
Gaussian generator's on the same seeds and the pooled 99th/99.9th height percentiles within
about 1.5 % of the target (measured over seeds 1-3 and the three targets below); the tests allow
5 %. The translation's expected spectrum (its correlation map, no sampling) is exact to 0.5 %.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy import special, stats

import roughstick as rs
from roughstick.surface import _marginal_kernels as kernels
from roughstick.surface.distribution import (
    evaluate,
    gauss_hermite,
    johnson_fit,
    standard_moments,
    standardised,
)
from roughstick.surface.generate import _half_plane_power
from roughstick.testing import raise_if_dask_computes

SPACING = 5e-9
SHAPE = 128
Q0 = 2 * np.pi / (8 * SPACING)  # correlation length of 8 pixels


def short_psd(q):
    """A PSD flat below Q0 and falling as q^-4 above, up to the Nyquist wave number."""
    return 1e-34 * (1 + (np.asarray(q) / Q0) ** 2) ** -2


TARGETS = [(0.8, 4.5), (-0.5, 3.5), (1.0, 6.0)]


def _bands(power, shape=SHAPE, spacing=SPACING, n_bands=8, support=None):
    q = 2 * np.pi * np.hypot(*np.meshgrid(np.fft.fftfreq(shape, spacing), np.fft.fftfreq(shape, spacing)))
    top = q.max() if support is None else q[support].max()
    edges = np.geomspace(q[q > 0].min() * 0.999, top * 1.001, n_bands + 1)
    return np.array([power[(q >= lo) & (q < hi)].sum() for lo, hi in zip(edges[:-1], edges[1:], strict=True)])


def _periodogram(z):
    return (np.abs(np.fft.fft2(z)) ** 2).mean(axis=0)


# ------------------------------------------------------------------------------ distributions
@pytest.mark.parametrize("skewness,kurtosis,family", [
    (0.4, 3.8, "johnson_su"), (-0.5, 3.5, "johnson_su"), (1.0, 6.0, "johnson_su"), (0.0, 6.0, "johnson_su"),
    (0.5, 3.0, "johnson_sb"), (1.0, 4.0, "johnson_sb"), (0.0, 2.5, "johnson_sb"), (-0.8, 3.2, "johnson_sb")])
def test_johnson_fit_recovers_the_moments(skewness, kurtosis, family):
    d = rs.surface.height_distribution(skewness=skewness, kurtosis=kurtosis)
    assert d.attrs["family"] == family
    assert d.attrs["skewness"] == pytest.approx(skewness, abs=1e-6)
    assert d.attrs["kurtosis"] == pytest.approx(kurtosis, abs=1e-6)
    # scipy's own distribution with the recorded parameters has them too, mean 0 and rms 1
    x, w = gauss_hermite()
    law = getattr(stats, family.replace("_", ""))(d.attrs["johnson_a"], d.attrs["johnson_b"],
                                                  d.attrs["johnson_loc"], d.attrs["johnson_scale"])
    mean, var, skew, excess = law.stats("mvsk")
    _, _, table_skew, table_kurt = standard_moments(evaluate(d.height.values, x), w)
    assert (table_skew, table_kurt) == pytest.approx((skewness, kurtosis), abs=2e-5)  # the table
    assert (float(mean), float(var)) == pytest.approx((0.0, 1.0), abs=2e-5)  # scipy integrates SB
    assert (float(skew), float(excess) + 3) == pytest.approx((skewness, kurtosis), abs=2e-5)
    # the table is the translation: F^-1(Phi(u))
    u = np.array([-3.0, -1.0, 0.5, 2.326, 3.09])
    np.testing.assert_allclose(evaluate(d.height.values, u), law.ppf(special.ndtr(u)), rtol=1e-5, atol=1e-5)


def test_johnson_refuses_impossible_moments_and_gaussian_is_normal():
    with pytest.raises(ValueError, match="kurtosis > 1 \\+ skewness"):
        rs.surface.height_distribution(skewness=1.0, kurtosis=1.9)
    assert johnson_fit(0.0, 3.0) == ("normal", 0.0, 1.0)
    d = rs.surface.height_distribution(skewness=0, kurtosis=3)
    np.testing.assert_array_equal(d.height.values, d.normal_score.values)


def test_empirical_distribution_of_maps():
    law = stats.johnsonsu(-1.2, 2.0)
    rng = np.random.default_rng(0)
    z = law.rvs(size=(2, 128, 128), random_state=rng)
    maps = rs.testing.make_topography(z * 1e-9, spacing=SPACING)
    d = rs.surface.height_distribution(maps)
    assert d.attrs["family"] == "empirical" and d.attrs["n_maps"] == 2
    assert d.attrs["n_pixels"] == z.size
    zs = (z - z.mean(axis=(1, 2), keepdims=True)) / z.std(axis=(1, 2), keepdims=True)
    assert d.attrs["skewness"] == pytest.approx(np.mean(zs**3), rel=1e-2)
    u = np.array([-2.0, 0.0, 1.0, 2.326, 3.09])
    np.testing.assert_allclose(evaluate(d.height.values, u), np.quantile(zs, special.ndtr(u)), atol=0.03)
    # beyond the data (u > 4.4 for 32768 pixels) the table goes on as a straight line
    beyond = d.height.sel(normal_score=slice(5.0, 8.0)).values
    np.testing.assert_allclose(np.diff(beyond, 2), 0, atol=1e-9)
    assert np.all(np.diff(d.height.values) >= 0)
    with pytest.raises(ValueError, match="not both"):
        rs.surface.height_distribution(maps, skewness=0.1, kurtosis=3)


# ------------------------------------------------------------------------------ generation
def test_gaussian_path_is_unchanged():
    psd = rs.datasets.family_psd("S1")
    kw = dict(n=3, shape=(32, 48), spacing=SPACING, seed=7, chunks=2)
    for amplitude in ("rayleigh", "fixed"):
        base = rs.surface.generate_surfaces(psd, amplitude=amplitude, **kw)
        none = rs.surface.generate_surfaces(psd, amplitude=amplitude, height_distribution=None, **kw)
        normal = rs.surface.generate_surfaces(psd, amplitude=amplitude, **kw, height_distribution=
                                              rs.surface.height_distribution(skewness=0, kurtosis=3))
        np.testing.assert_array_equal(base.values, none.values)
        np.testing.assert_array_equal(base.values, normal.values)
        assert base.attrs["history"].split(" ", 1)[1] == none.attrs["history"].split(" ", 1)[1]
        assert "height_distribution" not in normal.attrs


@pytest.mark.parametrize("method", ["translation", "iaaft"])
def test_bit_identical_whatever_the_chunking(method):
    d = rs.surface.height_distribution(skewness=0.9, kurtosis=5.0)
    kw = dict(shape=(24, 40), spacing=SPACING, seed=11, height_distribution=d, distribution_method=method)
    ref = rs.surface.generate_surfaces(short_psd, n=5, chunks=-1, **kw).values
    for chunks in (1, 2, (3, 2)):
        np.testing.assert_array_equal(rs.surface.generate_surfaces(short_psd, n=5, chunks=chunks, **kw).values, ref)
    alone = rs.surface.generate_surfaces(short_psd, realizations=[3], **kw).values
    np.testing.assert_array_equal(alone[0], ref[3])
    other = rs.surface.generate_surfaces(short_psd, n=5, **{**kw, "seed": 12}).values
    assert not np.allclose(other, ref)
    f32 = rs.surface.generate_surfaces(short_psd, n=5, dtype="float32", **kw).values
    assert f32.dtype == np.float32
    np.testing.assert_allclose(f32, ref, rtol=0, atol=1e-5 * np.abs(ref).max())


def test_lazy_and_recorded():
    d = rs.surface.height_distribution(skewness=0.5, kurtosis=4.0)
    with raise_if_dask_computes():
        h = rs.surface.generate_surfaces(short_psd, n=4, shape=32, spacing=SPACING, seed=1, chunks=2,
                                         height_distribution=d)
    assert h.chunks[0] == (2, 2)
    assert h.attrs["height_distribution"] == "johnson_su"
    assert h.attrs["distribution_method"] == "translation"
    assert "translation process" in h.attrs["history"] and "Shields" in h.attrs["references"]


@pytest.mark.parametrize("skewness,kurtosis", TARGETS)
def test_translation_holds_psd_and_tail(skewness, kurtosis):
    d = rs.surface.height_distribution(skewness=skewness, kurtosis=kurtosis)
    kw = dict(n=16, shape=SHAPE, spacing=SPACING, seed=2)
    gauss = rs.surface.generate_surfaces(short_psd, **kw).values
    z = rs.surface.generate_surfaces(short_psd, **kw, height_distribution=d).values
    # the PSD: octave bands within 5 % of the Gaussian generator's on the same seeds
    np.testing.assert_allclose(_bands(_periodogram(z)) / _bands(_periodogram(gauss)), 1, atol=0.05)
    # the upper tail: pooled 99th and 99.9th percentiles within 5 % of the target's
    sigma = np.sqrt(float((rs.surface.surface_filter(short_psd, shape=SHAPE, spacing=SPACING)).sum())
                    * (2 * np.pi / (SHAPE * SPACING)) ** 2)
    expected = sigma * evaluate(standardised(d.height.values), special.ndtri([0.99, 0.999]))
    np.testing.assert_allclose(np.quantile(z, [0.99, 0.999]), expected, rtol=0.05)
    assert stats.skew(z.ravel()) == pytest.approx(skewness, abs=0.15)


def test_translation_expected_spectrum_is_the_target():
    """The pre-corrected Gaussian spectrum, mapped through the correlation map, is the PSD."""
    d = rs.surface.height_distribution(skewness=1.0, kurtosis=6.0)
    for psd in (short_psd, rs.datasets.family_psd("table4")):  # the second has a cutoff
        P, _ = _half_plane_power(psd, SHAPE, SHAPE, SPACING, SPACING)
        (A, rows, ncols), scale, table, info = kernels.translation_setup(P, SHAPE, d.height.values, "rayleigh")
        G = np.zeros_like(P)
        G[rows, :ncols] = 2 * A**2  # the filter of a complex Gaussian draw holds sqrt(G / 2)
        full = kernels._full_plane(G, nx=SHAPE)
        forward, _ = kernels._correlation_map(kernels.hermite_coefficients(table))
        expected = np.fft.ifft2(forward(np.fft.fft2(full).real)).real
        target = kernels._full_plane(kernels._symmetrise(P, SHAPE), nx=SHAPE)
        target = target / target.sum()
        inside = target > 0
        np.testing.assert_allclose(_bands(expected, support=inside) / _bands(target, support=inside), 1, atol=5e-3)
        assert scale == pytest.approx(np.sqrt(P.sum() + P[:, 1:SHAPE // 2].sum()), rel=1e-9)
        assert "pre-corrected" in info


def test_iaaft_gives_every_surface_the_target_quantiles():
    d = rs.surface.height_distribution(skewness=0.8, kurtosis=4.5)
    kw = dict(n=4, shape=64, spacing=SPACING, seed=3)
    z = rs.surface.generate_surfaces(short_psd, **kw, height_distribution=d, distribution_method="iaaft").values
    sorted_target = np.sort(z[0].ravel())
    for k in range(1, 4):
        np.testing.assert_array_equal(np.sort(z[k].ravel()), sorted_target)
    sigma = np.sqrt(float(rs.surface.surface_filter(short_psd, shape=64, spacing=SPACING).sum())
                    * (2 * np.pi / (64 * SPACING)) ** 2)
    n = 64 * 64
    np.testing.assert_allclose(sorted_target, sigma * evaluate(standardised(d.height.values),
                                                                special.ndtri((np.arange(n) + 0.5) / n)))
    gauss = rs.surface.generate_surfaces(short_psd, **kw).values
    np.testing.assert_allclose(_bands(_periodogram(z), shape=64, n_bands=5)
                               / _bands(_periodogram(gauss), shape=64, n_bands=5), 1, atol=0.05)


def test_rms_of_the_distribution_is_checked_against_the_psd():
    d = rs.surface.height_distribution(skewness=0.5, kurtosis=4.0, rms="10 nm")
    with pytest.warns(UserWarning, match="the surfaces take the PSD's rms height"):
        rs.surface.generate_surfaces(short_psd, n=1, shape=32, spacing=SPACING, seed=1, height_distribution=d)


@pytest.mark.parametrize("kwargs,error,match", [
    ({"height_distribution": xr.Dataset()}, TypeError, "rs.surface.height_distribution"),
    ({"height_distribution": "maps"}, TypeError, "rs.surface.height_distribution"),
    ({"distribution_method": "shuffle"}, ValueError, "distribution_method must be one of"),
])
def test_bad_arguments(kwargs, error, match):
    with pytest.raises(error, match=match):
        rs.surface.generate_surfaces(short_psd, n=1, shape=32, spacing=SPACING, **kwargs)


# ------------------------------------------------------------------------------ diagnostics
def test_diagnostic_intervals_cover_gaussian_maps():
    """Over 40 seeds, a Gaussian map's statistics fall in the Gaussian's 95 % intervals about
    95 % of the time (measured 0.95-0.98 on 64 x 64 maps of S1), and the verdict says Gaussian."""
    h = rs.surface.generate_surfaces(rs.datasets.family_psd("S1"), n=40, shape=64, spacing=SPACING, seed=5).compute()
    inside, verdict = [], []
    for k in range(40):
        d = rs.surface.height_diagnostics(h.isel(realization=k), n=50, seed=k)
        inside.append([float(d[f"{s}_gaussian_lower"]) <= float(d[s]) <= float(d[f"{s}_gaussian_upper"])
                       for s in ("skewness", "kurtosis")]
                      + list(((d.tail_quantile_gaussian_lower <= d.tail_quantile)
                              & (d.tail_quantile <= d.tail_quantile_gaussian_upper)).values))
        verdict.append(bool(d.gaussian))
    assert np.all(np.mean(inside, axis=0) >= 0.85), np.mean(inside, axis=0)
    assert np.mean(verdict) >= 0.85


def test_diagnostics_flag_a_skewed_map_and_pool_maps():
    d = rs.surface.height_distribution(skewness=1.0, kurtosis=5.0)
    skewed = rs.surface.generate_surfaces(short_psd, n=2, shape=SHAPE, spacing=SPACING, seed=4,
                                          height_distribution=d).compute()
    diag = rs.surface.height_diagnostics(skewed, n=40)
    assert diag.gaussian.dims == ("realization",) and not diag.gaussian.any()
    assert np.all(diag.skewness > diag.skewness_gaussian_upper)
    assert np.all(diag.tail_quantile.sel(probability=0.999) > diag.tail_quantile_gaussian_upper.sel(probability=0.999))
    np.testing.assert_allclose(diag.tail_quantile_gaussian, special.ndtri([0.99, 0.999]))
    assert not rs.surface.is_gaussian(skewed, n=40)
    # maps of different sizes: a list
    pooled = rs.surface.height_diagnostics([skewed.isel(realization=0), skewed.isel(realization=1, x=slice(0, 64))],
                                           pooled=True, n=20)
    assert pooled.gaussian.dims == () and not bool(pooled.gaussian)


def test_roughness_statistics_carry_the_diagnostics():
    h = rs.surface.generate_surfaces(short_psd, n=2, shape=64, spacing=SPACING, seed=1)
    lazy = rs.surface.roughness_statistics(h)
    assert "gaussian" not in lazy and "dask-backed" in lazy.attrs["diagnostics"]
    st = rs.surface.roughness_statistics(h.compute())
    assert st.gaussian.dims == ("realization",) and st.tail_quantile.dims == ("realization", "probability")
    assert "Gaussian surrogates" in st.attrs["diagnostics"]
    quick = rs.surface.roughness_statistics(h.compute(), diagnostics=False)
    assert "gaussian" not in quick
