"""Tests of roughstick.psd: Eq. 37 and its inverse, PSD estimation, averaging, cutoff."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import quad

import roughstick as rs
from roughstick._core import units as _units

QMAX = 289e6  # rad/m (paper: 289 rad/µm)
TABLE4 = dict(roughness=[2.6e-9, 2.4e-9], radius=220e-9)


# ------------------------------------------------------------------ Eq. 37 and its inverse


def test_self_affine_psd_shape_and_branches():
    q = np.array([0.0, 1e6, 2e7, 5e7, 2e8, 2.0000001e8, 1e9])
    s = rs.self_affine_psd(q, s0=1e-32, s1=1e-38, q0=2e7, qmax=2e8)
    assert s.dims == ("q",) and s.name == "psd"
    rs.testing.assert_units(s, "m4")
    np.testing.assert_allclose(s.values[:3], 1e-32)
    np.testing.assert_allclose(s.values[4], 1e-38, rtol=1e-12)  # s(qmax) = s1
    assert s.values[5] == 0 and s.values[6] == 0
    # log-log straight line between q0 and qmax with slope log10(s1/s0)/log10(qmax/q0) = -6
    slope = np.log10(s.values[3] / 1e-32) / np.log10(5e7 / 2e7)
    np.testing.assert_allclose(slope, -6.0, rtol=1e-12)


def test_self_affine_psd_on_2d_grid_and_isotropic_to_2d():
    qx = xr.DataArray(np.linspace(-3e8, 3e8, 31), dims="qx", attrs={"units": "rad m-1"})
    qy = xr.DataArray(np.linspace(-3e8, 3e8, 21), dims="qy", attrs={"units": "rad m-1"})
    qx = qx.assign_coords(qx=qx.values)
    qy = qy.assign_coords(qy=qy.values)
    qmag = np.hypot(qy, qx).assign_attrs(units="rad m-1")
    s2 = rs.self_affine_psd(qmag, s0=1e-32, s1=1e-38, q0=2e7, qmax=2e8)
    assert s2.dims == ("qy", "qx")
    iso = rs.self_affine_psd(np.linspace(0, 4e8, 4001), s0=1e-32, s1=1e-38, q0=2e7, qmax=2e8)
    s2b = rs.isotropic_to_2d(iso, qx=qx.values, qy=qy.values)
    assert s2b.dims == ("qy", "qx")
    # linear interpolation in log of a power law on a fine grid: close to the exact 2D values
    np.testing.assert_allclose(s2b.values, s2.values, rtol=2e-3, atol=0)


def test_self_affine_psd_units_of_dataarray_params():
    s = rs.self_affine_psd(
        [1e7], s0=xr.DataArray(1e4, attrs={"units": "nm4"}), s1=1e-38, q0=2e7, qmax=2e8
    )
    np.testing.assert_allclose(s.values, 1e-32)
    with pytest.raises(_units.UnitsError, match="units"):
        rs.self_affine_psd([1e7], s0=xr.DataArray(1e4), s1=1e-38, q0=2e7, qmax=2e8)
    with pytest.raises(ValueError, match="q0 must be smaller"):
        rs.self_affine_psd([1e7], s0=1e-32, s1=1e-38, q0=3e8, qmax=2e8)
    with pytest.raises(ValueError, match="positive"):
        rs.self_affine_psd([1e7], s0=-1e-32, s1=1e-38, q0=2e7, qmax=2e8)


@pytest.mark.parametrize("beta_s1", [1e-38, 1e-34, 1e-32 * (10 ** -2 / 1)])
def test_self_affine_moments_closed_form_vs_quadrature(beta_s1):
    # independent check: numerical quadrature of the isotropic moment integrals
    p = dict(s0=1e-32, s1=beta_s1, q0=2e7, qmax=2e8)
    m = rs.self_affine_moments(**p)

    def s(q):
        return float(rs.self_affine_psd([q], **p).values[0])

    pts = [p["q0"]]
    m0 = 2 * np.pi * quad(lambda q: s(q) * q, 0, p["qmax"], points=pts, limit=200)[0]
    m2 = np.pi * quad(lambda q: s(q) * q**3, 0, p["qmax"], points=pts, limit=200)[0]
    m4 = 0.75 * np.pi * quad(lambda q: s(q) * q**5, 0, p["qmax"], points=pts, limit=200)[0]
    np.testing.assert_allclose([float(m.m0), float(m.m2), float(m.m4)], [m0, m2, m4], rtol=1e-7)


def test_self_affine_exponent_special_cases():
    # exponents -2, -4, -6 hit the logarithmic branches of the closed form
    for k in (2, 4, 6):
        s1 = 1e-32 * 10.0 ** (-k)  # qmax/q0 = 10, so exponent = -k
        m = rs.self_affine_moments(s0=1e-32, s1=s1, q0=2e7, qmax=2e8)
        m_near = rs.self_affine_moments(s0=1e-32, s1=s1 * (1 + 1e-7), q0=2e7, qmax=2e8)
        for v in ("m0", "m2", "m4"):
            np.testing.assert_allclose(float(m[v]), float(m_near[v]), rtol=1e-6)


def test_moments_from_asperities_table4():
    m = rs.moments_from_asperities(**TABLE4, density=80.1e12)
    np.testing.assert_allclose(np.sqrt(float(m.m0)), 3.54e-9, rtol=2e-3)  # Table 4: 3.54 nm
    np.testing.assert_allclose(float(m.m4), 9.1e12, rtol=5e-3)  # 9.1 µm^-2 (squared formula)
    np.testing.assert_allclose(float(m.m2), 0.0035, rtol=5e-3)  # Table 4: 0.0035
    assert m.m0.attrs["units"] == "m2" and m.m4.attrs["units"] == "m-2"
    # Nayak: density and radius come back from the moments
    n = float(m.m4) / (6 * np.pi * np.sqrt(3) * float(m.m2))
    np.testing.assert_allclose(n, 80.1e12, rtol=1e-12)
    with pytest.raises(ValueError, match="roughness"):
        rs.moments_from_asperities(roughness=-1e-9, radius=220e-9, density=80.1e12)
    with pytest.raises(ValueError, match="radius"):
        rs.moments_from_asperities(roughness=1e-9, radius=0, density=80.1e12)


def test_fit_self_affine_table4_as_computed_n801():
    """Table 4 with N = 80.1 µm^-2: q0 ≈ 21.2 rad/µm, s0 ≈ 5.5e3 nm^4, s1 ≈ 5.5e-3 nm^4."""
    m = rs.moments_from_asperities(**TABLE4, density=80.1e12)
    fit = rs.fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=QMAX)
    np.testing.assert_allclose(float(fit.q0), 21.2e6, rtol=5e-3)
    np.testing.assert_allclose(float(fit.s0), 5.5e-33, rtol=1e-2)
    np.testing.assert_allclose(float(fit.s1), 5.5e-39, rtol=1e-2)
    for k in ("m0", "m2", "m4"):
        assert abs(float(fit[f"residual_{k}"])) < 1e-9
    # it is NOT the printed solution (the discrepancy DESIGN.md §3 documents)
    assert abs(float(fit.q0) / 19.4e6 - 1) > 0.05


def test_fit_self_affine_table4_printed_values_need_n881():
    """The printed 19.4 rad/µm, 6.46e3 nm^4, 6.29e-3 nm^4 come out with N = 88.1 µm^-2."""
    m = rs.moments_from_asperities(**TABLE4, density=88.1e12)
    fit = rs.fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=QMAX)
    np.testing.assert_allclose(float(fit.q0), 19.4e6, rtol=1e-2)
    np.testing.assert_allclose(float(fit.s0), 6.46e-33, rtol=1.5e-2)
    np.testing.assert_allclose(float(fit.s1), 6.29e-39, rtol=1e-2)


def test_fit_self_affine_round_trip_and_units():
    p = dict(s0=3e-33, s1=4e-39, q0=3e7, qmax=3e8)
    m = rs.self_affine_moments(**p)
    m0_nm = (m.m0 * 1e18).assign_attrs(units="nm2")
    fit = rs.fit_self_affine(m0=m0_nm, m2=m.m2, m4=m.m4, qmax=p["qmax"])
    np.testing.assert_allclose(float(fit.q0), p["q0"], rtol=1e-6)
    np.testing.assert_allclose(float(fit.s0), p["s0"], rtol=1e-6)
    np.testing.assert_allclose(float(fit.s1), p["s1"], rtol=1e-5)
    assert fit.s0.attrs["units"] == "m4" and fit.q0.attrs["units"] == "rad m-1"
    assert "fit_self_affine" in fit.attrs["history"]
    # the fitted parameters feed self_affine_psd directly (DataArrays with units)
    s = rs.self_affine_psd([1e7, 2e8], s0=fit.s0, s1=fit.s1, q0=fit.q0, qmax=fit.qmax)
    np.testing.assert_allclose(s.values[0], p["s0"], rtol=1e-6)


def test_fit_self_affine_sweep_backend(backend, no_compute):
    p = dict(s1=4e-39, q0=3e7, qmax=3e8)
    s0 = xr.DataArray([2e-33, 3e-33, 5e-33], dims="sample", attrs={"units": "m4"})
    m = rs.self_affine_moments(s0=s0, **p)
    m0 = backend(m.m0.assign_attrs(units="m2"), {"sample": 1})
    with no_compute():
        fit = rs.fit_self_affine(m0=m0, m2=m.m2, m4=m.m4, qmax=p["qmax"])
    assert fit.s0.dims == ("sample",)
    assert isinstance(fit.s0.data, type(m0.data))
    np.testing.assert_allclose(fit.s0.values, s0.values, rtol=1e-6)
    np.testing.assert_allclose(fit.q0.values, 3e7, rtol=1e-6)


def test_fit_self_affine_unreachable_raises():
    # m2^2 > m0 m4 is impossible for any PSD (Cauchy-Schwarz): no Eq. 37 solution
    with pytest.raises(ValueError, match="no Eq. 37 PSD"):
        rs.fit_self_affine(m0=1e-17, m2=0.5, m4=1e12, qmax=QMAX)
    out = rs.fit_self_affine(m0=1e-17, m2=0.5, m4=1e12, qmax=QMAX, tolerance=np.inf)
    assert abs(float(out.residual_m2)) > 1e-3
    with pytest.raises(ValueError, match="positive"):
        rs.fit_self_affine(m0=0.0, m2=0.5, m4=1e12, qmax=QMAX)


# ------------------------------------------------------------------ PSD estimation


def filtered_noise(shape, spacing, filt, rng, sigma=1e-9):
    """Periodic Gaussian map whose expected 2D PSD is sigma² Δ² |H(q)|² / (2π)²."""
    ny, nx = shape[-2:]
    w = rng.normal(size=shape) * sigma
    qx = 2 * np.pi * np.fft.fftfreq(nx, spacing)
    qy = 2 * np.pi * np.fft.fftfreq(ny, spacing)
    H = filt(np.hypot(qx[None, :], qy[:, None]))
    z = np.fft.ifft2(np.fft.fft2(w) * H).real
    expected = lambda q: sigma**2 * spacing**2 * filt(q) ** 2 / (2 * np.pi) ** 2  # noqa: E731
    return rs.testing.make_topography(z, spacing=spacing, periodic=True), expected


def lorentz(q):
    return 1.0 / (1.0 + (q / 5e7) ** 2)


@pytest.mark.parametrize("shape", [(32, 32), (33, 20), (15, 64)])
def test_parseval_machine_precision_odd_nonsquare(shape):
    h = rs.testing.make_topography(np.random.default_rng(6).normal(size=shape) * 1e-9, spacing=3e-9)
    s = rs.power_spectrum(h)
    assert s.dims == ("qy", "qx") and s.shape == shape
    rs.testing.assert_units(s, "m4")
    np.testing.assert_allclose(s.attrs["spacing_x"], 3e-9, rtol=1e-12)
    dqx, dqy = float(s.qx[1] - s.qx[0]), float(s.qy[1] - s.qy[0])
    np.testing.assert_allclose(float(s.sum()) * dqx * dqy, h.values.var(), rtol=1e-12)
    assert 0.0 in s.qx.values and 0.0 in s.qy.values
    assert np.all(np.diff(s.qx.values) > 0)
    np.testing.assert_allclose(dqx, 2 * np.pi / (shape[1] * 3e-9))
    m = rs.psd_moments(s)
    np.testing.assert_allclose(float(m.m0), h.values.var(), rtol=1e-12)


def test_known_spectrum_recovered_within_statistical_error():
    rng = np.random.default_rng(7)
    h, expected = filtered_noise((8, 128, 128), 5e-9, lorentz, rng)
    s = rs.average_psd(rs.power_spectrum(h), "dim_0")
    iso = rs.psd_isotropic(s)
    ratio = iso / expected(iso.q)
    # each periodogram value is exponential (std = mean); a ring average of n values over
    # 8 maps has relative std 1/sqrt(8 n)
    err = 1 / np.sqrt(8 * iso.n_samples)
    z = ((ratio - 1) / err).isel(q=slice(1, None))
    assert float(abs(z).max()) < 5
    assert abs(float(z.mean())) < 5 / np.sqrt(z.size)  # no bias overall
    # moments of the estimate against the expected density on the same grid
    qq = np.hypot(s.qx, s.qy)
    exp2d = expected(qq)
    area = float(s.qx[1] - s.qx[0]) * float(s.qy[1] - s.qy[0])
    np.testing.assert_allclose(float(rs.psd_moments(s).m2), float((exp2d * s.qx**2).sum()) * area,
                               rtol=0.05)


def test_window_keeps_variance_on_average():
    rng = np.random.default_rng(8)
    h, _ = filtered_noise((6, 64, 64), 5e-9, lorentz, rng)
    s = rs.power_spectrum(h, window="hann")
    assert s.attrs["window"] == "hann"
    m0 = rs.psd_moments(s).m0.mean()
    np.testing.assert_allclose(float(m0), float(h.var(("y", "x")).mean()), rtol=0.1)


def test_power_spectrum_stack_lazy_and_chunk_error(backend, no_compute):
    h, _ = filtered_noise((3, 16, 24), 5e-9, lorentz, np.random.default_rng(9))
    inp = backend(h, {"dim_0": 1})
    with no_compute():
        s = rs.power_spectrum(inp)
        iso = rs.psd_isotropic(s)
        m = rs.psd_moments(s, qmax=3e8)
    assert isinstance(s.data, type(inp.data)) and isinstance(iso.data, type(inp.data))
    ref = rs.power_spectrum(h)
    np.testing.assert_allclose(s.values, ref.values, rtol=1e-12, atol=0)
    np.testing.assert_allclose(iso.values, rs.psd_isotropic(ref).values, rtol=1e-12)
    np.testing.assert_allclose(m.m4.values, rs.psd_moments(ref, qmax=3e8).m4.values, rtol=1e-12)
    with pytest.raises(ValueError, match=r"\.chunk\(\{'x': -1, 'y': -1\}\)"):
        rs.power_spectrum(h.chunk({"x": 8, "y": 8}))


def test_psd_metadata_identical():
    h = rs.testing.make_topography(np.random.default_rng(10).normal(size=(8, 8)) * 1e-9)
    s = rs.power_spectrum(h)
    expected = xr.DataArray(
        s.values, dims=("qy", "qx"),
        coords={"qy": 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(8, 5e-9)),
                "qx": 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(8, 5e-9))},
        name="psd",
        attrs={**rs.conventions.ATTRS["psd"], "spacing_x": s.attrs["spacing_x"], "spacing_y": s.attrs["spacing_y"],
               "window": "None", "references": s.attrs["references"]},
    )
    rs.conventions.set_coord_attrs(expected)
    xr.testing.assert_identical(s, expected)


def test_bad_psd_inputs():
    h = rs.testing.make_topography(np.random.default_rng(11).normal(size=(16, 16)) * 1e-9)
    s = rs.power_spectrum(h)
    with pytest.raises(ValueError, match="negative"):
        rs.psd_moments(s - s.max())
    with pytest.raises(_units.UnitsError, match="units"):
        rs.psd_isotropic(s.assign_attrs(units="m3"))
    with pytest.raises(ValueError, match="ascending"):
        rs.psd_moments(s.isel(qx=slice(None, None, -1)))
    with pytest.raises(ValueError, match="at least 8"):
        rs.power_spectrum(h.isel(y=slice(0, 6)))


def test_isotropic_and_moments_of_eq37_grid():
    # 2D sampling of the Eq. 37 PSD on a fine grid: moments agree with the closed form
    p = dict(s0=5.5e-33, s1=5.5e-39, q0=21.2e6, qmax=289e6)
    n, sp = 512, 5e-9
    q1 = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(n, sp))
    qx = xr.DataArray(q1, dims="qx", coords={"qx": q1}, attrs={"units": "rad m-1"})
    qy = xr.DataArray(q1, dims="qy", coords={"qy": q1}, attrs={"units": "rad m-1"})
    s2 = rs.self_affine_psd(np.hypot(qy, qx).assign_attrs(units="rad m-1"), **p)
    s2 = s2.assign_attrs(units="m4")
    exact = rs.self_affine_moments(**p)
    m2d = rs.psd_moments(s2)
    iso = rs.psd_isotropic(s2)
    miso = rs.psd_moments(iso)
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(float(m2d[k]), float(exact[k]), rtol=0.02)
        np.testing.assert_allclose(float(miso[k]), float(exact[k]), rtol=0.03)
    # cutting at q0 keeps only the plateau: pi q0^2 s0 within the grid's disc error
    np.testing.assert_allclose(float(rs.psd_moments(s2, qmax=p["q0"]).m0),
                               np.pi * p["q0"] ** 2 * p["s0"], rtol=0.05)


# ------------------------------------------------------------------ sub-maps, cutoff, interp


def test_submap_schemes_and_eq32():
    h, expected = filtered_noise((3, 128, 128), 5e-9, lorentz, np.random.default_rng(12))
    outs = {n: rs.submap_psd(h, n=n) for n in (1, 4, 16)}
    assert outs[1].shape == (128, 128) and outs[4].shape == (64, 64) and outs[16].shape == (32, 32)
    assert outs[16].attrs["n_averaged"] == 48 and outs[16].attrs["n_submaps"] == 16
    m0 = [float(rs.psd_moments(o).m0) for o in outs.values()]
    # sub-maps lose the longest wavelengths (their own means): m0 decreases slightly
    assert m0[0] >= m0[1] >= m0[2] > 0.7 * m0[0]
    # with a window, sub-map PSDs estimate the same density (rings well inside all grids)
    for n in (1, 4, 16):
        iso = rs.psd_isotropic(rs.submap_psd(h, n=n, window="hann"))
        for q in (2e8, 4e8):
            np.testing.assert_allclose(float(iso.interp(q=q)), float(expected(q)), rtol=0.3)
    # without one, tiles cut from a map are not periodic: edge leakage biases the high-q
    # tail upwards, the more the smaller the tiles (a bias Eq. 32 does not see)
    tail = [float(rs.psd_isotropic(outs[n]).interp(q=4e8)) / float(expected(4e8)) for n in (1, 16)]
    assert tail[0] < 1.3 < 1.6 < tail[1]
    chk = rs.submap_variance_check(h, n=4)
    assert chk.m0_submap.shape == (3, 4)
    e = np.sqrt(((chk.m0_submap.values - float(chk.m0)) ** 2).mean()) / float(chk.m0)
    np.testing.assert_allclose(float(chk.relative_std), e, rtol=1e-12)
    assert bool(chk.representative) == (e < 0.03)
    with pytest.raises(ValueError, match="perfect square"):
        rs.submap_psd(h, n=3)
    with pytest.raises(ValueError, match="8 x 8"):
        rs.submap_psd(h, n=400)


def test_choose_cutoff_recovers_known_qmax():
    h, _ = filtered_noise((64, 64), 5e-9, lorentz, np.random.default_rng(13))
    s = rs.power_spectrum(h)
    qtrue = 3.0e8
    target = rs.psd_moments(s, qmax=qtrue)
    cut = rs.choose_cutoff(s, target)
    rings = np.unique(np.hypot(*np.meshgrid(s.qx, s.qy)))
    q_expected = rings[rings <= qtrue].max()
    np.testing.assert_allclose(float(cut.qmax), q_expected, rtol=1e-12)
    for k in ("m0", "m2", "m4"):
        assert abs(float(cut[f"residual_{k}"])) < 1e-12
    assert cut.qmax.attrs["units"] == "rad m-1"
    # on a map smooth at the pixel scale, spline (spatial) and spectral moments agree and the
    # cutoff matches them to < 1 %
    smooth, _ = filtered_noise((128, 128), 5e-9, lambda q: np.exp(-((q / 3e7) ** 2)),
                               np.random.default_rng(13))
    spatial = rs.roughness_moments(smooth)
    spectral = rs.roughness_moments(smooth, method="spectral")
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(float(spatial[k]), float(spectral[k]), rtol=0.01)
    cut2 = rs.choose_cutoff(rs.power_spectrum(smooth), spatial)
    assert abs(float(cut2.residual_m4)) < 0.01 and abs(float(cut2.residual_m2)) < 0.01
    # with power up to the Nyquist wave number, cubic-spline curvatures exceed the spectral
    # m4 (spline response > q^2 near Nyquist): no cutoff can match, and the residual says so
    cut3 = rs.choose_cutoff(s, rs.roughness_moments(h))
    assert float(cut3.residual_m4) < -0.2


def test_interpolate_psd_preserves_moments():
    # a 1.28 µm (256 px) estimate drives a 10.24 µm (2048 px) grid (paper §4.2.1)
    h, _ = filtered_noise((4, 256, 256), 5e-9, lorentz, np.random.default_rng(14))
    s = rs.average_psd(rs.power_spectrum(h), "dim_0")
    big = rs.interpolate_psd(s, shape=(2048, 2048))
    assert big.shape == (2048, 2048)
    np.testing.assert_allclose(big.attrs["spacing_x"], 5e-9, rtol=1e-12)
    np.testing.assert_allclose(float(big.qx[1] - big.qx[0]), 2 * np.pi / 10.24e-6)
    before, after = rs.psd_moments(s), rs.psd_moments(big)
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(float(after[k]), float(before[k]), rtol=0.01)
    assert float(big.min()) >= 0
    # isotropic input goes through isotropic_to_2d
    iso = rs.self_affine_psd(np.linspace(0, 7e8, 3000), s0=5.5e-33, s1=5.5e-39, q0=21.2e6,
                             qmax=289e6)
    big2 = rs.interpolate_psd(iso, shape=(256, 256), spacing=5e-9)
    assert big2.dims == ("qy", "qx")


def test_psd_summary_and_plots(tmp_path):
    import matplotlib.pyplot as plt

    from roughstick.plotting import plot_height, plot_psd_schemes, plot_self_affine_psd

    h, _ = filtered_noise((2, 64, 64), 5e-9, lorentz, np.random.default_rng(15))
    ds = rs.psd_summary(h, n=4)
    assert ds.psd.dims == ("qy", "qx") and ds.psd_isotropic.dims == ("q",)
    np.testing.assert_allclose(float(ds.spatial_m0), float(h.var(("y", "x")).mean()), rtol=1e-12)
    fixed = rs.psd_summary(h, n=4, qmax=3e8)
    np.testing.assert_allclose(float(fixed.residual_m2), float(fixed.m2 / fixed.spatial_m2 - 1))
    rs.io.netcdf.check_cf(ds) if hasattr(rs.io.netcdf, "check_cf") else None
    fig, axes = plt.subplots(1, 3)
    plot_height(h.isel(dim_0=0), ax=axes[0])
    plot_psd_schemes({"4": ds.psd, "iso": ds.psd_isotropic}, ax=axes[1], qmax=3e8, title="t")
    fit = rs.fit_self_affine(m0=1.57e-17, m2=0.04, m4=5.08e14, qmax=QMAX)
    plot_self_affine_psd({"fit": fit}, measured={"h": ds.psd}, ax=axes[2])
    fig.savefig(tmp_path / "f.png")
    plt.close(fig)


@pytest.mark.slow
def test_demo_step_quick(tmp_path):
    from roughstick.demos import s20_topography

    files = s20_topography.run(tmp_path, quick=True)
    names = {f.name for f in files}
    assert {"topography_statistics.csv", "topography_statistics.nc", "fig12_psd_schemes.png",
            "fig19_self_affine_psd.png", "table4_self_affine.csv"} <= names
    text = (tmp_path / "table4_self_affine.csv").read_text()
    assert "21.19" in text and "19.49" in text and "19.4" in text


def test_cli_psd(tmp_path, capsys):
    from roughstick.cli import main

    rng = np.random.default_rng(16)
    for i in range(2):
        h, _ = filtered_noise((64, 64), 5e-9, lorentz, rng)
        np.save(tmp_path / f"m{i}.npy", h.values * 1e9)
    out = tmp_path / "psd.nc"
    args = ["psd", str(tmp_path / "m0.npy"), str(tmp_path / "m1.npy"), "--spacing", "5 nm",
            "--units", "nm", "--submaps", "4", "--out", str(out)]
    assert main(args) == 0
    assert "wrote" in capsys.readouterr().out
    ds = xr.open_dataset(out)
    assert ds.psd.dims == ("qy", "qx") and ds.attrs["n_maps"] == 2
    assert "roughstick psd" in ds.attrs["history"]
    ref = rs.psd_summary(
        xr.concat([rs.level(rs.read_afm(tmp_path / f"m{i}.npy", spacing=5e-9, units="nm"))
                   for i in range(2)], dim="map"), n=4)
    np.testing.assert_allclose(ds.psd.values, ref.psd.values, rtol=1e-10)
    ds.close()
    np.save(tmp_path / "small.npy", np.zeros((32, 32)))
    assert main(["psd", str(tmp_path / "m0.npy"), str(tmp_path / "small.npy"), "--spacing",
                 "5 nm", "--units", "nm", "--out", str(tmp_path / "x.nc")]) == 1
    assert "same size" in capsys.readouterr().err


def test_isotropic_to_2d_converts_units():
    iso = xr.DataArray([1e4, 1e2, 1.0], dims="q", coords={"q": [0.0, 1e8, 2e8]},
                       attrs={"units": "nm4"})
    s = rs.isotropic_to_2d(iso, qx=[0.0, 1e8], qy=[0.0])
    np.testing.assert_allclose(s.values, [[1e-32, 1e-34]], rtol=1e-12)
    assert s.attrs["units"] == "m4"


def test_submap_psd_accepts_a_single_dim_name():
    # a plain string names one dimension (it used to be split into characters)
    rng = np.random.default_rng(3)
    h = xr.concat(
        [rs.testing.make_topography(rng.normal(size=(32, 32)) * 1e-9, spacing=5e-9) for _ in range(2)], "map"
    )
    by_name = rs.submap_psd(h, n=4, average_dims="map")
    by_list = rs.submap_psd(h, n=4, average_dims=["map"])
    xr.testing.assert_identical(by_name, by_list)
    assert by_name.attrs["n_averaged"] == 8
