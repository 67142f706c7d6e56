"""The default call is the accurate answer: with no ``model=`` the curves and the ensembles come
from the cheapest model measured within the accuracy of the boundary-element reference, with no
warning against their own model, on surfaces of a PSD that no benchmark or validity map uses."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import roughstick as rs

#: A self-affine PSD of our own (Hurst 0.9 rolled off at 2e7 rad/m, 4 nm pixels): no family,
#: benchmark or measured validity map uses it.
UNTUNED = dict(s0=2e-36, s1=3e-37, q0=2e7, qmax=4e8)


def _untuned_psd():
    return rs.surface.self_affine_psd(np.geomspace(1e5, 1e10, 2000), **UNTUNED)


def _maps():
    untuned = rs.surface.generate_surfaces(_untuned_psd(), n=1, shape=(40, 40), spacing=4e-9,
                                           seed=9).isel(realization=0).compute()
    return {"untuned": untuned, **{f: rs.datasets.surface_family(f, shape=(40, 40), seed=3)
                                   for f in ("S2", "table4", "smooth")}}


@pytest.mark.parametrize("name", ["untuned", "S2", "table4", "smooth"])
def test_default_curves_are_within_accuracy_of_the_reference_and_do_not_warn(name):
    pytest.importorskip("tamaas")
    h = _maps()[name]
    rh = [0.3, 0.6, 0.9]
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.ValidityWarning)  # no warning against its own model
        warnings.simplefilter("ignore", rs.PixelResolutionWarning)  # the map's pixel, not the model
        default = rs.contact.curves(h, relative_humidity=rh)
    reference = rs.contact.curves(h, relative_humidity=rh, model="bem")
    g = rs.contact.summary(default).adhesive_energy.values
    g_ref = rs.contact.summary(reference).adhesive_energy.values
    assert default.attrs["model_selection"].startswith("auto -> ")
    np.testing.assert_array_less(np.abs(g / g_ref - 1), 0.10)  # the default accuracy


def test_the_paper_model_is_named_and_warns_where_it_is_not_measured_within_accuracy():
    h = _maps()["S2"]
    with pytest.warns(rs.ValidityWarning, match="modified_dmt may be off"):
        ds = rs.contact.curves(h, relative_humidity=[0.6], model="modified_dmt")
    assert ds.attrs["contact_model"] == "modified_dmt"


def test_a_small_default_ensemble_runs_the_accurate_model_on_every_surface():
    """Below MULTIFIDELITY_FROM realizations the default is the chosen model on all of them: the
    same numbers as naming it."""
    kw = dict(n=4, relative_humidity=[0.5], spacing=4e-9, shape=(32, 32), seed=5)
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.ValidityWarning)
        warnings.simplefilter("ignore", rs.PixelResolutionWarning)
        default = rs.ensemble.run(_untuned_psd(), **kw).compute()
        named = rs.ensemble.run(_untuned_psd(), model="fft_bem", **kw).compute()
    assert default.attrs["contact_model"] == "fft_bem" and "accurate_model" not in default.attrs
    np.testing.assert_array_equal(default.adhesive_energy.values, named.adhesive_energy.values)


@pytest.mark.slow
def test_the_default_multifidelity_ensemble_gives_the_accurate_median():
    """From 200 realizations the default runs Eq. 16 on all and fft_bem on a pilot-sized subset;
    the band's median is within 5 % of fft_bem on every one of the same surfaces (measured
    1.3 % and 0.1 % here, with 40 of 200 run by fft_bem)."""
    kw = dict(n=200, relative_humidity=[0.5, 0.8], spacing=4e-9, shape=(48, 48), seed=5)
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.ValidityWarning)
        warnings.simplefilter("ignore", rs.PixelResolutionWarning)
        default = rs.ensemble.run(_untuned_psd(), **kw).compute()
        accurate = rs.ensemble.run(_untuned_psd(), model="fft_bem", **kw).compute()
    assert default.attrs["accurate_model"] == "fft_bem"
    assert default.attrs["contact_model"] == "modified_dmt"
    band = rs.ensemble.confidence_band(default)
    median = band.adhesive_energy.sel(quantile=0.5).values
    truth = accurate.adhesive_energy.median("realization").values
    np.testing.assert_array_less(np.abs(median / truth - 1), 0.05)


def test_auto_refuses_distances_its_choice_cannot_take_before_the_work():
    """Given distances below the mean plane and a surface where auto picks a periodic BEM model
    (which needs a positive mean gap): a ValueError that names the choice and both fixes, raised
    before any curve is computed (also for a lazy map); the paper's model, named, takes them."""
    h = rs.generate_surfaces(rs.datasets.family_psd("table4"), n=1, shape=(64, 64), spacing=5e-9,
                             seed=1).isel(realization=0)
    s = float(h.std())
    distance = np.linspace(-s, 4 * s, 20)
    for height in (h, h.compute()):
        with pytest.raises(ValueError, match=r"model='auto' chose fft_bem.*mean plane.*"
                                             r"distance=None.*model='modified_dmt'"):
            rs.contact.curves(height, relative_humidity=0.5, distance=distance)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        c = rs.contact.curves(h, relative_humidity=0.5, distance=distance, model="modified_dmt")
    assert np.isfinite(c.pressure.values).all()
