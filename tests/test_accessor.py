"""The .rough accessor: explicit one-line forwarding methods, each to the public function of its name."""

import inspect

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.accessor import RoughDataArrayAccessor, RoughDatasetAccessor


@pytest.mark.parametrize("cls", [RoughDataArrayAccessor, RoughDatasetAccessor])
def test_every_method_forwards_to_the_public_function_of_its_name(cls):
    methods = [n for n in vars(cls) if not n.startswith("_")]
    assert len(methods) >= 10
    for name in methods:
        assert name in rs.__all__, f".rough.{name} forwards to no public rs.{name}"
        body = inspect.getsource(getattr(cls, name)).strip().splitlines()[1:]
        assert len(body) == 1 and body[0].strip().startswith("return ") and f".{name}(self._obj" in body[0], (
            f".rough.{name} is not a one-line forward")


def test_forwarding_gives_the_same_objects():
    rh = xr.DataArray([0.3, 0.5], dims="rh", coords={"rh": [0.3, 0.5]}, attrs={"units": "1"})
    rs.testing.assert_same_result(rh.rough.water_height(), rs.water_height(rh))
    h = rs.testing.make_topography(np.random.default_rng(0).normal(size=(16, 12)) * 1e-9)
    rs.testing.assert_same_result(h.rough.power_spectrum(window="hann"), rs.power_spectrum(h, window="hann"))
    m = h.rough.roughness_moments()
    rs.testing.assert_same_result(m.rough.asperity_statistics(), rs.asperity_statistics(m))


def test_unknown_names_say_what_is_offered():
    rh = xr.DataArray([0.3], dims="rh", attrs={"units": "1"})
    with pytest.raises(AttributeError, match="no public function 'not_a_function'.*water_height"):
        rh.rough.not_a_function()
    with pytest.raises(AttributeError, match="no public function 'level'"):
        xr.Dataset().rough.level()  # a height-map method is not offered on a Dataset
