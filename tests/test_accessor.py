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
    assert sorted(methods) == sorted(table)
    served = cls(xr.Dataset() if cls is RoughDatasetAccessor else xr.DataArray(0.0))._models()
    assert len(methods) + len(served) >= 10  # + <model>_curves of the contact-model registry
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
    rs.testing.assert_same_result(rh.rough.water_height(), rs.contact.water_height(rh))
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


def test_contact_models_are_served_from_the_registry():
    """``.rough.<model>_curves`` exists for every registered contact model (a map) or for those
    that take spectral moments (a Dataset), and is that model's function."""
    h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    names = {f"{m}_curves" for m in rs.contact.MODELS}
    assert names <= set(dir(h.rough))
    d = np.linspace(-1e-9, 1e-9, 5)
    rs.testing.assert_same_result(h.rough.fft_bem_curves(relative_humidity=0.5, distance=d + 2e-9),
                                  rs.contact.fft_bem_curves(h, relative_humidity=0.5, distance=d + 2e-9))
    xr.testing.assert_identical(h.rough.curves(relative_humidity=0.5, distance=d).pressure,
                                rs.contact.curves(h, relative_humidity=0.5, distance=d).pressure)
    m = h.rough.roughness_moments()
    assert "gw_curves" in dir(m.rough) and "fft_bem_curves" not in dir(m.rough)
    with pytest.raises(AttributeError, match="no public function 'fft_bem_curves'"):
        m.rough.fft_bem_curves()


def test_method_names_of_earlier_releases_warn_and_forward():
    h = rs.testing.make_topography(np.random.default_rng(0).normal(size=(16, 12)) * 1e-9)
    with pytest.warns(DeprecationWarning, match=r"\.rough\.curves"):
        method = h.rough.rough_contact_curves
    assert method.__func__.__forwards_to__ is rs.contact.curves
