"""Tests of roughstick.ensemble.run with every contact model (its model= keyword):
the lazy template matches what the model returns, "auto" is chosen once for the ensemble, and the
one-time validity check describes the model actually run."""

from __future__ import annotations

import importlib.util
import warnings

import numpy as np
import pytest

import roughstick as rs

SHAPE, SPACING, RH = (32, 32), 5e-9, [0.5]
MODELS = ["modified_dmt", "gw", "fft_bem",
          pytest.param("bem", marks=pytest.mark.skipif(importlib.util.find_spec("tamaas") is None,
                                                       reason="model='bem' needs the tamaas extra"))]


@pytest.fixture(scope="module")
def psd():
    return rs.surface.power_spectrum(rs.datasets.surface_family("S1", shape=(64, 64), seed=1))


def _run(psd, model, n=2):
    """The lazy run and the warnings it emitted (all recorded: which ones is what is tested)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = rs.ensemble.run(psd, n=n, shape=SHAPE, spacing=SPACING, relative_humidity=RH,
                             model=model)
    return ds, [w for w in caught if issubclass(w.category, rs.ValidityWarning)
                and not issubclass(w.category, rs.PixelResolutionWarning)]


def _compute(ds):
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.ValidityWarning)  # said before the graph, never per block
        return ds.compute(scheduler="sync")


@pytest.mark.parametrize("model", MODELS)
def test_every_model_runs_with_the_variables_it_returns(psd, model):
    """The template's variables are those of the model run (fft_bem's solver diagnostics, GW's
    summit density), so the lazy run computes; GW is not refused for a synthetic probe surface."""
    ds, _ = _run(psd, model)
    out = _compute(ds)
    assert set(out.data_vars) == set(ds.data_vars)
    assert out.attrs["contact_model"] == model
    assert np.isfinite(out.pressure).all() and np.isfinite(out.max_height).all()
    # the same variables as the model returns for one of the run's surfaces on its own
    h = rs.surface.generate_surfaces(psd, n=1, shape=SHAPE, spacing=SPACING, seed=0).isel(realization=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        direct = rs.contact.curves(h.compute(), relative_humidity=RH, model=model)
    assert set(direct.data_vars) <= set(out.data_vars)


@pytest.mark.parametrize("model", MODELS)
def test_validity_warning_describes_the_model_run(psd, model):
    """The one-time check looks up the model run (model=), not always the modified DMT: it
    warns exactly when that model's measured bound at the PSD's expected groups exceeds the
    tolerance, and only about that model (never for the reference BEM)."""
    _, said = _run(psd, model)
    groups = rs.contact.expected_surface_groups(psd, shape=SHAPE, spacing=SPACING, relative_humidity=RH)
    bound = max(rs.contact.model_error(model, groups.isel(rh=j)).upper for j in range(len(RH)))
    assert len(said) == int(bound > rs.contact.VALIDITY_BOUND), [str(w.message) for w in said]
    assert all(str(w.message).startswith(f"{model} may be off") for w in said)


def test_auto_is_chosen_once_meets_the_tolerance_and_is_recorded(psd):
    """model='auto' (the ValidityWarning's remedy) runs: one model for the whole ensemble, the
    cheapest one measured within the tolerance at the PSD's expected groups, recorded in attrs;
    no warning about a model that is not run."""
    ds, said = _run(psd, "auto")
    assert not said, [str(w.message) for w in said]
    chosen = ds.attrs["contact_model"]
    assert chosen in rs.contact.MODELS and chosen != "auto"
    assert ds.attrs["model_selection"].startswith(f"auto -> {chosen}")
    groups = rs.contact.expected_surface_groups(psd, shape=SHAPE, spacing=SPACING, relative_humidity=RH)
    worst = {m: max(rs.contact.model_error(m, groups.isel(rh=j)).upper for j in range(len(RH)))
             for m in ("gw", "modified_dmt", "fft_bem", "bem")}
    assert worst[chosen] <= rs.contact.VALIDITY_BOUND
    cheaper = list(worst)[:list(worst).index(chosen)]
    assert all(worst[m] > rs.contact.VALIDITY_BOUND for m in cheaper)
    out = _compute(ds)
    # every realization ran the chosen model: the same numbers as naming it explicitly
    explicit, _ = _run(psd, chosen)
    explicit = _compute(explicit)
    assert set(out.data_vars) == set(explicit.data_vars)
    np.testing.assert_array_equal(out.adhesive_energy.values, explicit.adhesive_energy.values)
    np.testing.assert_array_equal(out.pressure.values, explicit.pressure.values)


def test_unknown_model_is_refused_before_anything_runs(psd):
    with pytest.raises(ValueError, match="model must be one of"):
        rs.ensemble.run(psd, n=2, shape=SHAPE, spacing=SPACING, relative_humidity=RH, model="dmt")


def test_the_old_curves_kwargs_model_still_works_and_says_model(psd):
    """curves_kwargs={"model": ..., "tolerance": ...} is model=..., accuracy=... (with a
    DeprecationWarning naming them); the run, its parameters' hash included, is the same."""
    kw = dict(n=2, shape=SHAPE, spacing=SPACING, relative_humidity=RH)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        new = rs.ensemble.run(psd, model="gw", accuracy=0.3, **kw)
        with pytest.warns(DeprecationWarning) as said:
            old = rs.ensemble.run(psd, curves_kwargs={"model": "gw", "tolerance": 0.3}, **kw)
    assert {str(w.message).split(" is now ")[1].split(";")[0] for w in said
            if w.category is DeprecationWarning} == {"run(model=...)", "run(accuracy=...)"}
    assert old.attrs["params_hash"] == new.attrs["params_hash"]
    assert old.attrs["contact_model"] == new.attrs["contact_model"] == "gw"
    with pytest.raises(TypeError, match="model="):
        rs.ensemble.run(psd, model="gw", curves_kwargs={"model": "gw"}, **kw)


def test_size_study_runs_one_auto_model_for_every_size():
    # S2 at 20 % RH with a 30 % tolerance: select_model takes the modified DMT for 32 px zones
    # and the FFT-BEM for 64 px zones (their expected groups differ); a size study must not
    # compare two models under the name of two sizes
    psd = rs.surface.self_affine_psd(np.geomspace(1e5, 1e10, 2000), **rs.datasets.family_parameters("S2"))
    ck = {"model": "auto", "accuracy": 0.3}
    alone = [rs.ensemble.run(psd, n=2, shape=s, spacing=5e-9, relative_humidity=[0.2],
                             **ck).attrs["contact_model"] for s in (32, 64)]
    assert alone == ["modified_dmt", "fft_bem"]
    ds = rs.ensemble.surface_size_study(psd, shapes=[32, 64], spacing=5e-9, n=2,
                                        relative_humidity=[0.2], **ck)
    assert ds.attrs["contact_model"] == "fft_bem"
    assert "every size" in ds.attrs["model_selection"]


def test_a_callable_psd_is_refused_with_the_way_to_evaluate_it():
    with pytest.raises(TypeError, match=r"self_affine_psd\(numpy.geomspace"):
        rs.ensemble.run(rs.datasets.family_psd("S1"), n=2, shape=16, spacing=5e-9, relative_humidity=[0.5])
