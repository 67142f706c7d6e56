"""Tests of roughstick.surface.spectrum and .summary: PSD estimation, averaging, sub-maps, interpolation."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from conftest import filtered_noise, lorentz
from roughstick._core import units as _units

QMAX = 289e6  # rad/m (paper: 289 rad/µm)


@pytest.mark.parametrize("shape", [(32, 32), (33, 20), (15, 64)])
def test_parseval_machine_precision_odd_nonsquare(shape):
    h = rs.testing.make_topography(np.random.default_rng(6).normal(size=shape) * 1e-9, spacing=3e-9)
    s = rs.surface.power_spectrum(h, window=None)  # the estimator's normalisation (no window: exact)
    assert s.dims == ("qy", "qx") and s.shape == shape
    rs.testing.assert_units(s, "m4")
    np.testing.assert_allclose(s.attrs["spacing_x"], 3e-9, rtol=1e-12)
    dqx, dqy = float(s.qx[1] - s.qx[0]), float(s.qy[1] - s.qy[0])
    np.testing.assert_allclose(float(s.sum()) * dqx * dqy, h.values.var(), rtol=1e-12)
    assert 0.0 in s.qx.values and 0.0 in s.qy.values
    assert np.all(np.diff(s.qx.values) > 0)
    np.testing.assert_allclose(dqx, 2 * np.pi / (shape[1] * 3e-9))
    m = rs.surface.psd_moments(s)
    np.testing.assert_allclose(float(m.m0), h.values.var(), rtol=1e-12)


def test_known_spectrum_recovered_within_statistical_error():
    rng = np.random.default_rng(7)
    h, expected = filtered_noise((8, 128, 128), 5e-9, lorentz, rng)
    s = rs.surface.average_psd(rs.surface.power_spectrum(h), "dim_0")
    iso = rs.surface.psd_isotropic(s)
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
    np.testing.assert_allclose(float(rs.surface.psd_moments(s).m2), float((exp2d * s.qx**2).sum()) * area,
                               rtol=0.05)


def test_window_keeps_variance_on_average():
    rng = np.random.default_rng(8)
    h, _ = filtered_noise((6, 64, 64), 5e-9, lorentz, rng)
    s = rs.surface.power_spectrum(h, window="hann")
    assert s.attrs["window"] == "hann"
    m0 = rs.surface.psd_moments(s).m0.mean()
    np.testing.assert_allclose(float(m0), float(h.var(("y", "x")).mean()), rtol=0.1)


def test_power_spectrum_stack_lazy_and_chunk_error(backend, no_compute):
    h, _ = filtered_noise((3, 16, 24), 5e-9, lorentz, np.random.default_rng(9))
    inp = backend(h, {"dim_0": 1})
    with no_compute():
        s = rs.surface.power_spectrum(inp)
        iso = rs.surface.psd_isotropic(s)
        m = rs.surface.psd_moments(s, qmax=3e8)
    assert isinstance(s.data, type(inp.data)) and isinstance(iso.data, type(inp.data))
    ref = rs.surface.power_spectrum(h)
    np.testing.assert_allclose(s.values, ref.values, rtol=1e-12, atol=0)
    np.testing.assert_allclose(iso.values, rs.surface.psd_isotropic(ref).values, rtol=1e-12)
    np.testing.assert_allclose(m.m4.values, rs.surface.psd_moments(ref, qmax=3e8).m4.values, rtol=1e-12)
    with pytest.raises(ValueError, match=r"\.chunk\(\{'x': -1, 'y': -1\}\)"):
        rs.surface.power_spectrum(h.chunk({"x": 8, "y": 8}))


def test_psd_metadata_identical():
    h = rs.testing.make_topography(np.random.default_rng(10).normal(size=(8, 8)) * 1e-9)
    s = rs.surface.power_spectrum(h, window="none")
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
    s = rs.surface.power_spectrum(h)
    with pytest.raises(ValueError, match="negative"):
        rs.surface.psd_moments(s - s.max())
    with pytest.raises(_units.UnitsError, match="units"):
        rs.surface.psd_isotropic(s.assign_attrs(units="m3"))
    with pytest.raises(ValueError, match="ascending"):
        rs.surface.psd_moments(s.isel(qx=slice(None, None, -1)))
    with pytest.raises(ValueError, match="at least 8"):
        rs.surface.power_spectrum(h.isel(y=slice(0, 6)))


def test_submap_schemes_and_eq32():
    h, expected = filtered_noise((3, 128, 128), 5e-9, lorentz, np.random.default_rng(12))
    outs = {n: rs.surface.submap_psd(h, n=n, window=None) for n in (1, 4, 16)}  # the paper's Eq. 31
    assert outs[1].shape == (128, 128) and outs[4].shape == (64, 64) and outs[16].shape == (32, 32)
    assert outs[16].attrs["n_averaged"] == 48 and outs[16].attrs["n_submaps"] == 16
    m0 = [float(rs.surface.psd_moments(o).m0) for o in outs.values()]
    # sub-maps lose the longest wavelengths (their own means): m0 decreases slightly
    assert m0[0] >= m0[1] >= m0[2] > 0.7 * m0[0]
    # with a window, sub-map PSDs estimate the same density (rings well inside all grids)
    for n in (1, 4, 16):
        iso = rs.surface.psd_isotropic(rs.surface.submap_psd(h, n=n, window="hann"))
        for q in (2e8, 4e8):
            np.testing.assert_allclose(float(iso.interp(q=q)), float(expected(q)), rtol=0.3)
    # without one, tiles cut from a map are not periodic: edge leakage biases the high-q
    # tail upwards, the more the smaller the tiles (a bias Eq. 32 does not see)
    tail = [float(rs.surface.psd_isotropic(outs[n]).interp(q=4e8)) / float(expected(4e8)) for n in (1, 16)]
    assert tail[0] < 1.3 < 1.6 < tail[1]
    chk = rs.surface.submap_variance_check(h, n=4)
    assert chk.m0_submap.shape == (3, 4)
    e = np.sqrt(((chk.m0_submap.values - float(chk.m0)) ** 2).mean()) / float(chk.m0)
    np.testing.assert_allclose(float(chk.relative_std), e, rtol=1e-12)
    assert bool(chk.representative) == (e < 0.03)
    with pytest.raises(ValueError, match="perfect square"):
        rs.surface.submap_psd(h, n=3)
    with pytest.raises(ValueError, match="8 x 8"):
        rs.surface.submap_psd(h, n=400)


def test_interpolate_psd_preserves_moments():
    # a 1.28 µm (256 px) estimate drives a 10.24 µm (2048 px) grid (paper §4.2.1)
    h, _ = filtered_noise((4, 256, 256), 5e-9, lorentz, np.random.default_rng(14))
    s = rs.surface.average_psd(rs.surface.power_spectrum(h), "dim_0")
    big = rs.surface.interpolate_psd(s, shape=(2048, 2048))
    assert big.shape == (2048, 2048)
    np.testing.assert_allclose(big.attrs["spacing_x"], 5e-9, rtol=1e-12)
    np.testing.assert_allclose(float(big.qx[1] - big.qx[0]), 2 * np.pi / 10.24e-6)
    before, after = rs.surface.psd_moments(s), rs.surface.psd_moments(big)
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(float(after[k]), float(before[k]), rtol=0.01)
    assert float(big.min()) >= 0
    # isotropic input goes through isotropic_to_2d
    iso = rs.surface.self_affine_psd(np.linspace(0, 7e8, 3000), s0=5.5e-33, s1=5.5e-39, q0=21.2e6,
                             qmax=289e6)
    big2 = rs.surface.interpolate_psd(iso, shape=(256, 256), spacing=5e-9)
    assert big2.dims == ("qy", "qx")


def test_psd_summary_and_plots(tmp_path):
    import matplotlib.pyplot as plt

    from roughstick.plotting import plot_height, plot_psd_schemes, plot_self_affine_psd

    h, _ = filtered_noise((2, 64, 64), 5e-9, lorentz, np.random.default_rng(15))
    ds = rs.surface.psd_summary(h, n=4)
    assert ds.psd.dims == ("qy", "qx") and ds.psd_isotropic.dims == ("q",)
    np.testing.assert_allclose(float(ds.spatial_m0), float(h.var(("y", "x")).mean()), rtol=1e-12)
    fixed = rs.surface.psd_summary(h, n=4, qmax=3e8)
    np.testing.assert_allclose(float(fixed.residual_m2), float(fixed.m2 / fixed.spatial_m2 - 1))
    rs.io.netcdf.check_cf(ds) if hasattr(rs.io.netcdf, "check_cf") else None
    fig, axes = plt.subplots(1, 3)
    plot_height(h.isel(dim_0=0), ax=axes[0])
    plot_psd_schemes({"4": ds.psd, "iso": ds.psd_isotropic}, ax=axes[1], qmax=3e8, title="t")
    fit = rs.surface.fit_self_affine(m0=1.57e-17, m2=0.04, m4=5.08e14, qmax=QMAX)
    plot_self_affine_psd({"fit": fit}, measured={"h": ds.psd}, ax=axes[2])
    fig.savefig(tmp_path / "f.png")
    plt.close(fig)


def test_isotropic_to_2d_converts_units():
    iso = xr.DataArray([1e4, 1e2, 1.0], dims="q", coords={"q": [0.0, 1e8, 2e8]},
                       attrs={"units": "nm4"})
    s = rs.surface.isotropic_to_2d(iso, qx=[0.0, 1e8], qy=[0.0])
    np.testing.assert_allclose(s.values, [[1e-32, 1e-34]], rtol=1e-12)
    assert s.attrs["units"] == "m4"


def test_submap_psd_accepts_a_single_dim_name():
    # a plain string names one dimension (it used to be split into characters)
    rng = np.random.default_rng(3)
    h = xr.concat(
        [rs.testing.make_topography(rng.normal(size=(32, 32)) * 1e-9, spacing=5e-9) for _ in range(2)], "map"
    )
    by_name = rs.surface.submap_psd(h, n=4, average_dims="map")
    by_list = rs.surface.submap_psd(h, n=4, average_dims=["map"])
    rs.testing.assert_same_result(by_name, by_list)
    assert by_name.attrs["n_averaged"] == 8


def test_default_window_for_measured_scans():
    """Issue 16 item 4: without a window the edge step of a non-periodic scan leaks power to high
    q and inflates m2 and m4; the default ("auto") is Hann on non-periodic maps and no window on
    periodic ones (Parseval exact). Truth: the periodic surface the crops are cut from
    (benchmarks/psd_window.py measures all families and crop sizes)."""
    full = rs.datasets.surface_family("smooth", shape=(512, 512), seed=5)
    assert full.attrs["periodic"] == 1
    truth = rs.surface.psd_moments(rs.surface.power_spectrum(full), qmax=289e6)
    assert rs.surface.power_spectrum(full).attrs["window"] == "None"  # periodic: no window, exact
    np.testing.assert_allclose(float(truth.m0), float(full.var()), rtol=1e-10)
    rng = np.random.default_rng(1)
    err = {"none": [], "auto": []}
    for _ in range(6):
        iy, ix = rng.integers(0, 512 - 128, size=2)
        crop = full.isel(y=slice(iy, iy + 128), x=slice(ix, ix + 128)).assign_attrs(periodic=0)
        for w in err:
            s = rs.surface.power_spectrum(crop, window=w)
            assert s.attrs["window"] == ("hann" if w == "auto" else "None")
            m = rs.surface.psd_moments(s, qmax=289e6)
            err[w].append([float(m[k] / truth[k]) - 1 for k in ("m2", "m4")])
    none, auto = np.median(err["none"], axis=0), np.median(err["auto"], axis=0)
    # measured (benchmarks/psd_window.py, smooth 128²): none +36 % / +70 %, Hann +7 % / +5 %
    assert none[0] > 0.2 and none[1] > 0.4
    assert abs(auto[0]) < 0.12 and abs(auto[1]) < 0.12
    # a map without the attribute is treated as measured (not periodic)
    unmarked = crop.copy()
    del unmarked.attrs["periodic"]
    assert rs.surface.power_spectrum(unmarked).attrs["window"] == "hann"
    # sub-maps of a periodic map are not periodic: Hann; one sub-map of it: none
    assert rs.surface.submap_psd(full, n=4).attrs["window"] == "hann"
    assert rs.surface.submap_psd(full, n=1).attrs["window"] == "None"
