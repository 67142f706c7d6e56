"""Public testing helpers: unit assertions, small synthetic topographies and a dask-compute guard.

For the tests of roughstick and of code built on it (cf. ``xarray.testing`` and xarray's
``raise_if_dask_computes``).
"""

from __future__ import annotations

import re

import dask
import numpy as np
import xarray as xr

from ._core.conventions import ATTRS, set_coord_attrs
from ._core.validate import as_length

__all__ = [
    "assert_units", "assert_same_result", "make_topography", "sphere_topography", "raise_if_dask_computes",
]


def assert_units(obj: xr.DataArray, units: str) -> None:
    """Assert that ``obj`` and its canonical coordinates carry CF ``units``."""
    assert obj.attrs.get("units") == units, f"{obj.name!r}: units {obj.attrs.get('units')!r} != {units!r}"
    for c in obj.coords:
        if c in ATTRS:
            assert obj[c].attrs.get("units") == ATTRS[c]["units"], f"coordinate {c!r} lacks units"


_STAMP = re.compile(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ ", re.MULTILINE)


def _unstamped(obj):
    out = obj.copy(deep=False)
    parts = [out] + (list(out.data_vars.values()) if isinstance(out, xr.Dataset) else [])
    for p in parts:
        if "history" in p.attrs:
            p.attrs = {**p.attrs, "history": _STAMP.sub("", p.attrs["history"])}
    return out


def assert_same_result(a, b) -> None:
    """``xarray.testing.assert_identical`` except the time stamps of the ``history`` lines.

    Two calls that straddle a second boundary stamp different times on otherwise identical
    results (a comparison that includes them fails about once in a hundred runs); the lines
    themselves, values, coordinates and all other attributes must still be identical.

    Examples
    --------
    >>> a = rs.conventions.append_history(xr.DataArray([1.0]), "made")
    >>> b = a.copy(); b.attrs["history"] = "1999-01-01T00:00:00Z made"
    >>> rs.testing.assert_same_result(a, b)
    """
    xr.testing.assert_identical(_unstamped(a), _unstamped(b))


def make_topography(values, *, spacing: float = 5e-9, periodic: bool = False, name: str = "height") -> xr.DataArray:
    """Wrap a 2-D array of heights [m] as a ``height`` DataArray (y, x) with pixel-centre coords
    (``spacing`` in m, or with its unit: ``"5 nm"``).

    Examples
    --------
    >>> h = rs.testing.make_topography(np.zeros((4, 6)), spacing=1e-9)
    >>> h.dims, h.x.values[:2]
    (('y', 'x'), array([5.e-10, 1.5e-09]))
    """
    values = np.asarray(values, dtype=float)
    spacing = as_length(spacing, name="spacing")
    ny, nx = values.shape[-2:]
    da = xr.DataArray(
        values,
        dims=tuple(f"dim_{i}" for i in range(values.ndim - 2)) + ("y", "x"),
        coords={"y": (np.arange(ny) + 0.5) * spacing, "x": (np.arange(nx) + 0.5) * spacing},
        name=name,
        attrs={**ATTRS["height"], "periodic": int(periodic)},
    )
    return set_coord_attrs(da)


def sphere_topography(radius: float, *, n: int = 65, spacing: float, apex: float = 0.0) -> xr.DataArray:
    """A spherical cap of ``radius`` [m] with its apex at height ``apex``, centred on an n x n grid.

    Pixels outside the sphere's footprint are set to the lowest height of the cap. ``radius``
    and ``spacing`` are in m, or strings with their unit (``"200 nm"``).
    """
    radius, spacing = as_length(radius, name="radius"), as_length(spacing, name="spacing")
    c = (np.arange(n) - (n - 1) / 2) * spacing
    X, Y = np.meshgrid(c, c)
    r2 = X**2 + Y**2
    z = np.sqrt(np.clip(radius**2 - r2, 0, None)) - radius + apex
    z = np.where(r2 <= radius**2, z, z.min())
    return make_topography(z, spacing=spacing)


class _CountingScheduler:
    def __init__(self, max_computes=0):
        self.total = 0
        self.max_computes = max_computes

    def __call__(self, dsk, keys, **kwargs):
        self.total += 1
        if self.total > self.max_computes:
            raise RuntimeError(f"Too many dask computations were scheduled: {self.total}")
        return dask.get(dsk, keys, **kwargs)


def raise_if_dask_computes(max_computes: int = 0):
    """Context manager raising ``RuntimeError`` if dask computes more than ``max_computes`` times.

    Laziness is part of the contract (docs/architecture.md): build a pipeline inside it to check that
    nothing is computed.

    Examples
    --------
    >>> x = xr.DataArray(np.arange(4.0)).chunk(2)
    >>> with rs.testing.raise_if_dask_computes():
    ...     y = (x * 2).sum()  # still lazy
    """
    return dask.config.set(scheduler=_CountingScheduler(max_computes))
