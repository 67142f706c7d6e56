import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick._core.conventions import ATTRS, append_history, set_attrs
from roughstick._core.dask import as_seed_sequence, is_lazy, realization_rng
from roughstick._core.units import UnitsError, as_si, require
from roughstick._core.validate import check_core_not_chunked


@pytest.mark.parametrize(
    "units, factor", [("m", 1.0), ("nm", 1e-9), ("um", 1e-6), ("µm", 1e-6), ("mm", 1e-3), ("Å", 1e-10)]
)
def test_require_length_converts_to_metres(units, factor):
    da = xr.DataArray([1.0, 2.0], dims="x", attrs={"units": units})
    out = require(da, "length")
    np.testing.assert_allclose(out.values, np.array([1.0, 2.0]) * factor)
    assert out.attrs["units"] == "m"


def test_require_missing_units_names_fix():
    da = xr.DataArray([1.0], dims="x")
    with pytest.raises(UnitsError, match=r"attrs\['units'\] = 'm'"):
        require(da, "length")


def test_require_singular_unit_attr_hint():
    da = xr.DataArray([1.0], dims="x", attrs={"unit": "nm"})
    with pytest.raises(UnitsError, match="rename it to 'units'"):
        require(da, "length")


def test_require_wrong_kind():
    da = xr.DataArray([1.0], dims="x", attrs={"units": "Pa"})
    with pytest.raises(UnitsError, match="not a length unit"):
        require(da, "length")


def test_require_keeps_dask_lazy():
    da = xr.DataArray(np.ones(4), dims="x", attrs={"units": "nm"}).chunk(2)
    out = require(da, "length")
    assert is_lazy(out)
    np.testing.assert_allclose(out.compute().values, 1e-9)


def test_as_si_plain_numbers_pass_through():
    assert as_si(3, "length", name="r") == 3.0
    assert isinstance(as_si(xr.DataArray(1.0, attrs={"units": "GPa"}), "pressure", name="E"), xr.DataArray)


def test_set_attrs_and_history():
    da = xr.DataArray(np.zeros(3), dims="rh", coords={"rh": [0.3, 0.5, 0.7]})
    out = set_attrs(da, "water_height")
    assert out.attrs == ATTRS["water_height"]
    assert out.rh.attrs["standard_name"] == "relative_humidity"
    assert da.attrs == {}  # input untouched
    append_history(out, "first")
    append_history(out, "second")
    lines = out.attrs["history"].splitlines()
    assert len(lines) == 2 and lines[0].endswith("first") and lines[1].endswith("second")


def test_check_core_not_chunked_names_fix():
    da = xr.DataArray(np.zeros((4, 4)), dims=("y", "x")).chunk({"x": 2})
    with pytest.raises(ValueError, match=r"\.chunk\(\{'x': -1\}\)"):
        check_core_not_chunked(da, ("x", "y"))
    check_core_not_chunked(da.chunk({"x": -1}), ("x", "y"))


def test_realization_rng_independent_of_order():
    root = as_seed_sequence(42)
    a = [realization_rng(root, k).standard_normal(3) for k in range(4)]
    b = [realization_rng(root, k).standard_normal(3) for k in reversed(range(4))][::-1]
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)
    assert not np.array_equal(a[0], a[1])


def test_seed_validation():
    with pytest.raises(ValueError, match="non-negative"):
        as_seed_sequence(-1)
    with pytest.raises(TypeError, match="seed must be"):
        as_seed_sequence("abc")


def test_materials_moduli_match_paper():
    # two poly-Si bodies: K = 4/3 E* = 115.4 GPa (DESIGN.md §3)
    assert rs.materials.hertz_modulus() == pytest.approx(115.4e9, rel=1e-3)
    assert rs.materials.reduced_modulus() == pytest.approx(86.58e9, rel=1e-3)
    soft = rs.Material(youngs_modulus=1e9, poisson_ratio=0.5, name="soft")
    # rigid counter-body limit: E* -> E/(1-nu^2)
    rigid = rs.Material(youngs_modulus=1e20, poisson_ratio=0.0)
    assert rs.materials.reduced_modulus(soft, rigid) == pytest.approx(1e9 / 0.75, rel=1e-9)
    with pytest.raises(ValueError, match="positive"):
        rs.Material(youngs_modulus=-1.0)


def test_make_topography_coords():
    h = rs.testing.make_topography(np.zeros((3, 5)), spacing=2e-9, periodic=True)
    assert h.dims == ("y", "x") and h.attrs["periodic"] == 1
    np.testing.assert_allclose(np.diff(h.x.values), 2e-9)
    rs.testing.assert_units(h, "m")


def test_assert_same_result_ignores_only_the_history_time_stamps():
    a = rs.conventions.append_history(xr.DataArray([1.0], attrs={"units": "m"}), "made")
    b = a.copy()
    b.attrs["history"] = "1999-01-01T00:00:00Z made"
    rs.testing.assert_same_result(a, b)
    rs.testing.assert_same_result(a.to_dataset(name="v").assign_attrs(history=a.attrs["history"]),
                                  b.to_dataset(name="v").assign_attrs(history=b.attrs["history"]))
    for other in (b.assign_attrs(history="1999-01-01T00:00:00Z made twice"), b.assign_attrs(units="nm"), b * 2):
        with pytest.raises(AssertionError):
            rs.testing.assert_same_result(a, other)
