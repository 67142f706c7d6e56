"""Tests of roughstick.generate (paper Eqs. 33-35): statistics, reproducibility, laziness, bad input.

Statistical tests use fixed seeds and bounds derived from the exact sampling distributions of the
spectral representation: with Rayleigh (complex Gaussian) amplitudes every independent mode's
periodogram is P_k |xi|^2 with |xi|^2 ~ Exp(1) (chi2_1 for the self-conjugate modes), so a moment
estimate sum_k w_k P_k |xi_k|^2 over one surface has variance 2 sum_k w_k^2 P_k^2 (full plane).
"""

from __future__ import annotations

import dask
import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy import stats

import roughstick as rs
from roughstick._core.dask import is_lazy
from roughstick.surface.generate import generate_surfaces, surface_filter
from roughstick.testing import raise_if_dask_computes

SPACING = 5e-9
TABLE3 = {
    "S1": {"m0": 15.7e-18, "m2": 0.040, "m4": 5.08e-4 * 1e18},
    "S2": {"m0": 4.32e-18, "m2": 0.021, "m4": 3.99e-4 * 1e18},
}


def _self_affine(name):
    fit = rs.surface.fit_self_affine(**TABLE3[name], qmax=289e6)
    p = {k: float(fit[k]) for k in ("s0", "s1", "q0", "qmax")}

    def psd(q):
        q = np.asarray(q, dtype=float)
        return rs.surface.self_affine_psd(q.ravel(), **p).values.reshape(q.shape)

    return psd


S1 = _self_affine("S1")
S2 = _self_affine("S2")


def _grid_power(psd, shape, spacing=SPACING):
    """Mode powers P = s dqx dqy on the full FFT grid (fft order) and the qx grid."""
    f = surface_filter(psd, shape=shape, spacing=spacing)
    ny, nx = f.shape
    dq2 = (2 * np.pi) ** 2 / (ny * nx * spacing**2)
    P = np.fft.ifftshift(f.values) * dq2
    qx = np.fft.ifftshift(f.qx.values)[None, :]
    return P, qx


def _periodogram(z):
    """|fft2(z)|^2 / N^2 per realization: the power of each mode (sums to mean(z^2))."""
    n = z.shape[-1] * z.shape[-2]
    return np.abs(np.fft.fft2(z)) ** 2 / n**2


def _psd_2d(z, spacing):
    """2D PSD of one map, architecture contract formula, centred coords."""
    ny, nx = z.shape
    Lx, Ly = nx * spacing, ny * spacing
    s = np.abs(np.fft.fft2(z)) ** 2 * spacing**4 / ((2 * np.pi) ** 2 * Lx * Ly)
    qy = np.fft.fftshift(2 * np.pi * np.fft.fftfreq(ny, spacing))
    qx = np.fft.fftshift(2 * np.pi * np.fft.fftfreq(nx, spacing))
    return xr.DataArray(np.fft.fftshift(s), dims=("qy", "qx"), coords={"qy": qy, "qx": qx},
                        attrs={"units": "m4"}, name="psd")


def _independent_modes(ny, nx):
    """Mask of one representative per Hermitian pair (plus self-conjugate modes), and of the
    self-conjugate modes."""
    ky = np.arange(ny)[:, None]
    kx = np.arange(nx)[None, :]
    mky, mkx = (-ky) % ny, (-kx) % nx
    selfc = (mky == ky) & (mkx == kx)
    rep = (ky * nx + kx) <= (mky * nx + mkx)
    return rep, selfc


# --------------------------------------------------------------------------------------------
# normalisation: exact with fixed amplitudes
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("shape", [(64, 64), (31, 47), (33, 50), (50, 33), (2, 3)])
def test_fixed_amplitude_periodogram_is_the_target_exactly(shape):
    """|Z_k|^2 = P_k for every mode: normalisation (sum = variance) and Hermitian symmetry."""
    P, _ = _grid_power(S1, shape, spacing=20e-9)
    h = generate_surfaces(S1, n=3, shape=shape, spacing=20e-9, seed=7, amplitude="fixed")
    z = h.values
    per = _periodogram(z)
    np.testing.assert_allclose(per, np.broadcast_to(P, per.shape), rtol=1e-9, atol=1e-12 * P.max())
    np.testing.assert_allclose((z**2).mean(axis=(1, 2)), P.sum(), rtol=1e-10)


