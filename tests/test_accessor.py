"""The .rough accessor: one-line forwarding methods from one table per kind of data, each to a
public function of a namespace."""

import importlib
import inspect

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick import accessor
from roughstick.accessor import RoughDataArrayAccessor, RoughDatasetAccessor

TABLES = {RoughDataArrayAccessor: (accessor.HEIGHT_MAP, accessor.PSD, accessor.RELATIVE_HUMIDITY,
                                   accessor.SAMPLE),
          RoughDatasetAccessor: (accessor.CURVES, accessor.MOMENTS, accessor.ENSEMBLE)}


@pytest.mark.parametrize("cls", [RoughDataArrayAccessor, RoughDatasetAccessor])
def test_every_method_forwards_to_the_public_function_of_its_table(cls):
    methods = [n for n in vars(cls) if not n.startswith("_")]
    table = {k: v for t in TABLES[cls] for k, v in t.items()}
    assert len(methods) >= 10 and sorted(methods) == sorted(table)
    forward = inspect.getsource(accessor._forward)
    assert "return func(self._obj, *args, **kwargs)" in forward  # the one line, shared by all
    for name in methods:
        method = getattr(cls, name)
        func = method.__forwards_to__
        assert func is table[name] and method.__code__ is accessor._forward(name, func).__code__
        namespace = importlib.import_module(".".join(func.__module__.split(".")[:2]))
        assert getattr(namespace, func.__name__) is func and func.__name__ in namespace.__all__, (
            f".rough.{name} forwards to {func.__module__}.{func.__name__}, no public name")
        assert f"{namespace.__name__}.{func.__name__}" in method.__doc__


def test_forwarding_gives_the_same_objects():
    rh = xr.DataArray([0.3, 0.5], dims="rh", coords={"rh": [0.3, 0.5]}, attrs={"units": "1"})
    rs.testing.assert_same_result(rh.rough.water_height(), rs.water_height(rh))
    h = rs.testing.make_topography(np.random.default_rng(0).normal(size=(16, 12)) * 1e-9)
    rs.testing.assert_same_result(h.rough.power_spectrum(window="hann"), rs.surface.power_spectrum(h, window="hann"))
    m = h.rough.roughness_moments()
    rs.testing.assert_same_result(m.rough.asperity_statistics(), rs.surface.asperity_statistics(m))


def test_unknown_names_say_what_is_offered():
    rh = xr.DataArray([0.3], dims="rh", attrs={"units": "1"})
    with pytest.raises(AttributeError, match="no public function 'not_a_function'.*water_height"):
        rh.rough.not_a_function()
    with pytest.raises(AttributeError, match="no public function 'level'"):
        xr.Dataset().rough.level()  # a height-map method is not offered on a Dataset
