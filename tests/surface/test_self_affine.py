"""Tests of roughstick.surface.self_affine: Eq. 37 and its inverse."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick._core import units as _units

QMAX = 289e6  # rad/m (paper: 289 rad/µm)


TABLE4 = dict(roughness=[2.6e-9, 2.4e-9], radius=220e-9)


def test_self_affine_psd_shape_and_branches():
    q = np.array([0.0, 1e6, 2e7, 5e7, 2e8, 2.0000001e8, 1e9])
    s = rs.surface.self_affine_psd(q, s0=1e-32, s1=1e-38, q0=2e7, qmax=2e8)
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
    s2 = rs.surface.self_affine_psd(qmag, s0=1e-32, s1=1e-38, q0=2e7, qmax=2e8)
    assert s2.dims == ("qy", "qx")
    iso = rs.surface.self_affine_psd(np.linspace(0, 4e8, 4001), s0=1e-32, s1=1e-38, q0=2e7, qmax=2e8)
    s2b = rs.surface.isotropic_to_2d(iso, qx=qx.values, qy=qy.values)
    assert s2b.dims == ("qy", "qx")
    # linear interpolation in log of a power law on a fine grid: close to the exact 2D values
    np.testing.assert_allclose(s2b.values, s2.values, rtol=2e-3, atol=0)


def test_self_affine_psd_units_of_dataarray_params():
    s = rs.surface.self_affine_psd(
        [1e7], s0=xr.DataArray(1e4, attrs={"units": "nm4"}), s1=1e-38, q0=2e7, qmax=2e8
    )
    np.testing.assert_allclose(s.values, 1e-32)
    with pytest.raises(_units.UnitsError, match="units"):
        rs.surface.self_affine_psd([1e7], s0=xr.DataArray(1e4), s1=1e-38, q0=2e7, qmax=2e8)
    with pytest.raises(ValueError, match="q0 must be smaller"):
        rs.surface.self_affine_psd([1e7], s0=1e-32, s1=1e-38, q0=3e8, qmax=2e8)
    with pytest.raises(ValueError, match="positive"):
        rs.surface.self_affine_psd([1e7], s0=-1e-32, s1=1e-38, q0=2e7, qmax=2e8)


def test_self_affine_exponent_special_cases():
    # exponents -2, -4, -6 hit the logarithmic branches of the closed form
    for k in (2, 4, 6):
        s1 = 1e-32 * 10.0 ** (-k)  # qmax/q0 = 10, so exponent = -k
        m = rs.surface.self_affine_moments(s0=1e-32, s1=s1, q0=2e7, qmax=2e8)
        m_near = rs.surface.self_affine_moments(s0=1e-32, s1=s1 * (1 + 1e-7), q0=2e7, qmax=2e8)
        for v in ("m0", "m2", "m4"):
            np.testing.assert_allclose(float(m[v]), float(m_near[v]), rtol=1e-6)


def test_fit_self_affine_table4_as_computed_n801():
    """Table 4 with N = 80.1 µm^-2: q0 ≈ 21.2 rad/µm, s0 ≈ 5.5e3 nm^4, s1 ≈ 5.5e-3 nm^4."""
    m = rs.surface.moments_from_asperities(**TABLE4, density=80.1e12)
    fit = rs.surface.fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=QMAX)
    np.testing.assert_allclose(float(fit.q0), 21.2e6, rtol=5e-3)
    np.testing.assert_allclose(float(fit.s0), 5.5e-33, rtol=1e-2)
    np.testing.assert_allclose(float(fit.s1), 5.5e-39, rtol=1e-2)
    for k in ("m0", "m2", "m4"):
        assert abs(float(fit[f"residual_{k}"])) < 1e-9
    # it is NOT the printed solution (the discrepancy DESIGN.md §3 documents)
    assert abs(float(fit.q0) / 19.4e6 - 1) > 0.05


def test_fit_self_affine_table4_printed_values_need_n881():
    """The printed 19.4 rad/µm, 6.46e3 nm^4, 6.29e-3 nm^4 come out with N = 88.1 µm^-2."""
    m = rs.surface.moments_from_asperities(**TABLE4, density=88.1e12)
    fit = rs.surface.fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=QMAX)
    np.testing.assert_allclose(float(fit.q0), 19.4e6, rtol=1e-2)
    np.testing.assert_allclose(float(fit.s0), 6.46e-33, rtol=1.5e-2)
    np.testing.assert_allclose(float(fit.s1), 6.29e-39, rtol=1e-2)


def test_fit_self_affine_round_trip_and_units():
    p = dict(s0=3e-33, s1=4e-39, q0=3e7, qmax=3e8)
    m = rs.surface.self_affine_moments(**p)
    m0_nm = (m.m0 * 1e18).assign_attrs(units="nm2")
    fit = rs.surface.fit_self_affine(m0=m0_nm, m2=m.m2, m4=m.m4, qmax=p["qmax"])
    np.testing.assert_allclose(float(fit.q0), p["q0"], rtol=1e-6)
    np.testing.assert_allclose(float(fit.s0), p["s0"], rtol=1e-6)
    np.testing.assert_allclose(float(fit.s1), p["s1"], rtol=1e-5)
    assert fit.s0.attrs["units"] == "m4" and fit.q0.attrs["units"] == "rad m-1"
    assert "fit_self_affine" in fit.attrs["history"]
    # the fitted parameters feed self_affine_psd directly (DataArrays with units)
    s = rs.surface.self_affine_psd([1e7, 2e8], s0=fit.s0, s1=fit.s1, q0=fit.q0, qmax=fit.qmax)
    np.testing.assert_allclose(s.values[0], p["s0"], rtol=1e-6)


def test_fit_self_affine_sweep_backend(backend, no_compute):
    p = dict(s1=4e-39, q0=3e7, qmax=3e8)
    s0 = xr.DataArray([2e-33, 3e-33, 5e-33], dims="sample", attrs={"units": "m4"})
    m = rs.surface.self_affine_moments(s0=s0, **p)
    m0 = backend(m.m0.assign_attrs(units="m2"), {"sample": 1})
    with no_compute():
        fit = rs.surface.fit_self_affine(m0=m0, m2=m.m2, m4=m.m4, qmax=p["qmax"])
    assert fit.s0.dims == ("sample",)
    assert isinstance(fit.s0.data, type(m0.data))
    np.testing.assert_allclose(fit.s0.values, s0.values, rtol=1e-6)
    np.testing.assert_allclose(fit.q0.values, 3e7, rtol=1e-6)


def test_fit_self_affine_unreachable_raises():
    # m2^2 > m0 m4 is impossible for any PSD (Cauchy-Schwarz): no Eq. 37 solution
    with pytest.raises(ValueError, match="no Eq. 37 PSD"):
        rs.surface.fit_self_affine(m0=1e-17, m2=0.5, m4=1e12, qmax=QMAX)
    out = rs.surface.fit_self_affine(m0=1e-17, m2=0.5, m4=1e12, qmax=QMAX, solver_tolerance=np.inf)
    assert abs(float(out.residual_m2)) > 1e-3
    with pytest.raises(ValueError, match="positive"):
        rs.surface.fit_self_affine(m0=0.0, m2=0.5, m4=1e12, qmax=QMAX)