def test_filter_sums_to_table3_moments():
    """The discrete grid used for S1 and S2 reproduces the Table 3 PSD moments (Riemann sums)."""
    for name, psd in (("S1", S1), ("S2", S2)):
        P, qx = _grid_power(psd, (512, 512))
        t = TABLE3[name]
        np.testing.assert_allclose(P.sum(), t["m0"], rtol=2e-3)
        np.testing.assert_allclose((P * qx**2).sum(), t["m2"], rtol=2e-3)
        np.testing.assert_allclose((P * qx**4).sum(), t["m4"], rtol=2e-3)


# --------------------------------------------------------------------------------------------
# statistics with Rayleigh (Gaussian) amplitudes
# --------------------------------------------------------------------------------------------
def _mode_pvalues(I_mean, P, n, ny, nx):
    """Two-sided p-values of the ensemble-mean periodogram at every independent mode."""
    rep, selfc = _independent_modes(ny, nx)
    use = rep & (P > 0)
    r = I_mean[use] / P[use] * n  # ~ Gamma(n, 1) for pairs, chi2_n = Gamma(n/2, 2) self-conj.
    sc = selfc[use]
    cdf = np.where(sc, stats.gamma.cdf(r, n / 2, scale=2), stats.gamma.cdf(r, n))
    sf = np.where(sc, stats.gamma.sf(r, n / 2, scale=2), stats.gamma.sf(r, n))
    return 2 * np.minimum(cdf, sf), use.sum()


@pytest.mark.parametrize("shape", [(24, 31), (20, 20)])
def test_mean_psd_matches_target_at_every_mode(shape):
    """Ensemble-mean periodogram vs target at every independent wave vector: exact Gamma
    distribution per mode, Bonferroni bound at family-wise alpha = 1e-3."""
    ny, nx = shape
    n = 400
    P, _ = _grid_power(S2, shape, spacing=10e-9)
    z = generate_surfaces(S2, n=n, shape=shape, spacing=10e-9, seed=11).values
    I_mean = _periodogram(z).mean(axis=0)
    p, m = _mode_pvalues(I_mean, P, n, ny, nx)
    assert m > 100
    assert p.min() > 1e-3 / m, f"mode with p = {p.min():.2g} (bound {1e-3 / m:.2g})"
    # the same test rejects a target that is 10 % off: it can fail
    p_wrong, _ = _mode_pvalues(I_mean, 1.1 * P, n, ny, nx)
    combined = stats.combine_pvalues(p_wrong).pvalue
    assert combined < 1e-6
    assert stats.combine_pvalues(p).pvalue > 1e-3


@pytest.mark.parametrize("name", ["S1", "S2"])
def test_ensemble_moments_match_table3(name):
    """m0, m2, m4 of the ensemble (variances of height, spectral slope and curvature) match the
    grid moments within 4 sampling standard errors, and the grid moments match Table 3."""
    psd = S1 if name == "S1" else S2
    shape, n = (128, 128), 48
    P, qx = _grid_power(psd, shape)
    z = generate_surfaces(psd, n=n, shape=shape, spacing=SPACING, seed=5, chunks=16).values
    Z = np.fft.fft2(z)
    slope = np.fft.ifft2(1j * qx * Z).real
    curv = np.fft.ifft2(-(qx**2) * Z).real
    for w, est, key in ((1.0, z, "m0"), (qx**2, slope, "m2"), (qx**4, curv, "m4")):
        target = (w * P).sum()
        se = np.sqrt(2 * ((w * P) ** 2).sum() / n)
        got = (est**2).mean()
        assert abs(got - target) < 4 * se, (key, got, target, se)
        np.testing.assert_allclose(target, TABLE3[name][key], rtol=0.02)


