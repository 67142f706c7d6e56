"""Shared fixtures: numpy/dask backends, a dask-compute guard, paths to data."""

from __future__ import annotations

import pathlib

import dask
import dask.array as dsa
import numpy as np
import pytest
import xarray as xr

ROOT = pathlib.Path(__file__).resolve().parents[1]
DATA_SAMPLES = ROOT / "data_samples"
SHARED_AFM = ROOT.parent / "shared" / "afm"


@pytest.fixture(params=["numpy", "dask"])
def backend(request):
    """Parametrise a test over numpy- and dask-backed inputs; call ``backend(da)`` to convert."""
    kind = request.param

    def convert(obj, chunks=None):
        if kind == "numpy":
            return obj
        if isinstance(obj, (xr.DataArray, xr.Dataset)):
            return obj.chunk(chunks or {})
        return dsa.from_array(np.asarray(obj), chunks=chunks or -1)

    convert.kind = kind
    return convert


class _CountingScheduler:
    def __init__(self, max_computes=0):
        self.total = 0
        self.max_computes = max_computes

    def __call__(self, dsk, keys, **kwargs):
        self.total += 1
        if self.total > self.max_computes:
            raise RuntimeError(f"Too many dask computations were scheduled: {self.total}")
        return dask.get(dsk, keys, **kwargs)


def raise_if_dask_computes(max_computes=0):
    """Context manager raising if dask computes more than ``max_computes`` times (xarray's helper)."""
    return dask.config.set(scheduler=_CountingScheduler(max_computes))


@pytest.fixture
def no_compute():
    return raise_if_dask_computes


def pytest_configure(config):
    import matplotlib

    matplotlib.use("Agg")
