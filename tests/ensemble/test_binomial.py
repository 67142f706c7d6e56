"""Tests of roughstick.ensemble.binomial_interval (roughstick.ensemble.statistics) against scipy.stats."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy import stats

import roughstick as rs
from roughstick.testing import raise_if_dask_computes


@pytest.mark.parametrize("method,scipy_method", [("wilson", "wilson"), ("clopper-pearson", "exact")])
def test_binomial_interval_matches_scipy(method, scipy_method):
    for k, n in [(0, 10), (3, 20), (10, 10), (1, 1), (37, 200), (199, 200)]:
        for conf in (0.9, 0.95, 0.99):
            lo, hi = rs.ensemble.binomial_interval(k, n, confidence=conf, method=method)
            ref = stats.binomtest(k, n).proportion_ci(confidence_level=conf, method=scipy_method)
            assert float(lo) == pytest.approx(ref.low, abs=1e-12)
            assert float(hi) == pytest.approx(ref.high, abs=1e-12)


def test_binomial_interval_arrays_and_errors(backend):
    k = xr.DataArray([0, 5, 20], dims="beam_length")
    n = xr.DataArray([20, 20, 20], dims="beam_length")
    ki, ni = backend(k), backend(n)
    with raise_if_dask_computes():
        lo, hi = rs.ensemble.binomial_interval(ki, ni)
    assert isinstance(lo.data, type(ki.data))
    assert lo.dims == ("beam_length",)
    assert np.all(lo.values <= k.values / 20) and np.all(hi.values >= k.values / 20)
    lo0, hi0 = rs.ensemble.binomial_interval(0, 0)
    assert np.isnan(lo0) and np.isnan(hi0)
    with pytest.raises(ValueError, match="confidence"):
        rs.ensemble.binomial_interval(1, 2, confidence=95)
    with pytest.raises(ValueError, match="wilson"):
        rs.ensemble.binomial_interval(1, 2, method="agresti")