def test_finite_difference_slope_variance_agrees():
    """Real-space check independent of the FFT: the variance of forward differences along x and
    y equals sum P (2 sin(q dx/2)/dx)^2 within sampling error (orientation of x and y)."""
    psd = lambda q: np.where(q < 4e8, 1e-34 * (1 + q / 1e8) ** -3, 0.0)  # noqa: E731
    shape, n, d = (40, 56), 200, 4e-9
    h = generate_surfaces(psd, n=n, shape=shape, spacing=d, seed=3).values
    P, qx = _grid_power(psd, shape, spacing=d)
    f = surface_filter(psd, shape=shape, spacing=d)
    qy = np.fft.ifftshift(f.qy.values)[:, None]
    for axis, q in ((2, qx), (1, qy)):
        diff = (np.roll(h, -1, axis=axis) - h) / d
        w = (2 * np.sin(q * d / 2) / d) ** 2 * np.ones_like(P)
        target = (w * P).sum()
        se = np.sqrt(2 * ((w * P) ** 2).sum() / n)
        assert abs((diff**2).mean() - target) < 4 * se


def test_heights_are_gaussian():
    """KS test of the heights at two distant pixels over 2000 independent realizations against
    N(0, sum P); the same test rejects fixed-amplitude surfaces of a one-mode PSD (arcsine law)."""
    shape = (16, 16)
    P, _ = _grid_power(S2, shape, spacing=20e-9)
    sd = np.sqrt(P.sum())
    z = generate_surfaces(S2, n=2000, shape=shape, spacing=20e-9, seed=21).values
    for iy, ix in ((0, 0), (8, 8)):
        assert stats.kstest(z[:, iy, ix] / sd, "norm").pvalue > 1e-3
    s = xr.DataArray(np.zeros((16, 16)), dims=("qy", "qx"), attrs={"units": "m4"},
                     coords={"qy": np.fft.fftshift(2 * np.pi * np.fft.fftfreq(16, 20e-9)),
                             "qx": np.fft.fftshift(2 * np.pi * np.fft.fftfreq(16, 20e-9))})
    s[8, 10] = s[8, 6] = 1e-32  # one wave along x
    zf = generate_surfaces(s, n=2000, shape=shape, spacing=20e-9, seed=21, amplitude="fixed").values
    assert stats.kstest(zf[:, 0, 0] / zf[:, 0, 0].std(), "norm").pvalue < 1e-6
    # orientation: a wave along x does not vary along y
    np.testing.assert_allclose(zf[0], np.broadcast_to(zf[0, :1, :], (16, 16)), atol=1e-25)


# --------------------------------------------------------------------------------------------
# reproducibility and laziness
# --------------------------------------------------------------------------------------------
_REF = {}


def _reference():
    if "ref" not in _REF:
        _REF["ref"] = generate_surfaces(S1, n=7, shape=(12, 18), spacing=20e-9, seed=99,
                                        chunks=1).values
    return _REF["ref"]


@settings(max_examples=15, deadline=None, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.integers(1, 7), min_size=1, max_size=7).filter(lambda c: sum(c) >= 7))
def test_chunk_invariance(parts):
    """Any chunking of the realizations gives bit-identical surfaces."""
    chunks, total = [], 0
    for c in parts:
        c = min(c, 7 - total)
        if c > 0:
            chunks.append(c)
            total += c
    h = generate_surfaces(S1, n=7, shape=(12, 18), spacing=20e-9, seed=99, chunks=tuple(chunks))
    assert h.chunks[0] == tuple(chunks)
    np.testing.assert_array_equal(h.values, _reference())


def test_order_workers_and_single_realization():
    ref = _reference()
    h = generate_surfaces(S1, n=7, shape=(12, 18), spacing=20e-9, seed=99, chunks=2)
    with dask.config.set(scheduler="threads", num_workers=2):
        np.testing.assert_array_equal(h.values, ref)
    # evaluation in reverse order, one realization at a time
    for k in reversed(range(7)):
        np.testing.assert_array_equal(h.isel(realization=k).values, ref[k])
    one = generate_surfaces(S1, realizations=[5], shape=(12, 18), spacing=20e-9, seed=99)
    assert one.realization.values.tolist() == [5]
    np.testing.assert_array_equal(one.values[0], ref[5])
    other = generate_surfaces(S1, n=7, shape=(12, 18), spacing=20e-9, seed=100).values
    assert not np.array_equal(other, ref)


