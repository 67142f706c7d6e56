"""Figures a report can use as they are: legends beside the data, not over it."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from _figure_lint import figure_problems  # noqa: E402

import roughstick as rs  # noqa: E402
from conftest import lognormal_gamma  # noqa: E402


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
