"""Figures a report can use as they are: the band figure draws and says what the console prints
(the median), lines only where something was computed, legends beside the data, not over it."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from _figure_lint import figure_problems  # noqa: E402

import roughstick as rs  # noqa: E402
from conftest import lognormal_gamma  # noqa: E402
from roughstick.plotting import plot_energy_band, plot_stiction_vs_length  # noqa: E402


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


def _risk(lengths_um):
    g, _ = lognormal_gamma(n=30, rh=(0.4, 0.7, 0.9))
    g = rs.conventions.set_attrs(g, "surface_adhesive_energy")
    return rs.stiction.risk_summary(g, beam_length=np.asarray(lengths_um) * 1e-6, probabilities=[0.5])


def test_stiction_vs_length_draws_no_line_across_uncomputed_lengths():
    """With lengths 250-500 µm and 1500 µm a line ran from 500 to 1500 µm where nothing was
    computed. Now every computed length has a marker and lines join neighbours only."""
    lengths = [250, 300, 350, 400, 500, 1500]
    ax = plot_stiction_vs_length(_risk(lengths))
    drawn = [line for line in ax.lines if line.get_linestyle() not in ("None", "")]
    for line in drawn:
        x = np.asarray(line.get_xdata(), float)
        assert not (x.min() <= 500 < 1500 <= x.max()), f"a line spans 500-1500 µm: {x}"
    by_colour = {}
    for line in ax.lines:
        if line.get_marker() == "o":
            by_colour.setdefault(line.get_color(), []).extend(np.asarray(line.get_xdata(), float))
    assert len(by_colour) == 3  # one colour per humidity, a marker at every computed length
    for xs in by_colour.values():
        np.testing.assert_allclose(np.sort(xs), lengths)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["RH 40 %", "RH 70 %", "RH 90 %"]
    assert figure_problems(ax.figure) == []
    plt.close("all")
    # an evenly or geometrically spaced grid is one line per humidity
    for grid in ([100, 200, 300, 400], [100, 200, 400, 800]):
        ax = plot_stiction_vs_length(_risk(grid))
        assert len([line for line in ax.lines if line.get_linestyle() not in ("None", "")]) == 3
        plt.close("all")


def test_risk_figures_keep_legends_off_the_data():
    """stiction_probability.png had its legend over the curves of both panels (and fig17 over the
    distributions): every figure of the risk and ensemble plots passes the legend check."""
    from roughstick.paper import cantilever, ensemble

    g, _ = lognormal_gamma(n=25, rh=np.arange(0.3, 0.951, 0.05))
    g = rs.conventions.set_attrs(g, "surface_adhesive_energy")
    sample = xr.concat([g, 2 * g], dim=xr.DataArray(["none", "paper"], dims="adsorbed_layer"))
    risk = rs.stiction.risk_summary(sample, beam_length=[250e-6, 300e-6, 400e-6, 500e-6, 1500e-6], probabilities=[0.5])
    _, fig = cantilever.stiction_probability(risk, level=0.5)
    assert figure_problems(fig) == []
    _, fig = ensemble.fig17_energy_distributions(g.to_dataset(), rh_panels=[tuple(g.rh.values[[0, 6, 12]])])
    assert figure_problems(fig) == []
    plt.close("all")
