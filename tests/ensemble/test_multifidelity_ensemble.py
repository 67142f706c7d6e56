"""A multi-fidelity ensemble: the cheap model on every realization, the accurate one on a subset
drawn from the seed alone, combined by confidence_band into the accurate model's band."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.ensemble.multifidelity import accurate_subset


@pytest.fixture(scope="module")
def psd():
    q = np.geomspace(1e5, 4e9, 300)
    p = xr.DataArray(rs.datasets.family_psd("table4")(q), dims="q", coords={"q": q},
                     attrs={"units": "m4"})
    p["q"].attrs["units"] = "rad m-1"
    return p


def _run(psd, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the cheap model's validity and pixel warnings
        return rs.ensemble.run(psd, shape=(32, 32), spacing=5e-9, relative_humidity=[0.5, 0.9],
                               seed=3, model="modified_dmt", **kw)


@pytest.fixture(scope="module")
def mf(psd):
    return _run(psd, n=40, accurate_model="fft_bem", n_accurate=16, chunks=8).compute()


def test_the_accurate_subset_is_the_seed_s_and_its_values_are_the_model_s(mf, psd):
    members = accurate_subset(40, 16, seed=3)
    has = mf["adhesive_energy_accurate"].notnull().all("rh")
    assert np.array_equal(np.flatnonzero(has.values), members)
    assert mf.attrs["accurate_model"] == "fft_bem" and int(mf.attrs["n_accurate"]) == 16
    k = int(members[0])
    h = rs.surface.generate_surfaces(psd, n=40, shape=(32, 32), spacing=5e-9, seed=3).isel(
        realization=k).compute()
    for r in (0.5, 0.9):
        own = rs.contact.summary(rs.contact.fft_bem_curves(h, relative_humidity=[r]))
        assert float(mf["adhesive_energy_accurate"].sel(realization=k, rh=r)) == float(
            own["adhesive_energy"].sel(rh=r))


def test_bit_identical_across_chunkings(mf, psd):
    other = _run(psd, n=40, accurate_model="fft_bem", n_accurate=16,
                 chunks={"realization": 5, "rh": 1}).compute()
    for v in ("adhesive_energy", "adhesive_energy_accurate", "pull_off_pressure_accurate"):
        np.testing.assert_array_equal(mf[v].values, other[v].values)


def test_the_band_is_the_accurate_model_s_with_its_interval(mf, psd):
    band = rs.ensemble.confidence_band(mf[["adhesive_energy", "adhesive_energy_accurate"]])
    assert "adhesive_energy_accurate" not in band and "multi-fidelity" in band.attrs["band_method"]
    assert int(band["adhesive_energy_n_accurate"].isel(rh=0)) == 16
    full = _run(psd, n=40, chunks=8).compute()  # the same surfaces with the cheap model only
    np.testing.assert_allclose(band["adhesive_energy_cheap"].values,
                               full["adhesive_energy"].quantile(band["quantile"].values, "realization").values)
    # the all-accurate ensemble of the same 40 surfaces: its median inside the correction interval
    h = rs.surface.generate_surfaces(psd, n=40, shape=(32, 32), spacing=5e-9, seed=3).compute()
    acc = xr.concat([rs.contact.summary(rs.contact.fft_bem_curves(h.isel(realization=k),
                                                                  relative_humidity=[0.5, 0.9]))
                     ["adhesive_energy"] for k in range(40)], "realization")
    med = acc.quantile(0.5, "realization", method="inverted_cdf")
    lo = band["adhesive_energy_correction_lower"].sel(quantile=0.5)
    hi = band["adhesive_energy_correction_upper"].sel(quantile=0.5)
    assert bool(((lo <= med) & (med <= hi)).all()), (lo.values, med.values, hi.values)


def test_auto_sizes_the_subset_from_a_pilot_and_solves_each_map_once(psd, monkeypatch):
    """The pilot's maps are the first of the subset: the run reads their accurate summaries
    instead of solving them again: one accurate solve per map and humidity in all."""
    from roughstick.ensemble import pipeline

    pipeline._ACCURATE_DONE.clear()
    calls = []
    solve = pipeline.contact_curves

    def counted(*args, **kw):
        if args[0].shape == (32, 32):  # the run's maps (not the 16 x 16 probe of the layout)
            calls.append(kw["model"])
        return solve(*args, **kw)

    monkeypatch.setattr(pipeline, "contact_curves", counted)
    ens = _run(psd, n=60, accurate_model="fft_bem", n_accurate="auto", accuracy=0.3).compute()
    n = int(ens.attrs["n_accurate"])
    assert 40 <= n <= 60  # at least the pilot (40), at most n
    assert calls.count("fft_bem") == 2 * n  # two humidities, each map solved once
    assert int(ens["adhesive_energy_accurate"].notnull().all("rh").sum()) == n


def test_single_model_runs_keep_their_parameter_hash_and_bad_input_is_named(psd, mf):
    plain = _run(psd, n=40, chunks=8)
    assert plain.attrs["params_hash"] != mf.attrs["params_hash"]
    assert _run(psd, n=40, chunks=8).attrs["params_hash"] == plain.attrs["params_hash"]
    with pytest.raises(ValueError, match="accurate_model must be a registered contact model"):
        _run(psd, n=10, accurate_model="not_a_model")
    with pytest.raises(ValueError, match="give n"):
        _run(psd, n="auto", accurate_model="fft_bem")
    with pytest.raises(ValueError, match="n_accurate must be"):
        _run(psd, n=10, accurate_model="fft_bem", n_accurate=11)
