"""Figures a report can use as they are: the band figure draws and says what the console prints
(the median), legends beside the data, not over it."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from _figure_lint import figure_problems  # noqa: E402

import roughstick as rs  # noqa: E402
from conftest import lognormal_gamma  # noqa: E402
from roughstick.plotting import plot_energy_band  # noqa: E402


def test_energy_band_figure_draws_and_says_the_median():
    """`roughstick run` prints the median of Γ per humidity; its band figure drew the mean and
    labelled it "mean". The line is now the band's median, labelled so."""
    g, _ = lognormal_gamma(n=40, rh=(0.3, 0.6, 0.9), sigma=1.5)  # skewed: mean far above median
    ds = g.to_dataset()
    ax = plot_energy_band(ds)
    lines = [line for line in ax.lines if not line.get_label().startswith("_")]
    assert [line.get_label() for line in lines] == ["median"]
    np.testing.assert_allclose(lines[0].get_ydata(), g.median("realization").values * 1e3, rtol=1e-12)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert not any("mean" in t for t in labels), labels
    assert figure_problems(ax.figure) == []
    plt.close("all")


def test_risk_figures_keep_legends_off_the_data():
    """stiction_probability.png had its legend over the curves of both panels (and fig17 over the
    distributions): every figure of the risk and ensemble plots passes the legend check."""
    from roughstick.paper import cantilever, ensemble

    g, _ = lognormal_gamma(n=25, rh=np.arange(0.3, 0.951, 0.05))
    g = rs.conventions.set_attrs(g, "surface_adhesive_energy")
    sample = xr.concat([g, 2 * g], dim=xr.DataArray(["none", "paper"], dims="adsorbed_layer"))
    risk = rs.stiction_risk(sample, length=[250e-6, 300e-6, 400e-6, 500e-6, 1500e-6], levels=[0.5])
    _, fig = cantilever.stiction_probability(risk, level=0.5)
    assert figure_problems(fig) == []
    _, fig = ensemble.fig17_energy_distributions(g.to_dataset(), rh_panels=[tuple(g.rh.values[[0, 6, 12]])])
    assert figure_problems(fig) == []
    plt.close("all")
