"""Tests of roughstick.surface.profile: line scans' 1-D PSD, its relation to the 2D PSD, and
profile moments; line scans refused with a clear message where a 2-D map is needed."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs

A = 1e-36  # m4
Q0 = 2 * np.pi / 40e-9  # rad/m: Gaussian PSD s(q) = A exp(-(q/q0)^2)


def gauss(q):
    return A * np.exp(-((np.asarray(q) / Q0) ** 2))


def gauss_projected(qx):
    """Exact projection of the Gaussian: C(qx) = int s dqy = A sqrt(pi) q0 exp(-(qx/q0)^2)."""
    return A * np.sqrt(np.pi) * Q0 * np.exp(-((np.asarray(qx) / Q0) ** 2))


def profile(z, dx):
    x = (np.arange(np.shape(z)[-1]) + 0.5) * dx
    dims = ("x",) if np.ndim(z) == 1 else ("row", "x")
    return xr.DataArray(z, dims=dims, coords={"x": ("x", x, {"units": "m"})}, attrs={"units": "m"})


@pytest.mark.parametrize("n", [64, 37])
def test_parseval_exact(n):
    z = np.random.default_rng(n).normal(size=n) * 1e-9
    c = rs.surface.profile_psd(profile(z, 3e-9), window=None)
    assert c.dims == ("qx",) and c.attrs["units"] == "m3" and 0.0 in c.qx.values
    dq = float(c.qx[1] - c.qx[0])
    np.testing.assert_allclose(dq, 2 * np.pi / (n * 3e-9), rtol=1e-12)
    np.testing.assert_allclose(float(c.sum()) * dq, z.var(), rtol=1e-12)
    np.testing.assert_allclose(float(rs.surface.profile_moments(c).m0), z.var(), rtol=1e-12)


def test_rows_of_isotropic_surface_match_projected_psd_within_statistical_error():
    """Independent method: the closed-form projection of a known isotropic PSD. Each 2-D mode's
    periodogram is exponential with mean s (Rayleigh amplitudes), and the row-averaged profile
    PSD at qx is sum_qy of them times dqy, so its standard error is sqrt(sum s^2) dqy / sqrt(n)."""
    n, ny, nx, dx = 6, 96, 192, 2e-9
    h = rs.surface.generate_surfaces(gauss, n=n, shape=(ny, nx), spacing=dx, seed=3).compute()
    c = rs.surface.profile_psd(h).mean(["realization", "y"])  # rows are profiles along x
    qx = c.qx.values
    qy = 2 * np.pi * np.fft.fftfreq(ny, dx)
    dqy = 2 * np.pi / (ny * dx)
    s2 = gauss(np.hypot(qx[:, None], qy[None, :]))
    expected = gauss_projected(qx)
    np.testing.assert_allclose(s2.sum(axis=1) * dqy, expected, rtol=1e-9, atol=1e-12 * expected.max())
    se = np.sqrt((s2**2).sum(axis=1)) * dqy / np.sqrt(n)
    # +qx and -qx are complex conjugates: one independent value per |qx|, qx = 0 is removed with the row mean
    keep = (qx > 0) & (expected > 1e-3 * expected.max())
    zscore = (c.values - expected)[keep] / se[keep]
    assert keep.sum() > 20
    assert np.max(np.abs(zscore)) < 4.5, zscore
    assert 0.4 < np.mean(zscore**2) < 2.0  # chi-square per degree of freedom near 1
    # and the 2D estimator projected gives the same profile PSD (Parseval along y, exact off qx = 0)
    proj = rs.surface.project_psd(rs.surface.power_spectrum(h)).mean("realization")
    np.testing.assert_allclose(proj.values[qx != 0], c.values[qx != 0], rtol=1e-9, atol=1e-12 * c.values.max())


def test_project_isotropic_matches_closed_form_and_moments():
    q = np.linspace(0, 12 * Q0, 600)
    iso = xr.DataArray(gauss(q), dims="q", coords={"q": q}, attrs={"units": "m4"}, name="psd")
    qx = np.linspace(-3 * Q0, 3 * Q0, 61)
    c = rs.surface.project_psd(iso, qx=qx)
    np.testing.assert_allclose(c.values, gauss_projected(qx), rtol=2e-3, atol=1e-4 * gauss_projected(0))
    # profile moments of an isotropic surface = its one-direction Nayak moments (closed form)
    m = rs.surface.profile_moments(rs.surface.project_psd(iso))
    np.testing.assert_allclose(float(m.m0), np.pi * A * Q0**2, rtol=5e-3)
    np.testing.assert_allclose(float(m.m2), np.pi * A * Q0**4 / 2, rtol=5e-3)
    np.testing.assert_allclose(float(m.m4), 3 * np.pi * A * Q0**6 / 4, rtol=5e-3)
    mi = rs.surface.psd_moments(iso)
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(float(m[k]), float(mi[k]), rtol=5e-3)


def test_profile_m2_is_mean_squared_slope():
    """m2 of a profile is its mean squared slope, here by 4th-order central differences on a
    profile sampled 80 points per correlation length (truncation error < 1e-4)."""
    dx = 0.5e-9
    h = rs.surface.generate_surfaces(gauss, n=1, shape=(4, 2048), spacing=dx, seed=5).compute().isel(realization=0)
    z = h.values
    zp = np.concatenate([z[:, -2:], z, z[:, :2]], axis=1)  # periodic surface: wrap the stencil
    slope = (-zp[:, 4:] + 8 * zp[:, 3:-1] - 8 * zp[:, 1:-3] + zp[:, :-4]) / (12 * dx)
    msq = (slope**2).mean(axis=1)
    for method in ("spline", "spectral"):
        m = rs.surface.profile_moments(h, method=method)
        assert m.m2.dims == ("y",)
        np.testing.assert_allclose(m.m2.values, msq, rtol=1e-2)
        np.testing.assert_allclose(m.m0.values, z.var(axis=1), rtol=1e-12)
        rs.testing.assert_units(m.m2, "1")


def test_level_profile_removes_line_and_fills_nan():
    x = (np.arange(50) + 0.5) * 1e-9
    z = 0.3 * x + np.sin(x / 3e-9) * 1e-9
    z[[7, 8]] = np.nan
    with pytest.raises(ValueError, match="nan='fill'"):
        rs.surface.level_profile(profile(z, 1e-9))
    p = rs.surface.level_profile(profile(z, 1e-9), nan="fill")
    assert np.all(np.isfinite(p.values))
    assert abs(np.polyfit(x, p.values, 1)[0]) < 1e-12


def test_bad_profiles_are_refused_clearly():
    with pytest.raises(ValueError, match="at least 8"):
        rs.surface.profile_psd(profile(np.arange(5.0) * 1e-9, 1e-9))
    with pytest.raises(ValueError, match="constant"):
        rs.surface.profile_psd(profile(np.ones(16) * 1e-9, 1e-9))
    with pytest.raises(ValueError, match="dim 'x'"):
        rs.surface.profile_psd(xr.DataArray(np.ones(16), dims="t", attrs={"units": "m"}))
    with pytest.raises(TypeError, match="line_scan=True"):
        rs.surface.profile_psd(np.ones(16))
    c = rs.surface.profile_psd(profile(np.random.default_rng(0).normal(size=32) * 1e-9, 1e-9))
    with pytest.raises(ValueError, match="profile_moments"):
        rs.surface.psd_moments(c)


def test_line_scan_refused_where_a_map_is_needed():
    p = profile(np.random.default_rng(1).normal(size=64) * 1e-9, 2e-9)
    with pytest.raises(ValueError, match="line scan.*profile_psd"):
        rs.surface.validate_height(p)
    with pytest.raises(ValueError, match="line scan.*profile_psd"):
        rs.contact.curves(p, relative_humidity=0.5, distance=np.linspace(1e-9, 5e-9, 5))
    c = rs.surface.profile_psd(p)
    with pytest.raises(ValueError, match="profile PSD.*2-D"):
        rs.surface.generate_surfaces(c, n=1, shape=(16, 16), spacing=2e-9, seed=0)


def test_lazy_stack_equals_eager_bit_for_bit():
    z = np.random.default_rng(2).normal(size=(6, 50)) * 1e-9
    p = profile(z, 2e-9)
    eager = rs.surface.profile_psd(p, window="hann")
    lazy = rs.surface.profile_psd(p.chunk({"row": 2}), window="hann")
    assert lazy.chunks is not None
    np.testing.assert_array_equal(lazy.compute().values, eager.values)
    np.testing.assert_array_equal(rs.surface.profile_psd(p.isel(row=3)).values, rs.surface.profile_psd(p).isel(row=3).values)
