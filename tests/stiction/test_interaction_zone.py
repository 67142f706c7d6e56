"""Tests of roughstick.stiction.interaction_zone: Table 4 -> Eq. 37 -> the zone's ensemble (section 5.2)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs


def _spectral_moments(z, dy, dx):
    """Height, slope and curvature variances of periodic maps (..., y, x) from exact spectral
    derivatives, in x and in y: an estimate independent of roughstick's PSD code."""
    ny, nx = z.shape[-2:]
    qx = 2 * np.pi * np.fft.fftfreq(nx, dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, dy)
    zf = np.fft.fft2(z - z.mean(axis=(-2, -1), keepdims=True))
    power = np.abs(zf) ** 2 / (nx * ny) ** 2  # sum over modes = variance (Parseval)
    QX, QY = np.meshgrid(qx, qy)
    m0 = power.sum(axis=(-2, -1))
    return m0, (power * QX**2).sum(axis=(-2, -1)), (power * QX**4).sum(axis=(-2, -1)), \
        (power * QY**2).sum(axis=(-2, -1)), (power * QY**4).sum(axis=(-2, -1))


def test_table4_moments_and_eq37_both_densities():
    m = rs.stiction.cantilever_moments()
    assert float(m.m0) ** 0.5 == pytest.approx(3.54e-9, rel=2e-3)
    assert float(m.m4) == pytest.approx((3 * np.sqrt(np.pi) / (8 * 220e-9)) ** 2, rel=1e-12)
    assert float(m.m4) == pytest.approx(9.1e12, rel=5e-3)  # Table 4: 9.1 um^-2
    assert float(m.m2) == pytest.approx(0.0035, rel=5e-3)  # Table 4: 0.0035
    p = rs.stiction.cantilever_psd()
    assert float(p.q0) == pytest.approx(21.2e6, rel=5e-3)
    assert float(p.s0) == pytest.approx(5.5e3 * 1e-36, rel=1e-2)
    assert float(p.s1) == pytest.approx(5.5e-3 * 1e-36, rel=2e-2)
    assert "88.1" in p.attrs["note"]
    # the paper's printed solution comes from N = 88.1 um^-2 (within the 3 printed digits, ~1 %)
    printed = rs.stiction.cantilever_psd(asperity_density=88.1e12)
    assert float(printed.q0) == pytest.approx(19.4e6, rel=1e-2)
    assert float(printed.s0) == pytest.approx(6.46e3 * 1e-36, rel=1.5e-2)
    assert float(printed.s1) == pytest.approx(6.29e-3 * 1e-36, rel=1.5e-2)
    # the fitted PSD has the Table 4 moments (closed-form moments, independent of the solver)
    mom = rs.surface.self_affine_moments(s0=p.s0, s1=p.s1, q0=p.q0, qmax=p.qmax)
    for k in ("m0", "m2", "m4"):
        assert float(mom[k]) == pytest.approx(float(m[k]), rel=1e-5)


def test_table4_eq37_generated_rectangle_reproduces_moments():
    """Table 4 -> Eq. 37 -> surfaces on the interaction zone Delta s x w = 2.62 x 30 um at 5 nm
    (524 x 6000 pixels, the full rectangle): the sample moments match mu0, mu2, mu4 within
    the Monte-Carlo standard error plus the discretisation of the PSD on the wave-number grid."""
    p = rs.stiction.cantilever_psd()
    m = rs.stiction.cantilever_moments()

    def iso(q):
        return rs.surface.self_affine_psd(np.asarray(q).ravel(), s0=p.s0, s1=p.s1, q0=p.q0, qmax=p.qmax).values.reshape(np.shape(q))

    ny, nx, d = 524, 6000, 5e-9
    n = 4
    h = rs.generate_surfaces(iso, n=n, shape=(ny, nx), spacing=d, seed=7, chunks=1)
    assert h.sizes == {"realization": n, "y": ny, "x": nx}
    z = h.values
    m0, m2x, m4x, m2y, m4y = _spectral_moments(z, d, d)
    # expectation on the grid: the model PSD summed over the generated wave vectors (q = 0 excluded)
    qx = 2 * np.pi * np.fft.fftfreq(nx, d)
    qy = 2 * np.pi * np.fft.fftfreq(ny, d)
    QX, QY = np.meshgrid(qx, qy)
    S = iso(np.hypot(QX, QY)) * (2 * np.pi / (nx * d)) * (2 * np.pi / (ny * d))
    S[0, 0] = 0.0
    grid = {"m0": S.sum(), "m2x": (S * QX**2).sum(), "m4x": (S * QX**4).sum(),
            "m2y": (S * QY**2).sum(), "m4y": (S * QY**4).sum()}
    target = {"m0": float(m.m0), "m2x": float(m.m2), "m4x": float(m.m4), "m2y": float(m.m2), "m4y": float(m.m4)}
    sample = {"m0": m0, "m2x": m2x, "m4x": m4x, "m2y": m2y, "m4y": m4y}
    for k, v in sample.items():
        se = v.std(ddof=1) / np.sqrt(n)
        disc = abs(grid[k] - target[k])
        assert disc / target[k] < 0.02, (k, disc / target[k])  # grid quadrature of Eq. 37
        assert abs(v.mean() - grid[k]) < 4 * se + 1e-9 * grid[k], (k, v.mean(), grid[k], se)
        assert abs(v.mean() - target[k]) < 4 * se + disc, (k, v.mean() / target[k])


def test_predicted_gamma_layer_vs_no_layer():
    """Fig. 20a vs 20b on a small interaction zone (64 x 512 px, 6 surfaces): the same surfaces
    give the same Gamma without the layer below 65 % RH and a smaller one above it."""
    rh = [0.55, 0.6, 0.7, 0.8, 0.9]
    runs = {layer: rs.stiction.predict_adhesive_energy(n=6, shape=(64, 512), relative_humidity=rh,
                                              adsorbed_layer=layer, seed=3)
            for layer in ("none", "paper")}
    g = {k: v.adhesive_energy.compute() for k, v in runs.items()}
    assert g["none"].dims == ("realization", "rh") and g["none"].sizes["realization"] == 6
    assert (g["none"] > 0).all()
    below = [r for r in rh if r <= 0.65]
    above = [r for r in rh if r > 0.65]
    xr.testing.assert_allclose(g["none"].sel(rh=below), g["paper"].sel(rh=below), rtol=1e-12)
    assert (g["none"].sel(rh=above) < g["paper"].sel(rh=above)).all()
    assert runs["paper"].attrs["interaction_zone_shape"] == [64, 512]
    # risk on the prediction: longer beams stick at least as often
    risk = rs.stiction.risk_summary(g["paper"], beam_length=[150e-6, 250e-6, 400e-6, 800e-6])
    assert (risk.stiction_probability.diff("beam_length") >= 0).all()
