"""Tests of roughstick.ensemble.statistics: bands and their uncertainty, order-statistic and binomial intervals, distributions."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick._core.conventions import ATTRS
from roughstick._core.intervals import order_statistic_ranks
from roughstick.testing import raise_if_dask_computes


def _sample(n=400, seed=0):
    rng = np.random.default_rng(seed)
    return xr.DataArray(rng.lognormal(size=(n, 3)), dims=("realization", "rh"),
                        coords={"rh": [0.3, 0.5, 0.9]}, name="adhesive_energy",
                        attrs=dict(ATTRS["surface_adhesive_energy"]))


def test_confidence_band_values_and_metadata(backend):
    x = backend(_sample(), chunks={"realization": 50})
    with raise_if_dask_computes():
        b = rs.ensemble.confidence_band(x, confidence=0.9)
    ref = np.quantile(_sample().values, [0.05, 0.5, 0.95], axis=0)
    np.testing.assert_allclose(b.adhesive_energy.values, ref, rtol=1e-12)
    np.testing.assert_allclose(b.adhesive_energy_mean.values, _sample().mean("realization").values)
    np.testing.assert_allclose(b.adhesive_energy_mean_stderr.values,
                               _sample().std("realization", ddof=1).values / np.sqrt(400))
    assert b.adhesive_energy.dims == ("quantile", "rh")
    assert b.adhesive_energy.attrs["units"] == "J m-2"
    assert b["quantile"].attrs["units"] == "1"
    assert b.attrs["n_members"] == 400 and b.attrs["level"] == 0.9
    # in memory the members used are known; a lazy band would need a computation to count them
    assert b.attrs.get("n_samples") == (400 if backend.kind == "numpy" else None)
    assert (b.adhesive_energy_n_samples == 400).all()
    assert (b.adhesive_energy_ci_lower <= b.adhesive_energy).all()
    assert (b.adhesive_energy_ci_upper >= b.adhesive_energy).all()


def test_band_independent_of_chunking():
    a = rs.ensemble.confidence_band(_sample().chunk({"realization": 7})).compute()
    b = rs.ensemble.confidence_band(_sample()).compute()
    xr.testing.assert_allclose(a, b, rtol=1e-14)


def test_order_statistic_interval_covers_true_quantile():
    """Coverage of the distribution-free interval of the median and of the 90 % quantile."""
    from scipy.stats import binom, norm

    n, trials = 60, 3000
    rng = np.random.default_rng(1)
    x = xr.DataArray(rng.standard_normal((trials, n)), dims=("trial", "realization"))
    lo, hi = rs.ensemble.quantile_interval(x, [0.5, 0.9], confidence=0.95)
    for k, p in enumerate([0.5, 0.9]):
        truth = norm.ppf(p)
        cover = float(((lo[k] <= truth) & (truth <= hi[k])).mean())
        r = int(binom.ppf(0.025, n, p))
        s = int(binom.ppf(0.975, n, p)) + 1
        exact = binom.cdf(s - 1, n, p) - binom.cdf(r - 1, n, p)
        assert exact >= 0.95
        assert abs(cover - exact) < 3 * np.sqrt(exact * (1 - exact) / trials) + 1e-3


def test_interval_unbounded_when_n_too_small():
    x = xr.DataArray(np.arange(10.0), dims="realization")
    lo, hi = rs.ensemble.quantile_interval(x, [0.025, 0.975])
    assert np.isnan(lo[0]) and np.isnan(hi[1]) and np.isfinite(hi[0]) and np.isfinite(lo[1])
    assert "n too small to bound this edge" in lo.attrs["comment"]


def test_bootstrap_seeded_and_comparable():
    x = _sample(300)
    a = rs.ensemble.quantile_interval(x, [0.5], method="bootstrap", seed=4, n_bootstrap=200)
    b = rs.ensemble.quantile_interval(x.chunk({"rh": 1}), [0.5], method="bootstrap", seed=4, n_bootstrap=200)
    xr.testing.assert_identical(a[0], b[0].compute())
    o = rs.ensemble.quantile_interval(x, [0.5])
    w_boot = (a[1] - a[0]).values
    w_os = (o[1] - o[0]).values
    assert np.all(w_boot > 0.4 * w_os) and np.all(w_boot < 2.5 * w_os)
    with pytest.raises(ValueError, match="method"):
        rs.ensemble.quantile_interval(x, [0.5], method="jackknife")


def test_histogram_and_ecdf(backend):
    raw = _sample()
    x = backend(raw, chunks={"realization": 100})
    h = rs.ensemble.histogram(x, bins=20, range=(0, 10))
    ref = np.histogram(raw.values[:, 1], bins=20, range=(0, 10), density=True)[0]
    np.testing.assert_allclose(h.sel(rh=0.5).values, ref)
    assert h.dims == ("rh", "bin") and h.attrs["units"] == "J-1 m2"
    assert h.bin_upper.values[-1] == 10
    e = rs.ensemble.ecdf(x)
    np.testing.assert_array_equal(e.values, np.sort(raw.values, axis=0).T)
    assert e.cumulative_probability.values[-1] == 1.0
    assert e.dims == ("rh", "cumulative_probability")
    if backend.kind == "dask":
        with pytest.raises(ValueError, match="range"):
            rs.ensemble.histogram(x, bins=10)


def test_min_samples_to_bound_matches_the_ranks():
    """The n below which one edge of a 95 % band cannot be bounded (issue 16: 8-48 surfaces)."""
    for p in (0.025, 0.05, 0.5, 0.975):
        need = rs.ensemble.min_samples_to_bound(p, confidence=0.95)
        r, s = order_statistic_ranks(need, p, confidence=0.95)
        assert r >= 1 and s <= need
        r, s = order_statistic_ranks(need - 1, p, confidence=0.95)
        assert r < 1 or s > need - 1
    # closed form for the 2.5 % quantile: (1 - p)^n < 0.025
    assert rs.ensemble.min_samples_to_bound(0.025, confidence=0.95) == int(np.ceil(np.log(0.025) / np.log(0.975)))


def test_band_too_small_says_so_and_large_band_carries_intervals():
    small = _sample(48).rename("adhesive_energy").assign_attrs(units="J m-2", long_name="g")
    b = rs.ensemble.confidence_band(small)
    assert b.attrs["band_edges_bounded"] == 0 and b.attrs["n_samples_to_bound_band_edges"] == 146
    assert not np.isinf(b["adhesive_energy_ci_lower"]).any()  # NaN, never -inf in a file
    lines = rs.ensemble.band_summary(b)
    # one line per humidity, each marking its edges, and the reason said once, as a footnote
    assert len(lines) == small.sizes["rh"] + 1
    assert all("CI of the edges: not bounded [1]" in s and "n = 48" in s for s in lines[:-1])
    assert lines[-1] == "[1] n too small to bound a band edge (needs n >= 146 realizations)"
    big = _sample(400).rename("adhesive_energy").assign_attrs(units="J m-2", long_name="g")
    b = rs.ensemble.confidence_band(big)
    assert b.attrs["band_edges_bounded"] == 1
    lines = rs.ensemble.band_summary(b)
    assert not any("too small" in s for s in lines)
    lo = b["adhesive_energy_ci_lower"].sel(quantile=0.025).values[0] * 1e3
    assert f"lower edge [{lo:.4g}," in lines[0]


def test_band_summary_says_why_an_edge_is_unbounded_once_per_block():
    """A block of many humidities from a small ensemble said "n too small to bound this edge
    (needs n >= 146)" twice on every line; now each line carries a marker and the reason comes
    once, after the block (the median's too, with ``median_interval``)."""
    rng = np.random.default_rng(1)
    g = xr.DataArray(rng.lognormal(size=(16, 6)), dims=("realization", "rh"),
                     coords={"rh": np.linspace(0.3, 0.8, 6)}, name="adhesive_energy",
                     attrs={"units": "J m-2", "long_name": "g"})
    lines = rs.ensemble.band_summary(rs.ensemble.confidence_band(g), median_interval=True)
    text = "\n".join(lines)
    assert text.count("needs n >= 146") == 1 and text.count("n too small") == 1
    assert len(lines) == 6 + 1 and all(line.endswith("CI of the edges: not bounded [1]") for line in lines[:6])
    tiny = rs.ensemble.band_summary(rs.ensemble.confidence_band(g.isel(realization=slice(0, 4))), median_interval=True)
    assert "\n".join(tiny).count("needs n >= 6 realizations") == 1  # the median's reason, once
    assert tiny[-2:] == ["[1] n too small to bound the median (needs n >= 6 realizations)",
                         "[2] n too small to bound a band edge (needs n >= 146 realizations)"]
    assert all("CI of the median: not bounded [1])" in line for line in tiny[:6])


def test_band_keeps_run_parameters():
    x = _sample(20).rename("g").assign_attrs(units="1", long_name="g").to_dataset()
    x.attrs = {"seed": 3, "auto_converged": 0, "psd_source": "S1", "bad": [1, 2]}
    b = rs.ensemble.confidence_band(x)
    assert b.attrs["seed"] == 3 and b.attrs["auto_converged"] == 0 and b.attrs["psd_source"] == "S1"
    assert "bad" not in b.attrs


def test_plain_numpy_input_gets_the_fix_not_an_attribute_error():
    with pytest.raises(TypeError, match="wrap a plain array first"):
        rs.ensemble.confidence_band(np.ones((10, 2)))
    with pytest.raises(TypeError, match="labelled xarray DataArray"):
        rs.ensemble.quantile_interval(np.ones(10), [0.5])


def test_string_layer_coordinate_keeps_cf_attrs_through_band_and_histogram():
    """Issue 16 item 6: the ``adsorbed_layer`` labels ("none"/"paper") came out of the band and
    the histogram with the thickness attributes (long_name '... thickness', units 'm')."""
    g = xr.concat([_sample(), 2 * _sample()], dim=xr.DataArray(["none", "paper"], dims="adsorbed_layer"))
    band = rs.ensemble.confidence_band(g)
    hist = rs.ensemble.histogram(g, bins=10)
    for out in (band, hist):
        assert out["adsorbed_layer"].attrs == {"long_name": "adsorbed water layer model"}


def test_band_counts_only_the_members_it_used(backend):
    """A NaN member (e.g. a realization without an equilibrium) is skipped by the band, and the
    counts say so: per point (``v_n_samples``), as the fewest anywhere (attr ``n_samples``, in
    memory) and in band_summary's "from n = ..."; ``n_members`` keeps the size of the dim."""
    x = _sample(3)
    x[1, 1] = np.nan  # realization 1 has no value at RH 0.5
    band = rs.ensemble.confidence_band(backend(x)).compute()
    used = x.count("realization")
    assert (band.adhesive_energy_n_samples == used).all()
    assert band.attrs["n_members"] == x.sizes["realization"]
    if backend.kind == "numpy":
        assert band.attrs["n_samples"] == int(used.min()) < x.sizes["realization"]
    else:  # unknown before computing the members: no count that might be wrong
        assert "n_samples" not in band.attrs
    # the band at RH 0.5 is the band of the members that have a value there
    kept = rs.ensemble.confidence_band(x.sel(rh=[0.5]).dropna("realization"))
    np.testing.assert_allclose(band.adhesive_energy.sel(rh=[0.5]), kept.adhesive_energy)
    assert kept.attrs["n_samples"] == int(band.adhesive_energy_n_samples.sel(rh=0.5))
    lines = rs.ensemble.band_summary(band)
    for r, line in zip(x.rh.values, lines[:x.sizes["rh"]], strict=True):
        assert f"from n = {int(used.sel(rh=r))};" in line, line


def test_old_band_keywords_still_work_and_say_the_new_ones():
    """confidence_band(level=) is confidence_band(confidence=); with it, the old confidence= (the
    quantiles' intervals) is ci_confidence=."""
    x = _sample()
    new = rs.ensemble.confidence_band(x, confidence=0.9, ci_confidence=0.8)
    with pytest.warns(DeprecationWarning, match="confidence_band\\(confidence=...\\)"):
        old = rs.ensemble.confidence_band(x, level=0.9, confidence=0.8)
    rs.testing.assert_same_result(old, new)
    assert new.attrs["level"] == 0.9 and new.attrs["confidence"] == 0.8