def test_lazy_until_asked():
    with raise_if_dask_computes():
        h = generate_surfaces(S1, n=4, shape=(16, 16), spacing=10e-9, seed=1, chunks=2)
        reduced = (h**2).mean(("y", "x"))
    assert is_lazy(h) and is_lazy(reduced)
    assert h.chunks == ((2, 2), (16,), (16,))
    # a dask-backed PSD stays lazy too
    z = generate_surfaces(S1, n=1, shape=(16, 16), spacing=10e-9, seed=2, amplitude="fixed").values[0]
    psd = _psd_2d(z, 10e-9).chunk()
    with raise_if_dask_computes():
        h2 = generate_surfaces(psd, n=3, spacing=10e-9, seed=1, amplitude="fixed")
    np.testing.assert_allclose((h2.values**2).mean(axis=(1, 2)), (z**2).mean(), rtol=1e-10)
    assert reduced.compute().shape == (4,)


def test_attributes_and_seed_record():
    h = generate_surfaces(S2, n=2, shape=(8, 10), spacing=5e-9, seed=None)
    assert h.name == "height" and h.dims == ("realization", "y", "x")
    assert h.attrs["units"] == "m" and h.attrs["periodic"] == 1
    assert h.realization.values.tolist() == [0, 1]
    np.testing.assert_allclose(h.x.values, (np.arange(10) + 0.5) * 5e-9)
    again = generate_surfaces(S2, n=2, shape=(8, 10), spacing=5e-9, seed=h.attrs["seed"])
    np.testing.assert_array_equal(h.values, again.values)
    assert "generate_surfaces" in h.attrs["history"]


# --------------------------------------------------------------------------------------------
# domains and PSD inputs
# --------------------------------------------------------------------------------------------
def test_rectangular_cantilever_domain():
    """2.62 um x 30 um at 5 nm: 524 x 6000 pixels (not powers of two)."""
    h = generate_surfaces(S1, n=1, size=(2.62e-6, 30e-6), spacing=5e-9, seed=4)
    assert h.shape == (1, 524, 6000)
    P, qx = _grid_power(S1, (524, 6000))
    got = (h.values**2).mean()
    se = np.sqrt(2 * (P**2).sum())
    assert abs(got - P.sum()) < 4 * se
    np.testing.assert_allclose(P.sum(), TABLE3["S1"]["m0"], rtol=0.01)


def test_same_grid_2d_psd_is_used_exactly_and_larger_maps_interpolate():
    z = generate_surfaces(S2, n=1, shape=(32, 32), spacing=10e-9, seed=8).values[0]
    psd = _psd_2d(z, 10e-9)
    m0 = float(psd.sum()) * (2 * np.pi / (32 * 10e-9)) ** 2
    np.testing.assert_allclose(m0, (z**2).mean(), rtol=1e-12)  # Parseval of the contract
    same = generate_surfaces(psd, n=2, shape=(32, 32), spacing=10e-9, seed=1, amplitude="fixed").values
    np.testing.assert_allclose(_periodogram(same)[0], _periodogram(z[None])[0], rtol=1e-8,
                               atol=1e-12 * m0)
    # a surface 4x larger than the map the PSD came from: interpolated PSD, variance conserved
    with pytest.warns(rs.surface.ExtrapolatedPSDWarning, match=r"1.28 µm\) are larger than the scan.*0.32 µm"):
        big = surface_filter(psd, shape=(128, 128), spacing=10e-9)
    m0_big = float(big.sum()) * (2 * np.pi / (128 * 10e-9)) ** 2
    np.testing.assert_allclose(m0_big, m0, rtol=0.1)
    np.testing.assert_allclose(big.sel(qx=0.0, qy=0.0).item(), psd.sel(qx=0.0, qy=0.0).item(), rtol=1e-12)
    with pytest.warns(rs.surface.ExtrapolatedPSDWarning):
        hb = generate_surfaces(psd, n=2, shape=(128, 128), spacing=10e-9, seed=1, amplitude="fixed")
    np.testing.assert_allclose((hb.values**2).mean(axis=(1, 2)), m0_big, rtol=1e-10)


