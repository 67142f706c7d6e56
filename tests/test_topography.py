"""Tests of roughstick.topography: validation, levelling, NaN handling, roughness statistics."""

from __future__ import annotations

import numpy as np
import pytest

import roughstick as rs
from roughstick._core import units as _units
from roughstick.testing import make_topography

SP = 5e-9


def cosine_map(ny=64, nx=80, *, ax=2e-9, ay=1e-9, kx=3, ky=2, spacing=SP):
    """A periodic smooth map: ax cos(qx x) + ay cos(qy y) with whole periods in the box."""
    x = (np.arange(nx) + 0.5) * spacing
    y = (np.arange(ny) + 0.5) * spacing
    qx, qy = 2 * np.pi * kx / (nx * spacing), 2 * np.pi * ky / (ny * spacing)
    z = ax * np.cos(qx * x)[None, :] + ay * np.cos(qy * y)[:, None]
    return make_topography(z, spacing=spacing, periodic=True), qx, qy


# ------------------------------------------------------------------------------ validation


def test_validate_bad_inputs():
    h = make_topography(np.random.default_rng(0).normal(size=(16, 16)) * 1e-9)
    nounits = h.copy()
    nounits.attrs = {}
    with pytest.raises(_units.UnitsError, match="no 'units'"):
        rs.level(nounits)
    bad = h.copy()
    bad.attrs = {"units": "s"}
    with pytest.raises(_units.UnitsError, match="not a length"):
        rs.level(bad)
    with pytest.raises(ValueError, match="descending"):
        rs.level(h.isel(x=slice(None, None, -1)))
    xs = h.x.values.copy()
    xs[5] += 1e-9
    with pytest.raises(ValueError, match="not uniformly spaced"):
        rs.level(h.assign_coords(x=xs))
    with pytest.raises(ValueError, match="at least 8"):
        rs.level(h.isel(x=slice(0, 7)))
    with pytest.raises(ValueError, match="no 'x' coordinate"):
        rs.level(h.drop_vars("x"))
    with pytest.raises(ValueError, match=r"chunk\(\{'x': -1"):
        rs.level(h.chunk({"x": 4}))
    with pytest.raises(TypeError, match="DataArray"):
        rs.level(np.zeros((16, 16)))


def test_validate_converts_units_and_transposes():
    h = make_topography(np.arange(12 * 9, dtype=float).reshape(12, 9), spacing=1.0)
    h = (h * 1.0).assign_attrs(units="nm")
    h = h.assign_coords(x=h.x.assign_attrs(units="nm"), y=h.y.assign_attrs(units="nm"))
    v = rs.validate_height(h.transpose("x", "y"))
    assert v.dims == ("y", "x") and v.attrs["units"] == "m"
    np.testing.assert_allclose(v.values, h.values * 1e-9)
    np.testing.assert_allclose(v.attrs["spacing_x"], 1e-9)


# ------------------------------------------------------------------------------- levelling


def test_level_plane_mean_line():
    rng = np.random.default_rng(1)
    base = rng.normal(size=(24, 30)) * 1e-9
    h0 = make_topography(base)
    X, Y = np.meshgrid(h0.x.values, h0.y.values)
    tilted = make_topography(base + 3e-9 + 0.01 * X - 0.02 * Y)
    plane = rs.level(tilted, method="plane")
    # the plane fit of (base + plane) is the plane fit of base plus the plane: residual equals
    # base minus its own plane fit
    ref = rs.level(h0, method="plane")
    np.testing.assert_allclose(plane.values, ref.values, atol=1e-20)
    assert abs(float(rs.level(tilted, method="mean").mean())) < 1e-22
    # scan-line alignment removes per-line offsets and tilts exactly
    offsets = rng.normal(size=(24, 1)) * 5e-9 + rng.normal(size=(24, 1)) * 1e-3 * X
    lined = rs.level(make_topography(base + offsets), method="line")
    np.testing.assert_allclose(lined.values, rs.level(h0, method="line").values, atol=1e-20)
    assert "level: method='line'" in lined.attrs["history"]


