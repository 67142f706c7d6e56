"""The one pipeline and dispatcher above the rough-surface models (roughstick.contact.curves)
and the registry it reads."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr

import roughstick as rs


@pytest.fixture(scope="module")
def s1a_crop():
    """A 256² crop of the bundled S1A map (5 nm pixels), levelled."""
    h = rs.datasets.load_sample("S1A").isel(x=slice(0, 256), y=slice(0, 256))
    return rs.surface.level(h, method="plane")


def test_gw_same_result_whichever_entry_point(s1a_crop):
    # issue 11: rough_contact_curves(h, model="gw") used the spline moments and
    # gw_contact_curves(h) the periodogram's (Gamma(70 %) 0.0378 vs 0.0134 mJ m-2); one estimator now
    rh = [0.3, 0.7, 0.9]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.contact.ValidityWarning)
        via_dispatch = rs.contact.curves(s1a_crop, relative_humidity=rh, model="gw")
    d = via_dispatch.distance.values
    area = 256 * 256 * (5e-9) ** 2
    direct = rs.contact.gw_curves(s1a_crop, relative_humidity=rh, distance=d, apparent_area=area)
    xr.testing.assert_identical(via_dispatch.pressure, direct.pressure)
    # the default estimator is the paper's Table 2 one (cubic splines), which §3.4.2 feeds to GW
    from_moments = rs.contact.gw_curves(rs.surface.roughness_moments(s1a_crop, method="spline"),
                                        relative_humidity=rh, distance=d, apparent_area=area)
    xr.testing.assert_identical(direct.pressure, from_moments.pressure)
    gamma = rs.contact.summary(direct).adhesive_energy
    assert float(gamma.sel(rh=0.7)) == pytest.approx(0.0377e-3, rel=0.01)
    # the other estimator, by name, through both entry points alike
    kw = dict(moment_method="spectral", qmax=289e6)
    a = rs.contact.curves(s1a_crop, relative_humidity=rh, model="gw", distance=d, **kw)
    b = rs.contact.gw_curves(s1a_crop, relative_humidity=rh, distance=d, apparent_area=area, **kw)
    xr.testing.assert_identical(a.pressure, b.pressure)


def test_spectral_moments_with_the_paper_cutoff_match_the_spline_ones(s1a_crop):
    # Table 3: with xi_max = 289 rad/um the PSD moments reproduce the spatial (spline) ones;
    # without the cutoff the periodogram of a non-periodic map inflates m4 (edge discontinuity)
    # (the paper's periodogram has no window: window=None; the default Hann window needs no
    # cutoff: tests/surface/test_spectrum.py::test_default_window_for_measured_scans)
    spline = rs.surface.roughness_moments(s1a_crop, method="spline")
    cut = rs.surface.roughness_moments(s1a_crop, method="spectral", qmax=289e6, window=None)
    raw = rs.surface.roughness_moments(s1a_crop, method="spectral", window=None)
    assert float(cut.m0) == pytest.approx(float(spline.m0), rel=0.01)
    assert float(cut.m2) == pytest.approx(float(spline.m2), rel=0.08)
    assert float(cut.m4) == pytest.approx(float(spline.m4), rel=0.03)
    assert float(raw.m4) > 2 * float(spline.m4)


def test_map_moments_refuse_cutoff_with_splines_and_options_with_a_dataset(s1a_crop):
    with pytest.raises(ValueError, match="method='spectral' only"):
        rs.surface.roughness_moments(s1a_crop, qmax=289e6)
    m = rs.surface.roughness_moments(s1a_crop)
    with pytest.raises(ValueError, match="moments were given as a Dataset"):
        rs.contact.gw_curves(m, relative_humidity=0.5, distance=[0.0, 1e-9], moment_method="spectral")


def test_dispatcher_names_and_history():
    h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    with pytest.raises(ValueError, match="model must be one of"):
        rs.contact.curves(h, relative_humidity=0.5, model="jkr")
    with pytest.raises(TypeError, match="for model='modified_dmt'"):
        rs.contact.curves(h, relative_humidity=0.5, distance=[0.0], sphere_model="dmt")
    ds = rs.contact.curves(h, relative_humidity=0.5, distance=[-1e-9, 1e-9])
    direct = rs.contact.modified_dmt_curves(h, relative_humidity=0.5, distance=[-1e-9, 1e-9])
    xr.testing.assert_identical(ds.pressure, direct.pressure)
    assert ds.attrs["history"].splitlines()[-1].endswith("roughstick.contact.curves(model='modified_dmt')")
    assert np.isfinite(ds.pressure).all()


def test_heights_in_nm_labelled_m_are_refused_with_the_fix():
    """A 32² S1 map whose nm values are labelled m has an rms height of metres: every model is
    refused before it runs (the modified DMT used to return an equilibrium of 7.9 m)."""
    h = rs.datasets.surface_family("S1", shape=(32, 32), seed=1)
    wrong = (h * 1e9).assign_attrs(units="m")
    for model in ("modified_dmt", "fft_bem", "gw", "auto"):
        with pytest.raises(ValueError, match=r"rms height .*attrs\['units'\] = 'nm'"):
            rs.contact.curves(wrong, relative_humidity=0.5, model=model)


def test_auto_says_its_choice_and_cost_before_the_work(caplog, monkeypatch):
    """model="auto" explained its choice only after computing (attrs): it is now said, with the
    chosen model's estimated cost, before the chosen model starts (its first hook, ``prepare``)."""
    import dataclasses
    import logging

    from roughstick.contact import _model

    caplog.set_level(logging.INFO, logger="roughstick")
    said_when_called = {}
    for name, entry in list(rs.contact.MODELS.items()):
        def spy(ctx, _real=entry.prepare, _name=name):
            said_when_called[_name] = [r.getMessage() for r in caplog.records
                                       if r.getMessage().startswith("contact model auto -> ")]
            if _real is not None:
                _real(ctx)

        monkeypatch.setitem(_model._REGISTRY, name, dataclasses.replace(entry, prepare=spy))
    h = rs.datasets.surface_family("smooth", shape=(32, 32), seed=1, n=1).isel(realization=0).compute()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.contact.PixelResolutionWarning)
        ds = rs.contact.curves(h, relative_humidity=[0.5, 0.9], model="auto")
    chosen = ds.attrs["contact_model"]
    (said,) = said_when_called[chosen]
    assert said.startswith(f"contact model auto -> {chosen} for 2 curve(s) of 32 x 32 pixels, estimated about")
    assert ds.attrs["model_selection"].split(": ", 1)[1] in said  # the same reason as recorded