def test_interpolated_psd_is_reused_by_content_only():
    # an ensemble asks for the same interpolated PSD once per block: it is kept, keyed by the
    # PSD's values, coordinates and the target grid, so a changed PSD is never served stale
    z = generate_surfaces(S2, n=1, shape=(32, 32), spacing=10e-9, seed=8).values[0]
    psd = _psd_2d(z, 10e-9)
    kw = dict(shape=(64, 64), spacing=10e-9, amplitude="fixed")
    with pytest.warns(rs.surface.ExtrapolatedPSDWarning):
        a = generate_surfaces(psd, n=2, seed=1, **kw).values
        b = generate_surfaces(psd, realizations=[1], seed=1, **kw).values
        np.testing.assert_array_equal(a[1:], b)
        twice = psd.copy(data=2 * psd.values)
        c = generate_surfaces(twice, n=2, seed=1, **kw).values
        np.testing.assert_allclose(c, np.sqrt(2) * a, rtol=0, atol=1e-12 * np.abs(c).max())
        psd.values[...] *= 2  # in place: same object, new content
        d = generate_surfaces(psd, n=2, seed=1, **kw).values
    np.testing.assert_array_equal(c, d)


def test_isotropic_dataarray_matches_callable():
    q = np.linspace(0, 1.5 * np.pi / 5e-9, 4000)
    fit = rs.surface.fit_self_affine(**TABLE3["S1"], qmax=289e6)
    iso = rs.surface.self_affine_psd(q, **{k: float(fit[k]) for k in ("s0", "s1", "q0", "qmax")})
    a = surface_filter(iso, shape=(64, 64), spacing=5e-9)
    b = surface_filter(S1, shape=(64, 64), spacing=5e-9)
    np.testing.assert_allclose(a.sum(), b.sum(), rtol=2e-3)
    ha = generate_surfaces(iso, n=2, shape=(64, 64), spacing=5e-9, seed=3)
    hb = generate_surfaces(S1, n=2, shape=(64, 64), spacing=5e-9, seed=3)
    assert float(abs(ha - hb).max()) < 0.05 * float(hb.std())


def test_float32_error_is_single_precision_roundoff():
    h64 = generate_surfaces(S1, n=2, shape=(64, 96), spacing=5e-9, seed=6).values
    h32 = generate_surfaces(S1, n=2, shape=(64, 96), spacing=5e-9, seed=6, dtype="float32").values
    assert h32.dtype == np.float32
    assert np.abs(h32 - h64).max() < 1e-5 * h64.std()
    np.testing.assert_allclose((h32.astype(float) ** 2).mean(), (h64**2).mean(), rtol=1e-5)


# --------------------------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------------------------
def test_psd_grid_not_covering_the_spacing():
    z = generate_surfaces(S2, n=1, shape=(32, 32), spacing=10e-9, seed=8).values[0]
    psd = _psd_2d(z, 10e-9)
    with pytest.raises(ValueError, match="Nyquist"):
        generate_surfaces(psd, n=1, shape=(64, 64), spacing=5e-9, seed=1)
    iso = xr.DataArray(np.ones(5) * 1e-34, dims="q", coords={"q": np.linspace(0, 3e8, 5)},
                       attrs={"units": "m4"})
    with pytest.raises(ValueError, match="spacing >= "):
        generate_surfaces(iso, n=1, shape=8, spacing=5e-9)
    generate_surfaces(iso, n=1, shape=8, spacing=11e-9)  # coarse enough: accepted (flat: exact)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n": 0}, "at least 1"),
        ({"n": -3}, "at least 1"),
        ({"n": 2.5}, "integer"),
        ({"n": 2, "shape": (10.5, 10)}, "integer"),
        ({"n": 2, "shape": (16.0, 16)}, "Pass 16"),
        ({"n": 2, "shape": (1, 16)}, "at least 2"),
        ({"n": 2, "chunks": {"x": 4}}, "realization"),
        ({"n": 2, "chunks": {"realization": 1, "y": 8}}, "split"),
        ({"n": 2, "dtype": "int32"}, "float32"),
        ({"n": 2, "amplitude": "gaussian"}, "rayleigh"),
        ({"n": 2, "size": 81e-9}, "whole number of pixels"),
        ({"n": 2, "realizations": [0, 3]}, "out of range"),
        ({"n": 2, "shape": (16, 16, 16)}, r"\(y, x\) pair"),
    ],
)
def test_bad_arguments(kwargs, match):
    base = {"shape": 16, "spacing": 5e-9, "seed": 0}
    base.update(kwargs)
    if "size" in kwargs:
        base.pop("shape")
    with pytest.raises(ValueError, match=match):
        generate_surfaces(S1, **base)


