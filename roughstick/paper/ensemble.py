"""Monte Carlo ensembles, paper §4.3: Figs. 13 (generated surfaces), 14-15 (curve sets), 16 (Γ
bands versus RH, per surface size) and 17 (distributions of Γ).

Every function returns ``(Dataset, Figure)``. The bands are :func:`roughstick.ensemble.confidence_band`
results, so each edge carries its own order-statistic interval (NaN where n is too small to
bound it) and the figure says how many surfaces it rests on.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

import roughstick as rs

from ..plotting.ensemble import plot_energy_band, plot_energy_distribution, plot_ensemble_curves
from ..plotting.generation import plot_surfaces

__all__ = ["fig13_surfaces", "fig14_ensemble_curves", "fig16_energy_bands", "fig17_energy_distributions"]


def _plt():
    import matplotlib.pyplot as plt

    return plt


def fig13_surfaces(psd, *, shape: int, spacing: float = 5e-9, n: int = 3, seed=13,
                   title: str | None = None):
    """Fig. 13: ``n`` surfaces generated from ``psd`` (Eqs. 33-35).

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        ``height`` over ``(realization, y, x)`` and its images.
    """
    h = rs.surface.generate_surfaces(psd, n=n, shape=shape, spacing=spacing, seed=seed).compute()
    axes = plot_surfaces(h, title=title)
    return h.to_dataset(name="height"), np.atleast_1d(axes)[0].figure


def fig14_ensemble_curves(ens: xr.Dataset, *, title: str | None = None):
    """Figs. 14 (S1) and 15 (S2): the force-distance curves of an ensemble with their band.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        The 95 % band of the curves (:func:`roughstick.ensemble.confidence_band` of ``pressure``) and the
        figure.
    """
    fig = plot_ensemble_curves(ens)
    n = ens.sizes["realization"]
    if title:
        fig.suptitle(f"{title} (n = {n})")
    band = rs.ensemble.confidence_band(ens[["pressure"]]).compute()
    return band, fig


def fig16_energy_bands(ensembles: dict, *, title: str = "Fig. 16", labels: dict | None = None):
    """Fig. 16: apparent adhesive energy Γ versus RH, median and 95 % band, one panel per entry.

    Parameters
    ----------
    ensembles : dict of str to xarray.Dataset
        E.g. ``{"S1": ens_s1, "S2": ens_s2}``; each with ``adhesive_energy`` over
        ``(realization, rh)`` and optionally ``surface_size`` (one band per size).
    title : str
        Prefix of each panel title.
    labels : dict, optional
        Legend label per entry (default: the surface sizes).

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        The bands of Γ (dim ``sample`` when more than one entry) with their own intervals.
    """
    plt = _plt()
    fig, axes = plt.subplots(1, len(ensembles), figsize=(6.2 * len(ensembles), 3.8),
                             constrained_layout=True, squeeze=False)
    bands = []
    for ax, (name, ens) in zip(axes[0], ensembles.items(), strict=True):
        plot_energy_band(ens, ax=ax, label=(labels or {}).get(name))
        n = ens.sizes["realization"]
        band = rs.ensemble.confidence_band(ens[["adhesive_energy"]]).compute()
        edges = "" if band.attrs.get("band_edges_bounded") else \
            f"\n(band edges unbounded below n = {band.attrs['n_samples_to_bound_band_edges']})"
        ax.set_title(f"{title}: {name}, n = {n}{edges}", fontsize="medium")
        bands.append(band)
    if len(bands) == 1:
        return bands[0], fig
    out = xr.concat(bands, dim=xr.DataArray(list(ensembles), dims="sample", name="sample",
                                            attrs={"long_name": "PSD sample"}),
                    combine_attrs="drop_conflicts")
    return out, fig


def fig17_energy_distributions(ens: xr.Dataset, *, rh_panels=((0.3, 0.7, 0.9),),
                               title: str = "Fig. 17: distribution of Γ"):
    """Fig. 17: empirical CDFs of Γ at given humidities (per surface size), one panel per RH set.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        ``cumulative_probability`` of Γ per humidity (:func:`roughstick.ensemble.ecdf`) and the figure.
    """
    plt = _plt()
    fig, axes = plt.subplots(1, len(rh_panels), figsize=(6.8 * len(rh_panels), 4),
                             constrained_layout=True, squeeze=False)
    for ax, rhs in zip(axes[0], rh_panels, strict=True):
        plot_energy_distribution(ens, rh=list(rhs), ax=ax)
    fig.suptitle(f"{title} (n = {ens.sizes['realization']})")
    g = ens["adhesive_energy"].compute()
    ecdf = rs.ensemble.ecdf(g).rename("adhesive_energy").to_dataset()
    return ecdf, fig
