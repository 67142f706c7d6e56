"""Tests of roughstick.surface.combine: PSDs of maps of different sizes/spacings averaged on a
common q grid."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs

A = 1e-36  # m4
QR = 2 * np.pi / 50e-9  # rad/m


def known(q):
    """The synthetic surfaces' isotropic PSD: A (1 + (q/qr)^2)^-2."""
    return A * (1 + (np.asarray(q) / QR) ** 2) ** -2


def iso(q, values, units="m4"):
    return xr.DataArray(values, dims="q", coords={"q": q}, attrs={"units": units}, name="psd")


def test_two_map_sizes_and_spacings_average_to_the_known_psd():
    """A 256 nm scan at 2 nm pixels and a 576 nm scan at 6 nm pixels of one random surface
    (8 realizations each): the average on the common grid matches the known PSD within the
    periodogram's standard error (a ring of n pixels averages n/2 independent exponential
    values), z-scores below 4.5 and their mean square near 1."""
    n = 8
    psds, variances = [], []
    for shape, dx, seed in [((128, 128), 2e-9, 3), ((96, 96), 6e-9, 4)]:
        h = rs.surface.generate_surfaces(known, n=n, shape=shape, spacing=dx, seed=seed).compute()
        s = rs.surface.psd_isotropic(rs.surface.power_spectrum(h)).mean("realization")
        psds.append(s)
        var = known(s.q.values) ** 2 / (np.maximum(s.n_samples.values, 1) / 2 * n)
        variances.append(iso(s.q.values, var))
    with pytest.raises(ValueError, match="average_psd_common"):
        rs.surface.average_psd(psds, "map")
    ds = rs.surface.average_psd_common(psds, names=["fine", "coarse"])
    np.testing.assert_allclose(float(ds.q[0]), 2 * np.pi / 256e-9, rtol=1e-9)  # the smaller map's 2 pi / L
    np.testing.assert_allclose(float(ds.q[-1]), float(psds[1].q[-1]), rtol=1e-9)  # the coarser map's last ring
    assert np.all(ds.n_maps == 2) and ds.contributed.dims == ("map", "q")
    assert ds.psd.attrs["units"] == "m4" and list(ds["map"].values) == ["fine", "coarse"]
    se = np.sqrt(rs.surface.average_psd_common(variances).psd / ds.n_maps)
    z = ((ds.psd - known(ds.q)) / se).values
    assert np.max(np.abs(z)) < 4.5, z
    assert 0.3 < np.mean(z**2) < 2.0
    # union: each q is averaged over the maps whose band covers it
    u = rs.surface.average_psd_common(psds, band="union", names=["fine", "coarse"])
    lo, hi = float(u.q[0]), float(u.q[-1])
    np.testing.assert_allclose([lo, hi], [2 * np.pi / 576e-9, float(psds[0].q[-1])], rtol=1e-9)
    fine_only = u.q > float(psds[1].q[-1]) * (1 + 1e-9)
    assert np.all(u.n_maps.where(fine_only, 2) == np.where(fine_only, 1, 2))
    assert np.all(u.contributed.sel(map="coarse").values == (~fine_only).values)
    assert np.all(np.isfinite(u.psd))
    # the moments of the averaged PSD over its band: m0 of the known PSD over the same band
    m = rs.surface.psd_moments(ds.psd)
    qq = np.geomspace(float(ds.q[0]), float(ds.q[-1]), 4000)
    np.testing.assert_allclose(float(m.m0), 2 * np.pi * np.trapezoid(known(qq) * qq, qq), rtol=0.05)


def test_power_law_interpolation_is_exact_and_bands_are_recorded():
    q1, q2 = np.linspace(0, 1e9, 65), np.linspace(0, 4e8, 129)
    s1, s2 = iso(q1, 1e-40 * np.maximum(q1, 1) ** -3.0), iso(q2, 3e-40 * np.maximum(q2, 1) ** -3.0)
    ds = rs.surface.average_psd_common([s1, s2], n_q=50)
    assert ds.sizes["q"] == 50
    np.testing.assert_allclose(ds.psd.values, 2e-40 * ds.q.values**-3.0, rtol=1e-9)
    np.testing.assert_allclose(ds.q_min.values, [1e9 / 64, 4e8 / 128])
    np.testing.assert_allclose(ds.q_max.values, [1e9, 4e8])


def test_disjoint_bands_and_mixed_kinds_are_refused():
    a = iso(np.linspace(0, 1e7, 20), np.ones(20) * 1e-36)
    b = iso(np.linspace(0, 1e9, 20), np.ones(20) * 1e-38)
    with pytest.raises(ValueError, match="do not overlap.*band='union'"):
        rs.surface.average_psd_common([a, b])
    with pytest.raises(ValueError, match="no map covers.*gap"):
        rs.surface.average_psd_common([a, b], band="union")
    c = rs.surface.profile_psd(xr.DataArray(np.random.default_rng(0).normal(size=32) * 1e-9, dims="x",
                                    coords={"x": np.arange(32) * 1e-9}, attrs={"units": "m"}))
    with pytest.raises(ValueError, match="project_psd"):
        rs.surface.average_psd_common([a, c])
    with pytest.raises(ValueError, match="band must be"):
        rs.surface.average_psd_common([a], band="all")


def test_profiles_of_different_lengths_average_one_sided():
    """Line scans of 512 and 300 points of one Gaussian-PSD surface: the averaged one-sided
    profile PSD integrates (x2) to the closed-form m0 and m2 of the projection over the band."""
    from scipy.special import erf
    q0 = 2 * np.pi / 40e-9

    def gauss(q):
        return A * np.exp(-((np.asarray(q) / q0) ** 2))

    h = rs.surface.generate_surfaces(gauss, n=8, shape=(128, 512), spacing=1e-9, seed=9).compute()
    long = rs.surface.profile_psd(h).mean(["realization", "y"])
    # a 300-point crop is not periodic: without a window its edge step leaks ~1/q^2 power that
    # inflated the averaged m2 by 28 % here (measured); the Hann window of Eqs. 26-31 removes it
    short = rs.surface.profile_psd(h.isel(x=slice(0, 300)), window="hann").mean(["realization", "y"])
    ds = rs.surface.average_psd_common([long, short])
    assert ds.psd.attrs["units"] == "m3" and "qx" in ds.dims
    m = rs.surface.profile_moments(ds.psd)
    a, b = float(ds.qx[0]) / q0, float(ds.qx[-1]) / q0
    np.testing.assert_allclose(a, 2 * np.pi / 300e-9 / q0, rtol=1e-9)
    c0 = A * np.sqrt(np.pi) * q0  # C(qx) = c0 exp(-(qx/q0)^2)
    m0 = 2 * c0 * q0 * np.sqrt(np.pi) / 2 * (erf(b) - erf(a))
    t = np.linspace(a, b, 20001)
    m2 = 2 * c0 * q0**3 * np.trapezoid(t**2 * np.exp(-(t**2)), t)
    np.testing.assert_allclose(float(m.m0), m0, rtol=0.1)
    np.testing.assert_allclose(float(m.m2), m2, rtol=0.1)
