"""Tests of roughstick.surface.topography: validation, levelling, NaN handling."""

from __future__ import annotations

import numpy as np
import pytest

import roughstick as rs
from roughstick._core import units as _units
from roughstick.testing import make_topography


def test_validate_bad_inputs():
    h = make_topography(np.random.default_rng(0).normal(size=(16, 16)) * 1e-9)
    nounits = h.copy()
    nounits.attrs = {}
    with pytest.raises(_units.UnitsError, match="no 'units'"):
        rs.surface.level(nounits)
    bad = h.copy()
    bad.attrs = {"units": "s"}
    with pytest.raises(_units.UnitsError, match="not a length"):
        rs.surface.level(bad)
    with pytest.raises(ValueError, match="descending"):
        rs.surface.level(h.isel(x=slice(None, None, -1)))
    xs = h.x.values.copy()
    xs[5] += 1e-9
    with pytest.raises(ValueError, match="not uniformly spaced"):
        rs.surface.level(h.assign_coords(x=xs))
    with pytest.raises(ValueError, match="at least 8"):
        rs.surface.level(h.isel(x=slice(0, 7)))
    with pytest.raises(ValueError, match="no 'x' coordinate"):
        rs.surface.level(h.drop_vars("x"))
    with pytest.raises(ValueError, match=r"chunk\(\{'x': -1"):
        rs.surface.level(h.chunk({"x": 4}))
    with pytest.raises(TypeError, match="DataArray"):
        rs.surface.level(np.zeros((16, 16)))


def test_validate_converts_units_and_transposes():
    h = make_topography(np.arange(12 * 9, dtype=float).reshape(12, 9), spacing=1.0)
    h = (h * 1.0).assign_attrs(units="nm")
    h = h.assign_coords(x=h.x.assign_attrs(units="nm"), y=h.y.assign_attrs(units="nm"))
    v = rs.surface.validate_height(h.transpose("x", "y"))
    assert v.dims == ("y", "x") and v.attrs["units"] == "m"
    np.testing.assert_allclose(v.values, h.values * 1e-9)
    np.testing.assert_allclose(v.attrs["spacing_x"], 1e-9)


def test_level_plane_mean_line():
    rng = np.random.default_rng(1)
    base = rng.normal(size=(24, 30)) * 1e-9
    h0 = make_topography(base)
    X, Y = np.meshgrid(h0.x.values, h0.y.values)
    tilted = make_topography(base + 3e-9 + 0.01 * X - 0.02 * Y)
    plane = rs.surface.level(tilted, method="plane")
    # the plane fit of (base + plane) is the plane fit of base plus the plane: residual equals
    # base minus its own plane fit
    ref = rs.surface.level(h0, method="plane")
    np.testing.assert_allclose(plane.values, ref.values, atol=1e-20)
    assert abs(float(rs.surface.level(tilted, method="mean").mean())) < 1e-22
    # scan-line alignment removes per-line offsets and tilts exactly
    offsets = rng.normal(size=(24, 1)) * 5e-9 + rng.normal(size=(24, 1)) * 1e-3 * X
    lined = rs.surface.level(make_topography(base + offsets), method="line")
    np.testing.assert_allclose(lined.values, rs.surface.level(h0, method="line").values, atol=1e-20)
    assert "level: method='line'" in lined.attrs["history"]


def test_level_nan_fill_mask_raise():
    z = np.random.default_rng(2).normal(size=(20, 20)) * 1e-9
    z[3, 4] = z[10, 10] = np.nan
    h = make_topography(z)
    with pytest.raises(ValueError, match="NaN pixels"):
        rs.surface.level(h)
    filled = rs.surface.level(h, nan="fill")
    assert np.isfinite(filled.values).all()
    assert "2 NaN pixels" in filled.attrs["history"] and "filled" in filled.attrs["history"]
    masked = rs.surface.level(h, nan="mask")
    assert np.isnan(masked.values).sum() == 2 and "masked" in masked.attrs["history"]
    # masked maps are refused by the spectra with the fix named
    with pytest.raises(ValueError, match="nan='fill'"):
        rs.surface.power_spectrum(masked)
    z2 = z.copy()
    z2[:15] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        rs.surface.level(make_topography(z2), nan="fill")


def test_level_backend(backend, no_compute):
    stack = make_topography(np.random.default_rng(3).normal(size=(3, 16, 18)) * 1e-9)
    inp = backend(stack, {"dim_0": 1})
    with no_compute():
        out = rs.surface.level(inp, method="line")
    assert isinstance(out.data, type(inp.data))
    np.testing.assert_allclose(out.values, rs.surface.level(stack, method="line").values, atol=1e-22)


def test_constant_map_raises():
    with pytest.raises(ValueError, match="constant"):
        rs.surface.roughness_moments(make_topography(np.full((16, 16), 3e-9)))
    with pytest.raises(ValueError, match="constant"):
        rs.surface.power_spectrum(make_topography(np.full((16, 16), 3e-9)))
