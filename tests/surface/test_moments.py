"""Tests of roughstick.surface.moments: Nayak moments of maps and PSDs, Table 4, cutoff, summit statistics."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import quad

import roughstick as rs
from conftest import filtered_noise, lorentz
from roughstick.testing import make_topography

SP = 5e-9


def cosine_map(ny=64, nx=80, *, ax=2e-9, ay=1e-9, kx=3, ky=2, spacing=SP):
    """A periodic smooth map: ax cos(qx x) + ay cos(qy y) with whole periods in the box."""
    x = (np.arange(nx) + 0.5) * spacing
    y = (np.arange(ny) + 0.5) * spacing
    qx, qy = 2 * np.pi * kx / (nx * spacing), 2 * np.pi * ky / (ny * spacing)
    z = ax * np.cos(qx * x)[None, :] + ay * np.cos(qy * y)[:, None]
    return make_topography(z, spacing=spacing, periodic=True), qx, qy


TABLE4 = dict(roughness=[2.6e-9, 2.4e-9], radius=220e-9)


def test_moments_cosines_analytic_both_methods():
    h, qx, qy = cosine_map(ny=96, nx=128, kx=3, ky=2)
    ax, ay = 2e-9, 1e-9
    exact_x = dict(m0=(ax**2 + ay**2) / 2, m2=ax**2 * qx**2 / 2, m4=ax**2 * qx**4 / 2)
    exact_mean = dict(m0=exact_x["m0"], m2=(ax**2 * qx**2 + ay**2 * qy**2) / 4,
                      m4=(ax**2 * qx**4 + ay**2 * qy**4) / 4)
    for direction, exact in (("x", exact_x), ("mean", exact_mean)):
        spec = rs.surface.roughness_moments(h, method="spectral", direction=direction)
        spl = rs.surface.roughness_moments(h, method="spline", direction=direction)
        for k in ("m0", "m2", "m4"):
            np.testing.assert_allclose(float(spec[k]), exact[k], rtol=1e-10)  # exact (periodic)
            # spline: edge effects of the not-a-knot interpolant on a non-periodic fit only
            np.testing.assert_allclose(float(spl[k]), exact[k], rtol=1e-2)
    assert spl.m4.attrs["units"] == "m-2" and spl.m0.attrs["units"] == "m2"


def test_moments_backend_and_odd_nonsquare(backend, no_compute):
    z = np.random.default_rng(4).normal(size=(2, 33, 20)) * 1e-9
    h = make_topography(z)
    inp = backend(h, {"dim_0": 1})
    with no_compute():
        m = rs.surface.roughness_moments(inp)
    assert isinstance(m.m2.data, type(inp.data)) and m.m2.dims == ("dim_0",)
    ref = rs.surface.roughness_moments(h)
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(m[k].values, ref[k].values, rtol=1e-12)
    np.testing.assert_allclose(ref.m0.values, z.var(axis=(-2, -1)), rtol=1e-12)


def test_asperity_statistics_and_plasticity():
    m = rs.surface.moments_from_asperities(roughness=3.54e-9, radius=220e-9, density=80.1e12)
    st = rs.surface.asperity_statistics(m)
    np.testing.assert_allclose(float(st.summit_density), 80.1e12, rtol=1e-12)
    np.testing.assert_allclose(float(st.summit_radius), 220e-9, rtol=1e-12)
    alpha = float(m.m0 * m.m4 / m.m2**2)
    np.testing.assert_allclose(float(st.bandwidth), alpha, rtol=1e-12)
    # Eq. 15 by hand with sigma_s given
    psi = rs.surface.plasticity_index(m, hardness=10e9, summit_height_std=2e-9)
    e = 164e9 / (2 * (1 - 0.23**2))
    np.testing.assert_allclose(float(psi), e / 10e9 * np.sqrt(2e-9 / 220e-9), rtol=1e-12)
    assert psi.attrs["units"] == "1" and "doi" in psi.attrs["references"]
    with pytest.raises(ValueError, match="hardness"):
        rs.surface.plasticity_index(m)
    # Nayak: sigma_s < sqrt(m0), -> sqrt(m0) as alpha -> infinity
    assert 0 < float(st.summit_height_std) < np.sqrt(float(m.m0))


def test_roughness_statistics_table():
    h = make_topography(np.random.default_rng(5).normal(size=(40, 40)) * 1e-9)
    st = rs.surface.roughness_statistics(rs.surface.level(h))
    for v in ("m0", "m2", "m4", "rms_height", "rms_slope", "skewness", "kurtosis",
              "summit_density", "summit_radius", "bandwidth"):
        assert v in st and "units" in st[v].attrs
    assert 2 < float(st.kurtosis) < 4 and abs(float(st.skewness)) < 0.5


@pytest.mark.parametrize("beta_s1", [1e-38, 1e-34, 1e-32 * (10 ** -2 / 1)])
def test_self_affine_moments_closed_form_vs_quadrature(beta_s1):
    # independent check: numerical quadrature of the isotropic moment integrals
    p = dict(s0=1e-32, s1=beta_s1, q0=2e7, qmax=2e8)
    m = rs.surface.self_affine_moments(**p)

    def s(q):
        return float(rs.surface.self_affine_psd([q], **p).values[0])

    pts = [p["q0"]]
    m0 = 2 * np.pi * quad(lambda q: s(q) * q, 0, p["qmax"], points=pts, limit=200)[0]
    m2 = np.pi * quad(lambda q: s(q) * q**3, 0, p["qmax"], points=pts, limit=200)[0]
    m4 = 0.75 * np.pi * quad(lambda q: s(q) * q**5, 0, p["qmax"], points=pts, limit=200)[0]
    np.testing.assert_allclose([float(m.m0), float(m.m2), float(m.m4)], [m0, m2, m4], rtol=1e-7)


def test_moments_from_asperities_table4():
    m = rs.surface.moments_from_asperities(**TABLE4, density=80.1e12)
    np.testing.assert_allclose(np.sqrt(float(m.m0)), 3.54e-9, rtol=2e-3)  # Table 4: 3.54 nm
    np.testing.assert_allclose(float(m.m4), 9.1e12, rtol=5e-3)  # 9.1 µm^-2 (squared formula)
    np.testing.assert_allclose(float(m.m2), 0.0035, rtol=5e-3)  # Table 4: 0.0035
    assert m.m0.attrs["units"] == "m2" and m.m4.attrs["units"] == "m-2"
    # Nayak: density and radius come back from the moments
    n = float(m.m4) / (6 * np.pi * np.sqrt(3) * float(m.m2))
    np.testing.assert_allclose(n, 80.1e12, rtol=1e-12)
    with pytest.raises(ValueError, match="roughness"):
        rs.surface.moments_from_asperities(roughness=-1e-9, radius=220e-9, density=80.1e12)
    with pytest.raises(ValueError, match="radius"):
        rs.surface.moments_from_asperities(roughness=1e-9, radius=0, density=80.1e12)


def test_isotropic_and_moments_of_eq37_grid():
    # 2D sampling of the Eq. 37 PSD on a fine grid: moments agree with the closed form
    p = dict(s0=5.5e-33, s1=5.5e-39, q0=21.2e6, qmax=289e6)
    n, sp = 512, 5e-9
    q1 = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(n, sp))
    qx = xr.DataArray(q1, dims="qx", coords={"qx": q1}, attrs={"units": "rad m-1"})
    qy = xr.DataArray(q1, dims="qy", coords={"qy": q1}, attrs={"units": "rad m-1"})
    s2 = rs.surface.self_affine_psd(np.hypot(qy, qx).assign_attrs(units="rad m-1"), **p)
    s2 = s2.assign_attrs(units="m4")
    exact = rs.surface.self_affine_moments(**p)
    m2d = rs.surface.psd_moments(s2)
    iso = rs.surface.psd_isotropic(s2)
    miso = rs.surface.psd_moments(iso)
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(float(m2d[k]), float(exact[k]), rtol=0.02)
        np.testing.assert_allclose(float(miso[k]), float(exact[k]), rtol=0.03)
    # cutting at q0 keeps only the plateau: pi q0^2 s0 within the grid's disc error
    np.testing.assert_allclose(float(rs.surface.psd_moments(s2, qmax=p["q0"]).m0),
                               np.pi * p["q0"] ** 2 * p["s0"], rtol=0.05)


def test_choose_cutoff_recovers_known_qmax():
    h, _ = filtered_noise((64, 64), 5e-9, lorentz, np.random.default_rng(13))
    s = rs.surface.power_spectrum(h)
    qtrue = 3.0e8
    target = rs.surface.psd_moments(s, qmax=qtrue)
    cut = rs.surface.choose_cutoff(s, target)
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
    spatial = rs.surface.roughness_moments(smooth)
    spectral = rs.surface.roughness_moments(smooth, method="spectral")
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(float(spatial[k]), float(spectral[k]), rtol=0.01)
    cut2 = rs.surface.choose_cutoff(rs.surface.power_spectrum(smooth), spatial)
    assert abs(float(cut2.residual_m4)) < 0.01 and abs(float(cut2.residual_m2)) < 0.01
    # with power up to the Nyquist wave number, cubic-spline curvatures exceed the spectral
    # m4 (spline response > q^2 near Nyquist): no cutoff can match, and the residual says so
    cut3 = rs.surface.choose_cutoff(s, rs.surface.roughness_moments(h))
    assert float(cut3.residual_m4) < -0.2