def test_bad_psd_values_and_metadata():
    qs = np.fft.fftshift(2 * np.pi * np.fft.fftfreq(8, 5e-9))
    good = xr.DataArray(np.full((8, 8), 1e-34), dims=("qy", "qx"), coords={"qy": qs, "qx": qs},
                        attrs={"units": "m4"})
    with pytest.raises(ValueError, match="negative"):
        generate_surfaces(good.copy(data=-good.values), n=1, spacing=5e-9)
    with pytest.raises(ValueError, match="NaN"):
        bad = good.copy(data=good.values.copy())
        bad[2, 3] = np.nan
        generate_surfaces(bad, n=1, spacing=5e-9)
    with pytest.raises(ValueError, match="units"):
        no_units = good.copy()
        no_units.attrs = {}
        generate_surfaces(no_units, n=1, spacing=5e-9)
    with pytest.raises(ValueError, match="dims"):
        generate_surfaces(good.rename(qy="a"), n=1, spacing=5e-9)
    with pytest.raises(ValueError, match="spacing is required"):
        generate_surfaces(S1, n=1, shape=8)
    with pytest.raises(TypeError, match="callable"):
        generate_surfaces(np.ones((8, 8)), n=1, shape=8, spacing=5e-9)
    with pytest.raises(ValueError, match="negative"):
        generate_surfaces(lambda q: -np.ones_like(q), n=1, shape=8, spacing=5e-9)
    h = generate_surfaces(good, n=1, spacing=5e-9, seed=0)  # shape from the PSD grid
    assert h.shape == (1, 8, 8)
    good.attrs.update(spacing_x=5e-9, spacing_y=5e-9)
    assert generate_surfaces(good, n=1, shape=8, seed=0).shape == (1, 8, 8)


def test_one_sided_psd_is_symmetrised_and_power_conserved():
    """A 2D PSD given on one side only (s(q) != s(-q)) is made even: the variance is still the
    PSD integral, split over +q and -q."""
    qs = np.fft.fftshift(2 * np.pi * np.fft.fftfreq(8, 5e-9))
    s = xr.DataArray(np.zeros((8, 8)), dims=("qy", "qx"), coords={"qy": qs, "qx": qs},
                     attrs={"units": "m4"})
    s[5, 4] = 1e-32  # qy = +dq, qx = 0 only
    dq = 2 * np.pi / (8 * 5e-9)
    h = generate_surfaces(s, n=2, spacing=5e-9, seed=0, amplitude="fixed").values
    np.testing.assert_allclose((h**2).mean(axis=(1, 2)), 1e-32 * dq**2, rtol=1e-10)
    # a wave along y only
    np.testing.assert_allclose(h[0], np.broadcast_to(h[0, :, :1], (8, 8)), atol=1e-25)


def test_plotting_ensemble_psd_and_figures():
    """The radial ensemble PSD of the plotting helper agrees with the ring-averaged target."""
    import matplotlib.pyplot as plt

    from roughstick.plotting.generation import ensemble_psd, plot_generated_psd, plot_surfaces

    h = generate_surfaces(S1, n=40, shape=(64, 64), spacing=5e-9, seed=2)
    gen = ensemble_psd(h)
    P, _ = _grid_power(S1, (64, 64))
    total = float((gen * gen.n_samples).sum()) * (2 * np.pi / (64 * 5e-9)) ** 2
    # the S1 PSD is zero beyond 289 rad/um < Nyquist 628 rad/um: the rings hold all the variance
    se = np.sqrt(2 * (P**2).sum() / 40)
    assert abs(total - P.sum()) < 4 * se
    axes = plot_surfaces(h, ncols=3)
    assert len(axes) == 3
    ax = plot_generated_psd(h, S1)
    assert ax.get_xscale() == "log"
    plt.close("all")


def test_callable_may_return_a_dataarray():
    """rs.surface.self_affine_psd can be passed directly as a lambda (1-D |q| in, DataArray out)."""
    fit = rs.surface.fit_self_affine(**TABLE3["S2"], qmax=289e6)
    p = {k: float(fit[k]) for k in ("s0", "s1", "q0", "qmax")}
    a = generate_surfaces(lambda q: rs.surface.self_affine_psd(q, **p), n=2, shape=(20, 30),
                          spacing=5e-9, seed=4)
    b = generate_surfaces(S2, n=2, shape=(20, 30), spacing=5e-9, seed=4)
    np.testing.assert_array_equal(a.values, b.values)
    with pytest.raises(ValueError, match="elementwise"):
        generate_surfaces(lambda q: np.ones(3), n=1, shape=8, spacing=5e-9)


