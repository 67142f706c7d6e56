"""Shared fixtures: numpy/dask backends, the dask-compute guard, paths to data."""

from __future__ import annotations

import pathlib

import dask.array as dsa
import numpy as np
import pytest
import xarray as xr

from roughstick.testing import raise_if_dask_computes

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


@pytest.fixture
def no_compute():
    return raise_if_dask_computes


def pytest_configure(config):
    import matplotlib

    matplotlib.use("Agg")
