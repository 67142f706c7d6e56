"""Shared fixtures and helpers: numpy/dask backends, the dask-compute guard, paths to data,
synthetic maps with a known spectrum and a lognormal stand-in for an ensemble of adhesive energies
(``from conftest import filtered_noise, lognormal_gamma``)."""

from __future__ import annotations

import pathlib

import dask.array as dsa
import numpy as np
import pytest
import xarray as xr

from roughstick.testing import make_topography, raise_if_dask_computes

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



def filtered_noise(shape, spacing, filt, rng, sigma=1e-9):
    """Periodic Gaussian map whose expected 2D PSD is sigma² Δ² |H(q)|² / (2π)²."""
    ny, nx = shape[-2:]
    w = rng.normal(size=shape) * sigma
    qx = 2 * np.pi * np.fft.fftfreq(nx, spacing)
    qy = 2 * np.pi * np.fft.fftfreq(ny, spacing)
    H = filt(np.hypot(qx[None, :], qy[:, None]))
    z = np.fft.ifft2(np.fft.fft2(w) * H).real
    expected = lambda q: sigma**2 * spacing**2 * filt(q) ** 2 / (2 * np.pi) ** 2  # noqa: E731
    return make_topography(z, spacing=spacing, periodic=True), expected


def lorentz(q):
    return 1.0 / (1.0 + (q / 5e7) ** 2)


def lognormal_gamma(n=200, rh=(0.3, 0.5, 0.7, 0.9), *, seed=0, median=None, sigma=0.8):
    """Stand-in ensemble Gamma(realization, rh): lognormal, median growing with RH."""
    rng = np.random.default_rng(seed)
    rh = np.asarray(rh, dtype=float)
    mu = np.log(median if median is not None else 2e-4 * np.exp(3 * rh))
    vals = np.exp(mu + sigma * rng.standard_normal((n, rh.size)))
    return xr.DataArray(
        vals, dims=("realization", "rh"), coords={"realization": np.arange(n), "rh": rh},
        name="adhesive_energy", attrs={"units": "J m-2"},
    ), mu
