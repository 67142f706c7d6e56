"""The shared input checks of roughstick._core.validate (each declared once, used by every stage)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick._core.validate import (
    check_positive_block,
    distance_array,
    grid_spacing,
    positive,
    relative_humidity_array,
    relative_humidity_coordinate,
    relative_humidity_values,
)
from roughstick.testing import make_topography, raise_if_dask_computes


def test_positive_floats_sequences_and_dataarrays():
    assert positive(2.0, "length", "radius") == 2.0
    r = positive([1e-7, 2e-7], "length", "radius", dim="radius")
    assert r.dims == ("radius",) and r.attrs["units"] == "m"
    nm = xr.DataArray([5.0], dims="radius", attrs={"units": "nm"})
    np.testing.assert_allclose(positive(nm, "length", "radius").values, [5e-9])
    with pytest.raises(ValueError, match=r"radius must be positive, got -1.0\. Pass it in m"):
        positive(-1.0, "length", "radius", "Pass it in m.")
    with pytest.raises(ValueError, match="scalar, a 1-D sequence or a DataArray"):
        positive(np.ones((2, 2)), "length", "radius")
    assert positive(np.ones((2, 2)), None, "x", arrays=True).shape == (2, 2)
    assert positive(0.0, None, "gamma", allow_zero=True) == 0.0
    with pytest.raises(ValueError, match="must be >= 0"):
        positive(-1e-3, None, "gamma", allow_zero=True)
    with pytest.raises(ValueError, match="positive and finite"):
        check_positive_block([1.0, np.nan], "q0", finite=True)
    check_positive_block([1.0, np.nan], "q0")  # NaN passes unless finite


def test_positive_checks_lazy_data_lazily():
    bad = xr.DataArray([1.0, -2.0], dims="k", attrs={"units": "m"}).chunk()
    with raise_if_dask_computes():
        out = positive(bad, "length", "radius")
    with pytest.raises(ValueError, match="radius must be positive"):
        out.compute()


def test_relative_humidity_forms():
    pct = xr.DataArray([30.0, 70.0], dims="rh", coords={"rh": [30.0, 70.0]}, attrs={"units": "%"})
    np.testing.assert_allclose(rs.contact.as_relative_humidity(pct).values, [0.3, 0.7])
    np.testing.assert_allclose(relative_humidity_values(pct), [0.3, 0.7])
    lazy = xr.DataArray([0.3, 0.5], dims="rh", coords={"rh": [0.3, 0.5]}, attrs={"units": "1"}).chunk()
    with raise_if_dask_computes():
        np.testing.assert_allclose(relative_humidity_values(lazy), [0.3, 0.5])  # from the coordinate
    with pytest.raises(ValueError, match="known in advance"):
        relative_humidity_coordinate(lazy)
    with pytest.raises(ValueError, match="1-D along 'rh'"):
        relative_humidity_coordinate(xr.DataArray([0.3], dims="x", attrs={"units": "1"}))
    np.testing.assert_array_equal(relative_humidity_array(0.5), [0.5])
    with pytest.raises(ValueError, match="repeated"):
        relative_humidity_array([0.3, 0.3])
    with pytest.raises(ValueError, match="empty"):
        relative_humidity_array([])
    with pytest.raises(ValueError, match=r"did you mean 0.3\?"):
        relative_humidity_array([30.0])


def test_grid_spacing_errors_name_the_fix():
    h = make_topography(np.zeros((8, 10)), spacing=2e-9)
    assert grid_spacing(h, "x") == pytest.approx(2e-9, rel=1e-12)
    nm = h.assign_coords(x=h.x.values * 1e9)
    nm["x"].attrs["units"] = "nm"
    assert grid_spacing(nm, "x") == pytest.approx(2e-9, rel=1e-12)
    with pytest.raises(ValueError, match="at least 12 x 12"):
        grid_spacing(h, "y", min_pixels=12)
    with pytest.raises(ValueError, match="descending.*sortby"):
        grid_spacing(h.isel(x=slice(None, None, -1)), "x")
    with pytest.raises(ValueError, match="not uniformly spaced"):
        grid_spacing(h.assign_coords(x=h.x.values ** 1.1), "x")
    with pytest.raises(ValueError, match="no 'y' coordinate"):
        grid_spacing(h.drop_vars("y"), "y")


def test_distance_array():
    np.testing.assert_array_equal(distance_array([2e-9, 1e-9]), [1e-9, 2e-9])
    nm = xr.DataArray([1.0, 2.0], dims="distance", attrs={"units": "nm"})
    np.testing.assert_allclose(distance_array(nm), [1e-9, 2e-9])
    for bad, match in (([1e-9, 1e-9], "repeated"), ([np.nan, 1e-9], "finite"), (None, "required"),
                       ([1e-9], "at least 2")):
        with pytest.raises(ValueError, match=match):
            distance_array(bad, min_size=2)


# ------------------------------------------------------------------ unit slips (plausibility)


@pytest.mark.parametrize("value, unit, fixed", [(164, "GPa", "164e9"), (1e15, None, None)])
def test_material_modulus_unit_slip_is_refused_by_name(value, unit, fixed):
    # before: Material(youngs_modulus=164) was accepted (164 Pa: a "solid" softer than jelly)
    with pytest.raises(ValueError) as err:
        rs.Material(youngs_modulus=value)
    msg = str(err.value)
    assert f"youngs_modulus={value:g} Pa is implausible for a solid" in msg, msg
    assert "give it in Pa" in msg
    if unit:
        assert f"it looks like {unit}" in msg and f"youngs_modulus={fixed}" in msg, msg


@pytest.mark.parametrize("value", [1e6, 3e9, 164e9, 1.2e12, 1e20])  # soft polymer .. rigid
def test_material_accepts_plausible_moduli(value):
    assert rs.Material(youngs_modulus=value, poisson_ratio=0.3).youngs_modulus == value


def test_material_hardness_unit_slip_is_refused():
    with pytest.raises(ValueError, match=r"hardness=10 Pa .* it looks like GPa"):
        rs.Material(hardness=10)


@pytest.mark.parametrize("field, value, hint", [("length", 1500, "1500e-6"),
                                                ("thickness", 2.62, "2.62e-6"),
                                                ("youngs_modulus", 164, "164e9")])
def test_cantilever_unit_slip_is_refused_by_name(field, value, hint):
    with pytest.raises(ValueError, match=rf"Cantilever\.{field}={value:g} .*implausible.*"
                                         rf"Cantilever\.{field}={hint}"):
        rs.Cantilever(**{field: value})


@pytest.mark.parametrize("value, says", [
    (1.0, r"relative_humidity = 1.0: RH must lie strictly between 0 and 1: 1 is saturation \(RH 100 %\), "
          r"outside the models' range; give at most e.g. 0.99\."),
    (30.0, r"relative_humidity = 30.0: RH must lie strictly between 0 and 1 \(a fraction\): did you mean 0.3\?"),
    (1.2, r"relative_humidity = 1.2: .*1.2 is above saturation \(1\)\."),
    (120.0, r"\(a fraction, e.g. 0.6\); 120 is not a relative humidity\."),
    (xr.DataArray(120.0, attrs={"units": "%"}),
     r"relative_humidity = '120 %': 120 % is not a relative humidity: RH must lie strictly between 0 and 100 %"),
    (xr.DataArray(100.0, attrs={"units": "%"}), r"'100 %': 100 % is saturation.*at most e.g. '99 %'"),
])
def test_relative_humidity_advice_fits_the_value(value, says):
    """One converter: RH 1 is saturation (not "0.01"), 120 % is not a humidity (not "0.012")."""
    with pytest.raises(ValueError, match=says) as err:
        rs.contact.as_relative_humidity(value)
    assert "0.01" not in str(err.value) and "0.012" not in str(err.value)


def test_fraction_advice_is_the_same_from_python_flags_and_configs():
    from roughstick._core.validate import as_fraction, fraction_advice

    assert fraction_advice(0.5, quantity="relative_humidity") is None
    assert as_fraction("30 %", name="rh", quantity="relative_humidity") == pytest.approx(0.3)
    assert fraction_advice(95.0, label="confidence") == ("confidence must lie strictly between 0 and 1 (a "
                                                         "fraction): did you mean 0.95 or '95 %'?")
    assert fraction_advice(95.0, label="confidence", spell_percent=False).endswith("did you mean 0.95?")
    assert "not a percentage" in fraction_advice(30.0, quantity="ratio", label="tolerance")
    with pytest.raises(ValueError, match=r"confidence = 95: confidence must lie .* did you mean 0.95\?"):
        rs.ensemble.min_samples_to_bound(0.5, confidence=95)
