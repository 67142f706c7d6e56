"""Multi-fidelity estimates: unbiased for the accurate model, honest intervals, seeded subsets."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from roughstick.ensemble.multifidelity import (
    accurate_subset,
    accurate_subset_size,
    multifidelity_band,
    multifidelity_kernel,
)

PROBS = np.array([0.025, 0.5, 0.975])


def _population(n, rng, *, noise=0.1):
    """A cheap model and an accurate one related by a power law with scatter (log-normal Γ)."""
    lo = rng.lognormal(mean=-6.0, sigma=0.8, size=n)
    hi = 2.1 * lo ** 1.15 * np.exp(noise * rng.normal(size=n))
    return lo, hi


def _run(lo, hi, n, seed):
    acc = np.full(lo.size, np.nan)
    sub = accurate_subset(lo.size, n, seed=seed)
    acc[sub] = hi[sub]
    return multifidelity_kernel(lo, acc, probabilities=PROBS)


def test_the_subset_depends_on_the_seed_alone_and_grows_by_inclusion():
    a = accurate_subset(1000, 40, seed=7)
    assert np.array_equal(a, accurate_subset(1000, 40, seed=7))
    assert np.isin(a, accurate_subset(1000, 90, seed=7)).all()
    assert not np.array_equal(a, accurate_subset(1000, 40, seed=8))
    assert a.size == np.unique(a).size == 40 and a.min() >= 0 and a.max() < 1000
    with pytest.raises(ValueError, match="n <= n_total"):
        accurate_subset(10, 11)


def test_an_exact_relation_gives_the_all_accurate_quantiles():
    """Accurate = a monotone power of cheap, no scatter: the line in log-log space is exact, so
    the estimate is the all-accurate ensemble's quantile and mean (the fitting folds' members
    count with their own values, the others with exact predictions)."""
    rng = np.random.default_rng(1)
    lo, hi = _population(2000, rng, noise=0.0)
    r = _run(lo, hi, 50, seed=3)
    np.testing.assert_allclose(r["quantile"], np.quantile(hi, PROBS, method="inverted_cdf"),
                               rtol=1e-9)
    np.testing.assert_allclose(r["mean"], hi.mean(), rtol=1e-9)


def test_unbiased_mean_and_cdf_over_seeds():
    """Averaged over seeds, the estimate of the mean equals the mean of the same realizations
    all run accurately (within 4 standard errors of the average)."""
    rng = np.random.default_rng(2)
    lo, hi = _population(800, rng, noise=0.3)
    est = np.array([_run(lo, hi, 40, seed=s)["mean"] for s in range(120)])
    se = est.std(ddof=1) / np.sqrt(est.size)
    assert abs(est.mean() - hi.mean()) < 4 * se


@pytest.mark.parametrize("noise", [0.05, 0.2])
def test_intervals_cover(noise):
    """Over 60 seeds (new surfaces and a new subset each time), the correction interval holds the
    all-accurate ensemble's quantile and the total interval the population's mean in at least
    90 % of the runs (95 % nominal); an interval the sample cannot bound on one side (NaN) holds
    it on that side."""
    big = _population(2_000_000, np.random.default_rng(0), noise=noise)[1]
    true_mean = big.mean()
    hits_q = np.zeros(PROBS.size)
    hits_m = 0
    R = 60
    for s in range(R):
        lo, hi = _population(1000, np.random.default_rng(100 + s), noise=noise)
        r = _run(lo, hi, 80, seed=s)
        fin = np.quantile(hi, PROBS)
        low = np.where(np.isnan(r["correction_lower"]), -np.inf, r["correction_lower"])
        up = np.where(np.isnan(r["correction_upper"]), np.inf, r["correction_upper"])
        hits_q += (low <= fin) & (fin <= up)
        hits_m += r["mean_lower"] <= true_mean <= r["mean_upper"]
    assert (hits_q / R >= 0.9).all(), hits_q / R
    assert hits_m / R >= 0.88, hits_m / R


def test_uncorrelated_cheap_model_stays_unbiased_with_wide_intervals():
    """A cheap model unrelated to the accurate one cannot help: the estimate falls back to the
    accurate subset alone, still centred, with an interval as wide as the subset allows."""
    rng = np.random.default_rng(5)
    lo = rng.lognormal(size=2000)
    hi = rng.lognormal(size=2000)
    est = np.array([_run(lo, hi, 100, seed=s)["quantile"][1] for s in range(40)])
    assert abs(np.median(est) / np.median(hi) - 1) < 0.05
    r = _run(lo, hi, 100, seed=0)
    assert (r["correction_upper"][1] - r["correction_lower"][1]) / r["quantile"][1] > 0.2


def test_subset_size_grows_with_the_scatter_and_the_accuracy_asked():
    rng = np.random.default_rng(6)
    sizes = {}
    for noise in (0.02, 0.3):
        lo, hi = _population(40, rng, noise=noise)  # a pilot of 40 pairs
        sizes[noise] = (accurate_subset_size(lo, hi, n_total=3000, accuracy=0.05),
                        accurate_subset_size(lo, hi, n_total=3000, accuracy=0.01))
    assert 40 <= sizes[0.02][0] <= sizes[0.3][0]
    assert sizes[0.3][0] <= sizes[0.3][1] <= 3000
    assert accurate_subset_size(lo[:5], hi[:5], n_total=3000, accuracy=0.05) == 3000  # no pilot


def test_xarray_band_keeps_labels_units_and_is_the_same_lazily():
    rng = np.random.default_rng(8)
    lo, hi = _population(600, rng)
    lo2, hi2 = _population(600, rng)
    cheap = xr.DataArray(np.stack([lo, lo2], axis=1), dims=("realization", "rh"),
                         coords={"realization": np.arange(600), "rh": [0.3, 0.7]},
                         attrs={"units": "J m-2", "long_name": "apparent adhesive energy"})
    sub = accurate_subset(600, 60, seed=2)
    accurate = xr.DataArray(np.stack([hi, hi2], axis=1), dims=cheap.dims,
                            coords=cheap.coords).isel(realization=sub)
    band = multifidelity_band(cheap, accurate)
    assert band["value"].dims == ("rh", "quantile")
    assert band["value"].attrs["units"] == "J m-2"
    assert int(band["n_accurate"].isel(rh=0)) == 60
    lazy = multifidelity_band(cheap.chunk({"rh": 1}), accurate.chunk({"rh": 1}))
    lazy = lazy.compute()
    lazy.attrs["history"] = band.attrs["history"]  # written a moment later
    xr.testing.assert_identical(band, lazy)
    with pytest.raises(ValueError, match="dim="):
        multifidelity_band(cheap.rename(realization="r"), accurate)


def test_an_atom_of_the_accurate_values_is_held_exactly():
    """Half the accurate values equal one number (the pull-off of flooded maps at high humidity is
    one capillary limit), which exp(log v) misses by a rounding error: the interval edges are the
    accurate values themselves, so the correction interval of the median holds that number,
    compared exactly, in at least 8 of 10 seeds (95 % nominal)."""
    rng = np.random.default_rng(9)
    lo = rng.lognormal(mean=16.0, sigma=0.3, size=1000)
    cap = 14600267.81417
    assert np.exp(np.log(cap)) != cap
    hi = np.minimum(1.05 * lo * np.exp(0.02 * rng.normal(size=1000)), cap)
    hi[lo > np.median(lo)] = cap
    hits = 0
    for seed in range(10):
        r = _run(lo, hi, 100, seed=seed)
        lower = -np.inf if np.isnan(r["correction_lower"][1]) else r["correction_lower"][1]
        upper = np.inf if np.isnan(r["correction_upper"][1]) else r["correction_upper"][1]
        hits += lower <= cap <= upper
    assert hits >= 8, hits