def test_level_nan_fill_mask_raise():
    z = np.random.default_rng(2).normal(size=(20, 20)) * 1e-9
    z[3, 4] = z[10, 10] = np.nan
    h = make_topography(z)
    with pytest.raises(ValueError, match="NaN pixels"):
        rs.level(h)
    filled = rs.level(h, nan="fill")
    assert np.isfinite(filled.values).all()
    assert "2 NaN pixels" in filled.attrs["history"] and "filled" in filled.attrs["history"]
    masked = rs.level(h, nan="mask")
    assert np.isnan(masked.values).sum() == 2 and "masked" in masked.attrs["history"]
    # masked maps are refused by the spectra with the fix named
    with pytest.raises(ValueError, match="nan='fill'"):
        rs.power_spectrum(masked)
    z2 = z.copy()
    z2[:15] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        rs.level(make_topography(z2), nan="fill")


def test_level_backend(backend, no_compute):
    stack = make_topography(np.random.default_rng(3).normal(size=(3, 16, 18)) * 1e-9)
    inp = backend(stack, {"dim_0": 1})
    with no_compute():
        out = rs.level(inp, method="line")
    assert isinstance(out.data, type(inp.data))
    np.testing.assert_allclose(out.values, rs.level(stack, method="line").values, atol=1e-22)


# ------------------------------------------------------------------------------- moments


def test_moments_cosines_analytic_both_methods():
    h, qx, qy = cosine_map(ny=96, nx=128, kx=3, ky=2)
    ax, ay = 2e-9, 1e-9
    exact_x = dict(m0=(ax**2 + ay**2) / 2, m2=ax**2 * qx**2 / 2, m4=ax**2 * qx**4 / 2)
    exact_mean = dict(m0=exact_x["m0"], m2=(ax**2 * qx**2 + ay**2 * qy**2) / 4,
                      m4=(ax**2 * qx**4 + ay**2 * qy**4) / 4)
    for direction, exact in (("x", exact_x), ("mean", exact_mean)):
        spec = rs.roughness_moments(h, method="spectral", direction=direction)
        spl = rs.roughness_moments(h, method="spline", direction=direction)
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
        m = rs.roughness_moments(inp)
    assert isinstance(m.m2.data, type(inp.data)) and m.m2.dims == ("dim_0",)
    ref = rs.roughness_moments(h)
    for k in ("m0", "m2", "m4"):
        np.testing.assert_allclose(m[k].values, ref[k].values, rtol=1e-12)
    np.testing.assert_allclose(ref.m0.values, z.var(axis=(-2, -1)), rtol=1e-12)


def test_constant_map_raises():
    with pytest.raises(ValueError, match="constant"):
        rs.roughness_moments(make_topography(np.full((16, 16), 3e-9)))
    with pytest.raises(ValueError, match="constant"):
        rs.power_spectrum(make_topography(np.full((16, 16), 3e-9)))


# ------------------------------------------------------------------------- asperity stats


def test_asperity_statistics_and_plasticity():
    m = rs.moments_from_asperities(roughness=3.54e-9, radius=220e-9, density=80.1e12)
    st = rs.asperity_statistics(m)
    np.testing.assert_allclose(float(st.summit_density), 80.1e12, rtol=1e-12)
    np.testing.assert_allclose(float(st.summit_radius), 220e-9, rtol=1e-12)
    alpha = float(m.m0 * m.m4 / m.m2**2)
    np.testing.assert_allclose(float(st.bandwidth), alpha, rtol=1e-12)
    # Eq. 15 by hand with sigma_s given
    psi = rs.plasticity_index(m, hardness=10e9, summit_height_std=2e-9)
    e = 164e9 / (2 * (1 - 0.23**2))
    np.testing.assert_allclose(float(psi), e / 10e9 * np.sqrt(2e-9 / 220e-9), rtol=1e-12)
    assert psi.attrs["units"] == "1" and "doi" in psi.attrs["references"]
    with pytest.raises(ValueError, match="hardness"):
        rs.plasticity_index(m)
    # Nayak: sigma_s < sqrt(m0), -> sqrt(m0) as alpha -> infinity
    assert 0 < float(st.summit_height_std) < np.sqrt(float(m.m0))


def test_roughness_statistics_table():
    h = make_topography(np.random.default_rng(5).normal(size=(40, 40)) * 1e-9)
    st = rs.roughness_statistics(rs.level(h))
    for v in ("m0", "m2", "m4", "rms_height", "rms_slope", "skewness", "kurtosis",
              "summit_density", "summit_radius", "bandwidth"):
        assert v in st and "units" in st[v].attrs
    assert 2 < float(st.kurtosis) < 4 and abs(float(st.skewness)) < 0.5