def test_distributed_cluster_gives_the_same_surfaces():
    """Two worker processes of a dask.distributed LocalCluster reproduce the serial values."""
    distributed = pytest.importorskip("distributed")
    ref = _reference()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster):
        h = generate_surfaces(S1, n=7, shape=(12, 18), spacing=20e-9, seed=99, chunks=3)
        np.testing.assert_array_equal(h.values, ref)


def test_surfaces_larger_than_the_measured_scan_warn_on_the_python_path(recwarn):
    """Issue 16 item 5: the low-q PSD of surfaces larger than the scan is extrapolated: say so in
    the Python API too (not only `roughstick run`), for 2D and isotropic PSDs and run_ensemble."""
    import warnings

    z = generate_surfaces(S2, n=1, shape=(32, 32), spacing=10e-9, seed=8).values[0]
    psd = _psd_2d(z, 10e-9)  # measured on a 0.32 µm scan
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.surface.ExtrapolatedPSDWarning)
        generate_surfaces(psd, n=1, shape=(32, 32), spacing=10e-9, seed=1)  # same size: silent
        generate_surfaces(psd, n=1, shape=(16, 32), spacing=10e-9, seed=1)  # smaller: silent
    with pytest.warns(rs.surface.ExtrapolatedPSDWarning, match="0.64 µm.*0.32 µm, its qx step") as rec:
        generate_surfaces(psd, n=1, shape=(32, 64), spacing=10e-9, seed=1)
    assert rec[0].filename == __file__  # points at the caller, not inside roughstick
    iso = rs.surface.psd_isotropic(psd)
    scan = 2 * np.pi / float(iso.q[iso.q > 0].min())
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.surface.ExtrapolatedPSDWarning)
        generate_surfaces(iso, n=1, shape=int(scan / 10e-9), spacing=10e-9, seed=1)
    with pytest.warns(rs.surface.ExtrapolatedPSDWarning, match="2 pi / its lowest q"):
        generate_surfaces(iso, n=1, shape=int(scan / 10e-9) + 2, spacing=10e-9, seed=1)


def test_an_analytic_psd_flat_below_its_first_q_does_not_warn():
    """Eq. 37 is flat below its roll-off: holding its first value there is exact, not extrapolated."""
    import warnings

    q = np.geomspace(1e6, 1e9, 200)
    psd = rs.surface.self_affine_psd(q, s0=1e-36, s1=1e-37, q0=2e7, qmax=3e8)
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.surface.ExtrapolatedPSDWarning)
        generate_surfaces(psd, n=1, shape=(16, 2048), spacing=5e-9, seed=1)  # 10 µm > 2π/1e6 = 6 µm


def test_extrapolation_said_once_is_per_thread_and_leaves_the_filters_alone():
    """run_ensemble silences the per-block ExtrapolatedPSDWarning with a context variable, not
    with warnings.catch_warnings (which swaps the process-wide filters: not thread-safe under
    dask's threads)."""
    import threading
    import warnings

    from roughstick.surface.generate import extrapolation_said_once

    z = generate_surfaces(S2, n=1, shape=(32, 32), spacing=10e-9, seed=8).values[0]
    psd = _psd_2d(z, 10e-9)
    filters = list(warnings.filters)
    inside, outside = threading.Event(), threading.Event()

    def quiet_thread():
        with extrapolation_said_once():
            with warnings.catch_warnings(record=True) as caught:  # this thread's view only
                warnings.simplefilter("always")
                surface_filter(psd, shape=(128, 128), spacing=10e-9)
            assert not [w for w in caught if issubclass(w.category, rs.surface.ExtrapolatedPSDWarning)]
            inside.set()
            outside.wait(10)

    t = threading.Thread(target=quiet_thread)
    t.start()
    assert inside.wait(10)
    try:  # while the other thread is still inside its quiet block, this one warns
        with pytest.warns(rs.surface.ExtrapolatedPSDWarning):
            surface_filter(psd, shape=(128, 128), spacing=10e-9)
    finally:
        outside.set()
        t.join()
    assert warnings.filters == filters
