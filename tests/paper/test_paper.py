"""roughstick.paper: each figure function returns (Dataset, Figure); the data are the figure's."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402
from _figure_lint import figure_problems  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

import roughstick as rs  # noqa: E402
from roughstick.paper import ensemble, rough_contact  # noqa: E402

RH = [0.3, 0.7, 0.9]


def readable(fig):
    """Issue 16 item 8: the figure as the demo saves it passes tests/_figure_lint.py."""
    problems = figure_problems(fig)
    assert not problems, problems
    return True


@pytest.fixture(scope="module")
def ens():
    psd = rs.datasets.sample_psd("S2")
    return rs.ensemble.run(psd, n=6, shape=64, spacing=5e-9, relative_humidity=RH, seed=3,
                           chunks=3).compute()


def test_ensemble_figures(ens):
    band, fig = ensemble.fig14_ensemble_curves(ens, title="t")
    assert isinstance(fig, Figure) and "n = 6" in fig._suptitle.get_text() and readable(fig)
    xr.testing.assert_allclose(band["pressure"], rs.ensemble.confidence_band(ens[["pressure"]])["pressure"])
    band, fig = ensemble.fig16_energy_bands({"a": ens, "b": ens})
    assert band.sizes["sample"] == 2 and band.attrs["band_edges_bounded"] == 0
    assert all("unbounded below n = 146" in ax.get_title() for ax in fig.axes if ax.get_title())
    assert readable(fig)
    np.testing.assert_allclose(band["adhesive_energy"].sel(sample="a"),
                               ens.adhesive_energy.quantile([0.025, 0.5, 0.975], "realization"))
    ecdf, fig = ensemble.fig17_energy_distributions(ens, rh_panels=[(0.3,), (0.7, 0.9)])
    assert len(fig.axes) == 2 and ecdf["adhesive_energy"].sizes["rh"] == 3 and readable(fig)
    h, fig = ensemble.fig13_surfaces(rs.datasets.sample_psd("S2"), shape=32, n=2, seed=1)
    assert h["height"].sizes["realization"] == 2 and readable(fig)
    plt.close("all")


def test_rough_contact_figures_and_map_dataset():
    maps = {k: rs.datasets.load_sample(k).isel(x=slice(0, 128), y=slice(0, 128)) for k in ("S1A", "S1B")}
    curves = {k: rs.contact.curves(h, relative_humidity=RH) for k, h in maps.items()}
    summaries = {k: rs.contact.summary(c) for k, c in curves.items()}
    ds, fig = rough_contact.fig08_rough_curves(curves["S1A"], name="S1A", relative_humidity=RH)
    assert ds is curves["S1A"] and isinstance(fig, Figure) and readable(fig)
    gw, fig = rough_contact.fig10_mdmt_vs_gw(maps, curves, relative_humidity=RH, rh_shown=(0.3, 0.9))
    assert "pressure" in gw and gw.sizes["distance"] == 300 and readable(fig)
    s, fig = rough_contact.fig11_adhesion_vs_rh(summaries)
    np.testing.assert_array_equal(s.adhesive_energy.sel(map="S1B"), summaries["S1B"].adhesive_energy)
    assert readable(fig)
    both = rough_contact.curves_by_map(curves, summaries)
    assert both["pressure"].dims[0] == "map" and both["distance"].dims == ("map", "point")
    np.testing.assert_array_equal(both.pressure.sel(map="S1A").values, curves["S1A"].pressure.values)
    plt.close("all")


def test_sphere_and_topography_figures():
    from roughstick.paper import sphere, topography

    ds, fig = sphere.fig1b_meniscus(n=10)
    np.testing.assert_allclose(ds.laplace_pressure, rs.contact.laplace_pressure(ds.rh.values))
    assert readable(fig)
    ds, fig = sphere.fig3_sphere_models(n=51)
    assert ds.force.sizes["model"] == 3 and isinstance(fig, Figure) and readable(fig)
    t1 = sphere.table1()
    assert float(abs(t1.relative_error.sel(model="modified_dmt")).max()) < 0.01  # README: 0.62 %
    fits = topography.table4_self_affine()
    params, fig = topography.fig19_self_affine_psd(fits, measured={})
    assert params.sizes["fit"] == 2 and readable(fig)
    np.testing.assert_allclose(float(params.q0[0]) * 1e-6, 21.19, rtol=1e-3)  # as the demo's CSV
    plt.close("all")


def test_cantilever_figures_one_panel_per_layer():
    from conftest import lognormal_gamma
    from roughstick.paper import cantilever

    g, _ = lognormal_gamma(n=25, rh=np.arange(0.3, 0.951, 0.05))
    g = rs.conventions.set_attrs(g, "surface_adhesive_energy")
    sample = xr.concat([g, 2 * g], dim=xr.DataArray(["none", "paper"], dims="adsorbed_layer"))
    risk = rs.stiction.risk_summary(sample, beam_length=[300e-6, 500e-6], probabilities=[0.5])
    for func in (cantilever.stiction_probability, cantilever.stiction_vs_length, cantilever.crack_length,
                 cantilever.fig20_adhesive_energy_bands):
        ds, fig = func(risk)
        assert isinstance(ds, xr.Dataset) and len(ds.data_vars) > 0
        assert len([ax for ax in fig.axes if ax.get_title()]) >= 2, func.__name__
        assert readable(fig)
    plt.close("all")
